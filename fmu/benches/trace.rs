//! The MBS trace through the FMU: one wheel 10 s at 1 kHz through a curve
//! (`tools/mbs_trace.py`, written to target/mbs_trace.csv by `make bench`; another file: environment
//! variable `WHEELRAIL_TRACE`), every step through the exported C functions on one thread: set the row's
//! inputs and `fmi2DoStep` (timed together, as a master pays them), then `force_longitudinal`,
//! `force_lateral`, `max_temperature` and `evaluation_mode` (not timed). The bundled table
//! (fmu/resources/table) in `mode` 1 (table only) and 0 (auto) with `grid_size` automatic (mode 0 solves
//! the points the table does not serve on the grid per contact) and 2 (exact only, the reference) with
//! `grid_size` 30, warm start on; and mode 2 on the grids 7 × 7, 9 × 9, 15 × 15 and 20 × 20 (the exact
//! step's cost against its error).
//!
//! Per mode: how many steps the FMU evaluated by table and by the exact solver, and how many it refused
//! (`fmi2Error`; mode 1 refuses a geometry other than its table's: the pass goes on in a fresh
//! instance); the time per step (mean, p99, max over the evaluated steps, by path, by path and wetness
//! too; passes are repeated in fresh instances while they add up to less than [`TIMING_BUDGET`]) and the
//! real-time factor (simulated time over wall time, of one contact and of eight stepped on one thread);
//! the error against mode 2 at every evaluated step, |ΔF_x|/F_N, |ΔF_y|/F_N, |ΔF|/F_N and |ΔT_max|
//! (mean, p99, max; over all steps, the table's and the exact solver's). Written to target/bench/mbs_trace.json for `tools/bench_report.py`.
//! Criterion then times whole passes over the steps a mode evaluates (criterion group `mbs_trace`,
//! throughput = steps per pass) for the modes whose pass takes at most [`CRITERION_PASS_BUDGET`]: a
//! mode whose steps fall back to the exact solver (milliseconds each) is timed by its single pass only.
//! The times are also split by the row's wetness (dry: w = 0, wet: w > 0), and set beside Polach's on the
//! same trace in the same run, as wall time and as the thread's CPU time (which leaves out the
//! waits of a loaded shared machine): the library's Polach law (`friction.law = "polach"`, docs/model.md
//! §12.2, which the FMU does not offer) through the same evaluation policy, exact mode, with each row's
//! geometry, timed per step on this thread; every mode's mean and p99 as a ratio to Polach's mean.
//! Run with `cargo bench -p wheelrail-fmu --bench trace`; environment variable `WHEELRAIL_TRACE_MODES`
//! (names separated by commas, e.g. `exact 9x9,exact 15x15`) restricts the modes measured besides the
//! reference mode 2 on the default grid (always run: the force errors are against it).

use WheelRailFriction::contact::variables::{
    AUTOMATIC_GRID_SIZE, DEFAULT_GRID_SIZE, EVALUATION_MODE, FORCE_LATERAL, FORCE_LONGITUDINAL,
    MAX_TEMPERATURE, VARIABLES,
};
use WheelRailFriction::exports::*;
use WheelRailFriction::fmi2::ffi::Fmi2Component;
use WheelRailFriction::fmi2::variables::Causality;
use criterion::{Criterion, SamplingMode, Throughput, criterion_group, criterion_main};
use serde_json::{Value, json};
use std::ffi::CString;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use wheelrail::table::verify::Stats;

mod common;
use common::{Setup, instance, thread_cpu_ns};

/// Timed passes of one mode are repeated while their total stays below this.
const TIMING_BUDGET: Duration = Duration::from_secs(1);
/// … and at most this many passes.
const MAX_TIMING_PASSES: usize = 100;
/// The longest pass criterion repeats (it takes at least 11 passes).
const CRITERION_PASS_BUDGET: Duration = Duration::from_millis(250);
/// The contacts of a vehicle (two wheelsets per bogie, two bogies, one contact per wheel) for its
/// real-time factor.
const VEHICLE_CONTACTS: usize = 8;
/// `fmi2Error`.
const FMI2_ERROR: i32 = 3;

