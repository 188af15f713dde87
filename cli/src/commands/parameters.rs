//! `wheelrail parameters`: the parameter specification (`wheelrail::params::spec`) as a text table, as
//! JSON (read by the fmpy tests) or as the Markdown of `docs/parameters.md`.

use super::{compact, number_format, unit_text};
use anyhow::Result;
use clap::Args;
use std::fmt::Write;
use wheelrail::params::spec::{Bound, SEMI_AXIS_RANGE, Spec, specs};
use wheelrail::params::{Input, Key, Param};

/// Arguments of `wheelrail parameters`.
#[derive(Debug, Args)]
pub struct ParametersArgs {
    /// Print a JSON array with one object per row.
    #[arg(long, conflicts_with = "markdown")]
    json: bool,
    /// Print the Markdown of docs/parameters.md.
    #[arg(long)]
    markdown: bool,
}

/// Runs `wheelrail parameters`.
pub fn run(a: &ParametersArgs) -> Result<()> {
    if a.json {
        println!("{}", serde_json::to_string_pretty(&json())?);
    } else if a.markdown {
        print!("{}", markdown());
    } else {
        let line = |[key, unit, default, allowed, flag, fmu]: [&str; 6]| {
            let text = format!("{key:<31} {unit:<8} {default:>9}  {allowed:<26} {flag:<18} {fmu}");
            println!("{}", text.trim_end());
        };
        line(["key", "unit", "default", "allowed", "flag", "FMU variable"]);
        for s in specs() {
            line([
                &s.key.to_string(),
                unit_text(s),
                &number_format(s)(s.default),
                &s.range.bounds_with(number_format(s)),
                &s.cli.map(|f| format!("--{f}")).unwrap_or_default(),
                s.fmu.map_or("", |f| f.name),
            ]);
        }
    }
    Ok(())
}

/// A bound as JSON: the number, or null without one.
fn bound(b: Bound) -> (serde_json::Value, bool) {
    match b {
        Bound::Unbounded => (serde_json::Value::Null, false),
        Bound::Closed(x) => (x.into(), true),
        Bound::Open(x) => (x.into(), false),
    }
}

/// Every row as a JSON object.
fn json() -> serde_json::Value {
    specs()
        .map(|s| {
            let ((min, min_inclusive), (max, max_inclusive)) =
                (bound(s.range.lo), bound(s.range.hi));
            serde_json::json!({
                "name": s.key.to_string(),
                "kind": match s.key {
                    Key::Input(_) => "input",
                    _ => "parameter",
                },
                "toml": s.toml,
                "unit": s.unit.fmi(),
                "symbol": s.unit.symbol(),
                "min": min,
                "min_inclusive": min_inclusive,
                "max": max,
                "max_inclusive": max_inclusive,
                "allowed": s.allowed(),
                "default": s.default,
                "integer": s.integer,
                "cli": s.cli.map(|f| format!("--{f}")),
                "fmu": s.fmu.map(|f| f.name),
                "value_reference": s.fmu.map(|f| f.value_reference),
                "description": s.description,
            })
        })
        .collect()
}

/// One Markdown table of rows.
fn table(out: &mut String, first: &str, rows: impl Iterator<Item = &'static Spec>) {
    let _ = writeln!(
        out,
        "| {first} | Meaning | Unit | Default | Allowed | Flag | FMU variable (value reference) |"
    );
    let _ = writeln!(out, "|---|---|---|---|---|---|---|");
    for s in rows {
        let code = |x: &str| format!("`{x}`");
        let _ = writeln!(
            out,
            "| `{}` | {} | {} | {} | {} | {} | {} |",
            s.toml,
            s.description,
            unit_text(s),
            number_format(s)(s.default),
            s.range.bounds_with(number_format(s)),
            s.cli.map(|f| code(&format!("--{f}"))).unwrap_or_default(),
            s.fmu
                .map(|f| format!("`{}` ({})", f.name, f.value_reference))
                .unwrap_or_default()
        );
    }
}

/// The Markdown of `docs/parameters.md`.
fn markdown() -> String {
    let mut out = String::new();
    out.push_str(
        "# Parameters and inputs\n\
         \n\
         <!-- Generated from src/params/spec.rs by `wheelrail parameters --markdown` (`make parameter-docs`); \
         a test checks that it is current. Do not edit by hand. -->\n\
         \n\
         Every scalar parameter and operating-point input of the model, from the one specification in \
         `src/params/spec.rs`. A parameter is set by its TOML key in a parameter file (`--params FILE.toml`, \
         any subset; missing keys take the default), by its command-line flag where it has one (flags \
         override the file), and in the FMU by its variable where it has one (other parameters keep their \
         defaults there). Values outside the allowed range (and NaN or infinities) are rejected with an \
         error naming the key. SI units, temperatures in kelvin. `wheelrail parameters --json` prints the \
         same rows.\n\
         \n\
         ## Operating point\n\
         \n",
    );
    table(&mut out, "Input", Input::ALL.into_iter().map(Input::spec));
    out.push_str(
        "\nThe FMU's inputs accept more than the library's operating point: a negative `rolling_speed` \
         rolls backwards, a `normal_force` at or below 1 mN lifts the wheel, and `wetness` outside [0, 1] \
         is clamped (see the FMU's variable descriptions).\n\
         \n\
         ## Parameters\n\
         \n",
    );
    table(
        &mut out,
        "TOML key",
        Param::ALL.into_iter().map(Param::spec),
    );
    let _ = write!(
        out,
        "\n## Parameters that are not scalars\n\
         \n\
         - `friction.law`: `\"tomberger\"` (default), `\"constant\"` or `\"polach\"`; flag `--friction-law`.\n\
         - `tangential`: `\"fastsim\"` (default) or `\"exact\"` (Kalker's exact steady rolling, docs/model.md \
         §6.5); flag `--tangential`; FMU parameter `tangential` (0 fastsim, 1 exact).\n\
         - `pressure`: `\"auto\"` (default: Hertz's ellipsoid with the exact solver, the parabola with \
         FASTSIM), `\"hertz\"` or `\"parabolic\"`; flag `--pressure`.\n\
         - `geometry.semi_axes = [a, b]` [m]: prescribed semi-axes instead of the Hertz solution from the \
         curvatures (each {}); flag `--semi-axes a,b`. `--curvatures A,B` sets both \
         curvatures and removes prescribed semi-axes.\n\
         - `grid.nx`, `grid.ny` together: flag `--grid NX,NY`; FMU parameter `grid_size` (both).\n\
         - `solver.heat` (default true): flag `--no-heat` switches frictional heating off.\n\
         - FMU only: `mode`, `table_file`, `minimum_speed`, `warm_start` (see modelDescription.xml).\n",
        SEMI_AXIS_RANGE.bounds_with(compact)
    );
    out
}
