//! Lookup time of tables (target: all outputs ≤ 1 µs; ≤ 0.5 µs with the contact
//! geometry of every step), single thread:
//! - the bundled default table (fmu/resources/table) at random points and cell midpoints of its ranges;
//! - a table on the nodes of the whole-range table (tools/whole-range-axes.toml: 46 million points,
//!   2.2 GB in memory; values of a smooth synthetic function, `table::build::timing_files`, as the lookup
//!   cost does not depend on them):
//!   one wet point again and again (an MBS contact whose stencil stays cached), a new contact ellipse
//!   every evaluation around the default one (the FMU bench's random-geometry case: a few cells), and
//!   random points all over the table (every stencil from memory: the worst case, many contacts far
//!   apart); the new-ellipse case also with the AVX2 kernel where the CPU runs the AVX-512 one.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::path::Path;
use wheelrail::OperatingPoint;
use wheelrail::Params;
use wheelrail::table::build::timing_files;
use wheelrail::table::coords::{Ellipse, semi_axes};
use wheelrail::table::verify::{SplitMix64, sample_points};
use wheelrail::table::{Axes, Kernel, Table};

/// A table on the nodes of the whole-range table (by similarity: 12 linear corners), of synthetic values
/// ([`wheelrail::table::build::timing_files`]).
fn whole_range_table() -> Table {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/whole-range-axes.toml");
    let axes = Axes::from_toml_file(&file).expect("the whole-range axes");
    let files = timing_files(&Params::default(), &axes).expect("the timing files");
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
    let mut table = whole_range_table();
    // wet, all three creepages off their nodes, every linear corner weighted (the stencil in full)
    let wet = OperatingPoint {
        creepage_x: 0.003,
        creepage_y: 0.002,
        spin: 0.1,
        normal_force: 100e3,
        speed: 30.0,
        wetness: 0.07,
    };
    let ellipse = |[a, b]: [f64; 2]| Ellipse {
        a,
        b,
        load_exponent: 0.0,
    };
    let default_contact = ellipse(semi_axes(0.558, 0.771e9, 100e3));
    g.bench_function("whole-range nodes/evaluate_same_point_wet", |b| {
        b.iter(|| table.evaluate(black_box(&wet), &default_contact).unwrap())
    });
    let mut rng = SplitMix64::new(13);
    let contacts: Vec<Ellipse> = (0..1024)
        .map(|_| {
            let ratio = 0.5 + 0.1 * rng.uniform();
            let p_ref = 0.70e9 + 0.15e9 * rng.uniform();
            ellipse(semi_axes(ratio, p_ref, 100e3))
        })
        .collect();
    g.bench_function("whole-range nodes/evaluate_random_geometry_wet", |b| {
        b.iter(|| {
            i = (i + 1) % contacts.len();
            table.evaluate(black_box(&wet), &contacts[i]).unwrap()
        })
    });
    // the same with the AVX2 kernel where the CPU runs a faster one (AVX-512)
    if table.kernel() != Kernel::Avx2Fma && table.set_kernel(Kernel::Avx2Fma).is_ok() {
        g.bench_function(
            "whole-range nodes/evaluate_random_geometry_wet_avx2_kernel",
            |b| {
                b.iter(|| {
                    i = (i + 1) % contacts.len();
                    table.evaluate(black_box(&wet), &contacts[i]).unwrap()
                })
            },
        );
        table
            .set_kernel(Kernel::detect())
            .expect("the detected kernel");
    }
    let points = sample_points(&table, 1 << 16, 2);
    g.bench_function("whole-range nodes/evaluate_random_points", |b| {
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
