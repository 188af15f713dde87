//! The coupled solver against the paper's qualitative findings and independent limits (MODEL.md §9–11).

use wheelrail::params::FrictionLaw;
use wheelrail::{OperatingPoint, Params, solve};

fn dry(xi: f64, speed: f64) -> OperatingPoint {
    OperatingPoint {
        creepage_x: xi,
        speed,
        ..Default::default()
    }
}

fn f_of(params: &Params, pt: &OperatingPoint) -> f64 {
    let s = solve(params, pt).unwrap();
    assert!(s.report.converged, "not converged: {:?}", s.report);
    s.global.traction_coefficient
}

#[test]
fn pure_rolling_gives_no_force_and_no_heating() {
    let p = Params::default();
    let s = solve(&p, &dry(0.0, 30.0)).unwrap();
    assert!(s.report.converged);
    assert_eq!(s.global.force_x, 0.0);
    assert_eq!(s.global.force_y, 0.0);
    assert_eq!(s.global.max_temperature, p.material.bulk_temperature);
}

#[test]
fn table1_dry_traction_near_one_percent_is_between_0_3_and_0_6() {
    let f = f_of(&Params::default(), &dry(0.01, 30.0));
    assert!((0.3..=0.6).contains(&f), "f = {f}");
}

#[test]
fn dry_curve_at_30_m_s_peaks_near_one_percent_and_falls_far_more_than_at_0_1_m_s() {
    let p = Params::default();
    let xis = [0.002, 0.005, 0.01, 0.02, 0.05, 0.1];
    let fast: Vec<f64> = xis.iter().map(|&x| f_of(&p, &dry(x, 30.0))).collect();
    let slow: Vec<f64> = xis.iter().map(|&x| f_of(&p, &dry(x, 0.1))).collect();
    let (kmax, fmax) = fast
        .iter()
        .enumerate()
        .fold((0, 0.0), |b, (k, &f)| if f > b.1 { (k, f) } else { b });
    assert!(
        (0.005..=0.02).contains(&xis[kmax]),
        "30 m/s peak at ξ = {} ({fast:?})",
        xis[kmax]
    );
    assert!(fast[0] < fmax, "curve must rise to its peak");
    let fall_fast = (fmax - fast[5]) / fmax;
    let smax = slow.iter().cloned().fold(0.0, f64::max);
    let fall_slow = (smax - slow[5]) / smax;
    assert!(
        fall_fast > 0.05,
        "30 m/s curve falls only {fall_fast} ({fast:?})"
    );
    assert!(
        fall_slow < 0.25 * fall_fast,
        "0.1 m/s falls {fall_slow}, 30 m/s {fall_fast}"
    );
}

#[test]
fn forces_are_odd_in_the_creepages_and_oppose_the_slip() {
    let p = Params::default();
    let a = solve(
        &p,
        &OperatingPoint {
            creepage_x: 0.004,
            creepage_y: -0.002,
            spin: 0.3,
            ..Default::default()
        },
    )
    .unwrap();
    let b = solve(
        &p,
        &OperatingPoint {
            creepage_x: -0.004,
            creepage_y: 0.002,
            spin: -0.3,
            ..Default::default()
        },
    )
    .unwrap();
    let g = |s: &wheelrail::Solution| [s.global.force_x, s.global.force_y, s.global.spin_moment];
    for (x, y) in g(&a).iter().zip(g(&b)) {
        // ξ → −ξ also swaps the wheel/rail surface speeds, so the heat problem is mirrored only
        // approximately; forces agree to a small fraction
        assert!(
            (x + y).abs() <= 0.02 * x.abs().max(1.0),
            "{:?} vs {:?}",
            g(&a),
            g(&b)
        );
    }
    assert!(
        a.global.force_x < 0.0,
        "positive ξ must give negative F_x (Kalker)"
    );
}

#[test]
fn constant_mu_saturates_at_mu_and_reports_temperature() {
    let mut p = Params::default();
    p.friction.law = FrictionLaw::Constant;
    p.friction.mu = 0.3;
    let s = solve(&p, &dry(0.2, 30.0)).unwrap();
    assert!(s.report.converged);
    // full slip: |F| = Σ μ p_n dA; the grid sum of the parabola is within 1 % of F_N
    assert!((s.global.traction_coefficient - 0.3).abs() < 0.3 * 0.01);
    assert!(s.global.max_temperature > p.material.bulk_temperature + 50.0);
}

#[test]
fn polach_gives_global_forces_without_fields() {
    let mut p = Params::default();
    p.friction.law = FrictionLaw::Polach;
    let s = solve(&p, &dry(0.01, 30.0)).unwrap();
    assert!(s.fields.is_none());
    assert!(s.global.force_x < 0.0 && s.global.traction_coefficient > 0.1);
}

