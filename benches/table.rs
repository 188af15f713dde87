//! Lookup time of a table with the default axes (issue 5 target: all outputs ≤ 1 µs, single thread).
//! The values come from the closed-form Polach law, which builds in about a second; the lookup cost does
//! not depend on the values.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use wheelrail::Params;
use wheelrail::params::FrictionLaw;
use wheelrail::table::verify::sample_points;
use wheelrail::table::{Axes, Kernel, Table, build};

fn bench(c: &mut Criterion) {
    let mut params = Params::default();
    params.friction.law = FrictionLaw::Polach;
    let files = build(&params, &Axes::default(), None, &|| ()).expect("build");
    let mut table = Table::from_files(files, None).expect("table");
    println!("table kernel detected on this CPU: {:?}", table.kernel());
    // random points and cell midpoints all over the ranges: a cold-ish cache, as for many wheels
    let points = sample_points(&table, 4096, 1);
    let mut g = c.benchmark_group("table");
    let mut i = 0;
    g.bench_function("evaluate_random_points", |b| {
        b.iter(|| {
            i = (i + 1) % points.len();
            table.evaluate(black_box(&points[i])).unwrap()
        })
    });
    g.bench_function("evaluate_with_jacobian_random_points", |b| {
        b.iter(|| {
            i = (i + 1) % points.len();
            table.evaluate_with_jacobian(black_box(&points[i])).unwrap()
        })
    });
    // one wheel moving slowly through the table: the same cells stay cached
    let p = points[1];
    g.bench_function("evaluate_same_point", |b| {
        b.iter(|| table.evaluate(black_box(&p)).unwrap())
    });
    // the same with the kernel every x86_64 CPU runs (SSE2, no FMA)
    table.set_kernel(Kernel::Portable).expect("portable kernel");
    g.bench_function("evaluate_same_point_portable_kernel", |b| {
        b.iter(|| table.evaluate(black_box(&p)).unwrap())
    });
    g.bench_function("evaluate_random_points_portable_kernel", |b| {
        b.iter(|| {
            i = (i + 1) % points.len();
            table.evaluate(black_box(&points[i])).unwrap()
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
