//! The variable in which a table interpolates T_max: the temperature rise over the square root of the
//! relative yield stress,
//!
//!   G(T) = (T − T0)/sqrt(σ_y(T)/σ_y(T0))  [K]
//!
//! with σ_y(T) the table's own material curve (docs/model.md §3) and T0 its bulk temperature. The table
//! stores T_max; on loading, each node's value becomes G(T_max), the interpolation runs on G exactly as on
//! the other outputs, and T_max = G⁻¹ of the interpolated value (so every node is reproduced to rounding).
//!
//! Why (docs/model.md §12.3): the frictional heat that sets the contact temperature scales with the failure
//! stress τ_m = k·σ_y(T) (§5), and the yield-stress anomaly (σ_y rising between 341 and 424 °C) feeds back: a
//! contact at full slip heats steeply through 600–750 K and then saturates, so T_max is an S-shaped function
//! of the speed, the creepage and the load. Between speed nodes 2.43× apart, interpolating T_max itself
//! errs by up to 40 K there. Dividing the rise by a power of the relative yield stress takes most of that
//! shape out. The power ½ was measured (`table verify`, two 30 × 30 slices past the onset of the walls;
//! powers 0.25, 0.5, 0.75, 1 tried, ½ best on both): T_max p99 6.4–6.6 K against 6.8–7.6 K at 4.5–11 m/s,
//! 8.9–9.8 K against 15.6–16.5 K at 26.8–65 m/s; the forces do not change.
//!
//! G must rise strictly with T to be inverted. It does for the default steel (σ_y rises by at most 0.11 %
//! per kelvin in the anomaly); a material whose anomaly is so steep that G falls somewhere is interpolated in
//! T itself (G = T − T0, [`RiseVariable::is_plain`]).

use super::interp::{hermite_basis, hermite_basis_slope};
use crate::params::Material;

/// Range of temperature rises the inverse is tabulated over [K]; beyond it the inverse continues linearly.
const RISE_RANGE: f64 = 2500.0;
/// Number of intervals of the inverse's uniform grid in G (cubic Hermite: the inverse is exact to 1e-6 K
/// between the kinks of the material curve, to 0.02 K at them).
const INTERVALS: usize = 8192;
/// Temperature step of the check that G rises strictly [K].
const CHECK_STEP: f64 = 0.25;

/// The interpolation variable G of T_max and its inverse.
#[derive(Debug, Clone)]
pub struct RiseVariable {
    /// Bulk temperature T0 [K].
    t0: f64,
    /// σ_y(T0) [Pa]; 0 for the plain variable G = T − T0.
    yield_t0: f64,
    material: Material,
    /// Grid step of the inverse in G [K] and its reciprocal.
    step: f64,
    inv_step: f64,
    /// Per grid node G_i = i·step: T(G_i) [K] and dT/dG there [-].
    nodes: Vec<[f64; 2]>,
}

impl RiseVariable {
    /// The variable for `material` at its bulk temperature: G = (T − T0)/sqrt(σ_y(T)/σ_y(T0)), or the plain
    /// rise T − T0 where that G does not rise strictly with T over [T0, T0 + 2500 K] (see the module
    /// documentation).
    pub fn new(material: &Material) -> Self {
        let t0 = material.bulk_temperature;
        let yield_t0 = material.yield_stress_at(t0);
        let mut v = Self {
            t0,
            yield_t0,
            material: material.clone(),
            step: 0.0,
            inv_step: 0.0,
            nodes: Vec::new(),
        };
        let steps = (RISE_RANGE / CHECK_STEP) as usize;
        let mut last = 0.0;
        let rising = yield_t0 > 0.0
            && (1..=steps).all(|k| {
                let g = v.of(t0 + k as f64 * CHECK_STEP);
                let up = g > last;
                last = g;
                up
            });
        if !rising {
            v.yield_t0 = 0.0;
        }
        v.tabulate_inverse();
        v
    }

    /// Whether the variable is the plain rise T − T0 (the material's G does not rise strictly).
    pub fn is_plain(&self) -> bool {
        self.yield_t0 == 0.0
    }

    /// G(T) [K] (T in K).
    pub fn of(&self, t: f64) -> f64 {
        if self.is_plain() {
            return t - self.t0;
        }
        (t - self.t0) / (self.material.yield_stress_at(t) / self.yield_t0).sqrt()
    }

