//! The exported FMI 3.0 functions of WheelRailFriction (every function of `fmi3Functions.h`), beside the
//! FMI 2.0 ones in the same library (the names differ: `fmi3*`). Each body is one call into the generic
//! layer [`crate::fmi3::api`]. Scheduled Execution is not provided: its instantiation returns null and
//! `fmi3ActivateModelPartition` is an illegal call.
//!
//! # Safety
//! The importer must follow the FMI 3.0 standard (valid pointers, array lengths, one thread per instance).
//! That contract is the same for every function, so it is stated once here.
#![allow(clippy::missing_safety_doc, clippy::too_many_arguments)]

use crate::contact::WheelRailModel as M;
use crate::fmi2::variables::{Type, Value};
use crate::fmi3::api::{self, Arguments};
use crate::fmi3::ffi::*;
use crate::fmi3::state::{self, Interface};

/// `fmi3GetVersion`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetVersion() -> Fmi3String {
    FMI3_VERSION.as_ptr()
}

/// `fmi3SetDebugLogging`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    c: Fmi3Instance,
    logging_on: bool,
    n: usize,
    categories: *const Fmi3String,
) -> Fmi3StatusC {
    unsafe { api::set_debug_logging::<M>(c, logging_on, n, categories) }
}

/// `fmi3InstantiateModelExchange` (`visible` is ignored: there is no user interface).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    name: Fmi3String,
    token: Fmi3String,
    resource_path: Fmi3String,
    _visible: bool,
    logging_on: bool,
    environment: Fmi3InstanceEnvironment,
    log_message: Fmi3LogMessageCallback,
) -> Fmi3Instance {
    let a = Arguments {
        name,
        token,
        resource_path,
        logging_on,
        environment,
        log_message,
    };
    unsafe { api::instantiate::<M>(a, Interface::ModelExchange, false) }
}

/// `fmi3InstantiateCoSimulation` (no early return and no intermediate variables: the step is
/// synchronous; `visible` is ignored).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    name: Fmi3String,
    token: Fmi3String,
    resource_path: Fmi3String,
    _visible: bool,
    logging_on: bool,
    event_mode_used: bool,
    _early_return_allowed: bool,
    _required_intermediate_variables: *const Fmi3ValueReference,
    _n_required_intermediate_variables: usize,
    environment: Fmi3InstanceEnvironment,
    log_message: Fmi3LogMessageCallback,
    _intermediate_update: Fmi3IntermediateUpdateCallback,
) -> Fmi3Instance {
    let a = Arguments {
        name,
        token,
        resource_path,
        logging_on,
        environment,
        log_message,
    };
    unsafe { api::instantiate::<M>(a, Interface::CoSimulation, event_mode_used) }
}

/// `fmi3InstantiateScheduledExecution`: not provided (null, with the reason logged).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _name: Fmi3String,
    _token: Fmi3String,
    _resource_path: Fmi3String,
    _visible: bool,
    _logging_on: bool,
    environment: Fmi3InstanceEnvironment,
    log_message: Fmi3LogMessageCallback,
    _clock_update: Fmi3ClockUpdateCallback,
    _lock_preemption: Fmi3PreemptionCallback,
    _unlock_preemption: Fmi3PreemptionCallback,
) -> Fmi3Instance {
    if let Some(f) = log_message {
        unsafe {
            f(
                environment,
                crate::fmi2::ffi::Status::Error as Fmi3StatusC,
                c"logStatusError".as_ptr(),
                c"fmi3InstantiateScheduledExecution: this FMU provides Model Exchange and Co-Simulation only"
                    .as_ptr(),
            )
        }
    }
    std::ptr::null_mut()
}

/// `fmi3FreeInstance`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeInstance(c: Fmi3Instance) {
    unsafe { api::free_instance::<M>(c) }
}

/// `fmi3EnterInitializationMode` (tolerance and stop time are not used: quasi-static).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    c: Fmi3Instance,
    _tolerance_defined: bool,
    _tolerance: f64,
    start_time: f64,
    _stop_time_defined: bool,
    _stop_time: f64,
) -> Fmi3StatusC {
    unsafe {
        api::simple::<M>(c, "fmi3EnterInitializationMode", state::INSTANTIATED, |i| {
            i.enter_initialization_mode(start_time)
        })
    }
}

/// `fmi3ExitInitializationMode`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3ExitInitializationMode(c: Fmi3Instance) -> Fmi3StatusC {
    unsafe {
        api::simple::<M>(
            c,
            "fmi3ExitInitializationMode",
            state::EXIT_INITIALIZATION,
            |i| i.exit_initialization_mode(),
        )
    }
}

