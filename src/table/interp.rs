//! One-dimensional interpolation weights along one axis, precomputed per interval.
//!
//! **Cubic:** the C¹ cubic Hermite spline on non-uniform points whose node slopes are those of the parabola
//! through the node and its two neighbours, d_j = (h_(j−1)·s_j + h_j·s_(j−1))/(h_(j−1) + h_j) with
//! s_j = (y_(j+1) − y_j)/h_j (one-sided parabola at the ends) — the non-uniform Catmull–Rom spline. It is
//! linear in the data, so it is a weighted sum of four neighbouring values, exact for quadratics, with
//! error O(h³). On a mirrored axis the points are extended by their mirror images (ghost nodes), so the
//! spline is C¹ across 0 and the slope there is central.
//!
//! **Linear:** weights (1 − t, t).
//!
//! A [`Stencil`] holds the first node of the window (−1 for the ghost of node 1 on a mirrored axis) and the
//! weights and their derivatives with respect to the coordinate.

use super::axes::{Axis, Interpolation};

/// Weights of the nodes start..start+4 (linear: start..start+2) at one coordinate.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Stencil {
    /// First node of the window (−1: the mirror image of node 1).
    pub start: isize,
    /// Weights.
    pub w: [f64; 4],
    /// Derivatives of the weights with respect to the coordinate [1/unit].
    pub dw: [f64; 4],
}

/// Precomputed interpolation along one axis.
#[derive(Debug, Clone)]
pub(crate) struct AxisInterp {
    points: Vec<f64>,
    inv_h: Vec<f64>,
    /// Per interval: first node of the window.
    starts: Vec<isize>,
    /// Per interval: weight of window node r as the cubic Σ_p c[r][p]·t^p in t ∈ [0, 1].
    coeffs: Vec<[[f64; 4]; 4]>,
}

/// Slope weights of the parabola through three extended nodes at node j (over all extended nodes).
fn node_slope(x: &[f64], j: usize) -> [(usize, f64); 3] {
    let n = x.len();
    if j == 0 || j == n - 1 {
        // one-sided parabola through the end node and its two inner neighbours:
        // d_0 = s_0 + (s_0 − s_1)·h_0/(h_0 + h_1)
        let (a, b, c) = if j == 0 {
            (0, 1, 2)
        } else {
            (n - 1, n - 2, n - 3)
        };
        let h0 = x[b] - x[a];
        let h1 = x[c] - x[b];
        let f = h0 / (h0 + h1);
        // s0 = (y_b − y_a)/h0, s1 = (y_c − y_b)/h1
        let (sa, sb0) = (-1.0 / h0, 1.0 / h0);
        let (sb1, sc) = (-1.0 / h1, 1.0 / h1);
        [
            (a, sa * (1.0 + f)),
            (b, sb0 * (1.0 + f) - f * sb1),
            (c, -f * sc),
        ]
    } else {
        let hl = x[j] - x[j - 1];
        let hr = x[j + 1] - x[j];
        let s = hl + hr;
        let cr = hl / (hr * s);
        let cl = -hr / (hl * s);
        [(j - 1, cl), (j, -cr - cl), (j + 1, cr)]
    }
}

impl AxisInterp {
    /// The interpolation of `axis` with the given kind.
    pub fn new(axis: &Axis, kind: Interpolation) -> Self {
        let p = &axis.points;
        let n = p.len();
        let inv_h: Vec<f64> = p.windows(2).map(|w| 1.0 / (w[1] - w[0])).collect();
        let (starts, coeffs) = match kind {
            Interpolation::Linear => (
                (0..n - 1).map(|i| i as isize).collect(),
                vec![
                    [
                        [1.0, -1.0, 0.0, 0.0],
                        [0.0, 1.0, 0.0, 0.0],
                        [0.0; 4],
                        [0.0; 4]
                    ];
                    n - 1
                ],
            ),
            Interpolation::Cubic => {
                // extended points: mirror images of points 1.. in front of a mirrored axis
                let off = if axis.mirrored { n - 1 } else { 0 };
                let mut x: Vec<f64> = p[1..].iter().rev().map(|v| -v).take(off).collect();
                x.extend_from_slice(p);
                let ne = x.len();
                let mut starts = Vec::with_capacity(n - 1);
                let mut coeffs = Vec::with_capacity(n - 1);
                // Hermite basis h00, h10, h01, h11 as coefficients of 1, t, t², t³
                const H00: [f64; 4] = [1.0, 0.0, -3.0, 2.0];
                const H10: [f64; 4] = [0.0, 1.0, -2.0, 1.0];
                const H01: [f64; 4] = [0.0, 0.0, 3.0, -2.0];
                const H11: [f64; 4] = [0.0, 0.0, -1.0, 1.0];
                for i in 0..n - 1 {
                    let e = i + off;
                    let s = e.saturating_sub(1).min(ne - 4);
                    let h = x[e + 1] - x[e];
                    let mut c = [[0.0; 4]; 4];
                    for p in 0..4 {
                        c[e - s][p] += H00[p];
                        c[e + 1 - s][p] += H01[p];
                    }
                    for (node, basis) in [(e, H10), (e + 1, H11)] {
                        for (m, a) in node_slope(&x, node) {
                            for p in 0..4 {
                                c[m - s][p] += h * a * basis[p];
                            }
                        }
                    }
                    starts.push(s as isize - off as isize);
                    coeffs.push(c);
                }
                (starts, coeffs)
            }
        };
        Self {
            points: p.clone(),
            inv_h,
            starts,
            coeffs,
        }
    }

