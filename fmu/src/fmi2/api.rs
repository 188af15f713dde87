//! The generic implementation of every FMI 2.0 function (common, Co-Simulation and Model Exchange) for a
//! [`Model`]. The exported C
//! functions are one call each into these. Each function checks its pointers, checks that the call is
//! allowed in the instance's state (else "Illegal call sequence" and `fmi2Error`), runs inside
//! `catch_unwind` so that no panic crosses the C boundary, logs failures and returns the status.
//!
//! # Safety
//! Every function here trusts the importer as the FMI standard requires: a non-null component is a pointer
//! returned by [`instantiate`] of the same model and not yet freed; arrays have the stated lengths; an
//! instance is not used by two threads at once. Different instances are independent (the only shared mutable
//! state is the mutex-guarded registry of live FMU states, [`super::handles`]), so they may run on different
//! threads. FMU-state pointers are not trusted: only live handles of this FMU are used.

use super::description;
use super::ffi::*;
use super::handles;
use super::instance::{Failure, Instance, Outcome};
use super::logging::{Logger, c_sink};
use super::model::Model;
use super::resources::path_from_uri;
use super::snapshot::Snapshot;
use super::state::{self, Interface, Mask, StateBit};
use super::variables::{Type, Value};
use super::x87;
use std::ffi::{CStr, c_char, c_int};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::ptr::null_mut;

/// The message of a caught panic.
fn panic_message(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// Runs `f` on the instance behind `c` if the function belongs to the instance's interface type and
/// `allowed` contains its state; see the module documentation.
///
/// # Safety
/// `c` is null or a live instance of model `M`.
pub unsafe fn call<M: Model>(
    c: Fmi2Component,
    function: &str,
    allowed: Mask,
    f: impl FnOnce(&mut Instance<M>) -> Outcome,
) -> Fmi2StatusC {
    // SAFETY: see the function's contract.
    let Some(inst) = (unsafe { (c as *mut Instance<M>).as_mut() }) else {
        return Status::Error as c_int;
    };
    guarded(inst, function, allowed, f)
}

/// What [`guarded`] needs of an instance (of this layer or of FMI 3.0's).
pub trait Guarded {
    /// The state-machine state.
    type State: StateBit + std::fmt::Debug;
    /// The interface type the instance was instantiated as.
    fn interface(&self) -> Interface;
    /// The current state.
    fn state(&self) -> Self::State;
    /// The instance's logger.
    fn logger(&self) -> &Logger;
    /// Enters the Error state (a computation failed).
    fn enter_error(&mut self);
}

impl<M: Model> Guarded for Instance<M> {
    type State = state::State;
    fn interface(&self) -> Interface {
        self.interface
    }
    fn state(&self) -> state::State {
        self.state
    }
    fn logger(&self) -> &Logger {
        &self.log
    }
    fn enter_error(&mut self) {
        self.state = state::State::Error;
    }
}

/// Runs `f` on `inst` if the function belongs to the instance's interface type and `allowed` contains its
/// state (else "Illegal call sequence"), inside `catch_unwind` and with the standard x87 control word
/// ([`x87`]); logs a failure, and enters the Error state on a failed computation or a panic. The status
/// as a C int.
pub fn guarded<I: Guarded>(
    inst: &mut I,
    function: &str,
    allowed: Mask,
    f: impl FnOnce(&mut I) -> Outcome,
) -> c_int {
    if !allowed.serves(inst.interface()) {
        inst.logger().error(&format!(
            "{function}: Illegal call sequence (not a function of {}, the interface type this instance was \
             instantiated as)",
            inst.interface().name()
        ));
        return Status::Error as c_int;
    }
    if !allowed.allows(inst.state()) {
        inst.logger().error(&format!(
            "{function}: Illegal call sequence (the instance is in state {:?})",
            inst.state()
        ));
        return Status::Error as c_int;
    }
    let status = match catch_unwind(AssertUnwindSafe(|| x87::standard(|| f(inst)))) {
        Ok(Ok(status)) => status,
        Ok(Err(Failure::Rejected(msg))) => {
            inst.logger().error(&format!("{function}: {msg}"));
            Status::Error
        }
        Ok(Err(Failure::Failed(msg))) => {
            inst.logger().error(&format!("{function}: {msg}"));
            inst.enter_error();
            Status::Error
        }
        Err(p) => {
            inst.logger().error(&format!(
                "{function}: internal error (panic: {})",
                panic_message(&*p)
            ));
            inst.enter_error();
            Status::Error
        }
    };
    status as c_int
}

/// A slice from a C array; null is allowed only for length 0.
///
/// # Safety
/// A non-null `ptr` points to `n` valid elements that outlive the returned slice.
pub unsafe fn slice<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], Failure> {
    if n == 0 {
        Ok(&[])
    } else if ptr.is_null() {
        Err(Failure::Rejected(format!(
            "argument {what} is a null pointer"
        )))
    } else {
        // SAFETY: see the function's contract.
        Ok(unsafe { std::slice::from_raw_parts(ptr, n) })
    }
}