/// `fmi3EnterEventMode`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterEventMode(c: Fmi3Instance) -> Fmi3StatusC {
    unsafe {
        api::simple::<M>(c, "fmi3EnterEventMode", state::ENTER_EVENT_MODE, |i| {
            i.enter_event_mode()
        })
    }
}

/// `fmi3Terminate`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3Terminate(c: Fmi3Instance) -> Fmi3StatusC {
    unsafe { api::simple::<M>(c, "fmi3Terminate", state::TERMINATE, |i| i.terminate()) }
}

/// `fmi3Reset`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3Reset(c: Fmi3Instance) -> Fmi3StatusC {
    unsafe { api::simple::<M>(c, "fmi3Reset", state::ANY, |i| i.reset()) }
}

fn float64(v: &Value) -> f64 {
    match v {
        Value::Real(x) => *x,
        _ => unreachable!("values are read by type"),
    }
}

fn int32(v: &Value) -> i32 {
    match v {
        Value::Integer(x) => *x,
        _ => unreachable!("values are read by type"),
    }
}

fn boolean(v: &Value) -> bool {
    match v {
        Value::Boolean(x) => *x,
        _ => unreachable!("values are read by type"),
    }
}

/// The getters of the table's types: values of table type `$ty` converted by `$convert`.
macro_rules! typed_get {
    ($($name:ident, $c:ty, $ty:ident, $convert:ident;)*) => {$(
        #[doc = concat!("`", stringify!($name), "`.")]
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            c: Fmi3Instance,
            vrs: *const Fmi3ValueReference,
            nvr: usize,
            values: *mut $c,
            n: usize,
        ) -> Fmi3StatusC {
            unsafe {
                api::get::<M, _>(c, stringify!($name), Type::$ty, vrs, nvr, values, n, $convert)
            }
        }
    )*};
}

typed_get! {
    fmi3GetFloat64, f64, Real, float64;
    fmi3GetInt32, i32, Integer, int32;
    fmi3GetBoolean, bool, Boolean, boolean;
}

/// `fmi3GetString`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetString(
    c: Fmi3Instance,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
    values: *mut Fmi3String,
    n: usize,
) -> Fmi3StatusC {
    unsafe { api::get_string::<M>(c, vrs, nvr, values, n) }
}

/// `fmi3GetUInt64`: `contacts` and `threads`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetUInt64(
    c: Fmi3Instance,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
    values: *mut u64,
    n: usize,
) -> Fmi3StatusC {
    unsafe { api::counts::<M>(c, false, vrs, nvr, values, n) }
}

/// The setters of Float64 and Int32: each value becomes the table's `$variant`.
macro_rules! typed_set {
    ($($name:ident, $c:ty, $ty:ident, $variant:ident;)*) => {$(
        #[doc = concat!("`", stringify!($name), "`.")]
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            c: Fmi3Instance,
            vrs: *const Fmi3ValueReference,
            nvr: usize,
            values: *const $c,
            n: usize,
        ) -> Fmi3StatusC {
            unsafe {
                api::set::<M, _>(c, stringify!($name), Type::$ty, vrs, nvr, values, n, |x| {
                    Ok(Value::$variant(x))
                })
            }
        }
    )*};
}

typed_set! {
    fmi3SetFloat64, f64, Real, Real;
    fmi3SetInt32, i32, Integer, Integer;
}

/// `fmi3SetBoolean`: a C `bool` is read as a byte, so that any byte an importer passes is defined (0
/// false, anything else true).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetBoolean(
    c: Fmi3Instance,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
    values: *const bool,
    n: usize,
) -> Fmi3StatusC {
    unsafe {
        api::set::<M, u8>(
            c,
            "fmi3SetBoolean",
            Type::Boolean,
            vrs,
            nvr,
            values as *const u8,
            n,
            |x| Ok(Value::Boolean(x != 0)),
        )
    }
}

/// `fmi3SetString`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetString(
    c: Fmi3Instance,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
    values: *const Fmi3String,
    n: usize,
) -> Fmi3StatusC {
    unsafe {
        api::set::<M, Fmi3String>(c, "fmi3SetString", Type::String, vrs, nvr, values, n, |s| {
            crate::fmi2::api::string_value(s)
        })
    }
}

/// `fmi3SetUInt64`: `contacts` (in configuration mode) and `threads`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetUInt64(
    c: Fmi3Instance,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
    values: *const u64,
    n: usize,
) -> Fmi3StatusC {
    unsafe { api::counts::<M>(c, true, vrs, nvr, values as *mut u64, n) }
}

