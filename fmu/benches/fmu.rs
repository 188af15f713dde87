//! Cost of one `fmi2DoStep` through the exported C functions: in exact mode at the default grid (30 × 30
//! cells), each iteration sets a new longitudinal creepage (alternating between two values, so every step
//! solves) and calls `fmi2DoStep`, dry and wet, with warm starts (the default) and without; and in table
//! mode (target ≤ 2 µs), with a small table built for a 6 × 6 grid first (the lookup cost does not
//! depend on the grid), also with a new contact ellipse every step (random geometry), dry and wet with all
//! three creepages (the whole 16-corner stencil), and both by a table built by similarity (12 corners), and
//! on the nodes of the whole-range table (synthetic values, exact at the probe nodes: the layout's cost
//! without its build; ≈ 1 minute to set up, 1.2 GB in the temporary directory while it runs). Also a step followed by the six columns of the Jacobian (one
//! `fmi2GetDirectionalDerivative` call per input, as a master asks), by table and exact. Run with
//! `cargo bench -p wheelrail-fmu`.

use WheelRailFriction::contact::model::{INPUTS, OUTPUTS};
use WheelRailFriction::contact::variables::{
    CREEPAGE_LATERAL, CREEPAGE_LONGITUDINAL, EVALUATION_MODE, SEMI_AXIS_A, SEMI_AXIS_B,
    SPIN_CREEPAGE, WETNESS,
};
use WheelRailFriction::exports::*;
use criterion::{Criterion, criterion_group, criterion_main};
use std::ffi::CString;
use std::hint::black_box;

mod common;
use common::{Setup, instance, small_table, small_table_by_similarity, whole_range_timing_table};

/// Benchmarks `fmi2DoStep` on `fmu`, alternating the longitudinal creepage between two values.
///
/// # Safety
/// `fmu` is a live, initialised instance.
unsafe fn bench_steps(c: &mut Criterion, name: &str, fmu: *mut std::ffi::c_void, xi: [f64; 2]) {
    let mut k = 0usize;
    c.bench_function(name, |b| {
        b.iter(|| {
            k += 1;
            unsafe {
                fmi2SetReal(fmu, &(CREEPAGE_LONGITUDINAL as u32), 1, &xi[k % 2]);
                black_box(fmi2DoStep(fmu, 0.0, 1e-3, 1))
            }
        })
    });
}

/// Benchmarks a step followed by the full Jacobian of the six Real outputs with respect to the six Real
/// inputs, asked for as a master does: one `fmi2GetDirectionalDerivative` call per input (seed direction).
///
/// # Safety
/// `fmu` is a live, initialised instance.
unsafe fn bench_jacobian(c: &mut Criterion, name: &str, fmu: *mut std::ffi::c_void, xi: [f64; 2]) {
    let unknowns = OUTPUTS.map(|i| i as u32);
    let knowns = INPUTS.map(|i| i as u32);
    let mut k = 0usize;
    let mut column = [0.0; OUTPUTS.len()];
    c.bench_function(name, |b| {
        b.iter(|| {
            k += 1;
            unsafe {
                fmi2SetReal(fmu, &(CREEPAGE_LONGITUDINAL as u32), 1, &xi[k % 2]);
                assert_eq!(fmi2DoStep(fmu, 0.0, 1e-3, 1), 0);
                for known in knowns {
                    let status = fmi2GetDirectionalDerivative(
                        fmu,
                        unknowns.as_ptr(),
                        unknowns.len(),
                        &known,
                        1,
                        &1.0,
                        column.as_mut_ptr(),
                    );
                    assert_eq!(status, 0);
                    black_box(&column);
                }
            }
        })
    });
}

fn do_step(c: &mut Criterion) {
    let cases = [
        ("exact 30x30 dry, xi 0.2 %", [0.002, 0.0021], 0.0, true),
        ("exact 30x30 dry, xi 2 %", [0.02, 0.021], 0.0, true),
        ("exact 30x30 wet, xi 1 %", [0.01, 0.0101], 1.0, true),
        ("exact 30x30 dry, xi 2 %, cold", [0.02, 0.021], 0.0, false),
        ("exact 30x30 wet, xi 1 %, cold", [0.01, 0.0101], 1.0, false),
    ];
    for (label, creepages, wetness, warm) in cases {
        unsafe {
            let fmu = instance(&Setup {
                mode: 2,
                grid: 30,
                table: None,
                wetness,
                warm,
            });
            bench_steps(c, &format!("fmi2DoStep/{label}"), fmu, creepages);
            if label == "exact 30x30 dry, xi 2 %" {
                bench_jacobian(
                    c,
                    "fmi2DoStep + 6 directional derivatives/exact 30x30 dry, xi 2 %",
                    fmu,
                    creepages,
                );
            }
            fmi2FreeInstance(fmu);
        }
    }
}

