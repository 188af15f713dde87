//! The coupled solver against the paper's qualitative findings and independent limits (docs/model.md §9–11).

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
    assert_eq!(
        s.global.max_temperature.unwrap(),
        p.material.bulk_temperature
    );
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
    let g = |s: &wheelrail::Solution| {
        [
            s.global.force_x,
            s.global.force_y,
            s.global.spin_moment.unwrap(),
        ]
    };
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
    assert!(s.global.max_temperature.unwrap() > p.material.bulk_temperature + 50.0);
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
    assert_eq!(
        s.global.max_temperature.unwrap(),
        p.material.bulk_temperature
    );
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

/// `grid.accuracy` keeps its promise on the hardest cases of the measured convergence (docs/model.md §6.4):
/// the flange-root shape a/b = 5 under spin 3 /m, dry (the largest error on 8 × 8), and the default
/// contact wet with ξ = η = 0.2 % and 3 /m: at the cells chosen for 1 % and 0.5 % the forces are within the
/// target of the 120 × 120 solution, and the coarser grid the table rejects misses 0.5 % on the first.
#[test]
fn an_accuracy_target_chooses_a_grid_that_meets_it() {
    let flange = |p: &mut Params| p.geometry.semi_axes = Some([0.017601, 0.0035202]);
    type Case = (fn(&mut Params), OperatingPoint);
    let cases: [Case; 2] = [
        (
            flange,
            OperatingPoint {
                spin: 3.0,
                ..dry(0.0, 30.0)
            },
        ),
        (
            |_| {},
            OperatingPoint {
                creepage_x: 0.002,
                creepage_y: 0.002,
                spin: 3.0,
                wetness: 1.0,
                ..dry(0.0, 30.0)
            },
        ),
    ];
    let force_error = |a: &wheelrail::Solution, b: &wheelrail::Solution| {
        (a.global.force_x - b.global.force_x).hypot(a.global.force_y - b.global.force_y)
            / b.global.normal_force
    };
    for (k, (shape, point)) in cases.iter().enumerate() {
        let mut reference = Params::default();
        shape(&mut reference);
        reference.grid.nx = 120;
        reference.grid.ny = 120;
        let fine = solve(&reference, point).unwrap();
        assert!(fine.report.converged);
        for accuracy in [0.01, 0.005] {
            let mut p = Params::default();
            shape(&mut p);
            p.grid.accuracy = accuracy;
            let [n, _] = p.grid.cells();
            let s = solve(&p, point).unwrap();
            let e = force_error(&s, &fine);
            eprintln!("case {k}: accuracy {accuracy} -> {n} x {n}: |dF|/F_N {e:.2e}");
            assert!(
                s.report.converged && e <= accuracy,
                "case {k}, {n} x {n}: {e}"
            );
        }
        if k == 0 {
            let mut p = Params::default();
            shape(&mut p);
            p.grid.nx = 8;
            p.grid.ny = 8;
            let e = force_error(&solve(&p, point).unwrap(), &fine);
            assert!(e > 0.005, "8 x 8: {e}");
        }
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
        (fa.max_temperature.unwrap() - fb.max_temperature.unwrap()).abs()
            / (fa.max_temperature.unwrap() - 273.15),
        (fa.fluid_load_fraction.unwrap() - fb.fluid_load_fraction.unwrap()).abs(),
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

/// An unconverged solve says which solver kept it from converging: one outer iteration while the
/// temperature still moves is limited by the outer iteration; a one-sweep film with heat off (where one
/// outer iteration would do) by the film. (The heat partition's GMRES budget is a constant that the
/// solver's grids never exhaust: that limiter is tested with the convergence criterion in
/// src/solver/report.rs.)
#[test]
fn an_unconverged_solve_names_the_solver_that_limited_it() {
    use wheelrail::solver::{Limiter, Termination};
    let mut p = Params::default();
    p.grid.nx = 12;
    p.grid.ny = 12;
    let wet = OperatingPoint {
        wetness: 1.0,
        ..dry(0.01, 30.0)
    };
    let limited = |p: &Params, pt: &OperatingPoint| {
        let s = solve(p, pt).unwrap();
        assert_eq!(s.report.converged, s.report.termination.converged());
        s.report.termination.limited_by()
    };
    assert_eq!(limited(&p, &dry(0.01, 30.0)), None);
    p.solver.max_iterations = 1;
    let s = solve(&p, &dry(0.01, 30.0)).unwrap();
    assert!(!s.report.converged && s.report.iterations == 1);
    assert_eq!(
        s.report.termination,
        Termination::MaxIterationsReached {
            limited_by: Limiter::Outer
        }
    );
    assert_eq!(limited(&p, &wet), Some(Limiter::Outer));
    p.solver.heat = false;
    assert_eq!(limited(&p, &wet), None);
    p.solver.max_fluid_sweeps = 1;
    assert_eq!(limited(&p, &wet), Some(Limiter::Film));
    // given the iterations, the outer iteration makes up for a one-sweep film (each film starts from the
    // last)
    p.solver.max_iterations = 100;
    assert_eq!(limited(&p, &wet), None);
}

/// What a law does not model is absent, never a made-up number: Polach has no spin moment, temperature or
/// fluid; the constant law has temperatures but no fluid (it ignores the wetness); with heat off the
/// temperature is T0, the model's answer.
#[test]
fn quantities_a_law_does_not_model_are_absent() {
    let wet = OperatingPoint {
        wetness: 1.0,
        creepage_y: 0.002,
        spin: 0.5,
        ..dry(0.01, 30.0)
    };
    let mut p = Params::default();
    p.grid.nx = 12;
    p.grid.ny = 12;
    let t = solve(&p, &wet).unwrap().global;
    let fluid = |g: &wheelrail::solver::GlobalResults| {
        [
            g.fluid_load_fraction,
            g.mixed_lubrication_area_fraction,
            g.boundary_lubrication_area_fraction,
            g.fluid_mass_balance_error,
            g.fluid_rejected_fraction,
            g.min_separation,
            g.max_dry_area_fraction,
        ]
    };
    assert!(fluid(&t).iter().all(Option::is_some));
    assert!(t.spin_moment.unwrap() != 0.0 && t.max_temperature.unwrap() > 300.0);
    p.friction.law = FrictionLaw::Constant;
    let c = solve(&p, &wet).unwrap().global;
    assert!(fluid(&c).iter().all(Option::is_none));
    assert!(c.spin_moment.is_some() && c.max_temperature.unwrap() > 300.0);
    assert!(c.mean_temperature.is_some());
    p.friction.law = FrictionLaw::Polach;
    let g = solve(&p, &wet).unwrap().global;
    assert!(fluid(&g).iter().all(Option::is_none));
    assert_eq!(
        (g.spin_moment, g.max_temperature, g.mean_temperature),
        (None, None, None)
    );
    assert!(g.force_y < 0.0);
    p.friction.law = FrictionLaw::Tomberger;
    p.solver.heat = false;
    let cold = solve(&p, &wet).unwrap().global;
    let t0 = p.material.bulk_temperature;
    assert_eq!(cold.max_temperature, Some(t0));
    assert!((cold.mean_temperature.unwrap() - t0).abs() < 1e-9 * t0);
}

/// The heat partition's reported GMRES residual is the relative residual ‖G_r·q − (G_w + G_r)·q_w‖/‖G_r·q‖
/// of the returned fields (heat flux q and its share into the wheel q_w), recomputed here with the heat
/// model's influence kernels; and the temperature rise is G_w·q_w.
#[test]
fn the_reported_heat_residual_is_that_of_the_returned_heat_partition() {
    use wheelrail::solver::surface_speeds;
    use wheelrail::thermal::{Body, HeatModel};
    let p = Params::default();
    for pt in [dry(0.01, 30.0), dry(0.05, 10.0)] {
        let s = solve(&p, &pt).unwrap();
        let f = s.fields.as_ref().unwrap();
        let (v_w, v_r) = surface_speeds(&pt);
        // the solver's heat model: influence coefficients interpolated in the unit-cell lattice
        // (docs/model.md §7.2)
        let heat = HeatModel::interpolated(&f.grid, v_w, v_r, &p.material).unwrap();
        let q_rail: Vec<f64> = f
            .heat_flux
            .iter()
            .zip(&f.heat_flux_wheel)
            .map(|(q, w)| q - w)
            .collect();
        let rail = heat.one_body_rise(Body::Rail, &q_rail).unwrap();
        let wheel = heat.one_body_rise(Body::Wheel, &f.heat_flux_wheel).unwrap();
        let rhs = heat.one_body_rise(Body::Rail, &f.heat_flux).unwrap();
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let r: Vec<f64> = rail.iter().zip(&wheel).map(|(a, b)| a - b).collect();
        let residual = norm(&r) / norm(&rhs);
        let reported = s.report.heat_residual;
        assert!(
            reported <= 1e-12 && residual <= 1e-12,
            "{reported} vs {residual}"
        );
        // equal up to the rounding of two ways of applying the kernels
        assert!(
            residual > 0.0 && (residual - reported).abs() <= 1e-2 * residual,
            "{pt:?}: reported {reported}, recomputed {residual}"
        );
        for (t, w) in f.temperature.iter().zip(&wheel) {
            assert!((t - p.material.bulk_temperature - w).abs() <= 1e-9 * w.abs().max(1.0));
        }
    }
}

/// The dimensionless outputs of one solve: F_x/F_N, F_y/F_N, M_z/(F_N·c), T_max [K], the fluid load
/// fraction, P_f/(F_N·V), with c = sqrt(a·b).
fn similarity_invariants(params: &Params, pt: &OperatingPoint) -> [f64; 6] {
    let s = solve(params, pt).unwrap();
    assert!(s.report.converged, "not converged: {:?}", s.report);
    let g = &s.global;
    let (f, c) = (pt.normal_force, (g.semi_axis_a * g.semi_axis_b).sqrt());
    [
        g.force_x / f,
        g.force_y / f,
        g.spin_moment.unwrap() / (f * c),
        g.max_temperature.unwrap(),
        g.fluid_load_fraction.unwrap_or(0.0),
        g.frictional_power / (f * pt.speed),
    ]
}

/// Similarity of the model (docs/model.md §9.1): a contact λ times as large at the same peak pressure
/// (semi-axes λ·a, λ·b, so F_N → λ²·F_N; or curvatures A/λ, B/λ under Hertz) rolling at V/λ with spin φ/λ
/// and the same ξ, η and wetness has the same dimensionless outputs. The contact's size and speed enter
/// only through c·V: the heat (flux μ·p·V·ξ, Péclet number V·a/κ, temperature rise ∝ μ·p0·ξ·sqrt(a·V)),
/// the film (transport by the surfaces ∝ V·h against pressure-driven flow ∝ h³·p0/(η·a)) and FASTSIM
/// (spin slip φ·y over y ∝ c) — so a table needs no separate axes for F_N and V once p0 is one.
/// Checked dry and wet, cool and hot (T_max up to ≈ 600 K), with both geometry inputs and both
/// tangential theories, for λ from 1/4 to 2; and, as a control, that the size alone (V kept) does change
/// the outputs.
#[test]
fn outputs_depend_on_size_and_speed_only_through_their_product() {
    use wheelrail::params::{Geometry, Tangential};
    let mut base = Params::default();
    base.grid.nx = 10;
    base.grid.ny = 10;
    let pt = |w: f64| OperatingPoint {
        creepage_x: 0.04,
        creepage_y: -0.01,
        spin: 0.4,
        normal_force: 100e3,
        speed: 30.0,
        wetness: w,
    };
    let scaled = |p: &OperatingPoint, l: f64, speed_too: bool| OperatingPoint {
        normal_force: p.normal_force * l * l,
        speed: if speed_too { p.speed / l } else { p.speed },
        spin: p.spin / l,
        ..*p
    };
    let semi = |p: &Params, l: f64| {
        let mut q = p.clone();
        q.geometry = Geometry {
            semi_axes: Some([0.006 * l, 0.010 * l]),
            ..q.geometry
        };
        q
    };
    let curv = |p: &Params, l: f64| {
        let mut q = p.clone();
        q.geometry.curvature_x /= l;
        q.geometry.curvature_y /= l;
        q
    };
    let mut exact = base.clone();
    exact.tangential = Tangential::Exact;
    let cases: [(&Params, f64, &[f64]); 3] = [
        (&base, 0.0, &[0.25, 0.5, 2.0]),
        (&base, 0.1, &[0.5, 2.0]),
        (&exact, 0.0, &[2.0]),
    ];
    for (params, w, lambdas) in cases {
        for geometry in [semi, curv] {
            let reference = similarity_invariants(&geometry(params, 1.0), &pt(w));
            for &l in lambdas {
                let other = similarity_invariants(&geometry(params, l), &scaled(&pt(w), l, true));
                for (k, (x, y)) in other.iter().zip(&reference).enumerate() {
                    assert!(
                        (x - y).abs() <= 1e-9 * y.abs().max(1e-3),
                        "output {k}, λ = {l}, w = {w}, {:?}: {x} against {y}",
                        params.tangential
                    );
                }
            }
            // the control: twice the size at the same speed heats more (c·V doubled)
            let bigger = similarity_invariants(&geometry(params, 2.0), &scaled(&pt(w), 2.0, false));
            assert!(
                bigger[3] > reference[3] + 5.0,
                "T_max {} against {}",
                bigger[3],
                reference[3]
            );
        }
    }
}
