//! Tabulated dimensionless Greenwood–Williamson/ZMC integrals 𝒫(h, c), 𝒜(h, c) (docs/model.md §4; definitions
//! in `gw`): a fast replacement of the direct quadrature for the ranges the model reaches.
//!
//! For a fixed K = 0.454 + 0.41ν the integrals depend on h = d/z_s and c = ω_c/z_s only. Both are analytic
//! in (h, c) (with u = c·v the asperity law becomes c^1.5·g(v) with kinks at fixed v = 1, 54, and only the
//! Gaussian weight φ0(h + c·v) depends on h and c), so they are tabulated as
//! - ln 𝒫, (ln 𝒫)' = 𝒫'/𝒫, (ln 𝒫)'' = 𝒫''/𝒫 − (𝒫'/𝒫)² and the same for 𝒜 (′ = ∂/∂h) on a grid uniform in
//!   h (step 1/8, −10 ≤ h ≤ 38.5) and in ln c (step 1/50, 2e−3 ≤ c ≤ 10; the default steel and roughness
//!   reach 0.0069 ≤ c ≤ 3.54 for 200 K ≤ T ≤ 1800 K, 0 ≤ k_r ≤ 1), the logarithms because
//!   ln 𝒫 ≈ −h²/2 for large h, which keeps the relative accuracy uniform;
//! - interpolated by 8-point Lagrange polynomials in ln c and quintic Hermite polynomials in h. The returned
//!   h-derivatives are those of the interpolant (d𝒫/dh = 𝒫·(ln 𝒫)′ of the interpolated logarithm), so a
//!   Newton iteration on the interpolated values converges quadratically.
//!
//! The grid nodes come from a composite Gauss–Legendre quadrature in w = √u with breaks at u = c and
//! u = 54c (where the asperity law has kinks) and the Gaussian weight scaled by e^{h²/2}, accurate to about
//! 1e−13. The table is built lazily in blocks of 32 grid intervals in h (4 units of h) of one column (one c),
//! 5–15 µs each: a process pays only for the (c, h) it meets (a dry operating point, its c varying with
//! the temperature field, builds about 20 blocks, 0.2 ms); every block of every column would take 8.9 MB
//! and about 60 ms.
//!
//! Accuracy, relative, of 𝒫, 𝒜 and their h-derivatives against an independent quadrature (10 000 random
//! samples, a quarter of them in the plastic transitions c ≤ −h ≤ 54c): ≤ 5e−10 for the values and
//! ≤ 8e−9 for the derivatives. The error comes from the interpolation in ln c and is largest towards
//! h = −10, where the kinks of the law at u = c and u = 54c cross the Gaussian window at u ≈ −h within
//! Δln c ≈ 1/|h|; for h ≥ −4 it is about 1e−11 (values) and 1e−9 (derivatives). Above h ≈ 37 the values
//! (below 1e−300) underflow to subnormal numbers.

use super::gw::{H_ZERO, Law};
use crate::quadrature::gauss_legendre::GaussLegendre;
use std::cell::Cell;
use std::sync::{Mutex, OnceLock};

/// Lowest tabulated h = d/z_s.
pub const H_MIN: f64 = -10.0;
/// Grid step in h.
const H_STEP: f64 = 0.125;
/// Grid intervals in h per block (a block is built at once, for one c).
const BLOCK_INTERVALS: usize = 32;
/// Blocks per column: h = H_MIN … H_ZERO (the last block reaches beyond H_ZERO).
const BLOCKS: usize = (((H_ZERO - H_MIN) / H_STEP) as usize).div_ceil(BLOCK_INTERVALS);
/// Tabulated range of c = ω_c/z_s (the defaults of docs/model.md reach 0.007 … 3.5 for 200 K ≤ T ≤ 1800 K, 0 ≤ k_r ≤ 1).
pub const C_RANGE: (f64, f64) = (2e-3, 10.0);
/// Grid step in ln c.
const LN_C_STEP: f64 = 0.02;
/// Lagrange points in ln c (an even number: the stencil is centred on the interval holding c).
const ORDER: usize = 8;
/// Columns below the interval holding c in its stencil.
const BELOW: usize = ORDER / 2 - 1;
/// Drop of ln of the Gaussian weight beyond its peak at which a grid node's quadrature is cut: e^−40.
const WINDOW: f64 = 40.0;
/// Largest sub-interval in w = √u of the grid quadrature, and its Gauss–Legendre nodes.
const PIECE: f64 = 0.25;
const PIECE_NODES: usize = 10;
/// ln √(2π).
const LN_SQRT_2PI: f64 = 0.918_938_533_204_672_8;

