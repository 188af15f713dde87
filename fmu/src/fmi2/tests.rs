//! Tests of the generic layer through its C-facing functions, with a toy model y = gain·u.

use super::api;
use super::ffi::*;
use super::instance::Instance;
use super::logging::Logger;
use super::logging::tests::{Captured, capturing};
use super::model::{DefaultExperiment, Model, ModelInfo, Unit};
use super::state::{self, Interface, State};
use super::variables::{Causality, Kind, Type, Value, Values, Variability, Variable};
use std::ffi::{CStr, CString, c_int};
use std::ptr::{null, null_mut};

const U: u32 = 0;
const GAIN: u32 = 1;
const Y: u32 = 2;
const LABEL: u32 = 3;
const OK: c_int = Status::Ok as c_int;
const ERROR: c_int = Status::Error as c_int;

static VARS: [Variable; 4] = [
    Variable {
        name: "u",
        vr: U,
        causality: Causality::Input,
        variability: Variability::Continuous,
        kind: Kind::Real {
            unit: "1",
            start: Some(1.0),
            min: None,
            max: None,
            nominal: Some(1.0),
        },
        description: "input; u > 100 fails, u = 13 panics",
    },
    Variable {
        name: "gain",
        vr: GAIN,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        kind: Kind::Real {
            unit: "1",
            start: Some(2.0),
            min: None,
            max: None,
            nominal: None,
        },
        description: "gain",
    },
    Variable {
        name: "y",
        vr: Y,
        causality: Causality::Output,
        variability: Variability::Continuous,
        kind: Kind::Real {
            unit: "1",
            start: None,
            min: None,
            max: None,
            nominal: None,
        },
        description: "gain·u",
    },
    Variable {
        name: "label",
        vr: LABEL,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        kind: Kind::String { start: Some("toy") },
        description: "text",
    },
];

static INFO: ModelInfo = ModelInfo {
    model_name: "Toy",
    model_identifier: "Toy",
    description: "y = gain·u",
    author: "tests",
    version: "0",
    license: "none",
    generation_tool: "tests",
    units: &[Unit {
        name: "1",
        kg: 0,
        m: 0,
        s: 0,
        k: 0,
        display: &[],
    }],
    display_unit: |_| None,
    variables: &VARS,
    default_experiment: DefaultExperiment {
        start_time: 0.0,
        stop_time: 1.0,
        step_size: 0.1,
    },
};

struct Toy {
    calls: usize,
    accepted: usize,
}

fn toy_eval(values: &Values) -> Result<Values, String> {
    let u = values.real(0);
    if u > 100.0 {
        return Err(format!("u = {u} is too large"));
    }
    assert!(u != 13.0, "unlucky input");
    let mut v = values.clone();
    v.set(2, Value::Real(values.real(1) * u));
    Ok(v)
}

impl Model for Toy {
    type State = ();
    fn info() -> &'static ModelInfo {
        &INFO
    }
    fn state(&self) {}
    fn set_state(&mut self, _: &()) {}
    fn new(_: Option<std::path::PathBuf>) -> Self {
        Toy {
            calls: 0,
            accepted: 0,
        }
    }
    fn reset(&mut self) {
        self.calls = 0;
        self.accepted = 0;
    }
    fn calculate(&mut self, values: &mut Values, _: &Logger) -> Result<Status, String> {
        self.calls += 1;
        *values = toy_eval(values)?;
        Ok(Status::Ok)
    }
    // the toy remembers nothing, so a trial is a step and accepting changes nothing
    fn calculate_trial(&mut self, values: &mut Values, log: &Logger) -> Result<Status, String> {
        self.calculate(values, log)
    }
    fn accept(&mut self, _: &Values, _: &Logger) -> Result<Status, String> {
        self.accepted += 1;
        Ok(Status::Ok)
    }
    fn directional_derivative(
        &mut self,
        values: &Values,
        unknowns: &[usize],
        knowns: &[usize],
        seed: &[f64],
        _: &Logger,
    ) -> Result<Vec<f64>, String> {
        super::derivative::forward_difference(values, unknowns, knowns, seed, 1e-6, toy_eval)
    }
}

