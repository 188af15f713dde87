//! Heights of one fluid cell (paper eqs. P7–P11, P15; docs/model.md §8): base height, cell height, equivalent
//! metallic volume height and the void height open to the fluid.

use std::f64::consts::{PI, SQRT_2};

/// Inverse error function, |x| < 1 (Giles 2010 single-precision seed refined by two Newton steps on erf,
/// accurate to double precision).
pub fn erf_inv(x: f64) -> f64 {
    if x <= -1.0 {
        return f64::NEG_INFINITY;
    }
    if x >= 1.0 {
        return f64::INFINITY;
    }
    let w = -((1.0 - x) * (1.0 + x)).ln();
    let mut y = if w < 5.0 {
        let w = w - 2.5;
        let mut p = 2.810_226_36e-08;
        for c in [
            3.432_739_39e-07,
            -3.523_387_7e-06,
            -4.391_506_54e-06,
            0.000_218_580_87,
            -0.001_253_725_03,
            -0.004_177_681_64,
            0.246_640_727,
            1.501_409_41,
        ] {
            p = c + p * w;
        }
        p * x
    } else {
        let w = w.sqrt() - 3.0;
        let mut p = -0.000_200_214_257;
        for c in [
            0.000_100_950_558,
            0.001_349_343_22,
            -0.003_673_428_44,
            0.005_739_507_73,
            -0.007_622_461_3,
            0.009_438_870_47,
            1.001_674_06,
            2.832_976_82,
        ] {
            p = c + p * w;
        }
        p * x
    };
    for _ in 0..2 {
        let err = libm::erf(y) - x;
        y -= err / (2.0 / PI.sqrt() * (-y * y).exp());
    }
    y
}

/// Cell base height d_b = √2·z_s·erfinv(1 − 2ψ_b) [m] (P7): the height above which a share ψ_b of the
/// asperities reaches (ψ_b = 0.9995 → d_b = −3.2905·z_s).
pub fn base_height(z_s: f64, psi_b: f64) -> f64 {
    SQRT_2 * z_s * erf_inv(1.0 - 2.0 * psi_b)
}

/// Heights of one cell at separation d, all in m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellGeometry {
    /// Cell height l_c = d − d_b (P8).
    pub cell_height: f64,
    /// Equivalent metallic volume height l_m = ∫_{d_b}^{d} ψ(z) dz (P10, P11).
    pub metal_height: f64,
    /// Void height open to the fluid l_v = l_c − l_m (the height in A_x = l_v·h_y, P15).
    pub void_height: f64,
    /// d l_v / d d = 1 − ψ(d) [-].
    pub void_slope: f64,
}

/// Antiderivative of ψ(z) = ½·erfc(z/(√2 z_s)): ∫ψ dz = z·ψ(z) − z_s²·φ(z), φ the Gaussian density (P4).
fn psi_antiderivative(z: f64, z_s: f64) -> f64 {
    let t = z / z_s;
    let psi = 0.5 * libm::erfc(t / SQRT_2);
    let phi = (-0.5 * t * t).exp() / ((2.0 * PI).sqrt() * z_s);
    z * psi - z_s * z_s * phi
}

impl CellGeometry {
    /// Cell heights at separation `d` for the surface with height deviation `z_s` and base height `d_b`
    /// ([`CellHeights::at`]).
    pub fn at(d: f64, z_s: f64, d_b: f64) -> Self {
        CellHeights::new(z_s, d_b).at(d)
    }
}

/// The heights of the cells of one surface (height deviation z_s) and base height d_b (P7–P11), with the
/// terms of the closed forms that depend on d_b alone evaluated once: the film solve and the assembly of
/// a solution evaluate them for every cell at the same z_s and d_b.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellHeights {
    /// Height deviation z_s [m].
    z_s: f64,
    /// Base height d_b [m].
    d_b: f64,
    /// ∫ψ dz at d_b, [z·ψ(z) − z_s²·φ(z)] at z = d_b [m²/m].
    metal_at_base: f64,
    /// The same at z = −d_b, the lower limit of the void integral [m].
    void_at_base: f64,
}

