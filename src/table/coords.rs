//! The coordinates of a table point: an operating point and its contact ellipse in the table's axes, and
//! back (see `axes` for what they mean).
//!
//! - Creepages normalised by Kalker's linear theory (docs/model.md §6): ξ̂ = k_x·ξ, η̂ = k_y·η, φ̂ = k_φ·φ
//!   with k_x = G·c²·C11/F_N, k_y = G·c²·C22/F_N, k_φ = G·c³·C23/F_N, c = sqrt(a·b), G and ν of the
//!   material at the bulk temperature (those the solver's FASTSIM uses), C_ij(a/b, ν) from Kalker's table.
//!   The linear theory's F_x/F_N is then −ξ̂ (F_y/F_N = −(η̂ + φ̂)).
//! - Geometry: a/b and p_ref = p0·(F_ref/F_N)^(1/3), p0 = 3·F_N/(2π·a·b) (Hertz, docs/model.md §2).

use super::axes::{DIMS, REFERENCE_FORCE};
use crate::error::Result;
use crate::params::{OperatingPoint, Params};
use crate::tangential::kalker_coefficients;
use std::f64::consts::PI;

/// How a table turns an operating point and its contact into coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coordinates {
    /// Whether the creepages are normalised (format version 1: raw creepages).
    normalised: bool,
    /// Shear modulus G at the bulk temperature [Pa].
    shear_modulus: f64,
    /// Poisson's ratio ν [-].
    poisson: f64,
}

/// The contact ellipse of an evaluation: semi-axes at the point's normal force, and how they change with
/// it (for derivatives along F_N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipse {
    /// Semi-axis a along the rolling direction [m].
    pub a: f64,
    /// Semi-axis b lateral [m].
    pub b: f64,
    /// e in a, b ∝ F_N^e: 1/3 for Hertz contacts of given curvatures, 0 for prescribed semi-axes [-].
    pub load_exponent: f64,
}

impl Ellipse {
    /// The Hertz exponent of contacts from curvatures: a, b ∝ F_N^(1/3) (docs/model.md §2).
    pub const HERTZ: f64 = 1.0 / 3.0;

    /// c = sqrt(a·b) [m].
    pub fn radius(&self) -> f64 {
        (self.a * self.b).sqrt()
    }
}

/// The semi-axes [a, b] [m] of the ellipse with ratio a/b = `ratio` and reference pressure `p_ref` [Pa] at
/// normal force `force` [N]: p0 = p_ref·(F_N/F_ref)^(1/3), a·b = 3·F_N/(2π·p0) (Hertz, docs/model.md §2).
pub fn semi_axes(ratio: f64, p_ref: f64, force: f64) -> [f64; 2] {
    let p0 = p_ref * libm::cbrt(force / REFERENCE_FORCE);
    let ab = 3.0 * force / (2.0 * PI * p0);
    let b = (ab / ratio).sqrt();
    [ratio * b, b]
}

/// p_ref = p0·(F_ref/F_N)^(1/3) of semi-axes a, b [m] at normal force `force` [N], p0 = 3·F_N/(2π·a·b) [Pa].
pub fn reference_pressure(a: f64, b: f64, force: f64) -> f64 {
    3.0 * force / (2.0 * PI * a * b) * libm::cbrt(REFERENCE_FORCE / force)
}

impl Coordinates {
    /// The coordinates of tables of `params` with normalised (or, format version 1, raw) creepages.
    pub fn new(params: &Params, normalised: bool) -> Coordinates {
        let m = params.material.at(params.material.bulk_temperature);
        Coordinates {
            normalised,
            shear_modulus: m.shear_modulus,
            poisson: m.poisson,
        }
    }

    /// Whether the creepages are normalised.
    pub fn normalised(&self) -> bool {
        self.normalised
    }

    /// The creepage scales [k_x, k_y, k_φ] (see the module documentation; [1, 1, 1] for raw creepages)
    /// [-, -, m] of the contact `e` at normal force `force` [N]. Errors: semi-axes that are not positive.
    pub fn scales(&self, e: &Ellipse, force: f64) -> Result<[f64; 3]> {
        if !self.normalised {
            return Ok([1.0; 3]);
        }
        let k = kalker_coefficients(e.a, e.b, self.poisson)?;
        let c = e.radius();
        let gc2 = self.shear_modulus * c * c / force;
        Ok([gc2 * k.c11, gc2 * k.c22, gc2 * c * k.c23])
    }

    /// The table coordinates (ξ̂, η̂, φ̂, F_N, V, w, a/b, p_ref) of `point` with contact `e`, and the creepage
    /// scales.
    pub fn of(&self, point: &OperatingPoint, e: &Ellipse) -> Result<([f64; DIMS], [f64; 3])> {
        let k = self.scales(e, point.normal_force)?;
        Ok((
            [
                k[0] * point.creepage_x,
                k[1] * point.creepage_y,
                k[2] * point.spin,
                point.normal_force,
                point.speed,
                point.wetness,
                e.a / e.b,
                reference_pressure(e.a, e.b, point.normal_force),
            ],
            k,
        ))
    }

