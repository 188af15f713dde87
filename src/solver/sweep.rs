//! Sweeps: sequences of nearby operating points solved with continuation.

use super::coupled::solve_from;
use super::solution::Solution;
use super::warm::WarmStart;
use crate::error::Result;
use crate::params::{OperatingPoint, Params};

/// Number of warm-started chains a sweep is cut into (fixed, so that the results do not depend on the
/// thread count).
const SWEEP_CHAINS: usize = 8;

/// Solves a sequence of nearby operating points (a traction–creepage sweep, a line of a table) with
/// continuation: each point starts from its predecessor's solution ([`solve_from`]). The sequence is cut
/// into at most 8 contiguous chains solved in parallel (rayon); the first point of a chain, and a point
/// after a failed one, start cold. The cut does not depend on the thread count, so neither do the results.
pub fn solve_sweep(params: &Params, points: &[OperatingPoint]) -> Vec<Result<Solution>> {
    use rayon::prelude::*;
    let chain = points.len().div_ceil(SWEEP_CHAINS).max(1);
    points
        .par_chunks(chain)
        .flat_map_iter(|chunk| {
            let mut prev: Option<WarmStart> = None;
            chunk
                .iter()
                .map(|pt| {
                    let r = solve_from(params, pt, prev.as_ref());
                    prev = r.as_ref().ok().and_then(Solution::warm_start);
                    r
                })
                .collect::<Vec<_>>()
        })
        .collect()
}