/// One grid node: ln 𝒫, (ln 𝒫)', (ln 𝒫)'', ln 𝒜, (ln 𝒜)', (ln 𝒜)'' at one (h, c).
type Node = [f64; 6];
/// The nodes of one block: rows b·BLOCK_INTERVALS … (b + 1)·BLOCK_INTERVALS of one column (one c).
type Block = Box<[Node; BLOCK_INTERVALS + 1]>;

/// The lazily built table of one K: columns of fixed c = exp(ln_c0 + i·LN_C_STEP), each of BLOCKS blocks
/// in h built on first use.
pub struct GwTable {
    k: f64,
    /// ln c of column 0.
    ln_c0: f64,
    /// Block b of column i at i·BLOCKS + b.
    blocks: Box<[OnceLock<Block>]>,
}

impl std::fmt::Debug for GwTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let built = self.blocks.iter().filter(|b| b.get().is_some()).count();
        write!(
            f,
            "GwTable {{ k: {}, blocks built: {built} of {} }}",
            self.k,
            self.blocks.len()
        )
    }
}

impl GwTable {
    /// The process-wide table of K (created on first request; the tables of all K met stay for the
    /// lifetime of the process).
    pub fn for_k(k: f64) -> &'static GwTable {
        static TABLES: Mutex<Vec<&'static GwTable>> = Mutex::new(Vec::new());
        let mut tables = TABLES.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = tables.iter().find(|t| t.k.to_bits() == k.to_bits()) {
            return t;
        }
        let (lo, hi) = (C_RANGE.0.ln(), C_RANGE.1.ln());
        let columns = ((hi - lo) / LN_C_STEP).ceil() as usize + ORDER;
        let table: &'static GwTable = Box::leak(Box::new(GwTable {
            k,
            ln_c0: lo - BELOW as f64 * LN_C_STEP,
            blocks: (0..columns * BLOCKS).map(|_| OnceLock::new()).collect(),
        }));
        tables.push(table);
        table
    }

    /// K of this table.
    pub fn k(&self) -> f64 {
        self.k
    }

    /// The interpolation stencil at c, or None outside C_RANGE (or c not finite). The last stencil of each
    /// thread is kept: repeated calls for the same material state (a cell's root finding) reuse it.
    pub fn stencil(&'static self, c: f64) -> Option<Stencil> {
        thread_local! {
            static LAST: Cell<Option<(u64, Stencil)>> = const { Cell::new(None) };
        }
        let key = c.to_bits();
        if let Some((k, s)) = LAST.with(Cell::get)
            && k == key
            && std::ptr::eq(s.table, self)
        {
            return Some(s);
        }
        let s = self.new_stencil(c)?;
        LAST.with(|last| last.set(Some((key, s))));
        Some(s)
    }

    fn new_stencil(&'static self, c: f64) -> Option<Stencil> {
        if !(C_RANGE.0..=C_RANGE.1).contains(&c) {
            return None;
        }
        let x = (c.ln() - self.ln_c0) * (1.0 / LN_C_STEP);
        let i0 = (x as usize).clamp(BELOW, self.blocks.len() / BLOCKS - ORDER + BELOW);
        Some(Stencil {
            table: self,
            first: i0 - BELOW,
            weights: lagrange_weights(x - i0 as f64),
        })
    }

    /// Block b of column i (built on first use).
    #[inline]
    fn block(&self, i: usize, b: usize) -> &Block {
        self.blocks[i * BLOCKS + b].get_or_init(|| {
            let c = (self.ln_c0 + i as f64 * LN_C_STEP).exp();
            build_block(&Law::new(c, self.k), b)
        })
    }
}

