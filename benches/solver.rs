//! Time per operating point of the exact solver and of the fast alternatives (Table 1 conditions, single
//! thread), a 50-point traction–creepage sweep with warm starts, the exact dry point against the grid
//! size (for the scaling exponent), and one exact MBS step per grid, cold and warm (`exact_step`); the point
//! also with the exact tangential solver in place of FASTSIM (`exact_tangential_*`).
//! `make bench` prints all of them with their ratio to Polach.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use wheelrail::baselines::polach;
use wheelrail::params::FrictionLaw;
use wheelrail::solver::{normal_contact, solve_sweep};
use wheelrail::tangential::{Creepages, kalker_coefficients};
use wheelrail::{OperatingPoint, Params, Tangential, solve};

fn point(xi: f64, wetness: f64) -> OperatingPoint {
    OperatingPoint {
        creepage_x: xi,
        wetness,
        ..Default::default()
    }
}

fn with_law(law: FrictionLaw) -> Params {
    let mut p = Params::default();
    p.friction.law = law;
    p
}

/// The default parameters with the exact tangential solver (`tangential = "exact"`).
fn with_exact_tangential() -> Params {
    Params {
        tangential: Tangential::Exact,
        ..Params::default()
    }
}

fn points(c: &mut Criterion) {
    let mut g = c.benchmark_group("point");
    g.sample_size(10);
    let cases = [
        ("exact_dry_1pct_30mps", Params::default(), 0.0),
        ("exact_wet_1pct_30mps", Params::default(), 1.0),
        (
            "fastsim_constant_mu_1pct_30mps",
            with_law(FrictionLaw::Constant),
            0.0,
        ),
        ("polach_1pct_30mps", with_law(FrictionLaw::Polach), 0.0),
        // the coupled solver with Kalker's exact steady rolling instead of FASTSIM (docs/model.md §6.6)
        (
            "exact_tangential_dry_1pct_30mps",
            with_exact_tangential(),
            0.0,
        ),
        (
            "exact_tangential_wet_1pct_30mps",
            with_exact_tangential(),
            1.0,
        ),
    ];
    for (name, params, wetness) in cases {
        let pt = point(0.01, wetness);
        g.bench_function(name, |b| {
            b.iter(|| solve(black_box(&params), black_box(&pt)).unwrap())
        });
    }
    // the bare Polach formula, with the contact (Hertz, Kalker's coefficients) computed beforehand as an
    // MBS code that caches them per contact would
    let params = Params::default();
    let hertz = normal_contact(&params, 100e3).unwrap();
    let mat = params.material.at(params.material.bulk_temperature);
    let kalker = kalker_coefficients(hertz.a, hertz.b, mat.poisson).unwrap();
    let creep = Creepages {
        xi: 0.01,
        eta: 0.0,
        phi: 0.0,
    };
    g.bench_function("polach_formula_only_1pct_30mps", |b| {
        b.iter(|| {
            polach(
                black_box(&params.friction.polach),
                hertz.a,
                hertz.b,
                100e3,
                mat.shear_modulus,
                &kalker,
                black_box(creep),
                30.0,
            )
            .unwrap()
        })
    });
    g.finish();
}

/// A 50-point sweep ξ = 0.1 … 5 % with warm starts, on one thread and on all cores.
fn sweeps(c: &mut Criterion) {
    let mut g = c.benchmark_group("sweep");
    g.sample_size(10);
    let params = Params::default();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("thread pool");
    for wetness in [0.0, 1.0] {
        let pts: Vec<OperatingPoint> = (0..50)
            .map(|k| point(0.001 + 0.049 * k as f64 / 49.0, wetness))
            .collect();
        let label = if wetness > 0.0 { "wet" } else { "dry" };
        g.bench_function(format!("curve_50_points_{label}_1_thread"), |b| {
            b.iter(|| one.install(|| solve_sweep(black_box(&params), black_box(&pts))))
        });
        g.bench_function(format!("curve_50_points_{label}_all_threads"), |b| {
            b.iter(|| solve_sweep(black_box(&params), black_box(&pts)))
        });
    }
    g.finish();
}

/// The exact dry point (1 %, 30 m/s) on n × n grids.
fn grid_scaling(c: &mut Criterion) {
    let mut g = c.benchmark_group("grid_scaling");
    g.sample_size(10);
    for n in [10, 15, 20, 30, 45, 60] {
        let mut params = Params::default();
        params.grid.nx = n;
        params.grid.ny = n;
        let pt = point(0.01, 0.0);
        let cells = solve(&params, &pt)
            .unwrap()
            .fields
            .expect("fields")
            .grid
            .len();
        g.bench_with_input(
            BenchmarkId::new("exact_dry_cells", cells),
            &params,
            |b, p| b.iter(|| solve(black_box(p), black_box(&pt)).unwrap()),
        );
    }
    g.finish();
}