/// The trace: per row the time and the FMU inputs it sets.
struct Trace {
    path: PathBuf,
    /// FMU input names of the columns after `time`.
    names: Vec<String>,
    /// Their value references.
    vrs: Vec<u32>,
    times: Vec<f64>,
    /// Input values per row, in the order of `names`.
    rows: Vec<Vec<f64>>,
    /// The column of `normal_force` in `rows`.
    normal_force: usize,
    /// The column of `wetness` in `rows` (None: the trace is dry).
    wetness: Option<usize>,
    /// The communication step [s].
    step: f64,
}

impl Trace {
    /// Reads a CSV trace: a header `time,<FMU input>,…`, then one row per step at a uniform time step.
    fn load(path: &Path) -> Trace {
        let text = std::fs::read_to_string(path).unwrap_or_else(|e| {
            panic!(
                "{}: {e}; write it with `python3 tools/mbs_trace.py` (`make bench` does)",
                path.display()
            )
        });
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
        assert_eq!(header[0], "time", "the first column of {}", path.display());
        let names: Vec<String> = header[1..].iter().map(|s| s.to_string()).collect();
        let vrs = names
            .iter()
            .map(|n| {
                let v = VARIABLES
                    .iter()
                    .find(|v| v.name == n)
                    .unwrap_or_else(|| panic!("column {n} is no FMU variable"));
                assert_eq!(v.causality, Causality::Input, "column {n} is no FMU input");
                v.vr
            })
            .collect();
        let normal_force = names
            .iter()
            .position(|n| n == "normal_force")
            .expect("a normal_force column");
        let wetness = names.iter().position(|n| n == "wetness");
        let (mut times, mut rows) = (Vec::new(), Vec::new());
        for (i, line) in lines.enumerate() {
            let values: Vec<f64> = line
                .split(',')
                .map(|x| {
                    x.parse()
                        .unwrap_or_else(|e| panic!("row {}: {x:?}: {e}", i + 1))
                })
                .collect();
            assert_eq!(values.len(), header.len(), "row {}", i + 1);
            times.push(values[0]);
            rows.push(values[1..].to_vec());
        }
        assert!(
            times.len() >= 2,
            "{} has fewer than two rows",
            path.display()
        );
        let step = times[1] - times[0];
        for w in times.windows(2) {
            assert!(
                ((w[1] - w[0]) - step).abs() <= 1e-9 * step.max(1.0),
                "{}: the time step is not uniform at t = {}",
                path.display(),
                w[0]
            );
        }
        Trace {
            path: path.to_path_buf(),
            names,
            vrs,
            times,
            rows,
            normal_force,
            wetness,
            step,
        }
    }
}

/// One mode of the FMU, on a grid of `grid` × `grid` cells.
#[derive(Clone, Copy)]
struct Mode {
    code: i32,
    name: &'static str,
    grid: i32,
}

const TABLE_ONLY: Mode = Mode {
    code: 1,
    name: "table only",
    grid: AUTOMATIC_GRID_SIZE,
};
/// Mode 0 with `grid_size` automatic: the points the table does not serve on the grid per contact.
const AUTO: Mode = Mode {
    code: 0,
    name: "auto",
    grid: AUTOMATIC_GRID_SIZE,
};
const EXACT: Mode = Mode {
    code: 2,
    name: "exact",
    grid: DEFAULT_GRID_SIZE,
};
/// Exact mode on coarser grids (the cost of a warm exact step against its force error; the
/// error is against mode 2 on the default grid, which is within about 1e-3·F_N of the grid-converged
/// solution on this trace).
const EXACT_COARSE: [Mode; 4] = [
    Mode {
        code: 2,
        name: "exact 7x7",
        grid: 7,
    },
    Mode {
        code: 2,
        name: "exact 9x9",
        grid: 9,
    },
    Mode {
        code: 2,
        name: "exact 15x15",
        grid: 15,
    },
    Mode {
        code: 2,
        name: "exact 20x20",
        grid: 20,
    },
];

/// What one evaluated step gave.
#[derive(Clone, Copy)]
struct Outcome {
    force_x: f64,
    force_y: f64,
    /// `max_temperature` [K].
    max_temperature: f64,
    /// `evaluation_mode`: 1 table, 2 exact.
    path: i32,
    /// Time of setting the inputs and `fmi2DoStep` [ns].
    nanos: f64,
    /// The thread's CPU time in it [ns].
    cpu_nanos: f64,
}

impl Trace {
    /// Whether row `k` is wet (w > 0).
    fn wet(&self, k: usize) -> bool {
        self.wetness.is_some_and(|c| self.rows[k][c] > 0.0)
    }

