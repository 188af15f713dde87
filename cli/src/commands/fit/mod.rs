//! `wheelrail fit`: calibrates scalar parameters of the model to measured traction–creepage curves by
//! bounded nonlinear least squares, and writes the fitted parameter file, a report with the standard
//! errors and correlations, and a plot of the data and the fitted curves.

mod data;
mod free;
mod solve;
mod stats;

pub use data::FitInputError;

use super::ModelArgs;
use anyhow::{Context, Result};
use clap::Args;
use data::{Data, Measured, Row};
use free::Free;
use nalgebra::DMatrix;
use serde_json::{Map, Value, json};
use solve::{Fit, Modelled, Solves};
use std::path::{Path, PathBuf};
use wheelrail::model::Policy;
use wheelrail::params::Param;
use wheelrail::{Params, Tangential};
use wheelrail_cli::plot::{Chart, Series, data_and_lines_chart};

/// Arguments of `wheelrail fit`.
#[derive(Debug, Args)]
pub struct FitArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// The measurements (CSV): columns named as `point`'s flags (creepage-x, creepage-y, spin,
    /// normal-force, speed, wetness; semi-axis-a and semi-axis-b, or curvature-x and curvature-y), one or
    /// more measured columns (f: traction coefficient; force-x, force-y [N]) and an optional weight.
    /// Inputs without a column take the flags' values or the defaults.
    #[arg(long, value_name = "FILE.csv")]
    data: PathBuf,
    /// The parameters to fit: TOML keys of scalar parameters (`wheelrail parameters`), comma-separated.
    #[arg(
        long,
        value_name = "KEY[,KEY...]",
        value_delimiter = ',',
        required = true
    )]
    free: Vec<String>,
    /// Narrower bounds of free parameters than their allowed ranges.
    #[arg(long, value_name = "KEY=LO:HI", num_args = 1..)]
    bounds: Vec<String>,
    /// The directory for fitted.toml, report.json and fit.png (created if missing).
    #[arg(long, value_name = "DIR", default_value = ".")]
    out: PathBuf,
}

/// Runs `wheelrail fit`.
pub fn run(a: &FitArgs) -> Result<()> {
    let params = a.model.params()?;
    let base = a.model.point()?;
    let free = free::free_parameters(&a.free, &a.bounds)?;
    let data = data::read(&a.data, &base, &params)?;
    let n = data.rows.len() * data.measured.len();
    if n <= free.len() {
        return Err(FitInputError(format!(
            "data file {}: {n} measured values for {} free parameters: the fit needs more values than \
             parameters",
            a.data.display(),
            free.len()
        ))
        .into());
    }
    let initial: Vec<f64> = free.iter().map(|f| params.get(f.param)).collect();
    // the mapped start of each parameter and its value: the initial one, or moved off a bound
    let (u0, start): (Vec<f64>, Vec<f64>) = free
        .iter()
        .zip(&initial)
        .map(|(f, &x)| {
            let (u, moved) = f.map.start(x);
            if !moved {
                return (u, x);
            }
            eprintln!(
                "note: {} starts at {} instead of {x}, inside its bounds",
                f.spec().toml,
                f.value(u)
            );
            (u, f.value(u))
        })
        .unzip();
    let fit = Fit {
        base: &params,
        free: &free,
        data: &data,
        curves: data::curves(&data),
        policy: Policy {
            minimum_speed: super::point::MINIMUM_SPEED,
            ..Policy::default()
        },
    };
    let outcome = solve::minimise(&fit, &u0)?;
    let fitted = fit.params_at(&outcome.u);
    // the report's model values are those `wheelrail point --params fitted.toml` gives
    let modelled = fit
        .evaluate(std::slice::from_ref(&fitted), Solves::AsPoint)?
        .remove(0);
    let residuals = fit.residuals(&modelled);
    let rss = residuals.norm_squared();
    let j = fit
        .jacobian_at(&outcome.u)
        .context("the Jacobian at the fitted parameters")?;
    let j = in_units(j, &free, &outcome.u);
    let values: Vec<f64> = free.iter().map(|f| fitted.get(f.param)).collect();
    let names: Vec<&str> = free.iter().map(|f| f.spec().toml).collect();
    let unc = stats::uncertainty(&j, rss, &values, &names);

    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("creating the output directory {}", a.out.display()))?;
    let toml = fitted.to_toml_string();
    if Params::from_toml_str(&toml)? != fitted {
        anyhow::bail!("the fitted parameter set does not read back from its TOML text");
    }
    write(&a.out.join("fitted.toml"), &toml)?;
    let report = Report {
        free: &free,
        data: &data,
        fitted: &fitted,
        initial: &initial,
        start: &start,
        values: &values,
        unc: &unc,
        outcome: &outcome,
        modelled: &modelled,
        rms: (rss / n as f64).sqrt(),
    };
    let text = serde_json::to_string_pretty(&report.json())? + "\n";
    write(&a.out.join("report.json"), &text)?;
    plot(
        &a.out.join("fit.png"),
        &data,
        &fit.curves,
        &modelled,
        &fitted,
    )?;

    if !outcome.converged {
        eprintln!("warning: the fit did not converge: {}", outcome.reason);
    }
    for (f, why) in free.iter().zip(&unc.undetermined) {
        if let Some(why) = why {
            eprintln!(
                "warning: the data cannot determine {}: {why}",
                f.spec().toml
            );
        }
    }
    let unconverged = modelled.iter().filter(|m| !m.converged).count();
    if unconverged > 0 {
        eprintln!(
            "warning: {unconverged} of {} solves at the fitted parameters did not converge",
            modelled.len()
        );
    }
    Ok(())
}

