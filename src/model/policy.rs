//! The evaluation policy: how one operating point of a multibody simulation is evaluated, by the lookup
//! table or by the exact solver, in which frame, and what the caller is told about it (docs/model.md §1,
//! §12.3).
//!
//! - **Wheel lifted:** a normal force at or below the lift-off load ([`LIFT_OFF_LOAD`]) gives zero forces
//!   and moment, traction coefficient 0, fluid load fraction 0, maximum temperature = the bulk temperature,
//!   converged; nothing is solved or checked.
//! - **Frame:** rolling backwards, standstill and wetness outside [0, 1] as in `frame` (the wetness clamp is
//!   a [`Notice`]).
//! - **Geometry** ([`Evaluator::evaluate_at`]): each evaluation may give its own contact geometry (gap
//!   curvatures or prescribed semi-axes, docs/model.md §2) instead of the model's, without rebuilding the
//!   model: it is validated ([`Geometry::validate`]) unless it is the model's; the table evaluates the
//!   contacts its geometry axes (a/b, p_ref) cover.
//! - **Mode** ([`Mode`]): auto evaluates by the table where it was built for the model's parameters
//!   (geometry aside), covers the evaluation's contact and the point lies inside its ranges, else by the
//!   exact solver (a [`Notice::FellBack`] with the reason); table-only clamps points to the table's ranges
//!   ([`Notice::Clamped`]) and refuses other parameters ([`crate::Error::TableParameters`]) or a contact
//!   outside its geometry axes ([`crate::Error::TableGeometry`]); exact-only always solves.
//! - **Fallback grid** ([`FallbackGrid`]): where the model keeps the default grid, mode auto solves the
//!   points no table serves on the grid of each contact ([`crate::params::fallback_cells`], docs/model.md
//!   §6.4), mode exact-only on the model's; [`Evaluator::exact_cells`] says which, and
//!   [`Evaluator::evaluate_on`] solves on given cells (the evaluations behind one finite difference).
//! - **Several tables** ([`Evaluator::with_tables`], e.g. one per region of contact geometry): each point
//!   goes to the first table, in the given order, that is built for the model's parameters, covers the
//!   contact and holds the point inside its ranges; table-only clamps to the first that covers the
//!   contact. Where no table holds the point, auto falls back as with one table (the reason: other
//!   parameters if no table was built for them, else another geometry if none covers the contact, else
//!   outside the ranges).
//! - **Normal contact:** every evaluation states its contact ellipse and peak pressure ([`Patch`]): the
//!   exact solver's, by table the same Hertz solution (docs/model.md §2) of the evaluation's geometry (for
//!   the model's own geometry from its shape, made once). The frictional power (docs/model.md §6.3, §7.4)
//!   comes from the exact solver or a table of format version 2 (see [`Evaluation::frictional_power`]).
//! - **Derivatives:** by table, the exact derivatives of the interpolant chained through the frame turn,
//!   the minimum speed and the wetness clamp ([`Evaluator::table_jacobian`]). Elsewhere the caller
//!   differences [`Evaluator::evaluate`] with the solver tolerance tightened to [`DERIVATIVE_TOLERANCE`],
//!   so that solver noise (relative error ≈ tolerance/step) stays far below a step of 10⁻⁴.

use super::Model;
use super::frame::Solved;
use crate::error::{Error, Result, check_finite, check_positive};
use crate::params::{FrictionLaw, Geometry, GridParams, OperatingPoint, fallback_cells};
use crate::solver::{ContactShape, GlobalResults, SolverReport, WarmStart};

use crate::table::{Ellipse, Jacobian, Table, TableOutput, other_parameters};
use std::sync::Arc;

/// Normal force at or below which the wheel counts as lifted [N]: the library's smallest admissible load.
pub const LIFT_OFF_LOAD: f64 = 1e-3;
/// Default standstill regularisation: |V| below this speed is raised to it [m/s].
pub const DEFAULT_MINIMUM_SPEED: f64 = 0.01;
/// Solver tolerance of the exact evaluations behind a finite difference [-].
pub const DERIVATIVE_TOLERANCE: f64 = 1e-8;

/// Which evaluates an operating point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// The lookup table where usable (built for the model's parameters, point inside its ranges), else the
    /// exact solver. Without a table, the exact solver.
    Auto,
    /// Only the lookup table: points outside its ranges are clamped to them; a table built for other
    /// parameters is an error.
    TableOnly,
    /// Only the exact solver.
    ExactOnly,
}