type Log = Captured;

fn new_toy() -> (Fmi2Component, Log) {
    new_instance(Interface::CoSimulation)
}

fn new_instance(interface: Interface) -> (Fmi2Component, Log) {
    let (logger, seen) = capturing(true);
    let inst = Instance::new("toy".into(), interface, logger, Toy::new(None));
    (Box::into_raw(Box::new(inst)) as Fmi2Component, seen)
}

fn inst(c: Fmi2Component) -> &'static mut Instance<Toy> {
    unsafe { &mut *(c as *mut Instance<Toy>) }
}

fn set_real(c: Fmi2Component, vr: u32, x: f64) -> c_int {
    unsafe { api::set::<Toy, f64>(c, "fmi2SetReal", &vr, 1, &x, |v| Ok(Value::Real(v))) }
}

fn get_real(c: Fmi2Component, vr: u32) -> (c_int, f64) {
    let mut x = f64::NAN;
    let s = unsafe {
        api::get::<Toy, f64>(c, "fmi2GetReal", Type::Real, &vr, 1, &mut x, |v| match v {
            Value::Real(x) => *x,
            _ => unreachable!(),
        })
    };
    (s, x)
}

fn init(c: Fmi2Component) {
    unsafe {
        assert_eq!(api::setup_experiment::<Toy>(c, 0.0), OK);
        assert_eq!(api::enter_initialization_mode::<Toy>(c), OK);
        assert_eq!(api::exit_initialization_mode::<Toy>(c), OK);
    }
}

fn last_error(seen: &Log) -> String {
    seen.borrow()
        .iter()
        .rev()
        .find(|m| m.0 == Status::Error)
        .map(|m| m.2.clone())
        .unwrap_or_default()
}

#[test]
fn life_cycle_outputs_follow_inputs() {
    let (c, _) = new_toy();
    assert_eq!(set_real(c, GAIN, 3.0), OK);
    init(c);
    assert_eq!(get_real(c, Y), (OK, 3.0));
    assert_eq!(set_real(c, U, 2.0), OK);
    assert_eq!(unsafe { api::do_step::<Toy>(c, 0.0, 0.1) }, OK);
    assert_eq!(get_real(c, Y), (OK, 6.0));
    assert!((inst(c).time() - 0.1).abs() < 1e-15);
    // unchanged inputs: no recomputation
    let calls = inst(c).model().calls;
    assert_eq!(set_real(c, U, 2.0), OK);
    assert_eq!(unsafe { api::do_step::<Toy>(c, 0.1, 0.1) }, OK);
    assert_eq!(inst(c).model().calls, calls);
    assert_eq!(unsafe { api::terminate::<Toy>(c) }, OK);
    assert_eq!(unsafe { api::reset::<Toy>(c) }, OK);
    assert_eq!(inst(c).state, State::Instantiated);
    assert_eq!(inst(c).values().real(1), 2.0);
    unsafe { api::free_instance::<Toy>(c) };
}

#[test]
fn illegal_call_sequences_are_logged_and_change_nothing() {
    let (c, seen) = new_toy();
    assert_eq!(unsafe { api::do_step::<Toy>(c, 0.0, 0.1) }, ERROR);
    assert!(
        last_error(&seen).contains("fmi2DoStep: Illegal call sequence"),
        "{seen:?}"
    );
    assert_eq!(get_real(c, Y).0, ERROR);
    assert_eq!(unsafe { api::exit_initialization_mode::<Toy>(c) }, ERROR);
    assert_eq!(unsafe { api::cancel_step::<Toy>(c) }, ERROR);
    assert_eq!(inst(c).state, State::Instantiated);
    init(c);
    assert_eq!(unsafe { api::enter_initialization_mode::<Toy>(c) }, ERROR);
    // fixed parameters cannot change after initialization; outputs never
    assert_eq!(set_real(c, GAIN, 5.0), ERROR);
    assert!(last_error(&seen).contains("parameter gain is fixed"));
    assert_eq!(set_real(c, Y, 5.0), ERROR);
    assert!(last_error(&seen).contains("y is an output"));
    assert_eq!(set_real(c, 99, 5.0), ERROR);
    assert!(last_error(&seen).contains("reference 99"));
    assert_eq!(inst(c).state, State::StepComplete);
    unsafe { api::free_instance::<Toy>(c) };
}

