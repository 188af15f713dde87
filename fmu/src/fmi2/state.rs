//! The state machines of FMI 2.0 for Co-Simulation (standard §4.2.4) and Model Exchange (§3.2.3), with one
//! allowed-state mask per function in the style of the Modelica Reference-FMUs. A call outside its mask, or
//! a function of the other interface type (e.g. `fmi2DoStep` in a Model Exchange instance), is rejected
//! with "Illegal call sequence" and `fmi2Error`, and changes nothing.
//!
//! The standard's `stepFailed` state (after `fmi2DoStep` returned `fmi2Discard`) is never entered: a step
//! is synchronous and either completes (`fmi2OK`/`fmi2Warning`, outputs valid) or fails with `fmi2Error`.

/// The interface type of an instance (`fmuType` of `fmi2Instantiate`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Interface {
    /// `fmi2ModelExchange`: the importer's integrator drives the instance.
    ModelExchange = 1 << 0,
    /// `fmi2CoSimulation`: the instance advances by `fmi2DoStep`.
    CoSimulation = 1 << 1,
}

impl Interface {
    /// The interface type of an `fmuType` argument (`fmi2ModelExchange` = 0, `fmi2CoSimulation` = 1).
    pub fn of_fmu_type(fmu_type: i32) -> Option<Interface> {
        match fmu_type {
            0 => Some(Interface::ModelExchange),
            1 => Some(Interface::CoSimulation),
            _ => None,
        }
    }

    /// The name the standard uses.
    pub fn name(self) -> &'static str {
        match self {
            Interface::ModelExchange => "Model Exchange",
            Interface::CoSimulation => "Co-Simulation",
        }
    }
}

/// The state of one instance. Each state is one bit so that a set of states is a mask.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u16)]
pub enum State {
    /// After `fmi2Instantiate` or `fmi2Reset`: parameters and start values may be set.
    Instantiated = 1 << 0,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    InitializationMode = 1 << 1,
    /// Co-Simulation: a communication point: inputs may be set, outputs read, `fmi2DoStep` called.
    StepComplete = 1 << 2,
    /// After `fmi2Terminate`.
    Terminated = 1 << 4,
    /// A computation returned `fmi2Error`: only inquiries, state restore, reset and free are allowed.
    Error = 1 << 5,
    /// Model Exchange: after `fmi2ExitInitializationMode` and `fmi2EnterEventMode`: any input may change.
    EventMode = 1 << 6,
    /// Model Exchange: the integrator's continuous-time integration (`fmi2EnterContinuousTimeMode`).
    ContinuousTimeMode = 1 << 7,
}

impl State {
    /// Every state.
    pub const ALL: [State; 7] = [
        State::Instantiated,
        State::InitializationMode,
        State::StepComplete,
        State::Terminated,
        State::Error,
        State::EventMode,
        State::ContinuousTimeMode,
    ];

    /// Whether an instance of `interface` can be in this state (the states of the other interface's
    /// time integration are not).
    pub fn belongs_to(self, interface: Interface) -> bool {
        match self {
            State::StepComplete => interface == Interface::CoSimulation,
            State::EventMode | State::ContinuousTimeMode => interface == Interface::ModelExchange,
            _ => true,
        }
    }
}

/// A state of a state machine whose states are one bit each (those of FMI 2.0 here, of FMI 3.0 in
/// [`crate::fmi3::state`]), so that a [`Mask`] holds a set of them.
pub trait StateBit: Copy {
    /// The state's bit.
    fn bit(self) -> u16;
}

impl StateBit for State {
    fn bit(self) -> u16 {
        self as u16
    }
}

/// A set of states, and the interface types a function belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mask {
    states: u16,
    interfaces: u8,
}

impl Mask {
    /// The states `states`, for functions of both interface types.
    const fn of(states: &[State]) -> Mask {
        let mut bits = 0;
        let mut i = 0;
        while i < states.len() {
            bits |= states[i] as u16;
            i += 1;
        }
        Mask::of_bits(bits)
    }

