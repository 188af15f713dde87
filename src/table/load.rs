//! Loading a table: the rows in memory from verified files (values, φ̂ slopes, cell flags), the probe
//! nodes that prove the present model computed the table, and the per-process shared copy.

use super::axes::{Axes, DIMS, ETA, PHI, XI};
use super::coords::{Coordinates, Ellipse};
use super::file::{self, OUTPUT_INFO, OUTPUTS, TableFiles};
use super::flags::{
    NEAR_UNCONVERGED, UNRESOLVED, beside_unresolved, near_unconverged, unresolved_cells,
};
use super::interp::{self, AxisInterp};
use super::kernel::Kernel;
use super::layout::{PREFETCH_ABOVE, Row, SLOPE, VAL, memory_index, memory_strides};
use super::rise::RiseVariable;
use super::{PROBE_TOLERANCE, PROBES, Table, build, heating};
use crate::error::{Error, Result};
use crate::params::{OperatingPoint, Params};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock, Weak};

impl Table {
    /// A table from verified files (a complete table, not a shard).
    pub fn from_files(files: TableFiles, path: Option<&Path>) -> Result<Table> {
        let where_ = path.unwrap_or(Path::new("<memory>"));
        if let Some(s) = files.sidecar.shard {
            return Err(file::corrupt(
                where_,
                format!(
                    "is shard {}/{} of a table; join the shards with `wheelrail table merge`",
                    s.index, s.count
                ),
            ));
        }
        let axes = files.axes;
        let shape = axes.shape();
        let n = axes.len();
        if files.outputs.len() != OUTPUTS
            || files.outputs.iter().any(|o| o.len() != n)
            || files.converged.len() != n
            || files.film_intake.as_ref().is_some_and(|f| f.len() != n)
        {
            return Err(file::corrupt(where_, "array sizes do not match the axes"));
        }
        let strides = memory_strides(&shape);
        // the points, each ξ̂ slab followed by its padding
        let len = shape[XI] * strides[XI];
        // the file's C order over the axes → memory order
        let memory: Vec<usize> = (0..n).map(|i| memory_index(&shape, &strides, i)).collect();
        let rise = RiseVariable::new(&files.sidecar.params.material);
        let coordinates = Coordinates::new(&files.sidecar.params, &axes);
        let heating = heating::NodeFactors::new(&coordinates, &axes)?;
        let (mut rows, converged) = node_rows(
            &files.outputs,
            &files.converged,
            &shape,
            &memory,
            len,
            &rise,
            heating.as_ref(),
        );
        phi_slopes(&mut rows, &axes.0[PHI].points);
        let interp =
            std::array::from_fn(|d| AxisInterp::new(&axes.0[d], axes.0[d].interpolation(d)));
        let cell_flags = cell_flags(
            &shape,
            &files.outputs[3],
            &files.converged,
            files.film_intake.as_deref(),
            &interp,
            &memory,
            len,
        );
        Ok(Table {
            cell_flags,
            bulk_temperature: files.sidecar.params.material.bulk_temperature,
            rise,
            coordinates,
            has_power: files.sidecar.format_version > 1,
            converged,
            prefetch: len * std::mem::size_of::<Row>() > PREFETCH_ABOVE,
            sidecar: files.sidecar,
            axes,
            interp,
            strides,
            rows,
            path: path.map(Path::to_path_buf),
            kernel: Kernel::detect(),
        })
    }