/// Get and set functions of the types this FMU has no variables of: only no value references are
/// accepted.
macro_rules! no_variables {
    ($($name:ident, $ty:ty, $type_name:literal, $mask:ident;)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: there are no ", $type_name, " variables.")]
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            c: Fmi3Instance,
            vrs: *const Fmi3ValueReference,
            nvr: usize,
            _values: $ty,
            _n: usize,
        ) -> Fmi3StatusC {
            unsafe { api::no_variables::<M>(c, stringify!($name), $type_name, state::$mask, vrs, nvr) }
        }
    )*};
}

no_variables! {
    fmi3GetFloat32, *mut f32, "Float32", GET;
    fmi3GetInt8, *mut i8, "Int8", GET;
    fmi3GetUInt8, *mut u8, "UInt8", GET;
    fmi3GetInt16, *mut i16, "Int16", GET;
    fmi3GetUInt16, *mut u16, "UInt16", GET;
    fmi3GetUInt32, *mut u32, "UInt32", GET;
    fmi3GetInt64, *mut i64, "Int64", GET;
    fmi3SetFloat32, *const f32, "Float32", SET;
    fmi3SetInt8, *const i8, "Int8", SET;
    fmi3SetUInt8, *const u8, "UInt8", SET;
    fmi3SetInt16, *const i16, "Int16", SET;
    fmi3SetUInt16, *const u16, "UInt16", SET;
    fmi3SetUInt32, *const u32, "UInt32", SET;
    fmi3SetInt64, *const i64, "Int64", SET;
}

/// `fmi3GetBinary`: there are no Binary variables.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetBinary(
    c: Fmi3Instance,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
    _sizes: *mut usize,
    _values: *mut Fmi3Binary,
    _n: usize,
) -> Fmi3StatusC {
    unsafe { api::no_variables::<M>(c, "fmi3GetBinary", "Binary", state::GET, vrs, nvr) }
}

/// `fmi3SetBinary`: there are no Binary variables.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetBinary(
    c: Fmi3Instance,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
    _sizes: *const usize,
    _values: *const Fmi3Binary,
    _n: usize,
) -> Fmi3StatusC {
    unsafe { api::no_variables::<M>(c, "fmi3SetBinary", "Binary", state::SET, vrs, nvr) }
}

/// Clock functions: there are no Clocks.
macro_rules! no_clocks {
    ($($name:ident($($arg:ident: $ty:ty),*);)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: there are no Clocks.")]
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            c: Fmi3Instance,
            vrs: *const Fmi3ValueReference,
            nvr: usize,
            $($arg: $ty),*
        ) -> Fmi3StatusC {
            $(let _ = $arg;)*
            unsafe { api::no_variables::<M>(c, stringify!($name), "Clock", state::ANY, vrs, nvr) }
        }
    )*};
}

no_clocks! {
    fmi3GetClock(_values: *mut Fmi3Clock);
    fmi3SetClock(_values: *const Fmi3Clock);
    fmi3GetIntervalDecimal(_intervals: *mut f64, _qualifiers: *mut Fmi3IntervalQualifier);
    fmi3GetIntervalFraction(_counters: *mut u64, _resolutions: *mut u64, _qualifiers: *mut Fmi3IntervalQualifier);
    fmi3GetShiftDecimal(_shifts: *mut f64);
    fmi3GetShiftFraction(_counters: *mut u64, _resolutions: *mut u64);
    fmi3SetIntervalDecimal(_intervals: *const f64);
    fmi3SetIntervalFraction(_counters: *const u64, _resolutions: *const u64);
    fmi3SetShiftDecimal(_shifts: *const f64);
    fmi3SetShiftFraction(_counters: *const u64, _resolutions: *const u64);
}

/// Why the variable-dependency functions are not provided.
const NO_PER_ELEMENT_DEPENDENCIES: &str = "providesPerElementDependencies is false: every output \
    element depends on the input elements of its contact, as ModelStructure says per variable";

/// `fmi3GetNumberOfVariableDependencies`: not provided (providesPerElementDependencies="false").
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(
    c: Fmi3Instance,
    _vr: Fmi3ValueReference,
    _n: *mut usize,
) -> Fmi3StatusC {
    unsafe {
        api::not_provided::<M>(
            c,
            "fmi3GetNumberOfVariableDependencies",
            NO_PER_ELEMENT_DEPENDENCIES,
        )
    }
}

