//! One-dimensional interpolation along one axis, precomputed per interval.
//!
//! **Cubic (monotone):** the C¹ cubic Hermite spline on non-uniform points with the node slopes of Steffen
//! (M. Steffen, "A simple method for monotonic interpolation in one dimension", Astron. Astrophys. 239
//! (1990) 443–450): at an interior node
//! y'_i = (sign s_(i−1) + sign s_i)·min(|s_(i−1)|, |s_i|, ½|p_i|), p_i = (s_(i−1)·h_i + s_i·h_(i−1))/(h_(i−1) + h_i),
//! with s the secants; at an end node the one-sided parabola slope, limited to [0, 2·s]. The spline never
//! overshoots monotone data — creep curves bend sharply where they saturate, and an unlimited
//! (Catmull–Rom) spline overshoots there by several per cent of F_N — and is third-order accurate where the
//! data are smooth and monotone; it reproduces linear data exactly. On a mirrored axis the points are
//! extended by their mirror images (ghost nodes), so the spline is C¹ across 0 with a central slope there.
//!
//! The slope is piecewise linear and positively homogeneous in the data, so on each branch the interpolated
//! value is v = Σ_j w_j·y_j over the four window nodes with **data-dependent weights** w_j = ∂v/∂y_j: a
//! fibre evaluation returns them, which is what tensor-product evaluation and exact derivatives need.
//!
//! **Linear:** the five linearly interpolated dimensions are interpolated together: speed and wetness
//! multilinearly (they act jointly on the fluid film, with a large cross-derivative), normal force and
//! contact geometry (a/b, p_ref) on the Kuhn (Freudenthal) triangulation of their cell: with the fractions
//! t_d ∈ [0, 1] of these coordinates in their intervals sorted in descending order t_(o0) ≥ t_(o1) ≥ t_(o2),
//! the value is that of the simplex with corners v_0 = the cell's lowest node, v_(k+1) = v_k + e_(ok),
//! weights 1 − t_(o0), t_(o0) − t_(o1), t_(o1) − t_(o2), t_(o2). So 4 × 4 = 16 corners instead of the 32
//! of multilinear interpolation in five dimensions; continuous, exact for data multilinear in (V, w) and
//! affine in (F_N, a/b, p_ref), and a convex combination of node values (so it keeps the monotonicity of
//! the creep curves along the cubic axes). A single-point axis contributes nothing (its coordinate is that
//! point). On a log axis ([`Interpolation::Log`]) the fraction is that of ln x, so the class reproduced
//! exactly is affine (multilinear) in the logarithm of that coordinate; in the cells of a linear axis
//! from its [`Axis::sqrt_from`] point up, that of √x (data linear in √x there, in x below). Measured on
//! the format-1 default table (F_N, V, w linear): simplices over all three gave
//! |ΔF|/F_N p99 1.1e-2 against 6e-3 multilinear; with (V, w) multilinear the results are the multilinear
//! ones (F_N alone on the simplex is linear).

use super::axes::{Axis, Interpolation, LINEAR_DIMS};

/// Positions among the linear dimensions (F_N, V, w, a/b, p_ref) interpolated multilinearly: V, w.
pub const MULTILINEAR: [usize; 2] = [1, 2];
/// Positions among the linear dimensions interpolated on simplices: F_N, a/b, p_ref.
pub const SIMPLICIAL: [usize; 3] = [0, 3, 4];
/// Number of corners of the linear stencil: 2² multilinear × (3 + 1) simplex corners.
pub const CORNERS: usize = (1 << MULTILINEAR.len()) * (SIMPLICIAL.len() + 1);

/// Where a coordinate lies on a linear axis: interval start node, fraction t ∈ [0, 1], and the inverse
/// interval length (0 on a single-point axis, whose t is 0).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Fraction {
    /// First node of the interval.
    pub start: usize,
    /// Position in the interval [-].
    pub t: f64,
    /// 1/(x_(start+1) − x_start) [1/unit]; 0 on a single-point axis.
    pub inv_h: f64,
}

/// The corners of the linear stencil at one point: node `start + step[c]` along each linear dimension,
/// weights and their derivatives, for the first `n` corners (single-point axes add none: a table of one
/// geometry has 2² × 2 = 8).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Corners {
    /// Number of corners.
    pub n: usize,
    /// Node index along each linear dimension of the cell's lowest node.
    pub start: [usize; LINEAR_DIMS],
    /// Per corner: 0 or 1 node beyond `start` along each linear dimension.
    pub step: [[usize; LINEAR_DIMS]; CORNERS],
    /// Corner weights (≥ 0, sum 1).
    pub w: [f64; CORNERS],
    /// ∂w_c/∂x_d: derivatives of the weights with respect to each linear coordinate [1/unit].
    pub dw: [[f64; CORNERS]; LINEAR_DIMS],
}

/// The dimensions among `dims` whose axes have more than one point (a next node to step to), first, and
/// their number.
#[inline(always)]
fn stepping<const N: usize>(dims: [usize; N], f: &[Fraction; LINEAR_DIMS]) -> ([usize; N], usize) {
    let mut out = [0usize; N];
    let mut k = 0;
    for d in dims {
        if f[d].inv_h > 0.0 {
            out[k] = d;
            k += 1;
        }
    }
    (out, k)
}

/// Number of simplex corners: the simplicial dimensions plus one.
const SIMPLEX: usize = SIMPLICIAL.len() + 1;

/// The simplicial dimensions with more than one point, by descending fraction (ties keep the dimension
/// order), and their number.
#[inline(always)]
fn simplex_order(f: &[Fraction; LINEAR_DIMS]) -> ([usize; SIMPLICIAL.len()], usize) {
    let (mut order, k_s) = stepping(SIMPLICIAL, f);
    for i in 1..k_s {
        let mut j = i;
        while j > 0 && f[order[j - 1]].t < f[order[j]].t {
            order.swap(j - 1, j);
            j -= 1;
        }
    }
    (order, k_s)
}