    /// The library's inputs of row `k`: the operating point and the contact geometry (the FMU's input
    /// names mapped as the FMU maps them; columns the trace lacks keep the FMU's start values).
    fn library_inputs(&self, k: usize) -> (wheelrail::OperatingPoint, wheelrail::params::Geometry) {
        let value = |name: &str| {
            self.names
                .iter()
                .position(|n| n == name)
                .map(|c| self.rows[k][c])
        };
        let mut point = wheelrail::OperatingPoint::default();
        let defaults = wheelrail::Params::default().geometry;
        for (name, field) in [
            ("creepage_longitudinal", &mut point.creepage_x),
            ("creepage_lateral", &mut point.creepage_y),
            ("spin_creepage", &mut point.spin),
            ("normal_force", &mut point.normal_force),
            ("rolling_speed", &mut point.speed),
            ("wetness", &mut point.wetness),
        ] {
            if let Some(v) = value(name) {
                *field = v;
            }
        }
        let geometry = wheelrail::params::Geometry::of_inputs(
            value("curvature_longitudinal").unwrap_or(defaults.curvature_x),
            value("curvature_lateral").unwrap_or(defaults.curvature_y),
            [
                value("semi_axis_a").unwrap_or(0.0),
                value("semi_axis_b").unwrap_or(0.0),
            ],
        );
        (point, geometry)
    }
}

/// The time per step [ns] of the library's Polach law over the whole trace (see the module
/// documentation): one pass, then more while they add up to less than [`TIMING_BUDGET`]; per step the
/// wetness of the row, the wall time and the thread's CPU time [ns].
fn polach_times(trace: &Trace) -> Vec<(bool, f64, f64)> {
    use wheelrail::model::{Evaluator, Mode as Route, Policy};
    let mut params = wheelrail::Params::default();
    params.friction.law = wheelrail::params::FrictionLaw::Polach;
    let evaluator = Evaluator::new(
        wheelrail::Model::new(params).expect("valid parameters"),
        Route::ExactOnly,
        None,
        Policy::default(),
    )
    .expect("an evaluator");
    let inputs: Vec<_> = (0..trace.rows.len())
        .map(|k| trace.library_inputs(k))
        .collect();
    let mut times = Vec::new();
    let mut spent = 0.0;
    while times.is_empty()
        || (spent < TIMING_BUDGET.as_secs_f64() && times.len() < MAX_TIMING_PASSES * inputs.len())
    {
        let mut warm = None;
        for (k, (point, geometry)) in inputs.iter().enumerate() {
            let cpu = thread_cpu_ns();
            let start = Instant::now();
            let e = evaluator
                .evaluate_at(point, geometry, None, &mut warm)
                .unwrap_or_else(|e| panic!("Polach at row {k}: {e}"));
            let time = start.elapsed();
            let cpu = thread_cpu_ns() - cpu;
            std::hint::black_box(e);
            spent += time.as_secs_f64();
            times.push((trace.wet(k), time.as_nanos() as f64, cpu));
        }
    }
    times
}

/// The bench's instances: the bundled table, default grid, warm start. An instance that has evaluated by
/// the table is kept alive meanwhile: the table is loaded once per process while any instance holds it,
/// as in a master that keeps its instances, so freeing the last one would load it again for the next.
struct Instances {
    table: CString,
    keeper: Fmi2Component,
}

impl Instances {
    fn new() -> Instances {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/table");
        let mut instances = Instances {
            table: CString::new(dir.to_str().expect("utf-8 path")).expect("path"),
            keeper: std::ptr::null_mut(),
        };
        instances.keeper = instances.fresh(TABLE_ONLY);
        // a step at the start values (the table's geometry) loads the table
        assert_eq!(unsafe { fmi2DoStep(instances.keeper, 0.0, 1e-3, 1) }, 0);
        instances
    }

    /// A fresh initialised instance in `mode`.
    fn fresh(&self, mode: Mode) -> Fmi2Component {
        unsafe {
            instance(&Setup {
                mode: mode.code,
                grid: mode.grid,
                table: Some(&self.table),
                wetness: 0.0,
                warm: true,
            })
        }
    }
}

impl Drop for Instances {
    fn drop(&mut self) {
        unsafe { fmi2FreeInstance(self.keeper) };
    }
}

/// A step's time: wall [s] and the thread's CPU time [ns].
#[derive(Clone, Copy)]
struct Took {
    wall: Duration,
    cpu_ns: f64,
}

