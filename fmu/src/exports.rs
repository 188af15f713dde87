//! The exported FMI 2.0 functions of WheelRailFriction (all common, Co-Simulation and Model Exchange
//! functions of `fmi2Functions.h`). Each body is one call into the generic layer [`crate::fmi2::api`].
//!
//! # Safety
//! The importer must follow the FMI 2.0 standard (valid pointers, array lengths, one thread per instance).
//! That contract is the same for every function, so it is stated once here.
#![allow(clippy::missing_safety_doc)]

use crate::contact::WheelRailModel as M;
use crate::fmi2::api;
use crate::fmi2::ffi::*;
use crate::fmi2::state;
use crate::fmi2::variables::{Type, Value};
use std::ffi::c_int;

fn real(v: &Value) -> Fmi2Real {
    match v {
        Value::Real(x) => *x,
        _ => unreachable!("values are read by type"),
    }
}

fn integer(v: &Value) -> Fmi2Integer {
    match v {
        Value::Integer(x) => *x,
        _ => unreachable!("values are read by type"),
    }
}

fn boolean(v: &Value) -> Fmi2Boolean {
    match v {
        Value::Boolean(x) => Fmi2Boolean::from(*x),
        _ => unreachable!("values are read by type"),
    }
}

/// `fmi2GetTypesPlatform`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> Fmi2String {
    FMI2_TYPES_PLATFORM.as_ptr()
}

/// `fmi2GetVersion`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> Fmi2String {
    FMI2_VERSION.as_ptr()
}

/// `fmi2SetDebugLogging`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: Fmi2Component,
    logging_on: Fmi2Boolean,
    n_categories: usize,
    categories: *const Fmi2String,
) -> Fmi2StatusC {
    unsafe { api::set_debug_logging::<M>(c, logging_on, n_categories, categories) }
}

/// `fmi2Instantiate` (`visible` is ignored: there is no user interface).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: Fmi2String,
    fmu_type: c_int,
    fmu_guid: Fmi2String,
    fmu_resource_location: Fmi2String,
    functions: *const Fmi2CallbackFunctions,
    _visible: Fmi2Boolean,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    unsafe {
        api::instantiate::<M>(
            instance_name,
            fmu_type,
            fmu_guid,
            fmu_resource_location,
            functions,
            logging_on,
        )
    }
}

/// `fmi2FreeInstance`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
    unsafe { api::free_instance::<M>(c) }
}

/// `fmi2SetupExperiment` (tolerance and stop time are not used: the model's own solver tolerance applies).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: Fmi2Component,
    _tolerance_defined: Fmi2Boolean,
    _tolerance: Fmi2Real,
    start_time: Fmi2Real,
    _stop_time_defined: Fmi2Boolean,
    _stop_time: Fmi2Real,
) -> Fmi2StatusC {
    unsafe { api::setup_experiment::<M>(c, start_time) }
}

/// `fmi2EnterInitializationMode`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Fmi2Component) -> Fmi2StatusC {
    unsafe { api::enter_initialization_mode::<M>(c) }
}

/// `fmi2ExitInitializationMode`: computes the outputs of the current inputs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2StatusC {
    unsafe { api::exit_initialization_mode::<M>(c) }
}

/// `fmi2Terminate`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2StatusC {
    unsafe { api::terminate::<M>(c) }
}

/// `fmi2Reset`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2StatusC {
    unsafe { api::reset::<M>(c) }
}

/// `fmi2GetReal`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Real,
) -> Fmi2StatusC {
    unsafe { api::get::<M, _>(c, "fmi2GetReal", Type::Real, vr, nvr, value, real) }
}

/// `fmi2GetInteger`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetInteger(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Integer,
) -> Fmi2StatusC {
    unsafe { api::get::<M, _>(c, "fmi2GetInteger", Type::Integer, vr, nvr, value, integer) }
}

/// `fmi2GetBoolean`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2Boolean,
) -> Fmi2StatusC {
    unsafe { api::get::<M, _>(c, "fmi2GetBoolean", Type::Boolean, vr, nvr, value, boolean) }
}

/// `fmi2GetString`: the strings stay valid until the next `fmi2GetString` call of the instance.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetString(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *mut Fmi2String,
) -> Fmi2StatusC {
    unsafe { api::get_string::<M>(c, vr, nvr, value) }
}

/// `fmi2SetReal`: non-finite values are rejected with `fmi2Error`, naming the variable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Real,
) -> Fmi2StatusC {
    unsafe { api::set::<M, Fmi2Real>(c, "fmi2SetReal", vr, nvr, value, |x| Ok(Value::Real(x))) }
}

/// `fmi2SetInteger`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetInteger(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Integer,
) -> Fmi2StatusC {
    unsafe {
        api::set::<M, Fmi2Integer>(c, "fmi2SetInteger", vr, nvr, value, |x| {
            Ok(Value::Integer(x))
        })
    }
}

