//! Lookup time of tables (issue 5 target: all outputs ≤ 1 µs; issue 13: ≤ 0.5 µs with the contact
//! geometry of every step), single thread:
//! - the bundled default table (fmu/resources/table) at random points and cell midpoints of its ranges;
//! - a table over contact geometry as large as the caches are not (3 million points, 150 MB in memory,
//!   values of a smooth synthetic function: the lookup cost does not depend on the values) at random
//!   contacts, loads, speeds, wetness and creepages.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::path::Path;
use wheelrail::Params;
use wheelrail::table::verify::sample_points;
use wheelrail::table::{Axes, AxesSpec, AxisSpec, Kernel, Table, tabulate};

/// A table over geometry with the default creepage axes and coarser linear axes.
fn geometry_table() -> Table {
    let points = |p: &[f64]| {
        Some(AxisSpec {
            points: Some(p.to_vec()),
            ..Default::default()
        })
    };
    let axes = Axes::from_spec(&AxesSpec {
        normal_force: points(&[10e3, 30e3, 80e3, 250e3]),
        speed: points(&[1.0, 5.0, 20.0, 50.0, 100.0]),
        wetness: points(&[0.0, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0]),
        semi_axis_ratio: points(&[0.2, 0.6, 1.7, 5.0]),
        reference_pressure: points(&[0.15e9, 0.4e9, 1.0e9, 2.5e9]),
        ..Default::default()
    })
    .expect("axes");
    let files = tabulate(&Params::default(), &axes, &|q| {
        let sat = |x: f64| (x / 0.4).tanh();
        let lin = 1.0 - 0.001 * q[4] - 0.3 * q[5];
        [
            -0.4 * lin * sat(q[0]),
            -0.4 * lin * (sat(q[1]) + 0.1 * sat(q[2])),
            0.01 * sat(q[2]),
            300.0 + 100.0 * q[0].abs().sqrt(),
            0.5 * q[5],
            0.01 * sat(q[0]).abs(),
        ]
    });
    Table::from_files(files, None).expect("table")
}

fn bench(c: &mut Criterion) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fmu/resources/table");
    let mut table = Table::load(&dir).expect("the bundled table");
    println!("table kernel detected on this CPU: {:?}", table.kernel());
    // random points and cell midpoints all over the ranges: a cold-ish cache, as for many wheels
    let points = sample_points(&table, 4096, 1);
    let mut g = c.benchmark_group("table");
    let mut i = 0;
    g.bench_function("evaluate_random_points", |b| {
        b.iter(|| {
            i = (i + 1) % points.len();
            let s = &points[i];
            table.evaluate(black_box(&s.point), &s.ellipse).unwrap()
        })
    });
    g.bench_function("evaluate_with_jacobian_random_points", |b| {
        b.iter(|| {
            i = (i + 1) % points.len();
            let s = &points[i];
            table
                .evaluate_with_jacobian(black_box(&s.point), &s.ellipse)
                .unwrap()
        })
    });
    // one wheel moving slowly through the table: the same cells stay cached
    let p = points[1];
    g.bench_function("evaluate_same_point", |b| {
        b.iter(|| table.evaluate(black_box(&p.point), &p.ellipse).unwrap())
    });
    // the same with the kernel every x86_64 CPU runs (SSE2, no FMA)
    table.set_kernel(Kernel::Portable).expect("portable kernel");
    g.bench_function("evaluate_same_point_portable_kernel", |b| {
        b.iter(|| table.evaluate(black_box(&p.point), &p.ellipse).unwrap())
    });
    g.bench_function("evaluate_random_points_portable_kernel", |b| {
        b.iter(|| {
            i = (i + 1) % points.len();
            let s = &points[i];
            table.evaluate(black_box(&s.point), &s.ellipse).unwrap()
        })
    });
    drop(table);
    // random contact geometry every evaluation
    let table = geometry_table();
    let points = sample_points(&table, 4096, 2);
    g.bench_function("evaluate_random_geometry", |b| {
        b.iter(|| {
            i = (i + 1) % points.len();
            let s = &points[i];
            table.evaluate(black_box(&s.point), &s.ellipse).unwrap()
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = bench
}
criterion_main!(benches);
