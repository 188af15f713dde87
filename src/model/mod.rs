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
    Fallback, LIFT_OFF_LOAD, Mode, Notice, Notices, Patch, Policy,
};

use crate::error::Result;
use crate::params::{Geometry, OperatingPoint, Params};
/// Where an exact solve can start from (the state of a nearby solution), as the evaluator takes it.
pub use crate::solver::WarmStart;
use crate::solver::{self, SetupCache, Solution};
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

    /// The model with `geometry` (validated by the caller) and the coupled solver's tolerance tightened to
    /// at most `tolerance` if given (for the evaluations behind finite differences): this model itself
    /// when nothing changes, else a copy.
    fn with(&self, geometry: &Geometry, tolerance: Option<f64>) -> Cow<'_, Model> {
        if *geometry == self.params.geometry && tolerance.is_none() {
            return Cow::Borrowed(self);
        }
        let mut params = self.params.clone();
        params.geometry = geometry.clone();
        if let Some(t) = tolerance {
            params.solver.tolerance = params.solver.tolerance.min(t);
        }
        Cow::Owned(Model {
            params,
            cache: Arc::clone(&self.cache),
        })
    }
}
