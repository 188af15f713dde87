//! Time per operating point of the exact solver and of the fast alternatives (Table 1 conditions).

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use wheelrail::params::FrictionLaw;
use wheelrail::{OperatingPoint, Params, solve};

fn point(xi: f64) -> OperatingPoint {
    OperatingPoint {
        creepage_x: xi,
        ..Default::default()
    }
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("point");
    g.sample_size(10);
    let dry = Params::default();
    g.bench_function("exact_dry_1pct_30mps", |b| {
        b.iter(|| solve(black_box(&dry), black_box(&point(0.01))).unwrap())
    });
    let wet = OperatingPoint {
        wetness: 1.0,
        ..point(0.01)
    };
    g.bench_function("exact_wet_1pct_30mps", |b| {
        b.iter(|| solve(black_box(&dry), black_box(&wet)).unwrap())
    });
    let mut constant = Params::default();
    constant.friction.law = FrictionLaw::Constant;
    g.bench_function("fastsim_constant_mu_1pct_30mps", |b| {
        b.iter(|| solve(black_box(&constant), black_box(&point(0.01))).unwrap())
    });
    let mut polach = Params::default();
    polach.friction.law = FrictionLaw::Polach;
    g.bench_function("polach_1pct_30mps", |b| {
        b.iter(|| solve(black_box(&polach), black_box(&point(0.01))).unwrap())
    });
    g.finish();
}

criterion_group! {
    name = benches;
    // no plots: criterion's plotting backend needs system fonts
    config = Criterion::default().without_plots();
    targets = bench
}
criterion_main!(benches);
