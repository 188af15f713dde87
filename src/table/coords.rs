//! The coordinates of a table point: an operating point and its contact ellipse in the table's axes, and
//! back (see `axes` for what they mean).
//!
//! - Creepages normalised by Kalker's linear theory (docs/model.md §6): ξ̂ = k_x·ξ, η̂ = k_y·η, φ̂ = k_φ·φ
//!   with k_x = G·c²·C11/F_N, k_y = G·c²·C22/F_N, k_φ = G·c³·C23/F_N, c = sqrt(a·b), G and ν of the
//!   material at the bulk temperature (those the solver's FASTSIM uses), C_ij(a/b, ν) from Kalker's table.
//!   The linear theory's F_x/F_N is then −ξ̂ (F_y/F_N = −(η̂ + φ̂)).
//! - **Knee-blended creepages** (a creepage axis with a `raw_scale` k_r): the coordinate is ξ̂ below the
//!   knee of the creep curve and the raw creepage times k_r beyond it,
//!   q = k_r·ξ + (k − k_r)·ξ·σ(k·ξ/s), σ(z) = 1/sqrt(1 + z²), s = [`KNEE`]
//!   (q ≈ k·ξ = ξ̂ for |ξ̂| ≪ s, q ≈ k_r·ξ ± (1 − k_r/k)·s for |ξ̂| ≫ s; strictly increasing in ξ and in k).
//!   Why: below saturation the creep curves of all contacts coincide in ξ̂ (Kalker's linear theory and its
//!   saturation at the local friction); above it the friction follows the temperature, set by the raw slip
//!   speed V·ξ, and at equal ξ̂ two contacts whose k differ 2× slide 2× apart in speed (measured: across
//!   p_ref nodes 0.61 and 1.22 GPa, ξ̂ 8–16, |ΔF|/F_N 0.006–0.011 and |ΔT_max| 25–49 K at equal ξ̂, against
//!   0.000–0.005 and 1–33 K at equal q). It also gives every contact nearly the same coordinate range up to
//!   its raw limit (k_r·limit + (1 − k_r/k)·s), where ξ̂ spans 47–3200 × the limit over the geometry range.
//!   A spin axis with a `raw_length` L_r takes k_r·L/L_r for a contact of size L = sqrt(a² + b²): its raw
//!   part is then the spin's slip φ·L at the contact's edge (times k_r/L_r), which the full-slip forces
//!   follow (the sliding velocity (ξ − φ·y, η + φ·x) compares φ·b and φ·a with ξ and η) — with one k_r
//!   for all contacts, a large conformal contact's whole fall of F_x under spin crowds into a few
//!   nodes, at a place that moves from one a/b node to the next (docs/model.md §12.3).
//! - Geometry: a/b and p_ref = p0·(F_ref/F_N)^(1/3), p0 = 3·F_N/(2π·a·b) (Hertz, docs/model.md §2).
//! - **Similarity** (a table whose speed axis has `similarity`, docs/model.md §9.1): a contact (a, b, F_N,
//!   V, φ) is located by its equivalent at the reference load F_ref — semi-axes (a, b)/s, speed V·s, spin
//!   φ·s, s = sqrt(F_N/F_ref), the same ξ, η, w and p0 — whose outputs F/F_N, M_z/(F_N·c), T_max, fluid
//!   share and P_f/(F_N·V) are the contact's own. So the coordinates are (ξ̂, η̂, φ̂, F_ref, V·s, w, a/b, p0)
//!   (p_ref of the equivalent is its p0), and the raw limits apply to the equivalent's creepages.

use super::axes::{Axes, DIMS, REFERENCE_FORCE};
use super::heating::{FlexibilityRatios, Heating};
use crate::error::Result;
use crate::params::{OperatingPoint, Params};
use crate::tangential::{Flexibilities, KalkerCoefficients, kalker_coefficients};
use std::f64::consts::PI;

/// The knee s of knee-blended creepage coordinates: the linear theory's traction coefficient ξ̂ about
/// where the creep curves saturate (at the local friction, 0.1–0.6; full slip in Carter's theory at
/// ξ̂ = 3μ) [-]. Measured insensitive: s = 0.5, 1, 2 change the interpolation errors across p_ref by
/// less than 0.001 in |ΔF|/F_N.
pub const KNEE: f64 = 1.0;

