//! The rows of a table in memory: what a stored point holds and where, the memory order of the points, and
//! the padding of the ξ̂ slabs against L1 cache-set conflicts.

use super::axes::{DIMS, ETA, FORCE, LINEAR_DIMS, PHI, XI};
use super::file::OUTPUTS;
use super::interp::{Fraction, Offsets};

/// Values per stored point in memory: the outputs and their slopes along φ (three 4-wide vectors).
pub(super) const ROW: usize = 2 * OUTPUTS;

/// One stored point in memory: the values at the positions `VAL` and `SLOPE`, in the stored precision,
/// 16-byte aligned so that no 4-wide load crosses a cache line.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(16))]
pub(super) struct Row(pub(super) [f32; ROW]);

const _: () = assert!(std::mem::size_of::<Row>() == ROW * 4);

/// Tables whose rows take more memory than this are prefetched during a lookup (a smaller table stays in
/// the caches, where prefetches are pure overhead), by a lookup in another cell than the thread's previous
/// one ([`LAST_CELL`]) [bytes].
pub(super) const PREFETCH_ABOVE: usize = 8 << 20;

thread_local! {
    /// The rows (by [`rows_id`]) and the cell of this thread's last lookup in a table that prefetches.
    pub(super) static LAST_CELL: std::cell::Cell<(usize, usize)> = const { std::cell::Cell::new((0, usize::MAX)) };
}

/// An identity of a table's rows while they live: their address. (A table allocated where a dropped one
/// was may find the dropped one's last cell: one lookup then skips its prefetches, which only hint.)
pub(super) fn rows_id(rows: &[Row]) -> usize {
    rows.as_ptr() as usize
}

/// Positions in a row of output o's value and of its φ slope: values and slopes of outputs 0–1, 2–3 and 4–5
/// alternate in pairs. So the pairs a 16-byte vector holds are both values or both slopes, which keeps the
/// Hermite stage in registers.
pub(super) const VAL: [usize; OUTPUTS] = [0, 1, 4, 5, 8, 9];
pub(super) const SLOPE: [usize; OUTPUTS] = [2, 3, 6, 7, 10, 11];

/// The row strides of a table of `shape` in memory order: C order over (ξ̂, η̂, F_N, V, w, a/b, p_ref, φ̂).
pub(super) fn memory_strides(shape: &[usize; DIMS]) -> [usize; DIMS] {
    let mut strides = unpadded_strides(shape);
    strides[XI] += slab_padding(shape, &strides);
    strides
}

/// [`memory_strides`] without the padding of the ξ̂ slabs: the points contiguous.
pub(super) fn unpadded_strides(shape: &[usize; DIMS]) -> [usize; DIMS] {
    let mut strides = [1usize; DIMS];
    let mut s = shape[PHI];
    for d in (0..DIMS).rev().filter(|d| *d != PHI) {
        strides[d] = s;
        s *= shape[d];
    }
    strides
}

/// Sets of an L1 data cache: 64 (of 64-byte lines), the set index the address modulo 4 KB, on every
/// x86-64 CPU and most others (a virtually indexed cache of 4 KB pages).
const L1_SETS: usize = 64;
/// Ways of the smallest common L1 data cache (8: 32 KB; 12 in 48 KB ones).
const L1_WAYS: usize = 8;
/// Bytes per cache line.
pub(super) const LINE: usize = 64;

/// The rows of padding after each ξ̂ slab of a table of `shape` with unpadded `strides` (memory order): the
/// whole fibres along φ̂, at most 63 and a sixteenth of a slab, that leave the fewest of a lookup's lines
/// beyond the ways of an L1 set ([`l1_crowding`]), the fewest of those. Why: a stride that is a multiple of
/// 4 KB maps the four ξ̂ window nodes of every row to the same set. The whole-range table's ξ̂ slab is
/// 1 488 384 rows of 48 bytes, exactly 17 442 pages, so its stencil of ≈ 430 lines put up to 20 in one set
/// (≈ 180 lines per lookup beyond 8 ways); 16 fibres of padding (0.02 % more memory) leave none beyond
/// (at most 8 per set), and the same wet lookup took 510 instead of 540 ns.
pub(super) fn slab_padding(shape: &[usize; DIMS], strides: &[usize; DIMS]) -> usize {
    let fibre = shape[PHI];
    let most = (strides[XI] / (16 * fibre)).min(63);
    let crowding = |k: usize| {
        let mut padded = *strides;
        padded[XI] += k * fibre;
        l1_crowding(shape, &padded)
    };
    let best = (0..=most).min_by_key(|k| (crowding(*k), *k)).unwrap_or(0);
    best * fibre
}

/// How many of the cache lines a lookup reads lie beyond [`L1_WAYS`] in their L1 set, summed over a few
/// lookups into a table of `shape` laid out by `strides` from a page boundary: the 4 × 4 (ξ̂, η̂) window,
/// both φ̂ ends and the linear corners of a cell with distinct fractions (two orders of the simplex), at
/// the first two φ̂ nodes (rows shift the lines by 48 bytes per node).
pub(super) fn l1_crowding(shape: &[usize; DIMS], strides: &[usize; DIMS]) -> usize {
    const L: usize = LINEAR_DIMS;
    let linear_strides: [usize; L] = std::array::from_fn(|k| strides[FORCE + k]);
    let row = std::mem::size_of::<Row>();
    let mut crowding = 0;
    for t in [[0.7, 0.5, 0.5, 0.6, 0.4], [0.4, 0.5, 0.5, 0.6, 0.7]] {
        let fractions: [Fraction; L] = std::array::from_fn(|k| Fraction {
            start: 0,
            t: t[k],
            inv_h: if shape[FORCE + k] > 1 { 1.0 } else { 0.0 },
        });
        let stencil = Offsets::of(&fractions, &linear_strides);
        for phi in 0..shape[PHI].min(2) {
            let mut lines = Vec::new();
            for i in 0..shape[XI].min(4) {
                for j in 0..shape[ETA].min(4) {
                    for o in &stencil.off[..stencil.n] {
                        let first = i * strides[XI] + j * strides[ETA] + o + phi;
                        lines.extend(first * row / LINE..=((first + 2) * row - 1) / LINE);
                    }
                }
            }
            lines.sort_unstable();
            lines.dedup();
            let mut per_set = [0usize; L1_SETS];
            for l in lines {
                per_set[l % L1_SETS] += 1;
            }
            crowding += per_set
                .iter()
                .map(|n| n.saturating_sub(L1_WAYS))
                .sum::<usize>();
        }
    }
    crowding
}

/// The memory index of the point with flat (C-order, the files') index `flat` in a table of `shape`.
pub(super) fn memory_index(shape: &[usize; DIMS], strides: &[usize; DIMS], flat: usize) -> usize {
    let mut rest = flat;
    let mut m = 0;
    for d in (0..DIMS).rev() {
        m += (rest % shape[d]) * strides[d];
        rest /= shape[d];
    }
    m
}
