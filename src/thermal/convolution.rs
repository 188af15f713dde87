//! Influence matrices applied without forming them (docs/model.md §7: "use the translation invariance"): the
//! temperature rise at cell (i, j) is Σ G(i − i', |j − j'|)·q(i', j') over the active cells, a 2-D discrete
//! convolution of the flux (zero outside the contact) with the offset table of [`InfluenceTable`]. Only the
//! offsets with a non-zero coefficient are visited, so the cost falls from N² multiply–adds at low Péclet
//! number to a few per cell at high Péclet number, where the kernel lives in the thin wake behind a source.

use super::influence::InfluenceTable;
use crate::contact::ContactGrid;
use crate::error::{Error, Result, Stage};

/// One strip of the grid: consecutive columns, stored from the leading column backwards (as in
/// [`ContactGrid::cells`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Span {
    /// Row index j.
    row: usize,
    /// Column index i of the strip's first (leading) cell.
    lead: usize,
    /// Index of the first cell in the cell ordering.
    start: usize,
    /// Number of cells.
    len: usize,
}

/// The active cells of a grid as strips of consecutive columns.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StripLayout {
    nx: usize,
    spans: Vec<Span>,
    cells: usize,
}

impl StripLayout {
    /// Layout of `grid`; an error if a strip's cells are not consecutive columns (the ellipse's strips
    /// always are).
    pub fn new(grid: &ContactGrid) -> Result<Self> {
        let mut spans = Vec::with_capacity(grid.strips.len());
        for strip in &grid.strips {
            let cells = &grid.cells[strip.cells.clone()];
            let lead = cells[0].i;
            if cells
                .iter()
                .enumerate()
                .any(|(m, c)| c.j != strip.j || c.i + m != lead)
            {
                return Err(Error::Numerical {
                    stage: Stage::ThermalConvolution,
                    reason: format!("the cells of strip {} are not consecutive columns", strip.j),
                });
            }
            spans.push(Span {
                row: strip.j,
                lead,
                start: strip.cells.start,
                len: cells.len(),
            });
        }
        Ok(Self {
            nx: grid.nx,
            spans,
            cells: grid.len(),
        })
    }

    /// Number of active cells N.
    pub fn len(&self) -> usize {
        self.cells
    }

    /// True if there is no active cell.
    pub fn is_empty(&self) -> bool {
        self.cells == 0
    }

    /// Length of the longest strip.
    pub fn longest_strip(&self) -> usize {
        self.spans.iter().map(|s| s.len).max().unwrap_or(0)
    }

    /// The strips' cell ranges (leading cell first).
    pub fn strips(&self) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
        self.spans.iter().map(|s| s.start..s.start + s.len)
    }
}

/// Field cells handled together by [`KernelRow::correlate`] (their sums stay in registers).
const BLOCK: usize = 8;

/// The non-zero coefficients of one lateral offset Δj, G(Δi, Δj) for Δi = first … first + len − 1, stored
/// in reverse order between BLOCK zeros on either side: `reversed[BLOCK + first + len − 1 − Δi]`.
#[derive(Debug, Clone, PartialEq)]
struct KernelRow {
    first: isize,
    len: usize,
    reversed: Vec<f64>,
}

impl KernelRow {
    fn new(first: isize, values: &[f64]) -> Self {
        let mut reversed = vec![0.0; values.len() + 2 * BLOCK];
        for (r, v) in reversed[BLOCK..].iter_mut().zip(values.iter().rev()) {
            *r = *v;
        }
        Self {
            first,
            len: values.len(),
            reversed,
        }
    }

    fn coefficient(&self, di: isize) -> Option<f64> {
        let k = self.first + self.len as isize - 1 - di;
        (0..self.len as isize)
            .contains(&k)
            .then(|| self.reversed[BLOCK + k as usize])
    }

