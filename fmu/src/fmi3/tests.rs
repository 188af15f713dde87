//! Tests of the FMI 3.0 layer through its instance, with the wheel–rail model: elements against FMI 2.0
//! instances of the same values on any number of threads, the structural parameter's rules, array
//! lengths, FMU states and their serialization, derivatives, the model description. (The layer knows no
//! model; its tests use this FMU's, whose FMI 2.0 instances are the reference.)

use super::description::{model_description, token};
use super::instance::{Instance, Snapshot};
use super::state::{Interface, State};
use crate::contact::WheelRailModel;
use crate::contact::model::{INPUTS, OUTPUTS};
use crate::contact::variables::*;
use crate::fmi2::ffi::Status;
use crate::fmi2::instance::{Failure, Instance as Instance2};
use crate::fmi2::logging::Logger;
use crate::fmi2::model::Model;
use crate::fmi2::variables::{Type, Value};

type Vehicle = Instance<WheelRailModel>;

/// Inputs of contact `k` at step `s`: creepages, spin, load, speed, wetness (exact mode, all converge).
fn inputs(k: usize, s: usize) -> [f64; 6] {
    let k = k as f64;
    [
        0.001 * (k + 1.0) + 0.0007 * s as f64,
        -0.0005 * k,
        0.1 * k,
        70e3 + 10e3 * k,
        20.0 + 2.0 * k,
        [0.0, 0.4, 1.0][k as usize % 3],
    ]
}

/// A Co-Simulation instance of `contacts` exact contacts on a 6 × 6 grid, initialized.
fn vehicle(contacts: u64, threads: u64) -> Vehicle {
    vehicle_on(contacts, threads, 6)
}

/// A grid on which a step of three exact contacts takes well over the least work that is shared between
/// threads (tens of µs per contact on 6 × 6, a few hundred on this grid).
const THREADED_GRID: i32 = 16;

/// A Co-Simulation instance of `contacts` exact contacts on a `grid` × `grid` grid, initialized.
fn vehicle_on(contacts: u64, threads: u64, grid: i32) -> Vehicle {
    let mut v = Vehicle::new(
        "v".into(),
        Interface::CoSimulation,
        Logger::new(None, false),
        None,
    );
    v.configuration_mode(true).unwrap();
    v.set_counts(&[CONTACTS_VR], &[contacts]).unwrap();
    v.configuration_mode(false).unwrap();
    v.set_counts(&[THREADS_VR], &[threads]).unwrap();
    v.set(&[GRID_SIZE as u32, MODE as u32], Type::Integer, 2, |k| {
        Ok(Value::Integer([grid, 2][k]))
    })
    .unwrap();
    v.enter_initialization_mode(0.0).unwrap();
    v.exit_initialization_mode().unwrap();
    v
}

fn vehicle_step(v: &mut Vehicle, s: usize) -> Vec<u64> {
    let n = v.size();
    let vrs = INPUTS.map(|i| i as u32);
    v.set(&vrs, Type::Real, 6 * n, |j| {
        Ok(Value::Real(inputs(j % n, s)[j / n]))
    })
    .unwrap();
    v.do_step(1e-3 * s as f64, 1e-3).unwrap();
    let mut out = vec![0; OUTPUTS.len() * n];
    v.get(&OUTPUTS.map(|i| i as u32), Type::Real, out.len(), |j, x| {
        let Value::Real(x) = x else { unreachable!() };
        out[j] = x.to_bits()
    })
    .unwrap();
    out
}

