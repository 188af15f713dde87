//! The generic implementation of every FMI 3.0 function for an [`ArrayModel`]; the exported C functions
//! are one call each into these. Each function checks its pointers, checks that the call is allowed in
//! the instance's state (else "Illegal call sequence" and `fmi3Error`), runs inside `catch_unwind` so that
//! no panic crosses the C boundary (a panic on a worker thread of the instance's pool reaches the calling
//! thread), logs failures and returns the status.
//!
//! # Safety
//! As the FMI 2.0 layer's ([`crate::fmi2::api`]): a non-null instance is a pointer returned by an
//! instantiate function of the same model and not yet freed; arrays have the stated lengths; an instance is
//! not used by two threads at once. FMU-state pointers are not trusted: only live handles are used.

use super::arrays::ArrayModel;
use super::description;
use super::ffi::*;
use super::instance::{Instance, Snapshot};
use super::state::{self, Interface, Mask, State};
use crate::fmi2::api::{Guarded, guarded, out, slice, slice_mut, store_snapshot, text};
use crate::fmi2::ffi::Status;
use crate::fmi2::handles;
use crate::fmi2::instance::{Failure, Outcome};
use crate::fmi2::logging::{Logger, Sink, to_c_string};
use crate::fmi2::variables::{Type, Value};
use std::ffi::c_int;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::ptr::null_mut;

/// A sink of the importer's `fmi3LogMessageCallback`.
fn c_sink(logger: Fmi3LogMessageCallback, environment: Fmi3InstanceEnvironment) -> Option<Sink> {
    let f = logger?;
    let env = environment as usize;
    Some(Box::new(
        move |status: Status, category: &str, message: &str| {
            let category = to_c_string(category);
            let message = to_c_string(message);
            // SAFETY: the importer guarantees that the callback and its environment stay valid while the
            // instance lives; both strings are NUL-terminated and outlive the call.
            unsafe {
                f(
                    env as Fmi3InstanceEnvironment,
                    status as c_int,
                    category.as_ptr(),
                    message.as_ptr(),
                )
            }
        },
    ))
}

/// The instance's token.
fn token<M: ArrayModel>() -> String {
    description::token(M::info(), M::arrays())
}

/// Runs `f` on the instance behind `c` if the function belongs to the instance's interface type and
/// `allowed` contains its state.
///
/// # Safety
/// `c` is null or a live instance of model `M`.
pub unsafe fn call<M: ArrayModel>(
    c: Fmi3Instance,
    function: &str,
    allowed: Mask,
    f: impl FnOnce(&mut Instance<M>) -> Outcome,
) -> Fmi3StatusC {
    // SAFETY: see the function's contract.
    let Some(inst) = (unsafe { (c as *mut Instance<M>).as_mut() }) else {
        return Status::Error as c_int;
    };
    guarded(inst, function, allowed, f)
}

impl<M: ArrayModel> Guarded for Instance<M> {
    type State = State;
    fn interface(&self) -> Interface {
        self.interface
    }
    fn state(&self) -> State {
        self.state
    }
    fn logger(&self) -> &Logger {
        &self.log
    }
    fn enter_error(&mut self) {
        self.state = State::Error;
    }
}

/// What an instantiate function was given.
pub struct Arguments {
    /// `instanceName`.
    pub name: Fmi3String,
    /// `instantiationToken`.
    pub token: Fmi3String,
    /// `resourcePath`.
    pub resource_path: Fmi3String,
    /// `loggingOn`.
    pub logging_on: bool,
    /// `instanceEnvironment`.
    pub environment: Fmi3InstanceEnvironment,
    /// `logMessage`.
    pub log_message: Fmi3LogMessageCallback,
}