/// One exact step of an MBS run per grid (n × n cells; 7 × 7 is the grid that keeps the MBS trace within 1 %
/// of F_N of the grid-converged forces) at ξ = 1 %, 30 m/s, 100 kN, dry and wet, as the
/// FMU's exact mode takes it (`Model::solve_from`, the model keeping its set-up):
/// - `cold`: no warm start (the same point every time, so with the set-up reused);
/// - `warm`: from the state of the step before, a 1 kHz step earlier: load +1 %, speed −0.5 mm/s, ξ
///   +0.1 % (relative), so the contact and the surface speeds change and the set-up is made anew, as in an
///   MBS run (the steps alternate between the two points);
/// - `warm_same_contact`: as `warm` with only η changing (±1e-4), so the contact and the surface speeds are
///   the last step's and the set-up (heat model above all) is reused: the cost of the outer iterations
///   alone.
fn exact_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("exact_step");
    g.sample_size(10)
        .warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2));
    for n in [7, 9, 15, 20, 30] {
        let mut params = Params::default();
        params.grid.nx = n;
        params.grid.ny = n;
        let model = wheelrail::Model::new(params).expect("valid parameters");
        for wetness in [0.0, 1.0] {
            let label = if wetness > 0.0 { "wet" } else { "dry" };
            let a = point(0.01, wetness);
            let next = OperatingPoint {
                normal_force: a.normal_force * 1.01,
                speed: a.speed - 5e-4,
                creepage_x: a.creepage_x * 1.001,
                ..a
            };
            let other_eta = OperatingPoint {
                creepage_y: 1e-4,
                ..a
            };
            g.bench_function(format!("{n}x{n}/{label}/cold"), |b| {
                b.iter(|| model.solve(black_box(&a)).unwrap())
            });
            for (name, pair) in [("warm", [a, next]), ("warm_same_contact", [a, other_eta])] {
                let mut warm = model.solve(&pair[0]).unwrap().warm_start();
                let mut k = 0;
                g.bench_function(format!("{n}x{n}/{label}/{name}"), |b| {
                    b.iter(|| {
                        k += 1;
                        let s = model
                            .solve_from(black_box(&pair[k % 2]), warm.as_ref())
                            .unwrap();
                        warm = s.warm_start();
                        s.report.iterations
                    })
                });
            }
        }
    }
    g.finish();
}

/// Kalker's exact steady rolling alone (constant μ = 0.3, Hertz pressure, reference contact) on n × n grids,
/// cold start: the operator's set-up and the solve to the default tolerance.
fn exact_tangential(c: &mut Criterion) {
    use wheelrail::contact::{ContactGrid, HertzContact};
    use wheelrail::tangential::exact::{ExactSettings, SteadyRolling};
    let mut g = c.benchmark_group("exact_tangential");
    g.sample_size(10);
    let params = Params::default();
    let hertz: HertzContact = normal_contact(&params, 100e3).unwrap();
    let mat = params.material.at(params.material.bulk_temperature);
    for n in [15, 30] {
        let grid = ContactGrid::for_contact(&hertz, n, n);
        let bound: Vec<f64> = grid
            .cells
            .iter()
            .map(|c| {
                let s = 1.0 - (c.x / hertz.a).powi(2) - (c.y / hertz.b).powi(2);
                0.3 * hertz.p0 * s.max(0.0).sqrt()
            })
            .collect();
        g.bench_function(format!("setup_{n}x{n}"), |b| {
            b.iter(|| SteadyRolling::new(black_box(&grid), mat.shear_modulus, mat.poisson).unwrap())
        });
        let op = SteadyRolling::new(&grid, mat.shear_modulus, mat.poisson).unwrap();
        for xi in [0.001, 0.003] {
            let creep = Creepages {
                xi,
                eta: 0.0,
                phi: 0.0,
            };
            g.bench_function(format!("solve_{n}x{n}_xi_{xi}"), |b| {
                b.iter(|| {
                    op.solve(
                        &grid,
                        black_box(creep),
                        30.0,
                        &bound,
                        None,
                        ExactSettings::default(),
                    )
                    .unwrap()
                })
            });
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    // no plots: criterion's plotting backend needs system fonts
    config = Criterion::default().without_plots();
    targets = points, sweeps, grid_scaling, exact_step, exact_tangential
}
criterion_main!(benches);