/// A dry instance in table-only mode (`grid` the table's: 6 for the small tables) with the table at `dir`,
/// at ξ = 0.3 %, whose first step the table evaluated.
///
/// # Safety
/// The instance is freed by the caller (`fmi2FreeInstance`).
unsafe fn table_instance(dir: &std::path::Path, grid: i32) -> *mut std::ffi::c_void {
    let dir_c = CString::new(dir.to_str().unwrap()).unwrap();
    unsafe {
        let fmu = instance(&Setup {
            mode: 1,
            grid,
            table: Some(&dir_c),
            wetness: 0.0,
            warm: true,
        });
        // the table evaluates (table-only mode would fail otherwise)
        let xi = 0.003;
        assert_eq!(fmi2SetReal(fmu, &(CREEPAGE_LONGITUDINAL as u32), 1, &xi), 0);
        assert_eq!(fmi2DoStep(fmu, 0.0, 1e-3, 1), 0);
        let mut mode = 0;
        assert_eq!(
            fmi2GetInteger(fmu, &(EVALUATION_MODE as u32), 1, &mut mode),
            0
        );
        assert_eq!(mode, 1);
        fmu
    }
}

fn do_step_table(c: &mut Criterion) {
    let dir = small_table();
    unsafe {
        let fmu = table_instance(&dir, 6);
        bench_steps(c, "fmi2DoStep/table, dry, xi 0.3 %", fmu, [0.003, 0.0031]);
        bench_jacobian(
            c,
            "fmi2DoStep + 6 directional derivatives/table, dry, xi 0.3 %",
            fmu,
            [0.003, 0.0031],
        );
        bench_geometry_cases(c, "table", fmu);
        fmi2FreeInstance(fmu);
    }
    let _ = std::fs::remove_dir_all(dir);
    // the same by a table built by similarity (one normal force node: 12 corners, dry 6)
    let dir = small_table_by_similarity();
    unsafe {
        let fmu = table_instance(&dir, 6);
        bench_geometry_cases(c, "table by similarity", fmu);
        fmi2FreeInstance(fmu);
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// The random-geometry cases on the nodes of the whole-range table (synthetic values: the layout's cost
/// without its build; by similarity, 12 corners), at the FMU's default parameters.
fn do_step_whole_range(c: &mut Criterion) {
    let dir = whole_range_timing_table();
    let grid = wheelrail::Params::default().grid.nx as i32;
    unsafe {
        let fmu = table_instance(&dir, grid);
        bench_geometry_cases(c, "whole-range nodes (synthetic values)", fmu);
        fmi2FreeInstance(fmu);
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// The random-geometry table steps of a dry instance at ξ = 0.3 % ([`bench_random_geometry`], as
/// `fmi2DoStep/{kind}, …`), then wet with all three creepages, every linear corner weighted and every
/// creepage off its nodes (the stencil in full). Leaves the instance wet.
///
/// # Safety
/// As [`bench_random_geometry`].
unsafe fn bench_geometry_cases(c: &mut Criterion, kind: &str, fmu: *mut std::ffi::c_void) {
    unsafe {
        bench_random_geometry(
            c,
            &format!("fmi2DoStep/{kind}, dry, xi 0.3 %, random geometry"),
            fmu,
        );
        let vr = [
            CREEPAGE_LATERAL as u32,
            SPIN_CREEPAGE as u32,
            WETNESS as u32,
        ];
        let x = [0.002, 0.1, 0.07];
        assert_eq!(fmi2SetReal(fmu, vr.as_ptr(), 3, x.as_ptr()), 0);
        bench_random_geometry(
            c,
            &format!(
                "fmi2DoStep/{kind}, wet 0.07, xi 0.3 %, eta 0.2 %, spin 0.1 m-1, random geometry"
            ),
            fmu,
        );
    }
}

/// Benchmarks (as `name`) a table step at a new contact every step, as an MBS run feeds it: each iteration
/// sets the semi-axes (inputs `semi_axis_a`, `semi_axis_b`) of one of 1024 random ellipses inside the small
/// table's geometry axes (a/b 0.5–0.6, p_ref 0.70–0.85 GPa at the default 100 kN) and calls `fmi2DoStep`,
/// the other inputs as set. A dry contact (wetness on its first node) reads half the linear corners of a
/// wet one.
///
/// # Safety
/// `fmu` is a live, initialised instance in table-only mode with the small table.
unsafe fn bench_random_geometry(c: &mut Criterion, name: &str, fmu: *mut std::ffi::c_void) {
    let mut rng = wheelrail::table::verify::SplitMix64::new(13);
    let ellipses: Vec<[f64; 2]> = (0..1024)
        .map(|_| {
            let ratio = 0.5 + 0.1 * rng.uniform();
            let p_ref = 0.70e9 + 0.15e9 * rng.uniform();
            wheelrail::table::coords::semi_axes(ratio, p_ref, 100e3)
        })
        .collect();
    let set = |e: &[f64; 2]| unsafe {
        let vr = [SEMI_AXIS_A as u32, SEMI_AXIS_B as u32];
        fmi2SetReal(fmu, vr.as_ptr(), 2, e.as_ptr())
    };
    // every contact is inside the table (table-only mode fails a step outside it)
    for e in &ellipses {
        assert_eq!(set(e), 0);
        assert_eq!(unsafe { fmi2DoStep(fmu, 0.0, 1e-3, 1) }, 0);
    }
    let mut k = 0usize;
    c.bench_function(name, |b| {
        b.iter(|| {
            k = (k + 1) % ellipses.len();
            set(&ellipses[k]);
            black_box(unsafe { fmi2DoStep(fmu, 0.0, 1e-3, 1) })
        })
    });
}

criterion_group! {
    name = benches;
    // no plots: criterion's plotters backend needs system fonts
    config = Criterion::default().without_plots().sample_size(10);
    targets = do_step, do_step_table, do_step_whole_range
}
criterion_main!(benches);
