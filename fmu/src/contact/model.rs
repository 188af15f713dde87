//! The wheel–rail contact behind the FMI layer: maps the FMU's variables to the library's parameter set and
//! operating point, and the library's results back to outputs. No physics here beyond these conventions:
//!
//! - **Wheel lifted:** `normal_force` at or below [`LIFT_OFF_LOAD`] gives zero forces and moment, traction
//!   coefficient 0, fluid load fraction 0, `max_temperature` = `bulk_temperature`, `converged` true.
//! - **Rolling backwards** (`rolling_speed` < 0): the material enters the patch at x = −a instead of +a. The
//!   contact is solved in the frame turned by 180° about z (x' = −x, y' = −y), in which it rolls forwards at
//!   |V|. A rotation about z leaves spin and moment unchanged and reverses in-plane vectors, so the creepages
//!   there are ξ' = −ξ, η' = −η, φ' = φ, and the results turn back as F_x = −F'_x, F_y = −F'_y, M_z = M'_z.
//!   Consequence: without spin the forces depend on the slip direction only (same F for ±V), while the
//!   lateral force due to spin and the spin moment due to creepage (from the slip zone at the trailing
//!   edge) change sign with the rolling direction, as in Kalker's theory.
//! - **Standstill:** |V| below `minimum_speed` (default [`DEFAULT_MINIMUM_SPEED`] m/s) is raised to it, so
//!   a creepage still means a slip velocity and nothing divides by zero; V = 0 counts as forwards.
//! - **Wetness** outside [0, 1] is clamped, with one warning per instance (until `fmi2Reset`).
//! - **Derivatives:** one forward difference along the seed direction of the inputs, each evaluation with the
//!   solver tolerance tightened to [`DERIVATIVE_TOLERANCE`], so that solver noise (relative error ≈
//!   tolerance/step = 10⁻⁴) stays far below the step. Where a cell of the discretised contact switches
//!   between stick and slip, F(ξ) has a kink and this is the slope on the side of the seed direction.

use super::evaluator::{Evaluation, Evaluator, Mode, resolve, table_location};
use super::variables::*;
use crate::fmi2::derivative::forward_difference;
use crate::fmi2::ffi::Status;
use crate::fmi2::logging::Logger;
use crate::fmi2::model::{Model, ModelInfo};
use crate::fmi2::variables::{Value, Values};
use std::path::PathBuf;
use wheelrail::{Error, OperatingPoint, Params};

/// Normal force at or below which the wheel counts as lifted [N]: the library's smallest admissible load.
pub const LIFT_OFF_LOAD: f64 = 1e-3;
/// Solver tolerance of the evaluations behind a directional derivative [-].
pub const DERIVATIVE_TOLERANCE: f64 = 1e-8;
/// Relative finite-difference step of directional derivatives (times max(|u|, nominal) per input) [-].
pub const DERIVATIVE_STEP: f64 = 1e-4;

/// The library's names of values that the FMU exposes under other names (errors are reported with the
/// FMU's names).
const LIBRARY_NAMES: [(&str, usize); 14] = [
    ("roughness.k_r", ROUGHNESS),
    ("geometry.curvature_x", CURVATURE_LONGITUDINAL),
    ("geometry.curvature_y", CURVATURE_LATERAL),
    ("material.bulk_temperature", BULK_TEMPERATURE),
    ("fluid.k_wet", K_WET),
    ("fluid.flow_resistance", FLOW_RESISTANCE),
    ("fluid.psi_b", PSI_B),
    ("fluid.h_f_max", H_F_MAX),
    ("grid.nx", GRID_SIZE),
    ("creepage-x", CREEPAGE_LONGITUDINAL),
    ("creepage-y", CREEPAGE_LATERAL),
    ("spin", SPIN_CREEPAGE),
    ("normal-force", NORMAL_FORCE),
    ("speed", ROLLING_SPEED),
];

/// A library error in the FMU's terms.
fn translate(e: Error, values: &Values) -> String {
    match e {
        Error::OutOfRange { name, allowed, .. } => {
            match LIBRARY_NAMES.iter().find(|(n, _)| *n == name) {
                Some((_, i)) => {
                    let value = match &values.list()[*i] {
                        Value::Real(x) => x.to_string(),
                        Value::Integer(x) => x.to_string(),
                        other => format!("{other:?}"),
                    };
                    format!(
                        "invalid value for {}: {value} (allowed: {allowed})",
                        VARIABLES[*i].name
                    )
                }
                None => format!("invalid value for {name} (allowed: {allowed})"),
            }
        }
        other => other.to_string(),
    }
}