/// Writes one output file; the error names it.
fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}

/// The contents of report.json.
struct Report<'a> {
    free: &'a [Free],
    data: &'a Data,
    fitted: &'a Params,
    initial: &'a [f64],
    start: &'a [f64],
    values: &'a [f64],
    unc: &'a stats::Uncertainty,
    outcome: &'a solve::Outcome,
    modelled: &'a [Modelled],
    rms: f64,
}

/// The JSON key of a measured quantity: `point`'s key of the model value it is compared with.
fn json_key(m: Measured) -> &'static str {
    match m {
        Measured::TractionCoefficient => "traction_coefficient",
        Measured::ForceX => "force_x",
        Measured::ForceY => "force_y",
    }
}

impl Report<'_> {
    fn json(&self) -> Value {
        let mut parameters = Map::new();
        for (k, f) in self.free.iter().enumerate() {
            let s = f.spec();
            let (lower, upper) = f.map.bounds();
            parameters.insert(
                s.toml.into(),
                json!({
                    "value": self.values[k],
                    "initial": self.initial[k],
                    "start": self.start[k],
                    "std_error": self.unc.std_error[k],
                    "lower": lower,
                    "upper": if upper.is_finite() { Some(upper) } else { None },
                    "unit": s.unit.symbol(),
                    "determined": self.unc.undetermined[k].is_none(),
                    "undetermined_because": self.unc.undetermined[k],
                    "fmu_variable": s.fmu.map(|v| v.name),
                }),
            );
        }
        let keys: Vec<&str> = self.free.iter().map(|f| f.spec().toml).collect();
        let undetermined: Vec<&str> = keys
            .iter()
            .zip(&self.unc.undetermined)
            .filter(|(_, w)| w.is_some())
            .map(|(k, _)| *k)
            .collect();
        let points: Vec<Value> = self
            .data
            .rows
            .iter()
            .zip(self.modelled)
            .map(|(row, m)| self.point(row, m))
            .collect();
        json!({
            "rms": self.rms,
            "residual_count": self.data.rows.len() * self.data.measured.len(),
            "free": keys,
            "parameters": parameters,
            "correlation": { "keys": keys, "matrix": self.unc.correlation },
            "undetermined": undetermined,
            "converged": self.outcome.converged,
            "termination": self.outcome.reason,
            "evaluations": self.outcome.evaluations,
            "unconverged_solves": self.modelled.iter().filter(|m| !m.converged).count(),
            "fmu_parameters": fmu_parameters(self.fitted),
            "not_in_fmu": not_in_fmu(self.fitted),
            "points": points,
        })
    }

    /// One data row: its line, inputs, weight, and per measured column the measured and model values and
    /// the residual model − measured (in the column's unit).
    fn point(&self, row: &Row, m: &Modelled) -> Value {
        let mut v = Map::new();
        v.insert("line".into(), row.line.into());
        let p = serde_json::to_value(row.point).expect("an operating point serialises");
        v.extend(p.as_object().expect("object").clone());
        let g = row.geometry.of(self.fitted);
        match g.semi_axes {
            Some([a, b]) => {
                v.insert("semi_axis_a".into(), a.into());
                v.insert("semi_axis_b".into(), b.into());
            }
            None => {
                v.insert("curvature_x".into(), g.curvature_x.into());
                v.insert("curvature_y".into(), g.curvature_y.into());
            }
        }
        v.insert("weight".into(), row.weight.into());
        v.insert("converged".into(), m.converged.into());
        for ((q, measured), model) in self.data.measured.iter().zip(&row.values).zip(&m.values) {
            v.insert(
                json_key(*q).into(),
                json!({ "measured": measured, "model": model, "residual": model - measured }),
            );
        }
        Value::Object(v)
    }
}

