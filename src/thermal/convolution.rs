//! Influence matrices applied without forming them (MODEL.md §7: "use the translation invariance"): the
//! temperature rise at cell (i, j) is Σ G(i − i', |j − j'|)·q(i', j') over the active cells, a 2-D discrete
//! convolution of the flux (zero outside the contact) with the offset table of [`InfluenceTable`]. Only the
//! offsets with a non-zero coefficient are visited, so the cost falls from N² multiply–adds at low Péclet
//! number to a few per cell at high Péclet number, where the kernel lives in the thin wake behind a source.

use super::influence::InfluenceTable;
use crate::contact::ContactGrid;
use crate::error::{Error, Result};

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
                    stage: "thermal convolution",
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

/// The non-zero coefficients of one lateral offset Δj: G(Δi, Δj) for Δi = first, first + 1, ….
#[derive(Debug, Clone, PartialEq)]
struct KernelRow {
    first: isize,
    values: Vec<f64>,
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
                stage: "thermal convolution",
                reason: "no influence table".to_string(),
            })?;
        if nx != layout.nx || tables.iter().any(|t| t.size() != (nx, ny)) {
            return Err(Error::Numerical {
                stage: "thermal convolution",
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
                (Some(&first), Some(&last)) => rows.push(KernelRow {
                    first,
                    values: (first..=last).map(value).collect(),
                }),
                _ => break,
            }
        }
        Ok(Self { rows })
    }

    /// G(Δi, Δj) [K·m²/W] (zero outside the stored offsets).
    pub fn coefficient(&self, di: isize, dj: isize) -> f64 {
        self.rows
            .get(dj.unsigned_abs())
            .and_then(|row| {
                usize::try_from(di - row.first)
                    .ok()
                    .and_then(|k| row.values.get(k))
            })
            .copied()
            .unwrap_or(0.0)
    }

    /// Number of stored coefficients (a cost measure of [`Self::apply`]).
    pub fn stored(&self) -> usize {
        self.rows.iter().map(|r| r.values.len()).sum()
    }

    /// y = G·x over the active cells of `layout` (x, y: one value per cell, in the grid's cell order).
    ///
    /// Field strip f and source strip s at lateral offset Δj, field cell m and source cell m' (counted
    /// from each strip's leading cell), have Δi = (lead_f − m) − (lead_s − m') = shift − d with
    /// shift = lead_f − lead_s and d = m − m'; for each d with a non-zero coefficient the strip pair
    /// contributes one contiguous multiply–add y[m] += G(shift − d, Δj)·x[m − d].
    pub fn apply(&self, layout: &StripLayout, x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        for field in &layout.spans {
            let out = &mut y[field.start..field.start + field.len];
            for source in &layout.spans {
                let Some(row) = self.rows.get(field.row.abs_diff(source.row)) else {
                    continue;
                };
                let input = &x[source.start..source.start + source.len];
                let shift = field.lead as isize - source.lead as isize;
                let last = row.first + row.values.len() as isize - 1;
                let (f_len, s_len) = (field.len as isize, source.len as isize);
                let d_lo = (shift - last).max(1 - s_len);
                let d_hi = (shift - row.first).min(f_len - 1);
                for d in d_lo..=d_hi {
                    let c = row.values[(shift - d - row.first) as usize];
                    let m0 = d.max(0);
                    let m1 = f_len.min(s_len + d);
                    let dst = &mut out[m0 as usize..m1 as usize];
                    let src = &input[(m0 - d) as usize..(m1 - d) as usize];
                    for (yy, xx) in dst.iter_mut().zip(src) {
                        *yy += c * xx;
                    }
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
/// Within a strip the matrix is Toeplitz, T[m][m'] = G(m' − m, 0) (cells m counted from the leading one),
/// so every strip's matrix is a leading block of the longest strip's T; one LU factorisation of that T
/// without row exchanges (T = L·U, whose leading blocks factorise the leading blocks of T) serves all
/// strips.
#[derive(Debug, Clone, PartialEq)]
pub struct StripSolver {
    /// Order n of the factorised T (the longest strip).
    order: usize,
    /// L (unit diagonal, below) and U (on and above the diagonal), row-major n × n.
    lu: Vec<f64>,
}

impl StripSolver {
    /// Factorises the Δj = 0 Toeplitz matrix of `kernel` for the strips of `layout`; an error if a pivot
    /// is not finite or below 1e-13 of G(0, 0).
    pub fn new(kernel: &OffsetKernel, layout: &StripLayout) -> Result<Self> {
        let n = layout.longest_strip();
        let mut lu: Vec<f64> = (0..n * n)
            .map(|k| kernel.coefficient((k % n) as isize - (k / n) as isize, 0))
            .collect();
        let diagonal = kernel.coefficient(0, 0).abs();
        for k in 0..n {
            let pivot = lu[k * n + k];
            if !(pivot.is_finite() && pivot.abs() > PIVOT_RATIO_MIN * diagonal) {
                return Err(Error::Numerical {
                    stage: "thermal partition",
                    reason: format!(
                        "strip factorisation: pivot {k} is {pivot:.3e} against G(0, 0) = {diagonal:.3e}"
                    ),
                });
            }
            for i in k + 1..n {
                let factor = lu[i * n + k] / pivot;
                lu[i * n + k] = factor;
                if factor != 0.0 {
                    for j in k + 1..n {
                        lu[i * n + j] -= factor * lu[k * n + j];
                    }
                }
            }
        }
        Ok(Self { order: n, lu })
    }

    /// v ← T⁻¹·v strip by strip (forward substitution with L, back substitution with U on each strip's
    /// leading block).
    pub fn apply(&self, layout: &StripLayout, v: &mut [f64]) {
        let n = self.order;
        for strip in layout.strips() {
            let v = &mut v[strip];
            let len = v.len();
            for i in 1..len {
                let row = &self.lu[i * n..i * n + i];
                let dot: f64 = row.iter().zip(&v[..i]).map(|(l, x)| l * x).sum();
                v[i] -= dot;
            }
            for i in (0..len).rev() {
                let row = &self.lu[i * n + i + 1..i * n + len];
                let dot: f64 = row.iter().zip(&v[i + 1..]).map(|(u, x)| u * x).sum();
                v[i] = (v[i] - dot) / self.lu[i * n + i];
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
