//! How a solve went: why the outer iteration stopped, which solver limited it, and the inner solvers'
//! iteration counts and residuals.

use crate::fluid::FilmSolution;
use crate::thermal::HeatSolution;
use serde::Serialize;
use serde::ser::{SerializeMap, Serializer};

/// The solver whose convergence criterion was still unmet when the outer iteration stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Limiter {
    /// The outer fixed point: the relative change of the adhesion limit or of the temperature rise per
    /// iteration was above `solver.tolerance` (or the last film was solved only to the looser tolerance of
    /// an early iteration): `solver.max_iterations` was too few.
    Outer,
    /// The fluid film solve of the last outer iteration did not converge within `solver.max_fluid_sweeps`,
    /// or found no film at all ([`Termination::Stalled`]).
    Film,
    /// The exact tangential solve of the last outer iteration (`tangential = "exact"`) did not reach its
    /// tolerance within its sweep limit (docs/model.md §6.5).
    Tangential,
    /// The heat partition's GMRES of the last outer iteration did not reach its tolerance.
    Heat,
}

impl std::fmt::Display for Limiter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Limiter::Outer => "outer",
            Limiter::Film => "film",
            Limiter::Tangential => "tangential",
            Limiter::Heat => "heat",
        })
    }
}

/// The first unmet convergence criterion of one outer iteration, inner solvers first (an unconverged inner
/// solve makes the outer residual meaningless): the film of the iteration (its solve reached its sweep
/// limit), then its tangential solve (`tangential_converged` false: the exact solver's sweep limit), then
/// its heat partition (GMRES exhausted its budget), then the outer iteration (its residual above the
/// tolerance, `outer_met` false, or a film solved only to the looser tolerance of an early iteration
/// rather than to `fluid_tolerance`: another iteration was needed). None when all are met.
pub(super) fn first_unmet(
    outer_met: bool,
    film: Option<&FilmSolution>,
    fluid_tolerance: f64,
    tangential_converged: bool,
    heat: Option<&HeatSolution>,
) -> Option<Limiter> {
    if !film.is_none_or(|f| f.converged) {
        Some(Limiter::Film)
    } else if !tangential_converged {
        Some(Limiter::Tangential)
    } else if !heat.is_none_or(|h| h.converged) {
        Some(Limiter::Heat)
    } else if !(outer_met && film.is_none_or(|f| f.residual <= fluid_tolerance)) {
        Some(Limiter::Outer)
    } else {
        None
    }
}

/// Why the outer iteration stopped.
///
/// In JSON (flattened into [`SolverReport`]'s object) it is two keys: `termination` ("converged",
/// "max_iterations_reached", "stalled" or "closed_form") and `limited_by` ("outer", "film", "tangential",
/// "heat", or null
/// unless the iteration limit was reached or the iteration stalled).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Termination {
    /// Every criterion was met: the outer residual, the film and the heat partition.
    Converged,
    /// The iteration limit was reached first: the result is NOT converged; `limited_by` says which
    /// criterion was still unmet (the film, then the heat partition, then the outer
    /// residual: an unconverged inner solve makes the outer residual meaningless).
    MaxIterationsReached {
        /// The solver whose criterion was unmet at the last iteration.
        limited_by: Limiter,
    },
    /// The iteration stopped before its limit because further iterations could not help: the outer
    /// residual was met, but the film of the last iteration had no solution (neither Newton nor the
    /// Gauss–Seidel fallback converged; the result holds Newton's last film). The result is NOT converged.
    Stalled {
        /// The inner solver without solution (the film).
        limited_by: Limiter,
    },
    /// A closed-form law (Polach) needs no iteration.
    ClosedForm,
}

impl Termination {
    /// Whether the result is a solution: converged, or closed form.
    pub fn converged(self) -> bool {
        matches!(self, Termination::Converged | Termination::ClosedForm)
    }

    /// The solver that kept the iteration from converging (None if it did not).
    pub fn limited_by(self) -> Option<Limiter> {
        match self {
            Termination::MaxIterationsReached { limited_by }
            | Termination::Stalled { limited_by } => Some(limited_by),
            _ => None,
        }
    }