/// The weights of the simplex corners: 1 − t_(o0), t_(o0) − t_(o1), …, t_(o(k−1)) (the first `k_s` + 1).
#[inline(always)]
fn simplex_weights(
    f: &[Fraction; LINEAR_DIMS],
    order: &[usize; SIMPLICIAL.len()],
    k_s: usize,
) -> [f64; SIMPLEX] {
    let mut ws = [0.0; SIMPLEX];
    ws[0] = if k_s > 0 { 1.0 - f[order[0]].t } else { 1.0 };
    for k in 0..k_s {
        let next = if k + 1 < k_s { f[order[k + 1]].t } else { 0.0 };
        ws[k + 1] = f[order[k]].t - next;
    }
    ws
}

/// The corners of the linear stencil as row offsets: per corner (in the order of [`Corners::of`])
/// Σ_d (start_d + step_d)·stride_d and its weight, for the first `n`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Offsets {
    /// Number of corners.
    pub n: usize,
    /// Row offset of each corner.
    pub off: [usize; CORNERS],
    /// Corner weights (≥ 0, sum 1), those of [`Corners::of`].
    pub w: [f64; CORNERS],
}

impl Offsets {
    /// The corners of the stencil of the fractions `f` as offsets in rows of the given `strides` along the
    /// linear dimensions.
    #[inline(always)]
    pub fn of(f: &[Fraction; LINEAR_DIMS], strides: &[usize; LINEAR_DIMS]) -> Offsets {
        let (order, k_s) = simplex_order(f);
        let ws = simplex_weights(f, &order, k_s);
        let mut s_off = [0usize; SIMPLEX];
        for k in 0..k_s {
            s_off[k + 1] = s_off[k] + strides[order[k]];
        }
        let (multi, k_m) = stepping(MULTILINEAR, f);
        let start: usize = (0..LINEAR_DIMS).map(|d| f[d].start * strides[d]).sum();
        let mut c = Offsets {
            n: (1 << k_m) * (k_s + 1),
            off: [0; CORNERS],
            w: [0.0; CORNERS],
        };
        // the multilinear corners (bit b of m: one node further along multi[b]) times the simplex's
        for m in 0..(1 << k_m) {
            let (mut wm, mut o) = (1.0, start);
            for (b, &d) in multi[..k_m].iter().enumerate() {
                if (m >> b) & 1 == 1 {
                    wm *= f[d].t;
                    o += strides[d];
                } else {
                    wm *= 1.0 - f[d].t;
                }
            }
            for k in 0..=k_s {
                let i = m * (k_s + 1) + k;
                c.off[i] = o + s_off[k];
                c.w[i] = wm * ws[k];
            }
        }
        c
    }

    /// The corners of a value (no derivatives): those of [`Offsets::of`] without the steps along the
    /// dimensions whose coordinate lies on the first node of its interval (t = 0), as along a
    /// single-point axis. The corners one node further along such a dimension have weight 0 and add nothing
    /// to a value (0·y = 0 for finite y: the sums are bit for bit the same), so their rows need not be read:
    /// a dry contact's wetness 0 halves the corners, a simplicial coordinate on a node leaves one corner of
    /// the simplex out. (Corners of weight 0 at ties of simplicial fractions or at t = 1 remain.)
    #[inline(always)]
    pub fn of_value(f: &[Fraction; LINEAR_DIMS], strides: &[usize; LINEAR_DIMS]) -> Offsets {
        let mut on_nodes = *f;
        for x in &mut on_nodes {
            if x.t == 0.0 {
                x.inv_h = 0.0;
            }
        }
        Offsets::of(&on_nodes, strides)
    }

    /// The largest offset: that of the last corner, one node further along every dimension it steps along.
    #[inline(always)]
    pub fn farthest(&self) -> usize {
        self.off[self.n - 1]
    }
}

impl Corners {
    /// The stencil of the fractions `f` of the linear coordinates (simplex ties keep the dimension order,
    /// so the result is deterministic).
    #[inline(always)]
    pub fn of(f: &[Fraction; LINEAR_DIMS]) -> Corners {
        let (order, k_s) = simplex_order(f);
        let ws = simplex_weights(f, &order, k_s);
        let mut dws = [[0.0; SIMPLEX]; LINEAR_DIMS];
        let mut steps_s = [[0usize; LINEAR_DIMS]; SIMPLEX];
        for k in 0..k_s {
            let d = order[k];
            dws[d][k] = -f[d].inv_h;
            dws[d][k + 1] = f[d].inv_h;
            steps_s[k + 1] = steps_s[k];
            steps_s[k + 1][d] = 1;
        }
        // the multilinear axes with more than one point
        let (multi, k_m) = stepping(MULTILINEAR, f);
        let mut c = Corners {
            n: (1 << k_m) * (k_s + 1),
            start: std::array::from_fn(|d| f[d].start),
            step: [[0; LINEAR_DIMS]; CORNERS],
            w: [0.0; CORNERS],
            dw: [[0.0; CORNERS]; LINEAR_DIMS],
        };
        // the multilinear corners (bit b of m: one node further along multi[b]) times the simplex's
        for m in 0..(1 << k_m) {
            let mut wm = 1.0;
            let mut dwm = [1.0; MULTILINEAR.len()];
            let mut step = [0usize; LINEAR_DIMS];
            for (b, &d) in multi[..k_m].iter().enumerate() {
                let up = (m >> b) & 1 == 1;
                let (w, dw) = if up {
                    (f[d].t, f[d].inv_h)
                } else {
                    (1.0 - f[d].t, -f[d].inv_h)
                };
                step[d] = usize::from(up);
                wm *= w;
                for (e, x) in dwm[..k_m].iter_mut().enumerate() {
                    *x *= if e == b { dw } else { w };
                }
            }
            for k in 0..=k_s {
                let i = m * (k_s + 1) + k;
                c.w[i] = wm * ws[k];
                for (b, &d) in multi[..k_m].iter().enumerate() {
                    c.dw[d][i] = dwm[b] * ws[k];
                }
                for &d in &order[..k_s] {
                    c.dw[d][i] = wm * dws[d][k];
                }
                for d in 0..LINEAR_DIMS {
                    c.step[i][d] = step[d] + steps_s[k][d];
                }
            }
        }
        c
    }
}

