//! The wheel–rail contact behind the FMI layer: translates only. One step goes
//!
//! FMU values → [`input`] (the library's operating point in the MBS frame: signed rolling speed, any load
//! and wetness) → the library's evaluation policy ([`wheelrail::model::Evaluator`]: lifted wheel, frame
//! turn for rolling backwards, minimum speed, wetness clamp, table or exact solver by `mode`) → outputs
//! and `evaluation_mode` ([`write_outputs`]), the policy's notices → one log line each per instance, the
//! library's errors → messages naming the FMU's variables and the values set ([`translate`]).
//!
//! The conventions (docs/model.md §1) are the library's: a `normal_force` at or below
//! [`wheelrail::model::LIFT_OFF_LOAD`] lifts the wheel (zero forces and moment, `max_temperature` =
//! `bulk_temperature`, `converged` true); rolling backwards is solved in the frame turned by 180° about z;
//! |V| below `minimum_speed` is raised to it; `wetness` outside [0, 1] is clamped (one warning per instance,
//! until `fmi2Reset`); `mode` 0 (auto) evaluates by the table where it was built for the current parameters
//! and the point lies inside its ranges, else by the exact solver (each reason logged once per instance);
//! `mode` 1 (table only) clamps points to the ranges (one warning) and refuses other parameters.
//!
//! **Geometry** (`curvature_longitudinal`, `curvature_lateral`, `semi_axis_a`, `semi_axis_b`) is an input
//! of every step, outside the parameter cache: the library evaluates each step at its geometry
//! ([`wheelrail::model::Evaluator::evaluate_at`]); in mode 0 a geometry other than the table's goes to
//! the exact solver (logged once). Outputs `contact_semi_axis_a`, `contact_semi_axis_b`, `peak_pressure`
//! (the normal contact evaluated).
//!
//! **Derivatives:** by table, the exact derivatives of the interpolant (the library's chained Jacobian,
//! [`wheelrail::model::Evaluator::table_jacobian_at`]) for the table's outputs along the operating
//! point's inputs. Otherwise (the exact solver evaluates, a seed moves the geometry, which leaves the
//! table, or an unknown is an output the table does not give) one forward difference along the seed
//! direction of the inputs by the exact solver, each evaluation with the solver tolerance tightened to
//! [`DERIVATIVE_TOLERANCE`], so that solver noise (relative error ≈ tolerance/step = 10⁻⁴) stays far below
//! the step. Where a cell of the discretised contact switches between stick and slip, F(ξ) has a kink and
//! this is the slope on the side of the seed direction.
//!
//! **Warm start** (`warm_start`): in Co-Simulation each step's exact solve starts from the previous
//! step's final state ([`Model::calculate`]); in Model Exchange every evaluation starts from the state of
//! the last accepted point and leaves it ([`Model::calculate_trial`]), so that an integrator's repeated
//! evaluations give the same outputs for the same inputs, and [`Model::accept`] advances it.

use super::mode::{mode_of, resolve, table_locations};
use super::state::ContactState;
use super::variables::*;
use crate::fmi2::derivative::forward_difference;
use crate::fmi2::ffi::Status;
use crate::fmi2::logging::Logger;
use crate::fmi2::model::{Model, ModelInfo};
use crate::fmi2::variables::{Causality, Value, Values};
use std::path::{Path, PathBuf};
use wheelrail::model::{
    DERIVATIVE_TOLERANCE, Evaluated, Evaluation, Evaluator, Fallback, FallbackGrid, LIFT_OFF_LOAD,
    Mode::{Auto, ExactOnly},
    Notice, Notices, Policy, WarmStart,
};
use wheelrail::params::{Geometry, Key, Param, Tangential};
use wheelrail::table::{Jacobian, TableOutput};
use wheelrail::{Error, OperatingPoint, Params};

/// Relative finite-difference step of directional derivatives (times max(|u|, nominal) per input) [-].
pub const DERIVATIVE_STEP: f64 = 1e-4;

/// The FMU variable of a library key: the one of its specification row, and `grid_size` for the grid's
/// cell counts (which it sets both).
fn variable_of(key: Key) -> Option<usize> {
    match key {
        Key::Param(Param::GridNx | Param::GridNy) => Some(GRID_SIZE),
        Key::SemiAxisA => Some(SEMI_AXIS_A),
        Key::SemiAxisB => Some(SEMI_AXIS_B),
        _ => key.spec()?.fmu.map(|f| f.value_reference as usize),
    }
}

/// A library error in the FMU's terms: a value of an FMU variable is named by the variable, with the
/// value as the FMU has it (before the frame turn and the grid's conversion).
fn translate(e: Error, values: &Values) -> String {
    let (variable, name, allowed) = match &e {
        Error::Invalid { key, allowed, .. } => (variable_of(*key), key.to_string(), allowed),
        Error::OutOfRange { name, allowed, .. } => (None, name.clone(), allowed),
        _ => return e.to_string(),
    };
    match variable {
        Some(i) => {
            let value = match &values.list()[i] {
                Value::Real(x) => x.to_string(),
                Value::Integer(x) => x.to_string(),
                other => format!("{other:?}"),
            };
            format!(
                "invalid value for {}: {value} (allowed: {allowed})",
                VARIABLES[i].name
            )
        }
        None => format!("invalid value for {name} (allowed: {allowed})"),
    }
}

/// A library error in the FMU's terms: mode 1's refusal of a table built for other parameters, else
/// [`translate`].
fn fmu_error(e: Error, values: &Values) -> String {
    match e {
        Error::TableParameters { path, .. } => format!(
            "mode 1 (table only): the parameters differ from those the lookup table at {path} was built for"
        ),
        other => translate(other, values),
    }
}

/// What the current parameters give, rebuilt only when they change (a table-mode step costs a few hundred
/// nanoseconds; resolving the table, building and validating a parameter set and comparing it with the
/// table's would be a large part of it).
struct Setup {
    /// The stamp of the parameter values it was made for ([`Values::parameters_stamp`]): while the values
    /// carry it, nothing else need be compared.
    stamp: u64,
    /// `mode` and `table_file` the table was resolved for.
    mode: i32,
    table_file: String,
    /// The bit patterns of the parameter values the model was built from.
    key: ParamKey,
    /// The bit pattern of `minimum_speed`.
    minimum_speed: u64,
    /// The library's policy for these parameters.
    evaluator: Evaluator,
    /// The same model without a table, for the evaluations behind finite differences, which must not mix
    /// the table with the exact solver (a geometry seed leaves the table): in mode 2 exact-only (the
    /// model's grid), else auto (the grid of mode 0's fallback).
    exact: Evaluator,
    /// The table Jacobian (in the FMU's frame) at the last inputs a directional derivative was asked for
    /// (a master asks for one seed direction per call, all at the same point).
    jacobian: Option<(OperatingPoint, Geometry, Jacobian)>,
}

