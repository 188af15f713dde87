//! Influence tables of any cell size and surface speed by interpolation in a dimensionless form
//! (docs/model.md §7.2).
//!
//! Scaling the offsets of the moving-source kernel by the cell length h_x (ζ = h_x·ζ', η = h_x·η') gives
//! G(Δi, Δj; h_x, h_y, p) = h_x·G(Δi, Δj; 1, α, Pe) with the cell Péclet number Pe = p·h_x = v·h_x/(2κ)
//! and the cell aspect α = h_y/h_x: the coefficients of a grid are h_x times those of a unit cell that
//! depend on two numbers only. Tables of unit cells ("nodes", [`InfluenceTable::new`] with h_x = 1 m)
//! are made on a lattice uniform in (ln Pe, ln α) with spacing [`LATTICE_STEP`] and kept for the process
//! (a memo of a pure function: which nodes it holds changes no result); a grid's table is the bicubic
//! Lagrange interpolation of the 4 × 4 nodes around its (ln Pe, ln α). Its error against the direct
//! quadrature is below [`INTERPOLATION_ERROR`] of the coefficient scale h/sqrt(1 + p·h)/(2πλ),
//! h = min(h_x, h_y) (measured over Pe 0.05 … 5000, α 0.3 … 3 on 9 × 9 and 30 × 30 grids: at most
//! 1.65e-5; `tests::interpolation_matches_the_direct_quadrature`), against 1e-9 of the direct tables. The
//! spacing trades that error, far below the grid's discretisation error of the temperature (along the MBS
//! trace T_max moves by at most 3e-5 K against a lattice of half the spacing), for a quarter of the nodes
//! (each costs about one direct table when first made).
//!
//! Why: in an MBS run the speed and the contact ellipse change every step, so a direct table would be
//! made anew every step (most of a small grid's step); interpolated, a step costs 16 weighted sums of
//! node tables that earlier steps (or other solves of the process) have made.

use super::influence::{InfluenceTable, MovingHalfSpace};
use crate::error::{Result, check_positive};
use crate::params::Material;
use std::collections::HashMap;
use std::sync::{Arc, LazyLock, Mutex, PoisonError};

/// Spacing of the node lattice in ln Pe and in ln α.
pub const LATTICE_STEP: f64 = 0.1;
/// Bound of the interpolation error of a coefficient, relative to the grid's coefficient scale
/// h/sqrt(1 + p·h)/(2πλ) (see the module documentation).
pub const INTERPOLATION_ERROR: f64 = 2e-5;
/// The memo is emptied when it holds more coefficients than this (64 MB): a bound on its memory.
const MEMO_CAPACITY: usize = 8 << 20;

/// What a node table is made from: the grid's cell counts, the lattice indices of ln Pe and ln α, and the
/// material's conductivity and diffusivity (bit patterns).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct NodeKey {
    cells: [usize; 2],
    lattice: [i64; 2],
    material: [u64; 2],
}

/// The node tables made so far, and how many coefficients they hold.
#[derive(Default)]
struct Memo {
    nodes: HashMap<NodeKey, Arc<InfluenceTable>>,
    stored: usize,
}

static MEMO: LazyLock<Mutex<Memo>> = LazyLock::new(Mutex::default);

/// The unit-cell table of `key`: Pe = exp(LATTICE_STEP·lattice[0]), α = exp(LATTICE_STEP·lattice[1]),
/// from the memo or made (outside its lock) and stored.
fn node(key: NodeKey, material: &Material) -> Result<Arc<InfluenceTable>> {
    let lock = || MEMO.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some(t) = lock().nodes.get(&key) {
        return Ok(Arc::clone(t));
    }
    let [pe, alpha] = key.lattice.map(|k| (LATTICE_STEP * k as f64).exp());
    // the unit cell: h_x = 1 m, so p = Pe [1/m], i.e. v = 2κ·Pe
    let body = MovingHalfSpace::new(2.0 * material.diffusivity() * pe, material)?;
    let table = Arc::new(InfluenceTable::new(
        &body,
        key.cells[0],
        key.cells[1],
        1.0,
        alpha,
    )?);
    let mut memo = lock();
    let size = table.size();
    let count = (2 * size.0 - 1) * size.1;
    if memo.stored + count > MEMO_CAPACITY {
        memo.nodes.clear();
        memo.stored = 0;
    }
    if memo.nodes.insert(key, Arc::clone(&table)).is_none() {
        memo.stored += count;
    }
    Ok(table)
}

