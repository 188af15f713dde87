//! Dimensionless Greenwood–Williamson integrals with the Zhao–Maietta–Chang asperity law (docs/model.md §4).
//!
//! Heights, separation and interference are scaled by z_s: s = z/z_s, h = d/z_s, u = ω/z_s = s − h,
//! c = ω_c/z_s, c_p = ω_p/z_s = 54·c. With φ0 the standard normal density (P4 with z_s = 1),
//! - A_m/A_n = π·β·𝒜(h),  𝒜 = ∫_0^∞ a(u)·φ0(h + u) du, with a = u (elastic, u ≤ c),
//!   u·(1 + 3t² − 2t³) (elasto-plastic, t = (u − c)/(c_p − c)), 2u (fully plastic, u ≥ c_p);
//! - p_m·A_m/A_n = L0·𝒫(h), L0 = β·E*·sqrt(z_s/R_a), 𝒫 = ∫_0^∞ p(u)·φ0(h + u) du, with p = (4/3)·u^1.5
//!   (elastic), (2√c/K)·a(u)·(1 − (1 − 2K/3)·λ) (elasto-plastic, λ = ln(c_p/u)/ln 54), (2√c/K)·a(u)
//!   (plastic), because H = (2E*/(πK))·sqrt(ω_c/R_a);
//! - d𝒫/dh = −∫_0^∞ p(u)·(h + u)·φ0(h + u) du and d𝒜/dh likewise (the limits in u do not depend on h).
//!
//! Evaluation (fast, for any c): the elastic part is F_1.5(h) from a table minus its tail beyond c, the
//! elastic tail and the elasto-plastic band share one Gauss–Legendre quadrature over the band restricted
//! to the window where the Gaussian weight matters, and the fully plastic part is in closed form
//! (∫_{c_p}^∞ u·φ0(h + u) du = φ0(x) − h·F0(x), x = h + c_p). For small c (hot, soft asperities) the
//! elastic part is integrated directly over [0, c] instead, which avoids cancellation.

use super::table::ReferenceIntegral;
use crate::quadrature::gauss_legendre::GaussLegendre;

/// ω_p/ω_c of the ZMC model.
pub const PLASTIC_RATIO: f64 = 54.0;
/// 1/sqrt(2π).
const INV_SQRT_2PI: f64 = 0.398_942_280_401_432_7;
/// Drop of −ln φ0 beyond the peak at which the Gaussian weight is neglected: e^−27 ≈ 2e−12.
pub const TAIL: f64 = 27.0;
/// Above this h every integral underflows (φ0(38.6) < 1e−323): the result is exactly zero.
pub const H_ZERO: f64 = 38.5;

/// Standard normal density φ0(s) (P4 with z_s = 1).
#[inline]
pub fn phi0(s: f64) -> f64 {
    INV_SQRT_2PI * (-0.5 * s * s).exp()
}

/// Upper tail F0(x) = ∫_x^∞ φ0(s) ds = ½·erfc(x/√2) (P5 with z_s = 1).
#[inline]
pub fn upper_tail(x: f64) -> f64 {
    0.5 * libm::erfc(x * std::f64::consts::FRAC_1_SQRT_2)
}

/// F1(x) = ∫_x^∞ (s − x)·φ0(s) ds = φ0(x) − x·F0(x) (closed form).
#[inline]
pub fn f1(x: f64) -> f64 {
    phi0(x) - x * upper_tail(x)
}

/// The ZMC law in dimensionless form for one material state.
#[derive(Debug, Clone, Copy)]
pub struct Law {
    /// c = ω_c/z_s.
    pub c: f64,
    /// c_p = 54·c.
    pub cp: f64,
    /// 1 − 2K/3.
    kappa: f64,
    /// 2√c/K: elasto-plastic and plastic load per unit a(u) (= πβH/L0).
    pub plastic_coef: f64,
    /// ln c_p.
    ln_cp: f64,
    /// 1/(c_p − c).
    inv_band: f64,
}

impl Law {
    /// Law for c = ω_c/z_s > 0 and K = 0.454 + 0.41ν.
    pub fn new(c: f64, k: f64) -> Self {
        let cp = PLASTIC_RATIO * c;
        Self {
            c,
            cp,
            kappa: 1.0 - 2.0 * k / 3.0,
            plastic_coef: 2.0 * c.sqrt() / k,
            ln_cp: cp.ln(),
            inv_band: 1.0 / (cp - c),
        }
    }

    /// Dimensionless asperity area a(u) and load p(u) in every regime (u ≥ 0).
    pub fn asperity(&self, u: f64) -> (f64, f64) {
        if u <= self.c {
            (u, elastic(u))
        } else if u < self.cp {
            let (a, p) = self.band(u);
            (u + a, p)
        } else {
            (2.0 * u, 2.0 * self.plastic_coef * u)
        }
    }

    /// Elasto-plastic band, c ≤ u ≤ c_p: (a(u) − u, p(u)).
    #[inline]
    fn band(&self, u: f64) -> (f64, f64) {
        let t = (u - self.c) * self.inv_band;
        let bump = t * t * (3.0 - 2.0 * t);
        let lambda = (self.ln_cp - u.ln()) * (1.0 / PLASTIC_RATIO.ln());
        (
            u * bump,
            self.plastic_coef * u * (1.0 + bump) * (1.0 - self.kappa * lambda),
        )
    }
}

