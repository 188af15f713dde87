//! One vehicle of [`CONTACTS`] wheel–rail contacts along the MBS trace (target/mbs_trace.csv, `make bench`
//! writes it; another file: environment variable `WHEELRAIL_TRACE`): contact k reads the trace shifted by
//! k/[`CONTACTS`] of its length (the contacts phase-shifted), `mode` 0 (auto: the bundled table where it
//! serves, the exact solver on the grid per contact elsewhere, as the trace's geometry asks), warm start
//! on. Every vehicle step through the exported C functions: set every contact's inputs, step, read the
//! forces, the maximum temperature and `evaluation_mode` (all timed, as a master pays them), by
//!
//! - eight FMI 2.0 instances stepped one after another on this thread (`fmi2SetReal`, `fmi2DoStep`,
//!   `fmi2GetReal`, `fmi2GetInteger` per contact);
//! - one FMI 3.0 instance of eight contacts (`fmi3SetFloat64` of the arrays, `fmi3DoStep`,
//!   `fmi3GetFloat64`, `fmi3GetInt32`) with `threads` 1 and 2.
//!
//! The three runs of [`ROUNDS`] alternate (a shared machine's load changes between runs); each round
//! starts fresh instances. Per run: the time per vehicle step (median over the rounds of the round's mean;
//! min) and the CPU time of the process per step, the speed-up of each over the FMI 2.0 instances, the
//! share of contact steps the exact solver evaluated, and each contact's time per step (by the FMI 2.0
//! instances; the slowest contact bounds what two threads can gain, since a step waits for all). Every output of every step must be bit for bit the same in all three (else the bench fails).
//! [`STEPS`] vehicle steps (environment variable `WHEELRAIL_VEHICLE_STEPS`) from the trace's start. Run
//! with `cargo bench -p wheelrail-fmu --bench vehicle`.

use WheelRailFriction::contact::variables::*;
use WheelRailFriction::exports::*;
use WheelRailFriction::exports_fmi3::*;
use WheelRailFriction::fmi2::variables::Causality;
use WheelRailFriction::fmi3::ffi::Fmi3Instance;
use std::ffi::CString;
use std::path::PathBuf;
use std::ptr::{null, null_mut};
use std::time::Instant;

mod common;
use common::{Setup, instance, process_cpu_ns};

/// The contacts of a vehicle (two bogies of two wheelsets, one contact per wheel).
const CONTACTS: usize = 8;
/// Vehicle steps per run.
const STEPS: usize = 200;
/// Alternating rounds of the three runs.
const ROUNDS: usize = 3;
/// The bundled table (`table_file`).
const TABLE: &std::ffi::CStr = match std::ffi::CStr::from_bytes_with_nul(
    concat!(env!("CARGO_MANIFEST_DIR"), "/resources/table\0").as_bytes(),
) {
    Ok(t) => t,
    Err(_) => panic!("a C string"),
};
/// The outputs read each step (Float64).
const READ: [usize; 3] = [FORCE_LONGITUDINAL, FORCE_LATERAL, MAX_TEMPERATURE];

/// The trace's input columns (value references) and rows.
struct Trace {
    vrs: Vec<u32>,
    rows: Vec<Vec<f64>>,
    step: f64,
}

fn load() -> Trace {
    let path = std::env::var_os("WHEELRAIL_TRACE").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/mbs_trace.csv"),
        PathBuf::from,
    );
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
        panic!(
            "{}: {e}; write it with `python3 tools/mbs_trace.py` (`make bench` does)",
            path.display()
        )
    });
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let vrs = header[1..]
        .iter()
        .map(|n| {
            let v = VARIABLES
                .iter()
                .find(|v| v.name == *n)
                .unwrap_or_else(|| panic!("column {n} is no FMU variable"));
            assert_eq!(v.causality, Causality::Input, "column {n}");
            v.vr
        })
        .collect();
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().expect("a number")).collect())
        .collect();
    let step = rows[1][0] - rows[0][0];
    let rows = rows.into_iter().map(|r| r[1..].to_vec()).collect();
    Trace { vrs, rows, step }
}

/// The inputs of contact `k` at vehicle step `i`: the trace row shifted by k/CONTACTS of its length.
fn row(t: &Trace, k: usize, i: usize) -> &[f64] {
    &t.rows[(i + k * t.rows.len() / CONTACTS) % t.rows.len()]
}

/// Seconds per vehicle step: wall time, and the CPU time of all the process's threads.
#[derive(Debug, Clone, Copy)]
struct Timing {
    wall: f64,
    cpu: f64,
}

/// The start of a timed run.
struct Clock {
    wall: Instant,
    cpu: f64,
}