    /// The `termination` text: "converged", "max_iterations_reached", "stalled" or "closed_form".
    pub fn name(self) -> &'static str {
        match self {
            Termination::Converged => "converged",
            Termination::MaxIterationsReached { .. } => "max_iterations_reached",
            Termination::Stalled { .. } => "stalled",
            Termination::ClosedForm => "closed_form",
        }
    }
}

impl Serialize for Termination {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(2))?;
        map.serialize_entry("termination", self.name())?;
        map.serialize_entry("limited_by", &self.limited_by())?;
        map.end()
    }
}

/// How the coupled solve went.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SolverReport {
    /// Outer iterations performed.
    pub iterations: usize,
    /// Final residual: the larger of the relative change of the adhesion limit and of the temperature rise
    /// in the last iteration, or, where the outer iteration contracts measurably (plain steps, the last
    /// two temperature changes falling by q < 1/2; near the fixed point the secant q over any update along
    /// the increment), the a-posteriori estimate of the result's distance from the fixed point, q/(1 − q)
    /// times it after a plain step (docs/model.md §9).
    pub residual: f64,
    /// Whether the result is converged (equal to `termination.converged()`).
    pub converged: bool,
    /// Why the iteration stopped, and which solver limited it.
    #[serde(flatten)]
    pub termination: Termination,
    /// Largest number of root-finder iterations of one microcontact separation solve.
    pub max_microcontact_iterations: usize,
    /// Iterations of the last fluid film solve (0 without fluid).
    pub fluid_sweeps: usize,
    /// Residual of the last fluid film solve (0 without fluid).
    pub fluid_residual: f64,
    /// Largest volume-balance residual of a cell of the last film solve, relative to the flow of the
    /// inlet film through one cell width (0 without fluid) [-].
    pub fluid_balance_residual: f64,
    /// Gauss–Seidel sweeps of the last exact tangential solve (0 with FASTSIM, docs/model.md §6.5).
    pub tangential_sweeps: usize,
    /// Residual of the last exact tangential solve: its largest traction change of a sweep over the largest
    /// traction (0 with FASTSIM) [-].
    pub tangential_residual: f64,
    /// GMRES steps of the last heat partition solve (0 without heat).
    pub heat_iterations: usize,
    /// Relative residual of the last heat partition solve (0 without heat) [-].
    pub heat_residual: f64,
    /// Times the fluid film had no solution at a temperature update, so that the update was halved back
    /// and the film restarted cold.
    pub temperature_backtracks: usize,
}

impl SolverReport {
    /// The report of a closed-form evaluation: no iteration, converged.
    pub fn closed_form() -> Self {
        Self {
            iterations: 0,
            residual: 0.0,
            converged: true,
            termination: Termination::ClosedForm,
            max_microcontact_iterations: 0,
            fluid_sweeps: 0,
            fluid_residual: 0.0,
            fluid_balance_residual: 0.0,
            tangential_sweeps: 0,
            tangential_residual: 0.0,
            heat_iterations: 0,
            heat_residual: 0.0,
            temperature_backtracks: 0,
        }
    }

    /// The report before the first outer iteration.
    pub(super) fn start() -> Self {
        Self {
            residual: f64::INFINITY,
            converged: false,
            termination: Termination::MaxIterationsReached {
                limited_by: Limiter::Outer,
            },
            ..Self::closed_form()
        }
    }

