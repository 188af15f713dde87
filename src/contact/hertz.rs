//! Hertz solution for the elliptic contact of two bodies from their relative curvatures (docs/model.md §2).

use crate::error::{Error, Result, Stage, check_positive};
use std::f64::consts::PI;

/// Complete elliptic integrals K(e) and E(e) of the first and second kind, modulus `e` ∈ [0, 1)
/// (arithmetic–geometric mean; Abramowitz & Stegun 17.6). Returns (K, E).
pub fn complete_elliptic_integrals(e: f64) -> (f64, f64) {
    let mut a = 1.0_f64;
    let mut b = (1.0 - e * e).sqrt();
    let mut c = e;
    let mut sum = 0.5 * c * c;
    let mut pow = 0.5;
    for _ in 0..64 {
        if c.abs() < 1e-17 {
            break;
        }
        let an = 0.5 * (a + b);
        let bn = (a * b).sqrt();
        c = 0.5 * (a - b);
        pow *= 2.0;
        sum += pow * c * c;
        a = an;
        b = bn;
    }
    let k = PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// The Hertz contact: semi-axes, peak pressure and approach.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzContact {
    /// Semi-axis along the rolling direction x [m].
    pub a: f64,
    /// Lateral semi-axis along y [m].
    pub b: f64,
    /// Peak Hertz pressure p0 = 3·F_N/(2π·a·b) [Pa].
    pub p0: f64,
    /// Normal approach δ [m] (NaN when the semi-axes were prescribed).
    pub approach: f64,
    /// Normal force [N].
    pub normal_force: f64,
}

/// Ratio A_l/A_s of the curvatures as a function of the eccentricity e (docs/model.md §2).
fn curvature_ratio(e: f64) -> f64 {
    let (k, ee) = complete_elliptic_integrals(e);
    (ee / (1.0 - e * e) - k) / (k - ee)
}

/// The squared eccentricity e² ∈ (0, 1) of the contact ellipse whose curvature ratio
/// (E/(1−e²) − K)/(K − E) is `ratio` > 1 (docs/model.md §2). A_l/A_s(e) increases monotonically from 1 to
/// ∞; in t = −ln(1 − e²) its logarithm is nearly linear (≈ 3t/4 … for small e, ≈ t − ln(ln 4 + t/2 − 1)
/// for e → 1: K ≈ ln 4 + t/2, E → 1), so the root of ln(A_l/A_s(t)) − ln(ratio), bracketed in
/// t ∈ [0, −ln 1e-16], is found by secant steps inside the bracket (regula falsi with the Illinois halving
/// of the stale end's value, Dahlquist & Björck §6.2.3: superlinear, about 10 evaluations where bisection
/// on e² takes 53) until the bracket is below 1e-16 in e² (or a few ulps in t). NaN for a ratio that no e² < 1 reaches in
/// double precision.
fn eccentricity_squared(ratio: f64) -> f64 {
    let e2 = |t: f64| -(-t).exp_m1();
    let f = |t: f64| curvature_ratio(e2(t).sqrt()).ln() - ratio.ln();
    let (mut lo, mut f_lo) = (0.0_f64, -ratio.ln());
    let mut hi = -(1e-16_f64).ln();
    let mut f_hi = f(hi);
    if !(f_hi > 0.0 && f_lo < 0.0) {
        return f64::NAN;
    }
    // which end the last step moved (+1 hi, −1 lo): moving the same end twice halves the other's value
    let mut side = 0;
    for _ in 0..200 {
        // done when e² is bracketed to 1e-16 or t to a few ulps (where e² near 1 rounds coarser)
        if e2(hi) - e2(lo) < 1e-16 || hi - lo <= 4.0 * f64::EPSILON * hi {
            break;
        }
        let secant = lo - f_lo * (hi - lo) / (f_hi - f_lo);
        // a step that stalls at an end bisects instead
        let t = if secant > lo && secant < hi {
            secant
        } else {
            0.5 * (lo + hi)
        };
        let ft = f(t);
        if ft == 0.0 {
            return e2(t);
        }
        if ft < 0.0 {
            (lo, f_lo) = (t, ft);
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        } else {
            (hi, f_hi) = (t, ft);
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        }
    }
    0.5 * (e2(lo) + e2(hi))
}