    /// The states of the bits `states`, for functions of both interface types.
    pub const fn of_bits(states: u16) -> Mask {
        Mask {
            states,
            interfaces: Interface::ModelExchange as u8 | Interface::CoSimulation as u8,
        }
    }

    /// The same states for a function of `interface` only.
    pub const fn only(self, interface: Interface) -> Mask {
        Mask {
            states: self.states,
            interfaces: interface as u8,
        }
    }

    /// Whether `state` is in the set.
    pub fn allows(self, state: impl StateBit) -> bool {
        self.states & state.bit() != 0
    }

    /// Whether the function belongs to `interface`.
    pub fn serves(self, interface: Interface) -> bool {
        self.interfaces & interface as u8 != 0
    }
}

use Interface::{CoSimulation as CS, ModelExchange as ME};
use State::*;

/// Every state an instance can be in.
pub const ANY: Mask = Mask::of(&State::ALL);
/// `fmi2SetupExperiment`, `fmi2EnterInitializationMode`.
pub const SETUP: Mask = Mask::of(&[Instantiated]);
/// `fmi2ExitInitializationMode`.
pub const EXIT_INITIALIZATION: Mask = Mask::of(&[InitializationMode]);
/// `fmi2Terminate`.
pub const TERMINATE: Mask = Mask::of(&[StepComplete, EventMode, ContinuousTimeMode]);
/// `fmi2Get{Real,Integer,Boolean,String}`, `fmi2GetDirectionalDerivative`.
pub const GET: Mask = Mask::of(&[
    InitializationMode,
    StepComplete,
    EventMode,
    ContinuousTimeMode,
    Terminated,
    Error,
]);
/// `fmi2Set*` of inputs and of fixed parameters (parameters are further restricted by their variability).
pub const SET: Mask = Mask::of(&[
    Instantiated,
    InitializationMode,
    StepComplete,
    EventMode,
    ContinuousTimeMode,
]);
/// `fmi2SetRealInputDerivatives`.
pub const SET_INPUT_DERIVATIVES: Mask =
    Mask::of(&[Instantiated, InitializationMode, StepComplete]).only(CS);
/// `fmi2GetRealOutputDerivatives`.
pub const GET_OUTPUT_DERIVATIVES: Mask = Mask::of(&[StepComplete, Terminated, Error]).only(CS);
/// `fmi2DoStep`.
pub const DO_STEP: Mask = Mask::of(&[StepComplete]).only(CS);
/// `fmi2CancelStep`: only while an asynchronous step is in progress, which never happens here.
pub const CANCEL_STEP: Mask = Mask::of(&[]).only(CS);
/// `fmi2Get*Status`.
pub const STATUS: Mask = Mask::of(&[StepComplete, Terminated]).only(CS);
/// `fmi2Reset`, `fmi2FreeInstance`, the FMU-state functions, `fmi2SetDebugLogging`.
pub const RESET: Mask = ANY;
/// The states in which fixed parameters may still be set.
pub const SET_FIXED_PARAMETER: Mask = Mask::of(&[Instantiated, InitializationMode]);
/// `fmi2EnterEventMode`.
pub const ENTER_EVENT_MODE: Mask = Mask::of(&[EventMode, ContinuousTimeMode]).only(ME);
/// `fmi2NewDiscreteStates`.
pub const NEW_DISCRETE_STATES: Mask = Mask::of(&[EventMode]).only(ME);
/// `fmi2EnterContinuousTimeMode`.
pub const ENTER_CONTINUOUS_TIME_MODE: Mask = Mask::of(&[EventMode]).only(ME);
/// `fmi2CompletedIntegratorStep`.
pub const COMPLETED_INTEGRATOR_STEP: Mask = Mask::of(&[ContinuousTimeMode]).only(ME);
/// `fmi2SetTime`.
pub const SET_TIME: Mask = Mask::of(&[EventMode, ContinuousTimeMode]).only(ME);
/// `fmi2SetContinuousStates`.
pub const SET_CONTINUOUS_STATES: Mask = Mask::of(&[ContinuousTimeMode]).only(ME);
/// `fmi2GetEventIndicators`, `fmi2GetContinuousStates`.
pub const GET_EVENT_INDICATORS: Mask = Mask::of(&[
    InitializationMode,
    EventMode,
    ContinuousTimeMode,
    Terminated,
    Error,
])
.only(ME);
/// `fmi2GetDerivatives`.
pub const GET_DERIVATIVES: Mask =
    Mask::of(&[EventMode, ContinuousTimeMode, Terminated, Error]).only(ME);
