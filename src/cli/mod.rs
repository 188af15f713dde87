//! Command-line argument definitions and dispatch.

mod curve;
mod fields;
mod point;
mod reproduce;
mod table;

use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use wheelrail::solver::{GlobalResults, SolverReport};
use wheelrail::{FrictionLaw, OperatingPoint, Params};

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

/// The operating point and the model options shared by all subcommands.
#[derive(Debug, Args, Clone)]
pub struct ModelArgs {
    /// Longitudinal creepage ξ [-].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    creepage_x: f64,
    /// Lateral creepage η [-].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    creepage_y: f64,
    /// Spin creepage φ [1/m].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    spin: f64,
    /// Normal force F_N [N].
    #[arg(long, default_value_t = 100e3, allow_hyphen_values = true)]
    normal_force: f64,
    /// Rolling speed V [m/s].
    #[arg(long, default_value_t = 30.0, allow_hyphen_values = true)]
    speed: f64,
    /// Wetness w ∈ [0, 1] (0 dry, 1 flooded inlet).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    wetness: f64,
    /// Roughness parameter k_r ∈ [0, 1] [default: 0.5, or the parameter file's].
    #[arg(long, allow_hyphen_values = true)]
    roughness: Option<f64>,
    /// Local friction law [default: tomberger, or the parameter file's].
    #[arg(long, value_enum)]
    friction_law: Option<LawArg>,
    /// Friction coefficient of the constant law [-] [default: 0.4].
    #[arg(long, allow_hyphen_values = true)]
    mu: Option<f64>,
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
    /// Bulk temperature of wheel and rail [K] [default: 293.15].
    #[arg(long, allow_hyphen_values = true)]
    bulk_temperature: Option<f64>,
    /// Fluid flow-resistance factor ξ_f [Pa·s] [default: 0.012, water].
    #[arg(long, allow_hyphen_values = true)]
    flow_resistance: Option<f64>,
    /// Failure-stress factor under boundary lubrication k_wet [-] [default: 0.4].
    #[arg(long, allow_hyphen_values = true)]
    k_wet: Option<f64>,
    /// Probability of asperity occurrence at the cell base height ψ_b [-] [default: 0.9995].
    #[arg(long, allow_hyphen_values = true)]
    psi_b: Option<f64>,
    /// Inlet film height at wetness 1, h_f,max [m] [default: 20e-6].
    #[arg(long, allow_hyphen_values = true)]
    h_f_max: Option<f64>,
    /// Fluid height over which k blends from k_dry to k_wet, h_bl [m] [default: 0.1e-6].
    #[arg(long, allow_hyphen_values = true)]
    h_bl: Option<f64>,
    /// Parameter file (TOML); flags override its values.
    #[arg(long, value_name = "FILE.toml")]
    params: Option<PathBuf>,
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

/// Parses a grid "NX,NY": two whole numbers 4 ..= 400.
pub fn grid_arg(text: &str) -> Result<(usize, usize)> {
    let [nx, ny] = pair("grid", text)?;
    for (name, v) in [("grid (NX)", nx), ("grid (NY)", ny)] {
        if v.fract() != 0.0 || !(4.0..=400.0).contains(&v) {
            bail!(wheelrail::Error::out_of_range(
                name,
                v,
                "whole number 4 ..= 400"
            ));
        }
    }
    Ok((nx as usize, ny as usize))
}

impl ModelArgs {
    /// The parameter set: defaults, then the parameter file, then the flags; validated.
    pub fn params(&self) -> Result<Params> {
        let mut p = match &self.params {
            Some(path) => Params::from_toml_file(path)?,
            None => Params::default(),
        };
        if let Some(k) = self.roughness {
            p.roughness.k_r = k;
        }
        if let Some(law) = self.friction_law {
            p.friction.law = match law {
                LawArg::Tomberger => FrictionLaw::Tomberger,
                LawArg::Constant => FrictionLaw::Constant,
                LawArg::Polach => FrictionLaw::Polach,
            };
        }
        if let Some(mu) = self.mu {
            p.friction.mu = mu;
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
        if let Some(t) = self.bulk_temperature {
            p.material.bulk_temperature = t;
        }
        if let Some(v) = self.flow_resistance {
            p.fluid.flow_resistance = v;
        }
        if let Some(v) = self.k_wet {
            p.fluid.k_wet = v;
        }
        if let Some(v) = self.psi_b {
            p.fluid.psi_b = v;
        }
        if let Some(v) = self.h_f_max {
            p.fluid.h_f_max = v;
        }
        if let Some(v) = self.h_bl {
            p.fluid.h_bl = v;
        }
        p.validate()?;
        Ok(p)
    }

    /// The operating point as given.
    fn given(&self) -> OperatingPoint {
        OperatingPoint {
            creepage_x: self.creepage_x,
            creepage_y: self.creepage_y,
            spin: self.spin,
            normal_force: self.normal_force,
            speed: self.speed,
            wetness: self.wetness,
        }
    }

    /// The operating point, validated.
    pub fn point(&self) -> Result<OperatingPoint> {
        let pt = self.given();
        pt.validate()?;
        Ok(pt)
    }

    /// The operating point for the evaluation policy ([`wheelrail::model::Evaluator`]), in the frame of the
    /// flags: the rolling speed may be negative (rolling backwards) or zero, a normal force of at most
    /// 1 mN lifts the wheel. A negative load and a wetness outside [0, 1] are refused here (the policy
    /// would lift the wheel and clamp the wetness); the policy checks the rest of a point it evaluates.
    pub fn input(&self) -> Result<OperatingPoint> {
        let pt = self.given();
        if pt.normal_force.is_nan() || pt.normal_force < 0.0 {
            bail!(wheelrail::Error::out_of_range(
                "normal-force",
                pt.normal_force,
                "finite, >= 0 N (at most 1e-3 N: a lifted wheel)"
            ));
        }
        wheelrail::error::check_range("wetness", pt.wetness, 0.0, 1.0, "")?;
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
    }
}

/// Exit code of an error: 2 for invalid input (values, parameter files), 1 otherwise.
pub fn exit_code(e: &anyhow::Error) -> u8 {
    match e.downcast_ref::<wheelrail::Error>() {
        Some(
            wheelrail::Error::OutOfRange { .. }
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

/// Warns on stderr when the coupled iteration of a solve did not converge.
pub fn warn_unconverged(report: &SolverReport) {
    if !report.converged {
        eprintln!(
            "warning: not converged after {} iterations (residual {:.3e})",
            report.iterations, report.residual
        );
    }
}

/// The JSON object of a solution: global results, convergence report and the friction law.
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
    obj.insert(
        "friction_law".into(),
        serde_json::Value::String(params.friction.law.to_string()),
    );
    v
}