/// The load-independent part of a Hertz contact (docs/model.md §2): for curvatures A, B [1/m] and composite
/// modulus E* [Pa], the eccentricity e from (E/(1−e²) − K)/(K − E) = A_l/A_s, solved once; then
/// [`HertzShape::contact`] gives the contact at any normal force (m ∝ F_N^{1/3}) with the same arithmetic
/// as [`HertzContact::from_curvatures`], bit for bit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzShape {
    /// The factor of 3F_N in m³'s numerator: K − E for an ellipse, 1 for a circle [-].
    numerator: f64,
    /// m³'s denominator: 2π E* e² A_s for an ellipse, 8 E* A for a circle [Pa/m].
    denominator: f64,
    /// The minor over the major semi-axis, n/m = sqrt(1 − e²) [-].
    aspect: f64,
    /// K(e) (π/2 for a circle) [-].
    k_int: f64,
    /// E* [Pa].
    e_star: f64,
    /// Whether the major semi-axis lies along x (A ≤ B: along the direction of the smaller curvature).
    major_along_x: bool,
}

impl HertzShape {
    /// The shape for curvatures A (along x) and B (along y) [1/m] and composite modulus E* [Pa]
    /// (docs/model.md §2): the eccentricity from [`eccentricity_squared`].
    pub fn from_curvatures(curv_x: f64, curv_y: f64, e_star: f64) -> Result<Self> {
        check_positive("curvature_x", curv_x, "1/m")?;
        check_positive("curvature_y", curv_y, "1/m")?;
        check_positive("e_star", e_star, "Pa")?;
        let (a_s, a_l) = (curv_x.min(curv_y), curv_x.max(curv_y));
        let ratio = a_l / a_s;
        let (numerator, denominator, aspect, k_int) = if ratio < 1.0 + 1e-10 {
            // circle: (K − E)/e² → π/4, m³ = 3F/(8E*A)
            (1.0, 8.0 * e_star * a_s, 1.0, PI / 2.0)
        } else {
            let e2 = eccentricity_squared(ratio);
            if !(e2 > 0.0 && e2 < 1.0) {
                return Err(Error::Numerical {
                    stage: Stage::Hertz,
                    reason: format!("no eccentricity for curvature ratio {ratio}"),
                });
            }
            let (k, ee) = complete_elliptic_integrals(e2.sqrt());
            (k - ee, 2.0 * PI * e_star * e2 * a_s, (1.0 - e2).sqrt(), k)
        };
        Ok(Self {
            numerator,
            denominator,
            aspect,
            k_int,
            e_star,
            major_along_x: curv_x <= curv_y,
        })
    }

    /// The contact at normal force F_N [N] (docs/model.md §2): m³ = 3F_N(K − E)/(2π E* e² A_s) (circle:
    /// 3F_N/(8E*A)), n = m·sqrt(1 − e²), p0 = 3F_N/(2π m n), δ = 3F_N K/(2π E* m).
    pub fn contact(&self, normal_force: f64) -> Result<HertzContact> {
        check_positive("normal_force", normal_force, "N")?;
        let major = (3.0 * normal_force * self.numerator / self.denominator).cbrt();
        let minor = major * self.aspect;
        let (a, b) = if self.major_along_x {
            (major, minor)
        } else {
            (minor, major)
        };
        Ok(HertzContact {
            a,
            b,
            p0: 3.0 * normal_force / (2.0 * PI * a * b),
            approach: 3.0 * normal_force * self.k_int / (2.0 * PI * self.e_star * major),
            normal_force,
        })
    }
}

