//! Kalker's exact ("complete") theory of steady rolling with a local traction bound per cell
//! (docs/model.md §6.5; J.J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer 1990,
//! ch. 2 and 5; E.A.H. Vollebregt, *User guide for CONTACT*, the discretisation of module 3).
//!
//! **Discretisation.** Piecewise constant tractions p_J = [p_x, p_y] on the cells of the rectangular
//! [`ContactGrid`]; quasi-identical bodies (wheel and rail of one steel), so the tangential problem
//! decouples from the normal one. The surface displacement difference (wheel minus rail) at the centre of
//! cell I is u_I = Σ_J A(x_I − x_J, y_I − y_J)·p_J with Cerruti's point-load solution integrated over the
//! cell in closed form ([`influence`]). An interfacial layer of compliance h/G₃ between the bodies adds
//! (h/G₃)·p_I to u_I (docs/model.md §6.7; [`SteadyRolling::with_layer`]).
//!
//! **Steady rolling.** Material flows through the contact in −x at the rolling speed V (leading edge at
//! x = +a, as in FASTSIM). The slip of the wheel relative to the rail, per V, is
//! s/V = w − ∂u/∂x with the rigid slip w = (ξ − φ·y, η + φ·x) (docs/model.md §1); the derivative is the
//! upwind difference over one cell, s_I/V = w_I + (u_I − u(x_I + h_x, y_I))/h_x (Kalker's steady-state
//! scheme: the displacement of the previous time step shifted by one cell, time step h_x/V), so
//! s_I/V = w_I + Σ_J B_IJ·p_J with B(d) = (A(d) − A(d + h_x·e_x))/h_x.
//!
//! **Contact conditions** per cell, with the traction bound g_I ≥ 0 (μ·p_n, or the model's τ_l): either
//! stick, s_I = 0 and |p_I| ≤ g_I, or slip, |p_I| = g_I and s_I = −λ·p_I, λ ≥ 0 (the traction on the wheel
//! opposes its slip).
//!
//! **Solver** (the scheme of Vollebregt's SteadyGS in CONTACT, written anew here): Gauss–Seidel over the
//! cells, strip by strip, each strip **from the trailing cell to the leading one**. The unknowns are the
//! traction increments along the flow, q_k = p_k − p_(k+1) (k+1 the cell ahead of k; p = 0 ahead of the
//! leading cell), in sticking cells and the tractions in slipping ones: a change Δ of p_k moves the
//! tractions of the sticking cells behind k with it, up to the first slipping cell behind k (or the
//! trailing edge), where the change "lands". So s/V = w + (1/h_x)·Σ_J A(x − x_J)·q_J, and the change
//! adds (A(x − x_k) − A(x − x_land))·Δ/h_x to every cell's s/V. Each cell solves its own 2 × 2 problem
//! exactly given the others ([`local_problem`], with M_kk = (A(0) − A(x_k − x_land))/h_x). Sweeping from
//! the leading edge instead, or moving every traction behind k, diverges on long thin strips (measured:
//! a/b = 0.05). Convergence: the largest traction change of a sweep over the largest traction.
//!
//! **Cost of a sweep.** A change must reach its own strip's cells at once (the next cell's problem reads
//! them) but the other strips only before their turn: it acts directly on its own strip (O(nx)), and each
//! strip, when done, passes its row of increment changes to every other strip as a product in Fourier
//! space over x (the influence is translation invariant; circular convolution of length ≥ 2·nx is exact
//! for nx targets and nx + 1 sources). Each strip takes what it was sent when its turn comes, and all at
//! the end of a sweep: the iterates are those of updating every cell after every change, at
//! O(ny²·n_fft + N·nx) per sweep instead of O(N²) (N cells; on 30 × 30 about a quarter of the time).

use super::fastsim::{Creepages, TractionField};
use crate::contact::{ContactGrid, Strip};
use crate::error::{Error, Result, check_finite, check_positive, check_range};
use std::f64::consts::PI;

/// Influence coefficients of one grid, per cell offset (a function of the grid's cell size, the number of
/// cells, the elastic constants and an interfacial layer's compliance only: build once per grid and
/// material, reuse for every creepage).
#[derive(Debug, Clone)]
pub struct SteadyRolling {
    nx: usize,
    ny: usize,
    /// A_xx, A_xy (= A_yx), A_yy divided by h_x [1/Pa] of a source in the target's own row, per column
    /// offset d = i_t − c ∈ [−(nx − 1), nx] at index d + nx − 1 (source column c ∈ [−1, nx), −1: the
    /// released cell behind a strip's trailing cell in column 0).
    row: [Vec<f64>; 3],
    /// The transform of length ≥ 2·nx over which one row of increments acts on another.
    fft: Fft,
    /// Per row offset r = j_t − j_s + ny − 1 ∈ [0, 2ny − 1), the spectra α = (Â_xx + Â_yy)/2 and
    /// β = (Â_xx − Â_yy)/2 + i·Â_xy of the row's kernels (over the column offsets, circularly), divided by
    /// the transform length: runs of α_re, α_im, β_re, β_im, one value per frequency ([`accumulate`]).
    spectra: Vec<f64>,
    /// Whether the CPU has AVX2 and FMA (the sweeps are then compiled for them, [`iterate_fma`]).
    fma: bool,
}

/// Solver settings of [`SteadyRolling::solve`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExactSettings {
    /// Convergence tolerance: largest traction change of a sweep over the largest traction [-]. A sweep
    /// reduces the error by a factor ≈ 0.65 (measured on 30 × 30), so the tractions are within about 3×
    /// the tolerance of the converged ones.
    pub tolerance: f64,
    /// Largest number of Gauss–Seidel sweeps.
    pub max_sweeps: usize,
    /// Sweeps combined by Anderson's extrapolation ([`Anderson`]); 0: plain Gauss–Seidel. Measured on
    /// 30 × 30, reference contact, μ = 0.3, cold, tolerance 1e-7, sweeps with depth 0 / 3 / 5 / 8: ξ = 0.1 %
    /// 39 / 28 / 27 / 26; η = 0.1 % 42 / 30 / 27 / 26; φ = 0.2 /m 38 / 31 / 31 / 29; φ = 1 /m 34 / 29 / 28 / 28;
    /// ξ = 0.08 %, η = −0.04 %, φ = 0.4 /m 36 / 33 / 32 / 33.
    pub anderson_depth: usize,
}

impl Default for ExactSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-7,
            max_sweeps: 500,
            anderson_depth: 5,
        }
    }
}

/// Result of [`SteadyRolling::solve`]: the traction field (as FASTSIM's, so the heat model takes either) and
/// how the solve went.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactTraction {
    /// Resultants, tractions, slip velocities, power density and slip flags per cell.
    pub field: TractionField,
    /// Gauss–Seidel sweeps done.
    pub sweeps: usize,
    /// Largest traction change of the last sweep over the largest bound [-].
    pub residual: f64,
    /// Whether the residual reached the tolerance within `max_sweeps`.
    pub converged: bool,
}

/// ∫∫ of Cerruti's surface kernels over a rectangle, as corner functions F(X, Y) of the offset of the
/// target from a rectangle corner [m] (the double integral is F(X₂,Y₂) − F(X₁,Y₂) − F(X₂,Y₁) + F(X₁,Y₁)):
/// ∫∫ dA/r = X·ln(Y + r) + Y·ln(X + r), ∫∫ X²/r³ dA = Y·ln(X + r), ∫∫ X·Y/r³ dA = −r, with
/// X·ln(Y + r) = X·asinh(Y/|X|) + X·ln|X| and the last term cancelling between the corners of one X.
/// Returns the corner values of the xx, xy and yy kernels for Poisson ratio `nu`: (1 − ν)/r + ν·X²/r³,
/// ν·X·Y/r³, (1 − ν)/r + ν·Y²/r³ (K.L. Johnson, *Contact Mechanics*, 1985, eq. 2.19, z = 0, without the
/// normal component, which cancels between quasi-identical bodies).
fn corner(x: f64, y: f64, nu: f64) -> [f64; 3] {
    // X·asinh(Y/|X|) → 0 as X → 0 (and likewise with X, Y exchanged)
    let xa = if x == 0.0 {
        0.0
    } else {
        x * (y / x.abs()).asinh()
    };
    let ya = if y == 0.0 {
        0.0
    } else {
        y * (x / y.abs()).asinh()
    };
    let r = x.hypot(y);
    [(1.0 - nu) * xa + ya, -nu * r, (1.0 - nu) * ya + xa]
}