impl Clock {
    fn start() -> Clock {
        Clock {
            wall: Instant::now(),
            cpu: process_cpu_ns(),
        }
    }

    fn per_step(&self, steps: usize) -> Timing {
        Timing {
            wall: self.wall.elapsed().as_secs_f64() / steps as f64,
            cpu: (process_cpu_ns() - self.cpu) * 1e-9 / steps as f64,
        }
    }
}

/// What a run read: per vehicle step and contact the outputs' bits and `evaluation_mode`.
type Record = Vec<[u64; 4]>;

/// Eight FMI 2.0 instances stepped in turn: the time per vehicle step, the record, and each contact's
/// mean time per step [s] (the slowest contact bounds what threads can gain).
fn fmi2_run(t: &Trace, steps: usize) -> (Timing, Record, Vec<f64>) {
    let setup = Setup {
        mode: 0,
        grid: AUTOMATIC_GRID_SIZE,
        table: Some(TABLE),
        wetness: 0.0,
        warm: true,
    };
    let fmus: Vec<_> = (0..CONTACTS).map(|_| unsafe { instance(&setup) }).collect();
    let read: Vec<u32> = READ.iter().map(|i| *i as u32).collect();
    let mut record = Vec::with_capacity(steps * CONTACTS);
    let mut per_contact = vec![0.0; CONTACTS];
    let start = Clock::start();
    for i in 0..steps {
        for (k, fmu) in fmus.iter().enumerate() {
            let contact = Instant::now();
            let inputs = row(t, k, i);
            let (mut out, mut mode) = ([0.0; 3], 0);
            unsafe {
                assert!(fmi2SetReal(*fmu, t.vrs.as_ptr(), t.vrs.len(), inputs.as_ptr()) <= 1);
                assert!(fmi2DoStep(*fmu, i as f64 * t.step, t.step, 1) <= 1);
                assert!(fmi2GetReal(*fmu, read.as_ptr(), 3, out.as_mut_ptr()) <= 1);
                assert!(fmi2GetInteger(*fmu, &(EVALUATION_MODE as u32), 1, &mut mode) <= 1);
            }
            record.push([
                out[0].to_bits(),
                out[1].to_bits(),
                out[2].to_bits(),
                mode as u64,
            ]);
            per_contact[k] += contact.elapsed().as_secs_f64() / steps as f64;
        }
    }
    let seconds = start.per_step(steps);
    for fmu in fmus {
        unsafe { fmi2FreeInstance(fmu) };
    }
    (seconds, record, per_contact)
}

/// One FMI 3.0 instance of eight contacts on `threads` threads (mode 0, grid automatic, warm start on).
unsafe fn fmi3_instance(threads: u64) -> Fmi3Instance {
    let token = CString::new(WheelRailFriction::fmi3::description::token(&INFO, &ARRAYS)).unwrap();
    unsafe {
        let fmu = fmi3InstantiateCoSimulation(
            c"vehicle".as_ptr(),
            token.as_ptr(),
            null(),
            false,
            false,
            false,
            false,
            null(),
            0,
            null_mut(),
            None,
            None,
        );
        assert!(!fmu.is_null());
        assert_eq!(fmi3EnterConfigurationMode(fmu), 0);
        assert_eq!(
            fmi3SetUInt64(fmu, &CONTACTS_VR, 1, &(CONTACTS as u64), 1),
            0
        );
        assert_eq!(fmi3ExitConfigurationMode(fmu), 0);
        assert_eq!(fmi3SetUInt64(fmu, &THREADS_VR, 1, &threads, 1), 0);
        let table = TABLE.as_ptr();
        assert_eq!(fmi3SetString(fmu, &(TABLE_FILE as u32), 1, &table, 1), 0);
        assert_eq!(
            fmi3EnterInitializationMode(fmu, false, 0.0, 0.0, false, 0.0),
            0
        );
        assert_eq!(fmi3ExitInitializationMode(fmu), 0);
        fmu
    }
}