impl HertzContact {
    /// Hertz contact for curvatures A (along x) and B (along y) [1/m], normal force F_N [N] and composite
    /// modulus E* [Pa] (docs/model.md §2): [`HertzShape::from_curvatures`], then [`HertzShape::contact`].
    pub fn from_curvatures(
        curv_x: f64,
        curv_y: f64,
        normal_force: f64,
        e_star: f64,
    ) -> Result<Self> {
        check_positive("curvature_x", curv_x, "1/m")?;
        check_positive("curvature_y", curv_y, "1/m")?;
        check_positive("normal_force", normal_force, "N")?;
        HertzShape::from_curvatures(curv_x, curv_y, e_star)?.contact(normal_force)
    }

    /// Contact with prescribed semi-axes [m] (e.g. from a non-Hertzian normal solver).
    pub fn from_semi_axes(a: f64, b: f64, normal_force: f64) -> Result<Self> {
        check_positive("semi-axis a", a, "m")?;
        check_positive("semi-axis b", b, "m")?;
        check_positive("normal_force", normal_force, "N")?;
        Ok(Self {
            a,
            b,
            p0: 3.0 * normal_force / (2.0 * PI * a * b),
            approach: f64::NAN,
            normal_force,
        })
    }

    /// Peak of the parabolic pressure with the same force, 2·F_N/(π·a·b) [Pa] (paper §3, consistent with
    /// FASTSIM).
    pub fn parabolic_peak(&self) -> f64 {
        2.0 * self.normal_force / (PI * self.a * self.b)
    }

    /// Nominal pressure mapped to the parabola, p_n = (2F_N/(πab))·(1 − x²/a² − y²/b²), ≥ 0 [Pa].
    pub fn parabolic_pressure(&self, x: f64, y: f64) -> f64 {
        let s = 1.0 - (x / self.a).powi(2) - (y / self.b).powi(2);
        self.parabolic_peak() * s.max(0.0)
    }

    /// Hertz's ellipsoidal pressure, p_n = p0·sqrt(1 − x²/a² − y²/b²), ≥ 0 [Pa] (docs/model.md §2; K.L.
    /// Johnson, *Contact Mechanics*, 1985, eq. 7.39).
    pub fn hertz_pressure(&self, x: f64, y: f64) -> f64 {
        let s = 1.0 - (x / self.a).powi(2) - (y / self.b).powi(2);
        self.p0 * s.max(0.0).sqrt()
    }