/// The cubic window at one coordinate: nodes start..start + 4 (start = −1: the mirror image of node 1),
/// the interval between window nodes `a` and `a + 1`, and the Hermite basis there.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CubicStencil {
    /// First node of the window.
    pub start: isize,
    a: usize,
    /// Inverse spacings of the window's three gaps.
    inv_h: [f64; 3],
    /// Length of the interval.
    h: f64,
    /// Whether node a is the first (node a + 1 the last) point of the (extended) axis.
    first: bool,
    last: bool,
    /// Slope mixing factors of nodes a and a + 1: α = h_r/(h_l + h_r) inside, f = h_0/(h_0 + h_1) at an end.
    mix: [f64; 2],
    /// Hermite basis h00, h10, h01, h11 at t and their t-derivatives.
    basis: [f64; 4],
    dbasis: [f64; 4],
}

/// Steffen's slope at an interior node from the secants left and right of it and α = h_r/(h_l + h_r):
/// (sign s_l + sign s_r)·min(|s_l|, |s_r|, ½|p|), p = α·s_l + (1 − α)·s_r.
#[inline(always)]
fn interior_slope(sl: f64, sr: f64, alpha: f64) -> f64 {
    // branch-free (a select), so that lane loops over several fibres vectorise
    let p = alpha * sl + (1.0 - alpha) * sr;
    let m = (2.0 * sl.abs())
        .min(2.0 * sr.abs())
        .min(p.abs())
        .copysign(sl);
    if sl * sr <= 0.0 { 0.0 } else { m }
}

/// Steffen's slope at an end node from the adjacent secant s0, the next one s1 and f = h_0/(h_0 + h_1):
/// the one-sided parabola slope p = s0·(1 + f) − s1·f, 0 if it opposes s0, at most 2·s0.
#[inline(always)]
fn end_slope(s0: f64, s1: f64, f: f64) -> f64 {
    let p = s0 * (1.0 + f) - s1 * f;
    let m = p.abs().min(2.0 * s0.abs()).copysign(s0);
    if p * s0 <= 0.0 { 0.0 } else { m }
}

/// Steffen's slopes at all points of a (non-mirrored) axis `x` for the values `y` (at least 3 points):
/// the slopes the window evaluation uses, for precomputing them once per table point.
pub fn node_slopes(x: &[f64], y: &[f64], out: &mut [f64]) {
    let n = x.len();
    let sec = |i: usize| (y[i + 1] - y[i]) / (x[i + 1] - x[i]);
    let h = |i: usize| x[i + 1] - x[i];
    out[0] = end_slope(sec(0), sec(1), h(0) / (h(0) + h(1)));
    out[n - 1] = end_slope(sec(n - 2), sec(n - 3), h(n - 2) / (h(n - 2) + h(n - 3)));
    for (m, o) in out.iter_mut().enumerate().take(n - 1).skip(1) {
        *o = interior_slope(sec(m - 1), sec(m), h(m) / (h(m - 1) + h(m)));
    }
}

/// One fibre evaluated: value, derivative along the axis, and the weights ∂v/∂y_j of the window nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fibre {
    /// Interpolated value.
    pub v: f64,
    /// Derivative with respect to the coordinate [1/unit].
    pub dv: f64,
    /// v = Σ w_j·y_j, w_j = ∂v/∂y_j.
    pub w: [f64; 4],
}

/// Slope at a window node as coefficients over window nodes (a linear form in the data).
type Slope = [f64; 4];

impl CubicStencil {
    /// Steffen's slope at interior window node m (neighbours m − 1, m + 1).
    #[inline(always)]
    fn interior(&self, y: &[f64; 4], m: usize) -> Slope {
        let (il, ir) = (self.inv_h[m - 1], self.inv_h[m]);
        let sl = (y[m] - y[m - 1]) * il;
        let sr = (y[m + 1] - y[m]) * ir;
        let mut c = [0.0; 4];
        if sl * sr <= 0.0 {
            return c;
        }
        // p = α·s_l + β·s_r with α = h_r/(h_l + h_r), β = h_l/(h_l + h_r)
        let alpha = il / (il + ir);
        let beta = 1.0 - alpha;
        let p = alpha * sl + beta * sr;
        let (al, ar, ap) = (sl.abs(), sr.abs(), 0.5 * p.abs());
        if al <= ar && al <= ap {
            c[m - 1] = -2.0 * il;
            c[m] = 2.0 * il;
        } else if ar <= ap {
            c[m] = -2.0 * ir;
            c[m + 1] = 2.0 * ir;
        } else {
            c[m - 1] = -alpha * il;
            c[m] = alpha * il - beta * ir;
            c[m + 1] = beta * ir;
        }
        c
    }

    /// Steffen's slope at an end node e, from its inner neighbours n1 (gap g0) and n2 (gap g1): the
    /// one-sided parabola slope, 0 if it opposes the first secant, at most twice the first secant.
    #[inline(always)]
    fn end(&self, y: &[f64; 4], e: usize, n1: usize, n2: usize, g0: usize, g1: usize) -> Slope {
        // secants oriented from the end node inwards, expressed as d y/dx along the axis
        let (i0, i1) = (self.inv_h[g0], self.inv_h[g1]);
        let sign = if n1 > e { 1.0 } else { -1.0 };
        let s0 = sign * (y[n1] - y[e]) * i0;
        let s1 = sign * (y[n2] - y[n1]) * i1;
        let f = i1 / (i0 + i1); // h0/(h0 + h1)
        let p = s0 * (1.0 + f) - s1 * f;
        let mut c = [0.0; 4];
        if p * s0 <= 0.0 {
            return c;
        }
        if p.abs() > 2.0 * s0.abs() {
            c[e] = -2.0 * sign * i0;
            c[n1] = 2.0 * sign * i0;
        } else {
            c[e] = -sign * (1.0 + f) * i0;
            c[n1] = sign * ((1.0 + f) * i0 + f * i1);
            c[n2] = -sign * f * i1;
        }
        c
    }

