//! The lookup kernels: CPU detection, the dispatch to the kernel compiled for the CPU's instruction set, and
//! the φ̂ stage's corner sums (portable, AVX2 + FMA, AVX-512).

use super::coords::Ellipse;
use super::file::OUTPUTS;
use super::layout::{ROW, Row};
use super::{Jacobian, Table, TableOutput};
use crate::error::Result;
use crate::params::OperatingPoint;

/// The instruction set of the lookup kernel: one source compiled three times, chosen once per table by the
/// CPU it runs on. The vector kernels also fuse the corner sums' multiply-adds (one rounding instead of
/// two), so their results differ from the portable kernel's in the last bits only; the AVX-512 kernel's
/// are the AVX2 kernel's bit for bit (lane for lane the same operations in the same order).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kernel {
    /// Baseline instructions of the target (SSE2 on x86_64).
    Portable,
    /// AVX2 and FMA (x86_64, every x86_64 CPU since about 2015).
    Avx2Fma,
    /// AVX-512F besides AVX2 and FMA: the corner sums of a ξ̂ node's four η̂ window points at once, 8-wide
    /// ([`window_sums`]). [`Kernel::detect`] chooses it on AMD CPUs only: their cores with AVX-512 (Zen 4
    /// and later) run 512-bit instructions at the full clock, while several Intel server generations
    /// lower the clock of the whole core for 512-bit fused multiply-adds, which would slow the host
    /// simulation running on that core ([`Table::set_kernel`] chooses it anywhere).
    Avx512,
}

/// The kernels as the const parameter of the lookup's functions (`Table::eval`).
pub(super) const PORTABLE: u8 = 0;
const AVX2: u8 = 1;
const AVX512: u8 = 2;

impl Kernel {
    /// Every kernel, slowest first.
    pub const ALL: [Kernel; 3] = [Kernel::Portable, Kernel::Avx2Fma, Kernel::Avx512];