    /// sqrt(a·b) [m], Kalker's c.
    pub fn c(&self) -> f64 {
        (self.a * self.b).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn elliptic_integrals_known_values() {
        let (k, e) = complete_elliptic_integrals(0.0);
        assert!(rel(k, PI / 2.0) < 1e-15 && rel(e, PI / 2.0) < 1e-15);
        // K(k = sin 45°) = 1.854074677301372, E = 1.350643881047675 (A&S table 17.5)
        let (k, e) = complete_elliptic_integrals(std::f64::consts::FRAC_1_SQRT_2);
        assert!(rel(k, 1.854_074_677_301_372) < 1e-13);
        assert!(rel(e, 1.350_643_881_047_675) < 1e-13);
    }

    #[test]
    fn eccentricity_is_the_bisection_root() {
        // reference: plain bisection of the monotone curvature ratio on e² to 1e-16
        let bisection = |ratio: f64| {
            let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
            for _ in 0..200 {
                if hi - lo < 1e-16 {
                    break;
                }
                let mid = 0.5 * (lo + hi);
                if curvature_ratio(mid.sqrt()) < ratio {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        };
        for ratio in [1.001, 1.3, 2.408, 7.0, 16.6, 120.0, 1e4] {
            let (e2, reference) = (eccentricity_squared(ratio), bisection(ratio));
            // near a circle K − E and E/(1 − e²) − K cancel: the computed ratio is not monotone to
            // the last bits there, which blurs its root (measured: relative 5e-8 at a ratio of 1.001,
            // 2e-12 at 1.3, 4e-15 at 2.4), for bisection and secant alike
            let noise = 1e-12 + 2e-13 / (ratio - 1.0).powi(2);
            assert!(
                (e2 - reference).abs() <= noise * reference,
                "ratio {ratio}: {e2} vs {reference}"
            );
        }
        assert!(eccentricity_squared(1e300).is_nan());
    }

    #[test]
    fn model_md_reference_case_within_0_1_percent() {
        // F_N = 100 kN, A = 1.015, B = 0.4215 /m, E = 210 GPa, ν = 0.28 (Ertz & Knothe / CONTACT)
        let e_star = 210e9 / (2.0 * (1.0 - 0.28 * 0.28));
        let h = HertzContact::from_curvatures(1.015, 0.4215, 100e3, e_star).unwrap();
        assert!(rel(h.a, 5.879e-3) < 1e-3, "a = {}", h.a);
        assert!(rel(h.b, 10.540e-3) < 1e-3, "b = {}", h.b);
        assert!(rel(h.p0, 770.5e6) < 1e-3, "p0 = {}", h.p0);
        assert!(rel(h.approach, 0.0819e-3) < 1e-3, "δ = {}", h.approach);
    }

    #[test]
    fn circle_limit_matches_hertz_sphere() {
        // sphere R = 0.5 m on flat: A = B = 1/(2R) = 1; a³ = 3FR/(4E*)
        let e_star = 115e9;
        let f = 10e3;
        let h = HertzContact::from_curvatures(1.0, 1.0, f, e_star).unwrap();
        let a = (3.0 * f * 0.5 / (4.0 * e_star)).cbrt();
        assert!(rel(h.a, a) < 1e-12 && rel(h.b, a) < 1e-12);
        // δ = a²/R
        assert!(rel(h.approach, a * a / 0.5) < 1e-12);
        // nearly circular from the elliptic branch agrees with the circle branch
        let h2 = HertzContact::from_curvatures(1.0, 1.0 + 1e-6, f, e_star).unwrap();
        assert!(rel(h2.a, a) < 1e-5 && rel(h2.b, a) < 1e-5);
    }

    #[test]
    fn swapping_curvatures_swaps_axes_and_force_scales_as_cube_root() {
        let e_star = 113.9e9;
        let h1 = HertzContact::from_curvatures(1.015, 0.4215, 100e3, e_star).unwrap();
        let h2 = HertzContact::from_curvatures(0.4215, 1.015, 100e3, e_star).unwrap();
        assert!(rel(h1.a, h2.b) < 1e-12 && rel(h1.b, h2.a) < 1e-12);
        let h8 = HertzContact::from_curvatures(1.015, 0.4215, 800e3, e_star).unwrap();
        assert!(rel(h8.a, 2.0 * h1.a) < 1e-10);
        // parabola carries the same force: ∫∫ p dA = p_peak·πab/2
        assert!(rel(h1.parabolic_peak() * PI * h1.a * h1.b / 2.0, 100e3) < 1e-14);
    }

    /// Both pressures integrate to F_N (midpoint rule on a fine grid; the ellipsoid's square-root edge
    /// converges slowly), and the ellipsoid peaks at p0 = 1.5·F_N/(πab).
    #[test]
    fn hertz_and_parabolic_pressures_carry_the_normal_force() {
        let h = HertzContact::from_semi_axes(6e-3, 10e-3, 100e3).unwrap();
        let grid = crate::contact::ContactGrid::for_contact(&h, 400, 400);
        let force = |p: fn(&HertzContact, f64, f64) -> f64| {
            let v: Vec<f64> = grid.cells.iter().map(|c| p(&h, c.x, c.y)).collect();
            grid.integrate(&v)
        };
        assert!(rel(force(HertzContact::hertz_pressure), 100e3) < 1e-3);
        assert!(rel(force(HertzContact::parabolic_pressure), 100e3) < 1e-4);
        assert_eq!(h.hertz_pressure(0.0, 0.0), h.p0);
        assert_eq!(h.hertz_pressure(6e-3, 0.0), 0.0);
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(HertzContact::from_curvatures(-1.0, 1.0, 1e3, 1e11).is_err());
        assert!(HertzContact::from_curvatures(1.0, 1.0, f64::NAN, 1e11).is_err());
        assert!(HertzContact::from_semi_axes(0.0, 1.0, 1e3).is_err());
    }
}