#[test]
fn null_pointers_and_non_finite_values_are_rejected() {
    let (c, seen) = new_toy();
    let vr = U;
    let mut x = 0.0;
    unsafe {
        assert_eq!(api::do_step::<Toy>(null_mut(), 0.0, 1.0), ERROR);
        assert_eq!(
            api::set::<Toy, f64>(c, "fmi2SetReal", null(), 1, &x, |v| Ok(Value::Real(v))),
            ERROR
        );
        assert!(last_error(&seen).contains("vr[] is a null pointer"));
        assert_eq!(
            api::set::<Toy, f64>(c, "fmi2SetReal", &vr, 1, null(), |v| Ok(Value::Real(v))),
            ERROR
        );
        assert_eq!(
            api::set::<Toy, f64>(c, "fmi2SetReal", null(), 0, null(), |v| Ok(Value::Real(v))),
            OK
        );
        assert_eq!(api::get_fmu_state::<Toy>(c, null_mut()), ERROR);
        assert_eq!(api::set_fmu_state::<Toy>(c, null_mut()), ERROR);
        assert_eq!(
            api::get::<Toy, f64>(c, "fmi2GetReal", Type::Real, &vr, 1, null_mut(), |_| 0.0),
            ERROR
        );
        x = f64::NAN;
        assert_eq!(
            api::set::<Toy, f64>(c, "fmi2SetReal", &vr, 1, &x, |v| Ok(Value::Real(v))),
            ERROR
        );
    }
    assert!(
        last_error(&seen).contains("u = NaN is not a finite number"),
        "{}",
        last_error(&seen)
    );
    assert_eq!(set_real(c, U, f64::INFINITY), ERROR);
    assert_eq!(inst(c).values().real(0), 1.0);
    assert_eq!(inst(c).state, State::Instantiated);
    unsafe { api::free_instance::<Toy>(c) };
}

#[test]
fn failures_and_panics_enter_the_error_state_and_a_snapshot_recovers() {
    let (c, seen) = new_toy();
    init(c);
    let mut snap: Fmi2FmuState = null_mut();
    assert_eq!(unsafe { api::get_fmu_state::<Toy>(c, &mut snap) }, OK);
    assert_eq!(set_real(c, U, 1000.0), OK);
    assert_eq!(unsafe { api::do_step::<Toy>(c, 0.0, 0.1) }, ERROR);
    assert!(last_error(&seen).contains("u = 1000 is too large"));
    assert_eq!(inst(c).state, State::Error);
    assert_eq!(unsafe { api::do_step::<Toy>(c, 0.1, 0.1) }, ERROR);
    assert!(last_error(&seen).contains("Illegal call sequence"));
    assert_eq!(unsafe { api::set_fmu_state::<Toy>(c, snap) }, OK);
    assert_eq!(inst(c).state, State::StepComplete);
    assert_eq!(get_real(c, Y), (OK, 2.0));
    assert_eq!(set_real(c, U, 13.0), OK);
    assert_eq!(unsafe { api::do_step::<Toy>(c, 0.0, 0.1) }, ERROR);
    assert!(
        last_error(&seen).contains("panic: unlucky input"),
        "{}",
        last_error(&seen)
    );
    assert_eq!(inst(c).state, State::Error);
    unsafe {
        assert_eq!(api::free_fmu_state::<Toy>(c, &mut snap), OK);
        assert!(snap.is_null());
        api::free_instance::<Toy>(c);
    }
}

