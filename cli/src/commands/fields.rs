//! `wheelrail fields`: local fields of one operating point as CSV and heat maps.

use super::{ModelArgs, solve_reporting};
use anyhow::{Result, anyhow};
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use wheelrail::solver::Fields;
use wheelrail_cli::plot::heat_map;

/// Arguments of `wheelrail fields`.
#[derive(Debug, Args)]
pub struct FieldsArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// Write the CSV to this file instead of standard output.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Write one heat map (PNG) per field into this directory.
    #[arg(long, value_name = "DIR")]
    plot: Option<PathBuf>,
}

/// The columns of the fields CSV: name, unit, value per cell.
pub fn columns(f: &Fields) -> Vec<(&'static str, &'static str, Vec<f64>)> {
    let g = &f.grid;
    let v2 = |v: &[[f64; 2]], k: usize| v.iter().map(|p| p[k]).collect::<Vec<f64>>();
    let norm = |v: &[[f64; 2]]| v.iter().map(|p| p[0].hypot(p[1])).collect::<Vec<f64>>();
    vec![
        ("x", "m", g.cells.iter().map(|c| c.x).collect()),
        ("y", "m", g.cells.iter().map(|c| c.y).collect()),
        ("nominal_pressure", "Pa", f.nominal_pressure.clone()),
        ("separation", "m", f.separation.clone()),
        ("area_fraction", "-", f.area_fraction.clone()),
        ("friction_coefficient", "-", f.friction_coefficient.clone()),
        ("adhesion_limit", "Pa", f.adhesion_limit.clone()),
        ("traction_x", "Pa", v2(&f.traction, 0)),
        ("traction_y", "Pa", v2(&f.traction, 1)),
        ("traction", "Pa", norm(&f.traction)),
        ("slip_velocity_x", "m/s", v2(&f.slip_velocity, 0)),
        ("slip_velocity_y", "m/s", v2(&f.slip_velocity, 1)),
        ("slip_velocity", "m/s", norm(&f.slip_velocity)),
        ("heat_flux", "W/m^2", f.heat_flux.clone()),
        ("heat_flux_wheel", "W/m^2", f.heat_flux_wheel.clone()),
        ("temperature", "K", f.temperature.clone()),
        (
            "slipping",
            "-",
            f.slipping.iter().map(|s| f64::from(u8::from(*s))).collect(),
        ),
        ("fluid_pressure", "Pa", f.fluid_pressure.clone()),
        (
            "nominal_metal_pressure",
            "Pa",
            f.nominal_metal_pressure.clone(),
        ),
        ("metal_pressure", "Pa", f.metal_pressure.clone()),
        ("cell_height", "m", f.cell_height.clone()),
        ("metal_height", "m", f.metal_height.clone()),
        ("fluid_height", "m", f.fluid_height.clone()),
        (
            "failure_stress_factor",
            "-",
            f.failure_stress_factor.clone(),
        ),
        (
            "regime",
            "0 dry, 1 boundary, 2 mixed",
            f.regime.iter().map(|r| f64::from(r.code())).collect(),
        ),
        ("void_height", "m", f.void_height.clone()),
    ]
}

/// Runs `wheelrail fields`.
pub fn run(a: &FieldsArgs) -> Result<()> {
    let params = a.model.params()?;
    let pt = a.model.point()?;
    let s = solve_reporting(&params, &pt)?;
    let f = s
        .fields
        .ok_or_else(|| anyhow!("the {} law has no local fields", params.friction.law))?;
    let cols = columns(&f);
    let mut out: Box<dyn Write> = match &a.out {
        Some(p) => Box::new(std::io::BufWriter::new(std::fs::File::create(p)?)),
        None => Box::new(std::io::stdout().lock()),
    };
    let header: Vec<&str> = cols.iter().map(|c| c.0).collect();
    writeln!(out, "{}", header.join(","))?;
    for k in 0..f.grid.len() {
        let row: Vec<String> = cols.iter().map(|c| format!("{:e}", c.2[k])).collect();
        writeln!(out, "{}", row.join(","))?;
    }
    out.flush()?;
    if let Some(dir) = &a.plot {
        std::fs::create_dir_all(dir)?;
        for (name, unit, values) in cols.iter().skip(2) {
            let title = format!("{name} [{unit}]");
            heat_map(
                &dir.join(format!("{name}.png")),
                &title,
                unit,
                &f.grid,
                values,
            )?;
        }
    }
    Ok(())
}