/// `fmi2GetNominalsOfContinuousStates`.
pub const GET_NOMINALS: Mask = Mask::of(&[
    Instantiated,
    EventMode,
    ContinuousTimeMode,
    Terminated,
    Error,
])
.only(ME);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masks_follow_the_cosimulation_state_machine() {
        assert!(SETUP.allows(Instantiated) && !SETUP.allows(StepComplete));
        assert!(DO_STEP.allows(StepComplete) && !DO_STEP.allows(InitializationMode));
        assert!(!DO_STEP.allows(Error) && !DO_STEP.allows(Terminated));
        assert!(GET.allows(Error) && !GET.allows(Instantiated));
        assert!(
            SET_FIXED_PARAMETER.allows(InitializationMode)
                && !SET_FIXED_PARAMETER.allows(StepComplete)
        );
        assert!(!SET.allows(Error) && !SET.allows(Terminated));
        for s in State::ALL {
            assert!(ANY.allows(s));
            assert!(!CANCEL_STEP.allows(s));
        }
    }

    #[test]
    fn masks_follow_the_model_exchange_state_machine_and_separate_the_interfaces() {
        use Interface::{CoSimulation, ModelExchange};
        assert!(COMPLETED_INTEGRATOR_STEP.allows(ContinuousTimeMode));
        assert!(!COMPLETED_INTEGRATOR_STEP.allows(EventMode));
        assert!(
            NEW_DISCRETE_STATES.allows(EventMode)
                && !NEW_DISCRETE_STATES.allows(ContinuousTimeMode)
        );
        assert!(ENTER_EVENT_MODE.allows(EventMode) && ENTER_EVENT_MODE.allows(ContinuousTimeMode));
        assert!(!SET_TIME.allows(Instantiated) && !GET_DERIVATIVES.allows(InitializationMode));
        assert!(
            GET_NOMINALS.allows(Instantiated) && GET_EVENT_INDICATORS.allows(InitializationMode)
        );
        assert!(GET.allows(ContinuousTimeMode) && SET.allows(ContinuousTimeMode));
        assert!(TERMINATE.allows(EventMode) && !TERMINATE.allows(InitializationMode));
        for m in [
            DO_STEP,
            CANCEL_STEP,
            STATUS,
            SET_INPUT_DERIVATIVES,
            GET_OUTPUT_DERIVATIVES,
        ] {
            assert!(m.serves(CoSimulation) && !m.serves(ModelExchange));
        }
        for m in [
            ENTER_EVENT_MODE,
            NEW_DISCRETE_STATES,
            ENTER_CONTINUOUS_TIME_MODE,
            COMPLETED_INTEGRATOR_STEP,
            SET_TIME,
            SET_CONTINUOUS_STATES,
            GET_EVENT_INDICATORS,
            GET_DERIVATIVES,
            GET_NOMINALS,
        ] {
            assert!(m.serves(ModelExchange) && !m.serves(CoSimulation));
        }
        for m in [SETUP, EXIT_INITIALIZATION, TERMINATE, GET, SET, RESET] {
            assert!(m.serves(ModelExchange) && m.serves(CoSimulation));
        }
        assert!(StepComplete.belongs_to(CoSimulation) && !StepComplete.belongs_to(ModelExchange));
        assert!(
            EventMode.belongs_to(ModelExchange) && !ContinuousTimeMode.belongs_to(CoSimulation)
        );
        assert!(Terminated.belongs_to(ModelExchange) && Terminated.belongs_to(CoSimulation));
        assert_eq!(Interface::of_fmu_type(0), Some(ModelExchange));
        assert_eq!(Interface::of_fmu_type(1), Some(CoSimulation));
        assert_eq!(Interface::of_fmu_type(2), None);
    }
}