    /// The operating point and contact ellipse (prescribed semi-axes) of table coordinates `q`.
    pub fn point(&self, q: &[f64; DIMS]) -> Result<(OperatingPoint, Ellipse)> {
        let [a, b] = semi_axes(q[6], q[7], q[3]);
        let e = Ellipse {
            a,
            b,
            load_exponent: 0.0,
        };
        let k = self.scales(&e, q[3])?;
        Ok((
            OperatingPoint {
                creepage_x: q[0] / k[0],
                creepage_y: q[1] / k[1],
                spin: q[2] / k[2],
                normal_force: q[3],
                speed: q[4],
                wetness: q[5],
            },
            e,
        ))
    }

    /// d ln(k)/d ln(F_N) of the creepage scales [k_x, k_y, k_φ] for a contact whose semi-axes grow like
    /// F_N^e: k_x, k_y ∝ c²/F_N ∝ F_N^(2e−1), k_φ ∝ c³/F_N ∝ F_N^(3e−1) (a/b, hence C_ij, is fixed); 0 for
    /// raw creepages.
    pub fn scale_exponents(&self, load_exponent: f64) -> [f64; 3] {
        if !self.normalised {
            return [0.0; 3];
        }
        let e = load_exponent;
        [2.0 * e - 1.0, 2.0 * e - 1.0, 3.0 * e - 1.0]
    }
}

/// d ln(p_ref)/d ln(F_N) for semi-axes growing like F_N^e: p_ref ∝ F_N^(1 − 2e − 1/3).
pub fn reference_pressure_exponent(load_exponent: f64) -> f64 {
    2.0 / 3.0 - 2.0 * load_exponent
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::normal_contact;

    #[test]
    fn a_hertz_contact_keeps_its_reference_pressure_at_every_load() {
        let p = Params::default();
        let h = normal_contact(&p, REFERENCE_FORCE).unwrap();
        let p_ref = reference_pressure(h.a, h.b, REFERENCE_FORCE);
        assert!((p_ref / h.p0 - 1.0).abs() < 1e-14);
        for f in [10e3, 47e3, 250e3] {
            let h = normal_contact(&p, f).unwrap();
            assert!(
                (reference_pressure(h.a, h.b, f) / p_ref - 1.0).abs() < 1e-12,
                "{f}"
            );
            // and the ellipse of (a/b, p_ref) at that load is Hertz's
            let [a, b] = semi_axes(h.a / h.b, p_ref, f);
            assert!((a / h.a - 1.0).abs() < 1e-12 && (b / h.b - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn normalised_creepage_is_the_linear_theorys_traction_coefficient() {
        // the exact solver at a tiny creepage follows Kalker's linear theory (FASTSIM reproduces it):
        // F_x/F_N = −ξ̂, F_y/F_N = −η̂
        let params = Params::default();
        let c = Coordinates::new(&params, true);
        for (a, b) in [(6e-3, 10e-3), (9e-3, 3e-3)] {
            let mut q = params.clone();
            q.geometry.semi_axes = Some([a, b]);
            let e = Ellipse {
                a,
                b,
                load_exponent: 0.0,
            };
            let point = OperatingPoint {
                creepage_x: 1e-7,
                creepage_y: 1e-7,
                ..OperatingPoint::default()
            };
            let (x, _) = c.of(&point, &e).unwrap();
            let s = crate::solver::solve(&q, &point).unwrap();
            let f = point.normal_force;
            assert!((-s.global.force_x / f / x[0] - 1.0).abs() < 0.02, "{a} {b}");
            assert!((-s.global.force_y / f / x[1] - 1.0).abs() < 0.02, "{a} {b}");
            // and back
            let (back, e2) = c.point(&x).unwrap();
            assert!((back.creepage_x / point.creepage_x - 1.0).abs() < 1e-12);
            assert!((back.creepage_y / point.creepage_y - 1.0).abs() < 1e-12);
            assert!((e2.a / a - 1.0).abs() < 1e-12 && (e2.b / b - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn scale_exponents_match_finite_differences() {
        let params = Params::default();
        let c = Coordinates::new(&params, true);
        let h = normal_contact(&params, 80e3).unwrap();
        for e in [Ellipse::HERTZ, 0.0] {
            let at = |f: f64| {
                let s = (f / 80e3).powf(e);
                c.scales(
                    &Ellipse {
                        a: h.a * s,
                        b: h.b * s,
                        load_exponent: e,
                    },
                    f,
                )
                .unwrap()
            };
            let (lo, hi) = (at(80e3 * (1.0 - 1e-6)), at(80e3 * (1.0 + 1e-6)));
            let want = c.scale_exponents(e);
            for d in 0..3 {
                let fd = (hi[d].ln() - lo[d].ln()) / (2e-6);
                assert!((fd - want[d]).abs() < 1e-6, "e {e} d {d}: {fd}");
            }
            let p = |f: f64| {
                let s = (f / 80e3).powf(e);
                reference_pressure(h.a * s, h.b * s, f).ln()
            };
            let fd = (p(80e3 * (1.0 + 1e-6)) - p(80e3 * (1.0 - 1e-6))) / 2e-6;
            assert!((fd - reference_pressure_exponent(e)).abs() < 1e-6);
        }
    }
}
