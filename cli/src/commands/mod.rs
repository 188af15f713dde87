//! Command-line argument definitions and dispatch.

mod curve;
mod fields;
mod fit;
mod parameters;
mod plan;
mod point;
mod reproduce;
mod table;

use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use wheelrail::params::spec::Spec;
use wheelrail::params::{Input, Key, Param};
use wheelrail::solver::{GlobalResults, SolverReport};
use wheelrail::table::Storage;
use wheelrail::{FrictionLaw, OperatingPoint, Params, Pressure, Tangential};

/// Wheel–rail friction after Tomberger et al. (Wear 271, 2011): exact coupled solver.
#[derive(Debug, Parser)]
#[command(name = "wheelrail", version, about)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Evaluate one operating point and print the global results.
    Point(point::PointArgs),
    /// Sweep one creepage and write the traction–creepage curve (CSV or JSON lines, optional plot).
    Curve(curve::CurveArgs),
    /// Write the local fields of one operating point as CSV (optional heat maps).
    Fields(fields::FieldsArgs),
    /// Reproduce the paper's result figures (Figs. 5, 7, 10–21) as CSV, PNG and SVG.
    Reproduce(reproduce::ReproduceArgs),
    /// Build, merge, verify and describe lookup tables of the model (tabulation mode).
    Table(table::TableArgs),
    /// Fit scalar parameters to measured traction–creepage curves (bounded least squares): writes
    /// fitted.toml, report.json (values, standard errors, correlations, residuals) and fit.png.
    Fit(fit::FitArgs),
    /// Print the specification of the parameters and operating-point inputs: keys, units, ranges,
    /// defaults, flags and FMU variables (as text, JSON or the Markdown of docs/parameters.md).
    Parameters(parameters::ParametersArgs),
}

/// Friction law names on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum LawArg {
    /// The Tomberger et al. model.
    Tomberger,
    /// FASTSIM with a constant friction coefficient (--mu).
    Constant,
    /// Polach's closed form.
    Polach,
}

/// Table storage names on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum StorageArg {
    /// Little-endian f32 arrays (4 bytes per value).
    F32,
    /// 16-bit codes with a per-array offset and step (2 bytes per value; rounding ≤ range/131 070: about
    /// 1e-5 of F/F_N, 0.01 K of T_max).
    U16,
    /// The u16 codes compressed (differences along φ̂ and V, zlib): the same values in about a third of the
    /// bytes of u16.
    U16z,
    /// The predicted u16 codes compressed by xz (LZMA2) instead of zlib: about 40 % fewer bytes than u16z,
    /// slower to write and to read.
    U16x,
}

impl From<StorageArg> for Storage {
    fn from(s: StorageArg) -> Storage {
        match s {
            StorageArg::F32 => Storage::F32,
            StorageArg::U16 => Storage::U16,
            StorageArg::U16z => Storage::U16z,
            StorageArg::U16x => Storage::U16x,
        }
    }
}

/// Tangential solver names on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum TangentialArg {
    /// FASTSIM, Kalker's simplified theory.
    Fastsim,
    /// Kalker's exact steady-rolling theory.
    Exact,
}

impl From<TangentialArg> for Tangential {
    fn from(t: TangentialArg) -> Tangential {
        match t {
            TangentialArg::Fastsim => Tangential::Fastsim,
            TangentialArg::Exact => Tangential::Exact,
        }
    }
}

/// Normal pressure names on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum PressureArg {
    /// Hertz's ellipsoid with --tangential exact, the parabola with FASTSIM.
    Auto,
    /// Hertz's ellipsoidal pressure.
    Hertz,
    /// The parabola with the same force.
    Parabolic,
}