    /// out[m] += Σ_m' G(shift − m + m')·input[m'] for a field strip `out` and a source strip `input`
    /// (cells counted from each strip's leading cell, shift = lead_f − lead_s, so Δi = shift − m + m').
    ///
    /// BLOCK consecutive field cells at a time: for each source cell, their coefficients are BLOCK
    /// consecutive entries of the reversed row (the zero padding covers the pairs outside the row), so
    /// the sums stay in registers and vectorise.
    fn correlate(&self, shift: isize, input: &[f64], out: &mut [f64]) {
        let (f_len, s_len) = (out.len() as isize, input.len() as isize);
        let (lo_off, hi_off) = (
            self.first - shift,
            self.first - shift + self.len as isize - 1,
        );
        let end = self.first + self.len as isize - 1 + BLOCK as isize;
        for m0 in (0..f_len).step_by(BLOCK) {
            let block = (f_len - m0).min(BLOCK as isize);
            let lo = (m0 + lo_off).max(0);
            let hi = (m0 + block - 1 + hi_off).min(s_len - 1);
            if lo > hi {
                continue;
            }
            // source cell hi − t meets the window starting t entries after that of source cell hi
            let n = (hi - lo + 1) as usize;
            let k = (end - shift + m0 - hi) as usize;
            let coefficients = &self.reversed[k..k + n + BLOCK - 1];
            let mut sums = [0.0; BLOCK];
            for (x, c) in input[lo as usize..=hi as usize]
                .iter()
                .rev()
                .zip(coefficients.windows(BLOCK))
            {
                for (s, c) in sums.iter_mut().zip(c) {
                    *s += c * x;
                }
            }
            for (o, s) in out[m0 as usize..(m0 + block) as usize].iter_mut().zip(sums) {
                *o += s;
            }
        }
    }
}

/// An offset kernel G(Δi, |Δj|) (a sum of influence tables) on the offsets where it is non-zero.
#[derive(Debug, Clone, PartialEq)]
pub struct OffsetKernel {
    /// Rows Δj = 0, 1, … up to the last with a non-zero coefficient.
    rows: Vec<KernelRow>,
}

impl OffsetKernel {
    /// Σ of the `tables` (all built for `layout`'s grid) [K·m²/W].
    pub fn sum(layout: &StripLayout, tables: &[&InfluenceTable]) -> Result<Self> {
        let (nx, ny) = tables
            .first()
            .map(|t| t.size())
            .ok_or_else(|| Error::Numerical {
                stage: Stage::ThermalConvolution,
                reason: "no influence table".to_string(),
            })?;
        if nx != layout.nx || tables.iter().any(|t| t.size() != (nx, ny)) {
            return Err(Error::Numerical {
                stage: Stage::ThermalConvolution,
                reason: format!(
                    "influence tables of sizes {:?} for a grid with {} columns",
                    tables.iter().map(|t| t.size()).collect::<Vec<_>>(),
                    layout.nx
                ),
            });
        }
        let reach = nx as isize - 1;
        let mut rows = Vec::new();
        for dj in 0..ny as isize {
            let value = |di: isize| -> f64 {
                tables
                    .iter()
                    .map(|t| t.coefficient(di, dj).unwrap_or(0.0))
                    .sum()
            };
            let nonzero: Vec<isize> = (-reach..=reach).filter(|&di| value(di) != 0.0).collect();
            match (nonzero.first(), nonzero.last()) {
                (Some(&first), Some(&last)) => {
                    let values: Vec<f64> = (first..=last).map(value).collect();
                    rows.push(KernelRow::new(first, &values));
                }
                _ => break,
            }
        }
        Ok(Self { rows })
    }

    /// G(Δi, Δj) [K·m²/W] (zero outside the stored offsets).
    pub fn coefficient(&self, di: isize, dj: isize) -> f64 {
        self.rows
            .get(dj.unsigned_abs())
            .and_then(|row| row.coefficient(di))
            .unwrap_or(0.0)
    }

    /// Number of stored coefficients (a cost measure of [`Self::apply`]).
    #[cfg(test)]
    pub fn stored(&self) -> usize {
        self.rows.iter().map(|r| r.len).sum()
    }