    /// The spline's values for `L` fibres at once, window values `y[j][lane]` (per lane the value of
    /// [`CubicStencil::eval`], faster: no weights, and the lanes vectorise).
    #[inline(always)]
    pub fn value<const L: usize>(&self, y: &[[f64; L]; 4]) -> [f64; L] {
        match self.a {
            0 => self.value_at::<0, L>(y),
            1 => self.value_at::<1, L>(y),
            _ => self.value_at::<2, L>(y),
        }
    }

    /// [`CubicStencil::value`] on the interval between window nodes A and A + 1 (A = 0: first interval of
    /// the axis, A = 2: last): the three secants of the window and Steffen's slopes at the interval's ends.
    #[inline(always)]
    fn value_at<const A: usize, const L: usize>(&self, y: &[[f64; L]; 4]) -> [f64; L] {
        let [i0, i1, i2] = self.inv_h;
        let [m0, m1] = self.mix;
        let [h00, h10, h01, h11] = self.basis;
        let h = self.h;
        let mut out = [0.0; L];
        for (l, v) in out.iter_mut().enumerate() {
            let s0 = (y[1][l] - y[0][l]) * i0;
            let s1 = (y[2][l] - y[1][l]) * i1;
            let s2 = (y[3][l] - y[2][l]) * i2;
            let (da, db) = match A {
                0 => (end_slope(s0, s1, m0), interior_slope(s0, s1, m1)),
                1 => (interior_slope(s0, s1, m0), interior_slope(s1, s2, m1)),
                _ => (interior_slope(s1, s2, m0), end_slope(s2, s1, m1)),
            };
            *v = h00 * y[A][l] + h01 * y[A + 1][l] + h * (h10 * da + h11 * db);
        }
        out
    }

    /// The window node beyond the interval on its upper (`upper`) or lower side, if the window has one,
    /// as `(beyond, near, far, r)`: setting y_beyond = (1 + r)·y_near − r·y_far makes the secant from the
    /// interval's end to it the interval's own secant, so that Steffen's slope at that end is the
    /// interval's secant (a one-sided slope: the data beyond no longer bend the interval's spline).
    #[inline(always)]
    pub fn beyond(&self, upper: bool) -> Option<(usize, usize, usize, f64)> {
        let a = self.a;
        if upper {
            (a + 2 <= 3 && !self.last).then(|| (a + 2, a + 1, a, self.inv_h[a] / self.inv_h[a + 1]))
        } else {
            (a >= 1 && !self.first).then(|| (a - 1, a, a + 1, self.inv_h[a] / self.inv_h[a - 1]))
        }
    }

    /// The interval's lower node (stored index; the window's second point).
    #[inline(always)]
    pub fn lower(&self) -> usize {
        (self.start + self.a as isize).unsigned_abs()
    }

    /// For slopes given at the points: the first point of the interval (stored index), and the weights of
    /// (y_i, y'_i, y_(i+1), y'_(i+1)) and their derivatives with respect to the coordinate.
    #[inline(always)]
    pub fn hermite(&self) -> (isize, [f64; 4], [f64; 4]) {
        let [h00, h10, h01, h11] = self.basis;
        let [g00, g10, g01, g11] = self.dbasis;
        let (h, ih) = (self.h, self.inv_h[self.a]);
        (
            self.start + self.a as isize,
            [h00, h * h10, h01, h * h11],
            [g00 * ih, g10, g01 * ih, g11],
        )
    }

    /// Evaluates the spline of the window values `y`.
    #[inline(always)]
    pub fn eval(&self, y: &[f64; 4]) -> Fibre {
        let a = self.a;
        let da = if self.first {
            self.end(y, a, a + 1, a + 2, a, a + 1)
        } else {
            self.interior(y, a)
        };
        let db = if self.last {
            self.end(y, a + 1, a, a - 1, a, a - 1)
        } else {
            self.interior(y, a + 1)
        };
        let [h00, h10, h01, h11] = self.basis;
        let [g00, g10, g01, g11] = self.dbasis;
        let (h, ih) = (self.h, self.inv_h[a]);
        let mut w = [0.0; 4];
        let mut dw = [0.0; 4];
        for j in 0..4 {
            w[j] = h * (h10 * da[j] + h11 * db[j]);
            dw[j] = g10 * da[j] + g11 * db[j];
        }
        w[a] += h00;
        w[a + 1] += h01;
        dw[a] += g00 * ih;
        dw[a + 1] += g01 * ih;
        let mut v = 0.0;
        let mut dv = 0.0;
        for j in 0..4 {
            v += w[j] * y[j];
            dv += dw[j] * y[j];
        }
        Fibre { v, dv, w }
    }
}

/// Per interval of a cubic axis: window and spacings.
#[derive(Debug, Clone, Copy)]
struct CubicInterval {
    start: isize,
    a: usize,
    inv_h: [f64; 3],
    first: bool,
    last: bool,
    mix: [f64; 2],
}

/// The coordinate one interval of a linear axis is linear in.
#[derive(Debug, Clone, Copy)]
enum CellCoordinate {
    /// x itself.
    Linear,
    /// ln x ([`Interpolation::Log`]): 1/ln(x_(i+1)/x_i).
    Log { inv_ln: f64 },
    /// √x (the cells of [`Axis::sqrt_from`]): √x_i and 1/(√x_(i+1) − √x_i).
    Sqrt { root: f64, inv: f64 },
}