/// The operating point and the model options shared by all subcommands.
#[derive(Debug, Args, Clone)]
pub struct ModelArgs {
    #[command(flatten)]
    values: ValueFlags,
    /// Local friction law [default: tomberger, or the parameter file's].
    #[arg(long, value_enum)]
    friction_law: Option<LawArg>,
    /// Tangential contact solver [default: fastsim, or the parameter file's].
    #[arg(long, value_enum)]
    tangential: Option<TangentialArg>,
    /// Nominal normal pressure [default: auto (hertz with exact, parabolic with fastsim), or the
    /// parameter file's].
    #[arg(long, value_enum)]
    pressure: Option<PressureArg>,
    /// Gap curvatures A,B [1/m] (along x, along y).
    #[arg(long, value_name = "A,B", conflicts_with = "semi_axes")]
    curvatures: Option<String>,
    /// Prescribed semi-axes a,b [m] instead of Hertz from curvatures.
    #[arg(long, value_name = "a,b")]
    semi_axes: Option<String>,
    /// Grid cells NX,NY [default: 30,30].
    #[arg(long, value_name = "NX,NY")]
    grid: Option<String>,
    /// Switch frictional heating off (T = T0 everywhere).
    #[arg(long)]
    no_heat: bool,
    /// Parameter file (TOML); flags override its values.
    #[arg(long, value_name = "FILE.toml")]
    params: Option<PathBuf>,
}

/// The value flags generated from the parameter specification ([`wheelrail::params::spec`]): one
/// `--flag VALUE` per operating-point input and per scalar parameter with a command-line name, each
/// with the row's description, unit, range and default as its help.
#[derive(Debug, Clone, Default)]
struct ValueFlags {
    /// The parameters given on the command line.
    params: Vec<(Param, f64)>,
    /// The operating-point inputs given on the command line.
    inputs: Vec<(Input, f64)>,
}

/// The rows with a flag and the flag: the inputs first, then the parameters.
fn flagged() -> impl Iterator<Item = (&'static Spec, &'static str)> {
    let inputs = Input::ALL.into_iter().map(Input::spec);
    let params = Param::ALL.into_iter().map(Param::spec);
    inputs
        .chain(params)
        .filter_map(|s| s.cli.map(|flag| (s, flag)))
}

/// A number in the shorter of its plain and its exponent form (`0.012`, `2e-5`, `2.1e11`), exact.
pub fn compact(x: f64) -> String {
    let (plain, exponent) = (x.to_string(), format!("{x:e}"));
    if exponent.len() < plain.len() {
        exponent
    } else {
        plain
    }
}

/// The number format of a row's values: whole numbers plain (as a TOML file needs them), others
/// [`compact`].
pub fn number_format(s: &Spec) -> fn(f64) -> String {
    if s.integer {
        |x| x.to_string()
    } else {
        compact
    }
}

/// A unit for help texts and tables: its symbol, `-` when dimensionless.
pub fn unit_text(s: &Spec) -> &'static str {
    match s.unit.symbol() {
        "" => "-",
        u => u,
    }
}

/// The help text of a row's flag: description, unit, range and default.
fn flag_help(s: &Spec) -> String {
    let unit = unit_text(s);
    let fallback = match s.key {
        Key::Param(_) => ", or the parameter file's",
        _ => "",
    };
    format!(
        "{} [{unit}; {}] [default: {}{fallback}]",
        s.description,
        s.range.bounds_with(number_format(s)),
        number_format(s)(s.default)
    )
}

impl clap::FromArgMatches for ValueFlags {
    fn from_arg_matches(m: &clap::ArgMatches) -> std::result::Result<Self, clap::Error> {
        let mut v = ValueFlags::default();
        v.update_from_arg_matches(m)?;
        Ok(v)
    }

    fn update_from_arg_matches(
        &mut self,
        m: &clap::ArgMatches,
    ) -> std::result::Result<(), clap::Error> {
        let given = |s: &Spec| s.cli.and_then(|flag| m.get_one::<f64>(flag).copied());
        for i in Input::ALL {
            if let Some(x) = given(i.spec()) {
                self.inputs.retain(|(j, _)| *j != i);
                self.inputs.push((i, x));
            }
        }
        for p in Param::ALL {
            if let Some(x) = given(p.spec()) {
                self.params.retain(|(q, _)| *q != p);
                self.params.push((p, x));
            }
        }
        Ok(())
    }
}