/// Elastic asperity load (4/3)·u^1.5 (dimensionless).
#[inline]
fn elastic(u: f64) -> f64 {
    4.0 / 3.0 * u * u.sqrt()
}

/// Dimensionless results 𝒜, 𝒫 and d𝒫/dh.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Integrals {
    /// 𝒜(h) = (A_m/A_n)/(πβ).
    pub area: f64,
    /// 𝒫(h) = (p_m A_m/A_n)/L0.
    pub load: f64,
    /// d𝒫/dh.
    pub dload: f64,
    /// d𝒜/dh.
    pub darea: f64,
}

/// The quadrature scheme: rules (and the process-wide F_1.5 table, built on first use).
#[derive(Debug, Clone)]
pub struct Scheme {
    band_rule: GaussLegendre,
    band_pieces: usize,
    elastic_rule: GaussLegendre,
    /// Below this c the elastic part is integrated directly over [0, c].
    direct_below: f64,
}

impl Scheme {
    /// Scheme with `band_nodes` Gauss–Legendre nodes on each of `band_pieces` sub-intervals of the band
    /// (in w = √u), `elastic_nodes` on the direct elastic piece, and the direct/table switch at c = `direct_below`.
    pub fn new(
        band_nodes: usize,
        band_pieces: usize,
        elastic_nodes: usize,
        direct_below: f64,
    ) -> Self {
        Self {
            band_rule: GaussLegendre::new(band_nodes),
            band_pieces,
            elastic_rule: GaussLegendre::new(elastic_nodes),
            direct_below,
        }
    }

    /// Adds ∫ f(u)·φ0(h + u) du over [ua, ub] (area and load integrands from `f`) with `pieces` equal
    /// sub-intervals in w = √u (u = w², du = 2w dw), `rule` on each.
    #[inline]
    fn piece(
        rule: &GaussLegendre,
        pieces: usize,
        h: f64,
        ua: f64,
        ub: f64,
        f: impl Fn(f64) -> (f64, f64),
        acc: &mut Integrals,
    ) {
        if ub <= ua {
            return;
        }
        let (wa, wb) = (ua.sqrt(), ub.sqrt());
        let width = (wb - wa) / pieces as f64;
        let half = 0.5 * width;
        for k in 0..pieces {
            let mid = wa + (k as f64 + 0.5) * width;
            for (x, wt) in rule.nodes.iter().zip(&rule.weights) {
                let w = mid + half * x;
                let u = w * w;
                let (fa, fl) = f(u);
                let s = h + u;
                let g = wt * half * 2.0 * w * phi0(s);
                acc.area += g * fa;
                acc.load += g * fl;
                acc.dload -= g * fl * s;
                acc.darea -= g * fa * s;
            }
        }
    }

    /// 𝒜, 𝒫 and d𝒫/dh at h for the law (h finite or +∞; −∞ gives infinities).
    pub fn integrals(&self, h: f64, law: &Law) -> Integrals {
        if h >= H_ZERO {
            return Integrals::default();
        }
        let reach = (2.0 * TAIL).sqrt();
        let s_lo = h.max(-reach);
        let s_hi = (h.max(0.0).powi(2) + 2.0 * TAIL).sqrt();
        let (u_lo, u_hi) = (s_lo - h, s_hi - h);
        // elastic area part ∫_0^∞ u·φ0(h + u) du = F1(h), dF1/dh = −F0(h) (closed form)
        let mut acc = Integrals {
            area: f1(h),
            darea: -upper_tail(h),
            ..Integrals::default()
        };
        // elastic part: table minus tail (tail subtracted in the band and plastic pieces), or direct
        let subtract = law.c >= self.direct_below && u_lo == 0.0;
        if subtract {
            let (f, df) = ReferenceIntegral::f15().value_and_derivative(h);
            acc.load += 4.0 / 3.0 * f;
            acc.dload += 4.0 / 3.0 * df;
        } else {
            let (rule, pieces) = if law.c < self.direct_below {
                (&self.elastic_rule, 1)
            } else {
                (&self.band_rule, self.band_pieces)
            };
            Self::piece(
                rule,
                pieces,
                h,
                u_lo,
                law.c.min(u_hi),
                |u| (0.0, elastic(u)),
                &mut acc,
            );
        }
        let sub = if subtract { 1.0 } else { 0.0 };
        // elasto-plastic band, restricted to the window
        let (ba, bb) = (law.c.max(u_lo), law.cp.min(u_hi));
        Self::piece(
            &self.band_rule,
            self.band_pieces,
            h,
            ba,
            bb,
            |u| {
                let (a, p) = law.band(u);
                (a, p - sub * elastic(u))
            },
            &mut acc,
        );
        // fully plastic: ∫_{cp}^∞ u·φ0(h + u) du = φ0(x) − h·F0(x), x = h + c_p (closed form)
        let x = h + law.cp;
        let (f0x, phx) = (upper_tail(x), phi0(x));
        let m1 = phx - h * f0x;
        let pl = 2.0 * law.plastic_coef;
        let dm1 = -f0x - law.cp * phx;
        acc.area += m1;
        acc.darea += dm1;
        acc.load += pl * m1;
        acc.dload += pl * dm1;
        if subtract {
            // the elastic tail beyond c_p inside the window
            Self::piece(
                &self.band_rule,
                1,
                h,
                law.cp.max(u_lo),
                u_hi,
                |u| (0.0, -elastic(u)),
                &mut acc,
            );
        }
        acc
    }
}
