//! `wheelrail curve`: a traction–creepage curve over one creepage, or the forces over the contact ellipse's
//! shape.

use super::{ModelArgs, solution_json, warn_unconverged};
use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use std::io::Write;
use std::path::PathBuf;
use wheelrail::{Model, OperatingPoint};
use wheelrail_cli::plot::{Chart, Series, line_chart};

/// Which input is swept.
#[derive(Debug, Clone, Copy, ValueEnum, PartialEq)]
pub enum Over {
    /// Longitudinal creepage ξ [-].
    CreepageX,
    /// Lateral creepage η [-].
    CreepageY,
    /// Spin creepage φ [1/m].
    Spin,
    /// Ratio a/b of the contact ellipse's semi-axes [-], at the contact area (so the peak pressure) of the
    /// given geometry and normal force: prescribed semi-axes a = r·b, b = sqrt(a₀·b₀/r).
    SemiAxisRatio,
}

impl Over {
    fn name(self) -> &'static str {
        match self {
            Over::CreepageX => "creepage_x",
            Over::CreepageY => "creepage_y",
            Over::Spin => "spin",
            Over::SemiAxisRatio => "semi_axis_ratio",
        }
    }
}

/// Output format of the curve.
#[derive(Debug, Clone, Copy, ValueEnum, PartialEq)]
pub enum Format {
    /// Comma-separated values with a header line.
    Csv,
    /// One JSON object per line.
    Jsonl,
}

/// Arguments of `wheelrail curve`.
#[derive(Debug, Args)]
pub struct CurveArgs {
    #[command(flatten)]
    model: ModelArgs,
    /// The creepage or contact shape to sweep (the others stay at their flag values).
    #[arg(long, value_enum, default_value = "creepage-x")]
    over: Over,
    /// Start of the sweep.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    min: f64,
    /// End of the sweep (1/m for spin).
    #[arg(long, default_value_t = 0.05, allow_hyphen_values = true)]
    max: f64,
    /// Number of points, evenly spaced from --min to --max.
    #[arg(long, default_value_t = 41)]
    points: usize,
    /// Output format.
    #[arg(long, value_enum, default_value = "csv")]
    format: Format,
    /// Write to this file instead of standard output.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Draw the traction–creepage curve (f against the swept creepage) to FILE.png or FILE.svg.
    #[arg(long, value_name = "FILE")]
    plot: Option<PathBuf>,
}

/// The solutions of `point` for contact ellipses of the ratios a/b in `ratios` with the area of the
/// model's own contact at the point's normal force (docs/model.md §2: the peak pressure stays the same),
/// each solved cold (the grid changes with the shape), in parallel.
fn shapes(
    model: &Model,
    point: &OperatingPoint,
    ratios: &[f64],
) -> Result<Vec<wheelrail::Result<wheelrail::Solution>>> {
    use rayon::prelude::*;
    let h = wheelrail::solver::normal_contact(model.params(), point.normal_force)?;
    let area = h.a * h.b;
    let models = ratios
        .iter()
        .map(|&r| {
            if !(r.is_finite() && r > 0.0) {
                bail!(wheelrail::Error::out_of_range(
                    "semi_axis_ratio",
                    r,
                    "finite and > 0 (give --min and --max)"
                ));
            }
            let b = (area / r).sqrt();
            let mut p = model.params().clone();
            p.geometry.semi_axes = Some([r * b, b]);
            Ok(Model::new(p)?)
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(models.par_iter().map(|m| m.solve(point)).collect())
}

/// Runs `wheelrail curve`.
pub fn run(a: &CurveArgs) -> Result<()> {
    let model = Model::new(a.model.params()?)?;
    let params = model.params();
    let base = a.model.point()?;
    if a.points < 2 || a.points > 10_000 {
        bail!(wheelrail::Error::out_of_range(
            "points",
            a.points as f64,
            "2 ..= 10000"
        ));
    }
    if !(a.min.is_finite() && a.max.is_finite() && a.max != a.min) {
        bail!(wheelrail::Error::out_of_range(
            "max",
            a.max,
            "finite and different from --min"
        ));
    }
    let values: Vec<f64> = (0..a.points)
        .map(|k| a.min + (a.max - a.min) * k as f64 / (a.points - 1) as f64)
        .collect();
    let solutions = if a.over == Over::SemiAxisRatio {
        shapes(&model, &base, &values)?
    } else {
        let points: Vec<OperatingPoint> = values
            .iter()
            .map(|&v| {
                let mut pt = base;
                match a.over {
                    Over::CreepageX => pt.creepage_x = v,
                    Over::CreepageY => pt.creepage_y = v,
                    _ => pt.spin = v,
                }
                pt.validate()?;
                Ok(pt)
            })
            .collect::<Result<_>>()?;
        model.sweep(&points)
    };
    let rows: Vec<Result<serde_json::Value>> = solutions
        .into_iter()
        .zip(&values)
        .map(|(s, &v)| {
            let s = s.context("solving the operating point")?;
            warn_unconverged(&s.report);
            let mut j = solution_json(params, &s.global, &s.report);
            j.as_object_mut()
                .expect("object")
                .insert(a.over.name().into(), v.into());
            Ok(j)
        })
        .collect();
    let rows = rows.into_iter().collect::<Result<Vec<_>>>()?;
    let mut out: Box<dyn Write> = match &a.out {
        Some(p) => Box::new(std::io::BufWriter::new(std::fs::File::create(p)?)),
        None => Box::new(std::io::stdout().lock()),
    };
    match a.format {
        Format::Jsonl => {
            for r in &rows {
                writeln!(out, "{r}")?;
            }
        }
        Format::Csv => {
            let keys: Vec<String> = std::iter::once(a.over.name().to_string())
                .chain(
                    rows[0]
                        .as_object()
                        .expect("object")
                        .keys()
                        .filter(|k| *k != a.over.name())
                        .cloned(),
                )
                .collect();
            writeln!(out, "{}", keys.join(","))?;
            for r in &rows {
                let line: Vec<String> = keys
                    .iter()
                    .map(|k| match &r[k] {
                        serde_json::Value::String(s) => s.clone(),
                        serde_json::Value::Null => String::new(),
                        v => v.to_string(),
                    })
                    .collect();
                writeln!(out, "{}", line.join(","))?;
            }
        }
    }
    out.flush()?;
    if let Some(path) = &a.plot {
        let points = rows
            .iter()
            .zip(&values)
            .map(|(r, v)| (*v, r["traction_coefficient"].as_f64().unwrap_or(f64::NAN)))
            .collect();
        let x_label = match a.over {
            Over::CreepageX => "longitudinal creepage ξ [-]",
            Over::CreepageY => "lateral creepage η [-]",
            Over::Spin => "spin creepage φ [1/m]",
            Over::SemiAxisRatio => "semi-axis ratio a/b [-]",
        };
        let title = format!(
            "Traction–creepage, V = {} m/s, F_N = {} kN, w = {}, {}",
            base.speed,
            base.normal_force / 1e3,
            base.wetness,
            params.friction.law
        );
        line_chart(
            path,
            &Chart {
                title: &title,
                x_label,
                y_label: "traction coefficient f [-]",
            },
            &[Series {
                label: String::new(),
                points,
            }],
        )?;
    }
    Ok(())
}
