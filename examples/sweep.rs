//! A traction–creepage curve: F_x/F_N over ξ from −3 % to 3 % at 100 kN, 30 m/s, dry, solved as one sweep
//! with warm starts (`Model::sweep`) and printed as a table; run it with
//! `cargo run --release -p wheelrail --example sweep`.
//!
//! The checks: every point converged; F_x is odd in ξ (dry, η = φ = 0: the mirror ξ → −ξ flips F_x, and
//! the coupled model is symmetric under it, docs/model.md §12.3), to the solver tolerance; |F_x|/F_N grows
//! with |ξ| up to the peak and stays below 1; and at the smallest creepage the slope is Kalker's linear
//! theory, F_x = −G·a·b·C11·ξ (docs/model.md §6.1), within 5 % (the solver on the default grid).

use wheelrail::tangential::kalker_coefficients;
use wheelrail::{Model, OperatingPoint, Params};

fn main() -> wheelrail::Result<()> {
    let params = Params::default();
    let model = Model::new(params.clone())?;
    let creepages: Vec<f64> = [
        1e-5, 0.0005, 0.001, 0.002, 0.003, 0.005, 0.0075, 0.01, 0.015, 0.02, 0.03,
    ]
    .into_iter()
    .flat_map(|x| [-x, x])
    .collect();
    let at = |creepage_x: f64| OperatingPoint {
        creepage_x,
        creepage_y: 0.0,
        spin: 0.0,
        normal_force: 100e3,
        speed: 30.0,
        wetness: 0.0,
    };
    let points: Vec<OperatingPoint> = creepages.iter().map(|x| at(*x)).collect();
    let solutions = model.sweep(&points);
    println!("{:>9} {:>10} {:>10}", "ξ [%]", "F_x/F_N", "T_max [°C]");
    let mut forces = Vec::new();
    for (x, s) in creepages.iter().zip(solutions) {
        let s = s?;
        assert!(s.report.converged, "ξ = {x}: not converged");
        let g = s.global;
        println!(
            "{:9.3} {:10.5} {:10.1}",
            x * 100.0,
            g.force_x / g.normal_force,
            g.max_temperature.unwrap_or(f64::NAN) - 273.15
        );
        forces.push(g.force_x / g.normal_force);
    }
    // odd symmetry F_x(−ξ) = −F_x(ξ), to the solver tolerance (forces over F_N) of the warm-started chains
    let tolerance = 10.0 * params.solver.tolerance;
    for pair in forces.chunks_exact(2) {
        assert!((pair[0] + pair[1]).abs() <= tolerance, "{pair:?}");
        assert!(
            pair[1] < 0.0 && pair[1] > -1.0,
            "F_x opposes ξ, |F_x| < F_N: {pair:?}"
        );
    }
    // |F_x| grows with ξ over the first points (adhesion up to the peak)
    let positive: Vec<f64> = forces.chunks_exact(2).map(|p| -p[1]).collect();
    assert!(
        positive.windows(2).take(5).all(|w| w[1] > w[0]),
        "{positive:?}"
    );
    // Kalker's linear limit at ξ = 1e-5
    let hertz = wheelrail::solver::normal_contact(&params, 100e3)?;
    let m = params.material.at(params.material.bulk_temperature);
    let k = kalker_coefficients(hertz.a, hertz.b, m.poisson)?;
    let linear = -m.shear_modulus * hertz.a * hertz.b * k.c11 * 1e-5 / 100e3;
    println!(
        "Kalker's linear theory at ξ = 1e-5: F_x/F_N = {linear:.3e}, the model {:.3e}",
        forces[1]
    );
    assert!(
        (forces[1] / linear - 1.0).abs() < 0.05,
        "{} vs {linear}",
        forces[1]
    );
    Ok(())
}