    /// y = G·x over the active cells of `layout` (x, y: one value per cell, in the grid's cell order):
    /// for field strip f and source strip s at lateral offset Δj, field cell m and source cell m' (counted
    /// from each strip's leading cell) are Δi = (lead_f − m) − (lead_s − m') apart.
    pub fn apply(&self, layout: &StripLayout, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for field in &layout.spans {
            let out = &mut y[field.start..field.start + field.len];
            for source in &layout.spans {
                if let Some(row) = self.rows.get(field.row.abs_diff(source.row)) {
                    row.correlate(
                        field.lead as isize - source.lead as isize,
                        &x[source.start..source.start + source.len],
                        out,
                    );
                }
            }
        }
    }
}

/// Smallest admissible |pivot| of the strip factorisation relative to the diagonal coefficient G(0, 0).
const PIVOT_RATIO_MIN: f64 = 1e-13;

/// Exact solve with the strip-diagonal part of a kernel (its Δj = 0 coefficients, each strip on its own):
/// the block-Jacobi preconditioner of the heat partition, nearly exact at high Péclet number where the
/// wake of a source hardly reaches the neighbouring strips.
///
/// Within a strip the matrix is Toeplitz, T(m, m') = G(m' − m, 0) (cells m counted from the leading one),
/// so every strip's matrix is a leading block of the longest strip's T. Its LU factorisation without row
/// exchanges, T = L·U, and the triangular inverses L⁻¹, U⁻¹ have the same property: the leading L × L
/// blocks of L⁻¹ and U⁻¹ invert the strip's factors. So one factorisation serves all strips, and each
/// solve is two triangular matrix–vector products (column by column, which vectorises).
///
/// A source heats its own strip only in its wake and a few cells ahead of it (none at all at high Péclet
/// number, where T is lower triangular): T has an upper bandwidth q ≪ n (G(Δ, 0) = 0 for Δ > q), which
/// the factorisation keeps (U has the same band, Golub & Van Loan, Matrix Computations, 4th ed.,
/// §4.3), so only the band is eliminated and back-substituted; with q = 0, U and U⁻¹ are diagonal. The
/// entries left out are exact zeros: the results are those of the dense loops, bit for bit.
#[derive(Debug, Clone, PartialEq)]
pub struct StripSolver {
    /// Order n of the factorised T (the longest strip).
    order: usize,
    /// Upper bandwidth q of T (and U).
    upper_bandwidth: usize,
    /// L⁻¹ (unit lower triangular), column-major n × n.
    lower_inverse: Vec<f64>,
    /// U⁻¹ (upper triangular; diagonal when q = 0), column-major n × n.
    upper_inverse: Vec<f64>,
}

impl StripSolver {
    /// Factorises the Δj = 0 Toeplitz matrix of `kernel` for the strips of `layout`; an error if a pivot
    /// is not finite or below 1e-13 of G(0, 0).
    pub fn new(kernel: &OffsetKernel, layout: &StripLayout) -> Result<Self> {
        let n = layout.longest_strip();
        // G(Δ, 0) for Δ = 1 − n … n − 1 at [Δ + n − 1]
        let offsets: Vec<f64> = (1 - n as isize..n as isize)
            .map(|d| kernel.coefficient(d, 0))
            .collect();
        let q = (1..n)
            .rev()
            .find(|&d| offsets[n - 1 + d] != 0.0)
            .unwrap_or(0);
        // row-major T, T(i, j) = G(j − i, 0), overwritten by L (below the diagonal) and U
        let mut lu: Vec<f64> = (0..n * n).map(|k| offsets[n - 1 + k % n - k / n]).collect();
        let diagonal = kernel.coefficient(0, 0).abs();
        for k in 0..n {
            let pivot = lu[k * n + k];
            if !(pivot.is_finite() && pivot.abs() > PIVOT_RATIO_MIN * diagonal) {
                return Err(Error::Numerical {
                    stage: Stage::ThermalPartition,
                    reason: format!(
                        "strip factorisation: pivot {k} is {pivot:.3e} against G(0, 0) = {diagonal:.3e}"
                    ),
                });
            }
            // row k of U: columns k + 1 … k + q
            let end = (k + q + 1).min(n);
            let (head, tail) = lu.split_at_mut((k + 1) * n);
            let u_row = &head[k * n + k + 1..k * n + end];
            for row in tail.chunks_exact_mut(n) {
                let factor = row[k] / pivot;
                row[k] = factor;
                if factor != 0.0 {
                    for (x, u) in row[k + 1..end].iter_mut().zip(u_row) {
                        *x -= factor * u;
                    }
                }
            }
        }
        // column j of L⁻¹ by forward substitution on e_j, of U⁻¹ by back substitution (within the band
        // of U; none with q = 0)
        let mut lower_inverse = vec![0.0; n * n];
        let mut upper_inverse = vec![0.0; n * n];
        for j in 0..n {
            let col = &mut lower_inverse[j * n..(j + 1) * n];
            col[j] = 1.0;
            for i in j + 1..n {
                let (known, rest) = col.split_at_mut(i);
                let l_row = &lu[i * n + j..i * n + i];
                rest[0] = -l_row
                    .iter()
                    .zip(&known[j..])
                    .map(|(l, x)| l * x)
                    .sum::<f64>();
            }
            let col = &mut upper_inverse[j * n..(j + 1) * n];
            col[j] = 1.0 / lu[j * n + j];
            if q > 0 {
                for i in (0..j).rev() {
                    let end = (i + q).min(j);
                    let u_row = &lu[i * n + i + 1..=i * n + end];
                    col[i] = -u_row
                        .iter()
                        .zip(&col[i + 1..=end])
                        .map(|(u, x)| u * x)
                        .sum::<f64>()
                        / lu[i * n + i];
                }
            }
        }
        Ok(Self {
            order: n,
            upper_bandwidth: q,
            lower_inverse,
            upper_inverse,
        })
    }