    /// Loads and verifies the table in directory `dir` (see [`file`] for what is checked).
    ///
    /// # Example
    ///
    /// The table bundled with the FMU covers 10–200 kN and 1–100 m/s for the default parameters; loading
    /// re-solves its probe nodes, so a table the present model did not compute is refused. At zero
    /// creepage the contact transmits no tangential force: the table's ξ and η axes are mirrored
    /// (F_x odd in ξ, F_y odd in η), so F_x = F_y = 0 there exactly.
    ///
    /// ```
    /// use std::path::Path;
    /// use wheelrail::table::{Ellipse, Table};
    /// use wheelrail::{OperatingPoint, Params};
    /// let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fmu/resources/table");
    /// let table = Table::load(&dir)?;
    /// assert!(table.matches(&Params::default()));
    /// let forces = &table.axes().0[3].points;
    /// assert_eq!((forces[0], *forces.last().unwrap()), (10e3, 200e3));
    ///
    /// let point = OperatingPoint { creepage_x: 0.0, creepage_y: 0.0, spin: 0.0, ..OperatingPoint::default() };
    /// let hertz = wheelrail::solver::normal_contact(table.params(), point.normal_force)?;
    /// let e = Ellipse { a: hertz.a, b: hertz.b, load_exponent: Ellipse::HERTZ };
    /// let out = table.evaluate(&point, &e)?;
    /// assert!(out.in_range);
    /// assert_eq!((out.force_x, out.force_y), (0.0, 0.0));
    /// # Ok::<(), wheelrail::Error>(())
    /// ```
    pub fn load(dir: &Path) -> Result<Table> {
        let t = Table::from_files(TableFiles::read(dir)?, Some(dir))?;
        t.check_probes()?;
        Ok(t)
    }

    /// The nodes whose stored values [`Table::check_probes`] compares with the exact solver
    /// ([`probe_nodes`] of this table's axes and converged points).
    pub fn probe_nodes(&self) -> Vec<usize> {
        let shape = self.axes.shape();
        probe_nodes(&self.axes, |n| {
            self.converged[memory_index(&shape, &self.strides, n)] == 1
        })
    }

    /// The operating point and contact of node `n` (index in the arrays' order) and their exact solution
    /// ([`exact_at_node`]).
    pub(super) fn exact_at_node(
        &self,
        n: usize,
    ) -> Result<(OperatingPoint, Ellipse, [f32; OUTPUTS])> {
        exact_at_node(&self.sidecar.params, &self.coordinates, &self.axes, n)
    }

    /// The probe tolerance of output `o`: [`PROBE_TOLERANCE`], plus half the code step of a table stored
    /// as u16 codes (rounding to the nearest code: e.g. 9e-6 of F/F_N, 0.005 K of T_max).
    pub(super) fn probe_tolerance(&self, o: usize) -> f64 {
        let half_step = self
            .sidecar
            .outputs
            .get(o)
            .and_then(|r| r.quantization)
            .map_or(0.0, |q| 0.5 * q.step * (1.0 + 1e-6));
        PROBE_TOLERANCE[o] + half_step
    }

    /// Proof that the present model computed this table: the exact solver solves the
    /// [`Table::probe_nodes`] cold and must reproduce the stored outputs (measured on the default table,
    /// 200 nodes: within 1.5e-8 for F/F_N, M_z/(F_N·c), the fluid load fraction and P_f/(F_N·V) and 3e-5 K for
    /// T_max, f32 storage included; the tolerances [`PROBE_TOLERANCE`] leave a factor 60 or more). A table
    /// computed by a model whose physics has changed since (a different film transport, friction law,
    /// default, …) is refused with the node and the values, so that it is rebuilt: a few exact solves per
    /// load (milliseconds each).
    pub(crate) fn check_probes(&self) -> Result<()> {
        for n in self.probe_nodes() {
            let (point, e, want) = self.exact_at_node(n)?;
            let mut stored = self.rows[memory_index(&self.axes.shape(), &self.strides, n)].0;
            // the heat is stored per unit of the node's direction factor Λ
            let lambda = self.coordinates.of(&point, &e)?.heating as f32;
            stored[VAL[3]] *= lambda;
            stored[VAL[5]] *= lambda;
            let stale = (0..OUTPUTS).find(|&o| {
                let (a, b) = (f64::from(want[o]), f64::from(stored[VAL[o]]));
                // T_max compared as the stored G(T_max), its tolerance scaled by dG/dT
                let (a, scale) = if o == 3 {
                    (self.rise.of(a), self.rise.slope(a))
                } else {
                    (a, 1.0)
                };
                // a format-1 table stores no frictional power (NaN)
                let within = (a - b).abs() <= scale * self.probe_tolerance(o);
                let absent = b.is_nan() && o == OUTPUTS - 1;
                !(within || absent)
            });
            if let Some(o) = stale {
                let stored = match o {
                    3 => self.rise.temperature(f64::from(stored[VAL[3]])),
                    _ => f64::from(stored[VAL[o]]),
                };
                return Err(Error::Table {
                    path: self.location(),
                    reason: format!(
                        "was computed by another model (version {} of the sidecar, but the physics differs): \
                         at its point {point:?} with semi-axes [{:e}, {:e}] m it stores {} = {} where the \
                         exact solver now gives {} (tolerance {:e}); rebuild the table",
                        self.sidecar.model_version,
                        e.a,
                        e.b,
                        OUTPUT_INFO[o].name,
                        stored,
                        want[o],
                        PROBE_TOLERANCE[o]
                    ),
                });
            }
        }
        Ok(())
    }