/// Displacement difference (wheel minus rail) [m] at offset (dx, dy) [m] from the centre of a cell of size
/// hx × hy [m] carrying a unit traction [Pa] on the wheel (and its opposite on the rail): [A_xx, A_xy, A_yy]
/// (A_yx = A_xy), two half-spaces of shear modulus G [Pa] and Poisson ratio ν: the factor 2·1/(2πG) of
/// Cerruti's solution integrated over the cell ([`corner`]).
pub fn influence(dx: f64, dy: f64, hx: f64, hy: f64, shear_modulus: f64, nu: f64) -> [f64; 3] {
    let (x1, x2) = (dx - 0.5 * hx, dx + 0.5 * hx);
    let (y1, y2) = (dy - 0.5 * hy, dy + 0.5 * hy);
    rectangle(
        [
            corner(x2, y2, nu),
            corner(x1, y2, nu),
            corner(x2, y1, nu),
            corner(x1, y1, nu),
        ],
        shear_modulus,
    )
}

/// The double integral over a rectangle from its corner functions [F(x₂,y₂), F(x₁,y₂), F(x₂,y₁), F(x₁,y₁)]
/// ([`corner`]), times the two bodies' factor 1/(πG) [1/Pa·m].
fn rectangle(c: [[f64; 3]; 4], shear_modulus: f64) -> [f64; 3] {
    let scale = 1.0 / (PI * shear_modulus);
    std::array::from_fn(|k| scale * (c[0][k] - c[1][k] - c[2][k] + c[3][k]))
}

/// The cell's own 2 × 2 problem (Kalker's element problem): given r = s/V of the cell without its own
/// traction's contribution, the diagonal [d_x, d_y] (> 0) of its self-influence and the bound g ≥ 0, the
/// traction p and slip s/V = r + D·p with stick (s = 0, |p| ≤ g) or slip (|p| = g, s = −t·p, t ≥ 0).
/// In slip p_k = −r_k/(d_k + t) with t the root of Σ_k r_k²/(d_k + t)² = g², found by Newton on the
/// secular equation 1/|p(t)| − 1/g = 0 (concave and increasing in t, nearly linear as d_x ≈ d_y: two or
/// three steps; J.J. Moré and D.C. Sorensen, SIAM J. Sci. Stat. Comput. 4 (1983) 553–572, the same
/// equation for a trust-region step), monotone from the lower end of its bracket
/// [max(0, |r|/g − d_max), |r|/g − d_min].
#[inline(always)]
fn local_problem(r: [f64; 2], d: [f64; 2], g: f64) -> ([f64; 2], [f64; 2], bool) {
    let stick = [-r[0] / d[0], -r[1] / d[1]];
    // squares, not hypot: tractions are far from overflow and hypot dominated the solve's time
    if stick[0] * stick[0] + stick[1] * stick[1] <= g * g {
        return (stick, [0.0; 2], false);
    }
    if g == 0.0 {
        return ([0.0; 2], r, true);
    }
    let rn = (r[0] * r[0] + r[1] * r[1]).sqrt();
    let mut t = (rn / g - d[0].max(d[1])).max(0.0);
    for _ in 0..50 {
        let (q0, q1) = (1.0 / (d[0] + t), 1.0 / (d[1] + t));
        let (p0, p1) = (r[0] * q0, r[1] * q1);
        let squared = p0 * p0 + p1 * p1;
        let norm = squared.sqrt();
        // d(1/|p|)/dt = (p0²·q0 + p1²·q1)/|p|³
        let step = (norm - g) / g * squared / (p0 * p0 * q0 + p1 * p1 * q1);
        t += step;
        // quadratic convergence: the error after a step of 1e-10 relative is at round-off
        if step.abs() <= 1e-10 * (t + d[0]) {
            break;
        }
    }
    let p = [-r[0] / (d[0] + t), -r[1] / (d[1] + t)];
    // the slip follows from the converged t (so that it is exactly antiparallel to p)
    (p, [-t * p[0], -t * p[1]], true)
}

/// Anderson acceleration of the Gauss–Seidel sweep x ↦ G(x) (D.G. Anderson, J. ACM 12 (1965) 547–560;
/// H.F. Walker and P. Ni, SIAM J. Numer. Anal. 49 (2011) 1715–1735, "type II" with the last `depth`
/// differences): the next iterate is G(x_k) − Σ γ_i·(G(x_(i+1)) − G(x_i)), γ minimising
/// |f_k − Σ γ_i·(f_(i+1) − f_i)|, f = G(x) − x. The slips s are affine in the tractions, so the same
/// combination of the stored s gives the slips of the new iterate exactly, without a new evaluation. The
/// sweep solves each cell's problem from the slips, so an extrapolated traction outside its bound is
/// harmless: the next sweep puts it back.
/// One sweep in the history of [`Anderson`]: f = G(x) − x, G(x) and the slips s(G(x)).
type Iterate = (Vec<[f64; 2]>, Vec<[f64; 2]>, [Vec<f64>; 2]);

struct Anderson {
    depth: usize,
    /// (f = G(x) − x, G(x), s(G(x))) of the last `depth` + 1 sweeps, oldest first.
    history: std::collections::VecDeque<Iterate>,
}

impl Anderson {
    fn new(depth: usize) -> Self {
        Self {
            depth,
            history: std::collections::VecDeque::with_capacity(depth + 1),
        }
    }

    /// Records the sweep from `before` to `p` (with slips `s`) and replaces `p`, `s` by the extrapolated
    /// iterate (left as they are while there is no difference to combine, or if the least-squares problem
    /// is singular).
    #[inline(always)]
    fn extrapolate(&mut self, before: Vec<[f64; 2]>, p: &mut [[f64; 2]], s: &mut [Vec<f64>; 2]) {
        let f: Vec<[f64; 2]> = p
            .iter()
            .zip(&before)
            .map(|(g, x)| [g[0] - x[0], g[1] - x[1]])
            .collect();
        if self.history.len() == self.depth + 1 {
            self.history.pop_front();
        }
        self.history.push_back((f, p.to_vec(), s.clone()));
        let m = self.history.len() - 1;
        if m == 0 {
            return;
        }
        let dot = |a: &[[f64; 2]], b: &[[f64; 2]]| -> f64 {
            a.iter()
                .zip(b)
                .map(|(u, v)| u[0] * v[0] + u[1] * v[1])
                .sum()
        };
        let diff = |i: usize| -> Vec<[f64; 2]> {
            let (a, b) = (&self.history[i + 1].0, &self.history[i].0);
            a.iter()
                .zip(b)
                .map(|(u, v)| [u[0] - v[0], u[1] - v[1]])
                .collect()
        };
        let df: Vec<Vec<[f64; 2]>> = (0..m).map(diff).collect();
        let last = &self.history[m].0;
        // normal equations (m ≤ depth, symmetric positive semidefinite), Cholesky
        let mut a = vec![vec![0.0; m]; m];
        let mut gamma: Vec<f64> = (0..m).map(|i| dot(&df[i], last)).collect();
        for i in 0..m {
            for j in 0..=i {
                a[i][j] = dot(&df[i], &df[j]);
            }
        }
        for i in 0..m {
            for j in 0..=i {
                let sum: f64 = a[i][j] - (0..j).map(|k| a[i][k] * a[j][k]).sum::<f64>();
                if i == j {
                    if sum <= 1e-14 * a[0][0].max(f64::MIN_POSITIVE) {
                        return;
                    }
                    a[i][i] = sum.sqrt();
                } else {
                    a[i][j] = sum / a[j][j];
                }
            }
        }
        for i in 0..m {
            gamma[i] = (gamma[i] - (0..i).map(|k| a[i][k] * gamma[k]).sum::<f64>()) / a[i][i];
        }
        for i in (0..m).rev() {
            gamma[i] = (gamma[i] - (i + 1..m).map(|k| a[k][i] * gamma[k]).sum::<f64>()) / a[i][i];
        }
        for (i, g) in gamma.iter().enumerate() {
            let (next, prev) = (&self.history[i + 1], &self.history[i]);
            for (t, (u, v)) in p.iter_mut().zip(next.1.iter().zip(&prev.1)) {
                t[0] -= g * (u[0] - v[0]);
                t[1] -= g * (u[1] - v[1]);
            }
            for (sc, (u, v)) in s.iter_mut().zip(next.2.iter().zip(&prev.2)) {
                for (t, (u, v)) in sc.iter_mut().zip(u.iter().zip(v)) {
                    *t -= g * (u - v);
                }
            }
        }
    }
}