/// The evaluator chosen for a (mode, table_file) pair.
struct Resolved {
    mode: i32,
    table_file: String,
    evaluator: Evaluator,
}

/// The WheelRailFriction model.
pub struct WheelRailModel {
    resources: Option<PathBuf>,
    resolved: Option<Resolved>,
    wetness_warned: bool,
}

impl WheelRailModel {
    /// The evaluator for the current `mode` and `table_file` (resolved again only when they change); logs
    /// the auto-mode fallback warning once per change.
    fn evaluator(&mut self, values: &Values, log: &Logger) -> Result<(Evaluator, Status), String> {
        let (mode, table_file) = (values.integer(MODE), values.string(TABLE_FILE));
        if let Some(r) = &self.resolved
            && r.mode == mode
            && r.table_file == table_file
        {
            return Ok((r.evaluator.clone(), Status::Ok));
        }
        let location = table_location(table_file, self.resources.as_deref());
        let (evaluator, warning) = resolve(Mode::from_code(mode)?, location.as_deref())?;
        let status = match warning {
            Some(w) => {
                log.warning(&format!("mode 0 (auto): {w}"));
                Status::Warning
            }
            None => Status::Ok,
        };
        self.resolved = Some(Resolved {
            mode,
            table_file: table_file.to_string(),
            evaluator: evaluator.clone(),
        });
        Ok((evaluator, status))
    }

    /// The library's parameter set from the parameters (defaults for everything the FMU does not expose).
    fn params(values: &Values, tolerance: Option<f64>) -> Result<Params, String> {
        let mut p = Params::default();
        p.roughness.k_r = values.real(ROUGHNESS);
        p.geometry.curvature_x = values.real(CURVATURE_LONGITUDINAL);
        p.geometry.curvature_y = values.real(CURVATURE_LATERAL);
        p.material.bulk_temperature = values.real(BULK_TEMPERATURE);
        p.fluid.k_wet = values.real(K_WET);
        p.fluid.flow_resistance = values.real(FLOW_RESISTANCE);
        p.fluid.psi_b = values.real(PSI_B);
        p.fluid.h_f_max = values.real(H_F_MAX);
        // grid_size outside usize (negative) is mapped to 0, which the validation rejects by name
        let n = usize::try_from(values.integer(GRID_SIZE)).unwrap_or(0);
        p.grid.nx = n;
        p.grid.ny = n;
        if let Some(t) = tolerance {
            p.solver.tolerance = p.solver.tolerance.min(t);
        }
        p.validate().map_err(|e| translate(e, values))?;
        Ok(p)
    }

    /// Evaluates the outputs of the current values: (results in the FMU's frame, evaluation_mode, status).
    fn evaluate(
        &mut self,
        values: &Values,
        tolerance: Option<f64>,
        log: &Logger,
    ) -> Result<(Evaluation, i32, Status), String> {
        let (evaluator, mut status) = self.evaluator(values, log)?;
        let params = Self::params(values, tolerance)?;
        let minimum_speed = values.real(MINIMUM_SPEED);
        wheelrail::error::check_positive("minimum_speed", minimum_speed, "m/s")
            .map_err(|e| e.to_string())?;
        let normal_force = values.real(NORMAL_FORCE);
        if normal_force <= LIFT_OFF_LOAD {
            let lifted = Evaluation {
                force_x: 0.0,
                force_y: 0.0,
                spin_moment: 0.0,
                traction_coefficient: 0.0,
                max_temperature: params.material.bulk_temperature,
                fluid_load_fraction: 0.0,
                converged: true,
                iterations: 0,
                residual: 0.0,
            };
            return Ok((lifted, evaluator.code(), status));
        }
        let wetness = values.real(WETNESS);
        let clamped = wetness.clamp(0.0, 1.0);
        if clamped != wetness && !self.wetness_warned {
            log.warning(&format!(
                "wetness = {wetness} is outside [0, 1] and is clamped to {clamped} (warned once)"
            ));
            self.wetness_warned = true;
            status = Status::Warning;
        }
        let speed = values.real(ROLLING_SPEED);
        // rolling backwards: solve in the frame turned by 180° about z (module documentation)
        let turn = if speed < 0.0 { -1.0 } else { 1.0 };
        let point = OperatingPoint {
            creepage_x: turn * values.real(CREEPAGE_LONGITUDINAL),
            creepage_y: turn * values.real(CREEPAGE_LATERAL),
            spin: values.real(SPIN_CREEPAGE),
            normal_force,
            speed: speed.abs().max(minimum_speed),
            wetness: clamped,
        };
        let mut e = evaluator
            .evaluate(&params, &point)
            .map_err(|e| translate(e, values))?;
        e.force_x *= turn;
        e.force_y *= turn;
        Ok((e, evaluator.code(), status))
    }
}