    /// dG/dT at T [-]: 1 for the plain rise, else by a central difference (the material curves are smooth
    /// between their floors' kinks; the difference's error is far below the inverse's needs).
    pub fn slope(&self, t: f64) -> f64 {
        const H: f64 = 1e-3;
        if self.is_plain() {
            return 1.0;
        }
        (self.of(t + H) - self.of(t - H)) / (2.0 * H)
    }

    /// The grid of the inverse: uniform in G over [0, G(T0 + RISE_RANGE)], each node's T by Newton's method
    /// from the previous node's tangent (G rises strictly: the root lies in [previous T, T0 + RISE_RANGE]; a
    /// step that leaves the bracket bisects it instead), to 1e-12 of the node's G.
    fn tabulate_inverse(&mut self) {
        let top = self.of(self.t0 + RISE_RANGE);
        self.step = top / INTERVALS as f64;
        self.inv_step = 1.0 / self.step;
        let mut node = [self.t0, 1.0 / self.slope(self.t0)];
        self.nodes = Vec::with_capacity(INTERVALS + 1);
        self.nodes.push(node);
        for i in 1..=INTERVALS {
            let g = i as f64 * self.step;
            let (mut lo, mut hi) = (node[0], self.t0 + RISE_RANGE);
            let mut t = (node[0] + self.step * node[1]).clamp(lo, hi);
            for _ in 0..100 {
                let r = self.of(t) - g;
                if r.abs() <= 1e-12 * g {
                    break;
                }
                if r < 0.0 {
                    lo = t;
                } else {
                    hi = t;
                }
                let next = t - r / self.slope(t);
                t = if next > lo && next < hi {
                    next
                } else {
                    0.5 * (lo + hi)
                };
            }
            node = [t, 1.0 / self.slope(t)];
            self.nodes.push(node);
        }
    }

    /// Where `g` lies on the grid of the inverse: the interval and the fraction s ∈ [0, 1] in it, or the end
    /// node and the distance beyond it [K] (G ≤ 0 and NaN, which an interpolated value never is: the line
    /// through T0; G above the grid: the line through its top).
    #[inline]
    fn locate(&self, g: f64) -> Result<(usize, f64), ([f64; 2], f64)> {
        let x = g * self.inv_step;
        let last = self.nodes.len() - 1;
        if x <= 0.0 || x.is_nan() {
            Err((self.nodes[0], g))
        } else if x >= last as f64 {
            Err((self.nodes[last], g - last as f64 * self.step))
        } else {
            let i = x as usize;
            Ok((i, x - i as f64))
        }
    }

    /// T = G⁻¹(g) [K]: cubic Hermite on the grid, continued linearly beyond it.
    #[inline]
    pub fn temperature(&self, g: f64) -> f64 {
        match self.locate(g) {
            Err(([t, m], beyond)) => t + beyond * m,
            Ok((i, s)) => {
                let ([t0, m0], [t1, m1]) = (self.nodes[i], self.nodes[i + 1]);
                let [h00, h10, h01, h11] = hermite_basis(s);
                h00 * t0 + h01 * t1 + self.step * (h10 * m0 + h11 * m1)
            }
        }
    }