/// Radix-2 complex fast Fourier transform of one power-of-two length n (Cooley–Tukey, iterative, decimation
/// in time; W.H. Press et al., *Numerical Recipes*, 3rd ed., 2007, §12.2): X_k = Σ_m x_m·e^(∓2πi·k·m/n),
/// "−" forward, "+" inverse (unscaled).
#[derive(Debug, Clone)]
struct Fft {
    /// Per stage of half-length h = 1, 2, 4, …, n/2, the twiddles e^(−iπ·k/h), k < h (n − 1 in all):
    /// real parts, imaginary parts of the forward transform, and the latter negated (inverse).
    twiddles: [Vec<f64>; 3],
    /// The bit-reversal permutation of 0..n.
    reversed: Vec<usize>,
}

impl Fft {
    /// The transform of length `n` (a power of two ≥ 2).
    fn new(n: usize) -> Self {
        debug_assert!(n.is_power_of_two() && n >= 2);
        let bits = n.trailing_zeros();
        let angles: Vec<f64> = (0..bits)
            .flat_map(|stage| {
                let half = 1_usize << stage;
                (0..half).map(move |k| -PI * k as f64 / half as f64)
            })
            .collect();
        Self {
            twiddles: [
                angles.iter().map(|a| a.cos()).collect(),
                angles.iter().map(|a| a.sin()).collect(),
                angles.iter().map(|a| -a.sin()).collect(),
            ],
            reversed: (0..n)
                .map(|m| m.reverse_bits() >> (usize::BITS - bits))
                .collect(),
        }
    }

    /// The transform length n.
    fn len(&self) -> usize {
        self.reversed.len()
    }

    /// Transforms (`re`, `im`) in place, forward or `inverse` (unscaled).
    #[inline(always)]
    fn transform(&self, re: &mut [f64], im: &mut [f64], inverse: bool) {
        let n = self.len();
        let (re, im) = (&mut re[..n], &mut im[..n]);
        for (m, &r) in self.reversed.iter().enumerate() {
            if m < r {
                re.swap(m, r);
                im.swap(m, r);
            }
        }
        // the first stage, twiddle 1
        for (r, i) in re.chunks_exact_mut(2).zip(im.chunks_exact_mut(2)) {
            (r[0], r[1]) = (r[0] + r[1], r[0] - r[1]);
            (i[0], i[1]) = (i[0] + i[1], i[0] - i[1]);
        }
        let mut half = 2;
        while half < n {
            let (wr, wi) = (
                &self.twiddles[0][half - 1..2 * half - 1],
                &self.twiddles[if inverse { 2 } else { 1 }][half - 1..2 * half - 1],
            );
            for (r, i) in re
                .chunks_exact_mut(2 * half)
                .zip(im.chunks_exact_mut(2 * half))
            {
                let (ra, rb) = r.split_at_mut(half);
                let (ia, ib) = i.split_at_mut(half);
                for k in 0..half {
                    let tr = rb[k] * wr[k] - ib[k] * wi[k];
                    let ti = rb[k] * wi[k] + ib[k] * wr[k];
                    rb[k] = ra[k] - tr;
                    ib[k] = ia[k] - ti;
                    ra[k] += tr;
                    ia[k] += ti;
                }
            }
            half *= 2;
        }
    }
}

/// The slips W = S_x + i·S_y (spectra) that one row of traction increments with spectrum Z of
/// z = q_x + i·q_y causes in another row: W_k += α_k·Z_k + β_k·conj(Z_(n−k)), since Q_x = (Z_k + conj
/// Z_(n−k))/2, Q_y = (Z_k − conj Z_(n−k))/(2i) for real q_x, q_y and S = Â·Q with real kernels.
/// `spectrum` holds α_re, α_im, β_re, β_im (n each), `z` holds Z and Z' = conj(Z_(n−k)) as re, im, re, im.
/// With fused multiply–adds if `FMA`.
#[inline(always)]
fn accumulate<const FMA: bool>(spectrum: &[f64], z: [&[f64]; 4], w: [&mut [f64]; 2]) {
    let [wr, wi] = w;
    let n = wr.len();
    let (ar, ai, br, bi) = (
        &spectrum[..n],
        &spectrum[n..2 * n],
        &spectrum[2 * n..3 * n],
        &spectrum[3 * n..4 * n],
    );
    let (zr, zi, cr, ci, wi) = (&z[0][..n], &z[1][..n], &z[2][..n], &z[3][..n], &mut wi[..n]);
    for k in 0..n {
        if FMA {
            wr[k] = ar[k].mul_add(
                zr[k],
                (-ai[k]).mul_add(zi[k], br[k].mul_add(cr[k], (-bi[k]).mul_add(ci[k], wr[k]))),
            );
            wi[k] = ar[k].mul_add(
                zi[k],
                ai[k].mul_add(zr[k], br[k].mul_add(ci[k], bi[k].mul_add(cr[k], wi[k]))),
            );
        } else {
            wr[k] += ar[k] * zr[k] - ai[k] * zi[k] + br[k] * cr[k] - bi[k] * ci[k];
            wi[k] += ar[k] * zi[k] + ai[k] * zr[k] + br[k] * ci[k] + bi[k] * cr[k];
        }
    }
}

/// [`SteadyRolling::iterate`] compiled for AVX2 and FMA.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn iterate_fma(
    op: &SteadyRolling,
    grid: &ContactGrid,
    bound: &[f64],
    settings: ExactSettings,
    state: (&mut [[f64; 2]], &mut [Vec<f64>; 2], &mut [bool]),
) -> (usize, f64) {
    op.iterate::<true>(grid, bound, settings, state)
}

/// The slips of the rows not yet brought up to date, as spectra (see [`SteadyRolling::solve`]): per strip
/// the accumulated W = S_x + i·S_y of the increments of the other strips since the strip's last flush.
struct Pending {
    /// Per strip, W_re then W_im (transform length each).
    spectra: Vec<f64>,
    /// Per strip, whether anything was accumulated.
    dirty: Vec<bool>,
    /// One row of increments (then its transform): re, im, conj-mirror re, conj-mirror im.
    z: [Vec<f64>; 4],
}

impl SteadyRolling {
    /// The influence tables of `grid` for two bodies of shear modulus G [Pa] and Poisson ratio ν
    /// (`shear_modulus`, `poisson`): A at every offset between cells, and to the cell behind each strip's
    /// trailing cell, from [`influence`]; the same row's as values, the others as spectra over x. Without
    /// an interfacial layer ([`SteadyRolling::with_layer`] with compliance 0).
    pub fn new(grid: &ContactGrid, shear_modulus: f64, poisson: f64) -> Result<Self> {
        Self::with_layer(grid, shear_modulus, poisson, 0.0)
    }