impl CellHeights {
    /// The heights of a surface with height deviation `z_s` [m] and base height `d_b` [m].
    pub fn new(z_s: f64, d_b: f64) -> Self {
        Self {
            z_s,
            d_b,
            metal_at_base: psi_antiderivative(d_b, z_s),
            void_at_base: psi_antiderivative(-d_b, z_s),
        }
    }

    /// Cell heights at separation `d` (closed form of P11: l_m = [z·ψ(z) − z_s²·φ(z)] from d_b to d). The
    /// void height is computed as ∫_{d_b}^{d} (1 − ψ) dz directly, which keeps its full relative accuracy
    /// when it is tiny ([`Self::void`]).
    pub fn at(&self, d: f64) -> CellGeometry {
        let (void_height, void_slope) = self.void(d);
        CellGeometry {
            cell_height: d - self.d_b,
            metal_height: psi_antiderivative(d, self.z_s) - self.metal_at_base,
            void_height,
            void_slope,
        }
    }

    /// The void height l_v open to the fluid at separation `d` [m] and its slope d l_v / d d [-] (the
    /// fields `void_height`, `void_slope` of [`Self::at`]): l_v = ∫_{d_b}^{d} (1 − ψ) dz, with
    /// 1 − ψ(z) = ψ(−z), so ∫_{−d}^{−d_b} ψ(u) du.
    ///
    /// Below the base height (d < d_b, l_c < 0: asperities pressed so far that their voids lie below d_b,
    /// docs/model.md §8.2) the voids are closed: l_v = 0, and so is its slope, the derivative of the
    /// clamped l_v (the film's cell solve relies on it to step out of the closed range, docs/model.md
    /// §8.7). At d = d_b the slope is the one from above, 1 − ψ(d_b), where a closed cell opens.
    pub fn void(&self, d: f64) -> (f64, f64) {
        let void_height = (self.void_at_base - psi_antiderivative(-d, self.z_s)).max(0.0);
        let void_slope = if d - self.d_b >= 0.0 {
            0.5 * libm::erfc(-d / (SQRT_2 * self.z_s))
        } else {
            0.0
        };
        (void_height, void_slope)
    }
}

