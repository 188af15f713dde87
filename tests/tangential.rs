//! The full model with the exact tangential solver (`tangential = "exact"`, docs/model.md §6.5): against
//! the steady-rolling solver called directly, full slip, the odd symmetry of the creepages, Kalker's linear
//! theory and warm starts.

use wheelrail::contact::ContactGrid;
use wheelrail::params::{FrictionLaw, Pressure, Tangential};
use wheelrail::solver::normal_contact;
use wheelrail::tangential::exact::{ExactSettings, SteadyRolling};
use wheelrail::tangential::{Creepages, kalker_coefficients};
use wheelrail::{OperatingPoint, Params, Solution, solve, solve_from};

/// The default parameters with the exact tangential solver.
fn exact() -> Params {
    Params {
        tangential: Tangential::Exact,
        ..Params::default()
    }
}

/// Constant μ = 0.3 and no heating: the traction bound is μ·p_n, fixed.
fn constant_mu() -> Params {
    let mut p = exact();
    p.friction.law = FrictionLaw::Constant;
    p.friction.mu = 0.3;
    p.solver.heat = false;
    p
}

/// The default operating point at creepages (ξ, η, φ).
pub(crate) fn point(xi: f64, eta: f64, phi: f64) -> OperatingPoint {
    OperatingPoint {
        creepage_x: xi,
        creepage_y: eta,
        spin: phi,
        ..Default::default()
    }
}

/// The solution of `params` at `pt`, which must have converged.
pub(crate) fn converged(params: &Params, pt: &OperatingPoint) -> Solution {
    let s = solve(params, pt).unwrap();
    assert!(s.report.converged, "{:?}", s.report);
    s
}

/// With constant μ and heat off the model's traction is Kalker's exact steady rolling under the bound
/// μ·p_n with Hertz's ellipsoidal pressure: the same forces as `SteadyRolling::solve` called directly.
#[test]
fn exact_mode_is_steady_rolling_under_mu_times_the_hertz_pressure() {
    let p = constant_mu();
    let pt = point(0.001, -0.0005, 0.3);
    let s = converged(&p, &pt);
    assert_eq!(p.pressure_shape(), Pressure::Hertz);
    let hertz = normal_contact(&p, pt.normal_force).unwrap();
    let grid = ContactGrid::for_contact(&hertz, p.grid.nx, p.grid.ny);
    let mat = p.material.at(p.material.bulk_temperature);
    let op = SteadyRolling::new(&grid, mat.shear_modulus, mat.poisson).unwrap();
    let bound: Vec<f64> = grid
        .cells
        .iter()
        .map(|c| p.friction.mu * hertz.hertz_pressure(c.x, c.y))
        .collect();
    let creep = Creepages {
        xi: pt.creepage_x,
        eta: pt.creepage_y,
        phi: pt.spin,
    };
    let direct = op
        .solve(
            &grid,
            creep,
            pt.speed,
            &bound,
            None,
            ExactSettings::default(),
        )
        .unwrap();
    assert!(direct.converged);
    let fns = pt.normal_force;
    for (model, want) in [
        (s.global.force_x, direct.field.force_x),
        (s.global.force_y, direct.field.force_y),
        (s.global.spin_moment.unwrap(), direct.field.spin_moment),
    ] {
        assert!(
            (model - want).abs() <= 1e-9 * fns,
            "model {model} vs direct {want}"
        );
    }
    // partial slip here, so the case tells the methods apart: FASTSIM differs by more than 1 %
    let fastsim = converged(
        &Params {
            tangential: Tangential::Fastsim,
            ..p.clone()
        },
        &pt,
    );
    assert!(
        (fastsim.global.force_x - direct.field.force_x).abs() > 0.01 * direct.field.force_x.abs()
    );
    assert_eq!(s.report.tangential_sweeps, direct.sweeps);
    assert!(s.report.tangential_residual <= ExactSettings::default().tolerance);
    // the fields carry the pressure used
    let fields = s.fields.unwrap();
    assert_eq!(
        fields.nominal_pressure[0],
        hertz.hertz_pressure(grid.cells[0].x, grid.cells[0].y)
    );
}

/// At large creepage every cell slips: |F| = μ·Σ p_n dA (up to the slight misalignment of the cells'
/// slip directions, which only lowers |F|), within 0.5 % of μ·F_N on the default grid.
#[test]
fn exact_mode_saturates_at_mu_times_the_normal_force() {
    let p = constant_mu();
    let s = converged(&p, &point(0.05, 0.0, 0.0));
    let fields = s.fields.as_ref().unwrap();
    assert!(fields.slipping.iter().all(|x| *x));
    let carried = fields.grid.integrate(&fields.nominal_pressure);
    let f = s.global.traction_coefficient;
    let saturated = 0.3 * carried / s.global.normal_force;
    assert!(
        f <= saturated * (1.0 + 1e-12) && f >= saturated * (1.0 - 1e-4),
        "f = {f}, mu sum p dA / F_N = {saturated}"
    );
    assert!((f - 0.3).abs() <= 0.005 * 0.3, "f = {f}");
    assert!(s.global.force_x < 0.0);
}

