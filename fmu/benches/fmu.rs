//! Cost of one `fmi2DoStep` in exact mode at the default grid (30 × 30 cells), through the exported C
//! functions: each iteration sets a new longitudinal creepage (alternating between two values, so every
//! step solves) and calls `fmi2DoStep`, dry and wet; and in table mode (issue 5 target ≤ 2 µs), with a
//! small table built for a 6 × 6 grid first (the lookup cost does not depend on the grid). Run with
//! `cargo bench -p wheelrail-fmu`.

use WheelRailFriction::contact::variables::{
    CREEPAGE_LONGITUDINAL, EVALUATION_MODE, GRID_SIZE, INFO, MODE, TABLE_FILE, WETNESS,
};
use WheelRailFriction::exports::*;
use WheelRailFriction::fmi2::ffi::{FMI2_COSIMULATION, Fmi2CallbackFunctions};
use criterion::{Criterion, criterion_group, criterion_main};
use std::ffi::CString;
use std::hint::black_box;
use std::ptr::{null, null_mut};

fn do_step(c: &mut Criterion) {
    let guid = CString::new(WheelRailFriction::fmi2::description::guid(&INFO)).unwrap();
    let callbacks = Fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: null_mut(),
    };
    let mut group = c.benchmark_group("fmi2DoStep");
    group.sample_size(10);
    let cases = [
        ("exact 30x30 dry, xi 0.2 %", [0.002, 0.0021], 0.0),
        ("exact 30x30 dry, xi 2 %", [0.02, 0.021], 0.0),
        ("exact 30x30 wet, xi 1 %", [0.01, 0.0101], 1.0),
    ];
    for (label, creepages, wetness) in cases {
        unsafe {
            let fmu = fmi2Instantiate(
                c"bench".as_ptr(),
                FMI2_COSIMULATION,
                guid.as_ptr(),
                null(),
                &callbacks,
                0,
                0,
            );
            assert!(!fmu.is_null());
            assert_eq!(fmi2SetInteger(fmu, &(MODE as u32), 1, &2), 0);
            assert_eq!(fmi2SetReal(fmu, &(WETNESS as u32), 1, &wetness), 0);
            assert_eq!(fmi2EnterInitializationMode(fmu), 0);
            assert_eq!(fmi2ExitInitializationMode(fmu), 0);
            let mut k = 0usize;
            group.bench_function(label, |b| {
                b.iter(|| {
                    k += 1;
                    let xi = creepages[k % 2];
                    fmi2SetReal(fmu, &(CREEPAGE_LONGITUDINAL as u32), 1, &xi);
                    black_box(fmi2DoStep(fmu, 0.0, 1e-3, 1))
                })
            });
            fmi2FreeInstance(fmu);
        }
    }
    group.finish();
}

/// A table for the FMU's default parameters on a 6 × 6 grid (288 points).
fn small_table() -> std::path::PathBuf {
    use wheelrail::table::{Axes, AxesSpec, AxisSpec};
    let pts = |p: &[f64]| {
        Some(AxisSpec {
            points: Some(p.to_vec()),
            ..Default::default()
        })
    };
    let axes = Axes::from_spec(&AxesSpec {
        creepage_x: Some(AxisSpec {
            points: Some(vec![0.0, 0.002, 0.01]),
            mirrored: Some(true),
            ..Default::default()
        }),
        creepage_y: pts(&[0.0, 0.002, 0.01]),
        spin: pts(&[-0.5, -0.1, 0.1, 0.5]),
        normal_force: pts(&[80e3, 120e3]),
        speed: pts(&[20.0, 40.0]),
        wetness: pts(&[0.0, 0.2]),
    })
    .unwrap();
    let mut params = wheelrail::Params::default();
    params.grid.nx = 6;
    params.grid.ny = 6;
    let dir =
        std::env::temp_dir().join(format!("wheelrail-fmu-bench-table-{}", std::process::id()));
    let mut files = wheelrail::table::build(&params, &axes, None, &|| ()).unwrap();
    files.write(&dir).unwrap();
    dir
}

fn do_step_table(c: &mut Criterion) {
    let guid = CString::new(WheelRailFriction::fmi2::description::guid(&INFO)).unwrap();
    let callbacks = Fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: null_mut(),
    };
    let dir = small_table();
    let dir_c = CString::new(dir.to_str().unwrap()).unwrap();
    unsafe {
        let fmu = fmi2Instantiate(
            c"bench".as_ptr(),
            FMI2_COSIMULATION,
            guid.as_ptr(),
            null(),
            &callbacks,
            0,
            0,
        );
        assert!(!fmu.is_null());
        assert_eq!(fmi2SetInteger(fmu, &(MODE as u32), 1, &1), 0);
        assert_eq!(fmi2SetInteger(fmu, &(GRID_SIZE as u32), 1, &6), 0);
        assert_eq!(
            fmi2SetString(fmu, &(TABLE_FILE as u32), 1, &dir_c.as_ptr()),
            0
        );
        assert_eq!(fmi2EnterInitializationMode(fmu), 0);
        assert_eq!(fmi2ExitInitializationMode(fmu), 0);
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
        let mut k = 0usize;
        c.bench_function("fmi2DoStep/table, dry, xi 0.3 %", |b| {
            b.iter(|| {
                k += 1;
                let xi = [0.003, 0.0031][k % 2];
                fmi2SetReal(fmu, &(CREEPAGE_LONGITUDINAL as u32), 1, &xi);
                black_box(fmi2DoStep(fmu, 0.0, 1e-3, 1))
            })
        });
        fmi2FreeInstance(fmu);
    }
    let _ = std::fs::remove_dir_all(dir);
}

criterion_group! {
    name = benches;
    // no plots: criterion's plotters backend needs system fonts
    config = Criterion::default().without_plots();
    targets = do_step, do_step_table
}
criterion_main!(benches);