/// The separation d ≥ d_b [m] at which the void height (P10, P11) is `void` > 0 [m]: the inverse of
/// l_v(d) = ∫_{d_b}^{d} (1 − ψ) dz of [`CellGeometry::at`] above the base height `d_b` (docs/model.md §8.2).
///
/// With x = d/z_s, l_v = z_s·(G(x) − G(x_b)), G(x) = x·Φ(x) + φ0(x) (Φ, φ0 the standard normal distribution
/// and density; 1 − ψ(z) = Φ(z/z_s)). Newton's method on ln G(x) = ln(G(x_b) + l_v/z_s), started at x_b:
/// G is log-concave (the integral of the log-concave Φ), so the iterates increase monotonically to the root
/// without overshooting; stopped when the step is below 1e-15·max(1, |x|).
pub fn separation_for_void(void: f64, z_s: f64, d_b: f64) -> f64 {
    let g = |x: f64| {
        let cdf = 0.5 * libm::erfc(-x / SQRT_2);
        (x * cdf + (-0.5 * x * x).exp() / (2.0 * PI).sqrt(), cdf)
    };
    let x_b = d_b / z_s;
    let target = (g(x_b).0 + void / z_s).ln();
    let mut x = x_b;
    for _ in 0..200 {
        let (gx, cdf) = g(x);
        let step = (target - gx.ln()) * gx / cdf;
        x += step;
        if step.abs() <= 1e-15 * x.abs().max(1.0) {
            break;
        }
    }
    x * z_s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erf_inv_inverts_erf() {
        for x in [-0.999_999, -0.9, -0.3, 0.0, 1e-9, 0.5, 0.9995, 0.999_999_9] {
            let y = erf_inv(x);
            assert!((libm::erf(y) - x).abs() < 1e-15, "x = {x}");
        }
    }

    #[test]
    fn base_height_matches_model_md() {
        // ψ_b = 0.9995 → d_b = −3.2905·z_s
        let db = base_height(1e-6, 0.9995);
        assert!((db / 1e-6 + 3.2905).abs() < 1e-4, "{db}");
        // ψ(d_b) = ψ_b by definition (P5, P7)
        assert!((0.5 * libm::erfc(db / (SQRT_2 * 1e-6)) - 0.9995).abs() < 1e-12);
    }

    /// Composite Simpson on many panels: an independent numerical integration of P10/P11.
    fn simpson(f: impl Fn(f64) -> f64, a: f64, b: f64, n: usize) -> f64 {
        let h = (b - a) / n as f64;
        let mut s = f(a) + f(b);
        for k in 1..n {
            s += f(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        s * h / 3.0
    }

    #[test]
    fn metal_height_closed_form_equals_numerical_integral() {
        let z_s = 1.3e-6;
        let d_b = base_height(z_s, 0.9995);
        let psi = |z: f64| 0.5 * libm::erfc(z / (SQRT_2 * z_s));
        for t in [-3.0, -2.0, -0.5, 0.0, 1.0, 3.0] {
            let d = t * z_s;
            let g = CellGeometry::at(d, z_s, d_b);
            let lm = simpson(psi, d_b, d, 20_000);
            let lv = simpson(|z| 1.0 - psi(z), d_b, d, 20_000);
            assert!((g.metal_height - lm).abs() < 1e-10 * z_s, "l_m at {t}");
            assert!((g.void_height - lv).abs() < 1e-10 * z_s, "l_v at {t}");
            assert!((g.cell_height - g.metal_height - g.void_height).abs() < 1e-12 * z_s);
        }
    }

    /// Below the base height the void is closed: l_v = 0 and its slope 0 (the slope of the clamped
    /// height, which the film's cell solve steps along); from d_b up the slope is 1 − ψ. The separation
    /// of a void height inverts l_v(d) above d_b.
    #[test]
    fn the_void_is_closed_below_the_base_height_and_its_height_inverts() {
        let z_s = 5e-6;
        let d_b = base_height(z_s, 0.9995);
        for t in [-6.0, -4.0, -3.3] {
            let g = CellGeometry::at(t * z_s, z_s, d_b);
            assert_eq!((g.void_height, g.void_slope), (0.0, 0.0), "{t}");
        }
        let at_base = CellGeometry::at(d_b, z_s, d_b);
        assert_eq!(at_base.void_height, 0.0);
        assert!(
            (at_base.void_slope - 5e-4).abs() < 1e-12,
            "{}",
            at_base.void_slope
        );
        for void in [1e-15, 1e-12, 1e-9, 3e-8, 1e-6, 2e-5, 1e-3] {
            let d = separation_for_void(void, z_s, d_b);
            assert!(d > d_b);
            let back = CellGeometry::at(d, z_s, d_b).void_height;
            assert!(
                (back - void).abs() <= 1e-12 * void + 1e-22,
                "{void:e}: {back:e}"
            );
        }
    }

    #[test]
    fn void_height_is_positive_and_grows_with_separation() {
        let z_s = 1e-6;
        let d_b = base_height(z_s, 0.9995);
        let mut last = 0.0;
        for k in 0..60 {
            let d = d_b + 1e-9 + k as f64 * 0.15 * z_s;
            let g = CellGeometry::at(d, z_s, d_b);
            assert!(g.void_height > last);
            last = g.void_height;
            // slope: central difference
            let e = 1e-4 * z_s;
            let fd = (CellGeometry::at(d + e, z_s, d_b).void_height
                - CellGeometry::at(d - e, z_s, d_b).void_height)
                / (2.0 * e);
            assert!((fd - g.void_slope).abs() < 1e-6);
        }
        // far above the asperities the void is the whole gap above the mean plane: l_v → d (+ tiny)
        let g = CellGeometry::at(8.0 * z_s, z_s, d_b);
        assert!((g.void_height - 8.0 * z_s).abs() < 1e-3 * z_s);
    }
}
