//! Failure stress and local friction (paper §2.1, eqs. P1, P3, P6; docs/model.md §5).

/// Failure-stress factor k for a cell holding fluid of height `l_f` [m] (docs/model.md §5, project continuity
/// extension of P3): k = k_dry − (k_dry − k_wet)·min(1, l_f/h_bl). Dry cells (l_f = 0) give k_dry; a film of
/// h_bl or more gives the boundary-lubrication value k_wet.
pub fn failure_stress_factor(k_dry: f64, k_wet: f64, l_f: f64, h_bl: f64) -> f64 {
    let s = (l_f.max(0.0) / h_bl).min(1.0);
    k_dry - (k_dry - k_wet) * s
}

/// Tangential failure stress of the metallic contacts τ_m = k·σ_y(T) [Pa] (P3).
pub fn failure_stress(k: f64, yield_stress: f64) -> f64 {
    k * yield_stress
}

/// Tangential adhesion limit τ_l = τ_m·A_m/A_n [Pa] (P6).
pub fn adhesion_limit(tau_m: f64, area_fraction: f64) -> f64 {
    tau_m * area_fraction
}

/// Local friction coefficient μ = τ_m·(A_m/A_n)/p_n = τ_l/p_n [-] (P1, P6); zero where p_n = 0.
pub fn local_friction(tau_l: f64, p_n: f64) -> f64 {
    if p_n > 0.0 { tau_l / p_n } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factor_blends_continuously_from_dry_to_wet() {
        assert_eq!(failure_stress_factor(1.0, 0.4, 0.0, 1e-7), 1.0);
        assert_eq!(failure_stress_factor(1.0, 0.4, 1e-7, 1e-7), 0.4);
        assert_eq!(failure_stress_factor(1.0, 0.4, 5e-6, 1e-7), 0.4);
        let half = failure_stress_factor(1.0, 0.4, 0.5e-7, 1e-7);
        assert!((half - 0.7).abs() < 1e-15);
        // tiny films change k by a tiny amount: continuity in wetness
        assert!((failure_stress_factor(1.0, 0.4, 1e-15, 1e-7) - 1.0).abs() < 1e-7);
    }

    #[test]
    fn friction_is_limit_over_pressure() {
        let tau_l = adhesion_limit(failure_stress(1.0, 600e6), 0.5);
        assert_eq!(tau_l, 300e6);
        assert!((local_friction(tau_l, 1e9) - 0.3).abs() < 1e-15);
        assert_eq!(local_friction(tau_l, 0.0), 0.0);
    }
}