    /// v ← T⁻¹·v strip by strip: v ← U⁻¹·(L⁻¹·v) with each strip's leading blocks.
    pub fn apply(&self, layout: &StripLayout, v: &mut [f64]) {
        let n = self.order;
        let mut work = vec![0.0; n];
        for strip in layout.strips() {
            let v = &mut v[strip];
            let len = v.len();
            let work = &mut work[..len];
            work.fill(0.0);
            for (k, x) in v.iter().enumerate() {
                let col = &self.lower_inverse[k * n + k..k * n + len];
                for (w, l) in work[k..].iter_mut().zip(col) {
                    *w += l * x;
                }
            }
            v.fill(0.0);
            for (k, x) in work.iter().enumerate() {
                // column k of U⁻¹: rows 0 … k, only its diagonal with q = 0
                let top = if self.upper_bandwidth == 0 { k } else { 0 };
                let col = &self.upper_inverse[k * n + top..k * n + k + 1];
                for (y, u) in v[top..=k].iter_mut().zip(col) {
                    *y += u * x;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Material;
    use crate::thermal::MovingHalfSpace;

    fn table(grid: &ContactGrid, v: f64) -> InfluenceTable {
        InfluenceTable::for_grid(
            &MovingHalfSpace::new(v, &Material::default()).unwrap(),
            grid,
        )
        .unwrap()
    }

    /// A rough test vector: no structure the kernel could hide an indexing error in.
    fn rough(n: usize) -> Vec<f64> {
        (0..n).map(|k| (k as f64 * 1.7).sin() + 0.3).collect()
    }

    #[test]
    fn convolution_equals_the_dense_matrix_product() {
        // Unequal nx, ny so that rows and columns cannot be confused; low and high Péclet number.
        let grid = ContactGrid::new(5.879e-3, 10.54e-3, 17, 12);
        let layout = StripLayout::new(&grid).unwrap();
        let x = rough(grid.len());
        for (vw, vr) in [(0.1, 0.09), (30.0, 28.0), (1e-6, 1e-6)] {
            let (tw, tr) = (table(&grid, vw), table(&grid, vr));
            let kernel = OffsetKernel::sum(&layout, &[&tw, &tr]).unwrap();
            let dense = tw.matrix(&grid).unwrap() + tr.matrix(&grid).unwrap();
            let mut y = vec![0.0; grid.len()];
            kernel.apply(&layout, &x, &mut y);
            let reference = &dense * faer::ColRef::from_slice(&x);
            let ymax = reference.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            for (k, (a, b)) in y.iter().zip(reference.iter()).enumerate() {
                assert!(
                    (a - b).abs() <= 1e-13 * ymax,
                    "v = {vw}: cell {k}: {a} vs {b}"
                );
            }
            // Stored offsets: all of them at rest, only the wake at 30 m/s.
            let all = (2 * grid.nx - 1) * grid.ny;
            if vw < 1e-3 {
                assert_eq!(kernel.stored(), all);
            } else if vw > 1.0 {
                assert!(kernel.stored() < all / 5, "{} of {all}", kernel.stored());
            }
        }
    }

    #[test]
    fn strip_solver_inverts_every_strip_block() {
        // At rest the strip matrix is a full symmetric Toeplitz matrix, at 30 m/s nearly lower triangular.
        let grid = ContactGrid::new(5.879e-3, 10.54e-3, 24, 9);
        let layout = StripLayout::new(&grid).unwrap();
        for v in [1e-6, 0.1, 30.0] {
            let t = table(&grid, v);
            let kernel = OffsetKernel::sum(&layout, &[&t]).unwrap();
            let solver = StripSolver::new(&kernel, &layout).unwrap();
            let b = rough(grid.len());
            let mut x = b.clone();
            solver.apply(&layout, &mut x);
            let dense = t.matrix(&grid).unwrap();
            for strip in layout.strips() {
                for k in strip.clone() {
                    let tx: f64 = strip.clone().map(|l| dense[(k, l)] * x[l]).sum();
                    assert!(
                        (tx - b[k]).abs() < 1e-12,
                        "v = {v}: cell {k}: {tx} vs {}",
                        b[k]
                    );
                }
            }
        }
    }

    #[test]
    fn banded_strip_solver_solves_the_dense_system() {
        // the upper bandwidth q of T from the full matrix at rest to lower triangular at high speed (the
        // band loops against the dense strip matrices: T·x = b for every strip)
        let grid = ContactGrid::new(5.879e-3, 10.54e-3, 24, 6);
        let layout = StripLayout::new(&grid).unwrap();
        let mut bandwidths = Vec::new();
        for v in [1e-6, 0.003, 0.01, 0.03, 0.1, 0.3, 1.0, 30.0] {
            let t = table(&grid, v);
            let kernel = OffsetKernel::sum(&layout, &[&t]).unwrap();
            let solver = StripSolver::new(&kernel, &layout).unwrap();
            bandwidths.push(solver.upper_bandwidth);
            let b = rough(grid.len());
            let mut x = b.clone();
            solver.apply(&layout, &mut x);
            let dense = t.matrix(&grid).unwrap();
            for strip in layout.strips() {
                let scale = strip.clone().fold(0.0_f64, |m, k| m.max(b[k].abs()));
                for k in strip.clone() {
                    let tx: f64 = strip.clone().map(|l| dense[(k, l)] * x[l]).sum();
                    assert!(
                        (tx - b[k]).abs() < 1e-12 * scale,
                        "v = {v}: cell {k}: {tx} vs {}",
                        b[k]
                    );
                }
            }
        }
        let n = layout.longest_strip();
        println!("upper bandwidths {bandwidths:?}");
        assert_eq!(bandwidths[0], n - 1, "{bandwidths:?}");
        assert!(
            bandwidths.iter().any(|&q| q > 0 && q < n - 1),
            "{bandwidths:?}"
        );
        assert_eq!(*bandwidths.last().unwrap(), 0, "{bandwidths:?}");
    }

    #[test]
    fn mismatched_tables_are_an_error() {
        let grid = ContactGrid::new(5.879e-3, 10.54e-3, 10, 8);
        let other = ContactGrid::new(5.879e-3, 10.54e-3, 12, 8);
        let layout = StripLayout::new(&grid).unwrap();
        let t = table(&grid, 1.0);
        let u = table(&other, 1.0);
        assert!(OffsetKernel::sum(&layout, &[&t, &u]).is_err());
        assert!(OffsetKernel::sum(&layout, &[&u]).is_err());
        assert!(OffsetKernel::sum(&layout, &[]).is_err());
    }
}