/// `fmi3InstantiateModelExchange` / `fmi3InstantiateCoSimulation`: a new instance, or null (with a
/// logged reason) if the name is missing or the token differs. FMI 3.0's `resourcePath` is a path (with
/// a trailing separator), not a URI.
///
/// # Safety
/// Pointers are null or valid as FMI 3.0 requires.
pub unsafe fn instantiate<M: ArrayModel>(
    a: Arguments,
    interface: Interface,
    event_mode_used: bool,
) -> Fmi3Instance {
    catch_unwind(AssertUnwindSafe(|| {
        let log = Logger::new(c_sink(a.log_message, a.environment), a.logging_on);
        let function = match interface {
            Interface::ModelExchange => "fmi3InstantiateModelExchange",
            Interface::CoSimulation => "fmi3InstantiateCoSimulation",
        };
        let fail = |msg: &str| {
            log.error(&format!("{function}: {msg}"));
            null_mut()
        };
        // SAFETY: the strings are NUL-terminated or null.
        let name = match unsafe { text(a.name, "instanceName") } {
            Ok(n) if !n.is_empty() => n.to_string(),
            _ => return fail("instanceName is missing"),
        };
        let token = token::<M>();
        // SAFETY: as above.
        match unsafe { text(a.token, "instantiationToken") } {
            Ok(t) if t == token => {}
            _ => {
                return fail(&format!(
                    "instantiationToken does not match this binary's token {token}"
                ));
            }
        }
        let resources = match a.resource_path.is_null() {
            true => None,
            // SAFETY: as above.
            false => match unsafe { text(a.resource_path, "resourcePath") } {
                Ok("") => None,
                Ok(p) => Some(PathBuf::from(p)),
                Err(_) => {
                    log.warning(&format!(
                        "{function}: resourcePath is not UTF-8; resources are unavailable"
                    ));
                    None
                }
            },
        };
        log.event(&format!(
            "{function}: {} instance {name} created (resources: {resources:?})",
            interface.name()
        ));
        let mut inst = Instance::<M>::new(name, interface, log, resources);
        inst.event_mode_used = event_mode_used;
        Box::into_raw(Box::new(inst)) as Fmi3Instance
    }))
    .unwrap_or(null_mut())
}

/// `fmi3FreeInstance`.
///
/// # Safety
/// `c` is null or a live instance of `M`, which must not be used afterwards.
pub unsafe fn free_instance<M: ArrayModel>(c: Fmi3Instance) {
    if !c.is_null() {
        // SAFETY: see the function's contract; dropping cannot unwind into C because it is caught.
        let _ = catch_unwind(AssertUnwindSafe(|| {
            drop(unsafe { Box::from_raw(c as *mut Instance<M>) })
        }));
    }
}

/// `fmi3SetDebugLogging`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_debug_logging<M: ArrayModel>(
    c: Fmi3Instance,
    logging_on: bool,
    n: usize,
    categories: *const Fmi3String,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi3SetDebugLogging", state::ANY, |inst| {
            let names = slice(categories, n, "categories")?
                .iter()
                .map(|s| text(*s, "category"))
                .collect::<Result<Vec<_>, _>>()?;
            inst.log
                .set_debug_logging(logging_on, &names)
                .map_err(Failure::Rejected)?;
            Ok(Status::Ok)
        })
    }
}

/// A function whose whole work is one instance method: `fmi3ExitInitializationMode`, `fmi3Terminate` …
///
/// # Safety
/// See the module documentation.
pub unsafe fn simple<M: ArrayModel>(
    c: Fmi3Instance,
    function: &str,
    allowed: Mask,
    f: impl FnOnce(&mut Instance<M>) -> Outcome,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe { call::<M>(c, function, allowed, f) }
}

/// `fmi3Get{Float64,Int32,Boolean}`: values of table type `ty`, converted by `convert`.
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn get<M: ArrayModel, T>(
    c: Fmi3Instance,
    function: &str,
    ty: Type,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
    values: *mut T,
    n_values: usize,
    convert: impl Fn(&Value) -> T,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, state::GET, |inst| {
            let vrs = slice(vrs, nvr, "valueReferences")?;
            let out = slice_mut(values, n_values, "values")?;
            inst.get(vrs, ty, n_values, |k, v| out[k] = convert(v))
        })
    }
}