/// Three contacts of one instance equal three FMI 2.0 instances step by step (warm starts carried),
/// evaluated one after another, on two threads and on the cores (the first step measures the contacts'
/// times on the calling thread, the later ones are shared with the workers).
#[test]
fn contacts_equal_fmi2_instances_on_any_number_of_threads() {
    let mut singles: Vec<Instance2<WheelRailModel>> = (0..3)
        .map(|_| {
            let mut i = Instance2::new(
                "s".into(),
                Interface::CoSimulation,
                Logger::new(None, false),
                WheelRailModel::new(None),
            );
            i.set(&[GRID_SIZE as u32, MODE as u32], |k| {
                Ok(Value::Integer([THREADED_GRID, 2][k]))
            })
            .unwrap();
            i.enter_initialization_mode().unwrap();
            i.exit_initialization_mode().unwrap();
            i
        })
        .collect();
    let mut vehicles = [1, 2, 0].map(|threads| vehicle_on(3, threads, THREADED_GRID));
    for s in 0..6 {
        let mut want = vec![0; OUTPUTS.len() * 3];
        for (k, single) in singles.iter_mut().enumerate() {
            let vrs = INPUTS.map(|i| i as u32);
            single
                .set(&vrs, |j| Ok(Value::Real(inputs(k, s)[j])))
                .unwrap();
            single.do_step(1e-3 * s as f64, 1e-3).unwrap();
            for (i, o) in OUTPUTS.iter().enumerate() {
                want[i * 3 + k] = single.values().real(*o).to_bits();
            }
        }
        for v in &mut vehicles {
            assert_eq!(vehicle_step(v, s), want, "step {s}");
        }
    }
    assert!(!vehicles[0].has_shared());
    assert!(
        vehicles[1].has_shared(),
        "two threads: the steps were shared"
    );
    if std::thread::available_parallelism().is_ok_and(|n| n.get() > 1) {
        assert!(vehicles[2].has_shared(), "the cores: the steps were shared");
    }
}

/// `contacts` only in configuration mode and in its range; the array lengths of every call checked;
/// a non-finite element named by its index; nothing changed by a refused call.
#[test]
fn structural_parameter_and_array_lengths_are_checked() {
    let mut v = vehicle(2, 1);
    let refused = |r: Result<Status, Failure>, text: &str| match r {
        Err(Failure::Rejected(m)) => assert!(m.contains(text), "{m}"),
        other => panic!("{other:?}"),
    };
    refused(
        v.set_counts(&[CONTACTS_VR], &[3]),
        "may be set only in configuration mode",
    );
    refused(
        v.set(&[WETNESS as u32], Type::Real, 3, |_| Ok(Value::Real(0.5))),
        "nValues = 3, but the variables hold 2 values",
    );
    refused(
        v.set(&[NORMAL_FORCE as u32], Type::Real, 2, |k| {
            Ok(Value::Real([1e5, f64::NAN][k]))
        }),
        "normal_force[2] = NaN",
    );
    refused(
        v.set(&[BULK_TEMPERATURE as u32], Type::Real, 1, |_| {
            Ok(Value::Real(300.0))
        }),
        "fixed parameter",
    );
    assert_eq!(v.values(1).real(NORMAL_FORCE), 1e5);
    let mut n = [0];
    v.get_counts(&[CONTACTS_VR], &mut n).unwrap();
    assert_eq!(n, [2]);
    let mut fresh = Vehicle::new(
        "f".into(),
        Interface::ModelExchange,
        Logger::new(None, false),
        None,
    );
    fresh.configuration_mode(true).unwrap();
    refused(fresh.set_counts(&[CONTACTS_VR], &[0]), "allowed: 1 to");
    refused(
        fresh.set_counts(&[CONTACTS_VR], &[MAX_CONTACTS + 1]),
        "allowed: 1 to",
    );
    refused(
        fresh.set(&[WETNESS as u32], Type::Real, 1, |_| Ok(Value::Real(0.5))),
        "cannot be set in state ConfigurationMode",
    );
    // shared parameters are kept, array values start again
    fresh.set_counts(&[CONTACTS_VR], &[4]).unwrap();
    assert_eq!(fresh.size(), 4);
    assert_eq!(fresh.state, State::ConfigurationMode);
}