fn write_outputs(values: &mut Values, e: &Evaluation, mode: i32) {
    for (i, x) in [
        (FORCE_LONGITUDINAL, e.force_x),
        (FORCE_LATERAL, e.force_y),
        (SPIN_MOMENT, e.spin_moment),
        (TRACTION_COEFFICIENT, e.traction_coefficient),
        (MAX_TEMPERATURE, e.max_temperature),
        (FLUID_LOAD_FRACTION, e.fluid_load_fraction),
    ] {
        values.set(i, Value::Real(x));
    }
    values.set(EVALUATION_MODE, Value::Integer(mode));
    values.set(CONVERGED, Value::Boolean(e.converged));
}

impl Model for WheelRailModel {
    fn info() -> &'static ModelInfo {
        &INFO
    }

    fn new(resources: Option<PathBuf>) -> Self {
        WheelRailModel {
            resources,
            resolved: None,
            wetness_warned: false,
        }
    }

    fn reset(&mut self) {
        self.resolved = None;
        self.wetness_warned = false;
    }

    fn calculate(&mut self, values: &mut Values, log: &Logger) -> Result<Status, String> {
        let (e, mode, mut status) = self.evaluate(values, None, log)?;
        if !e.converged {
            log.warning(&format!(
                "the coupled solver did not converge after {} iterations (residual {:.3e}); output converged = false",
                e.iterations, e.residual
            ));
            status = Status::Warning;
        }
        write_outputs(values, &e, mode);
        Ok(status)
    }

    fn directional_derivative(
        &mut self,
        values: &Values,
        unknowns: &[usize],
        knowns: &[usize],
        seed: &[f64],
        log: &Logger,
    ) -> Result<Vec<f64>, String> {
        forward_difference(values, unknowns, knowns, seed, DERIVATIVE_STEP, |v| {
            let (e, mode, _) = self.evaluate(v, Some(DERIVATIVE_TOLERANCE), log)?;
            let mut out = v.clone();
            write_outputs(&mut out, &e, mode);
            Ok(out)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact() -> Values {
        let mut v = Values::start(&VARIABLES);
        v.set(MODE, Value::Integer(2));
        v
    }

    fn error_of(change: impl FnOnce(&mut Values)) -> String {
        let mut v = exact();
        change(&mut v);
        WheelRailModel::new(None)
            .calculate(&mut v, &Logger::new(None, false))
            .unwrap_err()
    }

    #[test]
    fn errors_name_the_fmu_variables_and_their_fmu_values() {
        let e = error_of(|v| v.set(GRID_SIZE, Value::Integer(2)));
        assert!(e.contains("grid_size: 2"), "{e}");
        // reversed: the library sees the turned creepage -2.5, the message shows the input 2.5
        let e = error_of(|v| {
            v.set(ROLLING_SPEED, Value::Real(-30.0));
            v.set(CREEPAGE_LONGITUDINAL, Value::Real(2.5));
        });
        assert!(e.contains("creepage_longitudinal: 2.5 "), "{e}");
        let e = error_of(|v| v.set(ROUGHNESS, Value::Real(1.5)));
        assert!(e.contains("roughness: 1.5"), "{e}");
        assert!(error_of(|v| v.set(MODE, Value::Integer(7))).contains("mode: 7"));
        assert!(error_of(|v| v.set(MINIMUM_SPEED, Value::Real(0.0))).contains("minimum_speed"));
    }

    #[test]
    fn a_lifted_wheel_needs_no_solve() {
        let mut v = exact();
        v.set(NORMAL_FORCE, Value::Real(1e-3));
        v.set(CREEPAGE_LONGITUDINAL, Value::Real(0.5));
        let status = WheelRailModel::new(None)
            .calculate(&mut v, &Logger::new(None, false))
            .unwrap();
        assert_eq!(status, Status::Ok);
        assert_eq!(
            [
                v.real(FORCE_LONGITUDINAL),
                v.real(FORCE_LATERAL),
                v.real(SPIN_MOMENT)
            ],
            [0.0; 3]
        );
        assert_eq!(v.real(MAX_TEMPERATURE), 293.15);
        assert!(v.boolean(CONVERGED));
        assert_eq!(v.integer(EVALUATION_MODE), 2);
    }
}
