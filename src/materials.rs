//! Temperature-dependent steel of wheel and rail (docs/model.md §3; the paper's Fig. 4 as project defaults).

use crate::params::Material;

/// Material properties at one temperature.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialState {
    /// Young's modulus E(T) [Pa].
    pub youngs_modulus: f64,
    /// Composite modulus of two identical bodies, E* = E/(2(1−ν²)) [Pa].
    pub e_star: f64,
    /// Shear modulus G = E/(2(1+ν)) [Pa].
    pub shear_modulus: f64,
    /// Bulk yield stress σ_y(T) [Pa].
    pub yield_stress: f64,
    /// Asperity hardness H(T) [Pa].
    pub hardness: f64,
    /// Poisson's ratio ν [-].
    pub poisson: f64,
}

impl Material {
    /// Young's modulus E(T) = E_ref·max(floor, 1 − slope·(T − T_ref)) [Pa], T in K (docs/model.md §3).
    pub fn youngs_modulus_at(&self, t: f64) -> f64 {
        let dt = t - self.reference_temperature;
        self.youngs_modulus * (1.0 - self.youngs_slope * dt).max(self.youngs_floor)
    }

    /// Yield stress σ_y(T) = σ_y,ref·max(floor, 1 − (T − T_ref)/span)·(1 + A·exp(−((T − T_a)/w)²)) [Pa]
    /// with the yield-stress anomaly bump (dynamic strain ageing, paper §2.2; docs/model.md §3).
    pub fn yield_stress_at(&self, t: f64) -> f64 {
        let dt = t - self.reference_temperature;
        let linear = (1.0 - dt / self.yield_span).max(self.yield_floor);
        let z = (t - self.anomaly_temperature) / self.anomaly_width;
        self.yield_stress * linear * (1.0 + self.anomaly_amplitude * (-z * z).exp())
    }

    /// Asperity hardness H(T) = H_ref·max(floor, 1 − (T − T_ref)/span) [Pa] (paper: linear in T).
    pub fn hardness_at(&self, t: f64) -> f64 {
        let dt = t - self.reference_temperature;
        self.hardness * (1.0 - dt / self.hardness_span).max(self.hardness_floor)
    }

    /// Thermal diffusivity κ = λ/(ρ·c) [m²/s].
    pub fn diffusivity(&self) -> f64 {
        self.conductivity / (self.density * self.specific_heat)
    }

    /// Thermal effusivity β_e = sqrt(λ·ρ·c) [W·s^0.5/(m²·K)].
    pub fn effusivity(&self) -> f64 {
        (self.conductivity * self.density * self.specific_heat).sqrt()
    }

    /// All properties at temperature `t` [K].
    pub fn at(&self, t: f64) -> MaterialState {
        let e = self.youngs_modulus_at(t);
        let nu = self.poisson;
        MaterialState {
            youngs_modulus: e,
            e_star: e / (2.0 * (1.0 - nu * nu)),
            shear_modulus: e / (2.0 * (1.0 + nu)),
            yield_stress: self.yield_stress_at(t),
            hardness: self.hardness_at(t),
            poisson: nu,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::CELSIUS_ZERO;

    #[test]
    fn room_temperature_values_and_falls() {
        let m = Material::default();
        let t20 = 20.0 + CELSIUS_ZERO;
        let s = m.at(t20);
        assert!((s.youngs_modulus - 210e9).abs() < 1.0);
        assert!((s.hardness - 4e9).abs() < 1.0);
        // anomaly at 20 °C is exp(-(430/80)^2) ≈ 3e-13: negligible
        assert!((s.yield_stress - 600e6).abs() < 1e-3 * 600e6);
        // E falls by about 11 % at 300 °C (docs/model.md §3)
        let e300 = m.youngs_modulus_at(300.0 + CELSIUS_ZERO);
        assert!((e300 / 210e9 - 0.888).abs() < 1e-9);
        // diffusivity 1.415e-5, effusivity 13 290
        assert!((m.diffusivity() - 1.415e-5).abs() < 1e-8);
        assert!((m.effusivity() - 13290.0).abs() < 5.0);
    }

    #[test]
    fn yield_anomaly_gives_a_local_rise_near_450_c() {
        let m = Material::default();
        let at = |c: f64| m.yield_stress_at(c + CELSIUS_ZERO);
        assert!(at(300.0) < at(20.0));
        assert!(
            at(450.0) > at(350.0),
            "anomaly should raise σ_y between 350 and 450 °C"
        );
        assert!(at(600.0) < at(450.0));
        // ratios fall with temperature apart from the bump
        let r = |c: f64| at(c) / m.hardness_at(c + CELSIUS_ZERO);
        assert!(r(250.0) < r(20.0));
    }

    #[test]
    fn floors_hold_at_extreme_temperature() {
        let m = Material::default();
        let s = m.at(5000.0);
        assert!(s.youngs_modulus >= 0.1 * 210e9 - 1.0);
        assert!(s.hardness > 0.0 && s.yield_stress > 0.0);
    }
}