impl Setup {
    /// The setup of the current parameters: the cached one in `slot` if they have not changed, else one
    /// rebuilt in its place. The table is resolved again when `mode` or `table_file` change (logging the
    /// auto-mode fallback warning once per change), the model is built and validated again when a
    /// parameter value changes.
    fn current<'a>(
        slot: &'a mut Option<Box<Setup>>,
        resources: Option<&Path>,
        values: &Values,
        log: &Logger,
    ) -> Result<(&'a mut Setup, Status), String> {
        let stamp = values.parameters_stamp();
        if let Some(s) = slot.take_if(|s| s.stamp == stamp) {
            return Ok((slot.insert(s), Status::Ok));
        }
        let (mode, table_file, key, minimum_speed) = (
            values.integer(MODE),
            values.string(TABLE_FILE),
            param_key(values),
            values.real(MINIMUM_SPEED),
        );
        let same_table = |s: &Setup| s.mode == mode && s.table_file == table_file;
        let mut status = Status::Ok;
        let setup = match slot.take() {
            Some(mut s)
                if same_table(&s) && s.key == key && s.minimum_speed == minimum_speed.to_bits() =>
            {
                s.stamp = stamp;
                s
            }
            old => {
                let old = old.as_deref();
                let (library_mode, tables) = match old.filter(|s| same_table(s)) {
                    Some(s) => (s.evaluator.mode(), s.evaluator.tables().to_vec()),
                    None => {
                        let library_mode = mode_of(mode)?;
                        let locations = table_locations(table_file, resources);
                        let (tables, warning) = resolve(library_mode, &locations)?;
                        if let Some(w) = warning {
                            log.warning(&format!("mode 0 (auto): {w}"));
                            status = Status::Warning;
                        }
                        (library_mode, tables)
                    }
                };
                let model = match old.filter(|s| s.key == key) {
                    Some(s) => s.evaluator.model().clone(),
                    None => wheelrail::model::Model::new(WheelRailModel::params(values)?)
                        .map_err(|e| translate(e, values))?,
                };
                let policy = Policy {
                    minimum_speed,
                    lift_off_load: LIFT_OFF_LOAD,
                    // grid_size set (or grid_accuracy: no default grid) is mode 0's fallback grid too
                    fallback_grid: match values.integer(GRID_SIZE) {
                        AUTOMATIC_GRID_SIZE => FallbackGrid::PerContact,
                        _ => FallbackGrid::Model,
                    },
                };
                // modes 0 and 1 difference on mode 0's fallback grid (auto without a table solves
                // every point), mode 2 on the model's
                let exact_mode = match library_mode {
                    ExactOnly => ExactOnly,
                    _ => Auto,
                };
                let exact = Evaluator::new(model.clone(), exact_mode, None, policy)
                    .map_err(|e| e.to_string())?;
                let evaluator = Evaluator::with_tables(model, library_mode, tables, policy)
                    .map_err(|e| e.to_string())?;
                Box::new(Setup {
                    stamp,
                    mode,
                    table_file: table_file.to_string(),
                    key,
                    minimum_speed: minimum_speed.to_bits(),
                    evaluator,
                    exact,
                    jacobian: None,
                })
            }
        };
        Ok((slot.insert(setup), status))
    }
}

/// The policy's notices already logged by an instance (each once, until `fmi2Reset`).
#[derive(Default)]
struct Warned {
    /// Whether a clamped wetness was logged (once, whatever the value).
    wetness: bool,
    /// The routing notices logged.
    routes: Vec<Notice>,
    /// The tables (indices in the evaluator's list) whose first step was logged.
    served: Vec<usize>,
}

impl Warned {
    /// With several tables in `table_file`: logs (as an event) the first step each table serves, so that
    /// the log says which table a contact moved to.
    fn log_table(&mut self, table: Option<usize>, evaluator: &Evaluator, log: &Logger) {
        let tables = evaluator.tables();
        let Some(k) = table.filter(|k| tables.len() > 1 && !self.served.contains(k)) else {
            return;
        };
        self.served.push(k);
        log.event(&format!(
            "the lookup table at {} (table {} of {} in table_file) serves this contact: its first step \
             by that table (logged once per table)",
            tables[k].location(),
            k + 1,
            tables.len()
        ));
    }

    /// Logs the notices not logged before by this instance (as warnings; `status` becomes Warning).
    fn log(&mut self, notices: &Notices, evaluator: &Evaluator, log: &Logger, status: &mut Status) {
        let at = || evaluator.table_locations();
        for notice in notices.iter() {
            let message = match notice {
                Notice::WetnessClamped { .. } if self.wetness => continue,
                Notice::WetnessClamped { given, used } => {
                    self.wetness = true;
                    format!(
                        "wetness = {given} is outside [0, 1] and is clamped to {used} (warned once)"
                    )
                }
                n if self.routes.contains(&n) => continue,
                Notice::FellBack(why) => {
                    let why = match why {
                        Fallback::OtherParameters => format!(
                            "the parameters differ from those the lookup table at {} was built for",
                            at()
                        ),
                        Fallback::OutsideRanges => {
                            "an operating point lies outside the lookup table's ranges".into()
                        }
                        Fallback::Unresolved => "an operating point lies in a cell of the lookup \
                                                 table across which the model jumps (a wet contact \
                                                 losing its film: a hot one's maximum temperature, \
                                                 or where metal begins to cover the contact)"
                            .into(),
                        Fallback::UnconvergedNodes => "the lookup table interpolates an operating point \
                                                       from points that did not converge when it was \
                                                       built"
                            .into(),
                        Fallback::OtherGeometry => format!(
                            "the contact geometry (curvature_longitudinal, curvature_lateral, semi_axis_a, \
                             semi_axis_b) differs from the one the lookup table at {} was built for",
                            at()
                        ),
                    };
                    format!(
                        "mode 0 (auto): {why}; the exact solver evaluates such points (warned once)"
                    )
                }
                Notice::Clamped => {
                    "mode 1 (table only): an operating point lies outside the lookup \
                                    table's ranges and is clamped to them (warned once)"
                        .into()
                }
            };
            if !matches!(notice, Notice::WetnessClamped { .. }) {
                self.routes.push(notice);
            }
            log.warning(&message);
            *status = Status::Warning;
        }
    }
}

/// The WheelRailFriction model.
///
/// What it keeps between calls: the warm start (part of the FMU state, [`ContactState`]), and caches that
/// are pure functions of the values and that state, so that a restored instance continues bit for bit:
/// the [`Setup`] (keyed by every value it is built from), the table Jacobian (keyed by the inputs and the
/// geometry), and the derivative base point and the Model Exchange trial (keyed by the values, dropped
/// whenever the warm start they were solved from is replaced or restored). The one-time warnings logged (`Warned`) belong to the instance's
/// log, not to the FMU state.
pub struct WheelRailModel {
    resources: Option<PathBuf>,
    setup: Option<Box<Setup>>,
    warned: Warned,
    /// The state of the last exact solve of `calculate` (parameter `warm_start`): the next exact solve
    /// starts from it. Part of the FMU state, forgotten by `fmi2Reset`.
    warm: Option<WarmStart>,
    /// The exact solver's outputs (at the derivative tolerance) for the values of the last directional
    /// derivative's unperturbed point: further seed directions at the same values need one solve each.
    /// Solved from `warm`, so dropped whenever `warm` changes.
    derivative_base: Option<(Values, Values)>,
    /// Model Exchange: the values of the last [`Model::calculate_trial`] and the warm start its exact
    /// solve ended in (None: no exact solve), which [`Model::accept`] makes the next start. Solved from
    /// `warm`, so dropped whenever `warm` changes.
    trial: Option<(Values, Option<WarmStart>)>,
}

/// What an evaluation does with the instance's warm start (parameter `warm_start` on; off, every exact
/// solve starts cold and nothing is kept).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Start {
    /// Start from it and replace it by the solve's final state (`calculate`: a Co-Simulation step).
    Advance,
    /// Start from it and keep it; remember the solve's final state as the trial (`calculate_trial`:
    /// Model Exchange within an integrator step).
    Trial,
    /// Start from it and keep it; forget the solve's final state (finite differences).
    Probe,
}

/// Whether two value sets agree in everything but the outputs (the inputs and parameters an evaluation
/// reads).
fn same_knowns(a: &Values, b: &Values) -> bool {
    a.table()
        .iter()
        .zip(a.list().iter().zip(b.list()))
        .all(|(v, (x, y))| v.causality == Causality::Output || x == y)
}