    /// The table in `dir`, loaded at most once per process while any user holds it: later calls for the
    /// same directory (by canonical path) share the same read-only copy.
    pub fn load_shared(dir: &Path) -> Result<Arc<Table>> {
        static CACHE: OnceLock<Mutex<HashMap<PathBuf, Weak<Table>>>> = OnceLock::new();
        let key = dir
            .canonicalize()
            .map_err(|e| file::corrupt(dir, format!("cannot open the table directory: {e}")))?;
        let mut cache = CACHE
            .get_or_init(Default::default)
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(t) = cache.get(&key).and_then(Weak::upgrade) {
            return Ok(t);
        }
        let t = Arc::new(Table::load(&key)?);
        cache.retain(|_, w| w.strong_count() > 0);
        cache.insert(key, Arc::downgrade(&t));
        Ok(t)
    }
}

/// The rows in memory of a table's stored `outputs` (in the files' C order over the axes of `shape`; the
/// files' point i in row `memory[i]` of `len`, padding included): T_max as G(T_max) (`rise`), the heat G and
/// P_f/(F_N·V) per unit of the direction factor Λ (`heating`), the others as stored; and the points'
/// converged flags (`converged_in`) in memory order.
fn node_rows(
    outputs: &[Vec<f32>],
    converged_in: &[u8],
    shape: &[usize; DIMS],
    memory: &[usize],
    len: usize,
    rise: &RiseVariable,
    heating: Option<&heating::NodeFactors>,
) -> (Vec<Row>, Vec<u8>) {
    let mut rows = vec![Row::default(); len];
    let mut converged = vec![0; len];
    // the node's indices along the axes (the files' C order: the last axis fastest)
    let mut idx = [0; DIMS];
    for (i, m) in memory.iter().enumerate() {
        for (o, v) in VAL.iter().enumerate() {
            rows[*m].0[*v] = outputs[o][i];
        }
        // T_max is interpolated as G(T_max) (`rise`), the heat G and P_f/(F_N·V) per unit of the
        // direction factor Λ (`heating`)
        let lambda = heating.map_or(1.0, |h| h.at(&idx));
        rows[*m].0[VAL[3]] = (rise.of(f64::from(outputs[3][i])) / lambda) as f32;
        rows[*m].0[VAL[5]] = (f64::from(outputs[5][i]) / lambda) as f32;
        converged[*m] = converged_in[i];
        for d in (0..DIMS).rev() {
            idx[d] += 1;
            if idx[d] < shape[d] {
                break;
            }
            idx[d] = 0;
        }
    }
    (rows, converged)
}

