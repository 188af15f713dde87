//! Exact-mode throughput of independent FMU instances on one thread and on two: [`INSTANCES`] instances
//! (exact mode, warm start on, dry, on a 15 × 15 grid and on the default grid) each step with a new
//! longitudinal creepage every step (alternating between two values per instance, so every step solves);
//! one thread steps them all in turn, or two threads step half of them each. The process-wide memos
//! (the heat model's influence tables, the microcontact tables) are warm before anything is timed.
//!
//! Criterion group `threads` (throughput = instance steps per iteration, so it reports steps per second),
//! then a summary of [`ROUNDS`] rounds that alternate the one- and two-thread runs (a shared machine's
//! load changes between runs): steps per second (min, median) of each and their ratio; the CPU time the
//! stepping threads used per second of wall time (near 2 with two threads unless they wait: for each
//! other, or for a core another process holds) and per step (more with two threads if they slow each
//! other down: shared caches, memory bandwidth, contended cache lines); and the machine's idle CPUs
//! (/proc/stat), which tell a wait for each other (a core idle) from a core another process holds. Run with `cargo bench -p wheelrail-fmu --bench threads`.

use WheelRailFriction::contact::variables::CREEPAGE_LONGITUDINAL;
use WheelRailFriction::exports::*;
use WheelRailFriction::fmi2::ffi::Fmi2Component;
use criterion::{Criterion, Throughput};
use std::hint::black_box;
use std::time::{Duration, Instant};

mod common;
use common::{Setup, instance, thread_cpu_ns};

/// Instances stepped per iteration (an even number: two threads take half each).
const INSTANCES: usize = 4;
/// Alternating rounds of the summary.
const ROUNDS: usize = 7;
/// Duration of a one-thread round of the summary [s] (two-thread rounds take the same steps).
const ROUND_TIME: f64 = 0.3;

/// Exact-mode instances, owned by the thread that steps them.
struct Instances(Vec<(Fmi2Component, [f64; 2])>);

// Each instance is stepped by one thread at a time: the one that holds it.
unsafe impl Send for Instances {}

impl Instances {
    /// `n` dry exact-mode instances on a `grid` × `grid` grid, warm start on, each with its own pair of
    /// creepages, stepped once.
    fn new(n: usize, grid: i32) -> Instances {
        let setup = Setup {
            mode: 2,
            grid,
            table: None,
            wetness: 0.0,
            warm: true,
        };
        let mut all = Instances(
            (0..n)
                .map(|k| {
                    // the same creepages in one part of all instances as in each of two parts
                    let xi = 0.002 + 5e-4 * (k % (INSTANCES / 2)) as f64;
                    (unsafe { instance(&setup) }, [xi, xi * 1.05])
                })
                .collect(),
        );
        all.step(1);
        all
    }

    /// `steps` steps of every instance in turn, each at the other of its creepages.
    fn step(&mut self, steps: u64) {
        for k in 0..steps {
            for (fmu, xi) in &self.0 {
                unsafe {
                    fmi2SetReal(
                        *fmu,
                        &(CREEPAGE_LONGITUDINAL as u32),
                        1,
                        &xi[k as usize % 2],
                    );
                    assert_eq!(black_box(fmi2DoStep(*fmu, 0.0, 1e-3, 1)), 0);
                }
            }
        }
    }
}

impl Drop for Instances {
    fn drop(&mut self) {
        for (fmu, _) in &self.0 {
            unsafe { fmi2FreeInstance(*fmu) };
        }
    }
}

/// Each part of the instances stepped `steps` times on a thread of its own: the wall time from the
/// threads' start to the last one's end, and the CPU time [s] the threads used together.
fn run(parts: &mut [Instances], steps: u64) -> (Duration, f64) {
    let start = Instant::now();
    let cpu: f64 = std::thread::scope(|s| {
        let threads: Vec<_> = parts
            .iter_mut()
            .map(|part| {
                s.spawn(move || {
                    let cpu = thread_cpu_ns();
                    part.step(steps);
                    thread_cpu_ns() - cpu
                })
            })
            .collect();
        threads.into_iter().map(|t| t.join().unwrap()).sum()
    });
    (start.elapsed(), cpu * 1e-9)
}