/// `fmi3GetString`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_string<M: ArrayModel>(
    c: Fmi3Instance,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
    values: *mut Fmi3String,
    n_values: usize,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi3GetString", state::GET, |inst| {
            let vrs = slice(vrs, nvr, "valueReferences")?;
            let out = slice_mut(values, n_values, "values")?;
            let (ptrs, status) = inst.get_strings(vrs, n_values)?;
            out.copy_from_slice(&ptrs);
            Ok(status)
        })
    }
}

/// `fmi3Set{Float64,Int32,Boolean,String}`: values of table type `ty`, converted by `convert`.
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn set<M: ArrayModel, T: Copy>(
    c: Fmi3Instance,
    function: &str,
    ty: Type,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
    values: *const T,
    n_values: usize,
    convert: impl Fn(T) -> Result<Value, Failure>,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, state::SET, |inst| {
            let vrs = slice(vrs, nvr, "valueReferences")?;
            let values = slice(values, n_values, "values")?;
            inst.set(vrs, ty, n_values, |k| convert(values[k]))
        })
    }
}

/// `fmi3GetUInt64` / `fmi3SetUInt64` (`set`: the values are read, else written).
///
/// # Safety
/// See the module documentation.
pub unsafe fn counts<M: ArrayModel>(
    c: Fmi3Instance,
    set: bool,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
    values: *mut u64,
    n_values: usize,
) -> Fmi3StatusC {
    let (function, allowed) = match set {
        true => ("fmi3SetUInt64", state::SET),
        false => ("fmi3GetUInt64", state::GET),
    };
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, allowed, |inst| {
            let vrs = slice(vrs, nvr, "valueReferences")?;
            match set {
                true => inst.set_counts(vrs, slice(values, n_values, "values")?),
                false => inst.get_counts(vrs, slice_mut(values, n_values, "values")?),
            }
        })
    }
}

/// A get or set of a type this FMU has no variables of (Float32, the other integer types, Binary, Clock):
/// nothing to do for no value references, else the first is unknown.
///
/// # Safety
/// See the module documentation.
pub unsafe fn no_variables<M: ArrayModel>(
    c: Fmi3Instance,
    function: &str,
    type_name: &str,
    allowed: Mask,
    vrs: *const Fmi3ValueReference,
    nvr: usize,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, allowed, |_| {
            match slice(vrs, nvr, "valueReferences")?.first() {
                None => Ok(Status::Ok),
                Some(vr) => Err(Failure::Rejected(format!(
                    "no {type_name} variable has value reference {vr}"
                ))),
            }
        })
    }
}

/// A function of a capability this FMU does not declare (per-element dependencies, output derivatives):
/// refused with the reason.
///
/// # Safety
/// See the module documentation.
pub unsafe fn not_provided<M: ArrayModel>(
    c: Fmi3Instance,
    function: &str,
    why: &str,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, state::ANY, |_| {
            Err(Failure::Rejected(format!("not provided: {why}")))
        })
    }
}

/// `fmi3GetFMUState`.
///
/// # Safety
/// See the module documentation; a non-null `*state` was returned by this FMU and not freed.
pub unsafe fn get_fmu_state<M: ArrayModel>(
    c: Fmi3Instance,
    state_out: *mut Fmi3FmuState,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi3GetFMUState", state::ANY, |inst| {
            store_snapshot(out(state_out, "FMUState")?, inst.snapshot());
            Ok(Status::Ok)
        })
    }
}

/// A snapshot from an FMU-state pointer: null, freed and foreign pointers are rejected.
///
/// # Safety
/// No snapshot is freed while the returned reference lives (one thread per instance).
unsafe fn snapshot_ref<'a, S>(s: Fmi3FmuState) -> Result<&'a Snapshot<S>, Failure> {
    let ptr = s as *const Snapshot<S>;
    if ptr.is_null() || !handles::is_live(ptr) {
        return Err(Failure::Rejected(
            "argument FMUState is not a live FMU state of this FMU (null, already freed, or not returned \
             by fmi3GetFMUState or fmi3DeserializeFMUState)"
                .into(),
        ));
    }
    // SAFETY: a live handle points to a snapshot of type `S` (see the function's contract).
    Ok(unsafe { &*ptr })
}