#[test]
fn serialized_states_round_trip_and_corruption_is_rejected() {
    let (c, seen) = new_toy();
    assert_eq!(set_real(c, GAIN, 4.0), OK);
    init(c);
    assert_eq!(set_real(c, U, 0.5), OK);
    let mut snap: Fmi2FmuState = null_mut();
    let mut size = 0usize;
    unsafe {
        assert_eq!(api::do_step::<Toy>(c, 0.0, 0.1), OK);
        assert_eq!(api::get_fmu_state::<Toy>(c, &mut snap), OK);
        assert_eq!(
            api::serialized_fmu_state_size::<Toy>(c, snap, &mut size),
            OK
        );
        let mut bytes = vec![0 as Fmi2Byte; size];
        assert_eq!(
            api::serialize_fmu_state::<Toy>(c, snap, bytes.as_mut_ptr(), size - 1),
            ERROR
        );
        assert!(last_error(&seen).contains("differs from the serialized size"));
        assert_eq!(
            api::serialize_fmu_state::<Toy>(c, snap, bytes.as_mut_ptr(), size),
            OK
        );
        // a second instance takes the state over
        let (d, seen_d) = new_toy();
        let mut restored: Fmi2FmuState = null_mut();
        assert_eq!(
            api::deserialize_fmu_state::<Toy>(d, bytes.as_ptr(), size, &mut restored),
            OK
        );
        assert_eq!(api::set_fmu_state::<Toy>(d, restored), OK);
        assert_eq!(get_real(d, Y), (OK, 2.0));
        assert_eq!(inst(d).values(), inst(c).values());
        assert!((inst(d).time() - 0.1).abs() < 1e-15);
        bytes[size / 2] ^= 1;
        assert_eq!(
            api::deserialize_fmu_state::<Toy>(d, bytes.as_ptr(), size, &mut restored),
            ERROR
        );
        assert!(
            last_error(&seen_d).contains("checksum mismatch"),
            "{seen_d:?}"
        );
        api::free_fmu_state::<Toy>(d, &mut restored);
        api::free_fmu_state::<Toy>(c, &mut snap);
        api::free_instance::<Toy>(d);
        api::free_instance::<Toy>(c);
    }
}

#[test]
fn strings_booleans_status_and_derivatives() {
    let (c, seen) = new_toy();
    let vr = LABEL;
    let text = CString::new("hello").unwrap();
    let p = text.as_ptr();
    unsafe {
        assert_eq!(
            api::set::<Toy, Fmi2String>(c, "fmi2SetString", &vr, 1, &p, |s| api::string_value(s)),
            OK
        );
        let bad: Fmi2String = null();
        assert_eq!(
            api::set::<Toy, Fmi2String>(c, "fmi2SetString", &vr, 1, &bad, |s| api::string_value(s)),
            ERROR
        );
        init(c);
        let mut got: Fmi2String = null();
        assert_eq!(api::get_string::<Toy>(c, &vr, 1, &mut got), OK);
        assert_eq!(CStr::from_ptr(got).to_str().unwrap(), "hello");
        assert_eq!(api::do_step::<Toy>(c, 0.0, 0.5), OK);
        let mut t = 0.0;
        assert_eq!(
            api::get_status::<Toy, f64>(
                c,
                "fmi2GetRealStatus",
                FMI2_LAST_SUCCESSFUL_TIME,
                &mut t,
                |i, _| Some(i.time())
            ),
            OK
        );
        assert_eq!(t, 0.5);
        let mut s = 0;
        assert_eq!(
            api::get_status::<Toy, c_int>(
                c,
                "fmi2GetIntegerStatus",
                FMI2_DO_STEP_STATUS,
                &mut s,
                |_, _| None
            ),
            Status::Discard as c_int
        );
        // d y / d u = gain = 2 along seed 3 → 6
        let (unknown, known, seed) = (Y, U, 3.0);
        let mut d = 0.0;
        assert_eq!(
            api::get_directional_derivative::<Toy>(c, &unknown, 1, &known, 1, &seed, &mut d),
            OK
        );
        assert!((d - 6.0).abs() < 1e-6, "{d}");
        assert_eq!(
            api::get_directional_derivative::<Toy>(c, &known, 1, &unknown, 1, &seed, &mut d),
            ERROR
        );
        assert!(last_error(&seen).contains("not a Real Output"));
        assert_eq!(
            api::unsupported::<Toy>(
                c,
                "fmi2SetRealInputDerivatives",
                state::SET_INPUT_DERIVATIVES,
                "canInterpolateInputs=false"
            ),
            ERROR
        );
        assert!(last_error(&seen).contains("not supported (canInterpolateInputs=false)"));
        api::free_instance::<Toy>(c);
    }
}