/// Nodes one holder used last (a solver's set-up cache keeps them, one per model): a memo in front of the
/// process's, so that a step's 16 nodes per body need neither its lock nor a shared reference count, for
/// which threads evaluating contacts at the same time would contend. Its nodes are the memo's (the same
/// coefficients, bit for bit).
#[derive(Debug, Default, Clone)]
pub struct RecentNodes {
    nodes: Vec<(NodeKey, Arc<InfluenceTable>)>,
}

/// The most nodes a [`RecentNodes`] keeps: both bodies' 4 × 4 stencils and their neighbours along the lattice.
const RECENT_NODES: usize = 64;

impl RecentNodes {
    /// The node of `key`: kept here, or the process memo's ([`node`]), then kept (the oldest dropped).
    fn get(&mut self, key: NodeKey, material: &Material) -> Result<&InfluenceTable> {
        let i = match self.nodes.iter().position(|(k, _)| *k == key) {
            Some(i) => i,
            None => {
                let t = node(key, material)?;
                if self.nodes.len() >= RECENT_NODES {
                    self.nodes.remove(0);
                }
                self.nodes.push((key, t));
                self.nodes.len() - 1
            }
        };
        Ok(&self.nodes[i].1)
    }
}

/// The 4 lattice indices around `x` (in units of the lattice step: x/LATTICE_STEP) and the cubic
/// Lagrange weights of the nodes at them: indices ⌊x⌋ − 1 … ⌊x⌋ + 2.
fn stencil(x: f64) -> (i64, [f64; 4]) {
    let base = x.floor();
    let t = x - base;
    // Lagrange basis on the nodes −1, 0, 1, 2 at t ∈ [0, 1)
    let weights = [
        -t * (t - 1.0) * (t - 2.0) / 6.0,
        (t + 1.0) * (t - 1.0) * (t - 2.0) / 2.0,
        -(t + 1.0) * t * (t - 2.0) / 2.0,
        (t + 1.0) * t * (t - 1.0) / 6.0,
    ];
    (base as i64 - 1, weights)
}

