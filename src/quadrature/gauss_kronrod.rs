//! Adaptive Gauss–Kronrod quadrature (7-point Gauss, 15-point Kronrod; Piessens et al., QUADPACK 1983)
//! with an absolute error target, used for the lateral integral of the moving-source kernel; its G7/K15 panel
//! also serves the microcontact's reference quadrature in tests.

/// Kronrod abscissae on [−1, 1] (non-negative half, descending); the odd entries are the Gauss nodes.
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
/// Kronrod weights belonging to [`XGK`].
const WGK: [f64; 8] = [
    0.022_935_322_010_529_225,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_18,
    0.140_653_259_715_525_92,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_83,
];
/// Gauss weights of the nodes XGK[1], XGK[3], XGK[5], XGK[7].
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// Result of an adaptive integration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quadrature {
    /// The integral.
    pub value: f64,
    /// Estimated absolute error (sum over panels of |Kronrod − Gauss|, a conservative bound).
    pub error: f64,
    /// Number of panels evaluated (15 integrand evaluations each).
    pub panels: usize,
    /// True if every accepted panel met its share of the tolerance within the panel budget.
    pub converged: bool,
}

/// The 15 Kronrod nodes of [lo, hi] in the order [`kronrod_sum`] expects: the centre, then the pairs
/// centre ∓ half·XGK[k] for k = 0…6.
pub(crate) fn kronrod_nodes(lo: f64, hi: f64) -> [f64; 15] {
    let centre = 0.5 * (lo + hi);
    let half = 0.5 * (hi - lo);
    let mut nodes = [centre; 15];
    for k in 0..7 {
        let dx = half * XGK[k];
        nodes[1 + 2 * k] = centre - dx;
        nodes[2 + 2 * k] = centre + dx;
    }
    nodes
}

/// One G7/K15 panel on [lo, hi] from the integrand's values at [`kronrod_nodes`]:
/// (Kronrod value, |Kronrod − Gauss|).
pub(crate) fn kronrod_sum(values: &[f64; 15], lo: f64, hi: f64) -> (f64, f64) {
    let half = 0.5 * (hi - lo);
    let mut kronrod = WGK[7] * values[0];
    let mut gauss = WG[3] * values[0];
    for k in 0..7 {
        let pair = values[1 + 2 * k] + values[2 + 2 * k];
        kronrod += WGK[k] * pair;
        if k % 2 == 1 {
            gauss += WG[k / 2] * pair;
        }
    }
    (kronrod * half, ((kronrod - gauss) * half).abs())
}

/// One G7/K15 panel on [lo, hi]: (Kronrod value, |Kronrod − Gauss|).
pub(crate) fn gauss_kronrod_15(f: &impl Fn(f64) -> f64, lo: f64, hi: f64) -> (f64, f64) {
    kronrod_sum(&kronrod_nodes(lo, hi).map(f), lo, hi)
}

/// Integrates `f` over [breaks[0], breaks[last]] (ascending break points, at least two), starting with one
/// panel per break interval and bisecting any panel whose error exceeds its share `tol·width/total` of the
/// absolute tolerance, up to `max_panels` panels. Features much narrower than a panel must sit at a break
/// point (a sampling rule cannot see a peak that falls between its nodes). Panels still too coarse when the budget runs out are
/// accepted and the result is flagged unconverged.
pub fn integrate_adaptive(
    f: impl Fn(f64) -> f64,
    breaks: &[f64],
    tol: f64,
    max_panels: usize,
) -> Quadrature {
    let mut result = Quadrature {
        value: 0.0,
        error: 0.0,
        panels: 0,
        converged: true,
    };
    let (Some(&first), Some(&last)) = (breaks.first(), breaks.last()) else {
        return result;
    };
    let total = last - first;
    if total <= 0.0 {
        return result;
    }
    let mut stack: Vec<(f64, f64)> = breaks
        .windows(2)
        .filter(|w| w[1] > w[0])
        .map(|w| (w[0], w[1]))
        .collect();
    while let Some((lo, hi)) = stack.pop() {
        let (value, error) = gauss_kronrod_15(&f, lo, hi);
        result.panels += 1;
        let share = tol * (hi - lo) / total;
        let mid = 0.5 * (lo + hi);
        let can_split = mid > lo && mid < hi;
        if error <= share || !can_split || result.panels + stack.len() >= max_panels {
            if error > share {
                result.converged = false;
            }
            result.value += value;
            result.error += error;
        } else {
            stack.push((mid, hi));
            stack.push((lo, mid));
        }
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polynomials_up_to_degree_22_are_exact_on_one_panel() {
        // K15 integrates degree 3·7+1 = 22 exactly: ∫_0^2 x^22 dx = 2^23/23.
        let q = integrate_adaptive(|x| x.powi(22), &[0.0, 2.0], 1e-6, 1);
        let exact = 2f64.powi(23) / 23.0;
        assert!(((q.value - exact) / exact).abs() < 1e-13);
        assert_eq!(q.panels, 1);
    }

    #[test]
    fn resolves_a_log_singularity_and_a_narrow_peak() {
        // ∫_0^1 ln x dx = −1 (endpoint singularity).
        let q = integrate_adaptive(f64::ln, &[0.0, 1.0], 1e-10, 10_000);
        assert!(q.converged && (q.value + 1.0).abs() < 1e-10, "{q:?}");
        // ∫_{-1}^{1} exp(−x²/(2σ²)) dx with σ = 1e-3: σ·sqrt(2π); the peak is announced by a break point
        // (features narrower than a panel that fall between nodes cannot be seen by any sampling rule).
        let s = 1e-3;
        let q = integrate_adaptive(
            |x| (-x * x / (2.0 * s * s)).exp(),
            &[-1.0, 0.0, 1.0],
            1e-12,
            10_000,
        );
        let exact = s * (2.0 * std::f64::consts::PI).sqrt();
        assert!(q.converged && (q.value - exact).abs() < 1e-12, "{q:?}");
    }

    #[test]
    fn exhausted_budget_is_reported() {
        let q = integrate_adaptive(|x| x.sin() / x.max(1e-300), &[1e-9, 1e4], 1e-14, 3);
        assert!(!q.converged);
        assert!(q.error > 0.0);
    }
}