    /// Records why the iteration stopped (`converged` follows).
    pub(super) fn stop(&mut self, termination: Termination) {
        self.termination = termination;
        self.converged = termination.converged();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A four-cell film as the film solver reports it.
    fn film(converged: bool, residual: f64) -> FilmSolution {
        let v = vec![0.0; 4];
        FilmSolution {
            separation: v.clone(),
            fluid_pressure: v.clone(),
            fluid_height: v.clone(),
            void_height: v.clone(),
            area_fraction: v.clone(),
            metal_load: v,
            regime: vec![crate::fluid::Regime::Dry; 4],
            iterations: 3,
            residual,
            balance_residual: 0.0,
            converged,
            inflow: 0.0,
            rejected: 0.0,
            outflow: 0.0,
            expelled: 0.0,
        }
    }

    /// A heat partition as GMRES reports it (the budget of 600 steps is a constant of the partition
    /// solve, never exhausted by the solver's grids: an exhausted one is provoked here).
    fn heat(converged: bool) -> HeatSolution {
        HeatSolution {
            temperature_rise: vec![1.0; 4],
            q_wheel: vec![1.0; 4],
            q_rail: vec![1.0; 4],
            mismatch: 0.0,
            iterations: 600,
            residual: if converged { 1e-13 } else { 1e-9 },
            converged,
        }
    }

    #[test]
    fn the_first_unmet_criterion_is_reported_inner_solvers_first() {
        let (good_film, good_heat) = (film(true, 1e-9), heat(true));
        let all = |outer, f: &FilmSolution, h: &HeatSolution| {
            first_unmet(outer, Some(f), 1e-8, true, Some(h))
        };
        assert_eq!(all(true, &good_film, &good_heat), None);
        assert_eq!(first_unmet(true, None, 1e-8, true, None), None);
        assert_eq!(all(false, &good_film, &good_heat), Some(Limiter::Outer));
        assert_eq!(
            first_unmet(false, None, 1e-8, true, None),
            Some(Limiter::Outer)
        );
        // the heat partition's GMRES exhausted its budget
        assert_eq!(all(true, &good_film, &heat(false)), Some(Limiter::Heat));
        assert_eq!(all(false, &good_film, &heat(false)), Some(Limiter::Heat));
        assert_eq!(
            first_unmet(true, None, 1e-8, true, Some(&heat(false))),
            Some(Limiter::Heat)
        );
        // the film did not converge; one converged only to the looser tolerance of an early iteration
        // needs another outer iteration
        assert_eq!(
            all(true, &film(false, 1e-9), &good_heat),
            Some(Limiter::Film)
        );
        assert_eq!(
            all(true, &film(true, 1e-7), &good_heat),
            Some(Limiter::Outer)
        );
        assert_eq!(
            all(false, &film(false, 1.0), &heat(false)),
            Some(Limiter::Film)
        );
        // the exact tangential solve reached its sweep limit: after the film, before the heat partition
        let tangential = |outer, f: &FilmSolution, h: &HeatSolution| {
            first_unmet(outer, Some(f), 1e-8, false, Some(h))
        };
        assert_eq!(
            tangential(false, &good_film, &heat(false)),
            Some(Limiter::Tangential)
        );
        assert_eq!(
            tangential(true, &film(false, 1e-9), &good_heat),
            Some(Limiter::Film)
        );
        assert_eq!(
            first_unmet(true, None, 1e-8, false, None),
            Some(Limiter::Tangential)
        );
    }

    #[test]
    fn the_report_serialises_termination_and_limiter_as_two_flat_keys() {
        let mut r = SolverReport::start();
        r.stop(Termination::MaxIterationsReached {
            limited_by: Limiter::Heat,
        });
        let v = serde_json::to_value(r).unwrap();
        assert_eq!(v["termination"], "max_iterations_reached");
        assert_eq!(v["limited_by"], "heat");
        assert_eq!(v["converged"], false);
        r.stop(Termination::Converged);
        let v = serde_json::to_value(r).unwrap();
        assert_eq!(v["termination"], "converged");
        assert!(v["limited_by"].is_null());
        assert_eq!(v["converged"], true);
        r.stop(Termination::Stalled {
            limited_by: Limiter::Film,
        });
        let v = serde_json::to_value(r).unwrap();
        assert_eq!(v["termination"], "stalled");
        assert_eq!(v["limited_by"], "film");
        assert_eq!(v["converged"], false);
        r.stop(Termination::MaxIterationsReached {
            limited_by: Limiter::Tangential,
        });
        assert_eq!(serde_json::to_value(r).unwrap()["limited_by"], "tangential");
        let v = serde_json::to_value(SolverReport::closed_form()).unwrap();
        assert_eq!(v["termination"], "closed_form");
        assert!(v["limited_by"].is_null());
    }
}
