//! The flags of a table's cells, computed at loading: cells that hold a jump of the model (unresolved),
//! cells whose stencil holds an unconverged point, and cells beside an unresolved one along ξ̂ or η̂.

use super::JUMP_SPREAD;
use super::axes::{DIMS, ETA, PHI, XI};
use super::file::FilmIntake;
use super::interp::AxisInterp;

/// Flag of a cell holding a jump of the model ([`unresolved_cells`]).
pub(super) const UNRESOLVED: u8 = 1;
/// Flag of a cell whose stencil holds an unconverged point ([`near_unconverged`]).
pub(super) const NEAR_UNCONVERGED: u8 = 2;
/// Flags of a cell whose neighbour cell below and above it along ξ̂ (first pair) and η̂ (second) holds a
/// jump of the model ([`beside_unresolved`]).
pub(super) const BESIDE_UNRESOLVED: [[u8; 2]; 2] = [[4, 8], [16, 32]];
/// Any of the ξ̂, resp. η̂, flags of [`BESIDE_UNRESOLVED`].
pub(super) const BESIDE_XI: u8 = BESIDE_UNRESOLVED[0][0] | BESIDE_UNRESOLVED[0][1];
pub(super) const BESIDE_ETA: u8 = BESIDE_UNRESOLVED[1][0] | BESIDE_UNRESOLVED[1][1];

/// Sets in `flags` (per point of a table of `shape`, C order: the flags of the cell whose lowest corner it
/// is) the [`BESIDE_UNRESOLVED`] flags of every cell whose neighbour along ξ̂ or η̂ is [`UNRESOLVED`]: its
/// spline along that axis takes the one-sided slope at their shared node (`core`).
pub(super) fn beside_unresolved(shape: &[usize; DIMS], flags: &mut [u8]) {
    if flags.iter().all(|f| f & UNRESOLVED == 0) {
        return;
    }
    for (axis, [below, above]) in [XI, ETA].into_iter().zip(BESIDE_UNRESOLVED) {
        let stride: usize = shape[axis + 1..].iter().product();
        let n = shape[axis];
        // blocks of the slower axes; in each, node k along the axis, then the faster axes (as
        // `near_unconverged`, without a division per point)
        for block in flags.chunks_exact_mut(n * stride) {
            for k in 0..n {
                for i in k * stride..(k + 1) * stride {
                    if k >= 1 && block[i - stride] & UNRESOLVED != 0 {
                        block[i] |= below;
                    }
                    if k + 2 < n && block[i + stride] & UNRESOLVED != 0 {
                        block[i] |= above;
                    }
                }
            }
        }
    }
}

/// Per point of a table of `shape` (C order), 1 where the cell whose lowest corner it is holds a jump of
/// the model that no interpolation follows ([`TableOutput::resolved`]): the stored T_max `t` [K] at the
/// cell's corners (two nodes along every axis of more than one point) spreads by more than
/// [`JUMP_SPREAD`], or its corners' film-intake codes `film` ([`FilmIntake`], if recorded) hold both a wet
/// contact that takes in all its film and one that the metal partly covers: the cell straddles the onset
/// of the walls, across which a wet contact's friction rises by up to ~0.03·F_N within 1 % of p0
/// (docs/model.md §8.5, §12.3). Dry corners straddle nothing (the walls change no dry contact).
pub(super) fn unresolved_cells(shape: &[usize; DIMS], t: &[f32], film: Option<&[u8]>) -> Vec<u8> {
    let hi = over_cells(shape, t.to_vec(), f32::max);
    let lo = over_cells(shape, t.to_vec(), f32::min);
    // per cell, the codes present at its corners as bits 1 << code
    let codes = film.map(|f| over_cells(shape, f.iter().map(|c| 1u8 << c).collect(), |a, b| a | b));
    let straddle = (1 << FilmIntake::All as u8) | (1 << FilmIntake::Limited as u8);
    (0..t.len())
        .map(|i| {
            let jump = f64::from(hi[i]) - f64::from(lo[i]) > JUMP_SPREAD;
            let onset = codes.as_ref().is_some_and(|c| c[i] & straddle == straddle);
            u8::from(jump || onset)
        })
        .collect()
}

/// Per point of a table of `shape` (C order): 1 where an evaluation in the cell whose lowest corner it is may
/// read a point that did not converge (`converged` ≠ 1): one pass per axis, each combining a point's
/// stencil along the axis ([`AxisInterp::stencil`]; along φ̂ the rows at the interval's ends and, for the
/// ghost η̂ points, their mirror images, see `core`), so the cell's flag covers the product of the stencils.
pub(super) fn near_unconverged(
    shape: &[usize; DIMS],
    converged: &[u8],
    interp: &[AxisInterp; DIMS],
) -> Vec<u8> {
    let mut v: Vec<u8> = converged.iter().map(|c| u8::from(*c != 1)).collect();
    for d in 0..DIMS {
        let n = shape[d];
        let stencils: Vec<Vec<usize>> = (0..n)
            .map(|x| {
                if d == PHI && x + 1 < n {
                    vec![x, x + 1, n - 2 - x, n - 1 - x]
                } else {
                    interp[d].stencil(x)
                }
            })
            .collect();
        let stride: usize = shape[d + 1..].iter().product();
        let previous = v.clone();
        // blocks of the slower axes; in each, point x along the axis, then the faster axes
        for (block, out) in previous
            .chunks_exact(n * stride)
            .zip(v.chunks_exact_mut(n * stride))
        {
            for (x, row) in out.chunks_exact_mut(stride).enumerate() {
                for (inner, u) in row.iter_mut().enumerate() {
                    *u = stencils[x]
                        .iter()
                        .fold(0, |a, k| a | block[k * stride + inner]);
                }
            }
        }
    }
    v
}

/// Per point of a table of `shape` (C order), `v` combined by `f` (associative and commutative: max, min,
/// or) over the corners of the cell whose lowest corner it is: one pass per axis, each combining a node
/// with its successor.
pub(super) fn over_cells<T: Copy>(
    shape: &[usize; DIMS],
    mut v: Vec<T>,
    f: impl Fn(T, T) -> T,
) -> Vec<T> {
    for d in 0..DIMS {
        let stride: usize = shape[d + 1..].iter().product();
        // ascending: the successor still holds the previous pass's value when a node reads it
        for i in 0..v.len() {
            if (i / stride) % shape[d] + 1 < shape[d] {
                v[i] = f(v[i], v[i + stride]);
            }
        }
    }
    v
}