    /// [`SteadyRolling::new`] with an interfacial layer of compliance h/G₃ = `layer_compliance` [m/Pa]
    /// between the bodies (docs/model.md §6.7): its shear h·τ/G₃ at a cell depends on that cell's traction
    /// only, so A_xx and A_yy gain h/G₃ at offset zero (the cell on itself) and nothing else changes. 0:
    /// the half-spaces alone, bit for bit.
    pub fn with_layer(
        grid: &ContactGrid,
        shear_modulus: f64,
        poisson: f64,
        layer_compliance: f64,
    ) -> Result<Self> {
        check_positive("shear modulus", shear_modulus, "Pa")?;
        check_range("Poisson ratio", poisson, 0.0, 0.5, "")?;
        if !(layer_compliance.is_finite() && layer_compliance >= 0.0) {
            return Err(Error::out_of_range(
                "interfacial layer compliance h/G_3",
                layer_compliance,
                "finite, >= 0 m/Pa",
            ));
        }
        let (nx, ny, hx, hy) = (grid.nx, grid.ny, grid.hx, grid.hy);
        let rows = 2 * ny - 1;
        // A at every column offset d = i_t − c ∈ [−(nx − 1), nx] and row offset (as [`influence`], from the
        // corner functions on the lattice of cell corners, each shared by four cells)
        let corners: Vec<[f64; 3]> = (0..=rows)
            .flat_map(|l| {
                let y = (l as f64 - ny as f64 + 0.5) * hy;
                (0..=2 * nx).map(move |k| corner((k as f64 - nx as f64 + 0.5) * hx, y, poisson))
            })
            .collect();
        let at = |k: usize, l: usize| corners[k + (2 * nx + 1) * l];
        // offset d at e = d + nx − 1; the layer's compliance on the cell itself (row offset ny − 1, d = 0)
        let offsets = |r: usize, e: usize| {
            let mut v = rectangle(
                [at(e + 1, r + 1), at(e, r + 1), at(e + 1, r), at(e, r)],
                shear_modulus,
            );
            if r == ny - 1 && e == nx - 1 {
                v[0] += layer_compliance;
                v[2] += layer_compliance;
            }
            v
        };
        let row =
            std::array::from_fn(|k| (0..2 * nx).map(|e| offsets(ny - 1, e)[k] / hx).collect());
        // a row of increments at m = c + 1 ∈ [0, nx] acts at i_t through the kernel κ(i_t − m) = A(d)
        // with d = i_t − m + 1 ∈ [−nx + 1, nx]: circular convolution of length ≥ 2·nx is exact
        let fft = Fft::new((2 * nx).next_power_of_two());
        let n = fft.len();
        let mut spectra = vec![0.0; rows * 4 * n];
        let mut buffers = [vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]];
        for r in 0..rows {
            // κ_xx + i·κ_yy and κ_xy + i·0, at index (i_t − m) mod n
            buffers.iter_mut().for_each(|b| b.fill(0.0));
            for e in 0..2 * nx {
                let v = offsets(r, e);
                let index = (e + n - nx) % n;
                buffers[0][index] = v[0] / hx;
                buffers[1][index] = v[2] / hx;
                buffers[2][index] = v[1] / hx;
            }
            let [xr, xi, yr, yi] = &mut buffers;
            fft.transform(xr, xi, false);
            fft.transform(yr, yi, false);
            let out = &mut spectra[r * 4 * n..(r + 1) * 4 * n];
            let scale = 1.0 / n as f64;
            for k in 0..n {
                // the transforms of the real κ_xx, κ_yy from that of κ_xx + i·κ_yy
                let mirror = (n - k) % n;
                let (axx, ayy) = (
                    [0.5 * (xr[k] + xr[mirror]), 0.5 * (xi[k] - xi[mirror])],
                    [0.5 * (xi[k] + xi[mirror]), -0.5 * (xr[k] - xr[mirror])],
                );
                let axy = [yr[k], yi[k]];
                out[k] = scale * 0.5 * (axx[0] + ayy[0]);
                out[n + k] = scale * 0.5 * (axx[1] + ayy[1]);
                out[2 * n + k] = scale * (0.5 * (axx[0] - ayy[0]) - axy[1]);
                out[3 * n + k] = scale * (0.5 * (axx[1] - ayy[1]) + axy[0]);
            }
        }
        Ok(Self {
            nx,
            ny,
            row,
            fft,
            spectra,
            #[cfg(target_arch = "x86_64")]
            fma: is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            #[cfg(not(target_arch = "x86_64"))]
            fma: false,
        })
    }

    /// Grid position of cell `k` in the slip arrays: i + nx·j.
    fn position(&self, grid: &ContactGrid, k: usize) -> usize {
        let c = grid.cells[k];
        c.i + self.nx * c.j
    }

    /// Column of the released cell of `strip`: one behind its trailing cell.
    fn released(grid: &ContactGrid, strip: &Strip) -> isize {
        grid.cells[strip.cells.end - 1].i as isize - 1
    }

    /// The index into [`SteadyRolling::row`] of a source in column `column` acting on column `target`.
    fn offset(&self, target: usize, column: isize) -> usize {
        (target as isize - column) as usize + self.nx - 1
    }

    /// The diagonal of cell `k`'s own coefficient M_kk = (A(0) − A(x_k − x_l))/h_x [1/Pa] for a traction
    /// change that lands in column `landing` of its row (x_l).
    fn own(&self, grid: &ContactGrid, k: usize, landing: isize) -> [f64; 2] {
        let i = grid.cells[k].i;
        let (here, behind) = (self.nx - 1, self.offset(i, landing));
        [
            self.row[0][here] - self.row[0][behind],
            self.row[2][here] - self.row[2][behind],
        ]
    }

    /// Adds to the s/V of `strip`'s cells the change (A(x − x_in) − A(x − x_out))·change/h_x of an
    /// increment `change` [Pa] entering at column `enter` of the strip's row and leaving at `leave`.
    #[inline(always)]
    fn move_in_row(
        &self,
        grid: &ContactGrid,
        strip: &Strip,
        enter: isize,
        leave: isize,
        change: [f64; 2],
        s: &mut [Vec<f64>; 2],
    ) {
        let first = grid.cells[strip.cells.end - 1].i;
        let len = grid.cells[strip.cells.start].i + 1 - first;
        let at = self.nx * strip.j + first;
        let (e, l) = (self.offset(first, enter), self.offset(first, leave));
        let [xx, xy, yy] = &self.row;
        let (ex, ey, ez) = (&xx[e..e + len], &xy[e..e + len], &yy[e..e + len]);
        let (lx, ly, lz) = (&xx[l..l + len], &xy[l..l + len], &yy[l..l + len]);
        let [sx, sy] = s;
        let (sx, sy) = (&mut sx[at..at + len], &mut sy[at..at + len]);
        for m in 0..len {
            let (axx, axy, ayy) = (ex[m] - lx[m], ey[m] - ly[m], ez[m] - lz[m]);
            sx[m] += axx * change[0] + axy * change[1];
            sy[m] += axy * change[0] + ayy * change[1];
        }
    }

    /// Accumulates in `pending` the slips that the row of increments `increments` (at m = column + 1,
    /// [Pa]) of strip `source` causes in every other strip (and in its own if `own`).
    #[inline(always)]
    fn spread<const FMA: bool>(
        &self,
        grid: &ContactGrid,
        source: usize,
        increments: &[[f64; 2]],
        own: bool,
        pending: &mut Pending,
    ) {
        let n = self.fft.len();
        let [zr, zi, cr, ci] = &mut pending.z;
        zr.fill(0.0);
        zi.fill(0.0);
        for (m, q) in increments.iter().enumerate() {
            zr[m] = q[0];
            zi[m] = q[1];
        }
        self.fft.transform(zr, zi, false);
        for k in 0..n {
            let mirror = (n - k) % n;
            cr[k] = zr[mirror];
            ci[k] = -zi[mirror];
        }
        let j = grid.strips[source].j;
        for (t, strip) in grid.strips.iter().enumerate() {
            if t == source && !own {
                continue;
            }
            let r = strip.j + self.ny - 1 - j;
            let spectrum = &self.spectra[r * 4 * n..(r + 1) * 4 * n];
            let (wr, wi) = pending.spectra[2 * t * n..2 * (t + 1) * n].split_at_mut(n);
            let z = [&zr[..], &zi[..], &cr[..], &ci[..]];
            accumulate::<FMA>(spectrum, z, [wr, wi]);
            pending.dirty[t] = true;
        }
    }

    /// Brings the s/V of strip `t`'s cells up to date with what `pending` holds for it.
    #[inline(always)]
    fn flush(&self, grid: &ContactGrid, t: usize, pending: &mut Pending, s: &mut [Vec<f64>; 2]) {
        if !pending.dirty[t] {
            return;
        }
        let n = self.fft.len();
        let (wr, wi) = pending.spectra[2 * t * n..2 * (t + 1) * n].split_at_mut(n);
        self.fft.transform(wr, wi, true);
        let strip = &grid.strips[t];
        let base = self.nx * strip.j;
        for k in strip.cells.clone() {
            let i = grid.cells[k].i;
            s[0][base + i] += wr[i];
            s[1][base + i] += wi[i];
        }
        wr.fill(0.0);
        wi.fill(0.0);
        pending.dirty[t] = false;
    }

    /// Steady rolling at creepages `creep` and rolling speed `speed` [m/s] with the traction bound
    /// `bound` = g per cell [Pa] (docs/model.md §6.5), started from `start` (the tractions of a previous
    /// solve on the same grid, [Pa]) or zero. Errors on a grid other than this operator's, non-finite
    /// creepages or start tractions, bounds that are negative or not finite.
    ///
    /// Each cell's change acts at once on its own strip (directly, O(nx)); its effect on the other strips
    /// is gathered per strip and passed on when the strip is done, as a product in Fourier space over x
    /// (the influence is translation invariant: one transform per strip, O(n log n) per pair of strips
    /// instead of O(nx²)). A strip takes what the others sent it when its turn comes, and every strip at the
    /// end of a sweep: the same Gauss–Seidel iterates as updating every cell at each change.
    pub fn solve(
        &self,
        grid: &ContactGrid,
        creep: Creepages,
        speed: f64,
        bound: &[f64],
        start: Option<&[[f64; 2]]>,
        settings: ExactSettings,
    ) -> Result<ExactTraction> {
        check_finite("creepage xi", creep.xi, "")?;
        check_finite("creepage eta", creep.eta, "")?;
        check_finite("spin creepage phi", creep.phi, "1/m")?;
        check_positive("speed", speed, "m/s")?;
        if grid.nx != self.nx || grid.ny != self.ny {
            return Err(Error::OutOfRange {
                name: "contact grid of the steady-rolling operator".into(),
                value: format!("{} × {}", grid.nx, grid.ny),
                allowed: format!("the operator's grid {} × {}", self.nx, self.ny),
            });
        }
        let n = grid.len();
        for (what, len) in [
            ("traction bound (number of values)", Some(bound.len())),
            ("start tractions (number of values)", start.map(<[_]>::len)),
        ] {
            if let Some(len) = len.filter(|&l| l != n) {
                return Err(Error::OutOfRange {
                    name: what.into(),
                    value: len.to_string(),
                    allowed: format!("one value per grid cell ({n})"),
                });
            }
        }
        if let Some(&bad) = bound.iter().find(|g| !(g.is_finite() && **g >= 0.0)) {
            return Err(Error::out_of_range(
                "traction bound",
                bad,
                "finite, >= 0 Pa",
            ));
        }
        if let Some(bad) = start
            .into_iter()
            .flatten()
            .flatten()
            .find(|v| !v.is_finite())
        {
            return Err(Error::out_of_range("start traction", *bad, "finite Pa"));
        }
        // tractions p (a start beyond this solve's bound is scaled onto it), their increments q along the
        // flow, and s/V of every cell at these increments
        let mut p: Vec<[f64; 2]> = match start {
            Some(s) => s
                .iter()
                .zip(bound)
                .map(|(p, &g)| {
                    let m = p[0].hypot(p[1]);
                    if m > g {
                        [p[0] * g / m, p[1] * g / m]
                    } else {
                        *p
                    }
                })
                .collect(),
            None => vec![[0.0; 2]; n],
        };
        // s/V per grid position i + nx·j (positions outside the contact stay unused)
        let mut s = [vec![0.0; self.nx * self.ny], vec![0.0; self.nx * self.ny]];
        for (k, c) in grid.cells.iter().enumerate() {
            let at = self.position(grid, k);
            s[0][at] = creep.xi - creep.phi * c.y;
            s[1][at] = creep.eta + creep.phi * c.x;
        }
        let mut slipping = vec![false; n];
        let (sweeps, residual) = {
            let state = (&mut p[..], &mut s, &mut slipping[..]);
            #[cfg(target_arch = "x86_64")]
            if self.fma {
                // SAFETY: `fma` is set only where the CPU has AVX2 and FMA (`SteadyRolling::new`)
                unsafe { iterate_fma(self, grid, bound, settings, state) }
            } else {
                self.iterate::<false>(grid, bound, settings, state)
            }
            #[cfg(not(target_arch = "x86_64"))]
            self.iterate::<false>(grid, bound, settings, state)
        };
        Ok(ExactTraction {
            field: self.field(grid, &p, &s, &slipping, speed),
            sweeps,
            converged: residual <= settings.tolerance,
            residual,
        })
    }
    /// The sweeps of [`SteadyRolling::solve`] from the tractions `p` [Pa], slips per V `s` and slip flags
    /// of `state` (left at the last sweep's), with fused multiply–adds if `FMA`: (sweeps, residual).
    #[inline(always)]
    fn iterate<const FMA: bool>(
        &self,
        grid: &ContactGrid,
        bound: &[f64],
        settings: ExactSettings,
        state: (&mut [[f64; 2]], &mut [Vec<f64>; 2], &mut [bool]),
    ) -> (usize, f64) {
        let (p, s, slipping) = state;
        let length = self.fft.len();
        let mut pending = Pending {
            spectra: vec![0.0; 2 * length * grid.strips.len()],
            dirty: vec![false; grid.strips.len()],
            z: std::array::from_fn(|_| vec![0.0; length]),
        };
        // the increments of one strip's row at m = column + 1 (m = 0: behind column 0)
        let mut increments = vec![[0.0; 2]; self.nx + 1];
        if p.iter().any(|q| *q != [0.0; 2]) {
            for (t, strip) in grid.strips.iter().enumerate() {
                increments.fill([0.0; 2]);
                let mut upstream = [0.0; 2];
                for k in strip.cells.clone() {
                    let m = grid.cells[k].i + 1;
                    increments[m] = [p[k][0] - upstream[0], p[k][1] - upstream[1]];
                    upstream = p[k];
                }
                // the sum of the increments, p of the trailing cell, leaves behind it
                let released = (Self::released(grid, strip) + 1) as usize;
                increments[released] = [-upstream[0], -upstream[1]];
                self.spread::<FMA>(grid, t, &increments, true, &mut pending);
            }
            for t in 0..grid.strips.len() {
                self.flush(grid, t, &mut pending, s);
            }
        }
        let mut sweeps = 0;
        let mut residual = f64::INFINITY;
        let mut anderson = Anderson::new(settings.anderson_depth);
        while sweeps < settings.max_sweeps {
            sweeps += 1;
            let before = p.to_vec();
            let mut largest = 0.0_f64;
            for (t, strip) in grid.strips.iter().enumerate() {
                // what the strips done since this one's last turn sent it
                self.flush(grid, t, &mut pending, s);
                let released = Self::released(grid, strip);
                let cells = strip.cells.clone();
                increments.fill([0.0; 2]);
                let mut changed = false;
                // from the trailing cell to the leading one
                for k in cells.clone().rev() {
                    let c = grid.cells[k];
                    // a change of p_k moves the tractions of the sticking cells behind it (their
                    // increments are kept) up to the first slipping cell, whose traction stays: the
                    // increment change enters at k and lands there (or behind the trailing cell)
                    let landing = (k + 1..cells.end).find(|&l| slipping[l]);
                    let column = landing.map_or(released, |l| grid.cells[l].i as isize);
                    let d = self.own(grid, k, column);
                    let at = self.position(grid, k);
                    // s_k = r + M_kk·p_k with r free of cell k's own move
                    let r = [s[0][at] - d[0] * p[k][0], s[1][at] - d[1] * p[k][1]];
                    let (pk, _, slip) = local_problem(r, d, bound[k]);
                    slipping[k] = slip;
                    let change = [pk[0] - p[k][0], pk[1] - p[k][1]];
                    if change != [0.0; 2] {
                        largest = largest.max(change[0] * change[0] + change[1] * change[1]);
                        self.move_in_row(grid, strip, c.i as isize, column, change, s);
                        let (enter, leave) = (c.i + 1, (column + 1) as usize);
                        increments[enter] = [
                            increments[enter][0] + change[0],
                            increments[enter][1] + change[1],
                        ];
                        increments[leave] = [
                            increments[leave][0] - change[0],
                            increments[leave][1] - change[1],
                        ];
                        changed = true;
                        for t in &mut p[k..landing.unwrap_or(cells.end)] {
                            t[0] += change[0];
                            t[1] += change[1];
                        }
                    }
                }
                if changed {
                    self.spread::<FMA>(grid, t, &increments, false, &mut pending);
                }
            }
            for t in 0..grid.strips.len() {
                self.flush(grid, t, &mut pending, s);
            }
            // largest squared change and squared traction
            let scale = p
                .iter()
                .fold(0.0_f64, |m, q| m.max(q[0] * q[0] + q[1] * q[1]));
            residual = if scale > 0.0 {
                (largest / scale).sqrt()
            } else {
                0.0
            };
            if residual <= settings.tolerance {
                break;
            }
            if settings.anderson_depth > 0 {
                anderson.extrapolate(before, p, s);
            }
        }
        (sweeps, residual)
    }

    /// The traction field of tractions `p` [Pa] and slips per V `s` at rolling speed `speed` [m/s].
    fn field(
        &self,
        grid: &ContactGrid,
        p: &[[f64; 2]],
        s: &[Vec<f64>; 2],
        slipping: &[bool],
        speed: f64,
    ) -> TractionField {
        let area = grid.cell_area();
        let (mut fx, mut fy, mut mz) = (0.0, 0.0, 0.0);
        for (c, q) in grid.cells.iter().zip(p) {
            fx += q[0];
            fy += q[1];
            mz += c.x * q[1] - c.y * q[0];
        }
        let slip_velocity: Vec<[f64; 2]> = (0..p.len())
            .map(|k| {
                if slipping[k] {
                    let at = self.position(grid, k);
                    [speed * s[0][at], speed * s[1][at]]
                } else {
                    [0.0; 2]
                }
            })
            .collect();
        let power_density = p
            .iter()
            .zip(&slip_velocity)
            .map(|(q, v)| q[0].hypot(q[1]) * v[0].hypot(v[1]))
            .collect();
        TractionField {
            force_x: fx * area,
            force_y: fy * area,
            spin_moment: mz * area,
            traction: p.to_vec(),
            slip_velocity,
            power_density,
            slipping: slipping.to_vec(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::HertzContact;
    use crate::tangential::kalker_coefficients;

    // the reference contact of contact-exact values: F_N = 100 kN, a = 5.87814 mm, b = 10.53911 mm
    const A: f64 = 5.87814e-3;
    const B: f64 = 10.53911e-3;
    const FN: f64 = 100e3;
    const NU: f64 = 0.28;
    const G: f64 = 210e9 / (2.0 * 1.28);
    const V: f64 = 30.0;

    /// Hertz's ellipsoidal pressure p0·sqrt(1 − x²/a² − y²/b²) at the cell centres, times μ.
    fn hertz_bound(grid: &ContactGrid, mu: f64) -> Vec<f64> {
        let h = HertzContact::from_semi_axes(grid.a, grid.b, FN).unwrap();
        grid.cells
            .iter()
            .map(|c| {
                let s = 1.0 - (c.x / grid.a).powi(2) - (c.y / grid.b).powi(2);
                mu * h.p0 * s.max(0.0).sqrt()
            })
            .collect()
    }

    fn solve(grid: &ContactGrid, op: &SteadyRolling, creep: Creepages, mu: f64) -> ExactTraction {
        let bound = hertz_bound(grid, mu);
        let r = op
            .solve(grid, creep, V, &bound, None, ExactSettings::default())
            .unwrap();
        assert!(r.converged, "{} sweeps, residual {}", r.sweeps, r.residual);
        r
    }

    /// The closed-form cell integral against Gauss–Legendre quadrature of Cerruti's kernel over the cell,
    /// at offsets where the kernel is smooth over the cell.
    #[test]
    fn influence_matches_quadrature() {
        let (hx, hy) = (0.4e-3, 0.7e-3);
        // 8-point Gauss–Legendre on [−1, 1]
        let nodes = [
            (0.183_434_642_495_649_8, 0.362_683_783_378_362),
            (0.525_532_409_916_329, 0.313_706_645_877_887_3),
            (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
            (0.960_289_856_497_536_3, 0.101_228_536_290_376_26),
        ];
        let gl: Vec<(f64, f64)> = nodes.iter().flat_map(|&(x, w)| [(x, w), (-x, w)]).collect();
        for (dx, dy) in [(3.0e-3, 1.0e-3), (-2.0e-3, 4.0e-3), (1.5e-3, -2.2e-3)] {
            let mut q = [0.0; 3];
            for &(u, wu) in &gl {
                for &(v, wv) in &gl {
                    let x = dx - 0.5 * hx * u;
                    let y = dy - 0.5 * hy * v;
                    let r = x.hypot(y);
                    let w = wu * wv * 0.25 * hx * hy / (PI * G);
                    q[0] += w * ((1.0 - NU) / r + NU * x * x / r.powi(3));
                    q[1] += w * NU * x * y / r.powi(3);
                    q[2] += w * ((1.0 - NU) / r + NU * y * y / r.powi(3));
                }
            }
            let c = influence(dx, dy, hx, hy, G, NU);
            for k in 0..3 {
                assert!(
                    (c[k] - q[k]).abs() <= 1e-9 * q[0].abs(),
                    "component {k} at ({dx}, {dy}): {} vs {}",
                    c[k],
                    q[k]
                );
            }
        }
        // the self-influence is finite, positive and symmetric
        let c = influence(0.0, 0.0, hx, hy, G, NU);
        assert!(c[0] > 0.0 && c[2] > 0.0 && c[1] == 0.0);
    }

    /// The element problem: stick inside the bound, otherwise |p| = g with s antiparallel to p.
    #[test]
    fn local_problem_stick_and_slip() {
        let d = [2.0, 3.0];
        let (p, s, slip) = local_problem([1.0, -1.5], d, 10.0);
        assert!(!slip && s == [0.0; 2]);
        assert_eq!(p, [-0.5, 0.5]);
        for r in [[4.0, 1.0], [-1.0, 7.0], [0.0, -5.0], [3.0, 0.0]] {
            let (p, s, slip) = local_problem(r, d, 0.5);
            assert!(slip);
            assert!((p[0].hypot(p[1]) - 0.5).abs() < 1e-14);
            // s = r + D·p and s = −t·p with t ≥ 0
            let sr = [r[0] + d[0] * p[0], r[1] + d[1] * p[1]];
            assert!((sr[0] - s[0]).abs() < 1e-13 && (sr[1] - s[1]).abs() < 1e-13);
            assert!(s[0] * p[1] - s[1] * p[0] == 0.0 || (s[0] * p[1] - s[1] * p[0]).abs() < 1e-13);
            assert!(s[0] * p[0] + s[1] * p[1] <= 0.0);
        }
    }

    /// Full stick (no bound) reproduces Kalker's linear theory, F_x = −G·c²·C11·ξ, F_y = −G·c²·C22·η,
    /// F_y = −G·c³·C23·φ (Kalker 1990, Table E.3), for a/b = 0.5, 1, 2: Richardson's extrapolation of two
    /// grids (the scheme is first order in h_x) within 1 %.
    #[test]
    fn linear_theory_reproduces_kalker_coefficients() {
        for ratio in [0.5, 1.0, 2.0] {
            let c = 8e-3;
            let (a, b) = (c * f64::sqrt(ratio), c / f64::sqrt(ratio));
            let k = kalker_coefficients(a, b, NU).unwrap();
            let small = 1e-7;
            let forces = |n: usize| {
                let grid = ContactGrid::new(a, b, n, n);
                let op = SteadyRolling::new(&grid, G, NU).unwrap();
                let free = vec![1e300; grid.len()];
                let run = |creep| {
                    let r = op
                        .solve(&grid, creep, V, &free, None, ExactSettings::default())
                        .unwrap();
                    assert!(r.converged);
                    r.field
                };
                let fx = run(Creepages {
                    xi: small,
                    eta: 0.0,
                    phi: 0.0,
                });
                let fy = run(Creepages {
                    xi: 0.0,
                    eta: small,
                    phi: 0.0,
                });
                let fs = run(Creepages {
                    xi: 0.0,
                    eta: 0.0,
                    phi: small / c,
                });
                [
                    -fx.force_x / (G * c * c * small),
                    -fy.force_y / (G * c * c * small),
                    -fs.force_y / (G * c * c * small),
                ]
            };
            let (coarse, fine) = (forces(20), forces(40));
            for (m, want) in [k.c11, k.c22, k.c23].into_iter().enumerate() {
                let extrapolated = 2.0 * fine[m] - coarse[m];
                eprintln!(
                    "a/b {ratio} C{}: 20 cells {:.4}, 40 cells {:.4}, extrapolated {extrapolated:.4}, Kalker {want:.4}",
                    ["11", "22", "23"][m],
                    coarse[m],
                    fine[m]
                );
                assert!(
                    (extrapolated - want).abs() < 0.01 * want,
                    "a/b {ratio}, C{}: {extrapolated} (grids {} {}) vs Kalker {want}",
                    ["11", "22", "23"][m],
                    coarse[m],
                    fine[m]
                );
            }
        }
    }

    /// CONTACT's exact values for the reference contact (μ = 0.3, Hertz pressure, 80 × 144 cells,
    /// docs/model.md §6.5): F_x within 2 %, M_z under η within 5 %, on a 30 × 30 grid.
    #[test]
    fn reference_contact_matches_contact() {
        let grid = ContactGrid::new(A, B, 30, 30);
        let op = SteadyRolling::new(&grid, G, NU).unwrap();
        let cases: [(f64, f64, f64, f64); 8] = [
            // ξ, η, F [N] (F_x for ξ, F_y for η), M_z [N·m]
            (0.0005, 0.0, -8826.1, 0.0),
            (0.001, 0.0, -15920.4, 0.0),
            (0.002, 0.0, -25347.3, 0.0),
            (0.003, 0.0, -29406.7, 0.0),
            (0.0, 0.0005, -7348.1, 15.57),
            (0.0, 0.001, -13496.7, 23.52),
            (0.0, 0.002, -22481.5, 24.20),
            (0.0, 0.003, -27618.7, 15.53),
        ];
        for (xi, eta, force, moment) in cases {
            let r = solve(&grid, &op, Creepages { xi, eta, phi: 0.0 }, 0.3);
            let f = &r.field;
            let got = if xi != 0.0 { f.force_x } else { f.force_y };
            eprintln!(
                "xi {xi} eta {eta}: F {got:.1} vs {force} ({:+.2} %), M_z {:.2} vs {moment}, {} sweeps",
                100.0 * (got / force - 1.0),
                f.spin_moment,
                r.sweeps
            );
            assert!((got - force).abs() < 0.02 * force.abs());
            if moment != 0.0 {
                assert!((f.spin_moment - moment).abs() < 0.05 * moment);
            }
        }
    }

    /// Pure spin φ = 1, 2, 3 /m on the reference contact (μ = 0.3, Hertz pressure; all but a few cells
    /// slip): CONTACT's converged F_y [N] and M_z [N·m] (docs/model.md §6.5), the first-order Richardson
    /// extrapolation 2·f(80 × 144) − f(40 × 72) of CONTACT (Vollebregt), module 3, over the Hertz ellipse.
    const CONTACT_SPIN: [(f64, f64, f64); 3] = [
        // φ [1/m], F_y [N], M_z [N·m]
        (1.0, -12136.8, -129.360),
        (2.0, -7873.9, -139.940),
        (3.0, -5775.1, -143.570),
    ];

    /// Spin (`CONTACT_SPIN`) converges at first order in the cell size: the successive differences of
    /// F_y on 15 × 15, 30 × 30 and 60 × 60 shrink by 1.6–2.8 per halving (measured 2.0–2.3; first order
    /// gives 2, second order 4), and the order-1 Richardson extrapolation 2·f(60) − f(30) lies within
    /// 0.5 % of CONTACT's converged F_y and M_z (measured 0.08–0.22 % and 0.11–0.13 %; the same
    /// extrapolation of 160 × 288 and 320 × 576 lies within 0.1 % and 0.01 %, the rest is the O(h²)
    /// remainder of the 30/60 pair). The default 30 × 30 grid itself is within 3.5 % in F_y (measured 2.3–2.9 % low) and 1 %
    /// in M_z (0.4–0.7 % high).
    #[test]
    fn spin_converges_at_first_order_to_contacts_values() {
        let operator = |n: usize| {
            let grid = ContactGrid::new(A, B, n, n);
            let op = SteadyRolling::new(&grid, G, NU).unwrap();
            (grid, op)
        };
        let grids: Vec<_> = [15, 30, 60].into_iter().map(operator).collect();
        for (phi, force, moment) in CONTACT_SPIN {
            let creep = Creepages {
                xi: 0.0,
                eta: 0.0,
                phi,
            };
            let f: Vec<(f64, f64)> = grids
                .iter()
                .map(|(grid, op)| {
                    let r = solve(grid, op, creep, 0.3).field;
                    (r.force_y, r.spin_moment)
                })
                .collect();
            let ratio = (f[1].0 - f[0].0) / (f[2].0 - f[1].0);
            let extrapolated = (2.0 * f[2].0 - f[1].0, 2.0 * f[2].1 - f[1].1);
            eprintln!(
                "phi {phi}: F_y {:.1} / {:.1} / {:.1}, ratio {ratio:.2}, extrapolated {:.1} vs CONTACT {force} \
                 ({:+.2} %); M_z {:.3} / {:.3} / {:.3}, extrapolated {:.3} vs {moment} ({:+.2} %)",
                f[0].0,
                f[1].0,
                f[2].0,
                extrapolated.0,
                100.0 * (extrapolated.0 / force - 1.0),
                f[0].1,
                f[1].1,
                f[2].1,
                extrapolated.1,
                100.0 * (extrapolated.1 / moment - 1.0)
            );
            assert!((1.6..2.8).contains(&ratio), "phi {phi}: ratio {ratio}");
            assert!((extrapolated.0 - force).abs() < 0.005 * force.abs());
            assert!((extrapolated.1 - moment).abs() < 0.005 * moment.abs());
            assert!((f[1].0 - force).abs() < 0.035 * force.abs());
            assert!((f[1].1 - moment).abs() < 0.01 * moment.abs());
        }
    }

    /// On CONTACT's own grid (40 × 72 cells over the Hertz ellipse) the spin forces differ from CONTACT's
    /// module 3 by the place of the spin's lateral rigid slip φ·x: CONTACT takes it at x + h_x/6 (its
    /// input FACPHI = 1/6), this solver at the cell centre. With FACPHI = 0, CONTACT gives this solver's
    /// F_y and M_z within 0.2 % (measured ≤ 0.03 % and ≤ 0.07 %: the pressure of CONTACT's discrete normal
    /// solve against Hertz's at the cell centres); with its default it lies more than 1 % above in |F_y|
    /// (1.6 %, 2.8 %, 4.1 % at φ = 1, 2, 3 /m), the first-order errors of the two placements having
    /// opposite signs.
    #[test]
    fn spin_on_contacts_grid_matches_contact_with_the_spin_term_at_the_centre() {
        // φ [1/m]; CONTACT 40 × 72 with FACPHI = 0: F_y [N], M_z [N·m]; with FACPHI = 1/6: F_y [N]
        let cases = [
            (1.0, -11930.46, -129.801, -12118.96),
            (2.0, -7723.79, -140.211, -7943.53),
            (3.0, -5655.13, -143.746, -5885.89),
        ];
        let grid = ContactGrid::new(A, B, 40, 72);
        let op = SteadyRolling::new(&grid, G, NU).unwrap();
        for (phi, force, moment, default) in cases {
            let creep = Creepages {
                xi: 0.0,
                eta: 0.0,
                phi,
            };
            let f = solve(&grid, &op, creep, 0.3).field;
            eprintln!(
                "phi {phi}: F_y {:.2} vs {force} ({:+.3} %), M_z {:.3} vs {moment} ({:+.3} %); \
                 CONTACT at x + h_x/6 {default} ({:+.2} %)",
                f.force_y,
                100.0 * (f.force_y / force - 1.0),
                f.spin_moment,
                100.0 * (f.spin_moment / moment - 1.0),
                100.0 * (default / f.force_y - 1.0)
            );
            assert!((f.force_y - force).abs() < 0.002 * force.abs());
            assert!((f.spin_moment - moment).abs() < 0.002 * moment.abs());
            assert!(default / f.force_y - 1.0 > 0.01, "phi {phi}");
        }
    }

    /// A long strip (a/b = 0.05) in longitudinal creepage: every slice y rolls as Carter's
    /// two-dimensional contact (K.L. Johnson, *Contact Mechanics*, 1985, §8.2): with the slice's
    /// half-width a(y) and peak pressure p0(y) of Hertz's ellipse, F_x(y)/(μ·P(y)) = 1 − (1 − ξ/ξ_s(y))²
    /// below saturation, ξ_s = 2μ·p0(y)·(1 − ν)/G, P(y) = π·a(y)·p0(y)/2. Within 3 % of μ·F_N.
    #[test]
    fn long_strip_follows_carter() {
        let (a, b, mu) = (1e-3, 20e-3, 0.3);
        let grid = ContactGrid::new(a, b, 40, 40);
        let op = SteadyRolling::new(&grid, G, NU).unwrap();
        let p0 = 3.0 * FN / (2.0 * PI * a * b);
        let saturation = 2.0 * mu * p0 * (1.0 - NU) / G;
        for fraction in [0.1, 0.3, 0.6, 1.0] {
            let xi = fraction * saturation;
            let r = solve(
                &grid,
                &op,
                Creepages {
                    xi,
                    eta: 0.0,
                    phi: 0.0,
                },
                mu,
            );
            // Carter per slice, integrated over y (Gauss–Legendre in y = b·sin θ)
            let slices = 2000;
            let mut carter = 0.0;
            for m in 0..slices {
                let theta = -PI / 2.0 + PI * (m as f64 + 0.5) / slices as f64;
                let (y, dy) = (b * theta.sin(), b * theta.cos() * PI / slices as f64);
                let shrink = (1.0 - (y / b).powi(2)).sqrt();
                let (ay, p0y) = (a * shrink, p0 * shrink);
                let k = (xi / (saturation * shrink)).min(1.0);
                carter += mu * PI * ay * p0y / 2.0 * (1.0 - (1.0 - k).powi(2)) * dy;
            }
            let got = -r.field.force_x;
            eprintln!(
                "xi/xi_s {fraction}: F_x/(mu F_N) {:.4} vs Carter {:.4}",
                got / (mu * FN),
                carter / (mu * FN)
            );
            assert!((got - carter).abs() < 0.03 * mu * FN);
        }
    }

    /// Anderson's extrapolation changes the path, not the solution: plain Gauss–Seidel and the
    /// accelerated sweeps agree to the tolerance (partial slip with spin), and the extrapolation saves
    /// sweeps (longitudinal creepage).
    #[test]
    fn anderson_extrapolation_keeps_the_solution_and_saves_sweeps() {
        let grid = ContactGrid::new(A, B, 24, 24);
        let op = SteadyRolling::new(&grid, G, NU).unwrap();
        let bound = hertz_bound(&grid, 0.3);
        let run = |creep, depth| {
            let settings = ExactSettings {
                tolerance: 1e-10,
                anderson_depth: depth,
                ..ExactSettings::default()
            };
            let r = op.solve(&grid, creep, V, &bound, None, settings).unwrap();
            assert!(r.converged);
            r
        };
        let spin = Creepages {
            xi: 0.0008,
            eta: -0.0004,
            phi: 0.4,
        };
        let (plain, fast) = (run(spin, 0), run(spin, 5));
        let scale = 0.3 * FN;
        for (a, b) in [
            (plain.field.force_x, fast.field.force_x),
            (plain.field.force_y, fast.field.force_y),
        ] {
            assert!((a - b).abs() < 1e-7 * scale, "{a} vs {b}");
        }
        assert!(
            (plain.field.spin_moment - fast.field.spin_moment).abs()
                < 1e-7 * plain.field.spin_moment.abs()
        );
        assert_eq!(plain.field.slipping, fast.field.slipping);
        let longitudinal = Creepages {
            xi: 0.001,
            eta: 0.0,
            phi: 0.0,
        };
        let (plain, fast) = (run(longitudinal, 0), run(longitudinal, 5));
        assert!(
            fast.sweeps * 6 < plain.sweeps * 5,
            "{} vs {} sweeps",
            fast.sweeps,
            plain.sweeps
        );
    }

    /// The largest violation of the discrete contact conditions by the tractions `p` of a solve, over the
    /// largest traction, evaluated independently of the solver's tables and transforms: s/V of every cell
    /// summed directly from [`influence`], s_I/V = w_I + Σ_J (A(x_I − x_J) − A(x_I + h_x − x_J))·p_J/h_x,
    /// then each cell's element problem (diagonal D = the cell's own coefficient) from r = s − D·p: it
    /// returns p itself exactly where p sticks (s = 0, |p| ≤ g) or slips (|p| = g, s = −λ·p, λ ≥ 0).
    /// Also the largest difference of the solver's slips in slipping cells from the direct ones [-].
    fn contact_violation(
        grid: &ContactGrid,
        creep: Creepages,
        bound: &[f64],
        r: &ExactTraction,
    ) -> (f64, f64) {
        let (hx, hy) = (grid.hx, grid.hy);
        let b = |dx: f64, dy: f64| {
            let (u, v) = (
                influence(dx, dy, hx, hy, G, NU),
                influence(dx + hx, dy, hx, hy, G, NU),
            );
            [(u[0] - v[0]) / hx, (u[1] - v[1]) / hx, (u[2] - v[2]) / hx]
        };
        let p = &r.field.traction;
        let scale = p.iter().fold(0.0_f64, |m, q| m.max(q[0].hypot(q[1])));
        let own = b(0.0, 0.0);
        let (mut violation, mut slip_error) = (0.0_f64, 0.0_f64);
        for (k, c) in grid.cells.iter().enumerate() {
            let mut s = [creep.xi - creep.phi * c.y, creep.eta + creep.phi * c.x];
            for (l, e) in grid.cells.iter().enumerate() {
                let m = b(c.x - e.x, c.y - e.y);
                s[0] += m[0] * p[l][0] + m[1] * p[l][1];
                s[1] += m[1] * p[l][0] + m[2] * p[l][1];
            }
            let d = [own[0], own[2]];
            let (q, _, _) =
                local_problem([s[0] - d[0] * p[k][0], s[1] - d[1] * p[k][1]], d, bound[k]);
            violation = violation.max((q[0] - p[k][0]).hypot(q[1] - p[k][1]) / scale);
            if r.field.slipping[k] {
                let v = r.field.slip_velocity[k];
                slip_error = slip_error.max((v[0] / V - s[0]).hypot(v[1] / V - s[1]));
            }
        }
        (violation, slip_error)
    }

    /// The Gauss–Seidel sweeps with the other strips' influence passed on in Fourier space solve the
    /// discrete problem: the contact conditions hold, checked by direct summation
    /// ([`contact_violation`]), within the tolerance ([`ExactSettings::tolerance`]; measured 0.1–0.6 of it) for longitudinal, lateral and spin creepage, full slip, a/b =
    /// 0.2 and 5, a bound varying along and across the contact (as the model's local τ_l), a warm start,
    /// and grids of 33 × 7 and 1 × 5 cells (transform lengths 128 and 2); a solve stopped at a loose tolerance fails the same check.
    #[test]
    fn solution_satisfies_the_contact_conditions_by_direct_summation() {
        let tolerance = ExactSettings::default().tolerance;
        let cases: [(f64, f64, f64, f64, &str, usize, usize); 10] = [
            // a/b, ξ, η, φ [1/m], bound, grid nx × ny
            (A / B, 0.001, 0.0, 0.0, "hertz", 20, 16),
            (A / B, 0.0, 0.002, 0.0, "hertz", 20, 16),
            (A / B, 0.0, 0.0, 0.6, "hertz", 20, 16),
            (A / B, 0.0008, -0.0004, 0.4, "varying", 20, 16),
            (A / B, 0.01, 0.003, 0.0, "hertz", 20, 16),
            (0.2, 0.0005, 0.0005, 0.2, "hertz", 20, 16),
            (5.0, 0.0005, 0.0005, 0.2, "varying", 20, 16),
            (A / B, 0.0015, 0.0, 0.2, "warm", 20, 16),
            // transforms of length 128 for 33 columns, and of the shortest length
            (A / B, 0.0008, -0.0004, 0.4, "hertz", 33, 7),
            (A / B, 0.0008, -0.0004, 0.4, "hertz", 1, 5),
        ];
        for (ratio, xi, eta, phi, kind, nx, ny) in cases {
            let c = (A * B).sqrt();
            let grid = ContactGrid::new(c * ratio.sqrt(), c / ratio.sqrt(), nx, ny);
            let op = SteadyRolling::new(&grid, G, NU).unwrap();
            let mut bound = hertz_bound(&grid, 0.3);
            if kind == "varying" {
                // friction falling towards the trailing edge and across, as heating would make it
                for (g, cell) in bound.iter_mut().zip(&grid.cells) {
                    *g *= 1.0 - 0.4 * (grid.a - cell.x) / (2.0 * grid.a) + 0.1 * cell.y / grid.b;
                }
            }
            let creep = Creepages { xi, eta, phi };
            let start = (kind == "warm").then(|| {
                let other = Creepages {
                    xi: 0.001,
                    eta: 0.0005,
                    phi: 0.0,
                };
                solve(&grid, &op, other, 0.3).field.traction
            });
            let run = |tolerance| {
                let settings = ExactSettings {
                    tolerance,
                    ..ExactSettings::default()
                };
                op.solve(&grid, creep, V, &bound, start.as_deref(), settings)
                    .unwrap()
            };
            let r = run(tolerance);
            assert!(r.converged);
            let (violation, slip_error) = contact_violation(&grid, creep, &bound, &r);
            let slipping = r.field.slipping.iter().filter(|&&s| s).count();
            eprintln!(
                "a/b {ratio:.2} xi {xi} eta {eta} phi {phi} {kind} {nx} x {ny}: {slipping}/{} slipping, {} sweeps, \
                 violation {violation:.2e}, slip error {slip_error:.2e}",
                grid.len(),
                r.sweeps
            );
            assert!(violation < tolerance, "violation {violation}");
            // the solver's slips are those of its tractions up to round-off
            assert!(slip_error < 1e-9 * xi.abs().max(eta.abs()).max(phi.abs() * c));
            let loose = run(1e-4);
            let (violation, _) = contact_violation(&grid, creep, &bound, &loose);
            assert!(violation > tolerance, "loose solve: violation {violation}");
        }
    }
}
