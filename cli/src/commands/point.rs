//! `wheelrail point`: one operating point, evaluated by the library's evaluation policy
//! ([`wheelrail::model::Evaluator`], as in the FMU): by the exact solver, by a lookup table, or by the table
//! where usable and else exactly; rolling backwards and a lifted wheel included.

use super::{ModelArgs, solution_json, warn_unconverged};
use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use std::path::PathBuf;
use std::sync::Arc;
use wheelrail::model::{
    Evaluated, Evaluation, Evaluator, Fallback, FallbackGrid, Mode, Notice, Policy,
};
use wheelrail::table::Table;
use wheelrail::{Error, Model, OperatingPoint};

/// Standstill regularisation of `point` [m/s]: the smallest rolling speed the model accepts
/// (`OperatingPoint::validate`), so that every speed it accepts is evaluated as given.
pub(super) const MINIMUM_SPEED: f64 = 1e-6;

/// Evaluation modes on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum ModeArg {
    /// The table of --table where it was built for these parameters and the point lies inside its
    /// ranges, else the exact solver (with a warning).
    Auto,
    /// Only the table of --table: outside its ranges the point is clamped to them (with a warning);
    /// parameters other than the table's are an error.
    Table,
    /// Only the exact solver.
    Exact,
}

impl From<ModeArg> for Mode {
    fn from(m: ModeArg) -> Mode {
        match m {
            ModeArg::Auto => Mode::Auto,
            ModeArg::Table => Mode::TableOnly,
            ModeArg::Exact => Mode::ExactOnly,
        }
    }
}

/// Arguments of `wheelrail point`.
#[derive(Debug, Args)]
pub struct PointArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Print one JSON object (SI units, kelvin) instead of a table.
    #[arg(long)]
    json: bool,
    /// Evaluate by interpolation in the lookup table in DIR (built for the same parameters) instead of
    /// the exact solver (everywhere, or only where usable: see --mode); repeated, several tables, each
    /// point by the first that covers its contact and holds it inside its ranges.
    #[arg(long, value_name = "DIR")]
    table: Vec<PathBuf>,
    /// How the point is evaluated [default: table with --table, else exact]; auto and table need --table.
    #[arg(long, value_enum)]
    mode: Option<ModeArg>,
}

/// Runs `wheelrail point`.
pub fn run(a: &PointArgs) -> Result<()> {
    let model = Model::new(a.model.params()?)?;
    let input = a.model.input()?;
    let mode = match a.mode {
        Some(m) => m.into(),
        None if a.table.is_empty() => Mode::ExactOnly,
        None => Mode::TableOnly,
    };
    if mode != Mode::ExactOnly && a.table.is_empty() {
        return Err(Error::NoTable { mode }).context("give --table DIR, or --mode exact");
    }
    let tables = match mode {
        Mode::ExactOnly => Vec::new(),
        _ => a
            .table
            .iter()
            .map(|dir| Table::load(dir).map(Arc::new))
            .collect::<wheelrail::Result<Vec<_>>>()?,
    };
    let policy = Policy {
        minimum_speed: MINIMUM_SPEED,
        // a grid on the command line is the fallback's grid too (a parameter file's other than the
        // default grid is, by the library's rule)
        fallback_grid: match a.model.sets_grid() {
            true => FallbackGrid::Model,
            false => FallbackGrid::PerContact,
        },
        ..Policy::default()
    };
    let evaluator = Evaluator::with_tables(model, mode, tables, policy)?;
    let e = evaluator
        .evaluate(&input, None, &mut None)
        .or_else(|e| match e {
            Error::TableParameters { .. } => Err(e).context(
                "give the parameter file and flags the table was built with, or drop --table",
            ),
            Error::OutOfRange { .. } => Err(e.into()),
            _ => Err(e).context("solving the operating point"),
        })?;
    warn(&evaluator, &e);
    let v = json(&evaluator, &input, &e)?;
    if a.json {
        println!("{v}");
    } else {
        for (k, val) in v.as_object().expect("object") {
            println!("{k:>28}  {val}");
        }
    }
    Ok(())
}

/// Warns on stderr about the evaluation's notices and unconverged results.
fn warn(evaluator: &Evaluator, e: &Evaluation) {
    for n in e.notices.iter() {
        match n {
            Notice::FellBack(Fallback::OutsideRanges) => eprintln!(
                "warning: the point lies outside the table's ranges; the exact solver evaluates it"
            ),
            Notice::FellBack(Fallback::Unresolved) => eprintln!(
                "warning: the point lies in a table cell across which the model jumps (a wet contact losing its film: T_max of a hot one, or where metal begins to cover the contact); the exact solver evaluates it"
            ),
            Notice::FellBack(Fallback::UnconvergedNodes) => eprintln!(
                "warning: the table interpolates the point from points that did not converge when it was built; the exact solver evaluates it"
            ),
            Notice::FellBack(Fallback::OtherParameters) => eprintln!(
                "warning: the table at {} was built for other parameters; the exact solver evaluates the point",
                evaluator.table_locations()
            ),
            Notice::FellBack(Fallback::OtherGeometry) => eprintln!(
                "warning: the table at {} was built for another contact geometry; the exact solver evaluates the point",
                evaluator.table_locations()
            ),
            Notice::Clamped => eprintln!(
                "warning: the point lies outside the table's ranges; each coordinate was clamped to its range"
            ),
            Notice::WetnessClamped { given, used } => {
                eprintln!("warning: wetness {given} is outside [0, 1] and was clamped to {used}")
            }
        }
    }
    match &e.by {
        Evaluated::Exact(x) => warn_unconverged(&x.report),
        Evaluated::Table(o) if !o.converged => eprintln!(
            "warning: the interpolation used table points whose exact solution did not converge"
        ),
        _ => {}
    }
}

/// The JSON object of an evaluation: by the exact solver its global results and report, by table the
/// keys of the exact point that a table provides plus `in_range`, for a lifted wheel the outputs; each
/// with `evaluation` ("exact", "table", "lifted").
fn json(
    evaluator: &Evaluator,
    input: &OperatingPoint,
    e: &Evaluation,
) -> Result<serde_json::Value> {
    let params = evaluator.model().params();
    let (mut v, by) = match &e.by {
        Evaluated::Exact(x) => {
            let mut v = solution_json(params, &x.global, &x.report);
            // the grid it was solved on: mode auto's fallback grid may differ from the parameters'
            v["grid_cells"] = serde_json::json!(x.cells);
            (v, "exact")
        }
        Evaluated::Table(o) => (super::table::point_json(params, input, o)?, "table"),
        Evaluated::Lifted(o) => {
            let mut v = serde_json::json!({
                "force_x": o.force_x,
                "force_y": o.force_y,
                "spin_moment": o.spin_moment,
                "traction_coefficient": o.traction_coefficient,
                "normal_force": input.normal_force,
                "max_temperature": o.max_temperature,
                "fluid_load_fraction": o.fluid_load_fraction,
                "converged": o.converged,
            });
            v.as_object_mut()
                .expect("object")
                .extend(super::methods_json(params));
            (v, "lifted")
        }
    };
    v.as_object_mut()
        .expect("object")
        .insert("evaluation".into(), by.into());
    Ok(v)
}