/// How a table turns an operating point and its contact into coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coordinates {
    /// Whether the creepages are normalised (format version 1: raw creepages).
    normalised: bool,
    /// Per creepage axis, the raw scale k_r of a knee-blended coordinate (None: ξ̂ = k·ξ).
    raw_scales: [Option<f64>; 3],
    /// Per creepage axis, the contact size L_r [m] its raw scale applies to (None: every contact's).
    raw_lengths: [Option<f64>; 3],
    /// Shear modulus G at the bulk temperature [Pa].
    shear_modulus: f64,
    /// Poisson's ratio ν [-].
    poisson: f64,
    /// Whether a contact is located by its equivalent at the reference load (docs/model.md §9.1).
    similarity: bool,
    /// Whether the heat is interpolated per unit of FASTSIM's direction factor Λ ([`super::heating`]):
    /// tables of FASTSIM.
    heating: bool,
}

/// Where a query lies in a table's coordinates, and how its coordinates move with its inputs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Located {
    /// The coordinates (ξ̂, η̂, φ̂, F_N, V, w, a/b, p_ref) (with similarity: of the equivalent contact).
    pub q: [f64; DIMS],
    /// The creepage coordinates with ∂q/∂(the query's raw creepage) and k·∂q/∂k of the located creepage.
    pub m: [Mapped; 3],
    /// ∂q_d/∂ln F_N of every coordinate, the contact's semi-axes growing like F_N^e (e its load exponent).
    pub dlnf: [f64; DIMS],
    /// ∂q_V/∂V (s with similarity, else 1).
    pub dv: f64,
    /// The raw creepages the axes' raw limits apply to (with similarity: the equivalent's, φ·s).
    pub raw: [f64; 3],
    /// The direction factor Λ of the frictional heat [-] ([`super::heating`]; 1 for tables of the exact
    /// tangential solver).
    pub heating: f64,
    /// ∂Λ/∂(ξ, η, φ, ln F_N) of the query's inputs [-, -, m, -].
    pub dheating: [f64; 4],
}

/// A creepage coordinate q(x, k) and its slopes: ∂q/∂x and k·∂q/∂k (the change with ln k).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mapped {
    /// The coordinate q.
    pub q: f64,
    /// ∂q/∂x [1/unit of x].
    pub dx: f64,
    /// k·∂q/∂k.
    pub dlnk: f64,
    /// k_r·∂q/∂k_r (0 without a raw scale).
    pub dlnr: f64,
}

/// The scales of one creepage axis for one contact: k of the linear theory and, knee-blended, the raw
/// scale k_r (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scale {
    /// k [-, -, m].
    pub k: f64,
    /// k_r [-, -, m], None for q = k·x.
    pub raw: Option<f64>,
}

impl Scale {
    /// The coordinate of raw creepage `x` ([`map`]).
    #[inline(always)]
    pub fn map(&self, x: f64) -> Mapped {
        map(x, self.k, self.raw)
    }

    /// The raw creepage of coordinate `q` ([`unmap`]).
    pub fn unmap(&self, q: f64) -> f64 {
        unmap(q, self.k, self.raw)
    }

    /// The larger scales of `self` and `other` (a coordinate grows with both, see [`map`]).
    pub fn max(self, other: Scale) -> Scale {
        Scale {
            k: self.k.max(other.k),
            raw: self.raw.zip(other.raw).map(|(a, b)| a.max(b)).or(self.raw),
        }
    }
}

