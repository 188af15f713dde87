//! Tabulation mode: the exact model precomputed on a grid of operating points and contact
//! geometries for one parameter set, stored as `.npy` arrays with a JSON sidecar, and interpolated at run
//! time.
//!
//! - Axes (see [`axes`]): ξ̂, η̂, φ̂ (creepages normalised by Kalker's linear theory, cubic Hermite,
//!   non-uniform sinh spacing dense near 0), F_N, V, w and the contact geometry a/b, p_ref (linear: V, w
//!   multilinear, F_N, a/b, p_ref on simplices, see [`interp`]). η ≥ 0 only, by the exact y-mirror symmetry;
//!   ξ ≥ 0 only by default, by the ξ mirror, exact dry and approximate wet (up to about 1e-2·F_N at the
//!   onset of boundary lubrication in full slip: tables for wet running store both signs).
//! - Stored outputs (see [`file::OUTPUT_INFO`]): F_x/F_N, F_y/F_N, M_z/(F_N·c) with c = sqrt(a·b), T_max,
//!   fluid load fraction, and a converged flag per point. The traction coefficient is |F_T|/F_N of the
//!   interpolated forces (the solver's definition, P2); T_max is interpolated as the variable G of
//!   [`rise`] (the rise over the root of the relative yield stress), and G and P_f/(F_N·V) per unit of
//!   FASTSIM's direction factor Λ of [`heating`] (which has kinks at η = 0 and φ = 0).
//! - [`Table::evaluate`] of an operating point and its contact ellipse ([`Ellipse`]): well under a
//!   microsecond (AVX-512 or AVX2 + FMA kernels, [`Kernel`]), no allocation; [`Table::evaluate_with_jacobian`] adds the
//!   exact derivatives of the interpolant for FMU directional derivatives.
//! - [`Table::load_shared`]: one copy per file and process, shared read-only by all FMU instances.

pub mod axes;
pub mod build;
pub mod coords;
pub mod file;
pub mod heating;
pub mod interp;
pub mod rise;
pub mod verify;

pub use axes::{Axes, AxesSpec, Axis, AxisSpec, DIMENSIONS, DIMS, Interpolation, Spacing};
pub use build::{build, is_built, merge, solve_with_retry, tabulate};
pub use coords::{Coordinates, Ellipse};
pub use file::{
    FilmIntake, OUTPUT_INFO, OUTPUTS, Quantization, Resolution, ShardRecord, Sidecar, Storage,
    TableFiles, fingerprint,
};

use crate::error::{Error, Result};
use crate::params::{OperatingPoint, Params};
use crate::solver::{GlobalResults, Solution, SolverReport};
use axes::{ETA, FORCE, LINEAR_DIMS, PHI, PRESSURE, RATIO, SPEED, WET, XI};
use interp::{AxisInterp, Corners, CubicStencil, Fraction, Offsets};
use rise::RiseVariable;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock, Weak};

/// Results of one table evaluation (SI units, kelvin; Kalker's sign convention as the exact solver).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableOutput {
    /// F_x [N].
    pub force_x: f64,
    /// F_y [N].
    pub force_y: f64,
    /// M_z [N·m].
    pub spin_moment: f64,
    /// |F_T|/F_N [-].
    pub traction_coefficient: f64,
    /// Highest surface temperature [K] (not below the bulk temperature).
    pub max_temperature: f64,
    /// Share of the normal force carried by the fluid [-] (clamped to [0, 1]).
    pub fluid_load_fraction: f64,
    /// The frictional power Σ|τ|·|s| dissipated in the contact [W] (docs/model.md §6.3, §7.4; not below 0);
    /// None from a table of format version 1, which does not store it.
    pub frictional_power: Option<f64>,
    /// Whether the point lies inside every axis range; outside, each coordinate is clamped to its range
    /// (the normalised outputs are held at the boundary; forces still scale with the actual F_N).
    pub in_range: bool,
    /// Whether every table point used by the interpolation converged when the table was built.
    pub converged: bool,
    /// Whether the table resolves the point's cell: its stored T_max varies by at most
    /// [`JUMP_SPREAD`] across the cell's corners, and (where the table records the film intake,
    /// [`FilmIntake`]) its wet corners either all take in their film or all are partly covered by metal.
    /// Otherwise the cell holds a jump of the model that no interpolation follows — the hottest region of
    /// a hot wet contact losing its film, T_max rising by ~330 K within 0.2 % of creepage, or the onset of
    /// the walls, the friction of a wet contact rising by up to 0.03 within 1 % of p0 (docs/model.md
    /// §12.3) — and mode auto solves the point exactly.
    pub resolved: bool,
}

impl TableOutput {
    /// The outputs as numbers, in the order of the CLI's and the FMU's columns: F_x [N], F_y [N], M_z [N·m],
    /// traction coefficient, T_max [K], fluid load fraction, frictional power [W] (NaN where the table
    /// does not store it).
    pub fn values(&self) -> [f64; 7] {
        [
            self.force_x,
            self.force_y,
            self.spin_moment,
            self.traction_coefficient,
            self.max_temperature,
            self.fluid_load_fraction,
            self.frictional_power.unwrap_or(f64::NAN),
        ]
    }

    /// The outputs of an exact solution in the table's form (`in_range` true, `converged` from its report).
    /// A solution without a tabulated quantity (of a friction law that does not model it: only the
    /// Tomberger law models them all) is an error naming it.
    pub fn from_solution(s: &Solution) -> Result<TableOutput> {
        Self::from_results(&s.global, &s.report)
    }

    /// [`TableOutput::from_solution`] of a solution's global results and report.
    pub fn from_results(g: &GlobalResults, report: &SolverReport) -> Result<TableOutput> {
        let modelled = |name: &str, v: Option<f64>| {
            v.ok_or_else(|| Error::Table {
                path: "<exact solution>".into(),
                reason: format!(
                    "has no {name}: its friction law does not model it (tables are of the tomberger law)"
                ),
            })
        };
        Ok(TableOutput {
            force_x: g.force_x,
            force_y: g.force_y,
            spin_moment: modelled("spin moment", g.spin_moment)?,
            traction_coefficient: g.traction_coefficient,
            max_temperature: modelled("maximum temperature", g.max_temperature)?,
            fluid_load_fraction: modelled("fluid load fraction", g.fluid_load_fraction)?,
            frictional_power: Some(g.frictional_power),
            in_range: true,
            converged: report.converged,
            resolved: true,
        })
    }
}

/// Number of inputs of an evaluation that the Jacobian differentiates by: ξ, η, φ, F_N, V, w (the contact
/// ellipse held as it is, or growing with F_N as its load exponent says).
pub const INPUTS: usize = 6;

/// Derivatives of the interpolant: rows in the order of [`TableOutput`]'s values (F_x [N], F_y [N],
/// M_z [N·m], traction coefficient, T_max [K], fluid load fraction), columns ∂/∂(ξ, η, φ, F_N, V, w) in the
/// inputs' SI units, with the contact's semi-axes ∝ F_N^e ([`Ellipse::load_exponent`]). Zero along clamped
/// (out-of-range) inputs and where an output is clamped.
pub type Jacobian = [[f64; INPUTS]; JACOBIAN_ROWS];

/// Rows of a [`Jacobian`].
pub const JACOBIAN_ROWS: usize = 6;

/// The largest spread of the stored T_max across the corners of a cell that the table serves in mode auto
/// [K] ([`TableOutput::resolved`]). Measured on the running-surface table (10 × 10 cells, `table verify`
/// 2000 samples, seeds 1–3): cells of spread ≤ 300 K hold 95 % of the samples, whose T_max errs by p99
/// 6.0–6.8 K, max 9.9–13.8 K, against p99 23–37 K, max 100–154 K over all; 200 K: 88–89 % of the samples,
/// p99 5.6–5.9 K; 400 K: 96 %, max 25–35 K.
pub const JUMP_SPREAD: f64 = 300.0;

/// Number of nodes a loaded table is checked at ([`Table::check_probes`]).
pub const PROBES: usize = 3;

/// Largest difference allowed between a stored output at a probe node and the present exact solver, per
/// output (F_x/F_N, F_y/F_N, M_z/(F_N·c), T_max [K], fluid load fraction, P_f/(F_N·V)).
pub const PROBE_TOLERANCE: [f64; OUTPUTS] = [1e-6, 1e-6, 1e-6, 1e-3, 1e-6, 1e-6];

/// Values per stored point in memory: the outputs and their slopes along φ (three 4-wide vectors).
const ROW: usize = 2 * OUTPUTS;

/// One stored point in memory: the values at the positions `VAL` and `SLOPE`, in the stored precision,
/// 16-byte aligned so that no 4-wide load crosses a cache line.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C, align(16))]
struct Row([f32; ROW]);

const _: () = assert!(std::mem::size_of::<Row>() == ROW * 4);

/// Tables whose rows take more memory than this are prefetched during a lookup (a smaller table stays in
/// the caches, where prefetches are pure overhead), by a lookup in another cell than the thread's previous
/// one ([`LAST_CELL`]) [bytes].
const PREFETCH_ABOVE: usize = 8 << 20;

thread_local! {
    /// The rows (by [`rows_id`]) and the cell of this thread's last lookup in a table that prefetches.
    static LAST_CELL: std::cell::Cell<(usize, usize)> = const { std::cell::Cell::new((0, usize::MAX)) };
}

/// An identity of a table's rows while they live: their address. (A table allocated where a dropped one
/// was may find the dropped one's last cell: one lookup then skips its prefetches, which only hint.)
fn rows_id(rows: &[Row]) -> usize {
    rows.as_ptr() as usize
}

/// Positions in a row of output o's value and of its φ slope: values and slopes of outputs 0–1, 2–3 and 4–5
/// alternate in pairs. So the pairs a 16-byte vector holds are both values or both slopes, which keeps the
/// Hermite stage in registers.
const VAL: [usize; OUTPUTS] = [0, 1, 4, 5, 8, 9];
const SLOPE: [usize; OUTPUTS] = [2, 3, 6, 7, 10, 11];

/// Interpolated normalised outputs and their derivatives with respect to the (mirrored, clamped)
/// coordinates.
struct Core {
    v: [f64; OUTPUTS],
    d: [[f64; DIMS]; OUTPUTS],
    converged: bool,
    resolved: bool,
}

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
const PORTABLE: u8 = 0;
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
fn amd() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        let id = std::arch::x86_64::__cpuid(0);
        let vendor = [id.ebx, id.edx, id.ecx].map(u32::to_le_bytes);
        vendor.as_flattened() == b"AuthenticAMD"
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
}

/// A loaded table, read-only.
pub struct Table {
    sidecar: Sidecar,
    axes: Axes,
    interp: [AxisInterp; DIMS],
    /// Row strides of the dimensions in `rows` and `converged` (memory order, see `rows`).
    strides: [usize; DIMS],
    /// Per point, the outputs and their monotone slopes along φ (precomputed, see `core`), in memory
    /// order: C order over (ξ̂, η̂, F_N, V, w, a/b, p_ref, φ̂), φ̂ innermost, so that the two φ̂ ends of a
    /// corner the lookup reads are adjacent.
    rows: Vec<Row>,
    /// Per point in memory order: whether it converged (1) when the table was built.
    converged: Vec<u8>,
    /// Per point in memory order, the flags of the cell whose lowest corner it is: [`UNRESOLVED`] where it
    /// holds a jump of the model ([`TableOutput::resolved`], [`unresolved_cells`]), [`NEAR_UNCONVERGED`]
    /// where an evaluation in it may read an unconverged point ([`near_unconverged`]: a superset, which
    /// `core` narrows to the corners of non-zero weight); empty where no cell has either.
    cell_flags: Vec<u8>,
    /// Whether lookups prefetch the rows of the next ξ̂ window node (tables larger than `PREFETCH_ABOVE`;
    /// only in another cell than the thread's previous lookup).
    prefetch: bool,
    bulk_temperature: f64,
    /// The variable T_max is interpolated in: `rows` hold G(T_max) ([`RiseVariable`]).
    rise: RiseVariable,
    /// The table's coordinates of operating points.
    coordinates: Coordinates,
    /// Whether the table stores the frictional power (format version 2).
    has_power: bool,
    path: Option<PathBuf>,
    kernel: Kernel,
}