/// The Steffen slopes along φ̂ (`phi`: its points) of every fibre of `rows` and every output, into the rows'
/// slope lanes.
fn phi_slopes(rows: &mut [Row], phi: &[f64]) {
    // Steffen slopes along φ of every fibre (fixed ξ̂, η̂, F_N, V, w, a/b, p_ref; contiguous in memory;
    // the padding is whole fibres of zeros)
    // and output, computed in f64 from the stored values and kept in the stored precision (f32)
    let np = phi.len();
    let (mut y, mut d) = (vec![0.0; np], vec![0.0; np]);
    for fibre in rows.chunks_exact_mut(np) {
        for o in 0..OUTPUTS {
            for (v, r) in y.iter_mut().zip(fibre.iter()) {
                *v = f64::from(r.0[VAL[o]]);
            }
            interp::node_slopes(phi, &y, &mut d);
            for (v, r) in d.iter().zip(fibre.iter_mut()) {
                r.0[SLOPE[o]] = *v as f32;
            }
        }
    }
}

/// The cells' flags of a table of `shape` in memory order (`memory`, `len` as [`node_rows`]): from its
/// stored T_max `t_max` and film-intake states `film` (unresolved cells), its points' `converged` flags
/// (cells near unconverged points, through the interpolation rules `interp`) and the unresolved cells'
/// neighbours; empty where no cell has a flag.
fn cell_flags(
    shape: &[usize; DIMS],
    t_max: &[f32],
    converged: &[u8],
    film: Option<&[u8]>,
    interp: &[AxisInterp; DIMS],
    memory: &[usize],
    len: usize,
) -> Vec<u8> {
    // the cells' flags in the files' order, then in memory order
    let mut flags: Vec<u8> = unresolved_cells(shape, t_max, film)
        .iter()
        .map(|u| UNRESOLVED * u)
        .collect();
    if converged.iter().any(|c| *c != 1) {
        for (f, u) in flags
            .iter_mut()
            .zip(near_unconverged(shape, converged, interp))
        {
            *f |= NEAR_UNCONVERGED * u;
        }
    }
    beside_unresolved(shape, &mut flags);
    let mut cell_flags = Vec::new();
    if flags.iter().any(|f| *f != 0) {
        cell_flags = vec![0; len];
        for (m, f) in memory.iter().zip(flags) {
            cell_flags[*m] = f;
        }
    }
    cell_flags
}

/// The nodes whose stored values loading compares with the exact solver ([`Table::check_probes`]), by
/// index in the arrays' order: in [`PROBES`] creepage cubes spread over a table on `axes` (the first cube
/// whose node converged, `converged(n)`, from each of PROBES equal parts), the creepage node (ξ̂ index 1, η̂
/// index 1, the φ̂ node just above the middle), which every cube solves (coverage windows start at
/// ξ̂ = η̂ = 0 and are symmetric in φ̂).
pub(crate) fn probe_nodes(axes: &Axes, converged: impl Fn(usize) -> bool) -> Vec<usize> {
    let shape = axes.shape();
    let cubes = file::cube_count(axes);
    let (i, j, l) = (
        1.min(shape[XI] - 1),
        1.min(shape[ETA] - 1),
        (shape[PHI] / 2 + 1).min(shape[PHI] - 1),
    );
    let node = (i * shape[ETA] + j) * shape[PHI] + l;
    (0..PROBES)
        .filter_map(|k| {
            (k * cubes / PROBES..(k + 1) * cubes / PROBES)
                .map(|t| node * cubes + t)
                .find(|&n| converged(n))
        })
        .collect()
}

/// The operating point and contact of node `n` (index in the arrays' order) of a table on `axes` for
/// `params` (whose `coordinates` they are) and their exact solution, cold, normalised as the table stores it
/// ([`build::normalised`]).
pub(crate) fn exact_at_node(
    params: &Params,
    coordinates: &Coordinates,
    axes: &Axes,
    n: usize,
) -> Result<(OperatingPoint, Ellipse, [f32; OUTPUTS])> {
    let (point, e) = coordinates.point(&axes.coordinates(n))?;
    let mut params = params.clone();
    params.geometry.semi_axes = Some([e.a, e.b]);
    let s = crate::solver::solve(&params, &point)?;
    Ok((point, e, build::normalised(&s, &point, e.radius())?))
}