    /// The coordinate clamped to the axis (lowest stored point to highest) and whether it was inside.
    #[inline]
    pub fn clamp(&self, x: f64) -> (f64, bool) {
        let lo = self.points[0];
        let hi = self.points[self.points.len() - 1];
        if x < lo {
            (lo, false)
        } else if x > hi {
            (hi, false)
        } else {
            (x, true)
        }
    }

    /// Weights at `x` (already inside the stored range).
    #[inline]
    pub fn stencil(&self, x: f64) -> Stencil {
        let n = self.points.len();
        let i = self.points.partition_point(|p| *p <= x).clamp(1, n - 1) - 1;
        let ih = self.inv_h[i];
        let t = (x - self.points[i]) * ih;
        let c = &self.coeffs[i];
        let mut st = Stencil {
            start: self.starts[i],
            ..Default::default()
        };
        for r in 0..4 {
            let [c0, c1, c2, c3] = c[r];
            st.w[r] = c0 + t * (c1 + t * (c2 + t * c3));
            st.dw[r] = (c1 + t * (2.0 * c2 + t * 3.0 * c3)) * ih;
        }
        st
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axis(points: &[f64], mirrored: bool) -> Axis {
        Axis {
            points: points.to_vec(),
            mirrored,
        }
    }

    /// Interpolates node values `y(x_j)` (with the mirror rule y(−x) = sign·y(x) for ghost nodes).
    fn interp(ai: &AxisInterp, y: &dyn Fn(f64) -> f64, sign: f64, x: f64) -> (f64, f64) {
        let st = ai.stencil(x);
        let (mut v, mut d) = (0.0, 0.0);
        for r in 0..4 {
            let g = st.start + r as isize;
            if st.w[r] == 0.0 && st.dw[r] == 0.0 {
                continue;
            }
            let yv = if g < 0 {
                sign * y(ai.points[(-g) as usize])
            } else {
                y(ai.points[g as usize])
            };
            v += st.w[r] * yv;
            d += st.dw[r] * yv;
        }
        (v, d)
    }

    #[test]
    fn cubic_reproduces_quadratics_on_non_uniform_points() {
        let pts = [-0.1, -0.03, -0.004, 0.0, 0.002, 0.01, 0.05, 0.1];
        let ai = AxisInterp::new(&axis(&pts, false), Interpolation::Cubic);
        let q = |x: f64| 0.3 - 2.0 * x + 7.0 * x * x;
        for k in 0..=200 {
            let x = -0.1 + 0.2 * k as f64 / 200.0;
            let (v, d) = interp(&ai, &q, 1.0, x);
            assert!((v - q(x)).abs() < 1e-13, "x {x}: {v} vs {}", q(x));
            assert!((d - (-2.0 + 14.0 * x)).abs() < 1e-10, "x {x}: {d}");
        }
    }

    #[test]
    fn mirrored_cubic_uses_ghost_nodes_for_odd_and_even_functions() {
        let pts = [0.0, 0.001, 0.004, 0.012, 0.03];
        let ai = AxisInterp::new(&axis(&pts, true), Interpolation::Cubic);
        assert_eq!(ai.stencil(0.0005).start, -1);
        let even = |x: f64| 1.0 + 3.0 * x * x;
        for k in 0..=100 {
            let x = 0.03 * k as f64 / 100.0;
            let (v, d) = interp(&ai, &even, 1.0, x);
            assert!((v - even(x)).abs() < 1e-13);
            assert!((d - 6.0 * x).abs() < 1e-9);
        }
        // odd data (ghost = −node): the slope at 0 is the central one through the ghost, y(x_1)/x_1, not
        // the one-sided parabola's (which is 0 for y = x·|x| = x² on x ≥ 0)
        let oddsq = |x: f64| x * x.abs();
        let (_, d0) = interp(&ai, &oddsq, -1.0, 0.0);
        assert!((d0 - 0.001).abs() < 1e-15, "{d0}");
        let lin = |x: f64| 2.0 * x;
        for k in 0..=100 {
            let x = 0.03 * k as f64 / 100.0;
            let (v, d) = interp(&ai, &lin, -1.0, x);
            assert!((v - 2.0 * x).abs() < 1e-15 && (d - 2.0).abs() < 1e-11);
        }
    }

    #[test]
    fn cubic_error_falls_as_h_cubed() {
        let f = |x: f64| (3.0 * x).sin();
        let err = |n: usize| {
            let pts: Vec<f64> = (0..n).map(|k| k as f64 / (n - 1) as f64).collect();
            let ai = AxisInterp::new(&axis(&pts, false), Interpolation::Cubic);
            (0..1000)
                .map(|k| {
                    let x = (k as f64 + 0.5) / 1000.0;
                    (interp(&ai, &f, 1.0, x).0 - f(x)).abs()
                })
                .fold(0.0, f64::max)
        };
        let (e1, e2) = (err(11), err(21));
        let order = (e1 / e2).log2();
        assert!(order > 2.7, "observed order {order} ({e1}, {e2})");
    }

    #[test]
    fn linear_weights_and_clamping() {
        let ai = AxisInterp::new(&axis(&[1.0, 2.0, 4.0], false), Interpolation::Linear);
        let st = ai.stencil(3.0);
        assert_eq!(st.start, 1);
        assert_eq!(&st.w[..2], &[0.5, 0.5]);
        assert_eq!(&st.dw[..2], &[-0.5, 0.5]);
        let st = ai.stencil(4.0);
        assert_eq!((st.start, st.w[1]), (1, 1.0));
        assert_eq!(ai.clamp(5.0), (4.0, false));
        assert_eq!(ai.clamp(0.0), (1.0, false));
        assert_eq!(ai.clamp(1.5), (1.5, true));
    }
}