/// `vehicles` FMI 3.0 instances of eight contacts on `threads` threads each, stepped in turn with the same
/// inputs: the time per vehicle step and the record (every vehicle's outputs must be the first's).
fn fmi3_run(t: &Trace, steps: usize, threads: u64, vehicles: usize) -> (Timing, Record) {
    let fmus: Vec<_> = (0..vehicles)
        .map(|_| unsafe { fmi3_instance(threads) })
        .collect();
    let read: Vec<u32> = READ.iter().map(|i| *i as u32).collect();
    // the inputs as the arrays are serialised: per variable, its value of each contact
    let n = t.vrs.len();
    let mut inputs = vec![0.0; n * CONTACTS];
    let mut out = vec![0.0; READ.len() * CONTACTS];
    let mut modes = vec![0i32; CONTACTS];
    let mut record = Vec::with_capacity(steps * CONTACTS);
    let (mut flags, mut last) = ([false; 3], 0.0);
    let start = Clock::start();
    for i in 0..steps {
        for k in 0..CONTACTS {
            for (j, x) in row(t, k, i).iter().enumerate() {
                inputs[j * CONTACTS + k] = *x;
            }
        }
        for (v, fmu) in fmus.iter().enumerate() {
            unsafe {
                assert!(
                    fmi3SetFloat64(*fmu, t.vrs.as_ptr(), n, inputs.as_ptr(), inputs.len()) <= 1
                );
                let [a, b, c] = &mut flags;
                assert!(fmi3DoStep(*fmu, i as f64 * t.step, t.step, true, a, b, c, &mut last) <= 1);
                assert!(fmi3GetFloat64(*fmu, read.as_ptr(), 3, out.as_mut_ptr(), out.len()) <= 1);
                let vr = EVALUATION_MODE as u32;
                assert!(fmi3GetInt32(*fmu, &vr, 1, modes.as_mut_ptr(), CONTACTS) <= 1);
            }
            for k in 0..CONTACTS {
                let r = [
                    out[k].to_bits(),
                    out[CONTACTS + k].to_bits(),
                    out[2 * CONTACTS + k].to_bits(),
                    modes[k] as u64,
                ];
                match v {
                    0 => record.push(r),
                    _ => assert!(record[i * CONTACTS + k] == r, "vehicle {v} differs"),
                }
            }
        }
    }
    let seconds = start.per_step(steps * vehicles);
    for fmu in fmus {
        unsafe { fmi3FreeInstance(fmu) };
    }
    (seconds, record)
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

fn main() {
    let trace = load();
    let steps = std::env::var("WHEELRAIL_VEHICLE_STEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(STEPS);
    let names = [
        "8 FMI 2.0 instances in turn",
        "FMI 3.0, threads 1",
        "FMI 3.0, threads 2",
        "2 vehicles in turn, threads 2",
    ];
    let mut times = vec![Vec::new(); names.len()];
    let mut reference: Option<Record> = None;
    let mut per_contact = Vec::new();
    for round in 0..ROUNDS {
        for (r, name) in names.iter().enumerate() {
            let (seconds, record) = match r {
                0 => {
                    let (seconds, record, contacts) = fmi2_run(&trace, steps);
                    per_contact = contacts;
                    (seconds, record)
                }
                3 => fmi3_run(&trace, steps, 2, 2),
                _ => fmi3_run(&trace, steps, r as u64, 1),
            };
            match &reference {
                None => reference = Some(record),
                Some(want) => assert!(
                    *want == record,
                    "round {round}: {name} differs from the first run's outputs"
                ),
            }
            times[r].push(seconds);
        }
    }
    let exact = reference
        .as_ref()
        .expect("a run")
        .iter()
        .filter(|r| r[3] == 2)
        .count();
    println!(
        "vehicle of {CONTACTS} contacts, {steps} steps of the MBS trace (mode 0, warm start), {ROUNDS} \
         rounds; {:.1} % of the contact steps by the exact solver; outputs bit for bit equal in all runs",
        100.0 * exact as f64 / (steps * CONTACTS) as f64
    );
    let wall = |r: usize| median(times[r].iter().map(|t| t.wall).collect());
    let cpu = |r: usize| median(times[r].iter().map(|t| t.cpu).collect());
    for (r, name) in names.iter().enumerate() {
        let min = times[r]
            .iter()
            .map(|t| t.wall)
            .fold(f64::INFINITY, f64::min);
        println!(
            "{name:<28} {:>7.3} ms per vehicle step (median; min {:.3}), speed-up {:.2}; CPU {:.3} ms per \
             step, {:.2} cores busy",
            wall(r) * 1e3,
            min * 1e3,
            wall(0) / wall(r),
            cpu(r) * 1e3,
            cpu(r) / wall(r)
        );
    }
    let total: f64 = per_contact.iter().sum();
    let slowest = per_contact.iter().cloned().fold(0.0, f64::max);
    let ms: Vec<String> = per_contact
        .iter()
        .map(|t| format!("{:.3}", t * 1e3))
        .collect();
    println!(
        "FMI 2.0 time per step by contact [ms]: {} (the slowest {:.0} % of the vehicle step: two threads \
         gain at most {:.2}x)",
        ms.join(" "),
        100.0 * slowest / total,
        total / (total / 2.0).max(slowest)
    );
    println!(
        "machine: {} cores, load average {}",
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        std::fs::read_to_string("/proc/loadavg")
            .unwrap_or_default()
            .split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
}