/// The creepage coordinate of raw creepage `x` for creepage scale `k` and raw scale `raw_scale` (see the
/// module documentation): q = k·x without a raw scale, else the knee blend
/// q = k_r·x + (k − k_r)·x·σ(k·x/s), with ∂q/∂x = k_r + (k − k_r)·σ³,
/// k·∂q/∂k = k·x·σ³·(1 + (k_r/k)·z²), z = k·x/s (σ + z·σ' = σ³, σ' = −z·σ³), and k_r·∂q/∂k_r =
/// k_r·x·(1 − σ) (≥ 0 for x ≥ 0: q grows with k_r too).
#[inline(always)]
pub fn map(x: f64, k: f64, raw_scale: Option<f64>) -> Mapped {
    match raw_scale {
        None => Mapped {
            q: k * x,
            dx: k,
            dlnk: k * x,
            dlnr: 0.0,
        },
        Some(kr) => {
            let z = k * x / KNEE;
            let sigma = 1.0 / (1.0 + z * z).sqrt();
            let s3 = sigma * sigma * sigma;
            Mapped {
                q: kr * x + (k - kr) * x * sigma,
                dx: kr + (k - kr) * s3,
                dlnk: k * x * s3 * (1.0 + kr / k * z * z),
                dlnr: kr * x * (1.0 - sigma),
            }
        }
    }
}

/// The raw creepage x of coordinate `q` ([`map`] inverted): q is odd and strictly increasing in x, and
/// |x| lies between |q|/k_r and |q|/k (|q| ≥ min(k, k_r)·|x| and |q| ≤ max(k, k_r)·|x|), so Newton's
/// method safeguarded by bisection in that bracket converges to the last bits.
pub fn unmap(q: f64, k: f64, raw_scale: Option<f64>) -> f64 {
    let Some(kr) = raw_scale else {
        return q / k;
    };
    let (m, sign) = (q.abs(), q.signum());
    let (mut lo, mut hi) = (m / k.max(kr), m / k.min(kr));
    let mut x = m / k;
    for _ in 0..100 {
        let f = map(x, k, raw_scale);
        if f.q < m {
            lo = x;
        } else if f.q > m {
            hi = x;
        } else {
            break;
        }
        let newton = x - (f.q - m) / f.dx;
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if next == x {
            break;
        }
        x = next;
    }
    sign * x
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
    peak_pressure(a, b, force) * libm::cbrt(REFERENCE_FORCE / force)
}

/// The contact similar to `point` with contact `e` at `ratio` times its load (docs/model.md §9.1): semi-axes
/// ·s, speed and spin /s, s = sqrt(ratio), the same ξ, η, w and p0. Its F/F_N, M_z/(F_N·c), T_max, fluid
/// share and P_f/(F_N·V) are those of `point`; a table by similarity locates both at the same coordinates.
pub fn carried(point: &OperatingPoint, e: &Ellipse, ratio: f64) -> (OperatingPoint, Ellipse) {
    let s = ratio.sqrt();
    (
        OperatingPoint {
            normal_force: point.normal_force * ratio,
            speed: point.speed / s,
            spin: point.spin / s,
            ..*point
        },
        Ellipse {
            a: e.a * s,
            b: e.b * s,
            ..*e
        },
    )
}

/// The peak pressure p0 = 3·F_N/(2π·a·b) [Pa] of semi-axes a, b [m] at normal force `force` [N] (Hertz,
/// docs/model.md §2).
pub fn peak_pressure(a: f64, b: f64, force: f64) -> f64 {
    3.0 * force / (2.0 * PI * a * b)
}

impl Coordinates {
    /// The coordinates of tables of `params` with `axes` (normalised creepages, or, format version 1, raw;
    /// knee-blended along creepage axes with a raw scale).
    pub fn new(params: &Params, axes: &Axes) -> Coordinates {
        let m = params.material.at(params.material.bulk_temperature);
        Coordinates {
            normalised: axes.normalised(),
            raw_scales: std::array::from_fn(|d| axes.0[d].raw_scale),
            raw_lengths: std::array::from_fn(|d| axes.0[d].raw_length),
            shear_modulus: m.shear_modulus,
            poisson: m.poisson,
            similarity: axes.similarity(),
            heating: super::heating::applies(params),
        }
    }

    /// Whether the creepages are normalised.
    pub fn normalised(&self) -> bool {
        self.normalised
    }

    /// The creepage scales [k_x, k_y, k_φ] (see the module documentation; [1, 1, 1] for raw creepages)
    /// [-, -, m] with their raw scales, of the contact `e` at normal force `force` [N]. Errors: semi-axes
    /// that are not positive.
    pub fn scales(&self, e: &Ellipse, force: f64) -> Result<[Scale; 3]> {
        let k = self
            .normalised
            .then(|| kalker_coefficients(e.a, e.b, self.poisson))
            .transpose()?;
        Ok(self.scales_of(e, force, k.as_ref()))
    }