/// An FMU state serialized and read back continues bit for bit, in an instance of another size; every
/// corruption is refused.
#[test]
fn fmu_states_round_trip_and_corruption_is_refused() {
    let mut a = vehicle(3, 2);
    vehicle_step(&mut a, 0);
    let token = token(&INFO, &ARRAYS);
    let bytes = a.snapshot().to_bytes(&token);
    let back = Snapshot::from_bytes(&bytes, &token, &VARIABLES, &ARRAYS).unwrap();
    assert_eq!(back, a.snapshot());
    let mut b = vehicle(1, 1);
    b.restore(&back).unwrap();
    assert_eq!(b.size(), 3);
    for s in 1..3 {
        assert_eq!(vehicle_step(&mut b, s), vehicle_step(&mut a, s), "step {s}");
    }
    for i in (0..bytes.len()).step_by(97) {
        let mut c = bytes.clone();
        c[i] ^= 0x10;
        assert!(
            Snapshot::<<WheelRailModel as Model>::State>::from_bytes(
                &c, &token, &VARIABLES, &ARRAYS
            )
            .is_err()
        );
    }
    assert!(
        Snapshot::<<WheelRailModel as Model>::State>::from_bytes(
            &bytes, "{other}", &VARIABLES, &ARRAYS
        )
        .unwrap_err()
        .contains("another FMU")
    );
}

/// J·v per contact, zero across contacts; the adjoint's Jᵀ·w satisfies ⟨w, J·v⟩ = ⟨Jᵀ·w, v⟩.
#[test]
fn derivatives_are_block_diagonal_and_the_adjoint_is_the_transpose() {
    let mut v = vehicle(2, 1);
    vehicle_step(&mut v, 0);
    let unknowns = [FORCE_LONGITUDINAL as u32, FORCE_LATERAL as u32];
    let knowns = [CREEPAGE_LONGITUDINAL as u32, CREEPAGE_LATERAL as u32];
    // only contact 2's longitudinal creepage
    let seed = [0.0, 1.0, 0.0, 0.0];
    let d = v.derivative(&unknowns, &knowns, &seed, 4, false).unwrap();
    assert_eq!(
        (d[0], d[2]),
        (0.0, 0.0),
        "contact 1 does not depend on contact 2"
    );
    assert!(d[1] < 0.0, "F_x falls with ξ (Kalker's convention): {d:?}");
    let w = [0.3, -1.0, 2.0, 0.5];
    let v_seed = [1.0, -0.5, 0.25, 2.0];
    let jv = v.derivative(&unknowns, &knowns, &v_seed, 4, false).unwrap();
    let jtw = v.derivative(&unknowns, &knowns, &w, 4, true).unwrap();
    let lhs: f64 = w.iter().zip(&jv).map(|(a, b)| a * b).sum();
    let rhs: f64 = jtw.iter().zip(&v_seed).map(|(a, b)| a * b).sum();
    // by the exact solver a derivative is one forward difference along the seed direction, linear in the
    // seed to within the relative step (the adjoint sums differences along each known)
    let step = crate::contact::model::DERIVATIVE_STEP;
    assert!((lhs - rhs).abs() <= step * lhs.abs(), "{lhs} {rhs}");
    assert!(v.derivative(&unknowns, &knowns, &seed, 3, false).is_err());
}

/// Every input, output and `roughness` is an array over `contacts`; the other parameters are scalars; the
/// token follows the document.
#[test]
fn the_model_description_dimensions_the_arrays() {
    let x = model_description(&INFO, &ARRAYS);
    let arrays = VARIABLES
        .iter()
        .filter(|v| v.causality != crate::fmi2::variables::Causality::Parameter)
        .count()
        + 1;
    assert_eq!(
        x.matches(&format!("<Dimension valueReference=\"{CONTACTS_VR}\"/>"))
            .count(),
        arrays
    );
    assert!(x.contains("causality=\"structuralParameter\" variability=\"fixed\""));
    assert!(x.contains("fmiVersion=\"3.0\"") && x.contains("causality=\"independent\""));
    assert!(x.contains(&format!("instantiationToken=\"{}\"", token(&INFO, &ARRAYS))));
    let mut other = ARRAYS;
    other.element_parameters = &[];
    assert_ne!(token(&INFO, &ARRAYS), token(&INFO, &other));
}