impl Args for ValueFlags {
    fn augment_args(cmd: clap::Command) -> clap::Command {
        flagged().fold(cmd, |cmd, (s, flag)| {
            cmd.arg(
                clap::Arg::new(flag)
                    .long(flag)
                    .value_name("VALUE")
                    .value_parser(clap::value_parser!(f64))
                    .allow_hyphen_values(true)
                    .help(flag_help(s)),
            )
        })
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

fn pair(name: &str, text: &str) -> Result<[f64; 2]> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != 2 {
        bail!(wheelrail::Error::OutOfRange {
            name: name.into(),
            value: text.into(),
            allowed: "two comma-separated numbers".into()
        });
    }
    let mut out = [0.0; 2];
    for (o, p) in out.iter_mut().zip(parts) {
        *o = p.parse::<f64>().map_err(|_| wheelrail::Error::OutOfRange {
            name: name.into(),
            value: text.into(),
            allowed: "two comma-separated numbers".into(),
        })?;
    }
    Ok(out)
}

/// Parses a grid "NX,NY": two whole numbers in the ranges of `grid.nx` and `grid.ny` (4 ..= 400).
pub fn grid_arg(text: &str) -> Result<(usize, usize)> {
    let [nx, ny] = pair("grid", text)?;
    for (name, row, v) in [
        ("grid (NX)", Param::GridNx, nx),
        ("grid (NY)", Param::GridNy, ny),
    ] {
        let range = row.spec().range;
        if v.fract() != 0.0 || !range.contains(v) {
            bail!(wheelrail::Error::out_of_range(
                name,
                v,
                &format!("whole number {}", range.bounds())
            ));
        }
    }
    Ok((nx as usize, ny as usize))
}

impl ModelArgs {
    /// Whether the command line sets the grid (`--grid` or `--grid-accuracy`): then mode auto solves the
    /// points no table serves on it too, not on the per-contact fallback grid.
    pub fn sets_grid(&self) -> bool {
        self.grid.is_some()
            || self
                .values
                .params
                .iter()
                .any(|(key, _)| *key == Param::GridAccuracy)
    }

    /// The parameter set: defaults, then the parameter file, then the flags; validated.
    pub fn params(&self) -> Result<Params> {
        let mut p = match &self.params {
            Some(path) => Params::from_toml_file(path)?,
            None => Params::default(),
        };
        for &(key, x) in &self.values.params {
            p.set(key, x);
        }
        if let Some(law) = self.friction_law {
            p.friction.law = match law {
                LawArg::Tomberger => FrictionLaw::Tomberger,
                LawArg::Constant => FrictionLaw::Constant,
                LawArg::Polach => FrictionLaw::Polach,
            };
        }
        if let Some(t) = self.tangential {
            p.tangential = t.into();
        }
        if let Some(shape) = self.pressure {
            p.pressure = match shape {
                PressureArg::Auto => Pressure::Auto,
                PressureArg::Hertz => Pressure::Hertz,
                PressureArg::Parabolic => Pressure::Parabolic,
            };
        }
        if let Some(c) = &self.curvatures {
            let [a, b] = pair("curvatures", c)?;
            p.geometry.curvature_x = a;
            p.geometry.curvature_y = b;
            p.geometry.semi_axes = None;
        }
        if let Some(s) = &self.semi_axes {
            p.geometry.semi_axes = Some(pair("semi-axes", s)?);
        }
        if let Some(g) = &self.grid {
            (p.grid.nx, p.grid.ny) = grid_arg(g)?;
        }
        if self.no_heat {
            p.solver.heat = false;
        }
        p.validate()?;
        Ok(p)
    }

