//! The state machine of FMI 3.0 for Co-Simulation (standard §4.2) and Model Exchange (§3.2), with one
//! allowed-state mask per function in the style of the Modelica Reference-FMUs. A call outside its mask, or
//! a function of the other interface type, is rejected with "Illegal call sequence" and `fmi3Error`, and
//! changes nothing. `Error` is the state after a computation failed (`fmi3Error` semantics: only inquiries,
//! FMU-state functions, reset and free remain).
//!
//! Configuration mode is entered from `Instantiated` only: the structural parameters are fixed, so there is
//! no reconfiguration mode in the step or event modes. Co-Simulation instantiated with `eventModeUsed`
//! enters event mode after initialization (and `fmi3EnterStepMode` leaves it); there are no events.

use crate::fmi2::state::StateBit;
pub use crate::fmi2::state::{Interface, Mask};

/// The state of one instance; each state one bit so that a set of states is a mask.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u16)]
pub enum State {
    /// After instantiation or `fmi3Reset`: parameters and start values may be set.
    Instantiated = 1 << 0,
    /// Between `fmi3EnterConfigurationMode` and `fmi3ExitConfigurationMode`: structural parameters may be
    /// set.
    ConfigurationMode = 1 << 1,
    /// Between `fmi3EnterInitializationMode` and `fmi3ExitInitializationMode`.
    InitializationMode = 1 << 2,
    /// Model Exchange, or Co-Simulation with event mode used: event handling.
    EventMode = 1 << 3,
    /// Co-Simulation: a communication point: inputs set, outputs read, `fmi3DoStep`.
    StepMode = 1 << 4,
    /// Model Exchange: continuous-time integration.
    ContinuousTimeMode = 1 << 5,
    /// After `fmi3Terminate`.
    Terminated = 1 << 6,
    /// A computation failed.
    Error = 1 << 7,
}

impl State {
    /// Every state.
    pub const ALL: [State; 8] = [
        State::Instantiated,
        State::ConfigurationMode,
        State::InitializationMode,
        State::EventMode,
        State::StepMode,
        State::ContinuousTimeMode,
        State::Terminated,
        State::Error,
    ];

    /// Whether an instance of `interface` can be in this state.
    pub fn belongs_to(self, interface: Interface) -> bool {
        match self {
            State::StepMode => interface == Interface::CoSimulation,
            State::ContinuousTimeMode => interface == Interface::ModelExchange,
            _ => true,
        }
    }
}

impl StateBit for State {
    fn bit(self) -> u16 {
        self as u16
    }
}

/// The mask of `states`, for functions of both interface types.
const fn of(states: &[State]) -> Mask {
    let mut bits = 0;
    let mut i = 0;
    while i < states.len() {
        bits |= states[i] as u16;
        i += 1;
    }
    Mask::of_bits(bits)
}

use Interface::{CoSimulation as CS, ModelExchange as ME};
use State::*;