impl std::fmt::Debug for Table {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Table")
            .field("path", &self.path)
            .field("shape", &self.axes.shape())
            .field("fingerprint", &self.sidecar.fingerprint)
            .finish_non_exhaustive()
    }
}

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
        let mut rows = vec![Row::default(); len];
        let mut converged = vec![0; len];
        // the node's indices along the axes (the files' C order: the last axis fastest)
        let mut idx = [0; DIMS];
        for (i, m) in memory.iter().enumerate() {
            for (o, v) in VAL.iter().enumerate() {
                rows[*m].0[*v] = files.outputs[o][i];
            }
            // T_max is interpolated as G(T_max) (`rise`), the heat G and P_f/(F_N·V) per unit of the
            // direction factor Λ (`heating`)
            let lambda = heating.as_ref().map_or(1.0, |h| h.at(&idx));
            rows[*m].0[VAL[3]] = (rise.of(f64::from(files.outputs[3][i])) / lambda) as f32;
            rows[*m].0[VAL[5]] = (f64::from(files.outputs[5][i]) / lambda) as f32;
            converged[*m] = files.converged[i];
            for d in (0..DIMS).rev() {
                idx[d] += 1;
                if idx[d] < shape[d] {
                    break;
                }
                idx[d] = 0;
            }
        }
        // Steffen slopes along φ of every fibre (fixed ξ̂, η̂, F_N, V, w, a/b, p_ref; contiguous in memory;
        // the padding is whole fibres of zeros)
        // and output, computed in f64 from the stored values and kept in the stored precision (f32)
        let phi = &axes.0[PHI].points;
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
        let interp =
            std::array::from_fn(|d| AxisInterp::new(&axes.0[d], axes.0[d].interpolation(d)));
        // the cells' flags in the files' order, then in memory order
        let mut flags: Vec<u8> =
            unresolved_cells(&shape, &files.outputs[3], files.film_intake.as_deref())
                .iter()
                .map(|u| UNRESOLVED * u)
                .collect();
        if files.converged.iter().any(|c| *c != 1) {
            for (f, u) in flags
                .iter_mut()
                .zip(near_unconverged(&shape, &files.converged, &interp))
            {
                *f |= NEAR_UNCONVERGED * u;
            }
        }
        beside_unresolved(&shape, &mut flags);
        let mut cell_flags = Vec::new();
        if flags.iter().any(|f| *f != 0) {
            cell_flags = vec![0; len];
            for (m, f) in memory.iter().zip(flags) {
                cell_flags[*m] = f;
            }
        }
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
    fn exact_at_node(&self, n: usize) -> Result<(OperatingPoint, Ellipse, [f32; OUTPUTS])> {
        exact_at_node(&self.sidecar.params, &self.coordinates, &self.axes, n)
    }

    /// The probe tolerance of output `o`: [`PROBE_TOLERANCE`], plus half the code step of a table stored
    /// as u16 codes (rounding to the nearest code: e.g. 9e-6 of F/F_N, 0.005 K of T_max).
    fn probe_tolerance(&self, o: usize) -> f64 {
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
    pub fn check_probes(&self) -> Result<()> {
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

    /// The sidecar (parameters, axes, build record, …).
    pub fn sidecar(&self) -> &Sidecar {
        &self.sidecar
    }

    /// The axes.
    pub fn axes(&self) -> &Axes {
        &self.axes
    }

    /// The parameter set the table was built for.
    pub fn params(&self) -> &Params {
        &self.sidecar.params
    }

    /// Where the table was loaded from.
    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    /// Where the table was loaded from, for messages ("<memory>" if built in memory).
    pub fn location(&self) -> String {
        self.path()
            .map_or("<memory>".into(), |p| p.display().to_string())
    }

    /// Whether the table was built for exactly this parameter set (equivalently: the same fingerprint, since
    /// every value survives the sidecar's JSON bit for bit). Cheap enough to call per evaluation.
    pub fn matches(&self, params: &Params) -> bool {
        self.sidecar.params == *params
    }

    /// Whether the table stores the frictional power (format version 2).
    pub fn stores_frictional_power(&self) -> bool {
        self.has_power
    }

    /// How the table turns operating points and contacts into its coordinates.
    pub fn coordinates(&self) -> &Coordinates {
        &self.coordinates
    }

    /// Whether the operating point with contact `e` lies inside every axis range and its creepages within
    /// their raw limits. Invalid input (see [`Table::evaluate`]) is outside.
    pub fn in_range(&self, p: &OperatingPoint, e: &Ellipse) -> bool {
        p.validate().is_ok()
            && self.coordinates.of(p, e).is_ok_and(|at| {
                self.within_raw_limits(&at.raw)
                    && self.creepages_inside(&at.q)
                    && (FORCE..DIMS).all(|d| self.interp[d].clamp(at.q[d]).1)
            })
    }

    /// Whether the contact `e` at normal force `force` [N] lies inside the table's geometry axes (a/b and
    /// p_ref).
    pub fn covers(&self, e: &Ellipse, force: f64) -> bool {
        self.covers_geometry(self.coordinates.geometry(e, force))
    }

    /// Whether the geometry coordinates [a/b, p_ref] lie inside the table's geometry axes.
    fn covers_geometry(&self, geometry: [f64; 2]) -> bool {
        geometry
            .iter()
            .zip(&self.interp[RATIO..])
            .all(|(x, a)| a.clamp(*x).1)
    }

    /// Whether the raw creepages `raw` (ξ, η, φ of the located point, [`coords::Located::raw`]) lie within
    /// the raw limits of normalised creepage axes.
    fn within_raw_limits(&self, raw: &[f64; 3]) -> bool {
        raw.iter()
            .zip(&self.axes.0)
            .all(|(x, a)| a.raw_limit.is_none_or(|l| x.abs() <= l))
    }

    /// The error of a contact `e` at `force` [N] outside the table's geometry axes.
    pub fn outside_geometry(&self, e: &Ellipse, force: f64) -> Error {
        let range = |d: usize| {
            let a = &self.axes.0[d];
            format!("{} {} to {}", DIMENSIONS[d].symbol, a.min(), a.max())
        };
        Error::TableGeometry {
            path: self.location(),
            ratio: e.a / e.b,
            reference_pressure: self.coordinates.geometry(e, force)[1],
            covered: format!("{}, {} Pa", range(RATIO), range(PRESSURE)),
        }
    }

    /// Whether the creepage coordinates in `q` lie inside their axes, mirrored ones by their magnitude.
    fn creepages_inside(&self, q: &[f64; DIMS]) -> bool {
        (0..3).all(|d| {
            let x = if self.axes.0[d].mirrored || d == ETA {
                q[d].abs()
            } else {
                q[d]
            };
            self.interp[d].clamp(x).1
        })
    }

    /// Evaluates one operating point with contact ellipse `e` (its semi-axes at the point's normal force) by
    /// interpolation (no allocation). Invalid input (NaN, non-positive load, speed or semi-axes, …) is an
    /// error; a valid point outside the ranges is clamped (`in_range` false).
    pub fn evaluate(&self, point: &OperatingPoint, e: &Ellipse) -> Result<TableOutput> {
        let geometry = self.coordinates.geometry(e, point.normal_force);
        self.dispatch::<false>(point, e, geometry).map(|(o, _)| o)
    }

    /// [`Table::evaluate`] where the table covers the contact `e` at the point's normal force, None where
    /// it does not ([`Table::covers`]): the contact's geometry coordinates are computed once for both.
    pub fn evaluate_covered(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
    ) -> Option<Result<TableOutput>> {
        self.covered::<false>(point, e).map(|r| r.map(|(o, _)| o))
    }

    /// [`Table::evaluate_covered`] plus the Jacobian of the interpolant.
    pub fn evaluate_covered_with_jacobian(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
    ) -> Option<Result<(TableOutput, Jacobian)>> {
        self.covered::<true>(point, e)
    }

    /// The evaluation (with the Jacobian if `JAC`) where the table covers the contact `e`.
    fn covered<const JAC: bool>(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
    ) -> Option<Result<(TableOutput, Jacobian)>> {
        let geometry = self.coordinates.geometry(e, point.normal_force);
        self.covers_geometry(geometry)
            .then(|| self.dispatch::<JAC>(point, e, geometry))
    }

    /// [`Table::evaluate`] plus the Jacobian of the interpolant.
    pub fn evaluate_with_jacobian(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
    ) -> Result<(TableOutput, Jacobian)> {
        let geometry = self.coordinates.geometry(e, point.normal_force);
        self.dispatch::<true>(point, e, geometry)
    }

    /// The kernel the evaluations run with.
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// Runs the evaluations with `kernel` instead of the detected one (to compare kernels); an error if
    /// this CPU cannot run it.
    pub fn set_kernel(&mut self, kernel: Kernel) -> Result<()> {
        if !kernel.supported() {
            return Err(Error::Table {
                path: self.location(),
                reason: format!("the {kernel:?} kernel needs instructions this CPU does not have"),
            });
        }
        self.kernel = kernel;
        Ok(())
    }

    /// [`Table::eval`] compiled for the table's kernel.
    fn dispatch<const JAC: bool>(
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
    fn eval_avx2<const JAC: bool>(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
        geometry: [f64; 2],
    ) -> Result<(TableOutput, Jacobian)> {
        self.eval::<JAC, AVX2>(point, e, geometry)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx2,fma")]
    fn eval_avx512<const JAC: bool>(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
        geometry: [f64; 2],
    ) -> Result<(TableOutput, Jacobian)> {
        self.eval::<JAC, AVX512>(point, e, geometry)
    }

    /// The evaluation of `point` with contact `e`, whose geometry coordinates are `geometry`
    /// ([`Coordinates::geometry`]).
    #[inline(always)]
    fn eval<const JAC: bool, const K: u8>(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
        geometry: [f64; 2],
    ) -> Result<(TableOutput, Jacobian)> {
        point.validate()?;
        if !(e.a > 0.0 && e.b > 0.0 && e.a.is_finite() && e.b.is_finite()) {
            return Err(Error::out_of_range(
                "semi-axes",
                e.a.min(e.b),
                "finite and > 0 m",
            ));
        }
        let at = self.coordinates.of_geometry(point, e, geometry)?;
        let (signed, m) = (at.q, at.m);
        let (mut q, mx, my) = self.stored_quadrant(signed);
        let mut inside = [true; DIMS];
        for d in 0..DIMS {
            (q[d], inside[d]) = self.interp[d].clamp(q[d]);
        }
        let mut core = self.core::<JAC, K>(&q);
        // the heat is interpolated per unit of the direction factor Λ (`heating`): times the query's own
        let lambda = at.heating;
        let heat = core.v[3];
        core.v[3] *= lambda;
        core.v[5] *= lambda;
        // undo the mirrors: output signs S and input signs D (J = S·J'·D)
        let sx = if mx { -1.0 } else { 1.0 };
        let sy = if my { -1.0 } else { 1.0 };
        let out_sign = [sx, sy, sy, 1.0, 1.0, 1.0];
        let in_sign = [sx, sy, sy, 1.0, 1.0, 1.0, 1.0, 1.0];
        let mut g = [0.0; OUTPUTS];
        for (o, x) in g.iter_mut().enumerate() {
            *x = out_sign[o] * core.v[o];
        }
        let f = point.normal_force;
        let c = e.radius();
        let max_temperature = self.rise.temperature(core.v[3]);
        let out = TableOutput {
            force_x: f * g[0],
            force_y: f * g[1],
            spin_moment: f * c * g[2],
            // (|g| ≤ a few: no overflow to guard against, as hypot does at 5× the cost)
            traction_coefficient: (g[0] * g[0] + g[1] * g[1]).sqrt(),
            max_temperature: max_temperature.max(self.bulk_temperature),
            fluid_load_fraction: core.v[4].clamp(0.0, 1.0),
            frictional_power: self
                .has_power
                .then(|| (f * point.speed.abs() * core.v[5]).max(0.0)),
            in_range: inside.iter().all(|x| *x) && self.within_raw_limits(&at.raw),
            converged: core.converged,
            resolved: core.resolved,
        };
        let mut jac = [[0.0; INPUTS]; JACOBIAN_ROWS];
        if JAC {
            // derivatives of the normalised outputs g by the coordinates, in the caller's frame
            let mut dq = [[0.0; DIMS]; OUTPUTS];
            for o in 0..OUTPUTS {
                for d in 0..DIMS {
                    if inside[d] {
                        dq[o][d] = out_sign[o] * core.d[o][d] * in_sign[d];
                    }
                }
            }
            // chained to the inputs (ξ, η, φ, F_N, V, w): ∂q/∂(raw creepage), F_N through every
            // coordinate that moves with it (the creepage scales k through k·∂q/∂k, p_ref for semi-axes
            // ∝ F_N^e, with similarity the equivalent's spin and speed; `coords::Located`), V through its
            // coordinate
            let mut dg = [[0.0; INPUTS]; OUTPUTS];
            for o in 0..OUTPUTS {
                for d in 0..3 {
                    dg[o][d] = dq[o][d] * m[d].dx;
                }
                dg[o][FORCE] = (0..DIMS).map(|d| dq[o][d] * at.dlnf[d]).sum::<f64>() / f;
                dg[o][FORCE + 1] = dq[o][SPEED] * at.dv;
                dg[o][FORCE + 2] = dq[o][WET];
            }
            // G = Λ·Ĝ: Λ·∂Ĝ + Ĝ·∂Λ (Λ moves with ξ, η, φ and, through c·φ, with F_N)
            let dlambda = [
                at.dheating[0],
                at.dheating[1],
                at.dheating[2],
                at.dheating[3] / f,
                0.0,
                0.0,
            ];
            for (x, dl) in dg[3].iter_mut().zip(dlambda) {
                *x = lambda * *x + heat * dl;
            }
            let f_t = out.traction_coefficient;
            let t_free = max_temperature > self.bulk_temperature;
            let dt_dg = self.rise.temperature_slope(core.v[3]);
            let l_free = core.v[4] > 0.0 && core.v[4] < 1.0;
            for d in 0..INPUTS {
                jac[0][d] = f * dg[0][d];
                jac[1][d] = f * dg[1][d];
                jac[2][d] = f * c * dg[2][d];
                if f_t > 0.0 {
                    jac[3][d] = (g[0] * dg[0][d] + g[1] * dg[1][d]) / f_t;
                }
                jac[4][d] = if t_free { dt_dg * dg[3][d] } else { 0.0 };
                jac[5][d] = if l_free { dg[4][d] } else { 0.0 };
            }
            // the normalisation's own F_N dependence: F = F_N·g, M = F_N·c·g, c ∝ F_N^e
            jac[0][FORCE] += g[0];
            jac[1][FORCE] += g[1];
            jac[2][FORCE] += c * g[2] * (1.0 + e.load_exponent);
        }
        Ok((out, jac))
    }

    /// Table coordinates `q` brought into the stored quadrant ξ ≥ 0 (if the ξ axis is mirrored), η ≥ 0 (the
    /// η mirror also reverses φ), and whether the ξ and the η mirror were applied.
    #[inline(always)]
    pub(crate) fn stored_quadrant(&self, mut q: [f64; DIMS]) -> ([f64; DIMS], bool, bool) {
        let mx = q[XI] < 0.0 && self.axes.0[XI].mirrored;
        let my = q[ETA] < 0.0;
        if mx {
            q[XI] = -q[XI];
        }
        if my {
            q[ETA] = -q[ETA];
            q[PHI] = -q[PHI];
        }
        (q, mx, my)
    }

    /// Tensor-product interpolation at stored-quadrant coordinates `q` (inside the ranges).
    ///
    /// At each of the 4 × 4 (ξ̂, η̂) window points and the two ends of the φ̂ interval, the 16 corners of
    /// the linear stencil over (F_N, V, w, a/b, p_ref) (see `interp`) are contracted, for the values and their precomputed
    /// Steffen slopes along φ̂; the cubic Hermite along φ̂ follows (linear in values and slopes), then the
    /// monotone splines along η̂ and ξ̂ evaluated on the contracted values. With derivatives, each stage
    /// carries them forward (the fibre weights are the partial derivatives, see `interp`). Ghost points of
    /// mirrored axes read the mirror-image point (φ̂ index reversed by the η mirror, which also reverses the
    /// φ̂ slope) with the symmetry's output signs. Next to an unresolved cell along η̂ or ξ̂ (a jump of the
    /// model) the spline takes the one-sided slope at the shared node: the window node beyond is replaced by
    /// the extrapolation of the cell's secant ([`interp::CubicStencil::beyond`]; docs/model.md §12.3).
    #[inline(always)]
    fn core<const JAC: bool, const K: u8>(&self, q: &[f64; DIMS]) -> Core {
        const L: usize = LINEAR_DIMS;
        let cx = self.interp[XI].cubic(q[XI]);
        let cy = self.interp[ETA].cubic(q[ETA]);
        let (k0, hw, hdw) = self.interp[PHI].cubic(q[PHI]).hermite();
        // (loops, not `array::from_fn`, whose closures stay calls outside this kernel's instruction set)
        let mut fractions = [Fraction::default(); L];
        let mut linear_strides = [0; L];
        let st = &self.strides;
        for k in 0..L {
            fractions[k] = self.interp[FORCE + k].fraction(q[FORCE + k]);
            linear_strides[k] = st[FORCE + k];
        }
        let n_phi = self.axes.0[PHI].points.len() as isize;
        // the point's cell, by its lowest corner (which keeps the cell's flags)
        let cell = cx.lower() * st[XI]
            + cy.lower() * st[ETA]
            + k0.unsigned_abs() * st[PHI]
            + (0..L)
                .map(|k| fractions[k].start * linear_strides[k])
                .sum::<usize>();
        let flags = if self.cell_flags.is_empty() {
            0
        } else {
            self.cell_flags
                .get(cell)
                .copied()
                .unwrap_or(UNRESOLVED | NEAR_UNCONVERGED)
        };
        // prefetch only when this thread's previous lookup was in another cell (or table): in the same
        // cell the stencil is that lookup's, still in the caches
        let prefetch = self.prefetch && {
            let key = (rows_id(&self.rows), cell);
            LAST_CELL.with(|last| last.replace(key) != key)
        };
        let resolved = flags & UNRESOLVED == 0;
        // whether the cell's stencil holds an unconverged point: then which corners of non-zero weight do
        let check_converged = flags & NEAR_UNCONVERGED != 0;
        // the linear corners' row offsets from the creepage node and weights (with the Jacobian, also the
        // weights' derivatives)
        // (a value skips the corners beyond coordinates on a node, of weight 0; the Jacobian needs every
        // corner, whose weights' derivatives need not vanish with the weight)
        let stencil = if JAC {
            Offsets::of(&fractions, &linear_strides)
        } else {
            Offsets::of_value(&fractions, &linear_strides)
        };
        let dl = JAC.then(|| Corners::of(&fractions).dw);
        let (off, wl) = (&stencil.off[..stencil.n], &stencil.w[..stencil.n]);
        let max_off = stencil.farthest();
        let rows = &self.rows[..];
        // the lower φ̂ node of the interval at a window point: k0, or on a ghost η̂ node (φ̂ reversed) the
        // mirror image of k0 + 1, n_φ − 2 − k0, so that the φ̂ ends run backwards
        let lower = |fy: bool| if fy { n_phi - 2 - k0 } else { k0 } as usize;
        // the Hermite weights of node k0 and k0 + 1 per lane of a row vector ([value, value, slope, slope]),
        // for the lower and the upper row in memory: reversed on a ghost η̂ node (index 1)
        let ends = [[hw[0], hw[0], hw[1], hw[1]], [hw[2], hw[2], hw[3], hw[3]]];
        let hermite = [ends, [ends[1], ends[0]]];
        // stages 0 and 1: values [j][i·OUTPUTS + o] after φ (the layout of the η stage's lanes), with
        // derivatives [i][j][o][F_N, V, w, a/b, p_ref, φ]
        // (the derivatives only with the Jacobian: a value does not clear their 4.6 kB)
        let mut c1 = [[0.0; 4 * OUTPUTS]; 4];
        let mut t1_rows;
        let t1: &mut [[[[f64; L + 1]; OUTPUTS]; 4]] = if JAC {
            t1_rows = [[[[0.0; L + 1]; OUTPUTS]; 4]; 4];
            &mut t1_rows
        } else {
            &mut []
        };
        let mut converged = true;
        // prefetch the corner rows of ξ window node i + 1 (all η, both φ ends) while node i is computed: on a
        // table far larger than the caches the loads then find their lines on the way
        let prefetch_node = |i: isize| {
            #[cfg(target_arch = "x86_64")]
            {
                use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
                let p0 = rows.as_ptr().cast::<i8>();
                let ii = (cx.start + i).unsigned_abs();
                for j in 0..4 {
                    let gj = cy.start + j as isize;
                    let base = ii * st[XI] + gj.unsigned_abs() * st[ETA] + lower(gj < 0);
                    for o in off {
                        let ptr = p0.wrapping_add((base + *o) * std::mem::size_of::<Row>());
                        // SAFETY: a prefetch is only a hint: it never faults and changes no memory
                        // (the addresses are those of the corner's two rows in any case).
                        unsafe {
                            for line in [0, 2 * std::mem::size_of::<Row>() - 1] {
                                _mm_prefetch::<_MM_HINT_T0>(ptr.wrapping_add(line));
                            }
                        }
                    }
                }
            }
        };

        for i in 0..4 {
            if prefetch && i < 3 {
                prefetch_node(i as isize + 1);
            }
            let gi = cx.start + i as isize;
            let (ii, fx) = (gi.unsigned_abs(), gi < 0);
            // the η̂ window points of this ξ̂ node: first rows and Hermite weights
            let mut bases = [0; 4];
            let mut hs = [Hermite {
                ends: &hermite[0],
                signs: &SIGN_LANES[0],
            }; 4];
            for j in 0..4 {
                let gj = cy.start + j as isize;
                let (jj, fy) = (gj.unsigned_abs(), gj < 0);
                bases[j] = ii * st[XI] + jj * st[ETA] + lower(fy);
                hs[j] = Hermite {
                    ends: &hermite[usize::from(fy)],
                    signs: &SIGN_LANES[2 * usize::from(fx) + usize::from(fy)],
                };
            }
            if !JAC {
                let v = window_sums::<K>(rows, &bases, off, max_off, wl, &hs);
                for (c1j, v) in c1.iter_mut().zip(v) {
                    c1j[i * OUTPUTS..(i + 1) * OUTPUTS].copy_from_slice(&v);
                }
            }
            for (j, c1j) in c1.iter_mut().enumerate() {
                let fy = cy.start + (j as isize) < 0;
                let (base, h) = (bases[j], hs[j]);
                if JAC {
                    let mut pair = [0.0; 2 * ROW];
                    let v = corner_sum::<K, true>(rows, base, off, max_off, wl, h, &mut pair);
                    c1j[i * OUTPUTS..(i + 1) * OUTPUTS].copy_from_slice(&v);
                    let (sv, sd) = signs(fx, fy);
                    // the corner sums at the lower and the upper φ̂ node in memory; a0 at k0, a1 at k0 + 1
                    let (lo, hi) = pair.split_at(ROW);
                    let (a0, a1) = if fy { (hi, lo) } else { (lo, hi) };
                    // the corner sums with the weights' derivatives along each linear dimension
                    // instead of the weights, in memory order as `pair` (by the same kernel; its
                    // Hermite stage is not needed here); the rows at k0 and k0 + 1 start at m0, m1
                    let mut dpair = [[0.0; 2 * ROW]; L];
                    for (dp, dlk) in dpair.iter_mut().zip(dl.iter().flatten()) {
                        corner_sum::<K, true>(rows, base, off, max_off, &dlk[..off.len()], h, dp);
                    }
                    let (m0, m1) = if fy { (ROW, 0) } else { (0, ROW) };
                    for o in 0..OUTPUTS {
                        let (y0, d0) = (sv[o] * a0[VAL[o]], sd[o] * a0[SLOPE[o]]);
                        let (y1, d1) = (sv[o] * a1[VAL[o]], sd[o] * a1[SLOPE[o]]);
                        for (k, dp) in dpair.iter().enumerate() {
                            t1[i][j][o][k] = sv[o]
                                * (hw[0] * dp[m0 + VAL[o]] + hw[2] * dp[m1 + VAL[o]])
                                + sd[o] * (hw[1] * dp[m0 + SLOPE[o]] + hw[3] * dp[m1 + SLOPE[o]]);
                        }
                        t1[i][j][o][L] = hdw[0] * y0 + hdw[1] * d0 + hdw[2] * y1 + hdw[3] * d1;
                    }
                }
                if check_converged {
                    // the nodes the value depends on (corners of non-zero weight), as in both paths
                    converged &= off.iter().zip(wl).all(|(o, w)| {
                        *w == 0.0
                            || (self.converged[base + o] == 1 && self.converged[base + o + 1] == 1)
                    });
                }
            }
        }
        // next to a cell that holds a jump of the model (unresolved), the spline of this cell takes the
        // one-sided slope at the shared node: the window's node beyond is replaced by the extrapolation of
        // this cell's secant (its values, and with the Jacobian their derivatives)
        // (the cell's flags say which neighbours are unresolved: [`beside_unresolved`]; out of line, so that
        // the common path compiles as without)
        if flags & BESIDE_ETA != 0 {
            one_sided(&cy, BESIDE_UNRESOLVED[1], flags, &mut c1, t1);
        }
        // stage 2: along η, all 4·OUTPUTS fibres at once; derivatives (F_N, V, w, a/b, p_ref, φ, η)
        let mut c2 = [[0.0; OUTPUTS]; 4];
        let mut t2 = [[[0.0; L + 2]; OUTPUTS]; 4];
        if JAC {
            for i in 0..4 {
                for o in 0..OUTPUTS {
                    let f = cy.eval(&std::array::from_fn(|j| c1[j][i * OUTPUTS + o]));
                    c2[i][o] = f.v;
                    for a in 0..=L {
                        t2[i][o][a] = (0..4).map(|j| f.w[j] * t1[i][j][o][a]).sum();
                    }
                    t2[i][o][L + 1] = f.dv;
                }
            }
        } else {
            let flat = cy.value(&c1);
            for (i, c) in c2.iter_mut().enumerate() {
                c.copy_from_slice(&flat[i * OUTPUTS..(i + 1) * OUTPUTS]);
            }
        }
        if flags & BESIDE_XI != 0 {
            let derivatives = if JAC {
                std::slice::from_mut(&mut t2)
            } else {
                &mut []
            };
            one_sided(&cx, BESIDE_UNRESOLVED[0], flags, &mut c2, derivatives);
        }
        // stage 3: along ξ
        let mut v = [0.0; OUTPUTS];
        let mut d = [[0.0; DIMS]; OUTPUTS];
        if JAC {
            for o in 0..OUTPUTS {
                let f = cx.eval(&std::array::from_fn(|i| c2[i][o]));
                v[o] = f.v;
                let t: [f64; L + 2] =
                    std::array::from_fn(|a| (0..4).map(|i| f.w[i] * t2[i][o][a]).sum());
                d[o][XI] = f.dv;
                d[o][ETA] = t[L + 1];
                d[o][PHI] = t[L];
                d[o][FORCE..].copy_from_slice(&t[..L]);
            }
        } else {
            v = cx.value(&c2);
        }
        Core {
            v,
            d,
            converged,
            resolved,
        }
    }
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

/// The one-sided slopes of a cubic stage next to unresolved cells (`core`): in the window values `values`
/// and in every window of their derivatives `derivatives`, the node beyond the interval on each side whose
/// flag in `bits` (below, above) is set in the cell's `flags` becomes the extrapolation of the interval.
#[cold]
#[inline(never)]
fn one_sided<V: Lanes, D: Lanes>(
    window: &CubicStencil,
    bits: [u8; 2],
    flags: u8,
    values: &mut [V; 4],
    derivatives: &mut [[D; 4]],
) {
    for (bit, upper) in bits.into_iter().zip([false, true]) {
        if let Some(node) = window.beyond(upper).filter(|_| flags & bit != 0) {
            extrapolate(values, node);
            for d in derivatives.iter_mut() {
                extrapolate(d, node);
            }
        }
    }
}

/// Window values of a cubic stage (per window node: a flat array of lanes, or per lane its derivatives).
trait Lanes: Copy {
    fn lanes(&self) -> &[f64];
    fn lanes_mut(&mut self) -> &mut [f64];
}

impl<const N: usize> Lanes for [f64; N] {
    fn lanes(&self) -> &[f64] {
        self
    }
    fn lanes_mut(&mut self) -> &mut [f64] {
        self
    }
}

impl<const N: usize, const M: usize> Lanes for [[f64; N]; M] {
    fn lanes(&self) -> &[f64] {
        self.as_flattened()
    }
    fn lanes_mut(&mut self) -> &mut [f64] {
        self.as_flattened_mut()
    }
}

/// The window node `beyond` of [`interp::CubicStencil::beyond`], (beyond, near, far, r), set to the linear
/// extrapolation of the window's interval, y_beyond = (1 + r)·y_near − r·y_far, in every lane.
#[inline(always)]
fn extrapolate<T: Lanes>(window: &mut [T; 4], (beyond, near, far, r): (usize, usize, usize, f64)) {
    let (n, f) = (window[near], window[far]);
    for ((y, n), f) in window[beyond]
        .lanes_mut()
        .iter_mut()
        .zip(n.lanes())
        .zip(f.lanes())
    {
        *y = (1.0 + r) * n - r * f;
    }
}

/// The symmetry signs of a window point on a ghost ξ̂ node (`fx`) or a ghost η̂ node (`fy`), of the values
/// and of the φ̂ slopes per output: the ξ mirror flips F_x, the η mirror flips F_y and M_z and reverses φ̂
/// (the slopes flip once more).
#[inline(always)]
const fn signs(fx: bool, fy: bool) -> ([f64; OUTPUTS], [f64; OUTPUTS]) {
    let sx = if fx { -1.0 } else { 1.0 };
    let sy = if fy { -1.0 } else { 1.0 };
    ([sx, sy, sy, 1.0, 1.0, 1.0], [sx * sy, 1.0, 1.0, sy, sy, sy])
}

/// [`signs`] per kind of window point (2·[ghost ξ̂ node] + [ghost η̂ node]) in the row layout: per 4-wide
/// vector k of a row, the signs of the values of outputs 2k, 2k + 1 and of their slopes.
const SIGN_LANES: [[[f64; 4]; 3]; 4] = {
    let mut lanes = [[[0.0; 4]; 3]; 4];
    let mut g = 0;
    while g < 4 {
        let (sv, sd) = signs(g >> 1 == 1, g & 1 == 1);
        let mut k = 0;
        while k < 3 {
            lanes[g][k] = [sv[2 * k], sv[2 * k + 1], sd[2 * k], sd[2 * k + 1]];
            k += 1;
        }
        g += 1;
    }
    lanes
};

/// The Hermite weights along φ̂ of a window point: `ends`, per lane of a 4-wide vector of a row (values of
/// two outputs, then their slopes, the row layout `VAL`, `SLOPE`), for the lower and the upper row of a
/// corner's pair in memory; and the point's symmetry signs per vector k of a row ([`SIGN_LANES`]). The
/// weight of a lane is their product (exact: the signs are ±1).
#[derive(Clone, Copy)]
struct Hermite<'a> {
    ends: &'a [[f64; 4]; 2],
    signs: &'a [[f64; 4]; 3],
}

/// The Hermite stage of one window point from the corner sums of its row pair (`pair`: lower row, upper
/// row): per output o, (value and slope terms of lane o) summed as the vector kernel sums them.
#[inline(always)]
fn hermite_of(pair: &[f64; 2 * ROW], h: Hermite) -> [f64; OUTPUTS] {
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
fn corner_sum<const K: u8, const PAIR: bool>(
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
fn window_sums<const K: u8>(
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
unsafe fn window_sums_avx512(
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
unsafe fn corner_sum_avx2<const PAIR: bool>(
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
fn hermite_avx2<const PAIR: bool>(
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

/// Flag of a cell holding a jump of the model ([`unresolved_cells`]).
const UNRESOLVED: u8 = 1;
/// Flag of a cell whose stencil holds an unconverged point ([`near_unconverged`]).
const NEAR_UNCONVERGED: u8 = 2;
/// Flags of a cell whose neighbour cell below and above it along ξ̂ (first pair) and η̂ (second) holds a
/// jump of the model ([`beside_unresolved`]).
const BESIDE_UNRESOLVED: [[u8; 2]; 2] = [[4, 8], [16, 32]];
/// Any of the ξ̂, resp. η̂, flags of [`BESIDE_UNRESOLVED`].
const BESIDE_XI: u8 = BESIDE_UNRESOLVED[0][0] | BESIDE_UNRESOLVED[0][1];
const BESIDE_ETA: u8 = BESIDE_UNRESOLVED[1][0] | BESIDE_UNRESOLVED[1][1];

/// Sets in `flags` (per point of a table of `shape`, C order: the flags of the cell whose lowest corner it
/// is) the [`BESIDE_UNRESOLVED`] flags of every cell whose neighbour along ξ̂ or η̂ is [`UNRESOLVED`]: its
/// spline along that axis takes the one-sided slope at their shared node (`core`).
fn beside_unresolved(shape: &[usize; DIMS], flags: &mut [u8]) {
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
fn unresolved_cells(shape: &[usize; DIMS], t: &[f32], film: Option<&[u8]>) -> Vec<u8> {
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
fn near_unconverged(
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
fn over_cells<T: Copy>(shape: &[usize; DIMS], mut v: Vec<T>, f: impl Fn(T, T) -> T) -> Vec<T> {
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

/// The row strides of a table of `shape` in memory order: C order over (ξ̂, η̂, F_N, V, w, a/b, p_ref, φ̂).
fn memory_strides(shape: &[usize; DIMS]) -> [usize; DIMS] {
    let mut strides = unpadded_strides(shape);
    strides[XI] += slab_padding(shape, &strides);
    strides
}

/// [`memory_strides`] without the padding of the ξ̂ slabs: the points contiguous.
fn unpadded_strides(shape: &[usize; DIMS]) -> [usize; DIMS] {
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
const LINE: usize = 64;

/// The rows of padding after each ξ̂ slab of a table of `shape` with unpadded `strides` (memory order): the
/// whole fibres along φ̂, at most 63 and a sixteenth of a slab, that leave the fewest of a lookup's lines
/// beyond the ways of an L1 set ([`l1_crowding`]), the fewest of those. Why: a stride that is a multiple of
/// 4 KB maps the four ξ̂ window nodes of every row to the same set. The whole-range table's ξ̂ slab is
/// 1 488 384 rows of 48 bytes, exactly 17 442 pages, so its stencil of ≈ 430 lines put up to 20 in one set
/// (≈ 180 lines per lookup beyond 8 ways); 16 fibres of padding (0.02 % more memory) leave none beyond
/// (at most 8 per set), and the same wet lookup took 510 instead of 540 ns.
fn slab_padding(shape: &[usize; DIMS], strides: &[usize; DIMS]) -> usize {
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
fn l1_crowding(shape: &[usize; DIMS], strides: &[usize; DIMS]) -> usize {
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
fn memory_index(shape: &[usize; DIMS], strides: &[usize; DIMS], flat: usize) -> usize {
    let mut rest = flat;
    let mut m = 0;
    for d in (0..DIMS).rev() {
        m += (rest % shape[d]) * strides[d];
        rest /= shape[d];
    }
    m
}

/// A table in memory from node values `f(coordinates) -> outputs` (for tests).
#[cfg(test)]
pub(crate) fn synthetic(
    axes: &Axes,
    params: &Params,
    f: &dyn Fn(&[f64; DIMS]) -> [f64; OUTPUTS],
) -> Table {
    Table::from_files(tabulate(params, axes, f), None).unwrap()
}

/// Axes with explicit points per dimension (ξ̂, η̂, φ̂, F_N, V, w, a/b, p_ref), ξ̂ mirrored (stored ξ̂ ≥ 0),
/// raw limits of the creepages `raw`.
#[cfg(test)]
fn explicit_axes(points: [&[f64]; DIMS], raw: [f64; 3]) -> Axes {
    let spec = |d: usize| {
        Some(AxisSpec {
            points: Some(points[d].to_vec()),
            mirrored: (d == XI).then_some(true),
            raw_limit: raw.get(d).copied(),
            ..Default::default()
        })
    };
    Axes::from_spec(&AxesSpec {
        creepage_x: spec(0),
        creepage_y: spec(1),
        spin: spec(2),
        normal_force: spec(3),
        speed: spec(4),
        wetness: spec(5),
        semi_axis_ratio: spec(6),
        reference_pressure: spec(7),
    })
    .expect("valid axes")
}

/// The axes of the small test table `tests/fixtures/small-axes.toml` (1152 points around the default
/// operating point and contact), which the FMU's and the command line's tests and benchmarks read from the
/// file.
#[cfg(test)]
pub(crate) fn small_axes() -> Axes {
    let spec: AxesSpec = toml::from_str(include_str!("../../tests/fixtures/small-axes.toml"))
        .expect("the fixture is an axes file");
    Axes::from_spec(&spec).expect("valid axes")
}

/// The default parameters on a coarse 6 × 6 grid: a table over [`tiny_axes`] builds in a fraction of a
/// second.
#[cfg(test)]
pub(crate) fn coarse_params() -> Params {
    let mut p = Params::default();
    p.grid.nx = 6;
    p.grid.ny = 6;
    p
}

/// Small valid axes (3·3·4·2·2·2·2·2 = 1152 points) around the default contact (a/b ≈ 0.56, p_ref ≈
/// 0.77 GPa), wider than [`small_axes`]: ξ̂ ≤ 10 (|ξ| up to about 5 %), η̂ ≤ 4 (|η| ≤ 2 %), |φ̂| ≤ 0.5
/// (|φ| up to about 1.4 /m).
#[cfg(test)]
pub(crate) fn tiny_axes() -> Axes {
    explicit_axes(
        [
            &[0.0, 1.0, 10.0],
            &[0.0, 0.6, 4.0],
            &[-0.5, -0.1, 0.1, 0.5],
            &[50e3, 100e3],
            &[10.0, 30.0],
            &[0.0, 1.0],
            &[0.5, 0.6],
            &[0.7e9, 0.85e9],
        ],
        [0.1, 0.03, 2.0],
    )
}

/// The error of evaluating `table` for `params` if it was built for other parameters (None if it was
/// built for them).
pub fn not_matching(table: &Table, params: &Params) -> Option<Error> {
    (!table.matches(params)).then(|| other_parameters(table, params))
}

/// The error of `table` asked to evaluate for `params`, which are not those it was built for.
pub fn other_parameters(table: &Table, params: &Params) -> Error {
    Error::TableParameters {
        path: table.location(),
        built: table.sidecar.fingerprint.clone(),
        given: file::fingerprint(params),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::FrictionLaw;

    /// A function with the model's symmetries, linear in each creepage coordinate and affine in the linear
    /// ones: the interpolant reproduces it exactly. Monomials x^a·y^b·φ^c: the ξ mirror multiplies them by
    /// (−1)^a, the (η, φ) mirror by (−1)^(b+c). F_x: odd, even; F_y and M_z: even, odd; T: even, even.
    fn symmetric_multilinear(c: &[f64; DIMS]) -> [f64; OUTPUTS] {
        let [x, y, p, f, v, w, r, pr] = *c;
        let lin = 1.0 + 2e-6 * f - 0.003 * v + 0.5 * w + 0.2 * r - 1e-10 * pr;
        [
            lin * (-0.03 * x + 0.04 * x * y * p),
            lin * (-0.02 * y + 0.01 * p),
            lin * (0.02 * p - 0.007 * y),
            300.0 + 50.0 * lin * (1.0 + 0.04 * y * p),
            0.3 * w + 0.001 * v,
            lin * (0.01 + 0.002 * x * x + 0.003 * y * p),
        ]
    }

    /// A smooth function with the symmetries and creep-curve-like saturation (not reproduced exactly).
    fn symmetric_saturating(c: &[f64; DIMS]) -> [f64; OUTPUTS] {
        let [x, y, p, f, v, w, r, pr] = *c;
        let lin = (1.0 + 2e-6 * f) * (1.0 - 0.003 * v) * (1.0 + 0.5 * w) * (1.0 + 0.1 * r)
            / (1.0 + 1e-10 * pr);
        let sat = |u: f64| (u / 0.5).tanh();
        [
            -lin * sat(x) * (1.0 + 0.3 * y * p),
            -lin * (sat(y) + 0.02 * p),
            lin * (0.02 * p - sat(y) * (1.0 + 0.01 * x * x)),
            300.0 + 50.0 * lin * (0.01 * x * x + y * p),
            0.3 * w * (1.0 - 0.002 * v),
            0.05 * lin * sat(x).abs(),
        ]
    }

    /// Random table coordinates inside [`tiny_axes`] whose raw creepages lie within its raw limits.
    fn random_coordinates(rng: &mut verify::SplitMix64) -> [f64; DIMS] {
        let mut u = || rng.uniform();
        [
            -8.0 + 16.0 * u(),
            -3.0 + 6.0 * u(),
            -0.4 + 0.8 * u(),
            50e3 + 50e3 * u(),
            10.0 + 20.0 * u(),
            u(),
            0.5 + 0.1 * u(),
            0.7e9 + 0.15e9 * u(),
        ]
    }

    /// `axes` (with one normal force point, F_ref among them) as a table by similarity: the normal force
    /// axis F_ref alone, the speed points equivalent speeds.
    fn similar(mut axes: Axes) -> Axes {
        axes.0[FORCE].points = vec![axes::REFERENCE_FORCE];
        axes.0[FORCE].logarithmic = false;
        axes.0[SPEED].similarity = true;
        axes.validate().unwrap();
        axes
    }

    /// The operating point and contact of table coordinates `q`, the contact's semi-axes growing with the
    /// load like F_N^e.
    fn at(t: &Table, q: &[f64; DIMS], e: f64) -> (OperatingPoint, Ellipse) {
        let (p, mut el) = t.coordinates().point(q).unwrap();
        el.load_exponent = e;
        (p, el)
    }

    /// The point and contact with input d (ξ, η, φ, F_N, V, w) moved by h (the semi-axes follow F_N).
    fn moved(p: &OperatingPoint, e: &Ellipse, d: usize, h: f64) -> (OperatingPoint, Ellipse) {
        let mut p = *p;
        let mut e = *e;
        match d {
            0 => p.creepage_x += h,
            1 => p.creepage_y += h,
            2 => p.spin += h,
            3 => {
                let s = ((p.normal_force + h) / p.normal_force).powf(e.load_exponent);
                p.normal_force += h;
                e.a *= s;
                e.b *= s;
            }
            4 => p.speed += h,
            _ => p.wetness += h,
        }
        (p, e)
    }

    /// The six outputs of normalised values `v` at point `p` with contact `e`.
    fn physical(p: &OperatingPoint, e: &Ellipse, v: &[f64; OUTPUTS]) -> [f64; JACOBIAN_ROWS] {
        let f = p.normal_force;
        [
            f * v[0],
            f * v[1],
            f * e.radius() * v[2],
            v[0].hypot(v[1]),
            v[3],
            v[4],
        ]
    }

    /// [`tiny_axes`] with knee-blended creepage coordinates (raw scales near the default contact's k).
    fn blended(mut axes: Axes) -> Axes {
        for (d, k) in [200.0, 170.0, 0.4].into_iter().enumerate() {
            axes.0[d].raw_scale = Some(k);
        }
        axes.validate().unwrap();
        axes
    }

    /// `axes` (knee-blended) with the spin's raw scale in proportion to the contact's size sqrt(a² + b²),
    /// 0.4 m at 6 mm: k_r moves with the contact's shape, size and (similarity) load.
    fn sized(mut axes: Axes) -> Axes {
        axes.0[PHI].raw_length = Some(6e-3);
        axes.validate().unwrap();
        axes
    }

    /// The linear dimensions of [`tiny_axes`] that can be interpolated in ln x (all but w), with a point
    /// of each axis.
    const LOG_DIMS: [(usize, f64); 4] = [
        (FORCE, 50e3),
        (SPEED, 10.0),
        (RATIO, 0.5),
        (PRESSURE, 0.7e9),
    ];

    /// `axes` with F_N, V, a/b and p_ref interpolated in ln x.
    fn logarithmic(mut axes: Axes) -> Axes {
        for (d, _) in LOG_DIMS {
            axes.0[d].logarithmic = true;
        }
        axes.validate().unwrap();
        axes
    }

    /// [`symmetric_multilinear`] of x0·(1 + ln(x/x0)) instead of x along F_N, V, a/b, p_ref: multilinear
    /// in their logarithms, the data class log axes reproduce.
    fn symmetric_multilinear_in_logs(c: &[f64; DIMS]) -> [f64; OUTPUTS] {
        let mut l = *c;
        for (d, x0) in LOG_DIMS {
            l[d] = x0 * (1.0 + (c[d] / x0).ln());
        }
        symmetric_multilinear(&l)
    }

    /// [`tiny_axes`] with a third speed point, 20 m/s, and the cell 20–30 m/s interpolated in √V if `sqrt`.
    fn sqrt_speeds(sqrt: bool) -> Axes {
        let mut axes = tiny_axes();
        axes.0[SPEED].points = vec![10.0, 20.0, 30.0];
        axes.0[SPEED].sqrt_from = sqrt.then_some(20.0);
        axes.validate().unwrap();
        axes
    }

    /// [`symmetric_multilinear`] of s(V) = V up to 20 m/s, 20 + 2√20·(√V − √20) above (C¹ at 20 m/s)
    /// instead of V: the data class of [`sqrt_speeds`] (linear in V in the first cell, in √V in the second).
    fn symmetric_multilinear_in_sqrt_speed(c: &[f64; DIMS]) -> [f64; OUTPUTS] {
        let mut l = *c;
        let r = 20f64.sqrt();
        if c[SPEED] > 20.0 {
            l[SPEED] = 20.0 + 2.0 * r * (c[SPEED].sqrt() - r);
        }
        symmetric_multilinear(&l)
    }

    /// `f` with its heat outputs read as what tables of `params` with `axes` interpolate: T_max's as the
    /// variable G ([`rise`]) and both T_max's and P_f/(F_N·V)'s per unit of the direction factor Λ of the
    /// point ([`heating`]). The table of the wrapped function stores T_max = G⁻¹(Λ·f's value) and Λ·f's
    /// P_f, so f's values are the data class the interpolant reproduces (f's values 300–400 K as G are T_max
    /// of about 600–700 K, through the yield-stress anomaly; Λ puts FASTSIM's kinks at η = 0, φ = 0 into
    /// the data).
    fn in_rise(
        params: &Params,
        axes: &Axes,
        f: impl Fn(&[f64; DIMS]) -> [f64; OUTPUTS],
    ) -> impl Fn(&[f64; DIMS]) -> [f64; OUTPUTS] {
        let rise = RiseVariable::new(&params.material);
        let coordinates = Coordinates::new(params, axes);
        move |c| {
            let (p, e) = coordinates.point(c).unwrap();
            let lambda = coordinates.of(&p, &e).unwrap().heating;
            let mut v = f(c);
            v[3] = rise.temperature(lambda * v[3]);
            v[5] *= lambda;
            v
        }
    }

    #[test]
    fn interpolant_reproduces_symmetric_multilinear_functions_and_their_derivatives() {
        let params = coarse_params();
        for axes in [
            tiny_axes(),
            blended(tiny_axes()),
            sized(blended(tiny_axes())),
        ] {
            let f = in_rise(&params, &axes, symmetric_multilinear);
            reproduces(&synthetic(&axes, &params, &f), &f);
        }
        // log axes: exact for data multilinear in the logarithms (and not for data multilinear in x)
        let log_axes = logarithmic(tiny_axes());
        let f_log = in_rise(&params, &log_axes, symmetric_multilinear_in_logs);
        let log = synthetic(&log_axes, &params, &f_log);
        reproduces(&log, &f_log);
        let f = in_rise(&params, &log_axes, symmetric_multilinear);
        let t = synthetic(&log_axes, &params, &f);
        let c = [0.0, 0.0, 0.0, 75e3, 10.0, 0.5, 0.5, 0.7e9];
        let (p, e) = at(&t, &c, 0.0);
        // G = 300 + 50·(1 + 2e-6·F_N + …): F_N interpolated at ln(1.5)/ln(2) of its cell, not at 1/2
        let off =
            t.rise.of(t.evaluate(&p, &e).unwrap().max_temperature) - symmetric_multilinear(&c)[3];
        assert!(
            (off - 50.0 * 2e-6 * 50e3 * (1.5f64.ln() / 2f64.ln() - 0.5)).abs() < 1e-4,
            "{off}"
        );
        // speed cells in √V from sqrt_from on: exact for data linear in V below and in √V above; the
        // same nodes interpolated in V miss them in the √V cell
        let axes = sqrt_speeds(true);
        let f_sqrt = in_rise(&params, &axes, symmetric_multilinear_in_sqrt_speed);
        reproduces(&synthetic(&axes, &params, &f_sqrt), &f_sqrt);
        let axes = sqrt_speeds(false);
        let f_sqrt = in_rise(&params, &axes, symmetric_multilinear_in_sqrt_speed);
        let t = synthetic(&axes, &params, &f_sqrt);
        let c = [0.0, 0.0, 0.0, 75e3, 25.0, 0.5, 0.5, 0.7e9];
        let (p, e) = at(&t, &c, 0.0);
        let off = t.rise.of(t.evaluate(&p, &e).unwrap().max_temperature)
            - symmetric_multilinear_in_sqrt_speed(&c)[3];
        // G's speed term −0.15·s: s(25) = 20 + 2·(√500 − 20), the cell's middle in V (s(20) + s(30))/2 = √600
        let missed = 20.0 + 2.0 * (500f64.sqrt() - 20.0) - 600f64.sqrt();
        assert!((off - 0.15 * missed).abs() < 1e-4, "{off} {missed}");
    }

    /// The interpolant of `f` (a function the table reproduces exactly) and its Jacobian (through the
    /// table's coordinates, plain or knee-blended) at 500 random points.
    fn reproduces(t: &Table, f: &dyn Fn(&[f64; DIMS]) -> [f64; OUTPUTS]) {
        let mut rng = verify::SplitMix64::new(7);
        for n in 0..500 {
            let c = random_coordinates(&mut rng);
            let exponent = if n % 2 == 0 { 0.0 } else { Ellipse::HERTZ };
            let (pt, e) = at(t, &c, exponent);
            let (o, j) = t.evaluate_with_jacobian(&pt, &e).unwrap();
            let want = f(&c);
            let force = c[FORCE];
            assert!(o.in_range && o.converged, "{c:?}");
            assert!((o.force_x / force - want[0]).abs() < 1e-6, "{c:?}");
            assert!((o.force_y / force - want[1]).abs() < 1e-6, "{c:?}");
            assert!(
                (o.spin_moment / (force * e.radius()) - want[2]).abs() < 1e-6,
                "{c:?}"
            );
            assert!((o.max_temperature - want[3]).abs() < 1e-4, "{c:?}");
            assert!((o.fluid_load_fraction - want[4]).abs() < 1e-6);
            let power = o.frictional_power.unwrap() / (force * pt.speed);
            assert!((power - want[5]).abs() < 1e-6, "{c:?}");
            // Jacobian against central differences of the exact function through the coordinates
            for d in 0..INPUTS {
                let h = [1e-8, 1e-8, 1e-6, 1.0, 1e-4, 1e-6][d];
                let exact = |h: f64| {
                    let (p, e) = moved(&pt, &e, d, h);
                    let q = t.coordinates().of(&p, &e).unwrap().q;
                    physical(&p, &e, &f(&q))
                };
                let (pp, pm) = (exact(h), exact(-h));
                for o in 0..JACOBIAN_ROWS {
                    let fd = (pp[o] - pm[o]) / (2.0 * h);
                    let scale = [force, force, force * e.radius(), 1.0, 700.0, 1.0][o]
                        / [0.05, 0.02, 1.0, 1e5, 20.0, 1.0][d];
                    // the node values are stored in f32: their rounding (relative 6e-8) over node
                    // spacings; T_max (650–800 K) rounded as stored (6e-5 K) becomes G with dG/dT up
                    // to 3.2 in the yield-stress anomaly
                    let tolerance = if o == 4 { 1e-3 } else { 1e-4 };
                    assert!(
                        (j[o][d] - fd).abs() < tolerance * (fd.abs() + 1e-2 * scale),
                        "∂{o}/∂{d} at {c:?} (e {exponent}): {} vs {fd}",
                        j[o][d]
                    );
                }
            }
        }
    }

    /// FASTSIM's frictional heat has kinks at η = 0 and φ = 0 (its combined flexibility, `heating`): T_max
    /// and P_f rise like |η| and |φ| from there on both sides. A table built by the exact solver (a/b 0.72,
    /// p0 1.51 GPa, 158 m/s, dry, ξ 0.2 %) follows them a third into the cells beside η̂ = 0 and φ̂ = 0
    /// (T_max rising by 20 and 54 K over them): measured 0.07 and −2.2 K off, P_f 6e-5 and 1.6 % — where
    /// the heat itself interpolated (Λ ≡ 1) lags by −2.4 and −7.4 K, P_f by 8.5 and 13 % (the spline's
    /// slope is 0 at those nodes: the η mirror's ghost nodes, Steffen's limit where the secants change
    /// sign).
    #[test]
    fn the_heat_follows_fastsims_kinks_across_zero_lateral_and_spin_creepage() {
        let mut params = Params::default();
        params.grid.nx = 10;
        params.grid.ny = 10;
        let axes = explicit_axes(
            [
                &[0.0, 0.2, 0.4, 0.8],
                &[0.0, 0.1, 0.2, 0.4],
                &[-0.2, -0.1, 0.0, 0.1, 0.2],
                &[100e3],
                &[158.0],
                &[0.0],
                &[0.72],
                &[1.51e9],
            ],
            [0.1, 0.1, 10.0],
        );
        let coords = Coordinates::new(&params, &axes);
        let exact = |q: &[f64; DIMS]| {
            let (point, e) = coords.point(q).unwrap();
            let mut p = params.clone();
            p.geometry.semi_axes = Some([e.a, e.b]);
            let s = crate::solver::solve(&p, &point).unwrap();
            assert!(s.report.converged);
            (build::normalised(&s, &point, e.radius()).unwrap(), point, e)
        };
        let t = synthetic(&axes, &params, &|q| exact(q).0.map(f64::from));
        for (d, h) in [(ETA, 0.1), (PHI, 0.1)] {
            let mut q = [0.2, 0.0, 0.0, 100e3, 158.0, 0.0, 0.72, 1.51e9];
            let t0 = exact(&q).0[3];
            q[d] = h;
            let rise = f64::from(exact(&q).0[3] - t0);
            q[d] = h / 3.0;
            let (want, point, e) = exact(&q);
            let got = t.evaluate(&point, &e).unwrap();
            let err = got.max_temperature - f64::from(want[3]);
            let power = got.frictional_power.unwrap() / (point.normal_force * point.speed);
            let power_err = power / f64::from(want[5]) - 1.0;
            assert!(
                rise > 15.0 && err.abs() < 0.06 * rise && power_err.abs() < 0.03,
                "along {d}: T_max rises by {rise:.1} K over the cell; a third into it {err:.2} K off, \
                 P_f {power_err:.1e}"
            );
        }
    }

    #[test]
    fn cells_across_which_t_max_jumps_are_not_resolved() {
        let params = coarse_params();
        let smooth = synthetic(&tiny_axes(), &params, &symmetric_saturating);
        assert!(smooth.cell_flags.is_empty());
        // T_max 400 K higher at the last ξ̂ node (10): the cells between ξ̂ = 1 and 10 hold the jump, for
        // both signs of ξ (the axis is mirrored); the smooth variation spreads by < 100 K across any cell
        let jump = |c: &[f64; DIMS]| {
            let mut o = symmetric_saturating(c);
            o[3] += if c[XI].abs() > 5.0 { 400.0 } else { 0.0 };
            o
        };
        let t = synthetic(&tiny_axes(), &params, &jump);
        let mut rng = verify::SplitMix64::new(17);
        let mut seen = [0; 2];
        for _ in 0..500 {
            let c = random_coordinates(&mut rng);
            let (p, e) = at(&t, &c, Ellipse::HERTZ);
            let o = t.evaluate(&p, &e).unwrap();
            assert!(o.in_range);
            assert_eq!(o.resolved, c[XI].abs() < 1.0, "{c:?}");
            assert!(smooth.evaluate(&p, &e).unwrap().resolved);
            seen[usize::from(o.resolved)] += 1;
        }
        assert!(seen.iter().all(|n| *n > 20), "{seen:?}");
    }

    /// A table over `axes` of `f` with the film-intake code `film(c)` at each node c.
    fn with_film_intake(
        axes: &Axes,
        f: &dyn Fn(&[f64; DIMS]) -> [f64; OUTPUTS],
        film: &dyn Fn(&[f64; DIMS]) -> FilmIntake,
    ) -> Table {
        let mut files = tabulate(&coarse_params(), axes, f);
        files.film_intake = Some(
            (0..axes.len())
                .map(|i| film(&axes.coordinates(i)) as u8)
                .collect(),
        );
        Table::from_files(files, None).unwrap()
    }

    #[test]
    fn cells_straddling_the_onset_of_the_walls_are_not_resolved() {
        // wet nodes: the metal covers part of the contact at the high p_ref node where |ξ̂| = 10 (a hot
        // contact reaches the onset first); dry nodes: no film. Only the cells between ξ̂ = 1 and 10 have a
        // corner of each wet kind; the T_max of `symmetric_saturating` spreads by < 100 K (no jump)
        let wet_onset =
            |c: &[f64; DIMS]| match (c[WET] > 0.0, c[XI].abs() > 5.0 && c[PRESSURE] > 0.8e9) {
                (false, _) => FilmIntake::Dry,
                (true, true) => FilmIntake::Limited,
                (true, false) => FilmIntake::All,
            };
        let t = with_film_intake(&tiny_axes(), &symmetric_saturating, &wet_onset);
        // every wet node covered: dry and covered corners straddle nothing
        let covered = |c: &[f64; DIMS]| {
            if c[WET] > 0.0 {
                FilmIntake::Limited
            } else {
                FilmIntake::Dry
            }
        };
        let all = with_film_intake(&tiny_axes(), &symmetric_saturating, &covered);
        assert!(all.cell_flags.is_empty());
        let mut rng = verify::SplitMix64::new(5);
        let mut seen = [0; 2];
        for _ in 0..500 {
            let c = random_coordinates(&mut rng);
            let (p, e) = at(&t, &c, Ellipse::HERTZ);
            let o = t.evaluate(&p, &e).unwrap();
            assert_eq!(o.resolved, c[XI].abs() < 1.0, "{c:?}");
            assert!(all.evaluate(&p, &e).unwrap().resolved);
            seen[usize::from(o.resolved)] += 1;
        }
        assert!(seen.iter().all(|n| *n > 20), "{seen:?}");
    }

    #[test]
    fn film_intake_codes_round_trip_through_every_storage_and_bad_codes_are_refused() {
        let axes = tiny_axes();
        let mut files = tabulate(&coarse_params(), &axes, &symmetric_saturating);
        let codes: Vec<u8> = (0..axes.len()).map(|i| (i % 3) as u8).collect();
        let dir =
            std::env::temp_dir().join(format!("wheelrail-film-intake-{}", std::process::id()));
        // a table without the codes (built before they were recorded) reads without them
        files.write(&dir.join("none")).unwrap();
        assert_eq!(
            TableFiles::read(&dir.join("none")).unwrap().film_intake,
            None
        );
        files.film_intake = Some(codes.clone());
        for storage in [Storage::F32, Storage::U16, Storage::U16z, Storage::U16x] {
            let mut f = files.clone();
            f.sidecar.storage = storage;
            let d = dir.join(storage.to_string());
            f.write(&d).unwrap();
            let back = TableFiles::read(&d).unwrap();
            assert_eq!(back.film_intake.as_deref(), Some(&codes[..]), "{storage}");
            assert_eq!(back.sidecar.film_intake.unwrap().name, "film_intake");
        }
        // a code beyond 2 (with a matching hash) is refused naming the file
        let mut bad = files.clone();
        bad.film_intake.as_mut().unwrap()[7] = 3;
        bad.write(&dir.join("bad")).unwrap();
        let e = TableFiles::read(&dir.join("bad")).unwrap_err().to_string();
        assert!(
            e.contains("film_intake.npy") && e.contains("holds 3"),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn every_kernel_this_cpu_runs_agrees_with_the_portable_one() {
        let params = coarse_params();
        let mut t = synthetic(&tiny_axes(), &params, &symmetric_saturating);
        assert_eq!(t.kernel(), Kernel::detect());
        assert!(t.set_kernel(Kernel::Portable).is_ok());
        let mut rng = verify::SplitMix64::new(5);
        let points: Vec<(OperatingPoint, Ellipse)> = (0..500)
            .map(|_| at(&t, &random_coordinates(&mut rng), Ellipse::HERTZ))
            .collect();
        let reference: Vec<(TableOutput, Jacobian)> = points
            .iter()
            .map(|(p, e)| {
                (
                    t.evaluate(p, e).unwrap(),
                    t.evaluate_with_jacobian(p, e).unwrap().1,
                )
            })
            .collect();
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (a.abs() + b.abs());
        let mut compared = 0;
        for kernel in Kernel::ALL {
            if t.set_kernel(kernel).is_err() {
                assert!(!kernel.supported());
                continue;
            }
            compared += 1;
            for ((p, e), (o, j)) in points.iter().zip(&reference) {
                let ok = t.evaluate(p, e).unwrap();
                let jk = t.evaluate_with_jacobian(p, e).unwrap().1;
                for (x, y) in [
                    (ok.force_x, o.force_x),
                    (ok.force_y, o.force_y),
                    (ok.spin_moment, o.spin_moment),
                    (ok.traction_coefficient, o.traction_coefficient),
                    (ok.max_temperature, o.max_temperature),
                    (ok.fluid_load_fraction, o.fluid_load_fraction),
                ] {
                    assert!(close(x, y), "{kernel:?} at {p:?}: {x} vs {y}");
                }
                assert_eq!((ok.in_range, ok.converged), (o.in_range, o.converged));
                // derivatives are differences of values over node spacings down to 1e-4 or so: the
                // values' rounding differences grow by that factor
                for (rk, r) in jk.iter().zip(j) {
                    let scale = r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                    for (x, y) in rk.iter().zip(r) {
                        assert!((x - y).abs() <= 1e-9 * scale, "{kernel:?}: {x} vs {y}");
                    }
                }
            }
        }
        assert!(compared >= 1);
    }

    /// The AVX-512 kernel's values and Jacobians are the AVX2 kernel's bit for bit (where this CPU runs
    /// both): on a table with 16 linear corners and one by similarity (12), at random points (ghost window
    /// points of both mirrors among them), dry ones (the wetness on its first node: half the corners), on
    /// the last speed node, and beside cells across which T_max jumps (one-sided slopes).
    #[test]
    fn the_avx512_kernel_is_the_avx2_kernel_bit_for_bit() {
        if !Kernel::Avx512.supported() {
            eprintln!("this CPU has no AVX-512: nothing to compare");
            return;
        }
        let params = coarse_params();
        let mut axes = tiny_axes();
        axes.0[XI].points = vec![0.0, 1.0, 2.0, 4.0, 10.0];
        let jump = |c: &[f64; DIMS]| {
            let mut o = symmetric_saturating(c);
            o[3] += if c[XI].abs() >= 10.0 { 800.0 } else { 0.0 };
            o
        };
        let tables = [
            synthetic(&tiny_axes(), &params, &symmetric_saturating),
            synthetic(&similar(tiny_axes()), &params, &symmetric_saturating),
            synthetic(&axes, &params, &jump),
        ];
        let mut rng = verify::SplitMix64::new(31);
        let mut kinds = [0; 3];
        for mut t in tables {
            let speeds = t.axes().0[SPEED].points.clone();
            let dry = t.axes().0[WET].points[0];
            for n in 0..400 {
                let mut c = random_coordinates(&mut rng);
                match n % 4 {
                    1 => c[WET] = dry,
                    2 => c[SPEED] = speeds[speeds.len() - 1],
                    _ => {}
                }
                let (p, e) = at(&t, &c, Ellipse::HERTZ);
                let mut results = Vec::new();
                for kernel in [Kernel::Avx2Fma, Kernel::Avx512] {
                    t.set_kernel(kernel).unwrap();
                    let o = t.evaluate(&p, &e).unwrap();
                    let (oj, j) = t.evaluate_with_jacobian(&p, &e).unwrap();
                    let bits = |o: &TableOutput| o.values().map(f64::to_bits);
                    let flags = (o.in_range, o.converged, o.resolved);
                    results.push((bits(&o), bits(&oj), flags, j.map(|r| r.map(f64::to_bits))));
                }
                assert_eq!(results[0], results[1], "{c:?}");
                kinds[0] += usize::from(c[XI] < 0.0 && c[ETA] < 0.0);
                kinds[1] += usize::from(!results[0].2.2);
                kinds[2] += usize::from(results[0].0[0] != 0);
            }
        }
        // both mirrors, unresolved cells and non-zero values among the points
        assert!(kinds.iter().all(|k| *k > 10), "{kinds:?}");
    }

    /// Timing files load (their probe nodes hold the exact solutions), a synthetic table without them does
    /// not.
    #[test]
    fn timing_files_pass_the_probes_a_synthetic_table_does_not() {
        let params = coarse_params();
        let axes = tiny_axes();
        let dir = std::env::temp_dir().join(format!("wheelrail-timing-{}", std::process::id()));
        let mut files = build::timing_files(&params, &axes).unwrap();
        files.write(&dir).unwrap();
        let loaded = Table::load(&dir);
        let mut plain = build::tabulate(&params, &axes, &|_| [0.1, 0.0, 0.0, 300.0, 0.0, 0.0]);
        plain.write(&dir).unwrap();
        let refused = Table::load(&dir);
        let _ = std::fs::remove_dir_all(&dir);
        assert!(loaded.is_ok(), "{loaded:?}");
        let reason = refused.unwrap_err().to_string();
        assert!(reason.contains("another model"), "{reason}");
    }

    #[test]
    fn jacobian_is_the_derivative_of_the_interpolant() {
        let params = coarse_params();
        let mut axes = tiny_axes();
        axes.0[XI].points = vec![0.0, 0.2, 0.6, 2.0, 6.0, 10.0];
        for axes in [
            axes.clone(),
            similar(axes.clone()),
            similar(blended(axes.clone())),
            sized(blended(axes.clone())),
            similar(sized(blended(axes))),
        ] {
            jacobian_is_the_derivative_of(&synthetic(&axes, &params, &symmetric_saturating));
        }
    }

    /// [`jacobian_is_the_derivative_of_the_interpolant`] for table `t`; in a table by similarity at
    /// contacts carried from F_ref to loads 0.3–2 × F_ref (their equivalents at random coordinates).
    fn jacobian_is_the_derivative_of(t: &Table) {
        let mut rng = verify::SplitMix64::new(11);
        for n in 0..300 {
            let mut c = random_coordinates(&mut rng);
            let exponent = if n % 2 == 0 { 0.0 } else { Ellipse::HERTZ };
            let (pt, e) = if t.axes().similarity() {
                c[FORCE] = axes::REFERENCE_FORCE;
                let (p, e) = at(t, &c, exponent);
                coords::carried(&p, &e, 0.3 + 1.7 * rng.uniform())
            } else {
                at(t, &c, exponent)
            };
            let (_, j) = t.evaluate_with_jacobian(&pt, &e).unwrap();
            for d in 0..INPUTS {
                let h = [1e-9, 1e-9, 1e-7, 0.1, 1e-5, 1e-7][d];
                let value = |h: f64| {
                    let (p, e) = moved(&pt, &e, d, h);
                    t.evaluate(&p, &e).unwrap()
                };
                let (p, m) = (value(h), value(-h));
                let fd = [
                    (p.force_x - m.force_x) / (2.0 * h),
                    (p.force_y - m.force_y) / (2.0 * h),
                    (p.spin_moment - m.spin_moment) / (2.0 * h),
                    (p.traction_coefficient - m.traction_coefficient) / (2.0 * h),
                    (p.max_temperature - m.max_temperature) / (2.0 * h),
                    (p.fluid_load_fraction - m.fluid_load_fraction) / (2.0 * h),
                ];
                for o in 0..JACOBIAN_ROWS {
                    let f = pt.normal_force;
                    let scale =
                        [f, f, f * 0.01, 1.0, 50.0, 0.3][o] / [0.05, 0.02, 1.0, 1e5, 20.0, 1.0][d];
                    assert!(
                        (j[o][d] - fd[o]).abs() < 1e-5 * scale.max(fd[o].abs()),
                        "∂{o}/∂{d} at {c:?}: {} vs {}",
                        j[o][d],
                        fd[o]
                    );
                }
            }
        }
    }

    /// The in-memory row layout (values and φ slopes interleaved, f32, linear corners) against a direct
    /// evaluation of the node values in C order: Steffen slopes along φ per corner fibre (mirror images for
    /// ghost η nodes), Hermite along φ, the linear corners, then the η and ξ fibres with their weights.
    #[test]
    fn row_layout_matches_a_direct_evaluation_of_the_node_values() {
        let params = coarse_params();
        let mut axes = tiny_axes();
        axes.0[XI].points = vec![0.0, 0.2, 0.6, 2.0, 6.0, 10.0];
        let t = synthetic(&axes, &params, &symmetric_saturating);
        let shape = axes.shape();
        // the stored (f32) node values, T_max as G(T_max) (`rise`), the heat per unit of the node's Λ
        // (`heating`), in f32
        let vals: Vec<[f64; OUTPUTS]> = (0..axes.len())
            .map(|k| {
                let c = axes.coordinates(k);
                let (p, e) = t.coordinates.point(&c).unwrap();
                let lambda = t.coordinates.of(&p, &e).unwrap().heating;
                let mut v = symmetric_saturating(&c).map(|v| f64::from(v as f32));
                v[3] = f64::from((t.rise.of(v[3]) / lambda) as f32);
                v[5] = f64::from((v[5] / lambda) as f32);
                v
            })
            .collect();
        let idx = |m: [usize; DIMS]| m.iter().zip(&shape).fold(0, |a, (i, s)| a * s + i);
        let phi = &axes.0[PHI].points;
        let np = phi.len();
        let mut rng = verify::SplitMix64::new(5);
        for _ in 0..300 {
            let mut q = random_coordinates(&mut rng);
            q[XI] = q[XI].abs();
            q[ETA] = q[ETA].abs();
            let cx = t.interp[XI].cubic(q[XI]);
            let cy = t.interp[ETA].cubic(q[ETA]);
            let (k0, hw, _) = t.interp[PHI].cubic(q[PHI]).hermite();
            let k0 = k0 as usize;
            let sx = Corners::of(&std::array::from_fn(|k| {
                t.interp[FORCE + k].fraction(q[FORCE + k])
            }));
            // the corners' node indices along the linear dimensions
            let corners: Vec<[usize; LINEAR_DIMS]> = (0..sx.n)
                .map(|c| std::array::from_fn(|k| sx.start[k] + sx.step[c][k]))
                .collect();
            let want: [f64; OUTPUTS] = std::array::from_fn(|o| {
                let along_eta: [f64; 4] = std::array::from_fn(|i| {
                    let gi = cx.start + i as isize;
                    let along_phi: [f64; 4] = std::array::from_fn(|j| {
                        let gj = cy.start + j as isize;
                        let sign = if (gi < 0 && o == 0) != (gj < 0 && (o == 1 || o == 2)) {
                            -1.0
                        } else {
                            1.0
                        };
                        corners
                            .iter()
                            .zip(sx.w)
                            .map(|(corner, w)| {
                                let fibre: Vec<f64> = (0..np)
                                    .map(|k| {
                                        let kk = if gj < 0 { np - 1 - k } else { k };
                                        let mut m = [
                                            gi.unsigned_abs(),
                                            gj.unsigned_abs(),
                                            kk,
                                            0,
                                            0,
                                            0,
                                            0,
                                            0,
                                        ];
                                        m[FORCE..].copy_from_slice(corner);
                                        sign * vals[idx(m)][o]
                                    })
                                    .collect();
                                let mut d = vec![0.0; np];
                                interp::node_slopes(phi, &fibre, &mut d);
                                // slopes are stored in f32 too
                                let d: Vec<f64> = d.iter().map(|x| f64::from(*x as f32)).collect();
                                w * (hw[0] * fibre[k0]
                                    + hw[1] * d[k0]
                                    + hw[2] * fibre[k0 + 1]
                                    + hw[3] * d[k0 + 1])
                            })
                            .sum()
                    });
                    cy.eval(&along_phi).v
                });
                cx.eval(&along_eta).v
            });
            let got = t.core::<false, PORTABLE>(&q).v;
            for o in 0..OUTPUTS {
                let scale = [1.0, 1.0, 0.1, 300.0, 0.3, 0.05][o];
                assert!(
                    (got[o] - want[o]).abs() < 1e-12 * scale,
                    "output {o} at {q:?}: {} vs {}",
                    got[o],
                    want[o]
                );
            }
        }
    }

    #[test]
    fn mirrored_points_obey_the_symmetries() {
        // node values of a non-symmetric function: the table still returns mirror images for η < 0, ξ < 0
        let params = coarse_params();
        let t = synthetic(&tiny_axes(), &params, &|c| {
            [
                c[0] + c[1] + c[2],
                c[1] * 2.0 + c[2],
                c[2] + c[0],
                300.0 + c[0],
                0.1,
                0.01 + c[0] * c[0],
            ]
        });
        let (pt, e) = at(&t, &[2.0, 0.8, 0.3, 70e3, 20.0, 0.5, 0.55, 0.8e9], 0.0);
        let a = t.evaluate(&pt, &e).unwrap();
        let b = t
            .evaluate(
                &OperatingPoint {
                    creepage_y: -pt.creepage_y,
                    spin: -pt.spin,
                    ..pt
                },
                &e,
            )
            .unwrap();
        assert_eq!(
            (b.force_x, b.force_y, b.spin_moment),
            (a.force_x, -a.force_y, -a.spin_moment)
        );
        assert_eq!(b.max_temperature, a.max_temperature);
        let c = t
            .evaluate(
                &OperatingPoint {
                    creepage_x: -pt.creepage_x,
                    ..pt
                },
                &e,
            )
            .unwrap();
        assert_eq!(
            (c.force_x, c.force_y, c.spin_moment),
            (-a.force_x, a.force_y, a.spin_moment)
        );
    }

    #[test]
    fn out_of_range_is_clamped_and_flagged_bad_input_is_an_error() {
        let t = synthetic(&tiny_axes(), &coarse_params(), &symmetric_multilinear);
        let (pt, e) = at(&t, &[4.0, 0.2, 0.1, 100e3, 30.0, 1.0, 0.55, 0.8e9], 0.0);
        let inside = t.evaluate(&pt, &e).unwrap();
        assert!(inside.in_range && t.in_range(&pt, &e) && t.covers(&e, pt.normal_force));
        let fast = OperatingPoint { speed: 60.0, ..pt };
        let (o, j) = t.evaluate_with_jacobian(&fast, &e).unwrap();
        assert!(!o.in_range && !t.in_range(&fast, &e));
        // V = 30 is the top of the speed axis: clamped to it
        assert!((o.force_x - inside.force_x).abs() < 1e-12 * inside.force_x.abs());
        assert_eq!(j[0][4], 0.0);
        // above the load range the normalised values are held, the force scales with F_N (the contact
        // held: its p_ref and the creepage scales change, so compare at the same coordinates)
        let (heavy, eh) = at(&t, &[4.0, 0.2, 0.1, 200e3, 30.0, 1.0, 0.55, 0.8e9], 0.0);
        let h = t.evaluate(&heavy, &eh).unwrap();
        assert!(!h.in_range);
        assert!((h.force_x / 200e3 - inside.force_x / 100e3).abs() < 1e-15);
        // a raw creepage beyond its raw limit is out of range even where its coordinate is on the axis
        let mut narrow = tiny_axes();
        narrow.0[XI].raw_limit = Some(0.5 * pt.creepage_x);
        let steep = synthetic(&narrow, &coarse_params(), &symmetric_multilinear);
        assert!(!steep.in_range(&pt, &e) && !steep.evaluate(&pt, &e).unwrap().in_range);
        // another contact: outside the geometry axes
        let flat = Ellipse {
            a: e.b,
            b: e.a,
            ..e
        };
        assert!(!t.covers(&flat, pt.normal_force) && !t.in_range(&pt, &flat));
        let err = t.outside_geometry(&flat, pt.normal_force).to_string();
        assert!(
            err.contains("a/b 0.5 to 0.6") && err.contains("p_ref"),
            "{err}"
        );
        for bad in [
            OperatingPoint {
                creepage_x: f64::NAN,
                ..pt
            },
            OperatingPoint {
                normal_force: -1.0,
                ..pt
            },
        ] {
            assert!(t.evaluate(&bad, &e).is_err() && !t.in_range(&bad, &e));
        }
        assert!(t.evaluate(&pt, &Ellipse { a: 0.0, ..e }).is_err());
    }

    /// [`synthetic`] with the points of flat (C-order, the files') indices `unconverged` not converged.
    fn synthetic_unconverged(
        axes: &Axes,
        params: &Params,
        f: &dyn Fn(&[f64; DIMS]) -> [f64; OUTPUTS],
        unconverged: &[usize],
    ) -> Table {
        let mut files = build::tabulate(params, axes, f);
        for i in unconverged {
            files.converged[*i] = 0;
        }
        Table::from_files(files, None).unwrap()
    }

    #[test]
    fn unconverged_nodes_taint_only_nearby_evaluations() {
        let mut axes = tiny_axes();
        axes.0[XI].points = vec![0.0, 0.2, 0.6, 2.0, 6.0, 10.0];
        let params = coarse_params();
        // flag the node at the largest coordinates
        let t = synthetic_unconverged(&axes, &params, &symmetric_multilinear, &[axes.len() - 1]);
        let near = [8.0, 3.5, 0.38, 90e3, 25.0, 0.9, 0.58, 0.83e9];
        let (p, e) = at(&t, &near, 0.0);
        assert!(!t.evaluate(&p, &e).unwrap().converged);
        // the cubic stencil at ξ̂ = 0.4 spans the points −0.2 (ghost) … 2
        let mut far = near;
        far[XI] = 0.4;
        let (p, e) = at(&t, &far, 0.0);
        assert!(t.evaluate(&p, &e).unwrap().converged);
    }

    #[test]
    fn a_cell_next_to_an_unresolved_cell_takes_one_sided_slopes_at_their_shared_node() {
        // data linear in ξ̂ (η̂) on the stored side, T_max's variable G too, but for a jump of G at the last
        // node, which makes the last cell unresolved: the cell before it reproduces the data exactly (its
        // spline no longer takes up to twice its secant as the slope at the shared node), values and
        // Jacobian
        let params = coarse_params();
        for (axis, points, last, cell) in [
            (XI, &[0.0, 1.0, 2.0, 4.0, 10.0][..], 10.0, [2.0, 4.0]),
            (ETA, &[0.0, 0.6, 1.5, 4.0, 9.0][..], 9.0, [1.5, 4.0]),
        ] {
            let mut axes = tiny_axes();
            axes.0[axis].points = points.to_vec();
            axes.validate().unwrap();
            let linear = move |c: &[f64; DIMS]| {
                let mut o = symmetric_multilinear(c);
                o[3] += 5.0 * c[axis].abs();
                o
            };
            let jump = move |c: &[f64; DIMS]| {
                let mut o = linear(c);
                o[3] += if c[axis].abs() >= last { 800.0 } else { 0.0 };
                o
            };
            let t = synthetic(&axes, &params, &in_rise(&params, &axes, jump));
            let want = in_rise(&params, &axes, linear);
            let mut rng = verify::SplitMix64::new(23);
            for n in 0..200 {
                let mut c = random_coordinates(&mut rng);
                c[axis] = cell[0] + (cell[1] - cell[0]) * rng.uniform();
                let (p, e) = at(&t, &c, 0.0);
                let (o, j) = t.evaluate_with_jacobian(&p, &e).unwrap();
                assert!(o.resolved, "{c:?}");
                let w = want(&c);
                let f = c[FORCE];
                assert!((o.force_x / f - w[0]).abs() < 1e-6, "{axis} {c:?}");
                assert!((o.force_y / f - w[1]).abs() < 1e-6, "{axis} {c:?}");
                assert!(
                    (o.max_temperature - w[3]).abs() < 1e-3,
                    "{axis} {c:?}: {} vs {}",
                    o.max_temperature,
                    w[3]
                );
                // the Jacobian's T_max column along the axis: the derivative of the same linear data
                if n % 10 == 0 {
                    let d = if axis == XI { 0 } else { 1 };
                    let h = 1e-8;
                    let value = |h: f64| {
                        let (p, e) = moved(&p, &e, d, h);
                        t.evaluate(&p, &e).unwrap().max_temperature
                    };
                    let fd = (value(h) - value(-h)) / (2.0 * h);
                    assert!(
                        (j[4][d] - fd).abs() < 1e-4 * fd.abs().max(1.0),
                        "{} vs {fd}",
                        j[4][d]
                    );
                }
            }
            // the cell beyond holds the jump
            let mut c = random_coordinates(&mut rng);
            c[axis] = 0.5 * (cell[1] + last);
            let (p, e) = at(&t, &c, 0.0);
            assert!(!t.evaluate(&p, &e).unwrap().resolved);
        }
    }

    #[test]
    fn xi_slabs_are_padded_so_that_no_l1_set_holds_more_of_a_lookup_than_its_ways() {
        // the whole-range table: 1 488 384 rows of 48 bytes per ξ̂ slab, a multiple of 4 KB (17 442 pages)
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/whole-range-axes.toml");
        let shape = Axes::from_toml_file(&file).unwrap().shape();
        let (padded, unpadded) = (memory_strides(&shape), unpadded_strides(&shape));
        assert_eq!(unpadded[XI], 1_488_384);
        assert_eq!(unpadded[XI] * std::mem::size_of::<Row>() % 4096, 0);
        // unpadded, the four ξ̂ window nodes of every row share a set: lines beyond the ways
        assert!(
            l1_crowding(&shape, &unpadded) > 100,
            "{}",
            l1_crowding(&shape, &unpadded)
        );
        let pad = padded[XI] - unpadded[XI];
        assert_eq!(pad % shape[PHI], 0, "whole fibres");
        assert!(pad > 0 && 16 * pad <= unpadded[XI], "{pad}");
        assert_eq!(l1_crowding(&shape, &padded), 0);
        // the test tables are padded too (fewer lines beyond the ways), so every test of lookups runs on
        // a padded layout
        for axes in [tiny_axes(), small_axes()] {
            let shape = axes.shape();
            let (padded, unpadded) = (memory_strides(&shape), unpadded_strides(&shape));
            assert!(padded[XI] > unpadded[XI]);
            assert!(l1_crowding(&shape, &padded) < l1_crowding(&shape, &unpadded));
        }
    }

    /// The cells flagged at loading as near an unconverged point ([`near_unconverged`]) hold every
    /// evaluation that reads one: with four points unconverged, random evaluations (values and Jacobians,
    /// both mirrors, every kind of cell) report `converged` as when every cell is checked corner by
    /// corner — and the flags spare most cells that check.
    #[test]
    fn cells_near_unconverged_points_are_flagged_at_loading_as_every_evaluation_finds_them() {
        let mut axes = tiny_axes();
        axes.0[XI].points = vec![0.0, 0.2, 0.6, 2.0, 6.0, 10.0];
        axes.0[ETA].points = vec![0.0, 0.3, 1.0, 2.0, 4.0];
        axes.0[PHI].points = vec![-0.5, -0.3, -0.1, 0.0, 0.1, 0.3, 0.5];
        axes.validate().unwrap();
        let params = coarse_params();
        let mut rng = verify::SplitMix64::new(11);
        let mut bad: Vec<usize> = (0..3).map(|_| rng.below(axes.len())).collect();
        // and one that only the ghost η̂ point −1 reads, where φ̂ runs backwards (η̂ 1, φ̂'s last point: in
        // the window of η̂'s first cell, read at the φ̂ rows of its first cell)
        let shape = axes.shape();
        let creepage = shape[XI] * shape[ETA] * shape[PHI];
        bad.push(((2 * shape[ETA] + 1) * shape[PHI] + shape[PHI] - 1) * (axes.len() / creepage));
        let t = synthetic_unconverged(&axes, &params, &symmetric_multilinear, &bad);
        let mut every = synthetic_unconverged(&axes, &params, &symmetric_multilinear, &bad);
        every
            .cell_flags
            .iter_mut()
            .for_each(|f| *f |= NEAR_UNCONVERGED);
        let flagged = t
            .cell_flags
            .iter()
            .filter(|f| **f & NEAR_UNCONVERGED != 0)
            .count();
        assert!(flagged > 0 && flagged < t.cell_flags.len() / 2, "{flagged}");
        let mut tainted = [0, 0];
        for n in 0..20000 {
            let mut c = random_coordinates(&mut rng);
            // the nodes themselves and the cells' faces too (weights exactly 0)
            if n % 4 == 0 {
                for (x, a) in c.iter_mut().zip(&axes.0).skip(FORCE) {
                    *x = a.points[rng.below(2)];
                }
            }
            let (p, e) = at(&t, &c, 0.0);
            let fast = t.evaluate(&p, &e).unwrap().converged;
            assert_eq!(fast, every.evaluate(&p, &e).unwrap().converged, "{c:?}");
            let (o, _) = t.evaluate_with_jacobian(&p, &e).unwrap();
            let (o_every, _) = every.evaluate_with_jacobian(&p, &e).unwrap();
            assert_eq!(o.converged, o_every.converged, "{c:?}");
            tainted[usize::from(fast)] += 1;
        }
        // both kinds occur
        assert!(
            tainted[0] > 100 && tainted[1] > 100,
            "{tainted:?} of {flagged}"
        );
    }

    /// A table stores quantities only the Tomberger law models: other laws are refused before any solve,
    /// and an exact solution of them has no table form.
    #[test]
    fn tables_are_of_the_tomberger_law_only() {
        for (law, missing) in [
            (FrictionLaw::Polach, "spin moment"),
            (FrictionLaw::Constant, "fluid load fraction"),
        ] {
            let mut p = coarse_params();
            p.friction.law = law;
            let e = build::build(&p, &tiny_axes(), None, &|| ()).unwrap_err();
            assert!(
                matches!(&e, Error::OutOfRange { name, .. } if name == "friction.law"),
                "{e}"
            );
            let s = crate::solve(&p, &OperatingPoint::default()).unwrap();
            let e = TableOutput::from_solution(&s).unwrap_err().to_string();
            assert!(e.contains(&format!("has no {missing}")), "{e}");
        }
        let s = crate::solve(&coarse_params(), &OperatingPoint::default()).unwrap();
        let o = TableOutput::from_solution(&s).unwrap();
        let g = &s.global;
        assert_eq!(
            [o.force_x, o.force_y, o.traction_coefficient],
            [g.force_x, g.force_y, g.traction_coefficient]
        );
        assert_eq!(
            [
                Some(o.spin_moment),
                Some(o.max_temperature),
                Some(o.fluid_load_fraction)
            ],
            [g.spin_moment, g.max_temperature, g.fluid_load_fraction]
        );
        assert!(o.in_range && o.converged);
    }

    #[test]
    fn shared_loading_returns_one_copy_per_directory() {
        let dir =
            std::env::temp_dir().join(format!("wheelrail-table-shared-{}", std::process::id()));
        let mut files = build::build(&coarse_params(), &tiny_axes(), None, &|| ()).unwrap();
        files.write(&dir).unwrap();
        let a = Table::load_shared(&dir).unwrap();
        let b = Table::load_shared(&dir.join(".")).unwrap();
        assert!(Arc::ptr_eq(&a, &b));
        assert!(a.matches(&coarse_params()) && !a.matches(&Params::default()));
        assert!(not_matching(&a, &Params::default()).is_some());
        drop((a, b));
        // released when the last user drops it, loaded again afterwards
        let c = Table::load_shared(&dir).unwrap();
        assert_eq!(c.axes(), &tiny_axes());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A table whose values another model computed is refused at loading: its probe nodes no
    /// longer match the exact solver. Here the "other model" is the present one with the forces 1e-4·F_N
    /// larger (as a change of the friction model would make them), the files otherwise consistent.
    #[test]
    fn a_table_of_another_model_is_refused_by_its_probe_nodes() {
        let dir =
            std::env::temp_dir().join(format!("wheelrail-table-probe-{}", std::process::id()));
        let mut files = build::build(&coarse_params(), &tiny_axes(), None, &|| ()).unwrap();
        files.write(&dir.join("good")).unwrap();
        let good = Table::load(&dir.join("good")).unwrap();
        assert_eq!(good.probe_nodes().len(), PROBES);
        let probes = good.probe_nodes();
        // the probes lie in different cubes and are solved nodes
        assert!(probes.windows(2).all(|w| w[0] < w[1]));
        for (k, o) in [(0usize, 1e-4f32), (3, 0.01)] {
            let mut stale = files.clone();
            for n in &probes {
                stale.outputs[k][*n] += o;
            }
            let d = dir.join(format!("stale-{k}"));
            stale.write(&d).unwrap();
            let e = Table::load(&d).unwrap_err().to_string();
            assert!(
                e.contains("computed by another model")
                    && e.contains(OUTPUT_INFO[k].name)
                    && e.contains("rebuild"),
                "{e}"
            );
        }
        // below the tolerance (f32 rounding, solver noise) it loads
        let mut close = files.clone();
        for n in &probes {
            close.outputs[0][*n] += 2e-8;
        }
        close.write(&dir.join("close")).unwrap();
        Table::load(&dir.join("close")).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A built table agrees with the exact solver at its nodes (they are the solutions, in f32) and between
    /// them within the interpolation error, for contacts across its geometry axes; the nodes a cube did not
    /// solve (beyond its coverage window) hold the nearest solved node's values.
    #[test]
    fn built_nodes_are_the_exact_solutions_of_their_contacts() {
        for axes in [
            tiny_axes(),
            blended(tiny_axes()),
            similar(tiny_axes()),
            similar(blended(tiny_axes())),
            similar(sized(blended(tiny_axes()))),
        ] {
            built_nodes_are_exact(&axes);
        }
    }

    /// Where the coupled thermal problem has two steady states, a node holds the one the exact solver
    /// finds from a cold start (what `table verify`, `wheelrail point` and a fresh FMU instance compute),
    /// whatever the continuation line it was solved on. Hot, fast, high-pressure contact at the onset of
    /// boundary lubrication (equivalent speed 65 m/s, p0 1.2 GPa, a/b 1.2, w 0.013, 10 × 10 cells): the line
    /// of ξ comes from ξ = −0.116 (T_max 1049 K) to −0.070, where a warm temperature led to the hot state
    /// (898 K, F_x/F_N 0.117) and the cold start to 579 K (0.0925); at +0.116, from +0.070 (583 K), the warm
    /// temperature gave 727 K and the cold start 1050 K.
    #[test]
    fn built_nodes_are_the_cold_start_solutions_where_the_heat_has_two_steady_states() {
        let spec: axes::AxesSpec = toml::from_str(
            r#"
            [creepage_x]
            points = [-22.0, -13.117, 0.0, 13.117, 22.0]
            raw_limit = 0.1
            raw_scale = 193.0
            [creepage_y]
            points = [0.0, 0.9531, 1.6077]
            raw_limit = 0.02
            raw_scale = 170.0
            [spin]
            points = [-0.349, -0.1097, 0.1097, 0.349]
            raw_limit = 1.0
            raw_scale = 0.4
            [normal_force]
            points = [100e3]
            [speed]
            similarity = true
            points = [65.097]
            [wetness]
            points = [0.013]
            [semi_axis_ratio]
            points = [1.2]
            [reference_pressure]
            points = [1.2e9]
            "#,
        )
        .unwrap();
        let axes = Axes::from_spec(&spec).unwrap();
        let mut params = Params::default();
        params.grid.nx = 10;
        params.grid.ny = 10;
        let files = build::build(&params, &axes, None, &|| ()).unwrap();
        let mut hottest: f64 = 0.0;
        for k in 0..axes.len() {
            let (p, e) = Coordinates::new(&params, &axes)
                .point(&axes.coordinates(k))
                .unwrap();
            let mut exact = params.clone();
            exact.geometry.semi_axes = Some([e.a, e.b]);
            let s = crate::solve(&exact, &p).unwrap();
            let t = s.global.max_temperature.unwrap();
            hottest = hottest.max(t);
            let stored = [files.outputs[0][k], files.outputs[3][k]].map(f64::from);
            let want = [s.global.force_x / p.normal_force, t];
            assert!(
                (stored[0] - want[0]).abs() < 1e-5 && (stored[1] - want[1]).abs() < 1e-2,
                "node {k} {p:?}: stored F_x/F_N {}, T_max {} against the cold start's {}, {}",
                stored[0],
                stored[1],
                want[0],
                want[1]
            );
        }
        // the hot state is reached: the test runs where the two steady states are
        assert!(hottest > 1000.0, "{hottest}");
    }

    /// A table over `axes` holds the exact solutions at 20 random nodes, and evaluates to them there; a
    /// table by similarity at contacts carried from the nodes' (at F_ref) to 0.1–2.5 × F_ref, whose exact
    /// solutions are compared.
    fn built_nodes_are_exact(axes: &Axes) {
        let params = coarse_params();
        let files = build::build(&params, axes, None, &|| ()).unwrap();
        let t = Table::from_files(files.clone(), None).unwrap();
        let mut rng = verify::SplitMix64::new(17);
        for _ in 0..20 {
            let k = rng.below(axes.len());
            let q = axes.coordinates(k);
            let node = t.coordinates().point(&q).unwrap();
            let (p, e) = if axes.similarity() {
                coords::carried(&node.0, &node.1, 0.1 * 25f64.powf(rng.uniform()))
            } else {
                node
            };
            let mut exact = params.clone();
            exact.geometry.semi_axes = Some([e.a, e.b]);
            let s = crate::solve(&exact, &p).unwrap();
            let f = p.normal_force;
            let stored = f64::from(files.outputs[0][k]);
            assert!(
                (stored - s.global.force_x / f).abs() < 1e-3,
                "node {q:?}: {stored} vs {}",
                s.global.force_x / f
            );
            let o = t.evaluate(&p, &e).unwrap();
            assert!((o.force_x / f - stored).abs() < 1e-6);
        }
    }
}
