//! The model contract: what a model provides to the generic FMI layer (Co-Simulation and Model
//! Exchange). The layer owns the instance, the state machines, the values of all variables, logging, FMU
//! states and the C boundary; a model only describes itself and computes its outputs from the current
//! values.

use super::ffi::Status;
use super::logging::Logger;
use super::snapshot::ModelState;
use super::variables::{Values, Variable};
use std::path::PathBuf;

/// A unit of `<UnitDefinitions>`: name and SI base-unit exponents (kg, m, s, K).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    /// Unit name as used in the variables' `unit` attribute.
    pub name: &'static str,
    /// Exponent of kilogram.
    pub kg: i32,
    /// Exponent of metre.
    pub m: i32,
    /// Exponent of second.
    pub s: i32,
    /// Exponent of kelvin.
    pub k: i32,
    /// The units an importer may show values of this unit in.
    pub display: &'static [DisplayUnit],
}

/// A `<DisplayUnit>` of a [`Unit`] (FMI 2.0 §2.2.2): a value shown in it is `factor · value + offset`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DisplayUnit {
    /// The display unit's name (the variables' `displayUnit` attribute).
    pub name: &'static str,
    /// Factor from the unit to the display unit.
    pub factor: f64,
    /// Offset added after the factor (e.g. −273.15 from kelvin to degrees Celsius).
    pub offset: f64,
}

/// `<DefaultExperiment>`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DefaultExperiment {
    /// Start time [s].
    pub start_time: f64,
    /// Stop time [s].
    pub stop_time: f64,
    /// Communication step size [s].
    pub step_size: f64,
}

/// Everything `modelDescription.xml` says about a model besides the generic layer's capability flags.
#[derive(Debug, Clone, Copy)]
pub struct ModelInfo {
    /// `modelName`.
    pub model_name: &'static str,
    /// `modelIdentifier`: the shared library's file stem.
    pub model_identifier: &'static str,
    /// `description`.
    pub description: &'static str,
    /// `author`.
    pub author: &'static str,
    /// `version` of the model (the crate version).
    pub version: &'static str,
    /// `license`.
    pub license: &'static str,
    /// `generationTool`.
    pub generation_tool: &'static str,
    /// Units used by the variables.
    pub units: &'static [Unit],
    /// The display unit a variable is shown in by default (its `displayUnit` attribute), if any: one of
    /// the display units of its unit.
    pub display_unit: fn(&Variable) -> Option<&'static str>,
    /// The variable table.
    pub variables: &'static [Variable],
    /// The default experiment.
    pub default_experiment: DefaultExperiment,
}

/// A model behind the generic FMI 2.0 layer. Every output is a function of the parameters,
/// the current inputs and the model's [`Model::State`] (no continuous states): the layer recomputes outputs
/// whenever a value changed.
pub trait Model: Sized {
    /// What the model remembers between calls that influences later outputs (an inner solver's warm
    /// start): part of the FMU state. Anything else the model keeps (caches) must be a pure function of
    /// the values and this state.
    type State: ModelState;

    /// The model description.
    fn info() -> &'static ModelInfo;

    /// A new model for an instance; `resources` is the FMU's unpacked `resources/` directory, if known.
    fn new(resources: Option<PathBuf>) -> Self;

    /// Forgets what the model remembers across calls (issued one-time warnings, caches); `fmi2Reset`.
    fn reset(&mut self);

    /// The model's current state (`fmi2GetFMUstate`).
    fn state(&self) -> Self::State;

    /// Continues from `state`, taken of this or another instance of the model, perhaps with other
    /// parameters (`fmi2SetFMUstate`): later outputs are bit for bit those the instance it was taken of
    /// gives for the same calls.
    fn set_state(&mut self, state: &Self::State);

    /// Computes every output from the parameters and inputs in `values` and writes them into `values`.
    /// Returns `Status::Ok` or `Status::Warning` (after logging the warning); `Err` is a message for
    /// `fmi2Error`.
    fn calculate(&mut self, values: &mut Values, log: &Logger) -> Result<Status, String>;

    /// Computes every output as [`Model::calculate`] does, but as a function of the values and the
    /// model's current state only: the state is left as it is, so that the same values give the same
    /// outputs however often and in whatever order they are evaluated (Model Exchange: an implicit
    /// integrator evaluates the outputs repeatedly within one step, e.g. in its Newton iteration).
    fn calculate_trial(&mut self, values: &mut Values, log: &Logger) -> Result<Status, String>;

    /// Advances the model's state to the one [`Model::calculate`] leaves when it starts from the current
    /// state at `values` (Model Exchange: at an accepted point of the integration). `values` hold the
    /// outputs of [`Model::calculate_trial`] at these values.
    fn accept(&mut self, values: &Values, log: &Logger) -> Result<Status, String>;

    /// The directional derivative Σ_j ∂y_i/∂u_j·seed_j of the Real outputs `unknowns` with respect to the
    /// Real inputs `knowns` (table indices) at the current values.
    fn directional_derivative(
        &mut self,
        values: &Values,
        unknowns: &[usize],
        knowns: &[usize],
        seed: &[f64],
        log: &Logger,
    ) -> Result<Vec<f64>, String>;
}