    /// [`Coordinates::scales`] with the contact's Kalker coefficients `k` already computed (needed for
    /// normalised creepages).
    #[inline(always)]
    fn scales_of(&self, e: &Ellipse, force: f64, k: Option<&KalkerCoefficients>) -> [Scale; 3] {
        let k = match k {
            Some(k) if self.normalised => {
                let c = e.radius();
                let gc2 = self.shear_modulus * c * c / force;
                [gc2 * k.c11, gc2 * k.c22, gc2 * c * k.c23]
            }
            _ => [1.0; 3],
        };
        // (a loop and matches, not `array::from_fn` and `Option::map`, whose closures stay calls outside
        // the lookup kernel's instruction set)
        let mut scales = [Scale { k: 1.0, raw: None }; 3];
        for d in 0..3 {
            scales[d] = Scale {
                k: k[d],
                raw: match (self.raw_scales[d], self.raw_lengths[d]) {
                    // (semi-axes of metres: no overflow to guard against, as hypot does at its cost)
                    (Some(kr), Some(l)) => Some(kr * (e.a * e.a + e.b * e.b).sqrt() / l),
                    (kr, _) => kr,
                },
            };
        }
        scales
    }

    /// The flexibility ratios L2/L1, L3/L1 of contact `e` that its direction factor Λ weighs η and c·φ with
    /// ([`super::heating`]), or None for tables of the exact tangential solver (Λ = 1). Errors: semi-axes
    /// that are not positive.
    pub fn flexibility_ratios(&self, e: &Ellipse) -> Result<Option<FlexibilityRatios>> {
        if !self.heating {
            return Ok(None);
        }
        let k = kalker_coefficients(e.a, e.b, self.poisson)?;
        Ok(Some(self.ratios_of(e, &k)))
    }

    /// [`Coordinates::flexibility_ratios`] with the Kalker coefficients `k` of contact `e`.
    #[inline(always)]
    fn ratios_of(&self, e: &Ellipse, k: &KalkerCoefficients) -> FlexibilityRatios {
        FlexibilityRatios::of(&Flexibilities::new(e.a, e.b, self.shear_modulus, k))
    }

    /// Whether contacts are located by their equivalents at the reference load (docs/model.md §9.1).
    pub fn similarity(&self) -> bool {
        self.similarity
    }

    /// The geometry coordinates [a/b, p_ref] of contact `e` at normal force `force` [N]; with similarity
    /// p_ref is that of the equivalent contact at F_ref, i.e. the contact's own p0.
    #[inline]
    pub fn geometry(&self, e: &Ellipse, force: f64) -> [f64; 2] {
        let pressure = if self.similarity {
            peak_pressure(e.a, e.b, force)
        } else {
            reference_pressure(e.a, e.b, force)
        };
        [e.a / e.b, pressure]
    }

    /// Where `point` with contact `e` lies in the table's coordinates ([`Located`]).
    pub fn of(&self, point: &OperatingPoint, e: &Ellipse) -> Result<Located> {
        self.of_geometry(point, e, self.geometry(e, point.normal_force))
    }