/// A mutable slice from a C array; null is allowed only for length 0.
///
/// # Safety
/// As [`slice`], and nothing else accesses the array meanwhile.
pub unsafe fn slice_mut<'a, T>(ptr: *mut T, n: usize, what: &str) -> Result<&'a mut [T], Failure> {
    if n == 0 {
        Ok(&mut [])
    } else if ptr.is_null() {
        Err(Failure::Rejected(format!(
            "argument {what} is a null pointer"
        )))
    } else {
        // SAFETY: see the function's contract.
        Ok(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
    }
}

/// A Rust string from a C string.
///
/// # Safety
/// A non-null `s` is NUL-terminated.
pub unsafe fn text<'a>(s: *const c_char, what: &str) -> Result<&'a str, Failure> {
    if s.is_null() {
        return Err(Failure::Rejected(format!(
            "argument {what} is a null pointer"
        )));
    }
    // SAFETY: see the function's contract.
    unsafe { CStr::from_ptr(s) }
        .to_str()
        .map_err(|_| Failure::Rejected(format!("argument {what} is not valid UTF-8")))
}

/// A non-null pointer for writing one result (the importer passes a valid pointer or null, as FMI
/// requires of every output argument).
#[allow(clippy::not_unsafe_ptr_arg_deref)]
pub fn out<'a, T>(ptr: *mut T, what: &str) -> Result<&'a mut T, Failure> {
    // SAFETY: the importer passes a valid pointer or null; null is rejected.
    unsafe { ptr.as_mut() }
        .ok_or_else(|| Failure::Rejected(format!("argument {what} is a null pointer")))
}

/// `fmi2Instantiate`: a new Co-Simulation or Model Exchange instance, or null (with a logged reason) if
/// the type is neither, the GUID differs, the name is missing, or `functions` is null.
///
/// # Safety
/// Pointers are null or valid as FMI 2.0 requires.
pub unsafe fn instantiate<M: Model>(
    instance_name: Fmi2String,
    fmu_type: c_int,
    fmu_guid: Fmi2String,
    resource_location: Fmi2String,
    functions: *const Fmi2CallbackFunctions,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    // SAFETY: the importer passes null or a valid struct, which is copied.
    let Some(cb) = (unsafe { functions.as_ref() }).copied() else {
        return null_mut();
    };
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the strings are NUL-terminated or null.
        let name = unsafe { text(instance_name, "instanceName") };
        let log = Logger::new(
            c_sink(
                cb.logger,
                cb.component_environment,
                name.as_ref().map_or("", |n| n),
            ),
            logging_on != FMI2_FALSE,
        );
        let fail = |msg: &str| {
            log.error(&format!("fmi2Instantiate: {msg}"));
            null_mut()
        };
        let name = match name {
            Ok(n) if !n.is_empty() => n.to_string(),
            _ => return fail("instanceName is missing"),
        };
        let Some(interface) = Interface::of_fmu_type(fmu_type) else {
            return fail(&format!(
                "fmuType {fmu_type} is neither fmi2ModelExchange ({FMI2_MODEL_EXCHANGE}) nor \
                 fmi2CoSimulation ({FMI2_COSIMULATION})"
            ));
        };
        let guid = description::guid(M::info());
        // SAFETY: as above.
        match unsafe { text(fmu_guid, "fmuGUID") } {
            Ok(g) if g == guid => {}
            _ => return fail(&format!("fmuGUID does not match this binary's GUID {guid}")),
        }
        let resources = if resource_location.is_null() {
            None
        } else {
            // SAFETY: as above.
            match unsafe { text(resource_location, "fmuResourceLocation") }
                .map_err(|_| "not UTF-8".to_string())
            {
                Ok("") => None,
                Ok(uri) => match path_from_uri(uri) {
                    Ok(p) => Some(p),
                    Err(e) => {
                        log.warning(&format!("fmi2Instantiate: {e}; resources are unavailable"));
                        None
                    }
                },
                Err(e) => {
                    log.warning(&format!(
                        "fmi2Instantiate: fmuResourceLocation is {e}; resources are unavailable"
                    ));
                    None
                }
            }
        };
        log.event(&format!(
            "fmi2Instantiate: {} instance {name} created (resources: {resources:?})",
            interface.name()
        ));
        let inst = Instance::new(name, interface, log, M::new(resources));
        Box::into_raw(Box::new(inst)) as Fmi2Component
    }))
    .unwrap_or(null_mut())
}