/// Weights of the ORDER-point Lagrange interpolation at points −BELOW, …, ORDER − 1 − BELOW for the
/// position t (between 0 and 1): w_m = Π_{n≠m} (t − n)/(m − n).
#[inline]
fn lagrange_weights(t: f64) -> [f64; ORDER] {
    // 1/Π_{n≠m} (m − n) for m = −3 … 4
    const INV_DENOMINATOR: [f64; ORDER] = [
        -1.0 / 5040.0,
        1.0 / 720.0,
        -1.0 / 240.0,
        1.0 / 144.0,
        -1.0 / 144.0,
        1.0 / 240.0,
        -1.0 / 720.0,
        1.0 / 5040.0,
    ];
    let d: [f64; ORDER] = std::array::from_fn(|n| t - (n as f64 - BELOW as f64));
    let mut prefix = [1.0; ORDER];
    let mut suffix = [1.0; ORDER];
    for m in 1..ORDER {
        prefix[m] = prefix[m - 1] * d[m - 1];
        suffix[ORDER - 1 - m] = suffix[ORDER - m] * d[ORDER - m];
    }
    std::array::from_fn(|m| prefix[m] * suffix[m] * INV_DENOMINATOR[m])
}

/// The table columns and Lagrange weights for one c: evaluates the integrals at any h.
#[derive(Debug, Clone, Copy)]
pub struct Stencil {
    table: &'static GwTable,
    /// First column of the stencil.
    first: usize,
    weights: [f64; ORDER],
}

impl Stencil {
    /// 𝒜, 𝒫 and their h-derivatives at h, or None outside H_MIN ≤ h < H_ZERO (or h not finite).
    #[cfg(test)]
    pub fn integrals(&self, h: f64) -> Option<super::gw::Integrals> {
        self.interpolant(h).map(|i| {
            let (load, dload) = i.load();
            let (area, darea) = i.area();
            super::gw::Integrals {
                area,
                load,
                dload,
                darea,
            }
        })
    }

    /// The interpolant of the integrals at h (None outside H_MIN ≤ h < H_ZERO, or h not finite), to
    /// evaluate 𝒫 and 𝒜 separately: [`Interpolant::load`], [`Interpolant::area`] are the fields of
    /// `integrals`, bit for bit.
    #[inline]
    pub fn interpolant(&self, h: f64) -> Option<Interpolant> {
        self.interpolant_reusing(h, &mut None)
    }

    /// As [`Self::interpolant`], taking the interval's nodes from `last` when h lies in the interval
    /// `last` holds and keeping the nodes of h's interval there otherwise (the same values, bit for bit:
    /// a root finder whose iterates stay in one interval interpolates its nodes in ln c once).
    #[inline]
    pub fn interpolant_reusing(
        &self,
        h: f64,
        last: &mut Option<IntervalNodes>,
    ) -> Option<Interpolant> {
        let (j, t) = locate(h)?;
        let y = match *last {
            Some(n) if n.interval == j => n.y,
            _ => {
                let y = self.rows(j);
                *last = Some(IntervalNodes { interval: j, y });
                y
            }
        };
        Some(Interpolant {
            y,
            basis: QuinticHermite::at(t),
        })
    }

    /// The nodes of rows j and j + 1 of the h grid interpolated in ln c (Lagrange, ORDER points).
    #[inline]
    fn rows(&self, j: usize) -> [f64; 12] {
        let (b, r) = (j / BLOCK_INTERVALS, j % BLOCK_INTERVALS);
        let mut y = [0.0; 12];
        for (m, w) in self.weights.iter().enumerate() {
            let block = self.table.block(self.first + m, b);
            let (n0, n1) = (&block[r], &block[r + 1]);
            for q in 0..6 {
                y[q] += w * n0[q];
                y[6 + q] += w * n1[q];
            }
        }
        y
    }
}

/// The interval j of the h grid holding h (rows h_j ≤ h < h_{j+1}) and the position t ∈ [0, 1) in it;
/// None outside H_MIN ≤ h < H_ZERO (or h not finite).
#[inline]
fn locate(h: f64) -> Option<(usize, f64)> {
    if !(H_MIN..H_ZERO).contains(&h) {
        return None;
    }
    let x = (h - H_MIN) * (1.0 / H_STEP);
    let j = x as usize;
    Some((j, x - j as f64))
}

/// The nodes of one interval of the h grid interpolated in ln c ([`Stencil::interpolant_reusing`]).
#[derive(Debug, Clone, Copy)]
pub struct IntervalNodes {
    interval: usize,
    y: [f64; 12],
}

/// The integrals' logarithms and their h-derivatives interpolated in ln c at both ends of one grid
/// interval in h, with the Hermite basis at h in it.
#[derive(Debug, Clone, Copy)]
pub struct Interpolant {
    /// ln 𝒫, (ln 𝒫)', (ln 𝒫)'', ln 𝒜, (ln 𝒜)', (ln 𝒜)'' at the interval's lower end, then at its upper end.
    y: [f64; 12],
    basis: QuinticHermite,
}