    /// [`Coordinates::of`] with the contact's geometry coordinates `geometry` already computed
    /// ([`Coordinates::geometry`]).
    ///
    /// With similarity the creepages are those of the equivalent contact at F_ref: semi-axes (a, b)/s,
    /// spin φ·s, s = sqrt(F_N/F_ref) (so ξ̂, η̂ and the normalised φ̂ are the contact's own, a knee-blended
    /// φ's raw part k_r·φ·s that of the equivalent), the speed V·s. How they move with F_N: k_x, k_y ∝
    /// c²/F_N ∝ F_N^(2e−1) either way; k_φ of the equivalent ∝ (c/s)³/F_ref ∝ F_N^(3e−3/2) (one half less
    /// than the contact's own c³/F_N), φ·s ∝ F_N^(1/2), V·s ∝ F_N^(1/2), p0 ∝ F_N^(1−2e); without
    /// similarity, p_ref ∝ F_N^(2/3−2e) and F_N itself.
    #[inline]
    pub fn of_geometry(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
        geometry: [f64; 2],
    ) -> Result<Located> {
        let f = point.normal_force;
        let (force, s) = if self.similarity {
            (REFERENCE_FORCE, (f / REFERENCE_FORCE).sqrt())
        } else {
            (f, 1.0)
        };
        let equivalent = Ellipse {
            a: e.a / s,
            b: e.b / s,
            load_exponent: e.load_exponent,
        };
        let kalker = (self.normalised || self.heating)
            .then(|| kalker_coefficients(equivalent.a, equivalent.b, self.poisson))
            .transpose()?;
        let k = self.scales_of(&equivalent, force, kalker.as_ref());
        let raw = [point.creepage_x, point.creepage_y, point.spin * s];
        // Λ of the equivalent, whose c·φ·s/s is the contact's own z = c·φ (Λ is the contact's): z grows
        // with F_N like c, ∝ F_N^e
        let z = equivalent.radius() * raw[2];
        let (heating, dheating) = match kalker.filter(|_| self.heating) {
            Some(kc) => {
                let h = self.ratios_of(&equivalent, &kc).at(raw[0], raw[1], z);
                let dz = h.slope[2];
                (
                    h.value,
                    [
                        h.slope[0],
                        h.slope[1],
                        dz * equivalent.radius() * s,
                        dz * z * e.load_exponent,
                    ],
                )
            }
            None => (Heating::ONE.value, [0.0; 4]),
        };
        let mut m = [k[0].map(raw[0]), k[1].map(raw[1]), k[2].map(raw[2])];
        let exponents = self.scale_exponents(e.load_exponent);
        // a raw scale ∝ the size of the (equivalent) contact: ∝ F_N^e, with similarity F_N^(e − 1/2)
        let raw_exponent = e.load_exponent - if self.similarity { 0.5 } else { 0.0 };
        let mut dlnf = [0.0; DIMS];
        for d in 0..3 {
            dlnf[d] = m[d].dlnk * exponents[d];
            if self.raw_lengths[d].is_some() {
                dlnf[d] += m[d].dlnr * raw_exponent;
            }
        }
        let pressure_exponent = if self.similarity {
            // the equivalent's k_φ and its spin φ·s
            dlnf[2] += -0.5 * m[2].dlnk + 0.5 * m[2].dx * raw[2];
            m[2].dx *= s;
            dlnf[4] = 0.5 * point.speed * s;
            1.0 - 2.0 * e.load_exponent
        } else {
            dlnf[3] = f;
            reference_pressure_exponent(e.load_exponent)
        };
        dlnf[7] = geometry[1] * pressure_exponent;
        Ok(Located {
            q: [
                m[0].q,
                m[1].q,
                m[2].q,
                force,
                point.speed * s,
                point.wetness,
                geometry[0],
                geometry[1],
            ],
            m,
            dlnf,
            dv: s,
            raw,
            heating,
            dheating,
        })
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
                creepage_x: k[0].unmap(q[0]),
                creepage_y: k[1].unmap(q[1]),
                spin: k[2].unmap(q[2]),
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
        let c = Coordinates::new(&params, &Axes::default());
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
            let x = c.of(&point, &e).unwrap().q;
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
    fn knee_blended_coordinates_invert_and_have_their_limits_and_slopes() {
        let kr = 193.0;
        for k in [47.0, 193.0, 3200.0] {
            let mut last = f64::NEG_INFINITY;
            for n in -400..=400 {
                // raw creepages from −0.2 to 0.2, denser near 0
                let x = 0.2 * (f64::from(n) / 400.0).powi(3);
                let m = map(x, k, Some(kr));
                // odd, strictly increasing
                assert!(m.q > last || (n == -400), "k {k} x {x}");
                last = m.q;
                assert_eq!(map(-x, k, Some(kr)).q, -m.q);
                // inverse to the rounding of q times the inverse's condition number q/(x·∂q/∂x) < 5
                let back = unmap(m.q, k, Some(kr));
                assert!((back - x).abs() <= 2e-15 * x.abs(), "k {k} x {x}: {back}");
                // slopes against central differences (in x, and in ln k)
                let h = 1e-7 * (x.abs() + 1e-6);
                let fx = (map(x + h, k, Some(kr)).q - map(x - h, k, Some(kr)).q) / (2.0 * h);
                assert!(
                    (m.dx - fx).abs() <= 1e-6 * m.dx,
                    "k {k} x {x}: {} vs {fx}",
                    m.dx
                );
                let g = 1e-6;
                let fk = (map(x, k * (1.0 + g), Some(kr)).q - map(x, k * (1.0 - g), Some(kr)).q)
                    / (2.0 * g);
                assert!(
                    (m.dlnk - fk).abs() <= 1e-6 * (m.dlnk.abs() + 1e-9),
                    "k {k} x {x}: {} vs {fk}",
                    m.dlnk
                );
                // (q is linear in k_r: the difference over k_r·(1 ± 1/2), a change of k_r in all, is
                // k_r·∂q/∂k_r but for rounding)
                let fr = map(x, k, Some(kr * 1.5)).q - map(x, k, Some(kr * 0.5)).q;
                assert!(
                    (m.dlnr - fr).abs() <= 1e-6 * (m.dlnr.abs() + 1e-9),
                    "k {k} x {x}: {} vs {fr}",
                    m.dlnr
                );
                // increasing in k and k_r at fixed x > 0 (the build's coverage windows rely on it)
                assert!(x <= 0.0 || (m.dlnk > 0.0 && m.dlnr > 0.0));
            }
            // the limits: ξ̂ below the knee, raw creepage × k_r (plus the offset) far beyond it
            let x = 1e-4 * KNEE / k;
            assert!((map(x, k, Some(kr)).q / (k * x) - 1.0).abs() < 1e-7);
            let x = 1e4 * KNEE / k;
            let far = kr * x + (1.0 - kr / k) * KNEE;
            assert!(
                (map(x, k, Some(kr)).q - far).abs() < 1e-6 * far.abs(),
                "k {k}"
            );
        }
        // without a raw scale: ξ̂ = k·ξ
        assert_eq!(
            map(0.01, 193.0, None),
            Mapped {
                q: 1.93,
                dx: 193.0,
                dlnk: 1.93,
                dlnr: 0.0
            }
        );
        assert_eq!(unmap(1.93, 193.0, None), 1.93 / 193.0);
    }

    /// Coordinates of the default contact's tables with knee-blended creepage axes, and their similarity
    /// version (equivalent speeds at F_ref); `sized`: the spin's raw scale in proportion to the contact's
    /// size.
    fn blended_coordinates(similarity: bool, sized: bool) -> Coordinates {
        let mut axes = Axes::default();
        for (d, k) in [200.0, 170.0, 0.4].into_iter().enumerate() {
            axes.0[d].raw_scale = Some(k);
        }
        if sized {
            axes.0[2].raw_length = Some(0.012);
        }
        if similarity {
            axes.0[3].points = vec![REFERENCE_FORCE];
            axes.0[4].similarity = true;
        }
        axes.validate().unwrap();
        Coordinates::new(&Params::default(), &axes)
    }

    /// A contact and its copy λ times as large at λ² the load, rolling at V/λ with spin φ/λ (the similarity
    /// of docs/model.md §9.1) lie at the same coordinates of a table by similarity: the equivalent at F_ref
    /// (F_N coordinate F_ref, speed V·sqrt(F_N/F_ref), p_ref = p0), creepages within the same raw limits.
    #[test]
    fn similarity_locates_a_contact_by_its_equivalent_at_the_reference_load() {
        for sized in [false, true] {
            located_by_the_equivalent(&blended_coordinates(true, sized));
        }
        assert!(!blended_coordinates(false, false).similarity());
    }

    fn located_by_the_equivalent(c: &Coordinates) {
        assert!(c.similarity());
        let point = OperatingPoint {
            creepage_x: 0.004,
            creepage_y: -0.002,
            spin: 0.3,
            normal_force: 60e3,
            speed: 25.0,
            wetness: 0.1,
        };
        let e = Ellipse {
            a: 4.0e-3,
            b: 7.0e-3,
            load_exponent: Ellipse::HERTZ,
        };
        let at = c.of(&point, &e).unwrap();
        let s = (60e3 / REFERENCE_FORCE).sqrt();
        assert_eq!(at.q[3], REFERENCE_FORCE);
        assert!((at.q[4] - 25.0 * s).abs() < 1e-12);
        assert!((at.q[7] / peak_pressure(4e-3, 7e-3, 60e3) - 1.0).abs() < 1e-14);
        assert!((at.raw[2] - 0.3 * s).abs() < 1e-15);
        for l in [0.25, 0.7, 3.0] {
            let (other, big) = carried(&point, &e, l * l);
            let there = c.of(&other, &big).unwrap();
            for d in 0..DIMS {
                assert!(
                    (there.q[d] - at.q[d]).abs() <= 1e-12 * at.q[d].abs().max(1e-3),
                    "λ {l}, coordinate {d}: {} vs {}",
                    there.q[d],
                    at.q[d]
                );
            }
            for d in 0..3 {
                assert!((there.raw[d] - at.raw[d]).abs() <= 1e-14);
            }
        }
    }

    /// The slopes of [`Located`] (∂q/∂ creepage, ∂q/∂ln F_N with the semi-axes following the load like
    /// F_N^e, ∂q_V/∂V) are those of finite differences, with and without similarity, knee-blended.
    #[test]
    fn located_slopes_match_finite_differences() {
        let point = OperatingPoint {
            creepage_x: 0.003,
            creepage_y: 0.001,
            spin: -0.2,
            normal_force: 80e3,
            speed: 30.0,
            wetness: 0.0,
        };
        for (similarity, sized) in [(false, false), (true, false), (false, true), (true, true)] {
            let c = blended_coordinates(similarity, sized);
            for exponent in [Ellipse::HERTZ, 0.0] {
                let e = Ellipse {
                    a: 5e-3,
                    b: 8e-3,
                    load_exponent: exponent,
                };
                let at = c.of(&point, &e).unwrap();
                let h = 1e-6;
                let loaded = |f: f64| {
                    let s = (f / point.normal_force).powf(exponent);
                    let el = Ellipse {
                        a: e.a * s,
                        b: e.b * s,
                        ..e
                    };
                    let p = OperatingPoint {
                        normal_force: f,
                        ..point
                    };
                    c.of(&p, &el).unwrap().q
                };
                let (hi, lo) = (
                    loaded(point.normal_force * (1.0 + h)),
                    loaded(point.normal_force * (1.0 - h)),
                );
                for d in 0..DIMS {
                    let fd = (hi[d] - lo[d]) / (2.0 * h);
                    assert!(
                        (fd - at.dlnf[d]).abs() <= 1e-5 * fd.abs().max(at.q[d].abs()).max(1e-3),
                        "similarity {similarity}, e {exponent}, ∂q_{d}/∂ln F_N: {fd} vs {}",
                        at.dlnf[d]
                    );
                }
                let moved = |d: usize, x: f64| {
                    let mut p = point;
                    match d {
                        0 => p.creepage_x += x,
                        1 => p.creepage_y += x,
                        2 => p.spin += x,
                        _ => p.speed += x,
                    }
                    c.of(&p, &e).unwrap().q
                };
                for (d, step, slope, coordinate) in [
                    (0, 1e-8, at.m[0].dx, 0),
                    (1, 1e-8, at.m[1].dx, 1),
                    (2, 1e-6, at.m[2].dx, 2),
                    (4, 1e-5, at.dv, 4),
                ] {
                    let fd =
                        (moved(d, step)[coordinate] - moved(d, -step)[coordinate]) / (2.0 * step);
                    assert!(
                        (fd - slope).abs() <= 1e-6 * fd.abs().max(1.0),
                        "similarity {similarity}, input {d}: {fd} vs {slope}"
                    );
                }
            }
        }
    }

    #[test]
    fn scale_exponents_match_finite_differences() {
        let params = Params::default();
        let c = Coordinates::new(&params, &Axes::default());
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
                let fd = (hi[d].k.ln() - lo[d].k.ln()) / (2e-6);
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
