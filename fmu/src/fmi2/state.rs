//! The co-simulation state machine of FMI 2.0 (standard §4.2.4), with one allowed-state mask per function
//! in the style of the Modelica Reference-FMUs. A call outside its mask is rejected with
//! "Illegal call sequence" and `fmi2Error`, and changes nothing.
//!
//! The standard's `stepFailed` state (after `fmi2DoStep` returned `fmi2Discard`) is never entered: a step
//! is synchronous and either completes (`fmi2OK`/`fmi2Warning`, outputs valid) or fails with `fmi2Error`.

/// The state of one instance. Each state is one bit so that a set of states is a mask.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u16)]
pub enum State {
    /// After `fmi2Instantiate` or `fmi2Reset`: parameters and start values may be set.
    Instantiated = 1 << 0,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    InitializationMode = 1 << 1,
    /// A communication point: inputs may be set, outputs read, `fmi2DoStep` called.
    StepComplete = 1 << 2,
    /// After `fmi2Terminate`.
    Terminated = 1 << 4,
    /// A computation returned `fmi2Error`: only inquiries, state restore, reset and free are allowed.
    Error = 1 << 5,
}

impl State {
    /// Every state.
    pub const ALL: [State; 5] = [
        State::Instantiated,
        State::InitializationMode,
        State::StepComplete,
        State::Terminated,
        State::Error,
    ];
}

/// A set of states.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mask(u16);

impl Mask {
    const fn of(states: &[State]) -> Mask {
        let mut bits = 0;
        let mut i = 0;
        while i < states.len() {
            bits |= states[i] as u16;
            i += 1;
        }
        Mask(bits)
    }

    /// Whether `state` is in the set.
    pub fn allows(self, state: State) -> bool {
        self.0 & state as u16 != 0
    }
}

use State::*;

/// Every state an instance can be in.
pub const ANY: Mask = Mask::of(&State::ALL);
/// `fmi2SetupExperiment`, `fmi2EnterInitializationMode`.
pub const SETUP: Mask = Mask::of(&[Instantiated]);
/// `fmi2ExitInitializationMode`.
pub const EXIT_INITIALIZATION: Mask = Mask::of(&[InitializationMode]);
/// `fmi2Terminate`.
pub const TERMINATE: Mask = Mask::of(&[StepComplete]);
/// `fmi2Get{Real,Integer,Boolean,String}`, `fmi2GetDirectionalDerivative`.
pub const GET: Mask = Mask::of(&[InitializationMode, StepComplete, Terminated, Error]);
/// `fmi2Set*` of inputs and of fixed parameters (parameters are further restricted by their variability).
pub const SET: Mask = Mask::of(&[Instantiated, InitializationMode, StepComplete]);
/// `fmi2SetRealInputDerivatives`.
pub const SET_INPUT_DERIVATIVES: Mask = Mask::of(&[Instantiated, InitializationMode, StepComplete]);
/// `fmi2GetRealOutputDerivatives`.
pub const GET_OUTPUT_DERIVATIVES: Mask = Mask::of(&[StepComplete, Terminated, Error]);
/// `fmi2DoStep`.
pub const DO_STEP: Mask = Mask::of(&[StepComplete]);
/// `fmi2CancelStep`: only while an asynchronous step is in progress, which never happens here.
pub const CANCEL_STEP: Mask = Mask::of(&[]);
/// `fmi2Get*Status`.
pub const STATUS: Mask = Mask::of(&[StepComplete, Terminated]);
/// `fmi2Reset`, `fmi2FreeInstance`, the FMU-state functions, `fmi2SetDebugLogging`.
pub const RESET: Mask = ANY;
/// The states in which fixed parameters may still be set.
pub const SET_FIXED_PARAMETER: Mask = Mask::of(&[Instantiated, InitializationMode]);

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
}
