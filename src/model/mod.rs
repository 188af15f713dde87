//! The model as its users see it: a validated parameter set ([`Model`]) that solves operating points, and
//! the evaluation policy ([`Evaluator`]) that the FMU and the command line share.
//!
//! The data path of one evaluation (one FMU step, one `wheelrail point`):
//!
//! 1. The caller translates its own values (FMU variables, CLI flags) into an [`OperatingPoint`] in the
//!    multibody (MBS) frame: signed rolling speed, any normal force, any wetness.
//! 2. [`Evaluator::evaluate`] applies the policy (`policy`): a lifted wheel needs no solve; the wetness is
//!    clamped to [0, 1]; the point is turned into the frame in which the contact rolls forwards at a speed
//!    of at least the minimum speed (`frame`); the mode routes it to the lookup table
//!    ([`crate::table::Table`]) or to the exact coupled solver ([`Model::solve_from`], [`crate::solver`]).
//! 3. The results come back turned into the MBS frame, with what evaluated them and the notices (fell back
//!    to the exact solver, clamped to the table's ranges, wetness clamped) for the caller to report once.
//! 4. The caller translates them back: FMU outputs, statuses and log lines; CLI JSON and warnings.
//!
//! Conventions of the policy: docs/model.md §1 (frame, rolling backwards, standstill, lifted wheel) and
//! §12.3 (the tabulated model).

mod frame;
mod policy;
#[cfg(test)]
mod tests;

pub use policy::{
    DEFAULT_MINIMUM_SPEED, DERIVATIVE_TOLERANCE, Evaluated, Evaluation, Evaluator, ExactResults,
    Fallback, FallbackGrid, LIFT_OFF_LOAD, Mode, Notice, Notices, Patch, Policy,
};

use crate::error::Result;
use crate::params::{Geometry, GridParams, OperatingPoint, Params};
/// Where an exact solve can start from (the state of a nearby solution), as the evaluator takes it.
pub use crate::solver::WarmStart;
use crate::solver::{self, ContactShape, SetupCache, Solution};
use std::borrow::Cow;
use std::sync::Arc;

/// The model for one parameter set: the parameters are validated once, when it is made, and every solve
/// uses them as they are. It keeps the set-up of its last solve ([`SetupCache`]: contact shape,
/// microcontact and heat model), shared with its clones, for the next solve with the same contact and
/// surface speeds; a pure function of its inputs, so no result depends on it (models compare by their
/// parameters).
#[derive(Debug, Clone)]
pub struct Model {
    params: Params,
    cache: Arc<SetupCache>,
}

impl PartialEq for Model {
    fn eq(&self, other: &Model) -> bool {
        self.params == other.params
    }
}

impl Model {
    /// The model of `params`, validated (an [`crate::Error::OutOfRange`] names the first bad value).
    ///
    /// # Example
    ///
    /// Equal gap curvatures A = B make the contact a circle, whose Hertz radius has the closed form
    /// a = (3·F_N·R/(4·E*))^(1/3) with R = 1/(2A) (docs/model.md §2): at A = B = 2.5 /m (R = 0.2 m),
    /// 100 kN and E* = E/(2(1 − ν²)) = 113 GPa, a = (3·1e5·0.2/(4·1.13e11))^(1/3) ≈ 5.1 mm; and the peak
    /// pressure is p0 = 3·F_N/(2π·a²) ≈ 1.8 GPa. A grid without cells (outside 4–400) is refused.
    ///
    /// ```
    /// use wheelrail::{Model, OperatingPoint, Params};
    /// let mut params = Params::default();
    /// params.geometry.curvature_x = 2.5;
    /// params.geometry.curvature_y = 2.5;
    /// let model = Model::new(params.clone())?;
    /// let point = OperatingPoint { normal_force: 100e3, ..OperatingPoint::default() };
    /// let g = model.solve(&point)?.global;
    /// let e_star = params.material.at(params.material.bulk_temperature).e_star;
    /// let a = (3.0 * 100e3 * 0.2 / (4.0 * e_star)).cbrt();
    /// assert!((g.semi_axis_a / a - 1.0).abs() < 1e-6 && (g.semi_axis_b / a - 1.0).abs() < 1e-6);
    /// assert!((a - 5.1e-3).abs() < 0.05e-3, "a = {a}");
    /// let p0 = 3.0 * 100e3 / (2.0 * std::f64::consts::PI * a * a);
    /// assert!((g.peak_pressure / p0 - 1.0).abs() < 1e-6 && (p0 - 1.8e9).abs() < 0.05e9);
    ///
    /// params.grid.nx = 0;
    /// assert!(Model::new(params).is_err());
    /// # Ok::<(), wheelrail::Error>(())
    /// ```
    pub fn new(params: Params) -> Result<Model> {
        params.validate()?;
        Ok(Model {
            params,
            cache: Arc::default(),
        })
    }

