//! The FMU's Model Exchange interface, driven through the C functions as an integrator would: the ME
//! state machine, outputs equal to those of Co-Simulation at the same inputs, repeatable evaluations
//! within an integrator step, exact restores between an evaluation and its acceptance, derivatives, and
//! the refusal of illegal calls and of the other interface type's functions.

use super::*;

/// The Model Exchange functions (fmi2Functions.h), all exported by the one binary.
const ME_FUNCTIONS: [&str; 10] = [
    "fmi2SetTime",
    "fmi2SetContinuousStates",
    "fmi2EnterEventMode",
    "fmi2NewDiscreteStates",
    "fmi2EnterContinuousTimeMode",
    "fmi2CompletedIntegratorStep",
    "fmi2GetDerivatives",
    "fmi2GetEventIndicators",
    "fmi2GetContinuousStates",
    "fmi2GetNominalsOfContinuousStates",
];

/// `fmi2EventInfo`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
struct EventInfo {
    new_discrete_states_needed: c_int,
    terminate_simulation: c_int,
    nominals_changed: c_int,
    values_changed: c_int,
    next_event_time_defined: c_int,
    next_event_time: f64,
}

#[allow(clippy::type_complexity)]
struct Me {
    set_time: unsafe extern "C" fn(Comp, f64) -> c_int,
    set_continuous_states: unsafe extern "C" fn(Comp, *const f64, usize) -> c_int,
    enter_event_mode: unsafe extern "C" fn(Comp) -> c_int,
    new_discrete_states: unsafe extern "C" fn(Comp, *mut EventInfo) -> c_int,
    enter_continuous_time_mode: unsafe extern "C" fn(Comp) -> c_int,
    completed_integrator_step: unsafe extern "C" fn(Comp, c_int, *mut c_int, *mut c_int) -> c_int,
    get_derivatives: unsafe extern "C" fn(Comp, *mut f64, usize) -> c_int,
    get_event_indicators: unsafe extern "C" fn(Comp, *mut f64, usize) -> c_int,
    get_nominals: unsafe extern "C" fn(Comp, *mut f64, usize) -> c_int,
}

fn me() -> &'static Me {
    static ME: OnceLock<Me> = OnceLock::new();
    ME.get_or_init(|| {
        fn sym<T: Copy>(name: &str) -> T {
            unsafe {
                *library()
                    .get::<T>(name)
                    .unwrap_or_else(|e| panic!("{name}: {e}"))
            }
        }
        Me {
            set_time: sym("fmi2SetTime"),
            set_continuous_states: sym("fmi2SetContinuousStates"),
            enter_event_mode: sym("fmi2EnterEventMode"),
            new_discrete_states: sym("fmi2NewDiscreteStates"),
            enter_continuous_time_mode: sym("fmi2EnterContinuousTimeMode"),
            completed_integrator_step: sym("fmi2CompletedIntegratorStep"),
            get_derivatives: sym("fmi2GetDerivatives"),
            get_event_indicators: sym("fmi2GetEventIndicators"),
            get_nominals: sym("fmi2GetNominalsOfContinuousStates"),
        }
    })
}

/// The bundled table as the value of `table_file`.
fn bundled_table() -> CString {
    CString::new(root().join("fmu/resources/table").to_str().unwrap()).unwrap()
}