/// The FMU's Real inputs in the order of the table's axes (ξ, η, φ, F_N, V, w).
pub const INPUTS: [usize; 6] = [
    CREEPAGE_LONGITUDINAL,
    CREEPAGE_LATERAL,
    SPIN_CREEPAGE,
    NORMAL_FORCE,
    ROLLING_SPEED,
    WETNESS,
];
/// The FMU's Real outputs in the order of the table Jacobian's rows.
pub const OUTPUTS: [usize; 6] = [
    FORCE_LONGITUDINAL,
    FORCE_LATERAL,
    SPIN_MOMENT,
    TRACTION_COEFFICIENT,
    MAX_TEMPERATURE,
    FLUID_LOAD_FRACTION,
];

/// The current geometry inputs as the library's contact geometry (validated by the evaluation).
fn geometry(values: &Values) -> Geometry {
    Geometry::of_inputs(
        values.real(CURVATURE_LONGITUDINAL),
        values.real(CURVATURE_LATERAL),
        [values.real(SEMI_AXIS_A), values.real(SEMI_AXIS_B)],
    )
}

/// The current inputs as the library's operating point in the MBS frame (signed rolling speed, any normal
/// force and wetness: the policy handles them).
fn input(values: &Values) -> OperatingPoint {
    OperatingPoint {
        creepage_x: values.real(CREEPAGE_LONGITUDINAL),
        creepage_y: values.real(CREEPAGE_LATERAL),
        spin: values.real(SPIN_CREEPAGE),
        normal_force: values.real(NORMAL_FORCE),
        speed: values.real(ROLLING_SPEED),
        wetness: values.real(WETNESS),
    }
}

/// The `evaluation_mode` output: 1 table, 2 exact; for a lifted wheel, 1 if the mode evaluates by a table.
fn evaluation_mode(by: &Evaluated, evaluator: &Evaluator) -> i32 {
    match by {
        Evaluated::Table(_) => 1,
        Evaluated::Exact(_) => 2,
        Evaluated::Lifted(_) if evaluator.table().is_some() => 1,
        Evaluated::Lifted(_) => 2,
    }
}

impl WheelRailModel {
    /// The library's parameter set from the parameters (defaults for everything the FMU does not expose).
    /// With a `parameter_file`, the file's values replace the defaults (every key, those without an FMU
    /// variable too); a parameter variable away from its start value overrides them, and is an error
    /// where the file sets that key to a third value (two sources naming different values).
    fn params(values: &Values) -> Result<Params, String> {
        let file = values.string(PARAMETER_FILE);
        let defaults = Params::default();
        let mut p = if file.is_empty() {
            defaults.clone()
        } else {
            Params::from_toml_file(Path::new(file))
                .map_err(|e| format!("parameter_file {file}: {e}"))?
        };
        // a variable at its start value leaves the file's value; one away from it overrides the file
        // unless the file names a third value
        let take = |name: &str, file_value: f64, default: f64, value: f64| {
            let differs = |a: f64, b: f64| a.to_bits() != b.to_bits();
            if !differs(value, default) {
                Ok(false)
            } else if differs(file_value, default) && differs(file_value, value) {
                Err(format!(
                    "{name} = {value} differs from parameter_file {file}'s {file_value}: set one of them"
                ))
            } else {
                Ok(true)
            }
        };
        for (param, i) in EXPOSED_PARAMETERS {
            let value = values.real(i);
            if take(VARIABLES[i].name, p.get(param), defaults.get(param), value)? {
                p.set(param, value);
            }
        }
        // grid_size 0 (automatic) keeps the file's or the library's default grid; a negative one is mapped
        // to 1, which the validation rejects by name
        match values.integer(GRID_SIZE) {
            AUTOMATIC_GRID_SIZE => {}
            n => {
                let cells = usize::try_from(n);
                let n = *cells.as_ref().unwrap_or(&1);
                let [nx, ny] = [p.grid.nx, p.grid.ny];
                if cells.is_ok()
                    && [nx, ny] != [defaults.grid.nx, defaults.grid.ny]
                    && [nx, ny] != [n, n]
                {
                    return Err(format!(
                        "grid_size = {n} differs from parameter_file {file}'s grid {nx} x {ny}: set one of them"
                    ));
                }
                p.grid.nx = n;
                p.grid.ny = n;
            }
        }
        match values.integer(TANGENTIAL) {
            0 => {}
            1 => p.tangential = Tangential::Exact,
            other => {
                return Err(format!(
                    "invalid value for tangential: {other} (allowed: 0 fastsim, 1 exact)"
                ));
            }
        }
        p.validate().map_err(|e| translate(e, values))?;
        Ok(p)
    }

    /// Evaluates the outputs of the current values: (results in the FMU's frame, evaluation_mode, status).
    /// `tolerance` tightens the exact solver's tolerance and selects the exact solver whatever the mode
    /// (for finite differences), on `cells` if given. With `warm_start` on, an exact solve starts from the
    /// instance's warm start; `start` says what becomes of the solve's final state.
    fn evaluate(
        &mut self,
        values: &Values,
        tolerance: Option<f64>,
        cells: Option<[usize; 2]>,
        start: Start,
        log: &Logger,
    ) -> Result<(Evaluation, i32, Status), String> {
        let (setup, mut status) =
            Setup::current(&mut self.setup, self.resources.as_deref(), values, log)?;
        let warm_start = values.boolean(WARM_START);
        // advancing, the solve starts from and leaves its state in the instance's warm start itself (not a
        // copy: a table step moves no solver state); otherwise from a copy, or from nothing
        let mut copy = None;
        let warm = match (warm_start, start) {
            (false, _) => &mut copy,
            (true, Start::Advance) => &mut self.warm,
            (true, _) => {
                copy = self.warm.clone();
                &mut copy
            }
        };
        let evaluator = match tolerance {
            Some(_) => &setup.exact,
            None => &setup.evaluator,
        };
        let result =
            evaluator.evaluate_on(&input(values), &geometry(values), cells, tolerance, warm);
        let exact = matches!(
            &result,
            Ok(Evaluation {
                by: Evaluated::Exact(_),
                ..
            })
        );
        match start {
            // an exact solve replaced the warm start the derivative base and the trial were solved from
            Start::Advance if warm_start && exact => {
                self.derivative_base = None;
                self.trial = None;
            }
            Start::Trial if warm_start => {
                self.trial = result
                    .is_ok()
                    .then(|| (values.clone(), copy.filter(|_| exact)));
            }
            _ => {}
        }
        let e = result.map_err(|e| fmu_error(e, values))?;
        self.warned.log_table(e.table, &setup.evaluator, log);
        if !e.notices.is_empty() {
            self.warned
                .log(&e.notices, &setup.evaluator, log, &mut status);
        }
        let mode = evaluation_mode(&e.by, evaluator);
        Ok((e, mode, status))
    }

    /// Computes every output of `values` and writes them into `values` (`start`: what becomes of the warm
    /// start); an unconverged solve is a warning.
    fn outputs(
        &mut self,
        values: &mut Values,
        start: Start,
        log: &Logger,
    ) -> Result<Status, String> {
        let (e, mode, mut status) = self.evaluate(values, None, None, start, log)?;
        let output = e.outputs().map_err(|err| fmu_error(err, values))?;
        if !output.converged {
            log.warning(&match e.by.report() {
                None => "the lookup table's points around this operating point did not converge when the \
                         table was built; output converged = false"
                    .to_string(),
                Some(r) => format!(
                    "the coupled solver did not converge after {} iterations (residual {:.3e}); output converged = false",
                    r.iterations, r.residual
                ),
            });
            status = Status::Warning;
        }
        write_outputs(values, &e, &output, mode)?;
        Ok(status)
    }