/// `fmi3SetFMUState`.
///
/// # Safety
/// See [`get_fmu_state`].
pub unsafe fn set_fmu_state<M: ArrayModel>(c: Fmi3Instance, s: Fmi3FmuState) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi3SetFMUState", state::ANY, |inst| {
            inst.restore(snapshot_ref::<M::State>(s)?)
        })
    }
}

/// `fmi3FreeFMUState`: frees `*state` (nothing if null) and sets it to null; a `*state` that is not a
/// live FMU state is rejected and nothing is freed.
///
/// # Safety
/// See the module documentation.
pub unsafe fn free_fmu_state<M: ArrayModel>(
    c: Fmi3Instance,
    state_ptr: *mut Fmi3FmuState,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi3FreeFMUState", state::ANY, |_| {
            let slot = out(state_ptr, "FMUState")?;
            let snapshot = *slot as *mut Snapshot<M::State>;
            if snapshot.is_null() {
                return Ok(Status::Ok);
            }
            if !handles::release(snapshot) {
                return Err(Failure::Rejected(
                    "*FMUState is not a live FMU state of this FMU; nothing is freed".into(),
                ));
            }
            drop(Box::from_raw(snapshot));
            *slot = null_mut();
            Ok(Status::Ok)
        })
    }
}

/// `fmi3SerializedFMUStateSize` (`bytes` null) and `fmi3SerializeFMUState`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn serialize<M: ArrayModel>(
    c: Fmi3Instance,
    s: Fmi3FmuState,
    size: *mut usize,
    bytes: *mut Fmi3Byte,
    n: usize,
) -> Fmi3StatusC {
    let function = match bytes.is_null() && !size.is_null() {
        true => "fmi3SerializedFMUStateSize",
        false => "fmi3SerializeFMUState",
    };
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, state::ANY, |_| {
            let data = snapshot_ref::<M::State>(s)?.to_bytes(&token::<M>());
            if !size.is_null() {
                *out(size, "size")? = data.len();
                return Ok(Status::Ok);
            }
            if n != data.len() {
                return Err(Failure::Rejected(format!(
                    "size {n} differs from the serialized size {} (fmi3SerializedFMUStateSize)",
                    data.len()
                )));
            }
            slice_mut(bytes, n, "serializedState")?.copy_from_slice(&data);
            Ok(Status::Ok)
        })
    }
}

/// `fmi3DeserializeFMUState`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn deserialize<M: ArrayModel>(
    c: Fmi3Instance,
    bytes: *const Fmi3Byte,
    n: usize,
    state_out: *mut Fmi3FmuState,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi3DeserializeFMUState", state::ANY, |_| {
            let data = slice(bytes, n, "serializedState")?;
            let snapshot = Snapshot::<M::State>::from_bytes(
                data,
                &token::<M>(),
                M::info().variables,
                M::arrays(),
            )
            .map_err(Failure::Rejected)?;
            store_snapshot(out(state_out, "FMUState")?, snapshot);
            Ok(Status::Ok)
        })
    }
}

/// `fmi3GetDirectionalDerivative` (`adjoint` false) and `fmi3GetAdjointDerivative` (true).
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn derivative<M: ArrayModel>(
    c: Fmi3Instance,
    adjoint: bool,
    unknowns: *const Fmi3ValueReference,
    n_unknowns: usize,
    knowns: *const Fmi3ValueReference,
    n_knowns: usize,
    seed: *const f64,
    n_seed: usize,
    sensitivity: *mut f64,
    n_sensitivity: usize,
) -> Fmi3StatusC {
    let function = match adjoint {
        true => "fmi3GetAdjointDerivative",
        false => "fmi3GetDirectionalDerivative",
    };
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, state::DERIVATIVE, |inst| {
            let unknowns = slice(unknowns, n_unknowns, "unknowns")?;
            let knowns = slice(knowns, n_knowns, "knowns")?;
            let seed = slice(seed, n_seed, "seed")?;
            let out = slice_mut(sensitivity, n_sensitivity, "sensitivity")?;
            let d = inst.derivative(unknowns, knowns, seed, n_sensitivity, adjoint)?;
            out.copy_from_slice(&d);
            Ok(Status::Ok)
        })
    }
}