/// The influence table of `body` on an nx × ny grid of cells h_x × h_y [m], interpolated in the node
/// lattice (see the module documentation): the coefficients of [`InfluenceTable::new`] to within
/// [`INTERPOLATION_ERROR`] of the coefficient scale. Its error estimate is the interpolation bound plus
/// the weighted quadrature errors of the nodes.
///
/// The nodes come from `recent` where it holds them (those taken from the process's memo are kept there):
/// the same coefficients whatever `recent` holds, bit for bit.
pub fn interpolated_table_with(
    body: &MovingHalfSpace,
    material: &Material,
    nx: usize,
    ny: usize,
    hx: f64,
    hy: f64,
    recent: &mut RecentNodes,
) -> Result<InfluenceTable> {
    check_positive("cell length h_x", hx, "m")?;
    check_positive("cell width h_y", hy, "m")?;
    let peclet = body.decay_rate() * hx;
    let (u0, wu) = stencil(peclet.ln() / LATTICE_STEP);
    let (v0, wv) = stencil((hy / hx).ln() / LATTICE_STEP);
    let material_key = [
        material.conductivity.to_bits(),
        material.diffusivity().to_bits(),
    ];
    let mut values = Vec::new();
    let mut node_error = 0.0;
    for (a, wa) in wu.iter().enumerate() {
        for (b, wb) in wv.iter().enumerate() {
            let t = recent.get(
                NodeKey {
                    cells: [nx, ny],
                    lattice: [u0 + a as i64, v0 + b as i64],
                    material: material_key,
                },
                material,
            )?;
            let w = wa * wb * hx;
            if values.is_empty() {
                values = vec![0.0; t.values().len()];
            }
            for (v, g) in values.iter_mut().zip(t.values()) {
                *v += w * g;
            }
            node_error += w.abs() * t.error_estimate();
        }
    }
    let h = hx.min(hy);
    let scale = h
        / (1.0 + body.decay_rate() * h).sqrt()
        / (2.0 * std::f64::consts::PI)
        / material.conductivity;
    InfluenceTable::from_values(nx, ny, values, node_error + INTERPOLATION_ERROR * scale)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Interpolated and direct tables of one (Pe, α) on an n × n grid: the largest coefficient difference
    /// relative to the coefficient scale.
    fn relative_error(n: usize, peclet: f64, alpha: f64) -> f64 {
        let m = Material::default();
        let hx = 1e-3;
        let body = MovingHalfSpace::new(2.0 * m.diffusivity() * peclet / hx, &m).unwrap();
        let direct = InfluenceTable::new(&body, n, n, hx, alpha * hx).unwrap();
        let interpolated =
            interpolated_table_with(&body, &m, n, n, hx, alpha * hx, &mut RecentNodes::default())
                .unwrap();
        let h = hx.min(alpha * hx);
        let scale =
            h / (1.0 + peclet / hx * h).sqrt() / (2.0 * std::f64::consts::PI * m.conductivity);
        direct
            .values()
            .iter()
            .zip(interpolated.values())
            .fold(0.0_f64, |e, (d, i)| e.max((d - i).abs()))
            / scale
    }

    #[test]
    fn interpolation_matches_the_direct_quadrature() {
        // cell Péclet numbers from near-static to far beyond a 1 kHz MBS run's (≈ 1000 on 9 x 9 at 25 m/s),
        // aspects of a/b from 0.3 to 3, off the lattice
        let cases = [
            (0.05, 2.0),
            (1.3, 0.5),
            (3.0, 1.0),
            (37.0, 1.3),
            (300.0, 3.0),
            (1200.0, 0.6),
            (5000.0, 0.3),
        ];
        for n in [9, 30] {
            for (pe, alpha) in cases {
                let e = relative_error(n, pe, alpha);
                assert!(
                    e <= INTERPOLATION_ERROR,
                    "{n}x{n}, Pe {pe}, alpha {alpha}: {e:.2e}"
                );
            }
        }
    }

    #[test]
    fn on_a_node_the_interpolation_is_the_node() {
        // Lagrange weights at a node: 1 there, 0 elsewhere (the error is the node's quadrature alone)
        let (_, w) = stencil(7.0);
        assert_eq!(w, [0.0, 1.0, 0.0, 0.0]);
        let (k, w) = stencil(-2.5);
        assert_eq!(k, -4);
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn the_memo_changes_no_bit() {
        let m = Material::default();
        let body = MovingHalfSpace::new(24.9, &m).unwrap();
        let table = |recent: &mut RecentNodes| {
            interpolated_table_with(&body, &m, 7, 5, 1.7e-3, 2.9e-3, recent).unwrap()
        };
        let mut recent = RecentNodes::default();
        let first = table(&mut recent);
        {
            let mut memo = MEMO.lock().unwrap();
            memo.nodes.clear();
            memo.stored = 0;
        }
        // made anew by the process memo; and again from the nodes kept in `recent`
        let again = table(&mut RecentNodes::default());
        let kept = table(&mut recent);
        let bits = |t: &InfluenceTable| t.values().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&first), bits(&again));
        assert_eq!(bits(&first), bits(&kept));
        assert_eq!(recent.nodes.len(), 16);
    }
}