/// Sets the inputs of row `k` and does its step; returns the status and the time both took.
///
/// # Safety
/// `fmu` is a live instance at a communication point.
unsafe fn step(fmu: Fmi2Component, trace: &Trace, k: usize) -> (i32, Took) {
    let cpu = thread_cpu_ns();
    let start = Instant::now();
    let status = unsafe {
        let set = fmi2SetReal(
            fmu,
            trace.vrs.as_ptr(),
            trace.vrs.len(),
            trace.rows[k].as_ptr(),
        );
        assert_eq!(set, 0, "fmi2SetReal of row {k}");
        fmi2DoStep(fmu, trace.times[k], trace.step, 1)
    };
    let wall = start.elapsed();
    (
        status,
        Took {
            wall,
            cpu_ns: thread_cpu_ns() - cpu,
        },
    )
}

/// One pass over `steps` (row indices, in order) in a fresh instance of `mode`: per step its outcome,
/// None where the FMU refused it (then the pass goes on in another fresh instance). Errors other than
/// mode 1's refusals stop the bench.
fn pass(instances: &Instances, mode: Mode, trace: &Trace, steps: &[usize]) -> Vec<Option<Outcome>> {
    let mut fmu = instances.fresh(mode);
    let outcomes = steps
        .iter()
        .map(|&k| unsafe {
            let (status, time) = step(fmu, trace, k);
            if status == FMI2_ERROR {
                assert_eq!(
                    mode.code, TABLE_ONLY.code,
                    "mode {} failed at row {k} (t = {} s)",
                    mode.name, trace.times[k]
                );
                fmi2FreeInstance(fmu);
                fmu = instances.fresh(mode);
                return None;
            }
            assert!(status <= 1, "fmi2DoStep status {status} at row {k}");
            let vrs = [
                FORCE_LONGITUDINAL as u32,
                FORCE_LATERAL as u32,
                MAX_TEMPERATURE as u32,
            ];
            let mut out = [0.0; 3];
            assert_eq!(fmi2GetReal(fmu, vrs.as_ptr(), 3, out.as_mut_ptr()), 0);
            let mut path = 0;
            assert_eq!(
                fmi2GetInteger(fmu, &(EVALUATION_MODE as u32), 1, &mut path),
                0
            );
            Some(Outcome {
                force_x: out[0],
                force_y: out[1],
                max_temperature: out[2],
                path,
                nanos: time.wall.as_nanos() as f64,
                cpu_nanos: time.cpu_ns,
            })
        })
        .collect();
    unsafe { fmi2FreeInstance(fmu) };
    outcomes
}

/// The time of each step of one pass over `steps` (row indices, in order; none refused) in a fresh
/// instance of `mode` (instance set-up not timed).
fn timed_pass(instances: &Instances, mode: Mode, trace: &Trace, steps: &[usize]) -> Vec<Took> {
    let fmu = instances.fresh(mode);
    let times = steps
        .iter()
        .map(|&k| {
            let (status, time) = unsafe { step(fmu, trace, k) };
            assert!(status <= 1, "fmi2DoStep status {status} at row {k}");
            time
        })
        .collect();
    unsafe { fmi2FreeInstance(fmu) };
    times
}

/// `Stats` as JSON.
fn stats(values: &[f64]) -> Value {
    let s = Stats::of(values);
    json!({"mean": s.mean, "p99": s.p99, "max": s.max, "count": values.len()})
}

/// The force errors of `outcomes` against `reference` at the evaluated steps `keep` selects, relative to
/// |F_N| of each step, and the errors of T_max [K].
fn errors(
    trace: &Trace,
    outcomes: &[Option<Outcome>],
    reference: &[Option<Outcome>],
    keep: impl Fn(&Outcome) -> bool,
) -> Value {
    let (mut dx, mut dy, mut d, mut dt) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (k, (o, r)) in outcomes.iter().zip(reference).enumerate() {
        if let (Some(o), Some(r)) = (o, r)
            && keep(o)
        {
            let f = trace.rows[k][trace.normal_force].abs();
            let (ex, ey) = (o.force_x - r.force_x, o.force_y - r.force_y);
            dx.push(ex.abs() / f);
            dy.push(ey.abs() / f);
            d.push(ex.hypot(ey) / f);
            dt.push((o.max_temperature - r.max_temperature).abs());
        }
    }
    json!({
        "force_x": stats(&dx),
        "force_y": stats(&dy),
        "force": stats(&d),
        "max_temperature_k": stats(&dt),
    })
}