/// The FMI 2.0 fuzzer's ideas at a small budget, through the exported C functions: random call sequences
/// (legal and illegal, in both interface types), array lengths right and wrong, NaN and infinite inputs,
/// `contacts` in and out of configuration mode, FMU states taken and set. Every call returns OK, Warning or
/// Error; no call panics (a caught panic logs "internal error"); `contacts` changes only by a valid value
/// in configuration mode (or a reset, or a restored state); a refused set leaves the values as they were.
#[test]
fn random_call_sequences_keep_the_invariants() {
    use crate::exports_fmi3::*;
    use std::ffi::{CString, c_char, c_void};
    use std::ptr::{null, null_mut};
    use std::sync::atomic::{AtomicUsize, Ordering};
    static PANICS: AtomicUsize = AtomicUsize::new(0);
    unsafe extern "C" fn log(_: *mut c_void, _: i32, _: *const c_char, message: *const c_char) {
        let m = unsafe { std::ffi::CStr::from_ptr(message) }.to_string_lossy();
        if m.contains("internal error") {
            PANICS.fetch_add(1, Ordering::Relaxed);
        }
    }
    /// Sequences and calls per sequence.
    const SEQUENCES: usize = 100;
    const CALLS: usize = 40;
    let token = CString::new(token(&INFO, &ARRAYS)).unwrap();
    let table = CString::new(concat!(env!("CARGO_MANIFEST_DIR"), "/resources/table")).unwrap();
    let mut seed: u64 = 16;
    let mut next = |n: u64| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 33) % n
    };
    let contacts_of = |fmu| {
        let mut n = 0u64;
        assert_eq!(unsafe { fmi3GetUInt64(fmu, &CONTACTS_VR, 1, &mut n, 1) }, 0);
        n
    };
    // an instance that holds the bundled table for the whole test (the process shares a loaded table
    // while an instance uses it; each sequence would load it again)
    let path = Value::String(table.to_str().unwrap().into());
    let mut holder = Vehicle::new(
        "t".into(),
        Interface::CoSimulation,
        Logger::new(None, false),
        None,
    );
    holder
        .set(&[TABLE_FILE as u32], Type::String, 1, |_| Ok(path.clone()))
        .unwrap();
    holder
        .set(&[MODE as u32], Type::Integer, 1, |_| Ok(Value::Integer(1)))
        .unwrap();
    holder.enter_initialization_mode(0.0).unwrap();
    holder.exit_initialization_mode().unwrap();
    for _ in 0..SEQUENCES {
        let me = next(2) == 0;
        let fmu = unsafe {
            match me {
                true => fmi3InstantiateModelExchange(
                    c"fuzz".as_ptr(),
                    token.as_ptr(),
                    null(),
                    false,
                    false,
                    null_mut(),
                    Some(log),
                ),
                false => fmi3InstantiateCoSimulation(
                    c"fuzz".as_ptr(),
                    token.as_ptr(),
                    null(),
                    false,
                    false,
                    next(2) == 0,
                    false,
                    null(),
                    0,
                    null_mut(),
                    Some(log),
                    None,
                ),
            }
        };
        assert!(!fmu.is_null());
        let (mode, table_vr) = (1i32, TABLE_FILE as u32);
        unsafe {
            assert_eq!(fmi3SetInt32(fmu, &(MODE as u32), 1, &mode, 1), 0);
            assert_eq!(fmi3SetString(fmu, &table_vr, 1, &table.as_ptr(), 1), 0);
        }
        let mut expected = 1u64;
        let mut in_configuration = false;
        let mut states = Vec::new();
        for _ in 0..CALLS {
            let n = contacts_of(fmu) as usize;
            assert_eq!(n as u64, expected);
            let status = unsafe {
                match next(15) {
                    0 => {
                        let s = fmi3EnterConfigurationMode(fmu);
                        in_configuration |= s == 0;
                        s
                    }
                    1 => {
                        let s = fmi3ExitConfigurationMode(fmu);
                        in_configuration &= s != 0;
                        s
                    }
                    2 => {
                        let want = next(7);
                        let s = fmi3SetUInt64(fmu, &CONTACTS_VR, 1, &want, 1);
                        let valid = in_configuration && want >= 1;
                        assert_eq!(s == 0, valid, "contacts {want}");
                        if valid {
                            expected = want;
                        }
                        s
                    }
                    3 => fmi3SetUInt64(fmu, &THREADS_VR, 1, &next(3), 1),
                    4 => fmi3EnterInitializationMode(fmu, false, 0.0, 0.0, false, 0.0),
                    5 => fmi3ExitInitializationMode(fmu),
                    6 | 7 => {
                        // an array of the right length or one off; finite, NaN or infinite
                        let len = match next(3) {
                            0 => n + 1,
                            _ => n,
                        };
                        let x = [0.003, f64::NAN, f64::INFINITY][next(3) as usize];
                        let values = vec![x; len];
                        let vr = CREEPAGE_LONGITUDINAL as u32;
                        let mut before = vec![0.0; n];
                        fmi3GetFloat64(fmu, &vr, 1, before.as_mut_ptr(), n);
                        let s = fmi3SetFloat64(fmu, &vr, 1, values.as_ptr(), len);
                        if len != n || !x.is_finite() {
                            assert_eq!(s, 3);
                            let mut after = vec![0.0; n];
                            fmi3GetFloat64(fmu, &vr, 1, after.as_mut_ptr(), n);
                            assert_eq!(before, after, "a refused set changed the values");
                        }
                        s
                    }
                    8 => {
                        let len = n + next(2) as usize;
                        let mut out = vec![0.0; len];
                        let vr = FORCE_LONGITUDINAL as u32;
                        let s = fmi3GetFloat64(fmu, &vr, 1, out.as_mut_ptr(), len);
                        if len != n {
                            assert_eq!(s, 3);
                        }
                        s
                    }
                    9 => {
                        let (mut a, mut b, mut c, mut t) = (false, false, false, 0.0);
                        let step = [1e-3, -1.0][next(2) as usize];
                        fmi3DoStep(fmu, 0.0, step, true, &mut a, &mut b, &mut c, &mut t)
                    }
                    10 => match next(4) {
                        0 => fmi3EnterEventMode(fmu),
                        1 => fmi3EnterStepMode(fmu),
                        2 => fmi3EnterContinuousTimeMode(fmu),
                        _ => {
                            let (mut a, mut b) = (false, false);
                            fmi3CompletedIntegratorStep(fmu, true, &mut a, &mut b)
                        }
                    },
                    11 => {
                        let mut s = null_mut();
                        let r = fmi3GetFMUState(fmu, &mut s);
                        if r == 0 {
                            states.push((s, contacts_of(fmu), in_configuration));
                        }
                        r
                    }
                    12 => match states.last() {
                        Some(&(s, k, configuring)) => {
                            let r = fmi3SetFMUState(fmu, s);
                            if r == 0 {
                                expected = k;
                                in_configuration = configuring;
                            }
                            r
                        }
                        None => fmi3SetFMUState(fmu, null_mut()),
                    },
                    13 => {
                        let r = fmi3Reset(fmu);
                        expected = 1;
                        in_configuration = false;
                        fmi3SetInt32(fmu, &(MODE as u32), 1, &mode, 1);
                        fmi3SetString(fmu, &table_vr, 1, &table.as_ptr(), 1);
                        r
                    }
                    _ => fmi3Terminate(fmu),
                }
            };
            assert!(matches!(status, 0 | 1 | 3), "status {status}");
        }
        for (mut s, _, _) in states {
            assert_eq!(unsafe { fmi3FreeFMUState(fmu, &mut s) }, 0);
        }
        unsafe { fmi3FreeInstance(fmu) };
    }
    holder.terminate().unwrap();
    assert_eq!(PANICS.load(Ordering::Relaxed), 0, "a call panicked");
}
