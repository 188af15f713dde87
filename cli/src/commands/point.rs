//! `wheelrail point`: one operating point.

use super::{ModelArgs, solution_json, solve_reporting};
use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `wheelrail point`.
#[derive(Debug, Args)]
pub struct PointArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Print one JSON object (SI units, kelvin) instead of a table.
    #[arg(long)]
    json: bool,
    /// Evaluate by interpolation in the lookup table in DIR (built for the same parameters) instead of
    /// the exact solver.
    #[arg(long, value_name = "DIR")]
    table: Option<PathBuf>,
}

/// Runs `wheelrail point`.
pub fn run(a: &PointArgs) -> Result<()> {
    let params = a.model.params()?;
    let pt = a.model.point()?;
    let v = match &a.table {
        Some(dir) => super::table::point_json(dir, &params, &pt)?,
        None => {
            let mut v = solution_json(&params, &solve_reporting(&params, &pt)?);
            v.as_object_mut()
                .expect("object")
                .insert("evaluation".into(), "exact".into());
            v
        }
    };
    if a.json {
        println!("{v}");
    } else {
        for (k, val) in v.as_object().expect("object") {
            println!("{k:>28}  {val}");
        }
    }
    Ok(())
}