/// The measurement of one mode: a first pass over the whole trace (outcomes, errors), then timing passes
/// over the steps it evaluated while they fit [`TIMING_BUDGET`]; its JSON and the evaluated steps.
fn measure(
    instances: &Instances,
    mode: Mode,
    trace: &Trace,
    reference: Option<&[Option<Outcome>]>,
) -> (Vec<Option<Outcome>>, Vec<usize>, Value) {
    let all: Vec<usize> = (0..trace.rows.len()).collect();
    let first = pass(instances, mode, trace, &all);
    let evaluated: Vec<usize> = all
        .iter()
        .copied()
        .filter(|&k| first[k].is_some())
        .collect();
    // per step: path, wet, wall time, CPU time [ns]
    let mut times: Vec<(i32, bool, f64, f64)> = all
        .iter()
        .zip(&first)
        .filter_map(|(&k, o)| o.map(|o| (o.path, trace.wet(k), o.nanos, o.cpu_nanos)))
        .collect();
    let mut spent: f64 = times.iter().map(|t| t.2).sum::<f64>() * 1e-9;
    let mut passes = 1;
    while !evaluated.is_empty() && spent < TIMING_BUDGET.as_secs_f64() && passes < MAX_TIMING_PASSES
    {
        for (&k, time) in evaluated
            .iter()
            .zip(timed_pass(instances, mode, trace, &evaluated))
        {
            times.push((
                first[k].map_or(0, |o| o.path),
                trace.wet(k),
                time.wall.as_nanos() as f64,
                time.cpu_ns,
            ));
            spent += time.wall.as_secs_f64();
        }
        passes += 1;
    }
    let by = |p: i32| first.iter().flatten().filter(|o| o.path == p).count();
    let select = |p: Option<i32>, wet: Option<bool>, cpu: bool| -> Vec<f64> {
        times
            .iter()
            .filter(|t| p.is_none_or(|p| t.0 == p) && wet.is_none_or(|w| t.1 == w))
            .map(|t| if cpu { t.3 } else { t.2 })
            .collect()
    };
    let time_of = |p, wet| select(p, wet, false);
    // simulated time per step over the mean wall time per step
    let real_time_factor = trace.step / (Stats::of(&time_of(None, None)).mean * 1e-9);
    let cpu_of = |wet| select(None, wet, true);
    let mut report = json!({
        "mode": mode.code,
        "name": mode.name,
        "grid": mode.grid,
        "steps": trace.rows.len(),
        "evaluated": evaluated.len(),
        "refused": trace.rows.len() - evaluated.len(),
        "by_table": by(1),
        "by_exact": by(2),
        "timing_passes": passes,
        "time_per_step_ns": stats(&time_of(None, None)),
        "time_per_step_ns_by_table": stats(&time_of(Some(1), None)),
        "time_per_step_ns_by_exact": stats(&time_of(Some(2), None)),
        "time_per_step_ns_dry": stats(&time_of(None, Some(false))),
        "time_per_step_ns_wet": stats(&time_of(None, Some(true))),
        "time_per_step_ns_by_exact_dry": stats(&time_of(Some(2), Some(false))),
        "time_per_step_ns_by_exact_wet": stats(&time_of(Some(2), Some(true))),
        // simulated time over the wall time of the steps (one contact), and of eight such contacts
        // stepped one after another on one thread
        "real_time_factor": real_time_factor,
        "real_time_factor_8_contacts": real_time_factor / VEHICLE_CONTACTS as f64,
        "cpu_time_per_step_ns": stats(&cpu_of(None)),
        "cpu_time_per_step_ns_dry": stats(&cpu_of(Some(false))),
        "cpu_time_per_step_ns_wet": stats(&cpu_of(Some(true))),
    });
    if let Some(r) = reference {
        report["error_vs_exact"] = json!({
            "all_steps": errors(trace, &first, r, |_| true),
            "table_steps": errors(trace, &first, r, |o| o.path == 1),
            "exact_steps": errors(trace, &first, r, |o| o.path == 2),
        });
    }
    (first, evaluated, report)
}