/// `fmi2SetBoolean`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2Boolean,
) -> Fmi2StatusC {
    unsafe {
        api::set::<M, Fmi2Boolean>(c, "fmi2SetBoolean", vr, nvr, value, |x| {
            Ok(Value::Boolean(x != FMI2_FALSE))
        })
    }
}

/// `fmi2SetString`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetString(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    nvr: usize,
    value: *const Fmi2String,
) -> Fmi2StatusC {
    unsafe {
        api::set::<M, Fmi2String>(c, "fmi2SetString", vr, nvr, value, |s| api::string_value(s))
    }
}

/// `fmi2GetFMUstate`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(
    c: Fmi2Component,
    state: *mut Fmi2FmuState,
) -> Fmi2StatusC {
    unsafe { api::get_fmu_state::<M>(c, state) }
}

/// `fmi2SetFMUstate`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Fmi2Component, state: Fmi2FmuState) -> Fmi2StatusC {
    unsafe { api::set_fmu_state::<M>(c, state) }
}

/// `fmi2FreeFMUstate`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(
    c: Fmi2Component,
    state: *mut Fmi2FmuState,
) -> Fmi2StatusC {
    unsafe { api::free_fmu_state::<M>(c, state) }
}

/// `fmi2SerializedFMUstateSize`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: Fmi2Component,
    state: Fmi2FmuState,
    size: *mut usize,
) -> Fmi2StatusC {
    unsafe { api::serialized_fmu_state_size::<M>(c, state, size) }
}

/// `fmi2SerializeFMUstate`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Fmi2Component,
    state: Fmi2FmuState,
    serialized_state: *mut Fmi2Byte,
    size: usize,
) -> Fmi2StatusC {
    unsafe { api::serialize_fmu_state::<M>(c, state, serialized_state, size) }
}

/// `fmi2DeSerializeFMUstate`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Fmi2Component,
    serialized_state: *const Fmi2Byte,
    size: usize,
    state: *mut Fmi2FmuState,
) -> Fmi2StatusC {
    unsafe { api::deserialize_fmu_state::<M>(c, serialized_state, size, state) }
}

/// `fmi2GetDirectionalDerivative`: Real outputs with respect to Real inputs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: Fmi2Component,
    v_unknown_ref: *const Fmi2ValueReference,
    n_unknown: usize,
    v_known_ref: *const Fmi2ValueReference,
    n_known: usize,
    dv_known: *const Fmi2Real,
    dv_unknown: *mut Fmi2Real,
) -> Fmi2StatusC {
    unsafe {
        api::get_directional_derivative::<M>(
            c,
            v_unknown_ref,
            n_unknown,
            v_known_ref,
            n_known,
            dv_known,
            dv_unknown,
        )
    }
}

/// `fmi2SetRealInputDerivatives`: not supported (`canInterpolateInputs="false"`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: Fmi2Component,
    _vr: *const Fmi2ValueReference,
    _nvr: usize,
    _order: *const Fmi2Integer,
    _value: *const Fmi2Real,
) -> Fmi2StatusC {
    unsafe {
        api::unsupported::<M>(
            c,
            "fmi2SetRealInputDerivatives",
            state::SET_INPUT_DERIVATIVES,
            "canInterpolateInputs is false",
        )
    }
}

/// `fmi2GetRealOutputDerivatives`: not supported (`maxOutputDerivativeOrder="0"`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: Fmi2Component,
    _vr: *const Fmi2ValueReference,
    _nvr: usize,
    _order: *const Fmi2Integer,
    _value: *mut Fmi2Real,
) -> Fmi2StatusC {
    unsafe {
        api::unsupported::<M>(
            c,
            "fmi2GetRealOutputDerivatives",
            state::GET_OUTPUT_DERIVATIVES,
            "maxOutputDerivativeOrder is 0",
        )
    }
}

/// `fmi2DoStep`: brings the outputs to the current inputs (quasi-static) and advances the time.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(
    c: Fmi2Component,
    current_communication_point: Fmi2Real,
    communication_step_size: Fmi2Real,
    _no_set_fmu_state_prior_to_current_point: Fmi2Boolean,
) -> Fmi2StatusC {
    unsafe { api::do_step::<M>(c, current_communication_point, communication_step_size) }
}

/// `fmi2CancelStep`: steps are synchronous, so this is always an illegal call sequence.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2StatusC {
    unsafe { api::cancel_step::<M>(c) }
}

/// `fmi2GetStatus`: `fmi2DoStepStatus` gives the status of the last `fmi2DoStep`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2StatusC,
) -> Fmi2StatusC {
    unsafe {
        api::get_status::<M, _>(c, "fmi2GetStatus", kind, value, |i, k| {
            (k == FMI2_DO_STEP_STATUS).then_some(i.last_step_status() as c_int)
        })
    }
}