impl Interpolant {
    /// 𝒫 and d𝒫/dh.
    #[inline]
    pub fn load(&self) -> (f64, f64) {
        self.basis.exp_of(&self.y[0..3], &self.y[6..9])
    }

    /// ln 𝒫 and d(ln 𝒫)/dh (what [`Self::load`] exponentiates; no exponential taken).
    #[inline]
    pub fn ln_load(&self) -> (f64, f64) {
        let (ln, dln) = self.basis.ln_of(&self.y[0..3], &self.y[6..9]);
        (ln, dln / H_STEP)
    }

    /// 𝒜 and d𝒜/dh.
    #[inline]
    pub fn area(&self) -> (f64, f64) {
        self.basis.exp_of(&self.y[3..6], &self.y[9..12])
    }
}

/// Quintic Hermite basis on one grid interval at t ∈ [0, 1] (value and d/dt).
#[derive(Debug, Clone, Copy)]
struct QuinticHermite {
    /// Basis of (p1 − p0, m0, a0, a1, m1): p = value, m = H_STEP·d/dh, a = H_STEP²·d²/dh².
    value: [f64; 5],
    slope: [f64; 5],
}

impl QuinticHermite {
    fn at(t: f64) -> Self {
        let (t2, s) = (t * t, 1.0 - t);
        let t3 = t2 * t;
        Self {
            // H5 = t³(10 − 15t + 6t²), H1 = t(1 − t)³(1 + 3t), H2 = ½t²(1 − t)³,
            // H3 = ½t³(1 − t)², H4 = −t³(1 − t)(4 − 3t)
            value: [
                t3 * (10.0 - 15.0 * t + 6.0 * t2),
                t * s * s * s * (1.0 + 3.0 * t),
                0.5 * t2 * s * s * s,
                0.5 * t3 * s * s,
                -t3 * s * (4.0 - 3.0 * t),
            ],
            slope: [
                30.0 * t2 * s * s,
                s * s * (1.0 + 2.0 * t - 15.0 * t2),
                0.5 * t * s * s * (2.0 - 5.0 * t),
                0.5 * t2 * s * (3.0 - 5.0 * t),
                -t2 * (12.0 - 28.0 * t + 15.0 * t2),
            ],
        }
    }

    /// exp(L) and d exp(L)/dh for L interpolated from (L, L', L'') at both ends of the interval.
    #[inline]
    fn exp_of(&self, y0: &[f64], y1: &[f64]) -> (f64, f64) {
        let (ln, dln) = self.ln_of(y0, y1);
        let f = ln.exp();
        (f, f * dln / H_STEP)
    }

    /// L and H_STEP·dL/dh interpolated from (L, L', L'') at both ends of the interval.
    #[inline]
    fn ln_of(&self, y0: &[f64], y1: &[f64]) -> (f64, f64) {
        let coef = [
            y1[0] - y0[0],
            H_STEP * y0[1],
            H_STEP * H_STEP * y0[2],
            H_STEP * H_STEP * y1[2],
            H_STEP * y1[1],
        ];
        let mut ln = y0[0];
        let mut dln = 0.0;
        for ((c, v), s) in coef.iter().zip(&self.value).zip(&self.slope) {
            ln += c * v;
            dln += c * s;
        }
        (ln, dln)
    }
}

