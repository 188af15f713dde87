//! The FMI 3.0 functions of the same shared library: every function of the standard's `fmi3Functions.h`
//! is exported, and each refuses a null instance with fmi3Error instead of crashing. (The FMI 3.0 FMU's
//! behaviour is tested through its C interface by tests/fmpy/test_fmi3.py, and through its instance by the
//! unit tests of `fmu/src/fmi3/`.)

use super::library;
use std::ffi::{CStr, c_char, c_int, c_void};
use std::ptr::null_mut;

/// The functions of `fmi3Functions.h` (FMI 3.0), in its order.
const FMI3_FUNCTIONS: [&str; 75] = [
    "fmi3GetVersion",
    "fmi3SetDebugLogging",
    "fmi3InstantiateModelExchange",
    "fmi3InstantiateCoSimulation",
    "fmi3InstantiateScheduledExecution",
    "fmi3FreeInstance",
    "fmi3EnterInitializationMode",
    "fmi3ExitInitializationMode",
    "fmi3EnterEventMode",
    "fmi3Terminate",
    "fmi3Reset",
    "fmi3GetFloat32",
    "fmi3GetFloat64",
    "fmi3GetInt8",
    "fmi3GetUInt8",
    "fmi3GetInt16",
    "fmi3GetUInt16",
    "fmi3GetInt32",
    "fmi3GetUInt32",
    "fmi3GetInt64",
    "fmi3GetUInt64",
    "fmi3GetBoolean",
    "fmi3GetString",
    "fmi3GetBinary",
    "fmi3GetClock",
    "fmi3SetFloat32",
    "fmi3SetFloat64",
    "fmi3SetInt8",
    "fmi3SetUInt8",
    "fmi3SetInt16",
    "fmi3SetUInt16",
    "fmi3SetInt32",
    "fmi3SetUInt32",
    "fmi3SetInt64",
    "fmi3SetUInt64",
    "fmi3SetBoolean",
    "fmi3SetString",
    "fmi3SetBinary",
    "fmi3SetClock",
    "fmi3GetNumberOfVariableDependencies",
    "fmi3GetVariableDependencies",
    "fmi3GetFMUState",
    "fmi3SetFMUState",
    "fmi3FreeFMUState",
    "fmi3SerializedFMUStateSize",
    "fmi3SerializeFMUState",
    "fmi3DeserializeFMUState",
    "fmi3GetDirectionalDerivative",
    "fmi3GetAdjointDerivative",
    "fmi3EnterConfigurationMode",
    "fmi3ExitConfigurationMode",
    "fmi3GetIntervalDecimal",
    "fmi3GetIntervalFraction",
    "fmi3GetShiftDecimal",
    "fmi3GetShiftFraction",
    "fmi3SetIntervalDecimal",
    "fmi3SetIntervalFraction",
    "fmi3SetShiftDecimal",
    "fmi3SetShiftFraction",
    "fmi3EvaluateDiscreteStates",
    "fmi3UpdateDiscreteStates",
    "fmi3EnterContinuousTimeMode",
    "fmi3CompletedIntegratorStep",
    "fmi3SetTime",
    "fmi3SetContinuousStates",
    "fmi3GetContinuousStateDerivatives",
    "fmi3GetEventIndicators",
    "fmi3GetContinuousStates",
    "fmi3GetNominalsOfContinuousStates",
    "fmi3GetNumberOfEventIndicators",
    "fmi3GetNumberOfContinuousStates",
    "fmi3EnterStepMode",
    "fmi3GetOutputDerivatives",
    "fmi3DoStep",
    "fmi3ActivateModelPartition",
];

#[test]
fn every_fmi3_function_is_exported_and_refuses_a_null_instance() {
    let lib = library();
    for name in FMI3_FUNCTIONS {
        assert!(
            unsafe { lib.get::<*const c_void>(name) }.is_ok(),
            "{name} is not exported"
        );
    }
    let version: libloading::Symbol<unsafe extern "C" fn() -> *const c_char> =
        unsafe { lib.get("fmi3GetVersion") }.unwrap();
    assert_eq!(unsafe { CStr::from_ptr(version()) }.to_str(), Ok("3.0"));
    // functions of one instance argument: null is an error, not a crash
    for name in [
        "fmi3ExitInitializationMode",
        "fmi3EnterEventMode",
        "fmi3Terminate",
        "fmi3Reset",
        "fmi3EnterConfigurationMode",
        "fmi3ExitConfigurationMode",
        "fmi3EvaluateDiscreteStates",
        "fmi3EnterContinuousTimeMode",
        "fmi3EnterStepMode",
    ] {
        let f: libloading::Symbol<unsafe extern "C" fn(*mut c_void) -> c_int> =
            unsafe { lib.get(name) }.unwrap();
        assert_eq!(unsafe { f(null_mut()) }, 3, "{name}");
    }
}