/// `fmi3GetVariableDependencies`: not provided (providesPerElementDependencies="false").
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetVariableDependencies(
    c: Fmi3Instance,
    _dependent: Fmi3ValueReference,
    _element_indices_of_dependent: *mut usize,
    _independents: *mut Fmi3ValueReference,
    _element_indices_of_independents: *mut usize,
    _kinds: *mut Fmi3DependencyKind,
    _n: usize,
) -> Fmi3StatusC {
    unsafe {
        api::not_provided::<M>(
            c,
            "fmi3GetVariableDependencies",
            NO_PER_ELEMENT_DEPENDENCIES,
        )
    }
}

/// `fmi3GetFMUState`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetFMUState(c: Fmi3Instance, s: *mut Fmi3FmuState) -> Fmi3StatusC {
    unsafe { api::get_fmu_state::<M>(c, s) }
}

/// `fmi3SetFMUState`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetFMUState(c: Fmi3Instance, s: Fmi3FmuState) -> Fmi3StatusC {
    unsafe { api::set_fmu_state::<M>(c, s) }
}

/// `fmi3FreeFMUState`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeFMUState(c: Fmi3Instance, s: *mut Fmi3FmuState) -> Fmi3StatusC {
    unsafe { api::free_fmu_state::<M>(c, s) }
}

/// `fmi3SerializedFMUStateSize`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    c: Fmi3Instance,
    s: Fmi3FmuState,
    size: *mut usize,
) -> Fmi3StatusC {
    if size.is_null() {
        return crate::fmi2::ffi::Status::Error as Fmi3StatusC;
    }
    unsafe { api::serialize::<M>(c, s, size, std::ptr::null_mut(), 0) }
}

/// `fmi3SerializeFMUState`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    c: Fmi3Instance,
    s: Fmi3FmuState,
    bytes: *mut Fmi3Byte,
    size: usize,
) -> Fmi3StatusC {
    unsafe { api::serialize::<M>(c, s, std::ptr::null_mut(), bytes, size) }
}

/// `fmi3DeserializeFMUState`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    c: Fmi3Instance,
    bytes: *const Fmi3Byte,
    size: usize,
    s: *mut Fmi3FmuState,
) -> Fmi3StatusC {
    unsafe { api::deserialize::<M>(c, bytes, size, s) }
}

/// `fmi3GetDirectionalDerivative` (J·seed) and `fmi3GetAdjointDerivative` (Jᵀ·seed): one signature.
macro_rules! derivative {
    ($($name:ident, $adjoint:literal;)*) => {$(
        #[doc = concat!("`", stringify!($name), "`.")]
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            c: Fmi3Instance,
            unknowns: *const Fmi3ValueReference,
            n_unknowns: usize,
            knowns: *const Fmi3ValueReference,
            n_knowns: usize,
            seed: *const f64,
            n_seed: usize,
            sensitivity: *mut f64,
            n_sensitivity: usize,
        ) -> Fmi3StatusC {
            unsafe {
                api::derivative::<M>(
                    c, $adjoint, unknowns, n_unknowns, knowns, n_knowns, seed, n_seed, sensitivity,
                    n_sensitivity,
                )
            }
        }
    )*};
}

derivative! {
    fmi3GetDirectionalDerivative, false;
    fmi3GetAdjointDerivative, true;
}

/// `fmi3EnterConfigurationMode` (from Instantiated: the structural parameter is fixed).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterConfigurationMode(c: Fmi3Instance) -> Fmi3StatusC {
    unsafe {
        api::simple::<M>(c, "fmi3EnterConfigurationMode", state::INSTANTIATED, |i| {
            i.configuration_mode(true)
        })
    }
}

/// `fmi3ExitConfigurationMode`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3ExitConfigurationMode(c: Fmi3Instance) -> Fmi3StatusC {
    unsafe {
        api::simple::<M>(
            c,
            "fmi3ExitConfigurationMode",
            state::EXIT_CONFIGURATION,
            |i| i.configuration_mode(false),
        )
    }
}

/// `fmi3EvaluateDiscreteStates`: there are no discrete states; the outputs are brought to the inputs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EvaluateDiscreteStates(c: Fmi3Instance) -> Fmi3StatusC {
    unsafe {
        api::simple::<M>(c, "fmi3EvaluateDiscreteStates", state::EVENT, |i| {
            i.update()
        })
    }
}

/// `fmi3UpdateDiscreteStates`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
    c: Fmi3Instance,
    discrete_states_need_update: *mut bool,
    terminate_simulation: *mut bool,
    nominals_changed: *mut bool,
    values_changed: *mut bool,
    next_event_time_defined: *mut bool,
    next_event_time: *mut f64,
) -> Fmi3StatusC {
    let flags = [
        discrete_states_need_update,
        terminate_simulation,
        nominals_changed,
        values_changed,
        next_event_time_defined,
    ];
    unsafe { api::update_discrete_states::<M>(c, flags, next_event_time) }
}