    /// The operating point: defaults, then the flags; validated.
    pub fn point(&self) -> Result<OperatingPoint> {
        let pt = self.given();
        pt.validate()?;
        Ok(pt)
    }

    /// The operating point as given by the flags (defaults for those not given), not validated.
    fn given(&self) -> OperatingPoint {
        let mut pt = OperatingPoint::default();
        for &(key, x) in &self.values.inputs {
            pt.set(key, x);
        }
        pt
    }

    /// The operating point for the evaluation policy ([`wheelrail::model::Evaluator`]), in the frame of the
    /// flags: the rolling speed may be negative (rolling backwards) or zero, a normal force of at most
    /// 1 mN lifts the wheel. A negative load and a wetness outside [0, 1] are refused here (the policy
    /// would lift the wheel and clamp the wetness); the policy checks the rest of a point it evaluates.
    pub fn input(&self) -> Result<OperatingPoint> {
        let pt = self.given();
        if pt.normal_force.is_nan() || pt.normal_force < 0.0 {
            bail!(Key::Input(Input::NormalForce).invalid(
                pt.normal_force,
                "finite, >= 0 N (at most 1e-3 N: a lifted wheel)".into()
            ));
        }
        Input::Wetness.spec().check(pt.wetness)?;
        Ok(pt)
    }
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Point(a) => point::run(&a),
        Command::Curve(a) => curve::run(&a),
        Command::Fields(a) => fields::run(&a),
        Command::Reproduce(a) => reproduce::run(&a),
        Command::Table(a) => table::run(&a),
        Command::Fit(a) => fit::run(&a),
        Command::Parameters(a) => parameters::run(&a),
    }
}

/// Exit code of an error: 2 for invalid input (values, parameter files), 1 otherwise.
pub fn exit_code(e: &anyhow::Error) -> u8 {
    if e.downcast_ref::<plan::ContactsError>().is_some()
        || e.downcast_ref::<fit::FitInputError>().is_some()
    {
        return 2;
    }
    match e.downcast_ref::<wheelrail::Error>() {
        Some(
            wheelrail::Error::OutOfRange { .. }
            | wheelrail::Error::Invalid { .. }
            | wheelrail::Error::ParameterFile { .. }
            | wheelrail::Error::NoTable { .. },
        ) => 2,
        _ => 1,
    }
}

/// Solves and warns on stderr when the coupled iteration did not converge.
pub fn solve_reporting(params: &Params, pt: &OperatingPoint) -> Result<wheelrail::Solution> {
    let s = wheelrail::solve(params, pt).context("solving the operating point")?;
    warn_unconverged(&s.report);
    Ok(s)
}

/// Warns on stderr when the coupled iteration of a solve did not converge, naming the solver that
/// limited it.
pub fn warn_unconverged(report: &SolverReport) {
    if let Some(limiter) = report.termination.limited_by() {
        eprintln!(
            "warning: not converged after {} iterations (residual {:.3e}, limited by the {limiter} solver)",
            report.iterations, report.residual
        );
    }
}

/// The model's methods as JSON keys: `friction_law`, `tangential` ("fastsim" or "exact") and `pressure`
/// (the pressure used: "parabolic" or "hertz"), `grid_cells` ([nx, ny] of the contact grid).
pub fn methods_json(params: &Params) -> serde_json::Map<String, serde_json::Value> {
    let mut m = serde_json::Map::new();
    m.insert(
        "friction_law".into(),
        params.friction.law.to_string().into(),
    );
    m.insert("tangential".into(), params.tangential.to_string().into());
    m.insert(
        "pressure".into(),
        params.pressure_shape().to_string().into(),
    );
    // the cells [nx, ny] of the contact grid (chosen by `grid.accuracy` when set)
    m.insert("grid_cells".into(), serde_json::json!(params.grid.cells()));
    m
}