/// Precomputed interpolation along one axis.
#[derive(Debug, Clone)]
pub struct AxisInterp {
    points: Vec<f64>,
    inv_h: Vec<f64>,
    /// Linear axes: the coordinate each interval is linear in (empty: x in every interval; cubic axes).
    cells: Vec<CellCoordinate>,
    /// Per interval (cubic axes only).
    cubic: Vec<CubicInterval>,
}

impl AxisInterp {
    /// The interpolation of `axis` with the given kind.
    pub fn new(axis: &Axis, kind: Interpolation) -> Self {
        let p = &axis.points;
        let n = p.len();
        let inv_h: Vec<f64> = p.windows(2).map(|w| 1.0 / (w[1] - w[0])).collect();
        let cells = match (kind, axis.sqrt_from) {
            (Interpolation::Log, _) => p
                .windows(2)
                .map(|w| CellCoordinate::Log {
                    inv_ln: 1.0 / (w[1] / w[0]).ln(),
                })
                .collect(),
            (Interpolation::Linear, Some(_)) => p
                .windows(2)
                .enumerate()
                .map(|(i, w)| {
                    if axis.cell_in_sqrt(i) {
                        let root = w[0].sqrt();
                        CellCoordinate::Sqrt {
                            root,
                            inv: 1.0 / (w[1].sqrt() - root),
                        }
                    } else {
                        CellCoordinate::Linear
                    }
                })
                .collect(),
            // x in every interval; cubic axes
            _ => Vec::new(),
        };
        let cubic = match kind {
            Interpolation::Linear | Interpolation::Log => Vec::new(),
            Interpolation::Cubic => {
                // extended points: mirror images of points 1.. in front of a mirrored axis
                let off = if axis.mirrored { n - 1 } else { 0 };
                let mut x: Vec<f64> = p[1..].iter().rev().map(|v| -v).take(off).collect();
                x.extend_from_slice(p);
                let ne = x.len();
                (0..n - 1)
                    .map(|i| {
                        let e = i + off;
                        let s = e.saturating_sub(1).min(ne - 4);
                        let h = |g: usize| x[g + 1] - x[g];
                        let (first, last) = (e == 0, e + 1 == ne - 1);
                        // α of an interior node m: h_m/(h_(m−1) + h_m); f of an end: h_0/(h_0 + h_1)
                        let mix_a = if first {
                            h(e) / (h(e) + h(e + 1))
                        } else {
                            h(e) / (h(e - 1) + h(e))
                        };
                        let mix_b = if last {
                            h(e) / (h(e) + h(e - 1))
                        } else {
                            h(e + 1) / (h(e) + h(e + 1))
                        };
                        CubicInterval {
                            start: s as isize - off as isize,
                            a: e - s,
                            inv_h: std::array::from_fn(|g| 1.0 / h(s + g)),
                            first,
                            last,
                            mix: [mix_a, mix_b],
                        }
                    })
                    .collect()
            }
        };
        Self {
            points: p.clone(),
            inv_h,
            cells,
            cubic,
        }
    }

    /// The stored points whose values an evaluation in interval `i` reads along this axis: a cubic axis'
    /// window (ghost points as the stored points they mirror), a linear axis' two ends; the point itself
    /// for the last point (no interval) and on a single-point axis.
    pub(crate) fn stencil(&self, i: usize) -> Vec<usize> {
        let n = self.points.len();
        if i + 1 >= n {
            vec![i]
        } else if let Some(c) = self.cubic.get(i) {
            (0..4).map(|r| (c.start + r).unsigned_abs()).collect()
        } else {
            vec![i, i + 1]
        }
    }

    /// The coordinate clamped to the axis (lowest stored point to highest) and whether it was inside. On
    /// a single-point axis, inside means within a relative 1e-9 of the point (rounding of the coordinate's
    /// computation, e.g. p_ref of a Hertz contact at another load).
    #[inline]
    pub fn clamp(&self, x: f64) -> (f64, bool) {
        let lo = self.points[0];
        let hi = self.points[self.points.len() - 1];
        if self.points.len() == 1 {
            (lo, (x - lo).abs() <= 1e-9 * lo.abs())
        } else if x < lo {
            (lo, false)
        } else if x > hi {
            (hi, false)
        } else {
            (x, true)
        }
    }

    /// Interval (cell) of `x` on an axis of at least two points: i with x_i ≤ x < x_(i+1), the last for
    /// x at the last point, the first or the last for x outside the range.
    #[inline(always)]
    pub(crate) fn interval(&self, x: f64) -> usize {
        let n = self.points.len();
        self.points.partition_point(|p| *p <= x).clamp(1, n - 1) - 1
    }

    /// Interval of `x` (inside the stored range) and the local coordinate t ∈ [0, 1].
    #[inline(always)]
    fn locate(&self, x: f64) -> (usize, f64) {
        let i = self.interval(x);
        (i, (x - self.points[i]) * self.inv_h[i])
    }

    /// The interval and fraction of `x` (inside the stored range) on a linear axis.
    #[inline(always)]
    pub fn fraction(&self, x: f64) -> Fraction {
        if self.points.len() == 1 {
            return Fraction::default();
        }
        let (i, t) = self.locate(x);
        match self.cells.get(i).copied().unwrap_or(CellCoordinate::Linear) {
            CellCoordinate::Linear => Fraction {
                start: i,
                t,
                inv_h: self.inv_h[i],
            },
            // t = ln(x/x_i)/ln(x_(i+1)/x_i), dt/dx = 1/(x·ln(x_(i+1)/x_i))
            CellCoordinate::Log { inv_ln } => Fraction {
                start: i,
                t: ((x / self.points[i]).ln() * inv_ln).clamp(0.0, 1.0),
                inv_h: inv_ln / x,
            },
            // t = (√x − √x_i)/(√x_(i+1) − √x_i), dt/dx = 1/(2√x·(√x_(i+1) − √x_i))
            CellCoordinate::Sqrt { root, inv } => {
                let r = x.sqrt();
                Fraction {
                    start: i,
                    t: ((r - root) * inv).clamp(0.0, 1.0),
                    inv_h: 0.5 * inv / r,
                }
            }
        }
    }