    /// The directional derivative from the table interpolant's Jacobian when the table evaluates the
    /// current point and the derivative is one of the table's outputs along its inputs (None: the exact
    /// solver does, the wheel is lifted, or the seed moves the geometry, which leaves the table, or an
    /// unknown is an output the table does not give).
    fn table_derivative(
        &mut self,
        values: &Values,
        unknowns: &[usize],
        knowns: &[usize],
        seed: &[f64],
        log: &Logger,
    ) -> Result<Option<Vec<f64>>, String> {
        let index = |list: &[usize], i: usize| list.iter().position(|x| *x == i);
        let rows: Option<Vec<usize>> = unknowns.iter().map(|&u| index(&OUTPUTS, u)).collect();
        let outside = |(&k, s): (&usize, &f64)| *s != 0.0 && index(&INPUTS, k).is_none();
        let Some(rows) = rows.filter(|_| !knowns.iter().zip(seed).any(outside)) else {
            return Ok(None);
        };
        let (setup, _) = Setup::current(&mut self.setup, self.resources.as_deref(), values, log)?;
        let (at, shape) = (input(values), geometry(values));
        let jac = match &setup.jacobian {
            Some((cached, cached_shape, jac)) if *cached == at && *cached_shape == shape => *jac,
            _ => {
                let (jac, notices) = (setup.evaluator)
                    .table_jacobian_at(&at, &shape)
                    .map_err(|e| fmu_error(e, values))?;
                self.warned
                    .log(&notices, &setup.evaluator, log, &mut Status::Ok);
                let Some(jac) = jac else {
                    return Ok(None);
                };
                setup.jacobian = Some((at, shape, jac));
                jac
            }
        };
        Ok(Some(
            rows.into_iter()
                .map(|r| {
                    knowns
                        .iter()
                        .zip(seed)
                        .map(|(&k, s)| index(&INPUTS, k).map_or(0.0, |c| jac[r][c] * s))
                        .sum()
                })
                .collect(),
        ))
    }
}

/// The bit patterns of the parameter values and of `grid_size`.
type ParamKey = ([u64; EXPOSED_PARAMETERS.len() + 2], String);

/// The key of the parameter-set cache ([`Setup`]): the values [`WheelRailModel::params`] reads.
fn param_key(values: &Values) -> ParamKey {
    let mut key = [0; EXPOSED_PARAMETERS.len() + 2];
    for (k, (_, i)) in key.iter_mut().zip(EXPOSED_PARAMETERS) {
        *k = values.real(i).to_bits();
    }
    key[EXPOSED_PARAMETERS.len()] = u64::from(values.integer(GRID_SIZE) as u32);
    key[EXPOSED_PARAMETERS.len() + 1] = u64::from(values.integer(TANGENTIAL) as u32);
    (key, values.string(PARAMETER_FILE).to_string())
}

/// Writes an evaluation's outputs: the six of the table, the contact ellipse and peak pressure, the
/// frictional power [W], and `evaluation_mode`, `converged`. An
/// evaluation without a frictional power (a table of format 1, which [`super::mode::resolve`] never
/// selects) is an error.
fn write_outputs(
    values: &mut Values,
    e: &Evaluation,
    o: &TableOutput,
    mode: i32,
) -> Result<(), String> {
    let frictional_power = e.frictional_power().ok_or_else(|| {
        "the lookup table does not store the frictional power (format version 1): rebuild it"
            .to_string()
    })?;
    for (i, x) in [
        (FORCE_LONGITUDINAL, o.force_x),
        (FORCE_LATERAL, o.force_y),
        (SPIN_MOMENT, o.spin_moment),
        (TRACTION_COEFFICIENT, o.traction_coefficient),
        (MAX_TEMPERATURE, o.max_temperature),
        (FLUID_LOAD_FRACTION, o.fluid_load_fraction),
        (CONTACT_SEMI_AXIS_A, e.patch.semi_axis_a),
        (CONTACT_SEMI_AXIS_B, e.patch.semi_axis_b),
        (PEAK_PRESSURE, e.patch.peak_pressure),
        (FRICTIONAL_POWER, frictional_power),
    ] {
        values.set(i, Value::Real(x));
    }
    values.set(EVALUATION_MODE, Value::Integer(mode));
    values.set(CONVERGED, Value::Boolean(o.converged));
    Ok(())
}

impl Model for WheelRailModel {
    type State = ContactState;

    fn info() -> &'static ModelInfo {
        &INFO
    }

    fn new(resources: Option<PathBuf>) -> Self {
        WheelRailModel {
            resources,
            setup: None,
            warned: Warned::default(),
            warm: None,
            derivative_base: None,
            trial: None,
        }
    }

    fn reset(&mut self) {
        self.setup = None;
        self.warned = Warned::default();
        self.warm = None;
        self.derivative_base = None;
        self.trial = None;
    }

    fn state(&self) -> ContactState {
        ContactState {
            warm: self.warm.clone(),
        }
    }

    fn set_state(&mut self, state: &ContactState) {
        self.warm = state.warm.clone();
        self.derivative_base = None;
        self.trial = None;
    }

    fn calculate(&mut self, values: &mut Values, log: &Logger) -> Result<Status, String> {
        self.outputs(values, Start::Advance, log)
    }

    /// With `warm_start` on, the exact solve starts from the warm start of the last accepted point, which
    /// stays: the outputs are a function of the values and that warm start (for an implicit integrator's
    /// Newton iteration), within the solver tolerance of a cold solve.
    fn calculate_trial(&mut self, values: &mut Values, log: &Logger) -> Result<Status, String> {
        self.outputs(values, Start::Trial, log)
    }

    /// The warm start becomes the final state of the exact solve at `values` from the current warm start:
    /// that of the last [`Model::calculate_trial`] if it was at these values, else solved again (after a
    /// restore, a reset, or a second accept at the same values), so that the result depends on the
    /// values and the FMU state only. Table evaluations leave the warm start as it is.
    fn accept(&mut self, values: &Values, log: &Logger) -> Result<Status, String> {
        if !values.boolean(WARM_START) {
            return Ok(Status::Ok);
        }
        let status = match &self.trial {
            Some((at, _)) if same_knowns(at, values) => Status::Ok,
            _ => self.calculate_trial(&mut values.clone(), log)?,
        };
        if let Some((_, Some(warm))) = self.trial.take() {
            self.derivative_base = None;
            self.warm = Some(warm);
        }
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
        if let Some(d) = self.table_derivative(values, unknowns, knowns, seed, log)? {
            return Ok(d);
        }
        // every evaluation of the difference on the grid of the unperturbed point: a grid chosen per
        // contact must not switch between them (at w = 0, a wetness seed would switch to the wet grid)
        let (setup, _) = Setup::current(&mut self.setup, self.resources.as_deref(), values, log)?;
        let cells = setup
            .exact
            .exact_cells(&input(values), &geometry(values))
            .map_err(|e| fmu_error(e, values))?;
        forward_difference(values, unknowns, knowns, seed, DERIVATIVE_STEP, |v| {
            // the unperturbed point is the same for every seed direction at one communication point
            if let Some((at, out)) = &self.derivative_base
                && at == v
            {
                return Ok(out.clone());
            }
            let (e, mode, _) = self.evaluate(
                v,
                Some(DERIVATIVE_TOLERANCE),
                Some(cells),
                Start::Probe,
                log,
            )?;
            let mut out = v.clone();
            let output = e.outputs().map_err(|err| fmu_error(err, v))?;
            write_outputs(&mut out, &e, &output, mode)?;
            if v == values {
                self.derivative_base = Some((v.clone(), out.clone()));
            }
            Ok(out)
        })
    }
}

/// In FMI 3.0, one instance holds `contacts` of these models, each evaluated as one FMI 2.0 instance.
impl crate::fmi3::arrays::ArrayModel for WheelRailModel {
    fn arrays() -> &'static crate::fmi3::arrays::ArrayInfo {
        &ARRAYS
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi2::logging::tests::capturing;

    fn exact() -> Values {
        let mut v = Values::start(&VARIABLES);
        v.set(MODE, Value::Integer(2));
        v
    }