#[test]
fn instantiate_checks_type_guid_and_callbacks() {
    let guid = CString::new(super::description::guid(&INFO)).unwrap();
    let functions = Fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: null_mut(),
    };
    unsafe {
        let c = api::instantiate::<Toy>(
            c"a".as_ptr(),
            FMI2_COSIMULATION,
            guid.as_ptr(),
            c"file:///tmp".as_ptr(),
            &functions,
            0,
        );
        assert!(!c.is_null());
        assert_eq!(inst(c).name, "a");
        api::free_instance::<Toy>(c);
        let me = api::instantiate::<Toy>(
            c"me".as_ptr(),
            FMI2_MODEL_EXCHANGE,
            guid.as_ptr(),
            null(),
            &functions,
            0,
        );
        assert_eq!(inst(me).interface, Interface::ModelExchange);
        api::free_instance::<Toy>(me);
        assert!(
            api::instantiate::<Toy>(c"a".as_ptr(), 2, guid.as_ptr(), null(), &functions, 0)
                .is_null()
        );
        assert!(
            api::instantiate::<Toy>(
                c"a".as_ptr(),
                FMI2_COSIMULATION,
                c"{x}".as_ptr(),
                null(),
                &functions,
                0
            )
            .is_null()
        );
        assert!(
            api::instantiate::<Toy>(
                null(),
                FMI2_COSIMULATION,
                guid.as_ptr(),
                null(),
                &functions,
                0
            )
            .is_null()
        );
        assert!(
            api::instantiate::<Toy>(
                c"a".as_ptr(),
                FMI2_COSIMULATION,
                guid.as_ptr(),
                null(),
                null(),
                0
            )
            .is_null()
        );
        api::free_instance::<Toy>(null_mut());
    }
}

fn me_init(c: Fmi2Component) {
    unsafe {
        assert_eq!(api::setup_experiment::<Toy>(c, 0.0), OK);
        assert_eq!(api::enter_initialization_mode::<Toy>(c), OK);
        assert_eq!(api::exit_initialization_mode::<Toy>(c), OK);
    }
}

fn completed_step(c: Fmi2Component) -> c_int {
    let (mut event, mut terminate) = (FMI2_TRUE, FMI2_TRUE);
    let s = unsafe { api::completed_integrator_step::<Toy>(c, &mut event, &mut terminate) };
    if s == OK {
        assert_eq!((event, terminate), (FMI2_FALSE, FMI2_FALSE));
    }
    s
}