    /// dT/dG of [`RiseVariable::temperature`] at `g` [-].
    #[inline]
    pub fn temperature_slope(&self, g: f64) -> f64 {
        match self.locate(g) {
            Err(([_, m], _)) => m,
            Ok((i, s)) => {
                let ([t0, m0], [t1, m1]) = (self.nodes[i], self.nodes[i + 1]);
                let [d00, d10, d01, d11] = hermite_basis_slope(s);
                (d00 * t0 + d01 * t1) * self.inv_step + d10 * m0 + d11 * m1
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Params;

    /// The inverse reproduces T from G(T) over the range a table meets, the anomaly included, and its slope
    /// is 1/G'(T); at T0 the variable is 0 with slope 1. Where σ_y(T) reaches its floor (1219.4 K with the
    /// default steel) G has a kink that the grid does not resolve: there the inverse is off by up to 0.016 K
    /// (measured), far below any table's interpolation error.
    #[test]
    fn the_inverse_undoes_the_variable() {
        let m = Params::default().material;
        let v = RiseVariable::new(&m);
        assert!(!v.is_plain());
        let t0 = v.t0;
        assert_eq!(v.of(t0), 0.0);
        assert!((v.slope(t0) - 1.0).abs() < 1e-6);
        let kink = m.reference_temperature + (1.0 - m.yield_floor) * m.yield_span;
        let (mut worst, mut at_kink): (f64, f64) = (0.0, 0.0);
        for k in 0..=40_000 {
            let t = t0 + 0.05 * k as f64;
            let (back, dt) = (v.temperature(v.of(t)), v.temperature_slope(v.of(t)));
            if (t - kink).abs() < 1.0 {
                at_kink = at_kink.max((back - t).abs());
                continue;
            }
            worst = worst.max((back - t).abs());
            assert!(
                (dt * v.slope(t) - 1.0).abs() < 1e-6,
                "{t}: {dt} vs 1/{}",
                v.slope(t)
            );
        }
        assert!(
            worst < 1e-6 && at_kink < 0.02,
            "{worst} K, {at_kink} K at the kink"
        );
    }

    /// The variable divides the rise by sqrt(σ_y(T)/σ_y(T0)): at the anomaly's peak (723 K, σ_y/σ_y(T0)
    /// = (1 − 430/975)·1.3 = 0.7267 with the default steel) G = 430/sqrt(0.7267) = 504.4 K.
    #[test]
    fn the_variable_is_the_rise_over_the_root_of_the_relative_yield_stress() {
        let m = Params::default().material;
        let v = RiseVariable::new(&m);
        let t = m.anomaly_temperature;
        let rise = t - m.bulk_temperature;
        let s = (1.0 - rise / m.yield_span) * (1.0 + m.anomaly_amplitude);
        assert!((v.of(t) - rise / s.sqrt()).abs() < 1e-9, "{}", v.of(t));
        assert!((v.of(t) - 504.4).abs() < 0.1, "{}", v.of(t));
    }

    /// A yield-stress anomaly steep enough that G falls with T (amplitude 3 over 20 K) makes the variable
    /// the plain rise, which the inverse undoes exactly.
    #[test]
    fn a_material_whose_variable_falls_is_interpolated_in_the_temperature_itself() {
        let mut m = Params::default().material;
        m.anomaly_amplitude = 3.0;
        m.anomaly_width = 20.0;
        let v = RiseVariable::new(&m);
        assert!(v.is_plain());
        for t in [m.bulk_temperature, 500.0, 900.0, 4000.0] {
            assert!((v.of(t) - (t - m.bulk_temperature)).abs() < 1e-12);
            let (back, dt) = (v.temperature(v.of(t)), v.temperature_slope(v.of(t)));
            assert!(
                (back - t).abs() < 1e-9 && (dt - 1.0).abs() < 1e-9,
                "{t}: {back}, {dt}"
            );
        }
    }

    /// Against the exact solver (30 × 30 cells; a = 4.79 mm, b = 6.65 mm, 100 kN: a/b 0.72, p0 1.5 GPa; ξ 8 %,
    /// η 1 %, φ 0.3 /m, dry: full slip, heating through the yield-stress anomaly): T_max midway between two
    /// speed nodes 2.4× apart, interpolated linearly in the speed as T_max itself and as G. Measured: at
    /// 4.5/7.75/11 m/s T_max 596.0/707.9/770.1 K, interpolated T_max −24.8 K off, G +1.0 K; at 26.8/46.5/65.1
    /// m/s 879.4/962.9/1012.3 K, −15.1 K and −6.9 K.
    #[test]
    fn interpolating_the_variable_follows_the_heating_through_the_anomaly() {
        let mut params = Params::default();
        params.grid.nx = 30;
        params.grid.ny = 30;
        params.geometry.semi_axes = Some([4.79e-3, 6.65e-3]);
        let v = RiseVariable::new(&params.material);
        let t_max = |speed: f64| {
            let point = crate::params::OperatingPoint {
                creepage_x: 0.08,
                creepage_y: 0.01,
                spin: 0.3,
                normal_force: 1e5,
                speed,
                wetness: 0.0,
            };
            let s = crate::solver::solve(&params, &point).unwrap();
            assert!(s.report.converged);
            s.global.max_temperature.unwrap()
        };
        for (v0, v1) in [(4.5, 11.0), (26.8, 65.1)] {
            let (t0, t1, mid) = (t_max(v0), t_max(v1), t_max(0.5 * (v0 + v1)));
            let plain = 0.5 * (t0 + t1) - mid;
            let through_g = v.temperature(0.5 * (v.of(t0) + v.of(t1))) - mid;
            assert!(
                through_g.abs() < 0.5 * plain.abs() && through_g.abs() < 8.0,
                "{v0}–{v1} m/s: T_max {t0:.1}/{mid:.1}/{t1:.1} K, interpolated {plain:.1} K off, \
                 through G {through_g:.1} K"
            );
        }
    }
}