/// The JSON object of a solution: global results, convergence report and the model's methods
/// ([`methods_json`]).
pub fn solution_json(
    params: &Params,
    global: &GlobalResults,
    report: &SolverReport,
) -> serde_json::Value {
    let mut v = serde_json::to_value(global).expect("global results serialise");
    let r = serde_json::to_value(report).expect("report serialises");
    let obj = v.as_object_mut().expect("global results are an object");
    if let serde_json::Value::Object(rm) = r {
        obj.extend(rm);
    }
    obj.extend(methods_json(params));
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::{CommandFactory, Parser};

    #[derive(Debug, Parser)]
    struct Model {
        #[command(flatten)]
        model: ModelArgs,
    }

    fn parse(args: &[&str]) -> ModelArgs {
        let argv = std::iter::once("wheelrail").chain(args.iter().copied());
        Model::try_parse_from(argv).unwrap().model
    }

    /// A valid value of a row other than its default.
    fn other_value(s: &Spec) -> f64 {
        [0.5, 1.5, 0.9, 1.01]
            .map(|f| s.default * f)
            .into_iter()
            .chain([0.5, -0.5, 1.0, 0.05, 1e-4])
            .find(|&x| x != s.default && s.range.contains(x))
            .unwrap()
    }

    #[test]
    fn the_command_line_is_well_formed() {
        Cli::command().debug_assert();
    }

    #[test]
    fn every_flag_of_the_specification_sets_its_row_over_the_parameter_file() {
        let file =
            std::env::temp_dir().join(format!("wheelrail-flags-{}.toml", std::process::id()));
        for (s, flag) in flagged() {
            let x = other_value(s);
            let given = parse(&[&format!("--{flag}"), &format!("{x:?}")]);
            match s.key {
                Key::Param(p) => {
                    assert_eq!(given.params().unwrap().get(p), x, "--{flag}");
                    // the flag overrides the parameter file, which overrides the default
                    let mut in_file = Params::default();
                    in_file.set(p, x);
                    std::fs::write(&file, in_file.to_toml_string()).unwrap();
                    let path = file.to_str().unwrap();
                    assert_eq!(parse(&["--params", path]).params().unwrap().get(p), x);
                    let both = parse(&[
                        "--params",
                        path,
                        &format!("--{flag}"),
                        &s.default.to_string(),
                    ]);
                    assert_eq!(both.params().unwrap().get(p), s.default, "--{flag}");
                    assert_eq!(given.point().unwrap(), OperatingPoint::default());
                }
                Key::Input(i) => {
                    assert_eq!(given.point().unwrap().get(i), x, "--{flag}");
                    assert_eq!(given.params().unwrap(), Params::default());
                }
                Key::SemiAxisA | Key::SemiAxisB => panic!("the semi-axes have no row"),
            }
            // out of range: the error names the row's key
            let bad = parse(&[&format!("--{flag}"), "NaN"]);
            let e = match s.key {
                Key::Param(_) => bad.params().unwrap_err(),
                _ => bad.point().unwrap_err(),
            };
            assert!(
                matches!(e.downcast_ref(), Some(wheelrail::Error::Invalid { key, .. }) if *key == s.key),
                "{e}"
            );
        }
        let _ = std::fs::remove_file(file);
    }

    #[test]
    fn the_help_of_every_flag_states_its_unit_range_and_default() {
        let help = Model::command().render_long_help().to_string();
        for (s, flag) in flagged() {
            let text = flag_help(s);
            assert!(help.contains(&format!("--{flag} <VALUE>")), "--{flag}");
            assert!(help.contains(s.description), "--{flag}");
            assert!(
                text.contains(&format!("[default: {}", compact(s.default))),
                "{text}"
            );
        }
        assert!(flag_help(Input::NormalForce.spec()).ends_with("[N; 1e-3 ..= 1e8] [default: 1e5]"));
        assert!(
            flag_help(Param::FlowResistance.spec())
                .ends_with("[Pa s; > 0] [default: 0.012, or the parameter file's]")
        );
    }
}
