//! Cost of one `fmi2DoStep` in exact mode at the default grid (30 × 30 cells), through the exported C
//! functions: each iteration sets a new longitudinal creepage (alternating between two values, so every
//! step solves) and calls `fmi2DoStep`, dry and wet. Run with `cargo bench -p wheelrail-fmu`.

use WheelRailFriction::contact::variables::{CREEPAGE_LONGITUDINAL, INFO, MODE, WETNESS};
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

criterion_group! {
    name = benches;
    // no plots: criterion's plotters backend needs system fonts
    config = Criterion::default().without_plots();
    targets = do_step
}
criterion_main!(benches);
