//! One operating point solved by the exact coupled model (`Model::new` + `Model::solve`), its forces
//! printed, and checked against what the physics requires: run it with
//! `cargo run --release -p wheelrail --example point`.
//!
//! The point: 100 kN on the default wheel–rail pair at 30 m/s, dry, ξ = 0.5 %, η = 0.1 %. The checks:
//! the solver converged; the forces oppose the creepages (Kalker's sign convention: F_x = −C·ξ in the
//! linear range); |F_T|/F_N is the reported traction coefficient; the peak pressure is Hertz's
//! p0 = 3·F_N/(2π·a·b) (docs/model.md §2); and with the constant friction law the traction is at most
//! μ·F_N (Coulomb's limit, which FASTSIM's adhesion limit τ_l = μ·p_n enforces cell by cell) and near it
//! in full slip.

use std::f64::consts::PI;
use wheelrail::{FrictionLaw, Model, OperatingPoint, Params};

fn main() -> wheelrail::Result<()> {
    let point = OperatingPoint {
        creepage_x: 0.005,
        creepage_y: 0.001,
        spin: 0.0,
        normal_force: 100e3,
        speed: 30.0,
        wetness: 0.0,
    };
    let model = Model::new(Params::default())?;
    let s = model.solve(&point)?;
    let g = &s.global;
    println!(
        "Tomberger law, ξ = {}, η = {}, F_N = {} N, V = {} m/s, dry",
        point.creepage_x, point.creepage_y, point.normal_force, point.speed
    );
    println!("  F_x   = {:10.1} N", g.force_x);
    println!("  F_y   = {:10.1} N", g.force_y);
    println!("  |F_T|/F_N = {:.4}", g.traction_coefficient);
    println!(
        "  T_max = {:.1} °C",
        g.max_temperature.unwrap_or(f64::NAN) - 273.15
    );
    println!(
        "  a, b  = {:.2} mm, {:.2} mm, p0 = {:.0} MPa",
        g.semi_axis_a * 1e3,
        g.semi_axis_b * 1e3,
        g.peak_pressure / 1e6
    );
    println!(
        "  {} outer iterations, residual {:.1e}",
        s.report.iterations, s.report.residual
    );

    assert!(
        s.report.converged,
        "the solver did not converge: {:?}",
        s.report.termination
    );
    assert!(
        g.force_x < 0.0 && g.force_y < 0.0,
        "the forces oppose the creepages"
    );
    let traction = g.force_x.hypot(g.force_y) / g.normal_force;
    assert!(
        (traction - g.traction_coefficient).abs() <= 1e-12,
        "{traction} vs {}",
        g.traction_coefficient
    );
    let p0 = 3.0 * g.normal_force / (2.0 * PI * g.semi_axis_a * g.semi_axis_b);
    assert!(
        (g.peak_pressure - p0).abs() <= 1e-9 * p0,
        "p0 {} vs Hertz {p0}",
        g.peak_pressure
    );

    // the same point with the constant friction law, in full slip at ξ = 5 %: |F_T| ≤ μ·F_N, and close to it
    // (μ times the pressure the grid's cells carry, whose sum is F_N to the grid's quadrature: 1e-3)
    let mut params = Params::default();
    params.friction.law = FrictionLaw::Constant;
    let mu = params.friction.mu;
    let slipping = OperatingPoint {
        creepage_x: 0.05,
        ..point
    };
    let c = Model::new(params)?.solve(&slipping)?;
    let f_t = c.global.force_x.hypot(c.global.force_y);
    println!(
        "constant law μ = {mu}, ξ = 5 %: |F_T| = {:.1} N = {:.4}·F_N",
        f_t,
        f_t / point.normal_force
    );
    assert!(c.report.converged);
    assert!(
        f_t <= mu * point.normal_force * (1.0 + 1e-3),
        "|F_T| {f_t} above μ·F_N"
    );
    assert!(
        f_t >= 0.9 * mu * point.normal_force,
        "full slip saturates near μ·F_N: {f_t}"
    );
    Ok(())
}
