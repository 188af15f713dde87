//! The C types of the FMI 3.0 interface, transcribed from the standard's headers `fmi3PlatformTypes.h` and
//! `fmi3FunctionTypes.h` (FMI 3.0). C enums are taken and returned as `c_int`; `fmi3Boolean` is C `bool`
//! (Rust `bool` has its layout).

use std::ffi::{c_char, c_int, c_void};

/// `fmi3Instance`: the opaque instance pointer handed to the importer.
pub type Fmi3Instance = *mut c_void;
/// `fmi3InstanceEnvironment`: the importer's pointer, passed back to the logger.
pub type Fmi3InstanceEnvironment = *mut c_void;
/// `fmi3FMUState`: an opaque snapshot of an instance.
pub type Fmi3FmuState = *mut c_void;
/// `fmi3ValueReference`.
pub type Fmi3ValueReference = u32;
/// `fmi3String`: a NUL-terminated UTF-8 string.
pub type Fmi3String = *const c_char;
/// `fmi3Byte`.
pub type Fmi3Byte = u8;
/// `fmi3Binary`.
pub type Fmi3Binary = *const Fmi3Byte;
/// `fmi3Clock` (a C `bool`).
pub type Fmi3Clock = bool;
/// `fmi3Status` as a C int (the values of [`crate::fmi2::ffi::Status`]: fmi3OK 0 … fmi3Fatal 4).
pub type Fmi3StatusC = c_int;
/// `fmi3DependencyKind` as a C int.
pub type Fmi3DependencyKind = c_int;
/// `fmi3IntervalQualifier` as a C int.
pub type Fmi3IntervalQualifier = c_int;

/// `fmi3Version`.
pub const FMI3_VERSION: &std::ffi::CStr = c"3.0";

/// `fmi3LogMessageCallback`.
pub type Fmi3LogMessageCallback =
    Option<unsafe extern "C" fn(Fmi3InstanceEnvironment, Fmi3StatusC, Fmi3String, Fmi3String)>;
/// `fmi3IntermediateUpdateCallback` (not used: no intermediate update).
pub type Fmi3IntermediateUpdateCallback = Option<
    unsafe extern "C" fn(Fmi3InstanceEnvironment, f64, bool, bool, bool, bool, *mut bool, *mut f64),
>;
/// `fmi3ClockUpdateCallback` (Scheduled Execution, which this FMU does not provide).
pub type Fmi3ClockUpdateCallback = Option<unsafe extern "C" fn(Fmi3InstanceEnvironment)>;
/// `fmi3LockPreemptionCallback` and `fmi3UnlockPreemptionCallback` (Scheduled Execution).
pub type Fmi3PreemptionCallback = Option<unsafe extern "C" fn()>;