/// `fmi2FreeInstance`.
///
/// # Safety
/// `c` is null or a live instance of `M`, which must not be used afterwards.
pub unsafe fn free_instance<M: Model>(c: Fmi2Component) {
    if !c.is_null() {
        // SAFETY: see the function's contract; dropping cannot unwind into C because it is caught.
        let _ = catch_unwind(AssertUnwindSafe(|| {
            drop(unsafe { Box::from_raw(c as *mut Instance<M>) })
        }));
    }
}

/// `fmi2SetDebugLogging`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_debug_logging<M: Model>(
    c: Fmi2Component,
    logging_on: Fmi2Boolean,
    n: usize,
    categories: *const Fmi2String,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2SetDebugLogging", state::RESET, |inst| {
            let names = slice(categories, n, "categories[]")?
                .iter()
                .map(|s| text(*s, "categories[]"))
                .collect::<Result<Vec<_>, _>>()?;
            inst.log
                .set_debug_logging(logging_on != FMI2_FALSE, &names)
                .map_err(Failure::Rejected)?;
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SetupExperiment` (tolerance and stop time are not used: the model's own solver tolerance applies).
///
/// # Safety
/// See the module documentation.
pub unsafe fn setup_experiment<M: Model>(c: Fmi2Component, start_time: f64) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2SetupExperiment", state::SETUP, |i| {
            i.setup_experiment(start_time)
        })
    }
}

/// `fmi2EnterInitializationMode`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn enter_initialization_mode<M: Model>(c: Fmi2Component) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2EnterInitializationMode", state::SETUP, |i| {
            i.enter_initialization_mode()
        })
    }
}

/// `fmi2ExitInitializationMode`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn exit_initialization_mode<M: Model>(c: Fmi2Component) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(
            c,
            "fmi2ExitInitializationMode",
            state::EXIT_INITIALIZATION,
            |i| i.exit_initialization_mode(),
        )
    }
}

/// `fmi2Terminate`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn terminate<M: Model>(c: Fmi2Component) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe { call::<M>(c, "fmi2Terminate", state::TERMINATE, |i| i.terminate()) }
}

/// `fmi2Reset`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn reset<M: Model>(c: Fmi2Component) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe { call::<M>(c, "fmi2Reset", state::RESET, |i| i.reset()) }
}

/// `fmi2Get{Real,Integer,Boolean}`: reads values of type `ty` and converts them with `convert`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get<M: Model, T>(
    c: Fmi2Component,
    function: &str,
    ty: Type,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *mut T,
    convert: impl Fn(&Value) -> T,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, state::GET, |inst| {
            let vrs = slice(vr, n, "vr[]")?;
            let dst = slice_mut(value, n, "value[]")?;
            inst.get(vrs, ty, |k, v| dst[k] = convert(v))
        })
    }
}

/// `fmi2GetString`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_string<M: Model>(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *mut Fmi2String,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2GetString", state::GET, |inst| {
            let vrs = slice(vr, n, "vr[]")?;
            let dst = slice_mut(value, n, "value[]")?;
            let (ptrs, status) = inst.get_strings(vrs)?;
            dst.copy_from_slice(&ptrs);
            Ok(status)
        })
    }
}

/// `fmi2Set{Real,Integer,Boolean,String}`: converts the C values with `convert` and writes them.
///
/// # Safety
/// See the module documentation.
pub unsafe fn set<M: Model, T: Copy>(
    c: Fmi2Component,
    function: &str,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const T,
    convert: impl Fn(T) -> Result<Value, Failure>,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, state::SET, |inst| {
            let vrs = slice(vr, n, "vr[]")?;
            let values = slice(value, n, "value[]")?;
            inst.set(vrs, |k| convert(values[k]))
        })
    }
}

/// Converts a C string argument of `fmi2SetString`.
///
/// # Safety
/// `s` is null (rejected) or NUL-terminated.
pub unsafe fn string_value(s: Fmi2String) -> Result<Value, Failure> {
    // SAFETY: see the function's contract.
    unsafe { text(s, "value[]") }.map(|t| Value::String(t.to_string()))
}

/// `fmi2GetFMUstate`: a new snapshot, or an overwritten one if `*state` is a previous snapshot.
///
/// # Safety
/// See the module documentation; a non-null `*state` was returned by this FMU and not freed.
pub unsafe fn get_fmu_state<M: Model>(
    c: Fmi2Component,
    state_out: *mut Fmi2FmuState,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2GetFMUstate", state::RESET, |inst| {
            let slot = out(state_out, "FMUstate")?;
            store_snapshot(slot, inst.snapshot());
            Ok(Status::Ok)
        })
    }
}

/// Puts `s` into `*slot`: into the snapshot there if `*slot` is a live handle (`fmi2GetFMUstate` with a
/// previous state), else into a new, registered snapshot (a null or foreign `*slot` is never written
/// through).
pub fn store_snapshot<T>(slot: &mut Fmi2FmuState, s: T) {
    let existing = *slot as *mut T;
    if handles::is_live(existing) {
        // SAFETY: a live handle is a snapshot of type `T` allocated by this function and not yet freed.
        unsafe { *existing = s };
    } else {
        let new = Box::into_raw(Box::new(s));
        handles::register(new);
        *slot = new as Fmi2FmuState;
    }
}

/// A snapshot from an FMU-state pointer: null, freed and foreign pointers are rejected.
///
/// # Safety
/// No snapshot is freed while the returned reference lives (one thread per instance).
unsafe fn snapshot_ref<'a, S>(s: Fmi2FmuState) -> Result<&'a Snapshot<S>, Failure> {
    let ptr = s as *const Snapshot<S>;
    if ptr.is_null() {
        return Err(Failure::Rejected(
            "argument FMUstate is a null pointer".into(),
        ));
    }
    if !handles::is_live(ptr) {
        return Err(Failure::Rejected(
            "argument FMUstate is not a live FMU state of this FMU (already freed, or not returned by \
             fmi2GetFMUstate or fmi2DeSerializeFMUstate)"
                .into(),
        ));
    }
    // SAFETY: a live handle points to a snapshot of type `S` (see the function's contract).
    Ok(unsafe { &*ptr })
}

/// `fmi2SetFMUstate`.
///
/// # Safety
/// See [`get_fmu_state`].
pub unsafe fn set_fmu_state<M: Model>(c: Fmi2Component, s: Fmi2FmuState) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2SetFMUstate", state::RESET, |inst| {
            inst.restore(snapshot_ref::<M::State>(s)?)
        })
    }
}

/// `fmi2FreeFMUstate`: frees `*state` (nothing if null) and sets it to null. A `*state` that is not a live
/// FMU state (freed before, or foreign) is rejected and nothing is freed. A master that passes the state
/// itself instead of its address (the Reference-FMUs' `fmusim` does, see [`super::handles`]) gets it freed
/// and a warning log line saying so, with `fmi2OK`: nothing is left for the master to act on, and `fmusim`
/// aborts its run (and a restart from a state file) on any status but `fmi2OK`.
///
/// # Safety
/// See the module documentation; a non-null `state_ptr` that is not a live FMU state points to an
/// `fmi2FMUstate`.
pub unsafe fn free_fmu_state<M: Model>(
    c: Fmi2Component,
    state_ptr: *mut Fmi2FmuState,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2FreeFMUstate", state::RESET, |inst| {
            let itself = state_ptr as *mut Snapshot<M::State>;
            if handles::release(itself) {
                drop(Box::from_raw(itself));
                inst.log.warning(
                    "fmi2FreeFMUstate: the argument is an FMU state itself, not the address of an \
                     fmi2FMUstate variable; the state is freed, but the master's variable still holds it",
                );
                return Ok(Status::Ok);
            }
            let slot = out(state_ptr, "FMUstate")?;
            let snapshot = *slot as *mut Snapshot<M::State>;
            if snapshot.is_null() {
                return Ok(Status::Ok);
            }
            if !handles::release(snapshot) {
                return Err(Failure::Rejected(
                    "*FMUstate is not a live FMU state of this FMU (already freed, or not returned by \
                     fmi2GetFMUstate or fmi2DeSerializeFMUstate); nothing is freed"
                        .into(),
                ));
            }
            drop(Box::from_raw(snapshot));
            *slot = null_mut();
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SerializedFMUstateSize`.
///
/// # Safety
/// See [`get_fmu_state`].
pub unsafe fn serialized_fmu_state_size<M: Model>(
    c: Fmi2Component,
    s: Fmi2FmuState,
    size: *mut usize,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2SerializedFMUstateSize", state::RESET, |_| {
            let bytes = snapshot_ref::<M::State>(s)?.to_bytes(&description::guid(M::info()));
            *out(size, "size")? = bytes.len();
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SerializeFMUstate`: `size` must equal the size reported by `fmi2SerializedFMUstateSize`.
///
/// # Safety
/// See [`get_fmu_state`]; `buffer` holds `size` bytes.
pub unsafe fn serialize_fmu_state<M: Model>(
    c: Fmi2Component,
    s: Fmi2FmuState,
    buffer: *mut Fmi2Byte,
    size: usize,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2SerializeFMUstate", state::RESET, |_| {
            let bytes = snapshot_ref::<M::State>(s)?.to_bytes(&description::guid(M::info()));
            if bytes.len() != size {
                return Err(Failure::Rejected(format!(
                    "buffer size {size} differs from the serialized size {}",
                    bytes.len()
                )));
            }
            let dst = slice_mut(buffer as *mut u8, size, "serializedState[]")?;
            dst.copy_from_slice(&bytes);
            Ok(Status::Ok)
        })
    }
}

/// `fmi2DeSerializeFMUstate`: corrupt or foreign bytes are rejected with the reason.
///
/// # Safety
/// See [`get_fmu_state`]; `buffer` holds `size` bytes.
pub unsafe fn deserialize_fmu_state<M: Model>(
    c: Fmi2Component,
    buffer: *const Fmi2Byte,
    size: usize,
    state_ptr: *mut Fmi2FmuState,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2DeSerializeFMUstate", state::RESET, |_| {
            let bytes = slice(buffer as *const u8, size, "serializedState[]")?;
            let slot = out(state_ptr, "FMUstate")?;
            let info = M::info();
            let s =
                Snapshot::<M::State>::from_bytes(bytes, &description::guid(info), info.variables)
                    .map_err(Failure::Rejected)?;
            store_snapshot(slot, s);
            Ok(Status::Ok)
        })
    }
}

/// `fmi2GetDirectionalDerivative`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_directional_derivative<M: Model>(
    c: Fmi2Component,
    unknown: *const Fmi2ValueReference,
    n_unknown: usize,
    known: *const Fmi2ValueReference,
    n_known: usize,
    dv_known: *const f64,
    dv_unknown: *mut f64,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2GetDirectionalDerivative", state::GET, |inst| {
            let unknowns = slice(unknown, n_unknown, "vUnknown_ref[]")?;
            let knowns = slice(known, n_known, "vKnown_ref[]")?;
            let seed = slice(dv_known, n_known, "dvKnown[]")?;
            let dst = slice_mut(dv_unknown, n_unknown, "dvUnknown[]")?;
            dst.copy_from_slice(&inst.directional_derivative(unknowns, knowns, seed)?);
            Ok(Status::Ok)
        })
    }
}

/// A function this FMU does not provide (its capability flag is false): logged and `fmi2Error`; called in
/// a state outside `allowed` or in an instance of the other interface type, it is an illegal call instead.
///
/// # Safety
/// See the module documentation.
pub unsafe fn unsupported<M: Model>(
    c: Fmi2Component,
    function: &str,
    allowed: Mask,
    reason: &str,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, allowed, |_| {
            Err(Failure::Rejected(format!("not supported ({reason})")))
        })
    }
}

/// `fmi2CancelStep`: `fmi2DoStep` is synchronous, so there is never a step to cancel.
///
/// # Safety
/// See the module documentation.
pub unsafe fn cancel_step<M: Model>(c: Fmi2Component) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe { call::<M>(c, "fmi2CancelStep", state::CANCEL_STEP, |_| Ok(Status::Ok)) }
}

/// `fmi2DoStep`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn do_step<M: Model>(c: Fmi2Component, current: f64, step: f64) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2DoStep", state::DO_STEP, |i| {
            i.do_step(current, step)
        })
    }
}

/// `fmi2Get{,Real,Integer,Boolean,String}Status`: `answer` gives the value for a status kind, or `None`
/// (`fmi2Discard`, logged) if that kind is not provided.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_status<M: Model, T>(
    c: Fmi2Component,
    function: &str,
    kind: Fmi2StatusKind,
    value: *mut T,
    answer: impl FnOnce(&Instance<M>, Fmi2StatusKind) -> Option<T>,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, state::STATUS, |inst| {
            let dst = out(value, "value")?;
            match answer(inst, kind) {
                Some(v) => {
                    *dst = v;
                    Ok(Status::Ok)
                }
                None => {
                    inst.log
                        .warning(&format!("{function}: status kind {kind} is not provided"));
                    Ok(Status::Discard)
                }
            }
        })
    }
}

/// `fmi2SetTime`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_time<M: Model>(c: Fmi2Component, time: f64) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe { call::<M>(c, "fmi2SetTime", state::SET_TIME, |i| i.set_time(time)) }
}

/// `fmi2EnterEventMode`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn enter_event_mode<M: Model>(c: Fmi2Component) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi2EnterEventMode", state::ENTER_EVENT_MODE, |i| {
            i.enter_event_mode()
        })
    }
}

/// `fmi2NewDiscreteStates`: the model has no discrete states and no time events, so one event
/// iteration always suffices.
///
/// # Safety
/// See the module documentation.
pub unsafe fn new_discrete_states<M: Model>(
    c: Fmi2Component,
    event_info: *mut Fmi2EventInfo,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(
            c,
            "fmi2NewDiscreteStates",
            state::NEW_DISCRETE_STATES,
            |_| {
                *out(event_info, "eventInfo")? = Fmi2EventInfo {
                    new_discrete_states_needed: FMI2_FALSE,
                    terminate_simulation: FMI2_FALSE,
                    nominals_of_continuous_states_changed: FMI2_FALSE,
                    values_of_continuous_states_changed: FMI2_FALSE,
                    next_event_time_defined: FMI2_FALSE,
                    next_event_time: 0.0,
                };
                Ok(Status::Ok)
            },
        )
    }
}

/// `fmi2EnterContinuousTimeMode`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn enter_continuous_time_mode<M: Model>(c: Fmi2Component) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(
            c,
            "fmi2EnterContinuousTimeMode",
            state::ENTER_CONTINUOUS_TIME_MODE,
            |i| i.enter_continuous_time_mode(),
        )
    }
}

/// `fmi2CompletedIntegratorStep`: accepts the current point; never asks for an event or to terminate.
///
/// # Safety
/// See the module documentation.
pub unsafe fn completed_integrator_step<M: Model>(
    c: Fmi2Component,
    enter_event_mode: *mut Fmi2Boolean,
    terminate_simulation: *mut Fmi2Boolean,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(
            c,
            "fmi2CompletedIntegratorStep",
            state::COMPLETED_INTEGRATOR_STEP,
            |i| {
                let event = out(enter_event_mode, "enterEventMode")?;
                let terminate = out(terminate_simulation, "terminateSimulation")?;
                let status = i.accept()?;
                *event = FMI2_FALSE;
                *terminate = FMI2_FALSE;
                Ok(status)
            },
        )
    }
}

/// The functions of the continuous states and event indicators (`fmi2SetContinuousStates`,
/// `fmi2GetContinuousStates`, `fmi2GetDerivatives`, `fmi2GetEventIndicators`,
/// `fmi2GetNominalsOfContinuousStates`): the model has none of either, so the only valid length `n` is 0
/// (and then nothing is read or written).
///
/// # Safety
/// See the module documentation.
pub unsafe fn no_states<M: Model>(
    c: Fmi2Component,
    function: &str,
    allowed: Mask,
    what: &str,
    n: usize,
) -> Fmi2StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, allowed, |_| match n {
            0 => Ok(Status::Ok),
            _ => Err(Failure::Rejected(format!(
                "this FMU has no {what}, but the call passes {n}"
            ))),
        })
    }
}