/// The [`INSTANCES`] instances of `grid` in `threads` equal parts.
fn parts(grid: i32, threads: usize) -> Vec<Instances> {
    (0..threads)
        .map(|_| Instances::new(INSTANCES / threads, grid))
        .collect()
}

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    x[x.len() / 2]
}

fn main() {
    let mut c = Criterion::default()
        .without_plots()
        .sample_size(10)
        .configure_from_args();
    for grid in [15, WheelRailFriction::contact::variables::DEFAULT_GRID_SIZE] {
        let mut group = c.benchmark_group("threads");
        group.throughput(Throughput::Elements(INSTANCES as u64));
        for threads in [1, 2] {
            let mut p = parts(grid, threads);
            run(&mut p, 3);
            group.bench_function(
                format!("exact {grid}x{grid} dry, {INSTANCES} instances on {threads} thread(s)"),
                |b| b.iter_custom(|iters| run(&mut p, iters).0),
            );
        }
        group.finish();
    }
    c.final_summary();
    // alternating rounds (not under criterion's filter: always run)
    for grid in [15, WheelRailFriction::contact::variables::DEFAULT_GRID_SIZE] {
        let mut p = [parts(grid, 1), parts(grid, 2)];
        // warm, and steps per round for ROUND_TIME on one thread
        let (wall, _) = run(&mut p[0], 3);
        let steps = ((ROUND_TIME / wall.as_secs_f64() * 3.0) as u64).max(3);
        run(&mut p[1], 3);
        let mut rounds = [Vec::new(), Vec::new()];
        for _ in 0..ROUNDS {
            for (i, part) in p.iter_mut().enumerate() {
                let idle = machine_idle_s();
                let (wall, cpu) = run(part, steps);
                let wall = wall.as_secs_f64();
                let n = (INSTANCES as u64 * steps) as f64;
                rounds[i].push([
                    n / wall,
                    cpu / wall,
                    cpu / n,
                    (machine_idle_s() - idle) / wall,
                ]);
            }
        }
        let median_of = |i: usize, q: usize| median(rounds[i].iter().map(|r| r[q]).collect());
        println!(
            "exact {grid}x{grid} dry, {INSTANCES} instances, {ROUNDS} alternating rounds of {steps} steps each:"
        );
        for (i, threads) in [1, 2].into_iter().enumerate() {
            let min = rounds[i].iter().map(|r| r[0]).fold(f64::INFINITY, f64::min);
            println!(
                "  {threads} thread(s): steps/s min {min:.0}, median {:.0}; medians: CPU s per wall s {:.2}, \
                 CPU per step {:.1} µs, idle CPUs of the machine {:.2}",
                median_of(i, 0),
                median_of(i, 1),
                median_of(i, 2) * 1e6,
                median_of(i, 3)
            );
        }
        println!(
            "  ratio of the medians, 2 threads / 1: {:.2}",
            median_of(1, 0) / median_of(0, 0)
        );
    }
}

/// The idle time of all the machine's CPUs so far [s] (/proc/stat: idle and iowait, in the kernel's
/// USER_HZ = 100 ticks per second; NaN where there is no /proc/stat).
fn machine_idle_s() -> f64 {
    const USER_HZ: f64 = 100.0;
    let stat = std::fs::read_to_string("/proc/stat").unwrap_or_default();
    let ticks: Vec<f64> = stat
        .lines()
        .next()
        .unwrap_or_default()
        .split_whitespace()
        .skip(1)
        .filter_map(|x| x.parse().ok())
        .collect();
    match ticks.get(3..5) {
        Some([idle, iowait]) => (idle + iowait) / USER_HZ,
        _ => f64::NAN,
    }
}