    /// The (validated) parameter set.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// Solves one operating point with the exact coupled solver from a cold start ([`solver::solve`]).
    ///
    /// # Example
    ///
    /// At a small creepage the whole contact sticks and the force is Kalker's linear theory,
    /// F_x = −G·a·b·C11·ξ (docs/model.md §6.1): at the default contact (a ≈ 5.9 mm, b ≈ 10.5 mm at
    /// 100 kN), G ≈ 80 GPa and C11 ≈ 4.3, ξ = 1e-5 gives F_x ≈ −0.19 kN (the solver on its default grid
    /// within 5 %). At ξ = 1 % the contact slides and the traction coefficient |F_T|/F_N saturates well
    /// below 1 (about 0.36 dry).
    ///
    /// ```
    /// use wheelrail::{Model, OperatingPoint, Params};
    /// use wheelrail::tangential::kalker_coefficients;
    /// let model = Model::new(Params::default())?;
    /// let at = |xi: f64| OperatingPoint { creepage_x: xi, creepage_y: 0.0, spin: 0.0, ..OperatingPoint::default() };
    /// let s = model.solve(&at(1e-5))?;
    /// assert!(s.report.converged);
    /// let g = s.global;
    /// let m = model.params().material.at(model.params().material.bulk_temperature);
    /// let k = kalker_coefficients(g.semi_axis_a, g.semi_axis_b, m.poisson)?;
    /// let linear = -m.shear_modulus * g.semi_axis_a * g.semi_axis_b * k.c11 * 1e-5;
    /// assert!((g.force_x / linear - 1.0).abs() < 0.05, "{} vs Kalker {linear}", g.force_x);
    /// assert!((linear + 190.0).abs() < 10.0, "{linear}");
    ///
    /// let full_slip = model.solve(&at(0.01))?.global;
    /// assert!(full_slip.traction_coefficient > 0.3 && full_slip.traction_coefficient < 0.45);
    /// # Ok::<(), wheelrail::Error>(())
    /// ```
    pub fn solve(&self, point: &OperatingPoint) -> Result<Solution> {
        self.solve_from(point, None)
    }

    /// Solves one operating point starting from a nearby solution's state ([`solver::solve_from`]), with
    /// the set-up kept from the last solve where its inputs are unchanged (bit for bit the same result).
    pub fn solve_from(&self, point: &OperatingPoint, warm: Option<&WarmStart>) -> Result<Solution> {
        solver::coupled::solve_cached(&self.params, point, warm, &self.cache)
    }

    /// How many set-up parts (contact shape, microcontact, heat model) this model's solves, and its
    /// clones', have reused.
    pub fn setup_reuses(&self) -> usize {
        self.cache.hits()
    }

    /// Solves a sequence of nearby operating points with warm starts, in parallel chains
    /// ([`solver::solve_sweep`]).
    pub fn sweep(&self, points: &[OperatingPoint]) -> Vec<Result<Solution>> {
        solver::solve_sweep(&self.params, points)
    }

    /// The contact shape of `geometry` with the model's material (from the set-up cache, which the next
    /// solve of that geometry finds it in).
    fn shape_of(&self, geometry: &Geometry) -> Result<ContactShape> {
        self.cache.shape(geometry, &self.params.material)
    }

    /// The model with `geometry` (validated by the caller), the grid of `cells` [nx, ny] if given and the
    /// coupled solver's tolerance tightened to at most `tolerance` if given (for the evaluations behind
    /// finite differences): this model itself when nothing changes, else a copy.
    fn with(
        &self,
        geometry: &Geometry,
        cells: Option<[usize; 2]>,
        tolerance: Option<f64>,
    ) -> Cow<'_, Model> {
        let cells = cells.filter(|c| *c != self.params.grid.cells());
        if *geometry == self.params.geometry && cells.is_none() && tolerance.is_none() {
            return Cow::Borrowed(self);
        }
        let mut params = self.params.clone();
        params.geometry = geometry.clone();
        if let Some([nx, ny]) = cells {
            params.grid = GridParams {
                nx,
                ny,
                accuracy: 0.0,
            };
        }
        if let Some(t) = tolerance {
            params.solver.tolerance = params.solver.tolerance.min(t);
        }
        Cow::Owned(Model {
            params,
            cache: Arc::clone(&self.cache),
        })
    }
}
