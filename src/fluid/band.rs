//! Band matrix with an in-place LU factorisation for the film Newton step.
//!
//! The film Jacobian couples each cell with its four face neighbours; with the cells ordered strip by strip
//! its nonzeros lie within one strip length of the diagonal. The pattern is symmetric, so Gaussian
//! elimination without pivoting keeps the fill inside the envelope: row i only has entries from column
//! first(i) = min(i, neighbours of i) on, and column j only from row first(j) on (Golub & Van Loan,
//! Matrix Computations, 4th ed., §4.3). Elimination without pivoting is stable for column diagonally dominant
//! matrices (ibid. §3.4.10), which the film Jacobian nearly is (conservative fluxes); a zero or non-finite
//! pivot is reported, and the caller falls back to a different iteration.

/// Square matrix whose nonzeros lie in the envelope of a symmetric sparsity pattern, stored densely over
/// the band |i − j| ≤ w, row by row.
#[derive(Debug, Clone)]
pub(crate) struct Band {
    n: usize,
    w: usize,
    /// Column of the first entry of each row (= row of the first entry of each column).
    first: Vec<usize>,
    /// reach[k]: the last row (and column) that elimination step k touches.
    reach: Vec<usize>,
    a: Vec<f64>,
}

impl Band {
    /// Zero matrix with the envelope of the symmetric pattern given by each row's off-diagonal columns.
    pub(crate) fn new<R: IntoIterator<Item = usize>>(rows: impl Iterator<Item = R>) -> Self {
        let first: Vec<usize> = rows
            .enumerate()
            .map(|(i, nb)| nb.into_iter().fold(i, usize::min))
            .collect();
        let n = first.len();
        let w = first
            .iter()
            .enumerate()
            .map(|(i, f)| i - f)
            .max()
            .unwrap_or(0);
        // reach[k] = max{i : first(i) ≤ k}, at least k
        let mut reach: Vec<usize> = (0..n).collect();
        for (i, f) in first.iter().enumerate() {
            reach[*f] = reach[*f].max(i);
        }
        for k in 1..n {
            reach[k] = reach[k].max(reach[k - 1]);
        }
        Self {
            n,
            w,
            first,
            reach,
            a: vec![0.0; n * (2 * w + 1)],
        }
    }

    fn idx(&self, i: usize, j: usize) -> usize {
        i * (2 * self.w + 1) + j + self.w - i
    }

    /// Sets all entries to zero.
    pub(crate) fn clear(&mut self) {
        self.a.fill(0.0);
    }

    /// Adds `v` to entry (i, j), which must lie in the envelope.
    pub(crate) fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(j >= self.first[i] && i >= self.first[j]);
        let k = self.idx(i, j);
        self.a[k] += v;
    }

    /// A·x for the matrix as stored (before factorisation).
    #[cfg(test)]
    pub(crate) fn mul(&self, x: &[f64]) -> Vec<f64> {
        (0..self.n)
            .map(|i| {
                let hi = (i + self.w).min(self.n - 1);
                (self.first[i]..=hi)
                    .map(|j| self.a[self.idx(i, j)] * x[j])
                    .sum()
            })
            .collect()
    }

    /// LU factorisation in place (L unit lower, U upper), without pivoting. Returns false on a zero or
    /// non-finite pivot (the factors are then unusable).
    pub(crate) fn factor(&mut self) -> bool {
        let stride = 2 * self.w + 1;
        for k in 0..self.n {
            let pivot = self.a[self.idx(k, k)];
            if pivot == 0.0 || !pivot.is_finite() {
                return false;
            }
            let last = self.reach[k];
            let len = last - k;
            for i in k + 1..=last {
                let ik = self.idx(i, k);
                if self.a[ik] == 0.0 {
                    continue;
                }
                let l = self.a[ik] / pivot;
                self.a[ik] = l;
                // row i, columns k+1..=last −= l · row k, same columns
                let (head, tail) = self.a.split_at_mut(i * stride);
                let src = &head[k * stride + self.w + 1..][..len];
                let dst = &mut tail[ik + 1 - i * stride..][..len];
                for (d, s) in dst.iter_mut().zip(src) {
                    *d -= l * s;
                }
            }
        }
        true
    }

    /// Solves A·x = b in place with the factors of [`Self::factor`].
    pub(crate) fn solve(&self, b: &mut [f64]) {
        for i in 0..self.n {
            let lo = self.first[i];
            let row = &self.a[self.idx(i, lo)..self.idx(i, i)];
            let s: f64 = row.iter().zip(&b[lo..i]).map(|(l, x)| l * x).sum();
            b[i] -= s;
        }
        for i in (0..self.n).rev() {
            let hi = self.reach[i];
            let row = &self.a[self.idx(i, i) + 1..=self.idx(i, hi)];
            let s: f64 = row.iter().zip(&b[i + 1..=hi]).map(|(u, x)| u * x).sum();
            b[i] = (b[i] - s) / self.a[self.idx(i, i)];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2-D grid pattern in strip order with an irregular (elliptic) outline, like the contact grid.
    fn pattern() -> Vec<Vec<usize>> {
        let (nx, ny) = (9, 7);
        let mut index = vec![None; nx * ny];
        let mut n = 0;
        for j in 0..ny {
            for i in 0..nx {
                let (x, y) = (i as f64 - 4.0, j as f64 - 3.0);
                if (x / 4.6).powi(2) + (y / 3.6).powi(2) < 1.0 {
                    index[i + nx * j] = Some(n);
                    n += 1;
                }
            }
        }
        let mut nb = vec![Vec::new(); n];
        for j in 0..ny as isize {
            for i in 0..nx as isize {
                let Some(k) = index[i as usize + nx * j as usize] else {
                    continue;
                };
                for (di, dj) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                    let (a, b) = (i + di, j + dj);
                    if a >= 0
                        && b >= 0
                        && (a as usize) < nx
                        && (b as usize) < ny
                        && let Some(m) = index[a as usize + nx * b as usize]
                    {
                        nb[k].push(m);
                    }
                }
            }
        }
        nb
    }

    #[test]
    fn factor_and_solve_give_a_vanishing_residual() {
        let nb = pattern();
        let n = nb.len();
        let mut m = Band::new(nb.iter().map(|l| l.iter().copied()));
        // nonsymmetric values, diagonally dominant by columns like the film Jacobian, with a
        // deterministic pseudo-random spread
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut col = vec![0.0; n];
        for (i, list) in nb.iter().enumerate() {
            for &j in list {
                let v = -rnd();
                m.add(i, j, v);
                col[j] += v.abs();
            }
        }
        for (j, c) in col.iter().enumerate() {
            m.add(j, j, c + 0.1 + rnd());
        }
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let b = m.mul(&x);
        let mut sol = b.clone();
        assert!(m.factor());
        m.solve(&mut sol);
        for (s, e) in sol.iter().zip(&x) {
            assert!((s - e).abs() < 1e-12, "{s} vs {e}");
        }
    }

    #[test]
    fn zero_pivot_is_reported() {
        let nb = pattern();
        let mut m = Band::new(nb.iter().map(|l| l.iter().copied()));
        m.add(0, 0, 0.0);
        assert!(!m.factor());
    }
}