/// An instance of `fmu_type` (0 ME, 1 CS) in `mode` (1: the bundled table; else the test grid), with
/// `warm_start`, initialized; an ME instance is then in continuous-time mode, as after the event
/// iteration of an integrator's start.
fn started(name: &str, fmu_type: c_int, mode: i32, warm: bool) -> Fmu {
    let f = Fmu::instantiate(name, None, fmu_type);
    assert_eq!(f.set_int("mode", mode), OK);
    assert_eq!(f.set_bool("warm_start", warm), OK);
    if mode == 1 {
        let table = bundled_table();
        assert_eq!(
            unsafe { (fmi().set_string)(f.c, &vr("table_file"), 1, &table.as_ptr()) },
            OK
        );
    } else {
        assert_eq!(f.set_int("grid_size", GRID), OK);
    }
    unsafe {
        assert_eq!((fmi().setup_experiment)(f.c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!((fmi().enter_initialization_mode)(f.c), OK);
        assert!(
            (fmi().exit_initialization_mode)(f.c) <= WARNING,
            "{:?}",
            f.errors()
        );
        if fmu_type == 0 {
            let mut info = EventInfo {
                new_discrete_states_needed: 1,
                terminate_simulation: 1,
                nominals_changed: 1,
                values_changed: 1,
                next_event_time_defined: 1,
                next_event_time: -1.0,
            };
            assert_eq!((me().new_discrete_states)(f.c, &mut info), OK);
            assert_eq!(
                (
                    info.new_discrete_states_needed,
                    info.terminate_simulation,
                    info.next_event_time_defined
                ),
                (0, 0, 0)
            );
            assert!((me().enter_continuous_time_mode)(f.c) <= WARNING);
        }
    }
    f
}

impl Fmu {
    /// `fmi2CompletedIntegratorStep`, checking that the FMU asks for neither an event nor termination.
    fn completed_step(&self) -> c_int {
        let (mut event, mut terminate) = (-1, -1);
        let s = unsafe { (me().completed_integrator_step)(self.c, 1, &mut event, &mut terminate) };
        if s <= WARNING {
            assert_eq!((event, terminate), (0, 0));
        }
        s
    }
}

/// Operating points through stick and slip, dry and wet (ξ, η, F_N, V, w).
const POINTS: [[f64; 5]; 5] = [
    [0.001, 0.0, 100e3, 30.0, 0.0],
    [0.004, 0.001, 90e3, 28.0, 0.2],
    [0.012, -0.002, 110e3, 25.0, 0.6],
    [0.03, 0.003, 80e3, 20.0, 1.0],
    [0.002, 0.0, 120e3, 32.0, 0.0],
];

#[test]
fn exports_every_fmi2_model_exchange_function() {
    for name in ME_FUNCTIONS {
        assert!(
            unsafe { library().get::<*const c_void>(name) }.is_ok(),
            "{name} is not exported"
        );
    }
    let xml =
        std::fs::read_to_string(root().join("modelDescription/modelDescription.xml")).unwrap();
    assert!(xml.contains("<ModelExchange modelIdentifier=\"WheelRailFriction\""));
    assert!(xml.contains("<CoSimulation modelIdentifier=\"WheelRailFriction\""));
}

/// An integrator's sequence (set time and inputs, read outputs, complete the step) gives the outputs a
/// co-simulation step gives at the same inputs: bit for bit by the table and by cold exact solves; with
/// the warm start, within the solver tolerance (1e-6 relative change per iteration): the warm starts
/// differ, since Model Exchange accepts the start point twice (initialization, then continuous-time mode).
#[test]
fn model_exchange_outputs_are_those_of_co_simulation_at_the_same_inputs() {
    for (mode, warm, rtol) in [(1, true, 0.0), (2, false, 0.0), (2, true, 1e-6)] {
        let m = started("me", 0, mode, warm);
        let c = started("cs", 1, mode, warm);
        for (k, point) in POINTS.into_iter().enumerate() {
            let t = 1e-3 * (k + 1) as f64;
            assert_eq!(unsafe { (me().set_time)(m.c, t) }, OK);
            m.set_inputs(point);
            let (me_out, me_mode) = m.outputs();
            assert!(m.completed_step() <= WARNING);
            assert!(c.step_at(t, point) <= WARNING);
            let (cs_out, cs_mode) = c.outputs();
            assert_eq!(me_mode, cs_mode);
            assert_eq!(me_mode, if mode == 1 { 1 } else { 2 });
            for ((a, b), name) in me_out.iter().zip(&cs_out).zip(REAL_OUTPUTS) {
                assert!(
                    (a - b).abs() <= rtol * b.abs(),
                    "mode {mode}, warm {warm}, point {k}: {name} {a} (ME) vs {b} (CS)"
                );
            }
            assert_eq!(m.get_bool("converged"), c.get_bool("converged"));
        }
        assert!(m.errors().is_empty(), "{:?}", m.errors());
    }
}

/// Within one integrator step the outputs are a function of the inputs (an implicit integrator's Newton
/// iteration revisits points): the warm start advances only when the step is completed, and an FMU state
/// taken between an evaluation and its acceptance continues bit for bit, in this and a fresh instance.
#[test]
fn evaluations_within_a_step_are_repeatable_and_the_warm_start_advances_at_completion() {
    let m = started("newton", 0, 2, true);
    let c = started("cs", 1, 2, true);
    let [u1, u2, u3] = [POINTS[1], POINTS[2], POINTS[3]];
    m.set_inputs(u1);
    let first = m.outputs();
    m.set_inputs(u2);
    let other = m.outputs();
    m.set_inputs(u1);
    assert_eq!(m.outputs(), first, "u1 after u2 within the step");
    m.set_inputs(u2);
    assert_eq!(m.outputs(), other, "u2 again within the step");
    // in co-simulation each step's solve starts from the previous one, so revisiting differs in general;
    // both agree within the solver tolerance
    c.set_inputs(u1);
    assert!(c.step(0.0) <= WARNING);
    c.set_inputs(u2);
    assert!(c.step(1e-3) <= WARNING);
    for (a, b) in other.0.iter().zip(c.outputs().0) {
        assert!((a - b).abs() <= 1e-6 * b.abs(), "{a} vs {b}");
    }
    // a state taken after an evaluation and before its acceptance
    let bytes = m.serialized_state();
    let fresh = Fmu::instantiate("fresh", None, 0);
    fresh.restore_from(&bytes);
    for f in [&m, &fresh] {
        assert!(f.completed_step() <= WARNING);
        f.set_inputs(u3);
    }
    assert_eq!(fresh.outputs(), m.outputs());
    // and back in the same instance
    m.restore_from(&bytes);
    assert!(m.completed_step() <= WARNING);
    m.set_inputs(u3);
    assert_eq!(m.outputs(), fresh.outputs());
}

/// Directional derivatives (the integrator's Jacobian of the algebraic outputs) in continuous-time mode
/// are those of Co-Simulation at the same point: bit for bit by the table and by cold solves.
#[test]
fn model_exchange_derivatives_are_those_of_co_simulation() {
    let unknown = [
        vr("force_longitudinal"),
        vr("force_lateral"),
        vr("spin_moment"),
    ];
    let known = [
        vr("creepage_longitudinal"),
        vr("creepage_lateral"),
        vr("normal_force"),
    ];
    for mode in [1, 2] {
        let m = started("me", 0, mode, false);
        let c = started("cs", 1, mode, false);
        m.set_inputs(POINTS[1]);
        c.set_inputs(POINTS[1]);
        assert!(c.step(0.0) <= WARNING);
        for seed in [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.5, 1e3],
        ] {
            let (mut dm, mut dc) = ([0.0; 3], [0.0; 3]);
            assert_eq!(m.derivative(&unknown, &known, &seed, &mut dm), OK);
            assert_eq!(c.derivative(&unknown, &known, &seed, &mut dc), OK);
            assert_eq!(dm, dc, "mode {mode}, seed {seed:?}");
        }
        // Kalker's sign convention: the longitudinal force opposes the creepage
        let mut d = [0.0];
        assert_eq!(m.derivative(&unknown[..1], &known[..1], &[1.0], &mut d), OK);
        assert!(d[0] < 0.0, "mode {mode}: dF_x/dxi = {}", d[0]);
    }
}

#[test]
fn illegal_model_exchange_calls_are_errors_with_a_log_line() {
    let f = Fmu::instantiate("illegal", None, 0);
    let mut x = [0.0];
    unsafe {
        assert_eq!((me().set_time)(f.c, 0.0), ERROR);
        assert!(
            f.last_error().contains(
                "fmi2SetTime: Illegal call sequence (the instance is in state Instantiated)"
            ),
            "{:?}",
            f.errors()
        );
        assert_eq!((me().get_nominals)(f.c, null_mut(), 0), OK);
    }
    f.init();
    unsafe {
        // in event mode after initialization
        assert_eq!(f.completed_step(), ERROR);
        assert!(
            f.last_error()
                .contains("fmi2CompletedIntegratorStep: Illegal call sequence")
        );
        assert_eq!((me().set_continuous_states)(f.c, x.as_ptr(), 0), ERROR);
        // Co-Simulation functions belong to the other interface type
        assert_eq!(f.step(0.0), ERROR);
        assert!(
            f.last_error()
                .contains("fmi2DoStep: Illegal call sequence (not a function of Model Exchange"),
            "{:?}",
            f.errors()
        );
        let mut s = 0;
        assert_eq!((fmi().get_status)(f.c, 0, &mut s), ERROR);
        assert_eq!((fmi().cancel_step)(f.c), ERROR);
        assert_eq!((me().enter_continuous_time_mode)(f.c), OK);
        assert_eq!((me().enter_continuous_time_mode)(f.c), ERROR);
        let mut info = std::mem::zeroed::<EventInfo>();
        assert_eq!((me().new_discrete_states)(f.c, &mut info), ERROR);
        assert_eq!((fmi().enter_initialization_mode)(f.c), ERROR);
        // no continuous states, no event indicators
        assert_eq!((me().get_derivatives)(f.c, x.as_mut_ptr(), 0), OK);
        assert_eq!((me().get_derivatives)(f.c, x.as_mut_ptr(), 1), ERROR);
        assert!(f.last_error().contains(
            "fmi2GetDerivatives: this FMU has no continuous states, but the call passes 1"
        ));
        assert_eq!((me().get_event_indicators)(f.c, x.as_mut_ptr(), 1), ERROR);
        assert!(f.last_error().contains("no event indicators"));
        assert_eq!((me().set_continuous_states)(f.c, x.as_ptr(), 1), ERROR);
        assert_eq!((me().set_time)(f.c, f64::INFINITY), ERROR);
        assert!(f.last_error().contains("time inf is not finite"));
        let mut event = 0;
        assert_eq!(
            (me().completed_integrator_step)(f.c, 1, &mut event, null_mut()),
            ERROR
        );
        assert!(
            f.last_error()
                .contains("terminateSimulation is a null pointer")
        );
        // a Co-Simulation instance's state at a communication point does not fit
        let cs = Fmu::new("cs", None);
        cs.init();
        let bytes = cs.serialized_state();
        let mut state: *mut c_void = null_mut();
        assert_eq!(
            (fmi().deserialize)(f.c, bytes.as_ptr(), bytes.len(), &mut state),
            OK
        );
        assert_eq!((fmi().set_fmu_state)(f.c, state), ERROR);
        assert!(f.last_error().contains("taken in state StepComplete"));
        assert_eq!((fmi().free_fmu_state)(f.c, &mut state), OK);
        // Model Exchange functions in the Co-Simulation instance
        assert_eq!((me().set_time)(cs.c, 0.0), ERROR);
        assert!(cs.last_error().contains("not a function of Co-Simulation"));
        assert_eq!((me().enter_event_mode)(cs.c), ERROR);
        // everything above left the instance usable: an event, then termination
        assert_eq!((me().enter_event_mode)(f.c), OK);
        assert_eq!(f.set("creepage_longitudinal", 0.003), OK);
        assert!(f.get("force_longitudinal") < 0.0);
        assert_eq!((fmi().terminate)(f.c), OK);
        assert_eq!((me().enter_event_mode)(f.c), ERROR);
    }
}