#[test]
fn model_exchange_runs_the_standard_state_machine_and_accepts_points() {
    let (c, seen) = new_instance(Interface::ModelExchange);
    assert_eq!(set_real(c, GAIN, 3.0), OK);
    me_init(c);
    assert_eq!(inst(c).state, State::EventMode);
    assert_eq!(inst(c).model().accepted, 1, "initialization is accepted");
    assert_eq!(get_real(c, Y), (OK, 3.0));
    let mut info = Fmi2EventInfo {
        new_discrete_states_needed: FMI2_TRUE,
        terminate_simulation: FMI2_TRUE,
        nominals_of_continuous_states_changed: FMI2_TRUE,
        values_of_continuous_states_changed: FMI2_TRUE,
        next_event_time_defined: FMI2_TRUE,
        next_event_time: 1.0,
    };
    unsafe {
        assert_eq!(api::new_discrete_states::<Toy>(c, &mut info), OK);
        assert_eq!(info.new_discrete_states_needed, FMI2_FALSE);
        assert_eq!(info.terminate_simulation, FMI2_FALSE);
        assert_eq!(info.next_event_time_defined, FMI2_FALSE);
        assert_eq!(api::enter_continuous_time_mode::<Toy>(c), OK);
        assert_eq!(inst(c).state, State::ContinuousTimeMode);
        // outputs follow the inputs lazily within the step, without accepting
        assert_eq!(api::set_time::<Toy>(c, 0.25), OK);
        assert_eq!(set_real(c, U, 2.0), OK);
        let calls = inst(c).model().calls;
        assert_eq!(get_real(c, Y), (OK, 6.0));
        assert_eq!(get_real(c, Y), (OK, 6.0));
        assert_eq!(inst(c).model().calls, calls + 1);
        assert_eq!(inst(c).model().accepted, 2);
        assert_eq!(completed_step(c), OK);
        assert_eq!(inst(c).model().accepted, 3);
        assert_eq!(inst(c).time(), 0.25);
        // no states, no event indicators: only length 0
        for (f, name, mask) in [
            (0, "fmi2GetDerivatives", state::GET_DERIVATIVES),
            (1, "fmi2GetEventIndicators", state::GET_EVENT_INDICATORS),
        ] {
            assert_eq!(api::no_states::<Toy>(c, name, mask, "things", 0), OK, "{f}");
            assert_eq!(api::no_states::<Toy>(c, name, mask, "things", 1), ERROR);
            assert!(last_error(&seen).contains("has no things, but the call passes 1"));
        }
        assert_eq!(api::enter_event_mode::<Toy>(c), OK);
        assert_eq!(api::enter_event_mode::<Toy>(c), OK);
        assert_eq!(set_real(c, U, 4.0), OK);
        assert_eq!(get_real(c, Y), (OK, 12.0));
        assert_eq!(api::set_time::<Toy>(c, f64::NAN), ERROR);
        assert_eq!(api::terminate::<Toy>(c), OK);
        api::free_instance::<Toy>(c);
    }
}

#[test]
fn model_exchange_refuses_illegal_sequences_and_co_simulation_functions() {
    let (c, seen) = new_instance(Interface::ModelExchange);
    unsafe {
        assert_eq!(api::set_time::<Toy>(c, 0.0), ERROR);
        assert!(last_error(&seen).contains(
            "fmi2SetTime: Illegal call sequence (the instance is in state Instantiated)"
        ));
        assert_eq!(api::enter_continuous_time_mode::<Toy>(c), ERROR);
        assert_eq!(completed_step(c), ERROR);
        me_init(c);
        // Co-Simulation functions belong to the other interface type
        assert_eq!(api::do_step::<Toy>(c, 0.0, 0.1), ERROR);
        assert!(
            last_error(&seen)
                .contains("fmi2DoStep: Illegal call sequence (not a function of Model Exchange"),
            "{}",
            last_error(&seen)
        );
        let mut t = 0.0;
        assert_eq!(
            api::get_status::<Toy, f64>(
                c,
                "fmi2GetRealStatus",
                FMI2_LAST_SUCCESSFUL_TIME,
                &mut t,
                |i, _| Some(i.time())
            ),
            ERROR
        );
        assert_eq!(api::cancel_step::<Toy>(c), ERROR);
        assert_eq!(
            api::unsupported::<Toy>(
                c,
                "fmi2GetRealOutputDerivatives",
                state::GET_OUTPUT_DERIVATIVES,
                "x"
            ),
            ERROR
        );
        assert!(last_error(&seen).contains("not a function of Model Exchange"));
        // event mode: no integrator step to complete
        assert_eq!(completed_step(c), ERROR);
        assert!(last_error(&seen).contains("fmi2CompletedIntegratorStep: Illegal call sequence"));
        assert_eq!(api::enter_continuous_time_mode::<Toy>(c), OK);
        let mut info = std::mem::zeroed::<Fmi2EventInfo>();
        assert_eq!(api::new_discrete_states::<Toy>(c, &mut info), ERROR);
        assert_eq!(api::enter_continuous_time_mode::<Toy>(c), ERROR);
        assert_eq!(api::enter_initialization_mode::<Toy>(c), ERROR);
        let (mut event, mut terminate) = (0, 0);
        assert_eq!(
            api::completed_integrator_step::<Toy>(c, null_mut(), &mut terminate),
            ERROR
        );
        assert!(last_error(&seen).contains("enterEventMode is a null pointer"));
        assert_eq!(
            api::completed_integrator_step::<Toy>(c, &mut event, &mut terminate),
            OK
        );
        // a Co-Simulation instance's snapshot at a communication point cannot enter this instance
        let (d, _) = new_toy();
        init(d);
        let mut snap: Fmi2FmuState = null_mut();
        assert_eq!(api::get_fmu_state::<Toy>(d, &mut snap), OK);
        assert_eq!(api::set_fmu_state::<Toy>(c, snap), ERROR);
        assert!(last_error(&seen).contains(
            "taken in state StepComplete, which a Model Exchange instance does not have"
        ));
        assert_eq!(inst(c).state, State::ContinuousTimeMode);
        // and Model Exchange functions are refused in the Co-Simulation instance
        assert_eq!(api::set_time::<Toy>(d, 0.0), ERROR);
        assert_eq!(api::enter_event_mode::<Toy>(d), ERROR);
        api::free_fmu_state::<Toy>(d, &mut snap);
        api::free_instance::<Toy>(d);
        api::free_instance::<Toy>(c);
    }
}