/// `fmi3DoStep`: no events, no early return.
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn do_step<M: ArrayModel>(
    c: Fmi3Instance,
    current: f64,
    step: f64,
    event_handling_needed: *mut bool,
    terminate_simulation: *mut bool,
    early_return: *mut bool,
    last_successful_time: *mut f64,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi3DoStep", state::DO_STEP, |inst| {
            let flags = [
                out(event_handling_needed, "eventHandlingNeeded")?,
                out(terminate_simulation, "terminateSimulation")?,
                out(early_return, "earlyReturn")?,
            ];
            let last = out(last_successful_time, "lastSuccessfulTime")?;
            let status = inst.do_step(current, step)?;
            for f in flags {
                *f = false;
            }
            *last = inst.time();
            Ok(status)
        })
    }
}

/// Writes `false` to each non-null flag (the event flags of `fmi3UpdateDiscreteStates` and
/// `fmi3CompletedIntegratorStep`: no events, no states).
fn no_events(flags: &[*mut bool]) {
    for f in flags {
        // SAFETY: the importer passes valid pointers or null.
        if let Some(f) = unsafe { f.as_mut() } {
            *f = false;
        }
    }
}

/// `fmi3UpdateDiscreteStates`: nothing changes, no next time event.
///
/// # Safety
/// See the module documentation.
pub unsafe fn update_discrete_states<M: ArrayModel>(
    c: Fmi3Instance,
    flags: [*mut bool; 5],
    next_event_time: *mut f64,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, "fmi3UpdateDiscreteStates", state::EVENT, |inst| {
            no_events(&flags);
            if let Some(t) = next_event_time.as_mut() {
                *t = inst.time();
            }
            inst.update()
        })
    }
}

/// `fmi3CompletedIntegratorStep`: the point is accepted; no event, no termination.
///
/// # Safety
/// See the module documentation.
pub unsafe fn completed_integrator_step<M: ArrayModel>(
    c: Fmi3Instance,
    enter_event_mode: *mut bool,
    terminate_simulation: *mut bool,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(
            c,
            "fmi3CompletedIntegratorStep",
            state::CONTINUOUS_TIME,
            |inst| {
                out(enter_event_mode, "enterEventMode")?;
                out(terminate_simulation, "terminateSimulation")?;
                let status = inst.accept()?;
                no_events(&[enter_event_mode, terminate_simulation]);
                Ok(status)
            },
        )
    }
}

/// The functions of continuous states and event indicators: there are none, so only arrays of length 0
/// are accepted (`values` may then be null).
///
/// # Safety
/// See the module documentation.
pub unsafe fn no_states<M: ArrayModel>(
    c: Fmi3Instance,
    function: &str,
    allowed: Mask,
    n: usize,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, allowed, |_| match n {
            0 => Ok(Status::Ok),
            n => Err(Failure::Rejected(format!(
                "the model has no continuous states and no event indicators, but {n} values were passed"
            ))),
        })
    }
}

/// `fmi3GetNumberOfContinuousStates`, `fmi3GetNumberOfEventIndicators`: 0.
///
/// # Safety
/// See the module documentation.
pub unsafe fn number_of<M: ArrayModel>(
    c: Fmi3Instance,
    function: &str,
    n: *mut usize,
) -> Fmi3StatusC {
    // SAFETY: see the module documentation.
    unsafe {
        call::<M>(c, function, state::NUMBERS, |_| {
            *out(n, "the number")? = 0;
            Ok(Status::Ok)
        })
    }
}