/// Reversing every creepage reverses every force and the spin moment (the full model's local limit,
/// dry, heat off: τ_l depends on the pressure only).
#[test]
fn exact_mode_is_odd_in_the_creepages() {
    let mut p = exact();
    p.solver.heat = false;
    for (xi, eta, phi) in [(0.002, 0.0, 0.0), (0.0, 0.001, 0.0), (0.0008, -0.0004, 0.4)] {
        let a = converged(&p, &point(xi, eta, phi)).global;
        let b = converged(&p, &point(-xi, -eta, -phi)).global;
        let tol = 1e-6 * a.normal_force;
        assert!((a.force_x + b.force_x).abs() <= tol, "{xi} {eta} {phi}");
        assert!((a.force_y + b.force_y).abs() <= tol, "{xi} {eta} {phi}");
        assert!(
            (a.spin_moment.unwrap() + b.spin_moment.unwrap()).abs() <= tol * a.semi_axis_b,
            "{xi} {eta} {phi}"
        );
        assert!(a.traction_coefficient > 0.0);
    }
}

/// In the linear limit (full stick) the full model with the exact solver gives Kalker's
/// F_x = −G·c²·C11·ξ: within 2.5 % on the default 30 × 30 grid (measured +2.0 %: the scheme is first
/// order in the cell size) and within 1 % on 60 × 60 (measured +0.3 %); and the spin moment of lateral
/// creepage, M_z = G·c³·C23·η, within 2 % (measured −0.1 %, −0.9 %), which FASTSIM misses by 30 %
/// (its independent flexibilities; measured 0.028 against 0.040 N·m).
#[test]
fn exact_mode_linear_limit_is_kalkers_c11() {
    let mut p = exact();
    let xi = 1e-6;
    for (cells, tolerance) in [(30, 0.025), (60, 0.01)] {
        p.grid.nx = cells;
        p.grid.ny = cells;
        // heat is negligible at this creepage; it is switched off on the fine grid only to save time
        p.solver.heat = cells == 30;
        let s = converged(&p, &point(xi, 0.0, 0.0));
        let mat = p.material.at(p.material.bulk_temperature);
        let (a, b) = (s.global.semi_axis_a, s.global.semi_axis_b);
        let k = kalker_coefficients(a, b, mat.poisson).unwrap();
        let want = -mat.shear_modulus * a * b * k.c11 * xi;
        let got = s.global.force_x;
        assert!(
            (got - want).abs() <= tolerance * want.abs(),
            "{cells} cells: {got} vs Kalker {want}"
        );
        assert!(s.fields.unwrap().slipping.iter().all(|x| !x));
        let s = converged(&p, &point(0.0, xi, 0.0));
        let c = (a * b).sqrt();
        let mz = mat.shear_modulus * c.powi(3) * k.c23 * xi;
        let got = s.global.spin_moment.unwrap();
        assert!(
            (got - mz).abs() <= 0.02 * mz,
            "{cells} cells: M_z {got} vs Kalker {mz}"
        );
    }
}

/// A solve started from a nearby point's state (temperature, film, tractions) reaches the cold solve's
/// result within the tolerances, dry and wet.
#[test]
fn exact_mode_warm_start_converges_to_the_cold_solution() {
    let p = exact();
    for wetness in [0.0, 1.0] {
        let near = OperatingPoint {
            wetness,
            ..point(0.003, 0.0005, 0.1)
        };
        let here = OperatingPoint {
            creepage_x: 0.0033,
            ..near
        };
        let start = converged(&p, &near).warm_start().unwrap();
        let cold = converged(&p, &here);
        let warm = solve_from(&p, &here, Some(&start)).unwrap();
        assert!(warm.report.converged, "{:?}", warm.report);
        let (c, w) = (&cold.global, &warm.global);
        let fns = c.normal_force;
        assert!(
            (c.force_x - w.force_x).abs() <= 1e-4 * fns,
            "w = {wetness}: {} vs {}",
            c.force_x,
            w.force_x
        );
        assert!((c.force_y - w.force_y).abs() <= 1e-4 * fns, "w = {wetness}");
        let t0 = p.material.bulk_temperature;
        let (tc, tw) = (
            c.max_temperature.unwrap() - t0,
            w.max_temperature.unwrap() - t0,
        );
        assert!((tc - tw).abs() <= 1e-3 * tc, "w = {wetness}: {tc} vs {tw}");
        // the same point again from its own state: the tangential solve starts at its solution
        let again = solve_from(&p, &here, cold.warm_start().as_ref()).unwrap();
        assert!(
            again.report.converged && again.report.iterations <= 2,
            "{:?}",
            again.report
        );
        assert!(again.report.tangential_sweeps <= 3, "{:?}", again.report);
    }
}