    /// A parameter set between two steps of one instance rebuilds what the parameters determine (its
    /// setup is kept while the values' parameter stamp is unchanged): each step equals a fresh instance's
    /// at the same values, and a parameter that acts on the forces moves them.
    #[test]
    fn parameters_set_between_steps_take_effect() {
        let (log, _) = capturing(false);
        let mut v = exact();
        v.set(GRID_SIZE, Value::Integer(6));
        v.set(CREEPAGE_LONGITUDINAL, Value::Real(0.004));
        // cold solves: a warm start would carry the previous parameters' solution into the next step
        v.set(WARM_START, Value::Boolean(false));
        let mut model = WheelRailModel::new(None);
        let mut forces = Vec::new();
        for (p, i) in EXPOSED_PARAMETERS {
            let s = p.spec();
            for value in [off_default(p, [0.8, 1.2]), s.default] {
                v.set(i, Value::Real(value));
                model.calculate(&mut v, &log).unwrap();
                let fresh = by_a_fresh_instance(&v, &log);
                let f = v.real(FORCE_LONGITUDINAL);
                assert_eq!(
                    f.to_bits(),
                    fresh.real(FORCE_LONGITUDINAL).to_bits(),
                    "{}",
                    s.toml
                );
                forces.push(f);
            }
        }
        // the dry contact's parameters move the force at 0.4 % creepage (the wet ones do not), and setting
        // one back restores it
        let moved = forces.chunks(2).filter(|f| f[0] != f[1]).count();
        assert!(moved >= 2, "{moved} of {}", EXPOSED_PARAMETERS.len());
        assert!(forces.chunks(2).all(|f| f[1] == forces[1]));
    }

    /// A long contact (gap curvatures of a flange root: a/b ≈ 2.6) at 0.4 % creepage, dry, in mode 0
    /// without a table (every point by the exact solver), cold solves.
    fn long_contact(grid_size: i32) -> Values {
        let mut v = Values::start(&VARIABLES);
        v.set(GRID_SIZE, Value::Integer(grid_size));
        v.set(CURVATURE_LONGITUDINAL, Value::Real(0.92));
        v.set(CURVATURE_LATERAL, Value::Real(3.5));
        v.set(CREEPAGE_LONGITUDINAL, Value::Real(0.004));
        v.set(WARM_START, Value::Boolean(false));
        v
    }

    /// The library's exact solve of `v`'s point and geometry on `cells` to the solver `tolerance`.
    fn solved_on(
        v: &Values,
        cells: [usize; 2],
        tolerance: f64,
    ) -> wheelrail::solver::GlobalResults {
        let mut p = Params {
            geometry: geometry(v),
            ..Params::default()
        };
        [p.grid.nx, p.grid.ny] = cells;
        p.solver.tolerance = tolerance;
        wheelrail::solve(&p, &input(v)).unwrap().global
    }

    /// `grid_size` 0 (automatic, the start value): mode 0 solves the points no table serves on the grid
    /// per contact, dry and wet; mode 2 on 30 × 30; a `grid_size` set is mode 0's grid too.
    #[test]
    fn grid_size_automatic_solves_mode_0s_fallback_on_the_grid_per_contact() {
        let (log, _) = capturing(false);
        assert_eq!(
            Values::start(&VARIABLES).integer(GRID_SIZE),
            AUTOMATIC_GRID_SIZE
        );
        for (wetness, cells) in [(0.0, [24, 6]), (1.0, [24, 12])] {
            let mut v = long_contact(AUTOMATIC_GRID_SIZE);
            v.set(WETNESS, Value::Real(wetness));
            let mut m = WheelRailModel::new(None);
            m.calculate(&mut v, &log).unwrap();
            assert_eq!(v.integer(EVALUATION_MODE), 2);
            let want = solved_on(&v, cells, Params::default().solver.tolerance);
            assert_eq!(
                [v.real(FORCE_LONGITUDINAL), v.real(FORCE_LATERAL)],
                [want.force_x, want.force_y],
                "w = {wetness}"
            );
            assert_eq!(Some(v.real(MAX_TEMPERATURE)), want.max_temperature);
        }
        let force_in = |mode: i32, grid_size: i32| {
            let mut v = long_contact(grid_size);
            v.set(MODE, Value::Integer(mode));
            WheelRailModel::new(None).calculate(&mut v, &log).unwrap();
            v.real(FORCE_LONGITUDINAL)
        };
        let tolerance = Params::default().solver.tolerance;
        let reference = solved_on(&long_contact(0), [30, 30], tolerance).force_x;
        assert_eq!(force_in(2, AUTOMATIC_GRID_SIZE), reference);
        assert_eq!(force_in(0, DEFAULT_GRID_SIZE), reference);
        assert_eq!(force_in(0, 12), force_in(2, 12));
        assert_ne!(force_in(0, AUTOMATIC_GRID_SIZE), reference);
        // a negative grid_size is refused by name
        let mut v = long_contact(-3);
        let e = WheelRailModel::new(None)
            .calculate(&mut v, &log)
            .unwrap_err();
        assert!(e.contains("grid_size: -3"), "{e}");
    }

    /// The evaluations behind a directional derivative stay on the grid of the unperturbed point: at
    /// w = 0 a wetness seed would otherwise difference the dry grid against the wet one (24 × 6 → 24 × 12
    /// on this long contact), a jump of the grids' difference over the step.
    #[test]
    fn a_derivative_keeps_the_grid_of_its_point() {
        let (log, _) = capturing(false);
        let v = long_contact(AUTOMATIC_GRID_SIZE);
        let mut m = WheelRailModel::new(None);
        let d = m
            .directional_derivative(&v, &[FORCE_LONGITUDINAL], &[WETNESS], &[1.0], &log)
            .unwrap()[0];
        // the difference on the dry point's grid, at the derivative tolerance
        let step = DERIVATIVE_STEP * VARIABLES[WETNESS].nominal();
        let on = |w: f64, cells| {
            let mut v = v.clone();
            v.set(WETNESS, Value::Real(w));
            solved_on(&v, cells, DERIVATIVE_TOLERANCE).force_x
        };
        let on_dry_grid = |w| on(w, [24, 6]);
        let want = (on_dry_grid(step) - on_dry_grid(0.0)) / step;
        assert!(
            (d - want).abs() <= 1e-9 * want.abs().max(1.0),
            "{d} vs {want}"
        );
        // across the grids the same difference is another number (the grids' difference over the step)
        let across = (on(step, [24, 12]) - on_dry_grid(0.0)) / step;
        assert!(
            (across - want).abs() > 0.5 * want.abs(),
            "{across} vs {want}"
        );
    }

    #[test]
    fn warm_started_steps_agree_with_cold_ones_within_the_solver_tolerance() {
        let (log, _) = capturing(false);
        let mut warm = WheelRailModel::new(None);
        let mut cold = WheelRailModel::new(None);
        let mut vw = exact();
        let mut vc = exact();
        vw.set(GRID_SIZE, Value::Integer(16));
        vc.set(GRID_SIZE, Value::Integer(16));
        vc.set(WARM_START, Value::Boolean(false));
        for (k, (xi, fz, w)) in [(0.002, 90e3, 0.0), (0.004, 95e3, 0.0), (0.004, 95e3, 1.0)]
            .into_iter()
            .enumerate()
        {
            for v in [&mut vw, &mut vc] {
                v.set(CREEPAGE_LONGITUDINAL, Value::Real(xi));
                v.set(NORMAL_FORCE, Value::Real(fz));
                v.set(WETNESS, Value::Real(w));
            }
            warm.calculate(&mut vw, &log).unwrap();
            cold.calculate(&mut vc, &log).unwrap();
            // the warm model carries the last state, the cold one never does
            assert!(warm.warm.is_some() && cold.warm.is_none(), "step {k}");
            let (a, b) = (outputs(&vw), outputs(&vc));
            for (x, y) in a.iter().zip(&b) {
                assert!(
                    (x - y).abs() <= 1e-6 * y.abs().max(1e-3),
                    "step {k}: {a:?} vs {b:?}"
                );
            }
        }
        warm.reset();
        assert!(warm.warm.is_none());
    }