/// `fmi2GetRealStatus`: `fmi2LastSuccessfulTime` gives the time after the last step.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2Real,
) -> Fmi2StatusC {
    unsafe {
        api::get_status::<M, _>(c, "fmi2GetRealStatus", kind, value, |i, k| {
            (k == FMI2_LAST_SUCCESSFUL_TIME).then_some(i.time())
        })
    }
}

/// `fmi2GetIntegerStatus`: no Integer status kind exists (`fmi2Discard`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2Integer,
) -> Fmi2StatusC {
    unsafe { api::get_status::<M, _>(c, "fmi2GetIntegerStatus", kind, value, |_, _| None) }
}

/// `fmi2GetBooleanStatus`: `fmi2Terminated` is always false (the FMU never asks to stop).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2Boolean,
) -> Fmi2StatusC {
    unsafe {
        api::get_status::<M, _>(c, "fmi2GetBooleanStatus", kind, value, |_, k| {
            (k == FMI2_TERMINATED).then_some(FMI2_FALSE)
        })
    }
}

/// `fmi2GetStringStatus`: `fmi2PendingStatus` does not exist for synchronous steps (`fmi2Discard`).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: Fmi2Component,
    kind: Fmi2StatusKind,
    value: *mut Fmi2String,
) -> Fmi2StatusC {
    unsafe { api::get_status::<M, _>(c, "fmi2GetStringStatus", kind, value, |_, _| None) }
}

/// `fmi2SetTime` (Model Exchange).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetTime(c: Fmi2Component, time: Fmi2Real) -> Fmi2StatusC {
    unsafe { api::set_time::<M>(c, time) }
}

/// `fmi2SetContinuousStates` (Model Exchange): there are no continuous states (`nx` must be 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetContinuousStates(
    c: Fmi2Component,
    _x: *const Fmi2Real,
    nx: usize,
) -> Fmi2StatusC {
    unsafe {
        api::no_states::<M>(
            c,
            "fmi2SetContinuousStates",
            state::SET_CONTINUOUS_STATES,
            "continuous states",
            nx,
        )
    }
}

/// `fmi2EnterEventMode` (Model Exchange).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterEventMode(c: Fmi2Component) -> Fmi2StatusC {
    unsafe { api::enter_event_mode::<M>(c) }
}

/// `fmi2NewDiscreteStates` (Model Exchange): no discrete states, no time events.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2NewDiscreteStates(
    c: Fmi2Component,
    event_info: *mut Fmi2EventInfo,
) -> Fmi2StatusC {
    unsafe { api::new_discrete_states::<M>(c, event_info) }
}

/// `fmi2EnterContinuousTimeMode` (Model Exchange).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: Fmi2Component) -> Fmi2StatusC {
    unsafe { api::enter_continuous_time_mode::<M>(c) }
}

/// `fmi2CompletedIntegratorStep` (Model Exchange): accepts the current point (the exact solver's warm
/// start advances here, see the README); never requests an event or termination.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
    c: Fmi2Component,
    _no_set_fmu_state_prior_to_current_point: Fmi2Boolean,
    enter_event_mode: *mut Fmi2Boolean,
    terminate_simulation: *mut Fmi2Boolean,
) -> Fmi2StatusC {
    unsafe { api::completed_integrator_step::<M>(c, enter_event_mode, terminate_simulation) }
}

/// `fmi2GetDerivatives` (Model Exchange): there are no continuous states (`nx` must be 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDerivatives(
    c: Fmi2Component,
    _derivatives: *mut Fmi2Real,
    nx: usize,
) -> Fmi2StatusC {
    unsafe {
        api::no_states::<M>(
            c,
            "fmi2GetDerivatives",
            state::GET_DERIVATIVES,
            "continuous states",
            nx,
        )
    }
}

/// `fmi2GetEventIndicators` (Model Exchange): there are no event indicators (`ni` must be 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetEventIndicators(
    c: Fmi2Component,
    _event_indicators: *mut Fmi2Real,
    ni: usize,
) -> Fmi2StatusC {
    unsafe {
        api::no_states::<M>(
            c,
            "fmi2GetEventIndicators",
            state::GET_EVENT_INDICATORS,
            "event indicators",
            ni,
        )
    }
}

/// `fmi2GetContinuousStates` (Model Exchange): there are no continuous states (`nx` must be 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetContinuousStates(
    c: Fmi2Component,
    _x: *mut Fmi2Real,
    nx: usize,
) -> Fmi2StatusC {
    unsafe {
        api::no_states::<M>(
            c,
            "fmi2GetContinuousStates",
            state::GET_EVENT_INDICATORS,
            "continuous states",
            nx,
        )
    }
}

/// `fmi2GetNominalsOfContinuousStates` (Model Exchange): there are no continuous states (`nx` must be 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(
    c: Fmi2Component,
    _x_nominal: *mut Fmi2Real,
    nx: usize,
) -> Fmi2StatusC {
    unsafe {
        api::no_states::<M>(
            c,
            "fmi2GetNominalsOfContinuousStates",
            state::GET_NOMINALS,
            "continuous states",
            nx,
        )
    }
}