#[test]
fn heat_off_keeps_bulk_temperature_and_raises_traction() {
    let mut p = Params::default();
    let hot = f_of(&p, &dry(0.05, 30.0));
    p.solver.heat = false;
    let s = solve(&p, &dry(0.05, 30.0)).unwrap();
    assert_eq!(s.global.max_temperature, p.material.bulk_temperature);
    assert!(s.global.traction_coefficient > hot);
}

#[test]
fn grid_convergence_below_one_percent() {
    // f changes by less than 1 % from the default grid to one twice as fine (dry, 30 m/s)
    let coarse = Params::default();
    let mut fine = Params::default();
    fine.grid.nx *= 2;
    fine.grid.ny *= 2;
    for xi in [0.002, 0.01, 0.1] {
        let fc = f_of(&coarse, &dry(xi, 30.0));
        let ff = f_of(&fine, &dry(xi, 30.0));
        let change = (fc - ff).abs() / ff;
        eprintln!("grid convergence ξ = {xi}: f = {fc:.5} (default) vs {ff:.5} (2x), {change:.4}");
        assert!(change < 0.01, "ξ = {xi}: {fc} vs {ff}");
    }
}

/// Relative difference of the global results that matter to a user (forces, f, temperature, fluid share).
fn global_difference(a: &wheelrail::Solution, b: &wheelrail::Solution) -> f64 {
    let fa = &a.global;
    let fb = &b.global;
    let scale = fa.normal_force;
    [
        (fa.force_x - fb.force_x).abs() / scale,
        (fa.force_y - fb.force_y).abs() / scale,
        (fa.traction_coefficient - fb.traction_coefficient).abs(),
        (fa.max_temperature - fb.max_temperature).abs() / (fa.max_temperature - 273.15),
        (fa.fluid_load_fraction - fb.fluid_load_fraction).abs(),
    ]
    .into_iter()
    .fold(0.0, f64::max)
}

#[test]
fn a_warm_start_converges_to_the_cold_solution_within_the_solver_tolerance() {
    let p = Params::default();
    // start from a far-away point (other creepage, load, speed, wetness) on the same grid topology
    let far = solve(
        &p,
        &OperatingPoint {
            creepage_x: 0.05,
            creepage_y: 0.003,
            normal_force: 150e3,
            speed: 10.0,
            wetness: 0.5,
            ..Default::default()
        },
    )
    .unwrap();
    for pt in [
        dry(0.01, 30.0),
        OperatingPoint {
            wetness: 1.0,
            ..dry(0.01, 30.0)
        },
        OperatingPoint {
            spin: 0.5,
            ..dry(-0.003, 60.0)
        },
    ] {
        let cold = solve(&p, &pt).unwrap();
        let warm = wheelrail::solve_from(&p, &pt, far.warm_start().as_ref()).unwrap();
        assert!(cold.report.converged && warm.report.converged);
        let d = global_difference(&cold, &warm);
        // each result is within the tolerance (1e-6, relative change per iteration) of the fixed point;
        // measured differences are ~1e-9
        assert!(d < 1e-6, "{pt:?}: warm differs from cold by {d}");
    }
    // another grid topology: the start is ignored, the result is the cold one exactly
    let mut fine = p.clone();
    fine.grid.nx = 20;
    fine.grid.ny = 20;
    let pt = dry(0.01, 30.0);
    assert_eq!(
        wheelrail::solve_from(&fine, &pt, far.warm_start().as_ref()).unwrap(),
        solve(&fine, &pt).unwrap()
    );
}

#[test]
fn a_continuation_sweep_equals_independent_solves() {
    let p = Params::default();
    let points: Vec<OperatingPoint> = (0..12)
        .map(|k| OperatingPoint {
            wetness: if k % 2 == 0 { 0.0 } else { 1.0 },
            ..dry(0.001 + 0.004 * k as f64, 30.0)
        })
        .collect();
    let swept = wheelrail::solver::solve_sweep(&p, &points);
    assert_eq!(swept.len(), points.len());
    for (pt, s) in points.iter().zip(swept) {
        let s = s.unwrap();
        let cold = solve(&p, pt).unwrap();
        assert!(s.report.converged);
        let d = global_difference(&cold, &s);
        assert!(d < 1e-6, "{pt:?}: sweep differs from cold by {d}");
    }
}

#[test]
fn a_sweep_gives_the_same_bits_whatever_the_thread_count() {
    let p = Params::default();
    let points: Vec<OperatingPoint> = (0..20)
        .map(|k| dry(0.0005 * (k + 1) as f64, 30.0))
        .collect();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| wheelrail::solver::solve_sweep(&p, &points))
            .into_iter()
            .map(|s| s.unwrap().global)
            .collect::<Vec<_>>()
    };
    assert_eq!(run(1), run(3));
}