/// Every state.
pub const ANY: Mask = of(&State::ALL);
/// No state (functions of an interface type this FMU does not provide).
pub const NONE: Mask = of(&[]);
/// `fmi3EnterInitializationMode`, `fmi3EnterConfigurationMode`.
pub const INSTANTIATED: Mask = of(&[Instantiated]);
/// `fmi3ExitConfigurationMode`.
pub const EXIT_CONFIGURATION: Mask = of(&[ConfigurationMode]);
/// `fmi3ExitInitializationMode`.
pub const EXIT_INITIALIZATION: Mask = of(&[InitializationMode]);
/// `fmi3EnterEventMode` (Co-Simulation only with event mode used).
pub const ENTER_EVENT_MODE: Mask = of(&[StepMode, ContinuousTimeMode]);
/// `fmi3Terminate`.
pub const TERMINATE: Mask = of(&[EventMode, StepMode, ContinuousTimeMode]);
/// `fmi3Get*`.
pub const GET: Mask = of(&[
    Instantiated,
    ConfigurationMode,
    InitializationMode,
    EventMode,
    StepMode,
    ContinuousTimeMode,
    Terminated,
    Error,
]);
/// `fmi3Set*` (each variable further restricted by its causality and variability).
pub const SET: Mask = of(&[
    Instantiated,
    ConfigurationMode,
    InitializationMode,
    EventMode,
    StepMode,
    ContinuousTimeMode,
]);
/// The states in which fixed parameters may be set.
pub const SET_FIXED_PARAMETER: Mask = of(&[Instantiated, InitializationMode]);
/// The states in which structural parameters of variability fixed may be set.
pub const SET_STRUCTURAL_PARAMETER: Mask = of(&[ConfigurationMode]);
/// The states in which inputs may be set.
pub const SET_INPUT: Mask = of(&[
    Instantiated,
    InitializationMode,
    EventMode,
    StepMode,
    ContinuousTimeMode,
]);
/// The states in which outputs are brought to the current inputs before they are read.
pub const UPDATE_OUTPUTS: Mask = of(&[InitializationMode, EventMode, StepMode, ContinuousTimeMode]);
/// `fmi3GetDirectionalDerivative`, `fmi3GetAdjointDerivative`.
pub const DERIVATIVE: Mask = of(&[
    InitializationMode,
    EventMode,
    StepMode,
    ContinuousTimeMode,
    Terminated,
    Error,
]);
/// `fmi3UpdateDiscreteStates`, `fmi3EvaluateDiscreteStates`.
pub const EVENT: Mask = of(&[EventMode]);
/// `fmi3EnterStepMode`.
pub const ENTER_STEP_MODE: Mask = of(&[EventMode]).only(CS);
/// `fmi3DoStep`.
pub const DO_STEP: Mask = of(&[StepMode]).only(CS);
/// `fmi3GetOutputDerivatives`.
pub const GET_OUTPUT_DERIVATIVES: Mask = of(&[StepMode, Terminated, Error]).only(CS);
/// `fmi3EnterContinuousTimeMode`.
pub const ENTER_CONTINUOUS_TIME_MODE: Mask = of(&[EventMode]).only(ME);
/// `fmi3CompletedIntegratorStep`, `fmi3SetContinuousStates`.
pub const CONTINUOUS_TIME: Mask = of(&[ContinuousTimeMode]).only(ME);
/// `fmi3SetTime`.
pub const SET_TIME: Mask = of(&[EventMode, ContinuousTimeMode]).only(ME);
/// `fmi3GetContinuousStateDerivatives`, `fmi3GetEventIndicators`, `fmi3GetContinuousStates`,
/// `fmi3GetNominalsOfContinuousStates`.
pub const GET_CONTINUOUS: Mask = of(&[
    InitializationMode,
    EventMode,
    ContinuousTimeMode,
    Terminated,
    Error,
])
.only(ME);
/// `fmi3GetNumberOfContinuousStates`, `fmi3GetNumberOfEventIndicators`.
pub const NUMBERS: Mask = ANY.only(ME);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masks_follow_the_state_machines_and_separate_the_interfaces() {
        assert!(INSTANTIATED.allows(Instantiated) && !INSTANTIATED.allows(StepMode));
        assert!(DO_STEP.allows(StepMode) && !DO_STEP.allows(EventMode));
        assert!(DO_STEP.serves(CS) && !DO_STEP.serves(ME));
        assert!(CONTINUOUS_TIME.serves(ME) && !CONTINUOUS_TIME.serves(CS));
        assert!(
            SET_STRUCTURAL_PARAMETER.allows(ConfigurationMode)
                && !SET_STRUCTURAL_PARAMETER.allows(Instantiated)
        );
        assert!(!SET_INPUT.allows(ConfigurationMode) && !SET.allows(Error));
        assert!(!SET_FIXED_PARAMETER.allows(StepMode) && GET.allows(Error));
        assert!(!TERMINATE.allows(InitializationMode));
        for s in State::ALL {
            assert!(ANY.allows(s) && !NONE.allows(s));
        }
        assert!(StepMode.belongs_to(CS) && !StepMode.belongs_to(ME));
        assert!(EventMode.belongs_to(CS) && EventMode.belongs_to(ME));
        assert!(!ContinuousTimeMode.belongs_to(CS));
    }
}