/// The Reference-FMUs' fmusim frees a state with `fmi2FreeFMUstate(c, state)` instead of `(c, &state)`
/// (its `--final-fmu-state-file` crashed with a segmentation fault); masters may also free a state twice
/// or pass a freed or foreign one: none of these may touch memory that is not a live snapshot.
#[test]
fn freed_foreign_and_misplaced_fmu_state_pointers_are_refused_not_dereferenced() {
    let (c, seen) = new_toy();
    init(c);
    let mut snap: Fmi2FmuState = null_mut();
    unsafe {
        assert_eq!(api::get_fmu_state::<Toy>(c, &mut snap), OK);
        // fmusim's call: the state itself where the address of the master's variable belongs
        assert_eq!(api::free_fmu_state::<Toy>(c, snap as *mut Fmi2FmuState), OK);
        let last = seen.borrow().last().unwrap().clone();
        assert_eq!(last.0, Status::Warning);
        assert!(last.2.contains("FMU state itself"), "{}", last.2);
        // the variable still holds the freed state: every use of it is refused by name
        assert_eq!(api::set_fmu_state::<Toy>(c, snap), ERROR);
        assert!(last_error(&seen).contains("not a live FMU state"));
        let mut size = 0usize;
        assert_eq!(
            api::serialized_fmu_state_size::<Toy>(c, snap, &mut size),
            ERROR
        );
        assert_eq!(api::free_fmu_state::<Toy>(c, &mut snap), ERROR);
        assert!(last_error(&seen).contains("nothing is freed"));
        // a pointer that was never a state: fmi2GetFMUstate does not write through it
        let mut junk = [0u64; 4];
        let mut foreign: Fmi2FmuState = junk.as_mut_ptr().cast();
        assert_eq!(api::set_fmu_state::<Toy>(c, foreign), ERROR);
        assert_eq!(api::get_fmu_state::<Toy>(c, &mut foreign), OK);
        assert_eq!(junk, [0; 4]);
        assert_ne!(foreign, junk.as_mut_ptr().cast());
        assert_eq!(api::set_fmu_state::<Toy>(c, foreign), OK);
        // the address form frees once and nulls the variable
        assert_eq!(api::free_fmu_state::<Toy>(c, &mut foreign), OK);
        assert!(foreign.is_null());
        assert_eq!(api::free_fmu_state::<Toy>(c, &mut foreign), OK);
        api::free_instance::<Toy>(c);
    }
}