    /// The cubic window at `x` (inside the stored range) of a cubic axis.
    #[inline(always)]
    pub fn cubic(&self, x: f64) -> CubicStencil {
        let (i, t) = self.locate(x);
        let c = &self.cubic[i];
        CubicStencil {
            start: c.start,
            a: c.a,
            inv_h: c.inv_h,
            h: 1.0 / self.inv_h[i],
            first: c.first,
            last: c.last,
            mix: c.mix,
            basis: hermite_basis(t),
            dbasis: hermite_basis_slope(t),
        }
    }
}

/// The cubic Hermite basis h00, h10, h01, h11 at t ∈ [0, 1]: the weights of the values at the interval's
/// ends and of their slopes (times the interval's length).
#[inline(always)]
pub(crate) fn hermite_basis(t: f64) -> [f64; 4] {
    let t2 = t * t;
    [
        1.0 + t2 * (2.0 * t - 3.0),
        t * (1.0 + t * (t - 2.0)),
        t2 * (3.0 - 2.0 * t),
        t2 * (t - 1.0),
    ]
}

/// The t-derivatives of [`hermite_basis`].
#[inline(always)]
pub(crate) fn hermite_basis_slope(t: f64) -> [f64; 4] {
    [
        6.0 * t * (t - 1.0),
        1.0 + t * (3.0 * t - 4.0),
        6.0 * t * (1.0 - t),
        t * (3.0 * t - 2.0),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cubic_axis(points: &[f64], mirrored: bool) -> AxisInterp {
        AxisInterp::new(
            &Axis {
                mirrored,
                ..Axis::linear(points.to_vec())
            },
            Interpolation::Cubic,
        )
    }

    /// Interpolates node values `y(x_j)` (ghost nodes: y(−x) = sign·y(x)).
    fn interp(ai: &AxisInterp, y: &dyn Fn(f64) -> f64, sign: f64, x: f64) -> Fibre {
        let st = ai.cubic(x);
        let vals: [f64; 4] = std::array::from_fn(|r| {
            let g = st.start + r as isize;
            if g < 0 {
                sign * y(ai.points[(-g) as usize])
            } else {
                y(ai.points[g as usize])
            }
        });
        st.eval(&vals)
    }

    const PTS: [f64; 8] = [-0.1, -0.03, -0.004, 0.0, 0.002, 0.01, 0.05, 0.1];

    #[test]
    fn monotone_cubic_reproduces_linear_data() {
        let ai = cubic_axis(&PTS, false);
        for k in 0..=400 {
            let x = -0.1 + 0.2 * k as f64 / 400.0;
            let f = interp(&ai, &|x| 0.3 - 2.0 * x, 1.0, x);
            assert!((f.v - (0.3 - 2.0 * x)).abs() < 1e-14, "x {x}");
            assert!((f.dv + 2.0).abs() < 1e-10, "x {x}: {}", f.dv);
        }
    }

    #[test]
    fn saturating_curve_is_not_overshot() {
        // a creep-curve-like knee: steep rise, then flat, on coarse points
        let knee = |x: f64| (x / 0.001).tanh();
        let ai = cubic_axis(&[0.0, 0.0004, 0.001, 0.003, 0.008], false);
        for k in 0..=1000 {
            let x = 0.008 * k as f64 / 1000.0;
            let f = interp(&ai, &knee, 1.0, x);
            assert!(
                f.v <= knee(0.008) + 1e-15 && f.v >= -1e-15,
                "x {x}: {}",
                f.v
            );
        }
        // the unlimited parabola slope at 0.001 would be (0.76 − 0.38)/0.0006·… ≫ the right secant: the
        // interval 0.001..0.003 stays between its end values
        for k in 0..=100 {
            let x = 0.001 + 0.002 * k as f64 / 100.0;
            let f = interp(&ai, &knee, 1.0, x);
            assert!(f.v >= knee(0.001) - 1e-15 && f.v <= knee(0.003) + 1e-15);
        }
    }

    #[test]
    fn error_falls_as_h_cubed_for_smooth_monotone_data() {
        let f = |x: f64| (3.0 * x).atan();
        let err = |n: usize| {
            let pts: Vec<f64> = (0..n).map(|k| k as f64 / (n - 1) as f64).collect();
            let ai = cubic_axis(&pts, false);
            (0..1000)
                .map(|k| {
                    let x = (k as f64 + 0.5) / 1000.0;
                    (interp(&ai, &f, 1.0, x).v - f(x)).abs()
                })
                .fold(0.0, f64::max)
        };
        let (e1, e2) = (err(21), err(41));
        let order = (e1 / e2).log2();
        assert!(order > 2.7, "observed order {order} ({e1}, {e2})");
    }

    #[test]
    fn weights_are_the_partial_derivatives_and_dv_the_slope() {
        let ai = cubic_axis(&PTS, false);
        let f = |x: f64| (40.0 * x).tanh() + 3.0 * x * x;
        for x in [-0.09, -0.01, -0.001, 0.0013, 0.03, 0.099] {
            let st = ai.cubic(x);
            let y: [f64; 4] = std::array::from_fn(|r| f(PTS[(st.start + r as isize) as usize]));
            let fib = st.eval(&y);
            for j in 0..4 {
                let mut yp = y;
                yp[j] += 1e-7;
                let d = (st.eval(&yp).v - fib.v) / 1e-7;
                assert!(
                    (d - fib.w[j]).abs() < 1e-6,
                    "x {x} j {j}: {d} vs {}",
                    fib.w[j]
                );
            }
            let h = 1e-8;
            let fd = (interp(&ai, &f, 1.0, x + h).v - interp(&ai, &f, 1.0, x - h).v) / (2.0 * h);
            assert!(
                (fd - fib.dv).abs() < 1e-5 * fd.abs().max(1.0),
                "x {x}: {fd} vs {}",
                fib.dv
            );
        }
    }

    #[test]
    fn fast_value_and_precomputed_slopes_agree_with_the_window_evaluation() {
        let ai = cubic_axis(&PTS, false);
        let f = |x: f64| (40.0 * x).tanh() + 3.0 * x * x - 0.5 * (90.0 * x).sin() * x;
        let y: Vec<f64> = PTS.iter().map(|x| f(*x)).collect();
        let mut d = vec![0.0; PTS.len()];
        node_slopes(&PTS, &y, &mut d);
        for k in 0..=500 {
            let x = -0.1 + 0.2 * k as f64 / 500.0;
            let st = ai.cubic(x);
            let win: [f64; 4] = std::array::from_fn(|r| y[(st.start + r as isize) as usize]);
            let fib = st.eval(&win);
            assert!(
                (st.value(&win.map(|v| [v]))[0] - fib.v).abs() < 1e-14,
                "x {x}"
            );
            let (i, w, dw) = st.hermite();
            let i = i as usize;
            let v = w[0] * y[i] + w[1] * d[i] + w[2] * y[i + 1] + w[3] * d[i + 1];
            let dv = dw[0] * y[i] + dw[1] * d[i] + dw[2] * y[i + 1] + dw[3] * d[i + 1];
            assert!((v - fib.v).abs() < 1e-13, "x {x}: {v} vs {}", fib.v);
            assert!((dv - fib.dv).abs() < 1e-9 * fib.dv.abs().max(1.0), "x {x}");
        }
    }

    #[test]
    fn mirrored_axis_uses_ghost_nodes() {
        let ai = cubic_axis(&[0.0, 0.001, 0.004, 0.012, 0.03], true);
        assert_eq!(ai.cubic(0.0005).start, -1);
        // odd data (ghost = −node): the slope at 0 is the central one through the ghost, y(x_1)/x_1, not
        // the one-sided parabola's (0 for y = x·|x| = x² on x ≥ 0)
        let f = interp(&ai, &|x: f64| x * x.abs(), -1.0, 0.0);
        assert!((f.dv - 0.001).abs() < 1e-15, "{}", f.dv);
        // even data: slope 0 at 0 (symmetric extremum)
        let f = interp(&ai, &|x: f64| 1.0 + 3.0 * x * x, 1.0, 0.0);
        assert_eq!(f.dv, 0.0);
        for k in 0..=100 {
            let x = 0.03 * k as f64 / 100.0;
            let f = interp(&ai, &|x| 2.0 * x, -1.0, x);
            assert!((f.v - 2.0 * x).abs() < 1e-15 && (f.dv - 2.0).abs() < 1e-11);
        }
    }

    #[test]
    fn linear_fractions_and_clamping() {
        let axis = |points: Vec<f64>| AxisInterp::new(&Axis::linear(points), Interpolation::Linear);
        let ai = axis(vec![1.0, 2.0, 4.0]);
        assert_eq!(
            ai.fraction(3.0),
            Fraction {
                start: 1,
                t: 0.5,
                inv_h: 0.5
            }
        );
        let f = ai.fraction(4.0);
        assert_eq!((f.start, f.t), (1, 1.0));
        assert_eq!(ai.clamp(5.0), (4.0, false));
        assert_eq!(ai.clamp(0.0), (1.0, false));
        assert_eq!(ai.clamp(1.5), (1.5, true));
        // a single point: inside only at the point (to rounding), never a step
        let one = axis(vec![7e8]);
        assert_eq!(one.clamp(7e8 * (1.0 + 1e-12)), (7e8, true));
        assert_eq!(one.clamp(7.1e8), (7e8, false));
        assert_eq!(one.fraction(7e8), Fraction::default());
        // cells from sqrt_from on: the fraction of √x, dt/dx = 1/(2√x·(√x_(i+1) − √x_i))
        let sqrt = AxisInterp::new(
            &Axis {
                sqrt_from: Some(4.0),
                ..Axis::linear(vec![1.0, 4.0, 16.0])
            },
            Interpolation::Linear,
        );
        assert_eq!(
            sqrt.fraction(9.0),
            Fraction {
                start: 1,
                t: 0.5,
                inv_h: 0.5 * 0.5 / 3.0
            }
        );
        assert_eq!(sqrt.fraction(2.0).t, 1.0 / 3.0);
    }

    /// The offsets and weights of [`Offsets::of`] are those of [`Corners::of`]'s corners, in its order;
    /// [`Offsets::of_value`] keeps every one of non-zero weight, in that order, and drops those beyond
    /// coordinates on a node; the last corner is the farthest.
    #[test]
    fn offsets_are_the_corners_in_rows() {
        let mut rng = super::super::verify::SplitMix64::new(7);
        let strides = [1000, 200, 40, 8, 1];
        for k in 0..500 {
            let mut f: [Fraction; LINEAR_DIMS] = std::array::from_fn(|d| Fraction {
                start: d + 1,
                t: rng.uniform(),
                inv_h: 1.0,
            });
            // single-point axes (a geometry axis, then also a multilinear one) and a tie
            if k % 3 == 1 {
                f[3] = Fraction::default();
            }
            if k % 5 == 2 {
                f[2] = Fraction::default();
            }
            if k % 7 == 3 {
                f[4].t = f[0].t;
            }
            // coordinates on nodes: a multilinear and a simplicial one at the start (t = 0) or the end
            // (t = 1) of their interval (a dry contact's wetness 0, the last node of an axis)
            if k % 4 == 0 {
                f[2].t = 0.0;
            }
            if k % 6 == 1 {
                f[1].t = 1.0;
            }
            if k % 9 == 4 {
                f[0].t = 0.0;
            }
            if k % 11 == 5 {
                f[3].t = 1.0;
            }
            let c = Corners::of(&f);
            let all = Offsets::of(&f, &strides);
            let o = Offsets::of_value(&f, &strides);
            for x in [&all, &o] {
                assert_eq!(x.farthest(), *x.off[..x.n].iter().max().unwrap(), "{k}");
            }
            assert_eq!(all.n, c.n);
            let want = |i: usize| -> (usize, u64) {
                let off = (0..LINEAR_DIMS)
                    .map(|d| (c.start[d] + c.step[i][d]) * strides[d])
                    .sum();
                (off, c.w[i].to_bits())
            };
            for i in 0..c.n {
                assert_eq!((all.off[i], all.w[i].to_bits()), want(i), "{k} {i}");
            }
            // the corners of non-zero weight, in order; of weight 0 only those beyond no node
            let kept: Vec<(usize, u64)> = (0..c.n).filter(|i| c.w[*i] != 0.0).map(want).collect();
            let nonzero: Vec<(usize, u64)> = (0..o.n)
                .filter(|j| o.w[*j] != 0.0)
                .map(|j| (o.off[j], o.w[j].to_bits()))
                .collect();
            assert_eq!(nonzero, kept, "{k}");
            let beyond_nodes = (0..c.n).filter(|i| {
                (0..LINEAR_DIMS).any(|d| f[d].inv_h > 0.0 && f[d].t == 0.0 && c.step[*i][d] == 1)
            });
            assert_eq!(o.n, c.n - beyond_nodes.count(), "{k}");
            if f.iter().all(|x| x.t > 0.0 && x.t < 1.0) && k % 7 != 3 {
                assert_eq!(o.n, c.n, "{k}: no corner of weight 0 inside the cell");
            }
            let total: f64 = o.w[..o.n].iter().sum();
            assert!((total - 1.0).abs() < 1e-12, "{k}: weights sum to {total}");
        }
        // a dry contact (wetness on its first node) reads half the corners
        let f: [Fraction; LINEAR_DIMS] = std::array::from_fn(|d| Fraction {
            start: 0,
            t: if d == 2 { 0.0 } else { 0.1 + 0.2 * d as f64 },
            inv_h: 1.0,
        });
        let o = Offsets::of_value(&f, &strides);
        assert_eq!((Corners::of(&f).n, o.n), (16, 8));
    }

    /// The corner weights are a partition of unity, ≥ 0, interpolate data multilinear in (V, w) and affine
    /// in (F_N, a/b, p_ref) exactly, and are continuous across the faces between simplices (where two
    /// fractions are equal); their derivatives are those of the weights.
    #[test]
    fn corner_weights_interpolate_their_data_class_and_are_continuous() {
        let mut rng = super::super::verify::SplitMix64::new(3);
        let data = |x: &[f64; LINEAR_DIMS]| {
            0.3 * x[0] - 1.2 * x[1] + 2.5 * x[2] + 0.7 * x[3] - 0.4 * x[4] + 0.9 * x[1] * x[2]
        };
        let eval = |c: &Corners, dw: Option<usize>| -> f64 {
            (0..c.n)
                .map(|k| {
                    let x: [f64; LINEAR_DIMS] =
                        std::array::from_fn(|d| (c.start[d] + c.step[k][d]) as f64);
                    dw.map_or(c.w[k], |d| c.dw[d][k]) * data(&x)
                })
                .sum()
        };
        for _ in 0..1000 {
            let mut f: [Fraction; LINEAR_DIMS] = std::array::from_fn(|d| Fraction {
                start: d,
                t: rng.uniform(),
                inv_h: 1.0,
            });
            // one single-point axis (a geometry axis of a one-geometry table)
            f[3] = Fraction::default();
            let c = Corners::of(&f);
            assert_eq!(
                c.n, 12,
                "2² multilinear × 3 simplex corners (a/b is a single point)"
            );
            assert!((c.w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            assert!(c.w.iter().all(|w| *w >= 0.0));
            let x: [f64; LINEAR_DIMS] = std::array::from_fn(|d| f[d].start as f64 + f[d].t);
            assert!((eval(&c, None) - data(&x)).abs() < 1e-12);
            assert!(c.step.iter().all(|s| s[3] == 0));
            // derivatives of the interpolant: those of the data
            for d in [0, 1, 2, 4] {
                let h = 1e-6;
                let mut g = f;
                g[d].t += h;
                let fd = (eval(&Corners::of(&g), None) - eval(&c, None)) / h;
                let want = [0.3, -1.2 + 0.9 * x[2], 2.5 + 0.9 * x[1], 0.7, -0.4][d];
                assert!((fd - want).abs() < 1e-5, "{d}: {fd}");
                assert!((eval(&c, Some(d)) - want).abs() < 1e-12, "{d}");
            }
        }
        // continuity across a simplex face: data that are not affine, t_F = t_(a/b) ± ε
        let curved = |x: &[f64; LINEAR_DIMS]| (x[0] * x[3]).sin() + x[2] * x[4];
        let value = |f: &[Fraction; LINEAR_DIMS]| -> f64 {
            let c = Corners::of(f);
            (0..c.n)
                .map(|k| {
                    let x: [f64; LINEAR_DIMS] =
                        std::array::from_fn(|d| (c.start[d] + c.step[k][d]) as f64);
                    c.w[k] * curved(&x)
                })
                .sum()
        };
        let base: [Fraction; LINEAR_DIMS] = std::array::from_fn(|d| Fraction {
            start: 1,
            t: [0.4, 0.3, 0.1, 0.4, 0.8][d],
            inv_h: 1.0,
        });
        let (mut a, mut b) = (base, base);
        a[0].t += 1e-12;
        b[3].t += 1e-12;
        assert!((value(&a) - value(&b)).abs() < 1e-11);
    }
}
