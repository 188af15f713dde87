//! Memory per FMU instance beyond the shared lookup table: a counting global allocator measures
//! the bytes an instance keeps allocated after `fmi2DoStep` (retained: variables, warm-start state, caches)
//! and the peak of live bytes during one step (working memory of the solver), for exact mode (dry and wet,
//! default grid, warm start on and off) and table mode, with the small test table and with the bundled
//! one: the first instance loads the table, which the further instances share while any instance holds
//! it, so the first instance (table included) and each further one are separate rows. Prints a table and writes target/bench/memory.json for the bench
//! report. Run with `cargo bench -p wheelrail-fmu --bench memory`.

use WheelRailFriction::contact::variables::{CREEPAGE_LONGITUDINAL, DEFAULT_GRID_SIZE};
use WheelRailFriction::exports::*;
use std::alloc::{GlobalAlloc, Layout, System};
use std::ffi::CString;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

mod common;
use common::{Setup, instance, small_table};

/// The system allocator, counting live and peak bytes.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let now = LIVE.fetch_add(layout.size(), Relaxed) + layout.size();
            PEAK.fetch_max(now, Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// A new instance of `setup` after one step at its own creepage (`k`-th), and the peak of live bytes
/// above those before the step during it.
fn stepped(setup: &Setup, k: usize) -> (WheelRailFriction::fmi2::ffi::Fmi2Component, usize) {
    unsafe {
        let fmu = instance(setup);
        let xi = 0.002 + 1e-4 * k as f64;
        assert_eq!(fmi2SetReal(fmu, &(CREEPAGE_LONGITUDINAL as u32), 1, &xi), 0);
        let start = LIVE.load(Relaxed);
        PEAK.store(start, Relaxed);
        assert_eq!(fmi2DoStep(fmu, 0.0, 1e-3, 1), 0);
        (fmu, PEAK.load(Relaxed) - start)
    }
}

/// (retained bytes per instance after a step, peak working bytes of one step) for `n` instances.
fn measure(setup: &Setup, n: usize) -> (f64, usize) {
    let before = LIVE.load(Relaxed);
    let (fmus, peaks): (Vec<_>, Vec<_>) = (0..n).map(|k| stepped(setup, k)).unzip();
    let per_instance = (LIVE.load(Relaxed) - before) as f64 / n as f64;
    for fmu in fmus {
        unsafe { fmi2FreeInstance(fmu) };
    }
    (per_instance, peaks.into_iter().max().unwrap_or(0))
}

/// The rows of a table mode `setup`: its first instance (which loads the table, shared with the later
/// instances while any of them lives) and each of 16 further instances while the first lives.
fn table_rows(name: &str, setup: &Setup) -> [(String, f64, usize); 2] {
    let before = LIVE.load(Relaxed);
    let (first, first_peak) = stepped(setup, 0);
    let with_table = (LIVE.load(Relaxed) - before) as f64;
    let (kept, peak) = measure(setup, 16);
    unsafe { fmi2FreeInstance(first) };
    [
        (
            format!("{name}: first instance (loads the table)"),
            with_table,
            first_peak,
        ),
        (format!("{name}: each further instance"), kept, peak),
    ]
}

fn main() {
    // criterion's harness flags (e.g. --bench) are not for this measurement
    let dir = small_table();
    let dir_c = CString::new(dir.to_str().expect("utf-8 path")).expect("path");
    let table = Setup {
        mode: 1,
        grid: 6,
        table: Some(&dir_c),
        wetness: 0.0,
        warm: true,
    };
    let cases = [
        ("exact 30x30 dry, warm start", 2, 30, 0.0, true),
        ("exact 30x30 dry, cold", 2, 30, 0.0, false),
        ("exact 30x30 wet, warm start", 2, 30, 1.0, true),
    ];
    // one exact solve first: process-wide one-time tables (microcontact F_1.5, Kalker) are not per instance
    measure(
        &Setup {
            mode: 2,
            grid: 30,
            table: None,
            wetness: 1.0,
            warm: false,
        },
        1,
    );
    let mut rows: Vec<(String, f64, usize)> = cases
        .iter()
        .map(|&(name, mode, grid, wetness, warm)| {
            let (kept, peak) = measure(
                &Setup {
                    mode,
                    grid,
                    table: None,
                    wetness,
                    warm,
                },
                4,
            );
            (name.to_string(), kept, peak)
        })
        .collect();
    let bundled = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("resources/table");
    let bundled_c = CString::new(bundled.to_str().expect("utf-8 path")).expect("path");
    rows.extend(table_rows("small test table", &table));
    rows.extend(table_rows(
        "bundled table",
        &Setup {
            mode: 1,
            grid: DEFAULT_GRID_SIZE,
            table: Some(&bundled_c),
            wetness: 0.0,
            warm: true,
        },
    ));
    println!("memory per FMU instance (bytes kept after a step; peak working bytes during a step)");
    for (name, kept, peak) in &rows {
        println!("  {name:<50} kept {kept:>10.0}   step peak {peak:>10}");
    }
    let json = serde_json::json!({
        "instances": rows.iter().map(|(n, k, p)| serde_json::json!({
            "case": n, "kept_bytes": k, "step_peak_bytes": p
        })).collect::<Vec<_>>(),
    });
    let out = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/bench");
    std::fs::create_dir_all(&out).expect("target/bench");
    std::fs::write(out.join("memory.json"), json.to_string()).expect("memory.json");
    let _ = std::fs::remove_dir_all(dir);
}