    #[test]
    fn the_derivative_base_is_dropped_with_the_warm_start_it_was_solved_from() {
        let log = Logger::new(None, false);
        let mut v = exact();
        v.set(GRID_SIZE, Value::Integer(12));
        v.set(WETNESS, Value::Real(0.5));
        v.set(CREEPAGE_LONGITUDINAL, Value::Real(0.004));
        let d = |m: &mut WheelRailModel, v: &Values| {
            m.directional_derivative(
                v,
                &[FORCE_LONGITUDINAL],
                &[CREEPAGE_LONGITUDINAL],
                &[1.0],
                &log,
            )
            .unwrap()
        };
        let mut m = WheelRailModel::new(None);
        m.calculate(&mut v, &log).unwrap();
        let solved_from_the_step = d(&mut m, &v);
        assert!(m.derivative_base.is_some());
        // restored to another instance's state: solved from its warm start, as a fresh instance in it
        let mut other = WheelRailModel::new(None);
        let mut u = v.clone();
        u.set(CREEPAGE_LONGITUDINAL, Value::Real(0.02));
        u.set(NORMAL_FORCE, Value::Real(80e3));
        other.calculate(&mut u, &log).unwrap();
        m.set_state(&other.state());
        let restored = d(&mut m, &v);
        let mut fresh = WheelRailModel::new(None);
        fresh.set_state(&other.state());
        assert_eq!(restored, d(&mut fresh, &v));
        assert_ne!(restored, solved_from_the_step);
        // a step's exact solve replaces the warm start: the base goes with it
        let mut w = v.clone();
        m.calculate(&mut w, &log).unwrap();
        assert!(m.warm.is_some() && m.derivative_base.is_none());
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

    /// The values a fresh instance computes from `v` (its outputs from its inputs and parameters).
    fn by_a_fresh_instance(v: &Values, log: &Logger) -> Values {
        let mut fresh = v.clone();
        WheelRailModel::new(None)
            .calculate(&mut fresh, log)
            .unwrap();
        fresh
    }

    /// A value of parameter `p` off its default: the default times the first of `factors` that stays in
    /// its range.
    fn off_default(p: Param, factors: [f64; 2]) -> f64 {
        let s = p.spec();
        factors
            .map(|f| f * s.default)
            .into_iter()
            .find(|&x| s.range.contains(x))
            .unwrap()
    }

    /// `parameter_file`: the file's values replace the defaults, those of keys without an FMU variable
    /// too (the model solved is the library's with the file's parameters, bit for bit); a variable at its
    /// start value leaves the file's value, one away from it overrides a key the file leaves at its
    /// default and is an error against a third value; a missing or bad file is an error naming it.
    #[test]
    fn a_parameter_file_sets_the_parameters_and_conflicts_are_errors() {
        let dir = std::env::temp_dir().join(format!("wheelrail-pfile-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("fitted.toml");
        // yield_span has no FMU variable; k_r has one
        let mut fitted = Params::default();
        fitted.set(Param::YieldSpan, 0.8 * Param::YieldSpan.default_value());
        fitted.set(Param::RoughnessKr, 0.7 * Param::RoughnessKr.default_value());
        std::fs::write(&file, fitted.to_toml_string()).unwrap();
        assert!(Param::YieldSpan.spec().fmu.is_none() && Param::RoughnessKr.spec().fmu.is_some());

        let mut v = Values::start(&VARIABLES);
        v.set(PARAMETER_FILE, Value::String(file.display().to_string()));
        let got = WheelRailModel::params(&v).unwrap();
        assert_eq!(got, fitted);
        // the solve is the library's with the file's parameters
        let (log, _) = capturing(false);
        let mut e = exact();
        e.set(PARAMETER_FILE, Value::String(file.display().to_string()));
        e.set(GRID_SIZE, Value::Integer(6));
        e.set(CREEPAGE_LONGITUDINAL, Value::Real(0.004));
        WheelRailModel::new(None).calculate(&mut e, &log).unwrap();
        let mut lib = fitted.clone();
        lib.geometry = geometry(&e);
        [lib.grid.nx, lib.grid.ny] = [6, 6];
        let want = wheelrail::solve(&lib, &input(&e)).unwrap().global;
        assert_eq!(e.real(FORCE_LONGITUDINAL).to_bits(), want.force_x.to_bits());

        // a variable away from its start value overrides a key the file leaves at its default
        let psi = off_default(Param::PsiB, [0.9, 1.1]);
        v.set(PSI_B, Value::Real(psi));
        assert_eq!(WheelRailModel::params(&v).unwrap().get(Param::PsiB), psi);
        // the file's own value through the variable is no conflict; a third value is
        let k_r = fitted.get(Param::RoughnessKr);
        let kr_vr = Param::RoughnessKr.spec().fmu.unwrap().value_reference as usize;
        v.set(kr_vr, Value::Real(k_r));
        assert_eq!(
            WheelRailModel::params(&v).unwrap().get(Param::RoughnessKr),
            k_r
        );
        v.set(kr_vr, Value::Real(0.9 * k_r));
        let err = WheelRailModel::params(&v).unwrap_err();
        let name = VARIABLES[kr_vr].name;
        assert!(
            err.contains(name) && err.contains("parameter_file") && err.contains("fitted.toml"),
            "{err}"
        );
        // grid_size against the file's grid
        let mut gridded = Params::default();
        [gridded.grid.nx, gridded.grid.ny] = [12, 12];
        std::fs::write(&file, gridded.to_toml_string()).unwrap();
        let mut g = Values::start(&VARIABLES);
        g.set(PARAMETER_FILE, Value::String(file.display().to_string()));
        assert_eq!(WheelRailModel::params(&g).unwrap().grid.nx, 12);
        g.set(GRID_SIZE, Value::Integer(12));
        assert_eq!(WheelRailModel::params(&g).unwrap().grid.ny, 12);
        g.set(GRID_SIZE, Value::Integer(20));
        let err = WheelRailModel::params(&g).unwrap_err();
        assert!(
            err.contains("grid_size = 20") && err.contains("12 x 12"),
            "{err}"
        );

        // a missing file and a corrupt one
        for (name, text) in [
            ("missing.toml", None),
            ("corrupt.toml", Some("[friction\nk_dry = ")),
        ] {
            let path = dir.join(name);
            if let Some(t) = text {
                std::fs::write(&path, t).unwrap();
            }
            let mut m = Values::start(&VARIABLES);
            m.set(PARAMETER_FILE, Value::String(path.display().to_string()));
            let err = WheelRailModel::params(&m).unwrap_err();
            assert!(
                err.starts_with("parameter_file ") && err.contains(name),
                "{err}"
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn every_exposed_parameter_reaches_the_library_and_its_errors_name_the_variable() {
        for (p, i) in EXPOSED_PARAMETERS {
            let s = p.spec();
            let x = off_default(p, [0.9, 1.01]);
            let mut v = Values::start(&VARIABLES);
            v.set(i, Value::Real(x));
            assert_eq!(WheelRailModel::params(&v).unwrap().get(p), x, "{}", s.toml);
            v.set(i, Value::Real(f64::NAN));
            let e = WheelRailModel::params(&v).err().unwrap();
            let name = VARIABLES[i].name;
            assert!(
                e.starts_with(&format!("invalid value for {name}: NaN (allowed: finite")),
                "{e}"
            );
        }
        let e = error_of(|v| v.set(FLOW_RESISTANCE, Value::Real(0.0)));
        assert!(
            e.contains("flow_resistance: 0 (allowed: finite, > 0 Pa s)"),
            "{e}"
        );
    }

    /// A small table for the FMU's default parameters on a 6 × 6 grid, written to a temporary directory.
    fn table_dir() -> PathBuf {
        use std::sync::OnceLock;
        static DIR: OnceLock<PathBuf> = OnceLock::new();
        DIR.get_or_init(|| {
            let axes = wheelrail::table::Axes::from_toml_file(
                &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("../tests/fixtures/small-axes.toml"),
            )
            .unwrap();
            let mut v = Values::start(&VARIABLES);
            v.set(GRID_SIZE, Value::Integer(6));
            let params = WheelRailModel::params(&v).unwrap();
            let dir =
                std::env::temp_dir().join(format!("wheelrail-fmu-table-{}", std::process::id()));
            let mut files = wheelrail::table::build(&params, &axes, None, &|| ()).unwrap();
            files.write(&dir).unwrap();
            dir
        })
        .clone()
    }

    fn with_table(mode: i32) -> Values {
        let mut v = Values::start(&VARIABLES);
        v.set(MODE, Value::Integer(mode));
        v.set(GRID_SIZE, Value::Integer(6));
        v.set(
            TABLE_FILE,
            Value::String(table_dir().to_str().unwrap().to_string()),
        );
        for (i, x) in [
            (0, 0.003),
            (1, -0.001),
            (2, 0.2),
            (3, 100e3),
            (4, 30.0),
            (5, 0.1),
        ] {
            v.set(INPUTS[i], Value::Real(x));
        }
        v
    }

    fn outputs(v: &Values) -> [f64; 6] {
        OUTPUTS.map(|i| v.real(i))
    }

    #[test]
    fn auto_mode_uses_the_table_inside_its_ranges_and_else_the_exact_solver_warning_once() {
        let (log, seen) = capturing(false);
        let mut m = WheelRailModel::new(None);
        let mut v = with_table(0);
        assert_eq!(m.calculate(&mut v, &log).unwrap(), Status::Ok);
        assert_eq!(v.integer(EVALUATION_MODE), 1);
        let t = wheelrail::table::Table::load_shared(&table_dir()).unwrap();
        let h = wheelrail::solver::normal_contact(t.params(), 100e3).unwrap();
        let ellipse = wheelrail::table::Ellipse {
            a: h.a,
            b: h.b,
            load_exponent: wheelrail::table::Ellipse::HERTZ,
        };
        let want = t
            .evaluate(
                &OperatingPoint {
                    creepage_x: 0.003,
                    creepage_y: -0.001,
                    spin: 0.2,
                    normal_force: 100e3,
                    speed: 30.0,
                    wetness: 0.1,
                },
                &ellipse,
            )
            .unwrap();
        assert_eq!(v.real(FORCE_LONGITUDINAL), want.force_x);
        assert_eq!(v.real(SPIN_MOMENT), want.spin_moment);
        assert!(v.boolean(CONVERGED));
        assert!(seen.borrow().is_empty());
        // outside the speed range: exact, one warning, then silent
        v.set(ROLLING_SPEED, Value::Real(60.0));
        assert_eq!(m.calculate(&mut v, &log).unwrap(), Status::Warning);
        assert_eq!(v.integer(EVALUATION_MODE), 2);
        assert_eq!(m.calculate(&mut v, &log).unwrap(), Status::Ok);
        assert_eq!(seen.borrow().len(), 1);
        assert!(
            seen.borrow()[0]
                .2
                .contains("outside the lookup table's ranges")
        );
        // other parameters: exact, with its own single warning
        v.set(ROLLING_SPEED, Value::Real(30.0));
        v.set(ROUGHNESS, Value::Real(0.6));
        assert_eq!(m.calculate(&mut v, &log).unwrap(), Status::Warning);
        assert_eq!(v.integer(EVALUATION_MODE), 2);
        m.calculate(&mut v, &log).unwrap();
        assert_eq!(seen.borrow().len(), 2);
        assert!(seen.borrow()[1].2.contains("parameters differ"));
        // back to the table's parameters: the table again
        v.set(ROUGHNESS, Value::Real(0.5));
        m.calculate(&mut v, &log).unwrap();
        assert_eq!(v.integer(EVALUATION_MODE), 1);
    }

    #[test]
    fn table_only_mode_clamps_with_one_warning_and_refuses_other_parameters() {
        let (log, seen) = capturing(false);
        let mut m = WheelRailModel::new(None);
        let mut v = with_table(1);
        v.set(ROLLING_SPEED, Value::Real(60.0));
        assert_eq!(m.calculate(&mut v, &log).unwrap(), Status::Warning);
        assert_eq!(v.integer(EVALUATION_MODE), 1);
        let clamped = outputs(&v);
        v.set(ROLLING_SPEED, Value::Real(40.0));
        assert_eq!(m.calculate(&mut v, &log).unwrap(), Status::Ok);
        assert_eq!(outputs(&v), clamped);
        assert_eq!(seen.borrow().len(), 1);
        assert!(seen.borrow()[0].2.contains("clamped"));
        v.set(K_WET, Value::Real(0.3));
        let e = m.calculate(&mut v, &log).unwrap_err();
        assert!(e.contains("table only") && e.contains("differ"), "{e}");
    }

    /// `tangential` = 1 selects the exact tangential solver: a table built with FASTSIM is not used for it
    /// (mode 0: the exact solver, one warning; mode 1: an error), and other codes are refused by name.
    #[test]
    fn tangential_exact_is_not_served_by_a_fastsim_table() {
        let (log, seen) = capturing(false);
        let mut m = WheelRailModel::new(None);
        let mut v = with_table(0);
        v.set(TANGENTIAL, Value::Integer(1));
        assert_eq!(m.calculate(&mut v, &log).unwrap(), Status::Warning);
        assert_eq!(v.integer(EVALUATION_MODE), 2);
        assert!(seen.borrow()[0].2.contains("parameters differ"));
        let params = WheelRailModel::params(&v).unwrap();
        assert_eq!(params.tangential, Tangential::Exact);
        let s = wheelrail::solve(&params, &input(&v)).unwrap();
        assert_eq!(v.real(FORCE_LONGITUDINAL), s.global.force_x);
        assert_eq!(v.real(FORCE_LATERAL), s.global.force_y);
        let mut v = with_table(1);
        v.set(TANGENTIAL, Value::Integer(1));
        let e = WheelRailModel::new(None)
            .calculate(&mut v, &log)
            .unwrap_err();
        assert!(e.contains("table only") && e.contains("differ"), "{e}");
        v.set(TANGENTIAL, Value::Integer(2));
        let e = WheelRailModel::new(None)
            .calculate(&mut v, &log)
            .unwrap_err();
        assert!(e.contains("invalid value for tangential: 2"), "{e}");
    }

    /// Directional derivatives along each input, one call per seed direction, as a master asks for them.
    fn columns(m: &mut WheelRailModel, v: &Values, log: &Logger) -> Vec<Vec<f64>> {
        (0..6)
            .map(|c| {
                let mut seed = [0.0; 6];
                seed[c] = 1.0;
                m.directional_derivative(v, &OUTPUTS, &INPUTS, &seed, log)
                    .unwrap()
            })
            .collect()
    }

    #[test]
    fn derivatives_reused_at_one_point_are_those_of_a_fresh_instance_and_not_reused_elsewhere() {
        let log = Logger::new(None, false);
        // outputs a pure function of the inputs, so that instances agree bit for bit
        let mut exact = exact();
        exact.set(GRID_SIZE, Value::Integer(8));
        exact.set(WARM_START, Value::Boolean(false));
        exact.set(WETNESS, Value::Real(0.5));
        for mut v in [exact, with_table(0)] {
            let mut m = WheelRailModel::new(None);
            for xi in [0.003, 0.004] {
                v.set(CREEPAGE_LONGITUDINAL, Value::Real(xi));
                m.calculate(&mut v, &log).unwrap();
                assert_eq!(by_a_fresh_instance(&v, &log), v);
                let reused = columns(&mut m, &v, &log);
                assert_eq!(reused, columns(&mut WheelRailModel::new(None), &v, &log));
                assert!(reused.iter().flatten().any(|d| *d != 0.0));
            }
        }
    }

    #[test]
    fn geometry_inputs_change_every_step_and_leave_the_table_for_another_geometry() {
        let (log, seen) = capturing(false);
        let mut m = WheelRailModel::new(None);
        let mut v = with_table(0);
        // cold exact solves: bit for bit the library's
        v.set(WARM_START, Value::Boolean(false));
        let default_contact = |v: &Values| {
            [CONTACT_SEMI_AXIS_A, CONTACT_SEMI_AXIS_B, PEAK_PRESSURE].map(|i| v.real(i))
        };
        m.calculate(&mut v, &log).unwrap();
        assert_eq!(v.integer(EVALUATION_MODE), 1);
        let by_table = (outputs(&v), default_contact(&v));
        let mut params = WheelRailModel::params(&v).unwrap();
        let exact = wheelrail::model::Model::new(params.clone()).unwrap();
        let s = exact.solve(&input(&v)).unwrap();
        let g = &s.global;
        assert_eq!(by_table.1, [g.semi_axis_a, g.semi_axis_b, g.peak_pressure]);
        // each step another geometry: curvatures, prescribed semi-axes, back to the table's
        for (k, (a_curv, b_curv, axes)) in [
            (4.0, 0.8, [0.0, 0.0]),
            (1.015, 0.4215, [4e-3, 7e-3]),
            (2.0, 0.3, [0.0, 0.0]),
            (1.015, 0.4215, [0.0, 0.0]),
        ]
        .into_iter()
        .enumerate()
        {
            v.set(CURVATURE_LONGITUDINAL, Value::Real(a_curv));
            v.set(CURVATURE_LATERAL, Value::Real(b_curv));
            v.set(SEMI_AXIS_A, Value::Real(axes[0]));
            v.set(SEMI_AXIS_B, Value::Real(axes[1]));
            m.calculate(&mut v, &log).unwrap();
            params.geometry = Geometry::of_inputs(a_curv, b_curv, axes);
            if k == 3 {
                assert_eq!(v.integer(EVALUATION_MODE), 1, "step {k}");
                assert_eq!((outputs(&v), default_contact(&v)), by_table);
                continue;
            }
            assert_eq!(v.integer(EVALUATION_MODE), 2, "step {k}");
            let s = wheelrail::solve(&params, &input(&v)).unwrap();
            let g = &s.global;
            let want = [g.semi_axis_a, g.semi_axis_b, g.peak_pressure];
            assert_eq!(default_contact(&v), want, "step {k}");
            assert_eq!(v.real(FORCE_LONGITUDINAL), g.force_x, "step {k}");
        }
        assert_eq!(v.real(CONTACT_SEMI_AXIS_A), by_table.1[0]);
        let warnings: Vec<String> = seen.borrow().iter().map(|(_, _, m)| m.clone()).collect();
        let warnings = warnings.join("\n");
        assert_eq!(
            warnings.matches("contact geometry").count(),
            1,
            "{warnings}"
        );
        // the errors name the geometry inputs
        v.set(SEMI_AXIS_A, Value::Real(5e-3));
        let e = m.calculate(&mut v, &log).unwrap_err();
        assert!(e.contains("invalid value for semi_axis_b: 0 "), "{e}");
        v.set(SEMI_AXIS_A, Value::Real(0.0));
        v.set(CURVATURE_LATERAL, Value::Real(-1.0));
        let e = m.calculate(&mut v, &log).unwrap_err();
        assert!(
            e.contains("invalid value for curvature_lateral: -1 "),
            "{e}"
        );
    }

    #[test]
    fn derivatives_along_the_geometry_are_exact_differences() {
        let log = Logger::new(None, false);
        let mut m = WheelRailModel::new(None);
        let mut v = with_table(0);
        v.set(WARM_START, Value::Boolean(false));
        let unknowns = [FORCE_LONGITUDINAL, CONTACT_SEMI_AXIS_A, PEAK_PRESSURE];
        for (knowns, at) in [
            ([CURVATURE_LONGITUDINAL, CURVATURE_LATERAL], [1.015, 0.4215]),
            ([SEMI_AXIS_A, SEMI_AXIS_B], [5e-3, 8e-3]),
        ] {
            v.set(knowns[0], Value::Real(at[0]));
            v.set(knowns[1], Value::Real(at[1]));
            let seed = [1.0, 0.5];
            let d = m
                .directional_derivative(&v, &unknowns, &knowns, &seed, &log)
                .unwrap();
            // central differences through exact evaluations at the derivative tolerance
            let h = 1e-4 * at[0];
            let mut shifted = |sign: f64| {
                let mut w = v.clone();
                for (k, s) in knowns.iter().zip(seed) {
                    w.set(*k, Value::Real(w.real(*k) + sign * h * s));
                }
                let (e, mode, _) = m
                    .evaluate(&w, Some(DERIVATIVE_TOLERANCE), None, Start::Probe, &log)
                    .unwrap();
                write_outputs(&mut w, &e, &e.outputs().unwrap(), mode).unwrap();
                unknowns.map(|i| w.real(i))
            };
            let (p, q) = (shifted(1.0), shifted(-1.0));
            for r in 0..unknowns.len() {
                let fd = (p[r] - q[r]) / (2.0 * h);
                assert!(fd != 0.0, "{r}");
                assert!(
                    (d[r] - fd).abs() <= 2e-2 * fd.abs(),
                    "{:?}, output {r}: {} vs {fd}",
                    knowns,
                    d[r]
                );
            }
            v.set(
                knowns[0],
                Value::Real(if knowns[0] == SEMI_AXIS_A { 0.0 } else { 1.015 }),
            );
            v.set(
                knowns[1],
                Value::Real(if knowns[1] == SEMI_AXIS_B {
                    0.0
                } else {
                    0.4215
                }),
            );
        }
    }

    #[test]
    fn table_derivatives_are_those_of_the_interpolant_in_the_fmu_frame() {
        let log = Logger::new(None, false);
        let mut m = WheelRailModel::new(None);
        let mut v = with_table(0);
        // rolling backwards: the creepages and F_x, F_y turn
        v.set(ROLLING_SPEED, Value::Real(-30.0));
        // output and input scales for an absolute floor of the comparison
        let out_scale = [1e5, 1e5, 1e3, 1.0, 300.0, 1.0];
        let in_scale = [1e-2, 1e-2, 1.0, 1e5, 30.0, 1.0];
        let steps = [1e-7, 1e-7, 1e-6, 1.0, 1e-5, 1e-7];
        for c in 0..6 {
            let mut seed = [0.0; 6];
            seed[c] = 1.0;
            let d = m
                .directional_derivative(&v, &OUTPUTS, &INPUTS, &seed, &log)
                .unwrap();
            let mut at = |x: f64| {
                let mut w = v.clone();
                w.set(INPUTS[c], Value::Real(v.real(INPUTS[c]) + x));
                m.calculate(&mut w, &log).unwrap();
                assert_eq!(w.integer(EVALUATION_MODE), 1);
                outputs(&w)
            };
            let (p, q) = (at(steps[c]), at(-steps[c]));
            for r in 0..6 {
                let fd = (p[r] - q[r]) / (2.0 * steps[c]);
                let floor = 1e-6 * out_scale[r] / in_scale[c];
                assert!(
                    (d[r] - fd).abs() <= 1e-4 * fd.abs() + floor,
                    "output {r}, input {c}: {} vs {fd}",
                    d[r]
                );
            }
        }
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
