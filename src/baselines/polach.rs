//! Polach's closed-form creep-force law with slip-velocity-dependent friction (O. Polach, Wear 258 (2005)
//! 992–1000; docs/model.md §12).

use crate::error::{Result, check_finite, check_positive};
use crate::params::{self, Key, Param};
use crate::tangential::{Creepages, KalkerCoefficients};
use std::f64::consts::PI;

/// Creep forces on the wheel from [`polach`] (Kalker's sign convention: opposite to the creepage).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolachForces {
    /// Longitudinal force F_x [N].
    pub force_x: f64,
    /// Lateral force F_y [N].
    pub force_y: f64,
    /// Friction coefficient μ(w) at the slip velocity w = s·V [-].
    pub friction_coefficient: f64,
}

/// Polach's creep forces (Wear 258, 2005; docs/model.md §12) for semi-axes `a`, `b` [m], normal force
/// `normal_force` [N], shear modulus `shear_modulus` [Pa], Kalker's coefficients `k`, creepages `creep` and
/// rolling speed `speed` [m/s]:
/// - s = sqrt(ξ² + η²), slip velocity w = s·V, μ = μ0·[(1 − A)·e^(−B·w) + A];
/// - c_jj = sqrt((C11·ξ/s)² + (C22·η/s)²), ε = (G·π·a·b·c_jj/(4·F_N·μ))·s;
/// - F = (2·F_N·μ/π)·[k_A·ε/(1 + (k_A·ε)²) + arctan(k_S·ε)], F_x = −F·ξ/s, F_y = −F·η/s.
///
/// The spin creepage is **ignored** (only ξ and η enter; Polach's separate spin correction of the lateral
/// force is not part of this baseline). Zero creepage gives zero force. For small ε the law is linear,
/// F ≈ ((k_A + k_S)/2)·G·a·b·c_jj·s, i.e. Kalker's linear theory when k_A = k_S = 1.
#[allow(clippy::too_many_arguments)]
pub fn polach(
    p: &params::Polach,
    a: f64,
    b: f64,
    normal_force: f64,
    shear_modulus: f64,
    k: &KalkerCoefficients,
    creep: Creepages,
    speed: f64,
) -> Result<PolachForces> {
    // μ0 > 0: Polach's law divides by it; the others need only be non-negative
    if !(p.mu0.is_finite() && p.mu0 > 0.0) {
        return Err(Key::Param(Param::PolachMu0).invalid(p.mu0, "finite, > 0".into()));
    }
    for (key, value) in [
        (Param::PolachARatio, p.a_ratio),
        (Param::PolachBRate, p.b_rate),
        (Param::PolachKA, p.k_a),
        (Param::PolachKS, p.k_s),
    ] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(Key::Param(key).invalid(value, "finite, >= 0".into()));
        }
    }
    check_positive("semi-axis a", a, "m")?;
    check_positive("semi-axis b", b, "m")?;
    check_positive("normal_force", normal_force, "N")?;
    check_positive("shear_modulus", shear_modulus, "Pa")?;
    check_positive("Kalker C11", k.c11, "")?;
    check_positive("Kalker C22", k.c22, "")?;
    check_finite("creepage xi", creep.xi, "")?;
    check_finite("creepage eta", creep.eta, "")?;
    check_finite("spin creepage phi", creep.phi, "1/m")?;
    check_positive("speed", speed, "m/s")?;

    let s = creep.xi.hypot(creep.eta);
    let mu = p.mu0 * ((1.0 - p.a_ratio) * (-p.b_rate * s * speed).exp() + p.a_ratio);
    if s == 0.0 || mu <= 0.0 {
        return Ok(PolachForces {
            force_x: 0.0,
            force_y: 0.0,
            friction_coefficient: mu,
        });
    }
    let c_jj = (k.c11 * creep.xi / s).hypot(k.c22 * creep.eta / s);
    let eps = shear_modulus * PI * a * b * c_jj / (4.0 * normal_force * mu) * s;
    let ka_eps = p.k_a * eps;
    let force =
        2.0 * normal_force * mu / PI * (ka_eps / (1.0 + ka_eps * ka_eps) + (p.k_s * eps).atan());
    Ok(PolachForces {
        force_x: -force * creep.xi / s,
        force_y: -force * creep.eta / s,
        friction_coefficient: mu,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tangential::kalker_coefficients;

    const A: f64 = 5.879e-3;
    const B: f64 = 10.54e-3;
    const FN: f64 = 100e3;
    const G: f64 = 210e9 / (2.0 * 1.28);
    const V: f64 = 30.0;

    fn forces(p: &params::Polach, xi: f64, eta: f64, phi: f64) -> PolachForces {
        let k = kalker_coefficients(A, B, 0.28).unwrap();
        polach(p, A, B, FN, G, &k, Creepages { xi, eta, phi }, V).unwrap()
    }

    /// Small creepage: F/s → ((k_A + k_S)/2)·G·a·b·c_jj (the derivative of the bracket at ε = 0 is k_A + k_S);
    /// with k_A = k_S = 1 this is Kalker's linear law F_x = −G·c²·C11·ξ, F_y = −G·c²·C22·η.
    #[test]
    fn small_creepage_slope() {
        let k = kalker_coefficients(A, B, 0.28).unwrap();
        let kalker = params::Polach {
            k_a: 1.0,
            k_s: 1.0,
            ..Default::default()
        };
        let s = 1e-8;
        let f = forces(&kalker, s, 0.0, 0.0);
        assert!((f.force_x / (-G * A * B * k.c11 * s) - 1.0).abs() < 1e-4);
        assert_eq!(f.force_y, 0.0);
        let f = forces(&kalker, 0.0, s, 0.0);
        assert!((f.force_y / (-G * A * B * k.c22 * s) - 1.0).abs() < 1e-4);
        let dflt = params::Polach::default();
        let (xi, eta) = (0.6 * s, 0.8 * s);
        let f = forces(&dflt, xi, eta, 0.0);
        let c_jj = ((k.c11 * 0.6).powi(2) + (k.c22 * 0.8).powi(2)).sqrt();
        let want = 0.5 * (dflt.k_a + dflt.k_s) * G * A * B * c_jj * s;
        assert!((f.force_x.hypot(f.force_y) / want - 1.0).abs() < 1e-4);
        assert!((f.friction_coefficient / dflt.mu0 - 1.0).abs() < 1e-6);
    }

    /// Large creepage: |F| → μ·F_N and μ → μ0·A at large slip velocity; the force is along −(ξ, η).
    #[test]
    fn large_creepage_saturates() {
        let p = params::Polach::default();
        let f = forces(&p, 0.6, -0.8, 0.0);
        let mu_inf = p.mu0 * p.a_ratio;
        assert!((f.friction_coefficient / mu_inf - 1.0).abs() < 1e-6);
        // Deficit of the bracket from π/2 at large ε: (1/k_S − 1/k_A)/ε ≈ 1.8e-3 here (ε ≈ 800).
        assert!((f.force_x.hypot(f.force_y) / (mu_inf * FN) - 1.0).abs() < 3e-3);
        assert!((f.force_x / f.force_y - 0.6 / -0.8).abs() < 1e-12);
        assert!(f.force_x < 0.0 && f.force_y > 0.0);
    }

    /// Zero creepage (and spin alone, which the baseline ignores) gives zero force; odd symmetry.
    #[test]
    fn zero_and_odd() {
        let p = params::Polach::default();
        let z = forces(&p, 0.0, 0.0, 0.0);
        assert_eq!((z.force_x, z.force_y), (0.0, 0.0));
        assert_eq!(z.friction_coefficient, p.mu0);
        let z = forces(&p, 0.0, 0.0, 5.0);
        assert_eq!((z.force_x, z.force_y), (0.0, 0.0));
        for (xi, eta) in [(3e-3, 1e-3), (-2e-2, 5e-3), (0.0, 1e-4)] {
            let f = forces(&p, xi, eta, 0.0);
            let g = forces(&p, -xi, -eta, 0.0);
            assert_eq!((f.force_x, f.force_y), (-g.force_x, -g.force_y));
            assert!(f.force_x * xi <= 0.0 && f.force_y * eta <= 0.0);
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        let p = params::Polach::default();
        let k = kalker_coefficients(A, B, 0.28).unwrap();
        let c = Creepages {
            xi: 1e-3,
            eta: 0.0,
            phi: 0.0,
        };
        assert!(polach(&p, A, B, FN, G, &k, c, V).is_ok());
        assert!(polach(&p, 0.0, B, FN, G, &k, c, V).is_err());
        assert!(polach(&p, A, B, -1.0, G, &k, c, V).is_err());
        assert!(polach(&p, A, B, FN, G, &k, c, 0.0).is_err());
        let bad = Creepages { eta: f64::NAN, ..c };
        assert!(polach(&p, A, B, FN, G, &k, bad, V).is_err());
        let bad_p = params::Polach {
            mu0: 0.0,
            ..Default::default()
        };
        assert!(polach(&bad_p, A, B, FN, G, &k, c, V).is_err());
        let bad_p = params::Polach {
            k_s: -1.0,
            ..Default::default()
        };
        assert!(polach(&bad_p, A, B, FN, G, &k, c, V).is_err());
    }
}
