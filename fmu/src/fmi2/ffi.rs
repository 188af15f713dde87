//! The C types of the FMI 2.0 interface, transcribed from the official headers `fmi2TypesPlatform.h` and
//! `fmi2FunctionTypes.h` (FMI 2.0.4). C enums are taken and returned as `c_int`; `fmi2Boolean` is a C int.

use std::ffi::{c_char, c_int, c_uint, c_void};

/// `fmi2Component`: the opaque instance pointer handed to the importer.
pub type Fmi2Component = *mut c_void;
/// `fmi2ComponentEnvironment`: the importer's pointer, passed back to the logger.
pub type Fmi2ComponentEnvironment = *mut c_void;
/// `fmi2FMUstate`: an opaque snapshot of an instance.
pub type Fmi2FmuState = *mut c_void;
/// `fmi2ValueReference`.
pub type Fmi2ValueReference = c_uint;
/// `fmi2Real`.
pub type Fmi2Real = f64;
/// `fmi2Integer`.
pub type Fmi2Integer = c_int;
/// `fmi2Boolean` (0 false, anything else true).
pub type Fmi2Boolean = c_int;
/// `fmi2String`: a NUL-terminated UTF-8 string.
pub type Fmi2String = *const c_char;
/// `fmi2Byte`.
pub type Fmi2Byte = c_char;
/// `fmi2Status` as a C int.
pub type Fmi2StatusC = c_int;

/// `fmi2True`.
pub const FMI2_TRUE: Fmi2Boolean = 1;
/// `fmi2False`.
pub const FMI2_FALSE: Fmi2Boolean = 0;
/// `fmi2Version`.
pub const FMI2_VERSION: &std::ffi::CStr = c"2.0";
/// `fmi2TypesPlatform`.
pub const FMI2_TYPES_PLATFORM: &std::ffi::CStr = c"default";
/// `fmi2ModelExchange` of `fmi2Type`.
pub const FMI2_MODEL_EXCHANGE: c_int = 0;
/// `fmi2CoSimulation` of `fmi2Type`.
pub const FMI2_COSIMULATION: c_int = 1;

/// `fmi2EventInfo`: what `fmi2NewDiscreteStates` reports (Model Exchange).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fmi2EventInfo {
    /// Another event iteration is needed.
    pub new_discrete_states_needed: Fmi2Boolean,
    /// The FMU asks to end the simulation.
    pub terminate_simulation: Fmi2Boolean,
    /// The nominal values of the continuous states changed.
    pub nominals_of_continuous_states_changed: Fmi2Boolean,
    /// The continuous states changed.
    pub values_of_continuous_states_changed: Fmi2Boolean,
    /// `next_event_time` is a time event.
    pub next_event_time_defined: Fmi2Boolean,
    /// The next time event [s], if defined.
    pub next_event_time: Fmi2Real,
}

/// `fmi2Status`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
#[repr(i32)]
pub enum Status {
    /// All well.
    Ok = 0,
    /// Something is not quite right, but the computation continued.
    Warning = 1,
    /// The step could not be completed (co-simulation).
    Discard = 2,
    /// The call failed; the instance needs a reset or a restored state to go on.
    Error = 3,
    /// The instance is unusable.
    Fatal = 4,
}

impl Status {
    /// The name FMI uses in log messages.
    pub fn name(self) -> &'static str {
        match self {
            Status::Ok => "fmi2OK",
            Status::Warning => "fmi2Warning",
            Status::Discard => "fmi2Discard",
            Status::Error => "fmi2Error",
            Status::Fatal => "fmi2Fatal",
        }
    }
}

/// `fmi2StatusKind` as a C int: which status `fmi2Get*Status` asks for.
pub type Fmi2StatusKind = c_int;
/// `fmi2DoStepStatus`.
pub const FMI2_DO_STEP_STATUS: Fmi2StatusKind = 0;
/// `fmi2PendingStatus`.
pub const FMI2_PENDING_STATUS: Fmi2StatusKind = 1;
/// `fmi2LastSuccessfulTime`.
pub const FMI2_LAST_SUCCESSFUL_TIME: Fmi2StatusKind = 2;
/// `fmi2Terminated`.
pub const FMI2_TERMINATED: Fmi2StatusKind = 3;

/// `fmi2CallbackLogger`: variadic, `printf`-style; this FMU always calls it with `"%s"` and one string.
pub type Fmi2CallbackLogger = Option<
    unsafe extern "C" fn(
        Fmi2ComponentEnvironment,
        Fmi2String,
        Fmi2StatusC,
        Fmi2String,
        Fmi2String,
        ...
    ),
>;
/// `fmi2CallbackAllocateMemory` (not used: `canNotUseMemoryManagementFunctions="true"`).
pub type Fmi2CallbackAllocateMemory = Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>;
/// `fmi2CallbackFreeMemory` (not used).
pub type Fmi2CallbackFreeMemory = Option<unsafe extern "C" fn(*mut c_void)>;
/// `fmi2StepFinished` (not used: `fmi2DoStep` is synchronous).
pub type Fmi2StepFinished = Option<unsafe extern "C" fn(Fmi2ComponentEnvironment, Fmi2StatusC)>;

/// `fmi2CallbackFunctions`.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct Fmi2CallbackFunctions {
    /// The logger (may be null: the instance then logs nothing).
    pub logger: Fmi2CallbackLogger,
    /// Memory allocation (ignored).
    pub allocate_memory: Fmi2CallbackAllocateMemory,
    /// Memory release (ignored).
    pub free_memory: Fmi2CallbackFreeMemory,
    /// Asynchronous step completion (ignored).
    pub step_finished: Fmi2StepFinished,
    /// Passed back as the first argument of the logger.
    pub component_environment: Fmi2ComponentEnvironment,
}