impl std::fmt::Display for Mode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Mode::Auto => "auto",
            Mode::TableOnly => "table",
            Mode::ExactOnly => "exact",
        })
    }
}

/// The settings of the policy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Policy {
    /// Standstill regularisation: |V| below this speed is raised to it [m/s] (finite, > 0).
    pub minimum_speed: f64,
    /// A normal force at or below this load lifts the wheel [N] (finite).
    pub lift_off_load: f64,
    /// The grid of mode auto's exact solves.
    pub fallback_grid: FallbackGrid,
}

impl Default for Policy {
    fn default() -> Self {
        Policy {
            minimum_speed: DEFAULT_MINIMUM_SPEED,
            lift_off_load: LIFT_OFF_LOAD,
            fallback_grid: FallbackGrid::default(),
        }
    }
}

/// The grid on which mode auto solves the points no table serves (mode exact-only always solves on the
/// model's grid, the reference).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FallbackGrid {
    /// Where the model keeps the default grid (`grid` unset: 30 × 30, no accuracy target), the grid of each
    /// evaluation's contact ellipse and film ([`crate::params::fallback_cells`]: 16 to 24 cells along x
    /// and 6 to 12 across, the cheapest that meet the bundled table's accuracy against 30 × 30,
    /// docs/model.md §6.4); otherwise the model's grid.
    #[default]
    PerContact,
    /// Always the model's grid.
    Model,
}

impl Policy {
    /// Checks the settings; the error names the bad one.
    pub fn validate(&self) -> Result<()> {
        check_positive("minimum_speed", self.minimum_speed, "m/s")?;
        check_finite("lift_off_load", self.lift_off_load, "N")
    }
}

/// Why mode auto evaluated a point by the exact solver although it has a table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fallback {
    /// The table was built for other parameters than the model's.
    OtherParameters,
    /// The point lies outside the table's ranges.
    OutsideRanges,
    /// The evaluation's contact lies outside the table's geometry axes (a/b, p_ref); the table was built
    /// for the other parameters.
    OtherGeometry,
    /// The point lies in a cell across which the model jumps: the tabulated T_max (a film-loss jump), or
    /// a wet contact's friction where metal begins to cover the contact (the onset of the walls,
    /// [`crate::table::TableOutput::resolved`]).
    Unresolved,
    /// The interpolation at the point uses table points that did not converge when the table was built
    /// ([`crate::table::TableOutput::converged`]; in the hottest wet corner of a table over the whole range
    /// some points have no stable steady state, docs/model.md §9, while most contacts around them do).
    UnconvergedNodes,
}

/// Something an evaluation did that its caller may want to report (the evaluator reports it every time;
/// the FMU and the command line tell the user once).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Notice {
    /// Mode auto evaluated by the exact solver: why.
    FellBack(Fallback),
    /// Mode table-only clamped the point to the table's ranges.
    Clamped,
    /// The wetness was outside [0, 1]: the value given and the one used.
    WetnessClamped {
        /// The caller's wetness [-].
        given: f64,
        /// The wetness evaluated [-].
        used: f64,
    },
}

/// The notices of one evaluation: at most one about the wetness and one about the route (no allocation).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Notices {
    wetness: Option<Notice>,
    route: Option<Notice>,
}

impl Notices {
    /// The notices, the wetness one first.
    pub fn iter(&self) -> impl Iterator<Item = Notice> + '_ {
        self.wetness.iter().chain(&self.route).copied()
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.wetness.is_none() && self.route.is_none()
    }
}

/// The exact solver's results behind an evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct ExactResults {
    /// Global results in the caller's frame (F_x and F_y turned back when rolling backwards).
    pub global: GlobalResults,
    /// How the coupled solve went (iterations, residual, converged).
    pub report: SolverReport,
    /// The cells [nx, ny] of the grid it was solved on (mode auto's fallback grid, or the model's).
    pub cells: [usize; 2],
}

/// What evaluated an operating point, with its results in the caller's frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Evaluated {
    /// Interpolation in the lookup table: the interpolated outputs.
    Table(TableOutput),
    /// The exact coupled solver: its global results (what the friction law does not model is absent) and
    /// report.
    Exact(Box<ExactResults>),
    /// Nothing: the wheel is lifted (zero forces and moment, the bulk temperature, no fluid).
    Lifted(TableOutput),
}