/// Block b of one column of the table: the grid nodes at rows h_j = H_MIN + j·H_STEP,
/// j = b·BLOCK_INTERVALS … (b + 1)·BLOCK_INTERVALS, for the law's c.
///
/// With s = h + u and the Gaussian weight scaled by e^{h²/2}·√(2π) (so that nothing underflows for large h),
/// 𝒫 = e^{−h²/2}/√(2π)·Σ_i W_i·p(u_i)·e^{−h·u_i − u_i²/2}, 𝒫' = −(…)·s_i and 𝒫'' = (…)·(s_i² − 1), with the
/// nodes u_i of composite Gauss–Legendre rules in w = √u on [0, c], [c, 54c], [54c, ∞) (sub-intervals of
/// at most PIECE in w) and, at each row, only the nodes in the window where φ0(s) > e^−WINDOW of its peak.
fn build_block(law: &Law, b: usize) -> Block {
    let rule = GaussLegendre::new(PIECE_NODES);
    let reach = (2.0 * WINDOW).sqrt();
    let row_h = |r: usize| H_MIN + (b * BLOCK_INTERVALS + r) as f64 * H_STEP;
    // the window in u at h: φ0(h + u) > e^−WINDOW·max φ0 on [0, ∞)
    let window = |h: f64| {
        (
            (-reach - h).max(0.0),
            (h.max(0.0).powi(2) + reach * reach).sqrt() - h,
        )
    };
    // both ends of the window fall with h: the block needs the nodes from the lowest end of its last row
    // to the highest end of its first row
    let (w_lo, w_hi) = (
        window(row_h(BLOCK_INTERVALS)).0.sqrt(),
        window(row_h(0)).1.sqrt(),
    );
    let breaks = [w_lo, law.c.sqrt(), law.cp.sqrt(), w_hi];
    // quadrature nodes, ascending in u: (u, weight, area integrand, load integrand)
    let mut nodes: Vec<(f64, f64, f64, f64)> = Vec::new();
    for seg in breaks.windows(2) {
        let (wa, wb) = (seg[0].clamp(w_lo, w_hi), seg[1].clamp(w_lo, w_hi));
        if wb <= wa {
            continue;
        }
        let pieces = ((wb - wa) / PIECE).ceil();
        let width = (wb - wa) / pieces;
        for k in 0..pieces as usize {
            let mid = wa + (k as f64 + 0.5) * width;
            for (x, wt) in rule.nodes.iter().zip(&rule.weights) {
                let w = mid + 0.5 * width * x;
                let u = w * w;
                let (a, p) = law.asperity(u);
                nodes.push((u, wt * width * w, a, p));
            }
        }
    }
    // the scaled weights g_i = W_i·e^{−h·u_i − u_i²/2} of the current row, carried to the next row by the
    // factor e^{−H_STEP·u_i}; a node gets its weight when it enters the window (at the window's lower end,
    // which falls as h grows), so there are two exponentials per node instead of one per node and row
    let mut g = vec![0.0; nodes.len()];
    let mut factor = vec![0.0; nodes.len()];
    let mut entered = nodes.len();
    let mut block: Block = Box::new([[0.0; 6]; BLOCK_INTERVALS + 1]);
    for (r, node) in block.iter_mut().enumerate() {
        let h = row_h(r);
        let (u_lo, u_hi) = window(h);
        let first = nodes.partition_point(|n| n.0 < u_lo);
        let last = nodes.partition_point(|n| n.0 <= u_hi);
        for i in first..entered.min(last) {
            let (u, wt, ..) = nodes[i];
            g[i] = wt * (-u * (h + 0.5 * u)).exp();
            factor[i] = (-H_STEP * u).exp();
        }
        entered = entered.min(first);
        let (mut sp, mut sa) = ([0.0; 3], [0.0; 3]);
        for i in first..last {
            let (u, _, a, p) = nodes[i];
            let s = h + u;
            let m = [g[i], g[i] * s, g[i] * (s * s - 1.0)];
            for q in 0..3 {
                sp[q] += m[q] * p;
                sa[q] += m[q] * a;
            }
            g[i] *= factor[i];
        }
        // ln 𝒫 = ln S0 − h²/2 − ln √(2π), (ln 𝒫)' = −S1/S0, (ln 𝒫)'' = S2/S0 − (S1/S0)²
        let logs = |m: [f64; 3]| {
            let d1 = -m[1] / m[0];
            [
                m[0].ln() - 0.5 * h * h - LN_SQRT_2PI,
                d1,
                m[2] / m[0] - d1 * d1,
            ]
        };
        let (lp, la) = (logs(sp), logs(sa));
        *node = [lp[0], lp[1], lp[2], la[0], la[1], la[2]];
    }
    block
}

#[cfg(test)]
mod tests {
    use super::super::gw::{Integrals, f1, phi0, upper_tail};
    use super::*;

    /// K of ν = 0.28 (the project's steel).
    const K: f64 = 0.454 + 0.41 * 0.28;