    /// Whether this CPU runs the kernel.
    pub fn supported(self) -> bool {
        match self {
            Kernel::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2Fma => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx512 => Kernel::Avx2Fma.supported() && is_x86_feature_detected!("avx512f"),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The fastest kernel this CPU runs, AVX-512 on AMD CPUs only ([`Kernel::Avx512`]).
    pub fn detect() -> Kernel {
        Kernel::ALL
            .into_iter()
            .rev()
            .find(|k| k.supported() && (*k != Kernel::Avx512 || amd()))
            .unwrap_or(Kernel::Portable)
    }
}

/// Whether the CPU is AMD's (CPUID vendor string "AuthenticAMD").
pub(super) fn amd() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        let id = std::arch::x86_64::__cpuid(0);
        let vendor = [id.ebx, id.edx, id.ecx].map(u32::to_le_bytes);
        vendor.as_flattened() == b"AuthenticAMD"
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
}

impl Table {
    /// [`Table::eval`] compiled for the table's kernel.
    pub(super) fn dispatch<const JAC: bool>(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
        geometry: [f64; 2],
    ) -> Result<(TableOutput, Jacobian)> {
        match self.kernel {
            Kernel::Portable => self.eval::<JAC, PORTABLE>(point, e, geometry),
            // SAFETY: a table holds a vector kernel only if the CPU has its instructions
            // (`Kernel::supported`, checked by `detect` and `set_kernel`)
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx2Fma => unsafe { self.eval_avx2::<JAC>(point, e, geometry) },
            #[cfg(target_arch = "x86_64")]
            Kernel::Avx512 => unsafe { self.eval_avx512::<JAC>(point, e, geometry) },
            #[cfg(not(target_arch = "x86_64"))]
            _ => self.eval::<JAC, PORTABLE>(point, e, geometry),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    pub(super) fn eval_avx2<const JAC: bool>(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
        geometry: [f64; 2],
    ) -> Result<(TableOutput, Jacobian)> {
        self.eval::<JAC, AVX2>(point, e, geometry)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx2,fma")]
    pub(super) fn eval_avx512<const JAC: bool>(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
        geometry: [f64; 2],
    ) -> Result<(TableOutput, Jacobian)> {
        self.eval::<JAC, AVX512>(point, e, geometry)
    }
}

/// The Hermite weights along φ̂ of a window point: `ends`, per lane of a 4-wide vector of a row (values of
/// two outputs, then their slopes, the row layout `VAL`, `SLOPE`), for the lower and the upper row of a
/// corner's pair in memory; and the point's symmetry signs per vector k of a row ([`SIGN_LANES`]). The
/// weight of a lane is their product (exact: the signs are ±1).
#[derive(Clone, Copy)]
pub(super) struct Hermite<'a> {
    pub(super) ends: &'a [[f64; 4]; 2],
    pub(super) signs: &'a [[f64; 4]; 3],
}

/// The Hermite stage of one window point from the corner sums of its row pair (`pair`: lower row, upper
/// row): per output o, (value and slope terms of lane o) summed as the vector kernel sums them.
#[inline(always)]
pub(super) fn hermite_of(pair: &[f64; 2 * ROW], h: Hermite) -> [f64; OUTPUTS] {
    std::array::from_fn(|o| {
        let (k, l) = (o / 2, o % 2);
        let lane = |l: usize| {
            let s = h.signs[k][l];
            h.ends[0][l] * s * pair[4 * k + l] + h.ends[1][l] * s * pair[ROW + 4 * k + l]
        };
        lane(l) + lane(l + 2)
    })
}

/// One window point's values after the φ̂ stage: Σ_c w_c·(row, next row) over the linear corners, the rows
/// `base + off[c]` and the one after it (the upper φ̂ node) of `rows`, widened to f64 and accumulated in
/// f64, then the Hermite weights `h` ([`hermite_of`]); the corner sums themselves are left in `pair` if
/// `PAIR`. FMA kernels use 4-wide conversions and fused multiply-adds (the kernels then differ in the last
/// bits only). `max_off` is the largest of `off` (the caller's invariant): the rows are checked to lie in
/// `rows` once per call; rows out of bounds give NaN, never a read outside `rows`.
#[inline(always)]
pub(super) fn corner_sum<const K: u8, const PAIR: bool>(
    rows: &[Row],
    base: usize,
    off: &[usize],
    max_off: usize,
    w: &[f64],
    h: Hermite,
    pair: &mut [f64; 2 * ROW],
) -> [f64; OUTPUTS] {
    let n = off.len().min(w.len());
    debug_assert!(off.iter().all(|o| *o <= max_off));
    if base + max_off + 2 > rows.len() {
        *pair = [f64::NAN; 2 * ROW];
        return [f64::NAN; OUTPUTS];
    }
    #[cfg(target_arch = "x86_64")]
    if K != PORTABLE {
        // SAFETY: FMA kernels run only on CPUs with AVX2 and FMA (`Kernel::supported`); every pair of rows
        // base + off[c], base + off[c] + 1 lies in `rows` (checked above)
        return unsafe { corner_sum_avx2::<PAIR>(rows, base, &off[..n], w, h, pair) };
    }
    *pair = [0.0; 2 * ROW];
    for c in 0..n {
        let s = base + off[c];
        for (e, r) in rows[s..s + 2].iter().enumerate() {
            for k in 0..ROW {
                pair[e * ROW + k] += w[c] * f64::from(r.0[k]);
            }
        }
    }
    hermite_of(pair, h)
}

/// [`corner_sum`] at the four η̂ window points of a ξ̂ node, whose first rows are `bases` (the same linear
/// corners `off`, weights `w` and `max_off` for all) and Hermite weights `hs`. The AVX-512 kernel sums the
/// four at once ([`window_sums_avx512`]), the others one after the other. Measured (criterion, AMD Zen 5,
/// the whole-range table's nodes, a wet lookup with a new ellipse every time): AVX2 one point at a time
/// 544–552 ns, AVX-512 four at once 485–496 ns; one point at a time with AVX-512 was no faster than AVX2 —
/// a point's twelve corners are a chain of fused multiply-adds into the same sums, whose latency the
/// four points' independent sums hide. With AVX2, two points at once (their twelve sums in the sixteen
/// registers) was slower (485–496 → 521–535 ns per library evaluation on the fixture table) and the four
/// in two passes (lower rows, then upper rows) no faster: the 4-wide sums are bound by their conversions.
#[inline(always)]
pub(super) fn window_sums<const K: u8>(
    rows: &[Row],
    bases: &[usize; 4],
    off: &[usize],
    max_off: usize,
    w: &[f64],
    hs: &[Hermite; 4],
) -> [[f64; OUTPUTS]; 4] {
    #[cfg(target_arch = "x86_64")]
    if K == AVX512 && bases.iter().all(|b| b + max_off + 2 <= rows.len()) {
        let n = off.len().min(w.len());
        // SAFETY: AVX-512 kernels run only on CPUs with AVX-512F (`Kernel::supported`); every pair of
        // rows base + off[c], base + off[c] + 1 lies in `rows` (checked above)
        return unsafe { window_sums_avx512(rows, bases, &off[..n], w, hs) };
    }
    let mut out = [[0.0; OUTPUTS]; 4];
    let mut pair = [0.0; 2 * ROW];
    for j in 0..4 {
        out[j] = corner_sum::<K, false>(rows, bases[j], off, max_off, w, hs[j], &mut pair);
    }
    out
}

/// [`window_sums`] with AVX-512F: per corner, its weight times each point's pair of rows (three 8-wide
/// f32 loads, conversions to f64 and fused multiply-adds per point: twelve independent sums); then the
/// Hermite stage per point ([`hermite_avx2`]). Lane for lane the operations of [`corner_sum_avx2`] in the
/// same order: the values are that kernel's bit for bit.
///
/// # Safety
/// Every pair of rows `bases[j] + off[c]`, `bases[j] + off[c] + 1` must lie in `rows`, and `w` hold at
/// least `off.len()` weights; the CPU must have AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx2,fma")]
pub(super) unsafe fn window_sums_avx512(
    rows: &[Row],
    bases: &[usize; 4],
    off: &[usize],
    w: &[f64],
    hs: &[Hermite; 4],
) -> [[f64; OUTPUTS]; 4] {
    use std::arch::x86_64::{
        _mm256_loadu_ps, _mm512_castpd512_pd256, _mm512_cvtps_pd, _mm512_extractf64x4_pd,
        _mm512_fmadd_pd, _mm512_set1_pd, _mm512_setzero_pd,
    };
    const { assert!(ROW == 12) };
    let mut v = [[_mm512_setzero_pd(); 3]; 4];
    let p = rows.as_ptr();
    for (c, o) in off.iter().enumerate() {
        // SAFETY: the caller guarantees c < w.len()
        let wc = _mm512_set1_pd(unsafe { *w.get_unchecked(c) });
        for (vj, b) in v.iter_mut().zip(bases) {
            // SAFETY: the caller guarantees that the rows lie in `rows`
            let r = unsafe { p.add(b + o).cast::<f32>() };
            for (k, x) in vj.iter_mut().enumerate() {
                // SAFETY: values 8k .. 8k + 8 of the two rows
                let row = unsafe { _mm512_cvtps_pd(_mm256_loadu_ps(r.add(8 * k))) };
                *x = _mm512_fmadd_pd(wc, row, *x);
            }
        }
    }
    let mut out = [[0.0; OUTPUTS]; 4];
    let mut pair = [0.0; 2 * ROW];
    for j in 0..4 {
        let quads = [
            _mm512_castpd512_pd256(v[j][0]),
            _mm512_extractf64x4_pd::<1>(v[j][0]),
            _mm512_castpd512_pd256(v[j][1]),
            _mm512_extractf64x4_pd::<1>(v[j][1]),
            _mm512_castpd512_pd256(v[j][2]),
            _mm512_extractf64x4_pd::<1>(v[j][2]),
        ];
        out[j] = hermite_avx2::<false>(quads, hs[j], &mut pair);
    }
    out
}

/// [`corner_sum`] with AVX2 and FMA: a pair of rows as six aligned 4-wide f32 loads, conversions to f64
/// and fused multiply-adds, then the Hermite stage ([`hermite_avx2`]).
///
/// # Safety
/// Every pair of rows `base + off[c]`, `base + off[c] + 1` must lie in `rows`, and `w` hold at least
/// `off.len()` weights.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn corner_sum_avx2<const PAIR: bool>(
    rows: &[Row],
    base: usize,
    off: &[usize],
    w: &[f64],
    h: Hermite,
    pair: &mut [f64; 2 * ROW],
) -> [f64; OUTPUTS] {
    use std::arch::x86_64::{
        _mm_load_ps, _mm256_cvtps_pd, _mm256_fmadd_pd, _mm256_set1_pd, _mm256_setzero_pd,
    };
    const { assert!(ROW == 12) };
    let mut v = [_mm256_setzero_pd(); 6];
    let p = rows.as_ptr();
    for (c, o) in off.iter().enumerate() {
        // SAFETY: the caller guarantees c < w.len() and that the rows lie in `rows`
        let (wc, r) = unsafe {
            (
                _mm256_set1_pd(*w.get_unchecked(c)),
                p.add(base + o).cast::<f32>(),
            )
        };
        for (k, x) in v.iter_mut().enumerate() {
            // SAFETY: values 4k .. 4k + 4 of the two rows, 16-byte aligned (`Row`)
            let row = unsafe { _mm256_cvtps_pd(_mm_load_ps(r.add(4 * k))) };
            *x = _mm256_fmadd_pd(wc, row, *x);
        }
    }
    hermite_avx2::<PAIR>(v, h, pair)
}

/// The Hermite stage on the six 4-wide corner sums `v` of a pair of rows, in registers: per output, the
/// value and slope lanes of both rows times their Hermite weights and signs ([`Hermite`]); the sums are
/// left in `pair` if `PAIR`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline]
pub(super) fn hermite_avx2<const PAIR: bool>(
    v: [std::arch::x86_64::__m256d; 6],
    h: Hermite,
    pair: &mut [f64; 2 * ROW],
) -> [f64; OUTPUTS] {
    use std::arch::x86_64::{
        _mm_add_pd, _mm_storeu_pd, _mm256_castpd256_pd128, _mm256_extractf128_pd, _mm256_fmadd_pd,
        _mm256_loadu_pd, _mm256_mul_pd, _mm256_storeu_pd,
    };
    if PAIR {
        for (k, x) in v.iter().enumerate() {
            // SAFETY: `pair` holds 24 values: the store writes 4k..4k + 4
            unsafe { _mm256_storeu_pd(pair.as_mut_ptr().add(4 * k), *x) };
        }
    }
    let mut out = [0.0; OUTPUTS];
    // SAFETY: the weights are 4 values each
    let (lo, hi) = unsafe {
        (
            _mm256_loadu_pd(h.ends[0].as_ptr()),
            _mm256_loadu_pd(h.ends[1].as_ptr()),
        )
    };
    for k in 0..3 {
        // SAFETY: the signs are 4 values each; `out` holds 6 values, the store writes 2k..2k + 2
        unsafe {
            let s = _mm256_loadu_pd(h.signs[k].as_ptr());
            let t = _mm256_mul_pd(v[k], _mm256_mul_pd(lo, s));
            let t = _mm256_fmadd_pd(v[k + 3], _mm256_mul_pd(hi, s), t);
            let s = _mm_add_pd(_mm256_castpd256_pd128(t), _mm256_extractf128_pd::<1>(t));
            _mm_storeu_pd(out.as_mut_ptr().add(2 * k), s);
        }
    }
    out
}