impl Evaluated {
    /// The exact solver's report (None by table or lifted).
    pub fn report(&self) -> Option<&SolverReport> {
        match self {
            Evaluated::Exact(e) => Some(&e.report),
            _ => None,
        }
    }
}

/// The normal contact of an evaluation: the contact ellipse and its peak pressure (docs/model.md §2; all
/// zero for a lifted wheel).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Patch {
    /// Semi-axis a along the rolling direction x [m].
    pub semi_axis_a: f64,
    /// Semi-axis b along y [m].
    pub semi_axis_b: f64,
    /// Peak pressure p0 = 3·F_N/(2π·a·b) [Pa].
    pub peak_pressure: f64,
}

/// One evaluated operating point.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// What evaluated it, with the results.
    pub by: Evaluated,
    /// The contact ellipse and peak pressure (by the exact solver its own; by table Hertz of the table's
    /// geometry, bit for bit the exact solver's).
    pub patch: Patch,
    /// The index in [`Evaluator::tables`] of the table that evaluated the point (None: the exact solver,
    /// or a lifted wheel).
    pub table: Option<usize>,
    /// What the caller may want to report.
    pub notices: Notices,
}

impl Evaluation {
    /// The six outputs of an MBS contact in the caller's frame (from the exact solver: `in_range` true).
    /// An error if the exact solver's friction law does not model one of them
    /// ([`TableOutput::from_results`]; the Tomberger law models them all).
    pub fn outputs(&self) -> Result<TableOutput> {
        match &self.by {
            Evaluated::Table(o) | Evaluated::Lifted(o) => Ok(*o),
            Evaluated::Exact(e) => TableOutput::from_results(&e.global, &e.report),
        }
    }

    /// The frictional power dissipated in the contact, Σ|τ|·|s| over the slipping cells [W]
    /// (docs/model.md §6.3, §7.4; the work-rate basis of Tγ wear indices): the exact solver's, 0 for a lifted
    /// wheel, by table the interpolated one — None from a table of format version 1, which does not store
    /// it (the creep power −(F_x·ξ + F_y·η + M_z·φ)·V that its outputs give is not it in general: it also
    /// contains the elastic energy released at the trailing edge, so no estimate is made).
    pub fn frictional_power(&self) -> Option<f64> {
        match &self.by {
            Evaluated::Exact(e) => Some(e.global.frictional_power),
            Evaluated::Table(o) | Evaluated::Lifted(o) => o.frictional_power,
        }
    }
}

/// A point evaluated by the table (possibly clamped): the point's contact ellipse, its peak pressure [Pa],
/// the table's evaluation of the point (made to route it: its `in_range` is [`Table::in_range`]) and the
/// table's index in [`Evaluator::tables`].
struct ByTable<O>(Ellipse, f64, Result<O>, usize);

/// How one point is evaluated: by the table, or (None) by the exact solver.
type Route<O> = Option<ByTable<O>>;

/// A table evaluation made to route a point: the outputs alone, or with the Jacobian.
trait Routed: Sized {
    /// The table's evaluation of `point` with contact `e` where the table covers the contact, None where
    /// it does not.
    fn covered(table: &Table, point: &OperatingPoint, e: &Ellipse) -> Option<Result<Self>>;
    /// The outputs.
    fn outputs(&self) -> &TableOutput;
}

impl Routed for TableOutput {
    fn covered(table: &Table, point: &OperatingPoint, e: &Ellipse) -> Option<Result<Self>> {
        table.evaluate_covered(point, e)
    }
    fn outputs(&self) -> &TableOutput {
        self
    }
}

impl Routed for (TableOutput, Jacobian) {
    fn covered(table: &Table, point: &OperatingPoint, e: &Ellipse) -> Option<Result<Self>> {
        table.evaluate_covered_with_jacobian(point, e)
    }
    fn outputs(&self) -> &TableOutput {
        &self.0
    }
}

/// The point of a caller in the solved frame, its route and the notices so far (None: wheel lifted).
type Prepared<O> = Option<(Solved, Route<O>, Notices)>;

/// The evaluation policy for one model: mode, lookup table and settings.
#[derive(Debug, Clone)]
pub struct Evaluator {
    model: Model,
    mode: Mode,
    /// The tables the mode uses, in the order they are tried (none in mode exact-only).
    tables: Vec<Arc<Table>>,
    /// Per table, whether it was built for the model's parameters, geometry aside (kept: comparing them is
    /// a large part of a table evaluation's cost).
    table_params: Vec<bool>,
    /// The shape of the model's geometry, which gives the normal contact of a table evaluation at any load
    /// without solving for the eccentricity every time.
    model_shape: ContactShape,
    policy: Policy,
}