    /// Independent reference of 𝒜, 𝒫 and their h-derivatives: composite 20-point Gauss–Legendre in w = √u,
    /// 24 equal sub-intervals on each of [0, c], [c, 54c], [54c, u_top] (clipped to where φ0(h + u) exceeds
    /// e^−45 of its peak), with the unscaled density φ0 (h ≤ 36 keeps it a normal number).
    fn reference(h: f64, c: f64, k: f64) -> Integrals {
        let law = Law::new(c, k);
        let rule = GaussLegendre::new(20);
        let reach = 90f64.sqrt();
        let (u_lo, u_hi) = (
            (-reach - h).max(0.0),
            (h.max(0.0).powi(2) + 90.0).sqrt() - h,
        );
        let mut acc = Integrals::default();
        for (a, b) in [(0.0, c), (c, law.cp), (law.cp, u_hi)] {
            let (a, b) = (a.clamp(u_lo, u_hi), b.clamp(u_lo, u_hi));
            if b <= a {
                continue;
            }
            let (wa, wb) = (a.sqrt(), b.sqrt());
            let width = (wb - wa) / 24.0;
            for i in 0..24 {
                let mid = wa + (i as f64 + 0.5) * width;
                for (x, wt) in rule.nodes.iter().zip(&rule.weights) {
                    let w = mid + 0.5 * width * x;
                    let (fa, fp) = law.asperity(w * w);
                    let s = h + w * w;
                    let g = wt * width * w * phi0(s);
                    acc.area += g * fa;
                    acc.load += g * fp;
                    acc.darea -= g * fa * s;
                    acc.dload -= g * fp * s;
                }
            }
        }
        acc
    }

    /// xorshift64: reproducible uniform numbers in [0, 1).
    struct Uniform(u64);

    impl Uniform {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    /// c uniform in ln c over the table.
    fn random_c(rng: &mut Uniform) -> f64 {
        (C_RANGE.0.ln() + (C_RANGE.1 / C_RANGE.0).ln() * rng.next()).exp()
    }

    #[test]
    fn matches_independent_quadrature_on_random_samples() {
        let table = GwTable::for_k(K);
        let mut rng = Uniform(0x9e37_79b9_7f4a_7c15);
        let (mut values, mut slopes) = (0.0f64, 0.0f64);
        for i in 0..10_000 {
            // every fourth sample in the plastic transitions c ≤ −h ≤ 54c, where the kinks of the law
            // pass through the Gaussian window
            let c = random_c(&mut rng);
            let h = if i % 4 == 0 {
                -(c + (53.0 * c).min(10.0) * rng.next()).min(-H_MIN)
            } else {
                H_MIN + (36.0 - H_MIN) * rng.next()
            };
            let q = table.stencil(c).unwrap().integrals(h).unwrap();
            let r = reference(h, c, K);
            values = values.max(rel(q.load, r.load)).max(rel(q.area, r.area));
            slopes = slopes.max(rel(q.dload, r.dload)).max(rel(q.darea, r.darea));
            assert!(
                values <= 1e-9 && slopes <= 1e-8,
                "h = {h}, c = {c}: {q:?} vs {r:?}"
            );
        }
        println!("worst relative error: values {values:.1e}, h-derivatives {slopes:.1e}");
    }

    #[test]
    fn elastic_limit_gives_the_reference_integrals() {
        // c = 10: every asperity in the Gaussian window is elastic for h ≥ −2, 𝒜 = F1, 𝒫 = (4/3)·F_1.5
        let stencil = GwTable::for_k(K).stencil(10.0).unwrap();
        // docs/model.md §4: F1.5 at h = 0..3
        for (h, f15) in [
            (0.0, 0.43002),
            (1.0, 0.075668),
            (2.0, 6.6482e-3),
            (3.0, 2.6397e-4),
        ] {
            let q = stencil.integrals(h).unwrap();
            assert!(rel(q.load, 4.0 / 3.0 * f15) < 1e-4, "h = {h}: {}", q.load);
        }
        // closed forms F1(h) = φ0(h) − h·F0(h), dF1/dh = −F0(h)
        for i in 0..=320 {
            let h = -2.0 + i as f64 * 0.1 + 1e-3;
            let q = stencil.integrals(h).unwrap();
            assert!(rel(q.area, f1(h)) < 1e-9, "h = {h}");
            assert!(rel(q.darea, -upper_tail(h)) < 1e-8, "h = {h}");
        }
    }

