//! `wheelrail point`: one operating point.

use super::{ModelArgs, solution_json, solve_reporting};
use anyhow::Result;
use clap::Args;

/// Arguments of `wheelrail point`.
#[derive(Debug, Args)]
pub struct PointArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Print one JSON object (SI units, kelvin) instead of a table.
    #[arg(long)]
    json: bool,
}

/// Runs `wheelrail point`.
pub fn run(a: &PointArgs) -> Result<()> {
    let params = a.model.params()?;
    let pt = a.model.point()?;
    let s = solve_reporting(&params, &pt)?;
    let v = solution_json(&params, &s);
    if a.json {
        println!("{v}");
    } else {
        for (k, val) in v.as_object().expect("object") {
            println!("{k:>28}  {val}");
        }
    }
    Ok(())
}
