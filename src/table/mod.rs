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
pub(crate) mod interp;
pub mod rise;
pub mod verify;

mod flags;
mod kernel;
mod layout;
mod load;
mod lookup;
#[cfg(test)]
mod testing;

pub use axes::{Axes, AxesSpec, Axis, AxisSpec, DIMENSIONS, DIMS, Interpolation, Spacing};
pub use build::{build, is_built, merge, solve_with_retry};
pub use coords::{Coordinates, Ellipse};
pub use file::{
    FilmIntake, OUTPUT_INFO, OUTPUTS, Quantization, Resolution, ShardRecord, Sidecar, Storage,
    TableFiles, fingerprint,
};

pub use kernel::Kernel;
pub(crate) use load::{exact_at_node, probe_nodes};
#[cfg(test)]
pub(crate) use testing::{coarse_params, small_axes, synthetic, tiny_axes};

use crate::error::{Error, Result};
use crate::params::{OperatingPoint, Params};
use crate::solver::{GlobalResults, Solution, SolverReport};
use axes::{ETA, FORCE, PRESSURE, RATIO};
use interp::AxisInterp;
use layout::Row;
use rise::RiseVariable;
use std::path::{Path, PathBuf};

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
pub(crate) const PROBES: usize = 3;

/// Largest difference allowed between a stored output at a probe node and the present exact solver, per
/// output (F_x/F_N, F_y/F_N, M_z/(F_N·c), T_max [K], fluid load fraction, P_f/(F_N·V)).
pub(crate) const PROBE_TOLERANCE: [f64; OUTPUTS] = [1e-6, 1e-6, 1e-6, 1e-3, 1e-6, 1e-6];

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
    pub(crate) fn outside_geometry(&self, e: &Ellipse, force: f64) -> Error {
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
    ///
    /// # Example
    ///
    /// The bundled table against the exact solver at a point between its nodes: the forces agree within
    /// the accuracy target of a table, |ΔF|/F_N ≤ [`verify::TARGET_MAX`] = 0.03 (`wheelrail table verify`
    /// measures it over random points); and the ξ mirror is exact, F_x(−ξ) = −F_x(ξ) bit for bit (the table
    /// stores ξ ≥ 0 and evaluates −ξ there with the sign of F_x turned).
    ///
    /// ```
    /// use std::path::Path;
    /// use wheelrail::table::{Ellipse, Table, verify::TARGET_MAX};
    /// use wheelrail::{Model, OperatingPoint};
    /// let table = Table::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("fmu/resources/table"))?;
    /// let point = OperatingPoint {
    ///     creepage_x: 0.003, creepage_y: 0.001, spin: 0.0, normal_force: 120e3, speed: 20.0, wetness: 0.0,
    /// };
    /// let hertz = wheelrail::solver::normal_contact(table.params(), point.normal_force)?;
    /// let e = Ellipse { a: hertz.a, b: hertz.b, load_exponent: Ellipse::HERTZ };
    /// let t = table.evaluate(&point, &e)?;
    /// let exact = Model::new(table.params().clone())?.solve(&point)?.global;
    /// let df = (t.force_x - exact.force_x).hypot(t.force_y - exact.force_y) / point.normal_force;
    /// assert!(t.in_range && df <= TARGET_MAX, "|ΔF|/F_N = {df}");
    ///
    /// let mirrored = table.evaluate(&OperatingPoint { creepage_x: -0.003, ..point }, &e)?;
    /// assert_eq!(mirrored.force_x, -t.force_x);
    /// # Ok::<(), wheelrail::Error>(())
    /// ```
    pub fn evaluate(&self, point: &OperatingPoint, e: &Ellipse) -> Result<TableOutput> {
        let geometry = self.coordinates.geometry(e, point.normal_force);
        self.dispatch::<false>(point, e, geometry).map(|(o, _)| o)
    }

    /// [`Table::evaluate`] where the table covers the contact `e` at the point's normal force, None where
    /// it does not ([`Table::covers`]): the contact's geometry coordinates are computed once for both.
    pub(crate) fn evaluate_covered(
        &self,
        point: &OperatingPoint,
        e: &Ellipse,
    ) -> Option<Result<TableOutput>> {
        self.covered::<false>(point, e).map(|r| r.map(|(o, _)| o))
    }

    /// [`Table::evaluate_covered`] plus the Jacobian of the interpolant.
    pub(crate) fn evaluate_covered_with_jacobian(
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
mod tests;