/// `fmi3EnterContinuousTimeMode`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterContinuousTimeMode(c: Fmi3Instance) -> Fmi3StatusC {
    unsafe {
        api::simple::<M>(
            c,
            "fmi3EnterContinuousTimeMode",
            state::ENTER_CONTINUOUS_TIME_MODE,
            |i| i.enter_continuous_time_mode(),
        )
    }
}

/// `fmi3CompletedIntegratorStep`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3CompletedIntegratorStep(
    c: Fmi3Instance,
    _no_set_fmu_state_prior: bool,
    enter_event_mode: *mut bool,
    terminate_simulation: *mut bool,
) -> Fmi3StatusC {
    unsafe { api::completed_integrator_step::<M>(c, enter_event_mode, terminate_simulation) }
}

/// `fmi3SetTime`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetTime(c: Fmi3Instance, time: f64) -> Fmi3StatusC {
    unsafe { api::simple::<M>(c, "fmi3SetTime", state::SET_TIME, |i| i.set_time(time)) }
}

/// The functions of continuous states and event indicators: there are none (only n = 0).
macro_rules! no_states {
    ($($name:ident, $ty:ty, $mask:ident;)*) => {$(
        #[doc = concat!("`", stringify!($name), "`: no continuous states, no event indicators.")]
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(c: Fmi3Instance, _values: $ty, n: usize) -> Fmi3StatusC {
            unsafe { api::no_states::<M>(c, stringify!($name), state::$mask, n) }
        }
    )*};
}

no_states! {
    fmi3SetContinuousStates, *const f64, CONTINUOUS_TIME;
    fmi3GetContinuousStateDerivatives, *mut f64, GET_CONTINUOUS;
    fmi3GetEventIndicators, *mut f64, GET_CONTINUOUS;
    fmi3GetContinuousStates, *mut f64, GET_CONTINUOUS;
    fmi3GetNominalsOfContinuousStates, *mut f64, GET_CONTINUOUS;
}

/// `fmi3GetNumberOfEventIndicators`: 0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(
    c: Fmi3Instance,
    n: *mut usize,
) -> Fmi3StatusC {
    unsafe { api::number_of::<M>(c, "fmi3GetNumberOfEventIndicators", n) }
}

/// `fmi3GetNumberOfContinuousStates`: 0.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(
    c: Fmi3Instance,
    n: *mut usize,
) -> Fmi3StatusC {
    unsafe { api::number_of::<M>(c, "fmi3GetNumberOfContinuousStates", n) }
}

/// `fmi3EnterStepMode`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterStepMode(c: Fmi3Instance) -> Fmi3StatusC {
    unsafe {
        api::simple::<M>(c, "fmi3EnterStepMode", state::ENTER_STEP_MODE, |i| {
            i.enter_step_mode()
        })
    }
}

/// `fmi3GetOutputDerivatives`: not provided (maxOutputDerivativeOrder="0").
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetOutputDerivatives(
    c: Fmi3Instance,
    _vrs: *const Fmi3ValueReference,
    _nvr: usize,
    _orders: *const i32,
    _values: *mut f64,
    _n: usize,
) -> Fmi3StatusC {
    unsafe {
        api::not_provided::<M>(
            c,
            "fmi3GetOutputDerivatives",
            "maxOutputDerivativeOrder is 0 (the outputs are a function of the current inputs)",
        )
    }
}

/// `fmi3DoStep`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3DoStep(
    c: Fmi3Instance,
    current: f64,
    step: f64,
    _no_set_fmu_state_prior: bool,
    event_handling_needed: *mut bool,
    terminate_simulation: *mut bool,
    early_return: *mut bool,
    last_successful_time: *mut f64,
) -> Fmi3StatusC {
    unsafe {
        api::do_step::<M>(
            c,
            current,
            step,
            event_handling_needed,
            terminate_simulation,
            early_return,
            last_successful_time,
        )
    }
}

/// `fmi3ActivateModelPartition`: Scheduled Execution is not provided, so no instance has partitions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3ActivateModelPartition(
    c: Fmi3Instance,
    _clock: Fmi3ValueReference,
    _time: f64,
) -> Fmi3StatusC {
    unsafe {
        api::simple::<M>(c, "fmi3ActivateModelPartition", state::NONE, |_| {
            unreachable!("no state allows it")
        })
    }
}