/// The FMU's parameter values that reproduce `params` in its mode 2 (exact; the FMU takes its parameters
/// by variable, not from a file): every scalar parameter the FMU exposes by its FMU name, the square grid
/// as `grid_size` and the tangential solver as `tangential` (0 FASTSIM, 1 exact).
fn fmu_parameters(params: &Params) -> Map<String, Value> {
    let mut m: Map<String, Value> = Param::ALL
        .into_iter()
        .filter_map(|p| {
            p.spec()
                .fmu
                .map(|v| (v.name.to_string(), params.get(p).into()))
        })
        .collect();
    if params.grid.nx == params.grid.ny {
        m.insert("grid_size".into(), params.grid.nx.into());
    }
    let tangential = match params.tangential {
        Tangential::Fastsim => 0,
        Tangential::Exact => 1,
    };
    m.insert("tangential".into(), tangential.into());
    m
}

/// The keys of `params` away from their defaults that the FMU has no variable for (they reach it only through
/// `parameter_file`): scalar keys (the grid when it is not square), the friction law, the pressure, heating and
/// prescribed semi-axes.
fn not_in_fmu(params: &Params) -> Vec<&'static str> {
    let defaults = Params::default();
    let square = params.grid.nx == params.grid.ny;
    let mut keys: Vec<&'static str> = Param::ALL
        .into_iter()
        .filter(|&p| p.spec().fmu.is_none() && params.get(p) != defaults.get(p))
        .filter(|&p| !(square && matches!(p, Param::GridNx | Param::GridNy)))
        .map(|p| p.spec().toml)
        .collect();
    for (key, differs) in [
        ("friction.law", params.friction.law != defaults.friction.law),
        ("pressure", params.pressure != defaults.pressure),
        ("solver.heat", params.solver.heat != defaults.solver.heat),
        // the FMU takes prescribed semi-axes as inputs of each step
        ("geometry.semi_axes", params.geometry.semi_axes.is_some()),
    ] {
        if differs {
            keys.push(key);
        }
    }
    keys
}

/// The creepage a curve sweeps: the first of ξ, η, φ that changes along it (ξ for a single point).
fn swept(rows: &[&Row]) -> usize {
    let c = |r: &Row, k: usize| [r.point.creepage_x, r.point.creepage_y, r.point.spin][k];
    (0..3)
        .find(|&k| rows.iter().any(|r| c(r, k) != c(rows[0], k)))
        .unwrap_or(0)
}

/// fit.png: per curve and measured column the data as points and the fitted model as a line, against
/// the swept creepage; forces as F/F_N.
fn plot(
    path: &Path,
    data: &Data,
    curves: &[Vec<usize>],
    modelled: &[Modelled],
    fitted: &Params,
) -> Result<()> {
    const LABELS: [&str; 3] = [
        "longitudinal creepage ξ [-]",
        "lateral creepage η [-]",
        "spin φ [1/m]",
    ];
    let (mut measured, mut model) = (Vec::new(), Vec::new());
    let mut sweeps = Vec::new();
    for curve in curves {
        let rows: Vec<&Row> = curve.iter().map(|&k| &data.rows[k]).collect();
        let k = swept(&rows);
        sweeps.push(k);
        for (c, q) in data.measured.iter().enumerate() {
            let at = |r: &Row| [r.point.creepage_x, r.point.creepage_y, r.point.spin][k];
            let p = &rows[0].point;
            let label = format!(
                "{}, F_N = {} kN, V = {} m/s, w = {}",
                match q {
                    Measured::TractionCoefficient => "f",
                    Measured::ForceX => "F_x/F_N",
                    Measured::ForceY => "F_y/F_N",
                },
                p.normal_force / 1e3,
                p.speed,
                p.wetness
            );
            measured.push(Series {
                label: label.clone(),
                points: curve
                    .iter()
                    .map(|&i| {
                        let r = &data.rows[i];
                        (at(r), r.values[c] / q.scale(&r.point))
                    })
                    .collect(),
            });
            model.push(Series {
                label,
                points: curve
                    .iter()
                    .map(|&i| {
                        let r = &data.rows[i];
                        (at(r), modelled[i].values[c] / q.scale(&r.point))
                    })
                    .collect(),
            });
        }
    }
    sweeps.sort_unstable();
    sweeps.dedup();
    let x_label = match sweeps.as_slice() {
        [k] => LABELS[*k],
        _ => "creepage ξ, η [-] or spin φ [1/m]",
    };
    let title = format!(
        "Fit: data (points) and fitted model (lines), {}",
        fitted.friction.law
    );
    data_and_lines_chart(
        path,
        &Chart {
            title: &title,
            x_label,
            y_label: "traction coefficient [-]",
        },
        &measured,
        &model,
    )
}

/// The Jacobian `j` with respect to the mapped variables `u` as the Jacobian with respect to the
/// parameters in their own units (the chain rule: each column divided by dθ/du).
fn in_units(mut j: DMatrix<f64>, free: &[Free], u: &[f64]) -> DMatrix<f64> {
    for (k, f) in free.iter().enumerate() {
        let slope = f.map.slope(u[k]);
        j.column_mut(k).apply(|x| *x /= slope);
    }
    j
}