impl Evaluator {
    /// The evaluator of `model` in `mode` with `table` (shared read-only, e.g. from
    /// [`Table::load_shared`]; ignored in mode exact-only). Errors: bad settings
    /// ([`Error::OutOfRange`]), mode table-only without a table ([`Error::NoTable`]).
    pub fn new(
        model: Model,
        mode: Mode,
        table: Option<Arc<Table>>,
        policy: Policy,
    ) -> Result<Evaluator> {
        Self::with_tables(model, mode, table.into_iter().collect(), policy)
    }

    /// [`Evaluator::new`] with several tables, tried in the given order for each point (see the module
    /// documentation); none is as [`Evaluator::new`] without a table.
    pub fn with_tables(
        model: Model,
        mode: Mode,
        tables: Vec<Arc<Table>>,
        policy: Policy,
    ) -> Result<Evaluator> {
        policy.validate()?;
        let tables = if mode == Mode::ExactOnly {
            Vec::new()
        } else {
            tables
        };
        if mode == Mode::TableOnly && tables.is_empty() {
            return Err(Error::NoTable { mode });
        }
        let table_params = tables
            .iter()
            .map(|t| {
                let mut params = model.params().clone();
                params.geometry = t.params().geometry.clone();
                t.matches(&params)
            })
            .collect();
        let model_shape = ContactShape::of(&model.params().geometry, &model.params().material)?;
        Ok(Evaluator {
            model,
            mode,
            tables,
            table_params,
            model_shape,
            policy,
        })
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The mode.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The (first) table the mode uses (None in mode exact-only, or in mode auto without a table).
    pub fn table(&self) -> Option<&Arc<Table>> {
        self.tables.first()
    }

    /// The tables the mode uses, in the order they are tried.
    pub fn tables(&self) -> &[Arc<Table>] {
        &self.tables
    }

    /// The tables' locations ([`Table::location`]) separated by "; ", `<none>` without a table (for
    /// messages).
    pub fn table_locations(&self) -> String {
        if self.tables.is_empty() {
            return "<none>".into();
        }
        let at: Vec<String> = self.tables.iter().map(|t| t.location()).collect();
        at.join("; ")
    }

    /// The settings.
    pub fn policy(&self) -> &Policy {
        &self.policy
    }

    /// Whether there is a table, built for the model's parameters (geometry aside), that covers the
    /// model's own contact geometry (at the reference load of its p_ref).
    pub fn matches(&self) -> bool {
        let force = crate::table::axes::REFERENCE_FORCE;
        self.contact(&self.model.params().geometry, force)
            .is_ok_and(|(e, _)| self.matching().any(|(_, t)| t.covers(&e, force)))
    }

    /// The tables built for the model's parameters (geometry aside), in order.
    /// The tables built for the model's parameters, with their indices in [`Evaluator::tables`].
    fn matching(&self) -> impl Iterator<Item = (usize, &Table)> {
        self.tables
            .iter()
            .zip(&self.table_params)
            .enumerate()
            .filter_map(|(k, (t, p))| p.then_some((k, t.as_ref())))
    }

    /// The contact ellipse of `geometry` at normal force `force` [N] (Hertz, docs/model.md §2, or the
    /// prescribed semi-axes), with the load exponent of its kind, and its peak pressure p0 [Pa] (bit for
    /// bit the exact solver's).
    #[inline(always)]
    fn contact(&self, geometry: &Geometry, force: f64) -> Result<(Ellipse, f64)> {
        let shape = if *geometry == self.model.params().geometry {
            self.model_shape
        } else {
            ContactShape::of(geometry, &self.model.params().material)?
        };
        let h = shape.contact(force)?;
        let e = Ellipse {
            a: h.a,
            b: h.b,
            load_exponent: if geometry.semi_axes.is_some() {
                0.0
            } else {
                Ellipse::HERTZ
            },
        };
        Ok((e, h.p0))
    }

    /// Which way a point of the solved frame with `geometry` goes, and the notice about it.
    #[inline(always)]
    fn route<O: Routed>(
        &self,
        point: &OperatingPoint,
        geometry: &Geometry,
    ) -> Result<(Route<O>, Option<Notice>)> {
        let Some(first) = self.tables.first() else {
            return Ok((None, None));
        };
        let Some((_, built)) = self.matching().next() else {
            return match self.mode {
                Mode::TableOnly => Err(other_parameters(
                    first,
                    self.model.with(geometry, None, None).params(),
                )),
                _ => Ok((None, Some(Notice::FellBack(Fallback::OtherParameters)))),
            };
        };
        let (e, p0) = self.contact(geometry, point.normal_force)?;
        // the first table that covers the contact, holds the point inside its ranges, resolves its cell and
        // interpolates it from converged points; else the first that holds it in an unresolved cell or
        // next to unconverged points (table-only serves it as it is), else the first that covers the
        // contact at all (table-only clamps to it). Each evaluation flags a point outside the ranges (and
        // an invalid one is an error), as `Table::in_range` would: evaluating once is half the cost of
        // asking first
        let (mut held, mut clamped) = (None, None);
        for (index, table) in self.matching() {
            let Some(output) = O::covered(table, point, &e) else {
                continue;
            };
            match output.as_ref().map(|o| {
                let o = o.outputs();
                (o.in_range, o.resolved, o.converged)
            }) {
                Ok((true, true, true)) => return Ok((Some(ByTable(e, p0, output, index)), None)),
                Ok((true, resolved, _)) if held.is_none() => {
                    let why = if resolved {
                        Fallback::UnconvergedNodes
                    } else {
                        Fallback::Unresolved
                    };
                    held = Some((output, why, index));
                }
                _ if clamped.is_none() => clamped = Some((output, index)),
                _ => {}
            }
        }
        match (self.mode, held, clamped) {
            (Mode::TableOnly, Some((output, _, index)), _) => {
                Ok((Some(ByTable(e, p0, output, index)), None))
            }
            (Mode::TableOnly, None, Some((output, index))) => {
                Ok((Some(ByTable(e, p0, output, index)), Some(Notice::Clamped)))
            }
            (Mode::TableOnly, None, None) => Err(built.outside_geometry(&e, point.normal_force)),
            (_, Some((_, why, _)), _) => Ok((None, Some(Notice::FellBack(why)))),
            (_, None, Some(_)) => Ok((None, Some(Notice::FellBack(Fallback::OutsideRanges)))),
            (_, None, None) => Ok((None, Some(Notice::FellBack(Fallback::OtherGeometry)))),
        }
    }

    /// The caller's point in the solved frame, its route and notices (None: the wheel is lifted). A
    /// geometry other than the model's is validated.
    #[inline(always)]
    fn prepare<O: Routed>(
        &self,
        input: &OperatingPoint,
        geometry: &Geometry,
    ) -> Result<Prepared<O>> {
        if input.normal_force <= self.policy.lift_off_load {
            return Ok(None);
        }
        if *geometry != self.model.params().geometry {
            geometry.validate()?;
        }
        let solved = Solved::of(input, self.policy.minimum_speed);
        let mut notices = Notices::default();
        if solved.wetness_clamped() {
            notices.wetness = Some(Notice::WetnessClamped {
                given: input.wetness,
                used: solved.point.wetness,
            });
        }
        let (route, notice) = self.route::<O>(&solved.point, geometry)?;
        solved.check(input)?;
        notices.route = notice;
        Ok(Some((solved, route, notices)))
    }

    /// Evaluates one operating point given in the caller's (MBS) frame with the model's geometry:
    /// [`Evaluator::evaluate_at`].
    ///
    /// # Example
    ///
    /// In mode exact-only the evaluation is the exact solve of the point. Rolling backwards (V < 0) turns
    /// the frame: the contact rolls forwards in the turned frame, and F_x, F_y come back turned, so a
    /// braking wheel (F_x opposing ξ when rolling forwards) keeps F_x(−V, −ξ) = −F_x(V, ξ) by the
    /// symmetry of the contact (dry, η = φ = 0, bit for bit: the same solve). A normal force at or below
    /// [`LIFT_OFF_LOAD`] lifts the wheel: zero forces, no solve.
    ///
    /// ```
    /// use wheelrail::model::{Evaluated, Evaluator, Mode, Policy};
    /// use wheelrail::{Model, OperatingPoint, Params};
    /// let model = Model::new(Params::default())?;
    /// let evaluator = Evaluator::new(model.clone(), Mode::ExactOnly, None, Policy::default())?;
    /// let point = OperatingPoint { creepage_x: 0.002, ..OperatingPoint::default() };
    /// let forward = evaluator.evaluate(&point, None, &mut None)?.outputs()?;
    /// assert_eq!(forward.force_x, model.solve(&point)?.global.force_x);
    /// assert!(forward.force_x < 0.0 && forward.force_x.abs() < 0.5 * point.normal_force);
    ///
    /// let backward = OperatingPoint { creepage_x: -0.002, speed: -point.speed, ..point };
    /// let turned = evaluator.evaluate(&backward, None, &mut None)?.outputs()?;
    /// assert_eq!(turned.force_x, -forward.force_x);
    ///
    /// let lifted = OperatingPoint { normal_force: 0.0, ..point };
    /// let e = evaluator.evaluate(&lifted, None, &mut None)?;
    /// assert!(matches!(e.by, Evaluated::Lifted(_)));
    /// assert_eq!((e.outputs()?.force_x, e.outputs()?.force_y), (0.0, 0.0));
    /// # Ok::<(), wheelrail::Error>(())
    /// ```
    pub fn evaluate(
        &self,
        input: &OperatingPoint,
        tolerance: Option<f64>,
        warm: &mut Option<WarmStart>,
    ) -> Result<Evaluation> {
        self.evaluate_at(input, &self.model.params().geometry, tolerance, warm)
    }

    /// Evaluates one operating point given in the caller's (MBS) frame: any sign of the rolling speed, a
    /// lifted wheel, any wetness (see the module documentation), with the contact `geometry` (the model's
    /// or any other: the results are those of the model with this geometry). An exact solve uses the
    /// solver tolerance tightened to `tolerance` if given, starts from `warm` if it holds a state and
    /// leaves its own state there. Errors: invalid input (named as the caller gave it; the geometry by
    /// `geometry.curvature_x`, `geometry.semi_axes[0]`, …), mode table-only with a table for other
    /// parameters or another geometry, the solver's.
    pub fn evaluate_at(
        &self,
        input: &OperatingPoint,
        geometry: &Geometry,
        tolerance: Option<f64>,
        warm: &mut Option<WarmStart>,
    ) -> Result<Evaluation> {
        self.evaluate_on(input, geometry, None, tolerance, warm)
    }

    /// [`Evaluator::evaluate_at`] with an exact solve on `cells` [nx, ny] if given (e.g. those
    /// [`Evaluator::exact_cells`] gave for a nearby point: the evaluations behind a finite difference keep
    /// one grid), else on the grid the policy chooses.
    pub fn evaluate_on(
        &self,
        input: &OperatingPoint,
        geometry: &Geometry,
        cells: Option<[usize; 2]>,
        tolerance: Option<f64>,
        warm: &mut Option<WarmStart>,
    ) -> Result<Evaluation> {
        let Some((solved, route, notices)) = self.prepare::<TableOutput>(input, geometry)? else {
            return Ok(self.lifted());
        };
        let (mut by, patch, table) = match route {
            Some(ByTable(e, p0, output, index)) => {
                let patch = Patch {
                    semi_axis_a: e.a,
                    semi_axis_b: e.b,
                    peak_pressure: p0,
                };
                (Evaluated::Table(output?), patch, Some(index))
            }
            None => {
                let cells = match cells {
                    Some(c) => c,
                    None => self.solve_cells(&solved.point, geometry)?,
                };
                let e = self.exact(&solved.point, geometry, cells, tolerance, warm)?;
                let patch = Patch {
                    semi_axis_a: e.global.semi_axis_a,
                    semi_axis_b: e.global.semi_axis_b,
                    peak_pressure: e.global.peak_pressure,
                };
                (Evaluated::Exact(e), patch, None)
            }
        };
        match &mut by {
            Evaluated::Table(o) | Evaluated::Lifted(o) => {
                solved.turn_back(&mut o.force_x, &mut o.force_y)
            }
            Evaluated::Exact(e) => solved.turn_back(&mut e.global.force_x, &mut e.global.force_y),
        }
        Ok(Evaluation {
            by,
            patch,
            table,
            notices,
        })
    }

    /// The Jacobian of [`Evaluator::evaluate`]'s outputs (rows F_x, F_y, M_z, traction coefficient, T_max,
    /// fluid load fraction) with respect to the caller's inputs (columns ξ, η, φ, F_N, V, w), both in the
    /// caller's frame, where the table evaluates `input`: the interpolant's exact derivatives chained
    /// through the frame turn, the minimum speed and the wetness clamp. None where the exact solver would
    /// evaluate or the wheel is lifted. With the evaluation's notices. At the model's geometry:
    /// [`Evaluator::table_jacobian_at`].
    pub fn table_jacobian(&self, input: &OperatingPoint) -> Result<(Option<Jacobian>, Notices)> {
        self.table_jacobian_at(input, &self.model.params().geometry)
    }

    /// [`Evaluator::table_jacobian`] at the contact `geometry` (held fixed: curvatures or prescribed
    /// semi-axes): None unless the table evaluates the point.
    pub fn table_jacobian_at(
        &self,
        input: &OperatingPoint,
        geometry: &Geometry,
    ) -> Result<(Option<Jacobian>, Notices)> {
        let Some((solved, route, notices)) =
            self.prepare::<(TableOutput, Jacobian)>(input, geometry)?
        else {
            return Ok((None, Notices::default()));
        };
        let Some(ByTable(_, _, output, _)) = route else {
            return Ok((None, notices));
        };
        let (_, jac) = output?;
        Ok((Some(solved.jacobian_back(&jac)), notices))
    }

    /// The outputs of a lifted wheel.
    fn lifted(&self) -> Evaluation {
        Evaluation {
            by: Evaluated::Lifted(TableOutput {
                force_x: 0.0,
                force_y: 0.0,
                spin_moment: 0.0,
                traction_coefficient: 0.0,
                max_temperature: self.model.params().material.bulk_temperature,
                fluid_load_fraction: 0.0,
                frictional_power: Some(0.0),
                in_range: true,
                converged: true,
                resolved: true,
            }),
            patch: Patch {
                semi_axis_a: 0.0,
                semi_axis_b: 0.0,
                peak_pressure: 0.0,
            },
            table: None,
            notices: Notices::default(),
        }
    }

    /// The cells [nx, ny] on which an exact solve of `input` (in the caller's frame) with `geometry` would
    /// run: the model's grid, or in mode auto the policy's [`FallbackGrid`]. Errors: invalid input or
    /// geometry (as [`Evaluator::evaluate_at`]).
    pub fn exact_cells(&self, input: &OperatingPoint, geometry: &Geometry) -> Result<[usize; 2]> {
        if input.normal_force <= self.policy.lift_off_load {
            // a lifted wheel solves nothing
            return Ok(self.model.params().grid.cells());
        }
        if *geometry != self.model.params().geometry {
            geometry.validate()?;
        }
        let solved = Solved::of(input, self.policy.minimum_speed);
        solved.check(input)?;
        self.solve_cells(&solved.point, geometry)
    }

    /// The cells of an exact solve of `point` (in the solved frame): the per-contact fallback grid
    /// ([`crate::params::fallback_cells`] of the Hertz ellipse at the point's normal force and of its film)
    /// in mode auto with [`FallbackGrid::PerContact`] and the default grid, else the model's grid.
    fn solve_cells(&self, point: &OperatingPoint, geometry: &Geometry) -> Result<[usize; 2]> {
        let params = self.model.params();
        let per_contact = self.mode == Mode::Auto
            && self.policy.fallback_grid == FallbackGrid::PerContact
            && params.grid == GridParams::default();
        if !per_contact {
            return Ok(params.grid.cells());
        }
        let hertz = self.model.shape_of(geometry)?.contact(point.normal_force)?;
        // a film is modelled where the inlet film w·h_f,max is positive under the Tomberger law (§8)
        let wet = point.wetness * params.fluid.h_f_max > 0.0
            && params.friction.law == FrictionLaw::Tomberger;
        Ok(fallback_cells(hertz.a, hertz.b, wet))
    }

    /// The exact solver's results at a point of the solved frame with `geometry` on `cells` (see
    /// [`Evaluator::evaluate_at`]).
    fn exact(
        &self,
        point: &OperatingPoint,
        geometry: &Geometry,
        cells: [usize; 2],
        tolerance: Option<f64>,
        warm: &mut Option<WarmStart>,
    ) -> Result<Box<ExactResults>> {
        let model = self.model.with(geometry, Some(cells), tolerance);
        let s = model.solve_from(point, warm.as_ref())?;
        *warm = s.warm_start();
        Ok(Box::new(ExactResults {
            global: s.global,
            report: s.report,
            cells,
        }))
    }
}