    #[test]
    fn derivatives_are_those_of_the_interpolant() {
        let table = GwTable::for_k(K);
        let mut rng = Uniform(7);
        let eps = 1e-4;
        for _ in 0..2000 {
            let c = random_c(&mut rng);
            // up to h = 36, where 𝒫 ≈ 1e−285 (near H_ZERO the results underflow to subnormal numbers)
            let h = H_MIN + eps + (36.0 - H_MIN) * rng.next();
            let s = table.stencil(c).unwrap();
            let (q, up, dn) = (
                s.integrals(h).unwrap(),
                s.integrals(h + eps).unwrap(),
                s.integrals(h - eps).unwrap(),
            );
            // central differences of ln 𝒫, ln 𝒜 (error ≈ eps²/6·(ln 𝒫)''' plus rounding ≈ 1e−9)
            let fd_load = (up.load.ln() - dn.load.ln()) / (2.0 * eps);
            let fd_area = (up.area.ln() - dn.area.ln()) / (2.0 * eps);
            assert!(rel(q.dload / q.load, fd_load) < 1e-7, "h = {h}, c = {c}");
            assert!(rel(q.darea / q.area, fd_area) < 1e-7, "h = {h}, c = {c}");
            assert!(q.dload < 0.0 && q.darea < 0.0);
        }
    }

    #[test]
    fn continuous_across_grid_lines() {
        let table = GwTable::for_k(K);
        let close = |a: Integrals, b: Integrals, tol: f64| {
            rel(a.load, b.load) < tol
                && rel(a.area, b.area) < tol
                && rel(a.dload, b.dload) < tol
                && rel(a.darea, b.darea) < tol
        };
        // rows in h: value and slope continuous (the quintic Hermite interpolant is C²)
        let s = table.stencil(0.9).unwrap();
        for j in 1..((36.0 - H_MIN) / H_STEP) as usize {
            let h = H_MIN + j as f64 * H_STEP;
            let (a, b) = (
                s.integrals(h - 1e-12).unwrap(),
                s.integrals(h + 1e-12).unwrap(),
            );
            assert!(close(a, b, 1e-10), "h = {h}: {a:?} vs {b:?}");
        }
        // columns in c: the stencil moves by one column, both interpolate the same column value there
        for i in (BELOW + 1..table.blocks.len() / BLOCKS - ORDER + BELOW).step_by(7) {
            let c = (table.ln_c0 + i as f64 * LN_C_STEP).exp();
            let (lo, hi) = (
                table.stencil(c * (1.0 - 1e-13)).unwrap(),
                table.stencil(c * (1.0 + 1e-13)).unwrap(),
            );
            for h in [-9.3, -4.1, 0.7, 6.2, 21.0] {
                let (a, b) = (lo.integrals(h).unwrap(), hi.integrals(h).unwrap());
                assert!(close(a, b, 1e-10), "c = {c}, h = {h}: {a:?} vs {b:?}");
            }
        }
    }

    #[test]
    fn outside_the_table_is_none() {
        let table = GwTable::for_k(K);
        for c in [
            0.99 * C_RANGE.0,
            1.01 * C_RANGE.1,
            f64::NAN,
            f64::INFINITY,
            0.0,
        ] {
            assert!(table.stencil(c).is_none(), "c = {c}");
        }
        let s = table.stencil(1.0).unwrap();
        for h in [H_MIN - 1e-9, H_ZERO, 50.0, f64::NAN, f64::NEG_INFINITY] {
            assert!(s.integrals(h).is_none(), "h = {h}");
        }
        assert!(s.integrals(H_MIN).is_some() && s.integrals(H_ZERO - 1e-9).is_some());
    }

    #[test]
    fn one_table_per_k() {
        let (a, b) = (GwTable::for_k(K), GwTable::for_k(K));
        assert!(std::ptr::eq(a, b));
        let other = GwTable::for_k(zmc_k_of(0.3));
        assert!(!std::ptr::eq(a, other) && other.k() == zmc_k_of(0.3));
        // the other K's integrals differ (plastic load ∝ 1/K)
        let (p, q) = (
            a.stencil(0.05).unwrap().integrals(-1.0).unwrap(),
            other.stencil(0.05).unwrap().integrals(-1.0).unwrap(),
        );
        assert!(rel(p.load, q.load) > 1e-3 && rel(p.area, q.area) < 1e-12);
        let r = reference(-1.0, 0.05, zmc_k_of(0.3));
        assert!(rel(q.load, r.load) < 1e-9);
    }

    fn zmc_k_of(poisson: f64) -> f64 {
        super::super::zmc_k(poisson)
    }
}