/// The time two `Instant::now` calls take apart (median of many) [ns]: the timer's share of a step time.
fn timer_overhead() -> f64 {
    let mut t: Vec<f64> = (0..10_001)
        .map(|_| {
            let s = Instant::now();
            s.elapsed().as_nanos() as f64
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

/// /proc/loadavg (the machine's load while measuring; empty where there is none).
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .unwrap_or_default()
        .trim()
        .to_string()
}

fn mbs_trace(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let path = std::env::var_os("WHEELRAIL_TRACE")
        .map_or_else(|| root.join("target/mbs_trace.csv"), PathBuf::from);
    let trace = Trace::load(&path);
    let load_start = load_average();
    let instances = Instances::new();
    println!(
        "MBS trace {}: {} steps of {} s, inputs {}",
        trace.path.display(),
        trace.rows.len(),
        trace.step,
        trace.names.join(", ")
    );
    let polach = polach_times(&trace);
    let polach_select = |wet: Option<bool>, cpu: bool| -> Vec<f64> {
        polach
            .iter()
            .filter(|t| wet.is_none_or(|w| t.0 == w))
            .map(|t| if cpu { t.2 } else { t.1 })
            .collect()
    };
    let polach_of = |wet| polach_select(wet, false);
    let polach_mean = Stats::of(&polach_of(None)).mean;
    let polach_cpu_mean = Stats::of(&polach_select(None, true)).mean;
    let wanted = std::env::var("WHEELRAIL_TRACE_MODES").ok();
    let selected = |mode: &Mode| {
        wanted
            .as_deref()
            .is_none_or(|w| w.split(',').any(|n| n.trim() == mode.name))
    };
    let (reference, _, exact) = measure(&instances, EXACT, &trace, None);
    let mut modes = vec![exact];
    let mut criterion_runs = Vec::new();
    for mode in [TABLE_ONLY, AUTO]
        .into_iter()
        .chain(EXACT_COARSE)
        .filter(selected)
    {
        let (outcomes, evaluated, report) = measure(&instances, mode, &trace, Some(&reference));
        let first_pass: f64 = outcomes.iter().flatten().map(|o| o.nanos * 1e-9).sum();
        let by_exact = outcomes.iter().flatten().filter(|o| o.path == 2).count();
        criterion_runs.push((mode, evaluated, first_pass, by_exact));
        modes.push(report);
    }
    // a mode's time per step (all, dry, wet steps; mean and p99) over Polach's mean on the same clock
    let ratios = |m: &Value, key: &str, polach: f64| {
        let r =
            |part: &str, stat: &str| m[format!("{key}{part}")][stat].as_f64().map(|t| t / polach);
        json!({
            "mean": r("", "mean"),
            "p99": r("", "p99"),
            "dry_mean": r("_dry", "mean"),
            "dry_p99": r("_dry", "p99"),
            "wet_mean": r("_wet", "mean"),
            "wet_p99": r("_wet", "p99"),
        })
    };
    for m in modes.iter_mut() {
        let wall = ratios(m, "time_per_step_ns", polach_mean);
        let cpu = ratios(m, "cpu_time_per_step_ns", polach_cpu_mean);
        m["ratio_to_polach"] = wall;
        m["cpu_ratio_to_polach"] = cpu;
    }
    println!(
        "  Polach (library, exact mode, same trace): time per step mean {:.3} µs, p99 {:.3} µs",
        polach_mean * 1e-3,
        Stats::of(&polach_of(None)).p99 * 1e-3
    );
    for m in &modes {
        let t = &m["time_per_step_ns"];
        println!(
            "  mode {} ({}): {} steps evaluated ({} by table, {} by exact), {} refused; time per step mean {:.3} µs, p99 {:.3} µs",
            m["mode"],
            m["name"].as_str().unwrap_or(""),
            m["evaluated"],
            m["by_table"],
            m["by_exact"],
            m["refused"],
            t["mean"].as_f64().unwrap_or(f64::NAN) * 1e-3,
            t["p99"].as_f64().unwrap_or(f64::NAN) * 1e-3,
        );
        let us = |v: &Value| v.as_f64().unwrap_or(f64::NAN) * 1e-3;
        for (what, dry, wet, ratio) in [
            (
                "wall",
                "time_per_step_ns_dry",
                "time_per_step_ns_wet",
                "ratio_to_polach",
            ),
            (
                "CPU",
                "cpu_time_per_step_ns_dry",
                "cpu_time_per_step_ns_wet",
                "cpu_ratio_to_polach",
            ),
        ] {
            let (d, w) = (&m[dry], &m[wet]);
            println!(
                "    {what}: dry mean {:.3} µs, p99 {:.3} µs; wet mean {:.3} µs, p99 {:.3} µs; mean {:.1}x Polach's",
                us(&d["mean"]),
                us(&d["p99"]),
                us(&w["mean"]),
                us(&w["p99"]),
                m[ratio]["mean"].as_f64().unwrap_or(f64::NAN),
            );
        }
        let (xd, xw) = (
            &m["time_per_step_ns_by_exact_dry"],
            &m["time_per_step_ns_by_exact_wet"],
        );
        let solved = m["by_exact"].as_u64().unwrap_or(0) > 0;
        if solved {
            println!(
                "    exact steps: dry mean {:.3} µs, p99 {:.3} µs; wet mean {:.3} µs, p99 {:.3} µs; real-time factor {:.2} (1 contact), {:.2} (8 contacts, one thread)",
                us(&xd["mean"]),
                us(&xd["p99"]),
                us(&xw["mean"]),
                us(&xw["p99"]),
                m["real_time_factor"].as_f64().unwrap_or(f64::NAN),
                m["real_time_factor_8_contacts"]
                    .as_f64()
                    .unwrap_or(f64::NAN),
            );
        }
        if let Some(e) = m.get("error_vs_exact") {
            let f = |x: &Value| x.as_f64().unwrap_or(f64::NAN);
            let (force, t) = (
                &e["all_steps"]["force"],
                &e["all_steps"]["max_temperature_k"],
            );
            println!(
                "    against mode 2: |ΔF|/F_N mean {:.2e}, p99 {:.2e}, max {:.2e}; |ΔT_max| mean {:.2} K, p99 {:.2} K, max {:.2} K",
                f(&force["mean"]),
                f(&force["p99"]),
                f(&force["max"]),
                f(&t["mean"]),
                f(&t["p99"]),
                f(&t["max"]),
            );
        }
    }
    let mut group = c.benchmark_group("mbs_trace");
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    let mut criterion = Vec::new();
    for (mode, evaluated, pass_time, by_exact) in criterion_runs {
        let budget = CRITERION_PASS_BUDGET.as_secs_f64();
        let note = if evaluated.is_empty() {
            "skipped: the mode evaluated no step".to_string()
        } else if pass_time > budget {
            format!(
                "skipped: one pass takes {pass_time:.1} s (> {budget} s; {by_exact} of its {} steps by the exact solver): timed by its single pass",
                evaluated.len()
            )
        } else {
            group.throughput(Throughput::Elements(evaluated.len() as u64));
            group.bench_function(mode.name, |b| {
                b.iter_custom(|iters| {
                    (0..iters)
                        .flat_map(|_| timed_pass(&instances, mode, &trace, &evaluated))
                        .map(|t| t.wall)
                        .sum()
                })
            });
            "run".to_string()
        };
        println!("  criterion mbs_trace/{}: {note}", mode.name);
        criterion.push(json!({
            "id": format!("mbs_trace/{}", mode.name),
            "mode": mode.code,
            "steps_per_iteration": evaluated.len(),
            "status": note,
        }));
    }
    group.finish();
    let report = json!({
        "trace": {
            "path": trace.path.display().to_string(),
            "steps": trace.rows.len(),
            "step_size": trace.step,
            "inputs": trace.names,
        },
        "threads": 1,
        "timer_overhead_ns": timer_overhead(),
        "load_average_start": load_start,
        "load_average_end": load_average(),
        "polach": {
            "time_per_step_ns": stats(&polach_of(None)),
            "time_per_step_ns_dry": stats(&polach_of(Some(false))),
            "time_per_step_ns_wet": stats(&polach_of(Some(true))),
            "cpu_time_per_step_ns": stats(&polach_select(None, true)),
        },
        "modes": modes,
        "criterion": criterion,
    });
    let out = root.join("target/bench");
    std::fs::create_dir_all(&out).expect("target/bench");
    std::fs::write(
        out.join("mbs_trace.json"),
        serde_json::to_string_pretty(&report).expect("json"),
    )
    .expect("mbs_trace.json");
}

criterion_group! {
    name = benches;
    // no plots: criterion's plotters backend needs system fonts
    config = Criterion::default().without_plots();
    targets = mbs_trace
}
criterion_main!(benches);
