//! The outer fixed-point iteration of the coupled model (paper Fig. 1, docs/model.md §9).
//!
//! Start at T = T0 (or a warm start's temperature), p_f = 0. Each iteration: materials at T → microcontact
//! and fluid film ([`Setup::local`]) → failure stress and adhesion limit ([`Setup::adhesion`]) → FASTSIM
//! or, with `tangential = "exact"`, Kalker's exact steady rolling with τ_l as the traction bound
//! (docs/model.md §6.5; started from the previous iteration's tractions) (traction, slip) → frictional heat → surface temperature (the heat partition) → residual → relaxed
//! temperature update ([`Relaxation`]), or Aitken's extrapolation where a solve started near its fixed point
//! contracts measurably ([`Coupled::update`]); a film without solution backtracks the update
//! ([`Backtracking`]).

use super::assembly::{Iterate, assemble};
use super::backtracking::Backtracking;
use super::cache::SetupCache;
use super::closed_form::solve_polach;
use super::local::{Adhesion, DryIterate, Local};
use super::relaxation::Relaxation;
use super::report::{Limiter, SolverReport, Termination, first_unmet};
use super::setup::Setup;
use super::solution::Solution;
use super::warm::WarmStart;
use crate::contact::HertzContact;
use crate::error::{Error, Result, Stage};
use crate::fluid::{FilmSolution, FilmStart};
use crate::materials::MaterialState;
use crate::params::{FrictionLaw, OperatingPoint, Params};
use crate::tangential::{
    Creepages, KalkerCoefficients, TractionField, fastsim, kalker_coefficients,
};
use crate::thermal::HeatSolution;

/// Solves one operating point with the exact (coupled) model from a cold start (T = T0, no fluid); see
/// the module documentation.
pub fn solve(params: &Params, point: &OperatingPoint) -> Result<Solution> {
    solve_from(params, point, None)
}

/// As [`solve`], starting the fixed point from a nearby solution's state ([`WarmStart`]): its temperature,
/// its separations as the microcontact Newton's starting points, its film as the film solver's start and
/// its tractions as the exact tangential solver's start.
/// The start is used only if it fits the grid (same nx × ny); otherwise the solve starts cold. The
/// converged result is the same fixed point to within the solver tolerance.
pub fn solve_from(
    params: &Params,
    point: &OperatingPoint,
    warm: Option<&WarmStart>,
) -> Result<Solution> {
    params.validate()?;
    solve_cached(params, point, warm, &SetupCache::default())
}

/// [`solve_from`] with parameters that have passed [`Params::validate`] (the point is validated here),
/// taking the set-up's contact shape, microcontact model and heat model from `cache` where it holds them
/// for this solve's inputs (and leaving this solve's there): the same bits as without the cache
/// ([`SetupCache`]).
pub(crate) fn solve_cached(
    params: &Params,
    point: &OperatingPoint,
    warm: Option<&WarmStart>,
    cache: &SetupCache,
) -> Result<Solution> {
    point.validate()?;
    let (hertz, mat0, kalker, creep) = contact_of(params, point, cache)?;
    match params.friction.law {
        FrictionLaw::Polach => return solve_polach(params, point, &hertz, &kalker, creep),
        FrictionLaw::Tomberger | FrictionLaw::Constant => {}
    }
    let setup = Setup::new(params, point, hertz, &mat0, &kalker, creep, cache)?;
    let iterate = Coupled::start(&setup, warm).run()?;
    Ok(assemble(&setup, iterate))
}

/// What a solve of `point` is set up from: the Hertz contact at its normal force (the shape from `cache`,
/// docs/model.md §2), the material at the bulk temperature, Kalker's coefficients of the ellipse (§6.1)
/// and the creepages.
fn contact_of(
    params: &Params,
    point: &OperatingPoint,
    cache: &SetupCache,
) -> Result<(HertzContact, MaterialState, KalkerCoefficients, Creepages)> {
    let hertz = cache
        .shape(&params.geometry, &params.material)?
        .contact(point.normal_force)?;
    let mat0 = params.material.at(params.material.bulk_temperature);
    let kalker = kalker_coefficients(hertz.a, hertz.b, mat0.poisson)?;
    let creep = Creepages {
        xi: point.creepage_x,
        eta: point.creepage_y,
        phi: point.spin,
    };
    Ok((hertz, mat0, kalker, creep))
}

/// The largest contraction factor of the outer fixed point for which the a-posteriori estimate
/// q/(1 − q)·change stands for the residual ([`Coupled::contraction`]): at most the change itself.
const MAX_CONTRACTION: f64 = 0.5;

/// The largest measured contraction factor q for which the outer iteration extrapolates its update by
/// Aitken's 1/(1 − q) ([`Relaxation::extrapolate`]): a slow contraction of a hot contact is nonlinear
/// and alternates between monotone and oscillating steps, where the extrapolation overshoots.
const MAX_EXTRAPOLATED_CONTRACTION: f64 = 0.2;

/// The largest relative temperature change of the first iteration from a warm start (its largest
/// increment over the largest rise) for which the solve counts as started near its fixed point
/// ([`Coupled::near`]).
const NEAR_START: f64 = 0.1;

/// Iterations without a new smallest residual after which the outer iteration counts as stalled and damps
/// its oscillating cells one by one ([`Relaxation::damp_cells`], docs/model.md §9).
const STALL_ITERATIONS: usize = 6;

/// The state of the outer iteration between two iterations.
struct Coupled<'s, 'w> {
    setup: &'s Setup<'s>,
    /// The temperature iterate per cell [K].
    temperature: Vec<f64>,
    /// Per-cell separations to start the first iteration's microcontact Newton from: the warm start's.
    dry_guess: Option<Vec<f64>>,
    /// The last iterate's dry state and the materials it was solved at (see [`DryIterate`]).
    dry_previous: Option<DryIterate>,
    /// The adhesion limit of the last iteration [Pa].
    prev_tau: Option<Vec<f64>>,
    /// The film of the last iteration (dropped on a backtrack: the film restarts cold).
    film: Option<FilmSolution>,
    /// The warm start's film, the start of the first iteration's film only.
    warm_film: Option<FilmStart<'w>>,
    /// Whether the temperature started from a warm start's (see [`Coupled::film_tolerance`]).
    warm_temperature: bool,
    /// The temperature part of the last outer residual (∞ before the first).
    temperature_change: f64,
    /// The last temperature update where its step measures the contraction of the fixed-point map
    /// ([`Coupled::contraction`]) and no backtrack followed: near the fixed point ([`Coupled::near`]) an
    /// update along its increment (T ← T + ω·Δ, any global ω, no per-cell damping), otherwise a plain
    /// one.
    last_update: Option<LastUpdate>,
    /// Whether the solve started near its fixed point: from a warm start's temperature that the first
    /// iteration changed by at most [`NEAR_START`]. Only then is the contraction measured over relaxed
    /// and extrapolated updates and do updates extrapolate; from a cold or distant start the iteration is
    /// nonlinear in its first steps, and the contraction is measured after plain steps only, as the
    /// ratio of the last two changes.
    near: bool,
    /// Whether an extrapolated update was taken back in this solve ([`Coupled::reject`]): no further
    /// update extrapolates.
    extrapolation_rejected: bool,
    /// The last heat partition: the start of the next one.
    heat_solution: Option<HeatSolution>,
    /// The tractions to start the exact tangential solve from [Pa]: the last iteration's, or the warm
    /// start's (unused with FASTSIM).
    traction_start: Option<Vec<[f64; 2]>>,
    /// Whether the last exact tangential solve converged (true with FASTSIM, which does not iterate).
    tangential_converged: bool,
    relaxation: Relaxation,
    /// The smallest residual so far and the iteration that reached it (for the stall test).
    best: (f64, usize),
    backtracking: Backtracking,
    /// Whether this iteration's film had no solution (Newton's last film kept, see [`Coupled::local`]).
    film_failed: bool,
    report: SolverReport,
}

/// A temperature update along its increment: the iterate it started from and that iterate's target [K],
/// and the target's largest rise over T0 (at least 1 K, the scale of the relative changes) [K].
struct LastUpdate {
    iterate: Vec<f64>,
    target: Vec<f64>,
    rise_scale: f64,
    /// Whether the update extrapolated beyond the target (ω > 1, [`Relaxation::extrapolate`]).
    extrapolated: bool,
}

/// The contraction of the outer fixed point measured over the last update's step s = T_k − T_{k−1}
/// ([`Coupled::contraction`]).
#[derive(Clone, Copy)]
struct Contraction {
    /// The contraction factor q = max|T*(T_k) − T*(T_{k−1})| / max|s|, each over its rise scale (after a
    /// plain step the ratio of the last two relative changes) [-].
    factor: f64,
    /// This iteration's temperature increment over the step, max|T*(T_k) − T_k| / max|s| (q itself after
    /// a plain step, T_k = T*(T_{k−1})) [-].
    increment_ratio: f64,
    /// Whether the increment points along the step (Σ Δ_k·s > 0): the iteration approaches the fixed
    /// point from one side, which Aitken's extrapolation 1/(1 − q) assumes (false where the contraction is
    /// not measured over the step: far from the fixed point, [`Coupled::near`]).
    monotone: bool,
}

impl Contraction {
    /// The a-posteriori estimate of the iterate's distance from the fixed point (docs/model.md §9), in the
    /// units of the outer residual: the returned temperature T*(T_k) lies within q/(1 − q) times the
    /// relative temperature change `temperature_change`; T_k itself within the increment over 1 − q,
    /// which τ_l(T_k) follows by its measured sensitivity, its relative change `tau_change` over the
    /// step: increment ratio/(1 − q) times `tau_change`.
    fn residual(self, temperature_change: f64, tau_change: f64) -> f64 {
        let q = self.factor;
        if self.increment_ratio == q {
            // (the same value, after a plain step)
            q / (1.0 - q) * temperature_change.max(tau_change)
        } else {
            (q * temperature_change).max(self.increment_ratio * tau_change) / (1.0 - q)
        }
    }
}

/// What one outer iteration produced before the convergence test.
struct Step {
    /// The materials per cell of the iterate.
    mats: Vec<MaterialState>,
    local: Local,
    adhesion: Adhesion,
    traction: TractionField,
    /// The temperature this traction field produces [K].
    target: Vec<f64>,
    /// Heat flux density into the wheel [W/m²].
    heat_flux_wheel: Vec<f64>,
}

impl<'s, 'w> Coupled<'s, 'w> {
    /// The iteration before its first step, from `warm` if it fits the grid. A warm temperature is used
    /// only when it feeds back (heat on, Tomberger law).
    fn start(setup: &'s Setup<'s>, warm: Option<&'w WarmStart>) -> Self {
        let warm = warm.filter(|w| w.fits(&setup.grid));
        let warm_temperature = warm.is_some() && setup.temperature_feeds_back();
        let temperature = match warm {
            Some(w) if warm_temperature => w.temperature.clone(),
            _ => vec![setup.bulk_temperature(); setup.grid.len()],
        };
        Self {
            setup,
            temperature,
            dry_guess: warm.map(|w| w.separation.clone()),
            dry_previous: None,
            prev_tau: None,
            film: None,
            warm_film: warm.and_then(WarmStart::film),
            warm_temperature,
            temperature_change: f64::INFINITY,
            last_update: None,
            near: false,
            extrapolation_rejected: false,
            heat_solution: None,
            traction_start: warm
                .filter(|_| setup.steady.is_some())
                .map(|w| w.traction.clone()),
            tangential_converged: true,
            relaxation: Relaxation::new(setup.params.solver.relaxation),
            best: (f64::INFINITY, 0),
            backtracking: Backtracking::default(),
            film_failed: false,
            report: SolverReport::start(),
        }
    }

    /// Iterates until every criterion is met or the iteration limit is reached (the report says which).
    fn run(mut self) -> Result<Iterate> {
        loop {
            if let Some(step) = self.iteration()? {
                return Ok(self.finish(step));
            }
        }
    }

    /// One outer iteration with its convergence test: the last step once the iteration stops (the report
    /// says why), None where another iteration follows (updated, backtracked, or an extrapolation taken
    /// back).
    fn iteration(&mut self) -> Result<Option<Step>> {
        self.report.iterations += 1;
        let Some(step) = self.step()? else {
            return Ok(None);
        };
        let increment: Vec<f64> = step
            .target
            .iter()
            .zip(&self.temperature)
            .map(|(t, tc)| t - tc)
            .collect();
        let (temperature_change, tau_change) = self.outer_changes(&step, &increment);
        if self.temperature_change.is_infinite() {
            self.near = self.warm_temperature && temperature_change <= NEAR_START;
        }
        let contraction = self.contraction(&step.target, temperature_change);
        let overshot = self.overshot(temperature_change);
        if !overshot {
            self.temperature_change = temperature_change;
        }
        // the a-posteriori estimate of this iterate's distance from the fixed point where the
        // iteration is known to contract, else the change itself
        self.report.residual = contraction.map_or(temperature_change.max(tau_change), |c| {
            c.residual(temperature_change, tau_change)
        });
        self.watch_for_stall();

        let solver = &self.setup.params.solver;
        let outer_met = self.report.residual <= solver.tolerance;
        let unmet = first_unmet(
            outer_met,
            step.local.film.as_ref(),
            solver.fluid_tolerance,
            self.tangential_converged,
            self.heat_solution.as_ref(),
        );
        let termination = match unmet {
            None => Termination::Converged,
            Some(limited_by) if self.report.iterations >= solver.max_iterations => {
                Termination::MaxIterationsReached { limited_by }
            }
            // the temperature has settled and the film has no solution: the next iteration would
            // solve the same film
            Some(Limiter::Film) if outer_met && self.film_failed => Termination::Stalled {
                limited_by: Limiter::Film,
            },
            Some(_) if overshot => {
                self.reject();
                return Ok(None);
            }
            Some(_) => {
                self.update(step, increment, contraction);
                return Ok(None);
            }
        };
        self.report.stop(termination);
        Ok(Some(step))
    }

    /// Switches on per-cell damping once the residual has not reached a new smallest value for
    /// [`STALL_ITERATIONS`] iterations: the global factor then keeps a few steep cells in a cycle (see
    /// [`Relaxation`]).
    fn watch_for_stall(&mut self) {
        let (residual, iteration) = (self.report.residual, self.report.iterations);
        if residual < self.best.0 {
            self.best = (residual, iteration);
        } else if iteration - self.best.1 >= STALL_ITERATIONS {
            self.relaxation.damp_cells();
        }
    }

    /// One outer iteration up to the new temperature target; None if the film had no solution and the
    /// temperature update was backtracked.
    fn step(&mut self) -> Result<Option<Step>> {
        let params = self.setup.params;
        // materials at T → microcontact and fluid → failure stress → adhesion limit
        let mats: Vec<MaterialState> = self
            .temperature
            .iter()
            .map(|t| params.material.at(*t))
            .collect();
        let Some(local) = self.local(&mats)? else {
            return Ok(None);
        };
        let adhesion = self.setup.adhesion(&local, &mats);
        let traction = self.tangential(&adhesion.limit)?;
        let (target, heat_flux_wheel) = self.heat(&traction.power_density)?;
        Ok(Some(Step {
            mats,
            local,
            adhesion,
            traction,
            target,
            heat_flux_wheel,
        }))
    }

    /// The film tolerance of this iteration (an inexact inner solve): while the temperature still moves,
    /// the film need only be as accurate as the outer iteration; once the outer residual is within 100×
    /// the tolerance (the next iteration may be the last) the film is solved to the full fluid tolerance.
    /// From a warm start's temperature, the second iteration (whose residual is still ∞: the first
    /// adhesion limit has no predecessor) solves its film to the full tolerance: a warm step may end
    /// there, by the a-posteriori estimate of the contraction ([`Coupled::contraction`]).
    fn film_tolerance(&self) -> f64 {
        let solver = &self.setup.params.solver;
        let fluid_tol = solver.fluid_tolerance;
        let second = self.temperature_change.is_finite();
        let residual = match self.report.residual {
            r if r.is_infinite() && self.warm_temperature && second => 0.0,
            r => r,
        };
        if self.setup.temperature_feeds_back() && residual > 1e2 * solver.tolerance {
            (1e-2 * residual).clamp(fluid_tol, fluid_tol.max(1e-5))
        } else {
            fluid_tol
        }
    }

    /// Microcontact and film at the materials `mats`; None after a backtrack (the film had no solution at
    /// the updated temperature: the update is halved back, the relaxation damped, the film restarted
    /// cold). Where the film has no solution and no backtrack is left (at the first iteration, after
    /// MAX_BACKTRACKS, at the iteration limit), the iteration goes on with Newton's last film, which is not
    /// converged: the report says so (limited by the film, stalled once the temperature has settled)
    /// unless a later iteration's film converges.
    fn local(&mut self, mats: &[MaterialState]) -> Result<Option<Local>> {
        let film_tolerance = self.film_tolerance();
        let start = self
            .film
            .as_ref()
            .map(FilmSolution::as_start)
            .or(self.warm_film.take());
        let local = |setup: &Setup, fallback, report: &mut SolverReport| {
            setup.local(
                mats,
                self.dry_guess.as_deref(),
                self.dry_previous.as_ref(),
                start,
                film_tolerance,
                fallback,
                report,
            )
        };
        self.film_failed = false;
        let error = match local(self.setup, true, &mut self.report) {
            Ok(local) => return Ok(Some(local)),
            Err(e) => e,
        };
        let film = matches!(
            error,
            Error::Numerical {
                stage: Stage::Fluid,
                ..
            }
        );
        let stepped_back = self.backtracking.step_back(
            error,
            self.report.temperature_backtracks,
            &mut self.temperature,
        );
        match stepped_back {
            Ok(()) if self.report.iterations < self.setup.params.solver.max_iterations => {}
            Err(e) if !film => return Err(e),
            _ => {
                self.film_failed = true;
                return local(self.setup, false, &mut self.report).map(Some);
            }
        }
        self.relaxation.damp();
        self.last_update = None;
        self.film = None;
        self.report.temperature_backtracks += 1;
        Ok(None)
    }

    /// The traction field under the adhesion limit `bound` [Pa]: FASTSIM, or Kalker's exact steady rolling
    /// (docs/model.md §6.5) started from the last iteration's tractions (or the warm start's), its sweeps,
    /// residual and convergence recorded for the report.
    fn tangential(&mut self, bound: &[f64]) -> Result<TractionField> {
        let setup = self.setup;
        let Some(steady) = &setup.steady else {
            return fastsim(
                &setup.grid,
                setup.creep,
                setup.point.speed,
                &setup.flex,
                bound,
            );
        };
        let exact = steady.solve(
            &setup.grid,
            setup.creep,
            setup.point.speed,
            bound,
            self.traction_start.as_deref(),
            setup.exact,
        )?;
        self.report.tangential_sweeps = exact.sweeps;
        self.report.tangential_residual = exact.residual;
        self.tangential_converged = exact.converged;
        Ok(exact.field)
    }

    /// The surface temperature [K] and the heat flux density into the wheel [W/m²] that the frictional
    /// power density `q` [W/m²] produces: T0 + the rise of the heat partition (warm-started from the last
    /// one), or T0 and no flux without a heat model.
    fn heat(&mut self, q: &[f64]) -> Result<(Vec<f64>, Vec<f64>)> {
        let t0 = self.setup.bulk_temperature();
        let Some(model) = &self.setup.heat else {
            let n = self.setup.grid.len();
            return Ok((vec![t0; n], vec![0.0; n]));
        };
        let hs = match &self.heat_solution {
            Some(previous) => model.solve_from(q, previous)?,
            None => model.solve(q)?,
        };
        let t: Vec<f64> = hs.temperature_rise.iter().map(|r| t0 + r).collect();
        let q_wheel = hs.q_wheel.clone();
        self.report.heat_iterations = hs.iterations;
        self.report.heat_residual = hs.residual;
        self.heat_solution = Some(hs);
        Ok((t, q_wheel))
    }

    /// The two parts of the outer residual (the larger of them): the relative temperature increment (its
    /// largest value over the largest rise above T0, at least 1 K) and the relative change of τ_l since
    /// the last iteration (∞ at the first); both 0 when the temperature does not feed back (one pass is
    /// the solution).
    fn outer_changes(&self, step: &Step, increment: &[f64]) -> (f64, f64) {
        if !self.setup.temperature_feeds_back() {
            return (0.0, 0.0);
        }
        let tau_l = &step.adhesion.limit;
        let tau_scale = tau_l
            .iter()
            .cloned()
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        let tau_change = match &self.prev_tau {
            Some(pt) => max_abs_diff(pt, tau_l) / tau_scale,
            None => f64::INFINITY,
        };
        let t_change =
            increment.iter().fold(0.0, |m: f64, d| m.max(d.abs())) / self.rise_scale(&step.target);
        (t_change, tau_change)
    }

    /// The largest rise of `target` over T0, at least 1 K: the scale of the relative temperature changes
    /// [K].
    fn rise_scale(&self, target: &[f64]) -> f64 {
        let t0 = self.setup.bulk_temperature();
        target.iter().map(|t| t - t0).fold(1.0, f64::max)
    }

    /// The contraction of the outer fixed point T ↦ T* over the last update's step s = T_k − T_{k−1},
    /// given this iteration's `target` T*(T_k) [K] and relative temperature change `temperature_change`
    /// (max|Δ_k| over the rise scale). Near the fixed point ([`Coupled::near`]; an update along its
    /// increment, s = ω·Δ_{k−1}): the factor q = max|T*(T_k) − T*(T_{k−1})| / max|s|, the secant of the
    /// map along its last increment, each over its rise scale (after a plain step, ω = 1, the ratio of the
    /// last two changes, Δ_k ≈ J·Δ_{k−1}). Otherwise (a plain step) that ratio of the last two changes.
    /// None where there is no such step or q ≥ [`MAX_CONTRACTION`] (the first iteration, backtracked or
    /// per-cell damped updates, relaxed ones far from the fixed point, slow or no contraction). With it,
    /// [`Contraction::residual`] bounds the iterate's distance from the fixed point.
    fn contraction(&self, target: &[f64], temperature_change: f64) -> Option<Contraction> {
        let last = self.last_update.as_ref()?;
        if !self.near {
            let q = temperature_change / self.temperature_change;
            return (self.temperature_change > 0.0 && q < MAX_CONTRACTION).then_some(Contraction {
                factor: q,
                increment_ratio: q,
                monotone: false,
            });
        }
        let step = max_abs_diff(&self.temperature, &last.iterate) / last.rise_scale;
        let factor = max_abs_diff(target, &last.target) / self.rise_scale(target) / step;
        let along: f64 = target
            .iter()
            .zip(&self.temperature)
            .zip(&last.iterate)
            .map(|((t_target, t), t_last)| (t_target - t) * (t - t_last))
            .sum();
        (step > 0.0 && factor < MAX_CONTRACTION).then_some(Contraction {
            factor,
            increment_ratio: temperature_change / step,
            monotone: along > 0.0,
        })
    }

    /// Whether the last update extrapolated (ω > 1) and this iterate's relative temperature change
    /// `temperature_change` is not below the last one's: the extrapolation did not reduce the increment,
    /// it is taken back ([`Coupled::reject`]).
    fn overshot(&self, temperature_change: f64) -> bool {
        self.last_update.as_ref().is_some_and(|u| u.extrapolated)
            && temperature_change >= self.temperature_change
    }

    /// Takes back an extrapolated update: the temperature becomes the plain step T*(T_{k−1}) of the
    /// iterate the update started from, whose adhesion limit, separations, film and tractions stay the
    /// references and starts of the next iteration (as after a plain update), and no later update of
    /// this solve extrapolates.
    fn reject(&mut self) {
        if let Some(last) = &mut self.last_update {
            self.temperature.copy_from_slice(&last.target);
            last.extrapolated = false;
        }
        self.relaxation.reject();
        self.extrapolation_rejected = true;
    }

    /// Prepares the next iteration: the temperature update, extrapolated by Aitken's 1/(1 − q) where the
    /// iteration contracts measurably by q from one side ([`Relaxation::extrapolate`]) and no
    /// extrapolation was taken back, else relaxed ([`Relaxation::apply`]); and this iteration's adhesion
    /// limit, separations and film as the next one's references and starts.
    fn update(&mut self, step: Step, increment: Vec<f64>, contraction: Option<Contraction>) {
        self.backtracking.remember(&self.temperature);
        let iterate = self.temperature.clone();
        // far from the fixed point the contraction is measured after plain updates only: the factor the
        // last update left is 1
        let plain = self.relaxation.is_plain();
        let extrapolated = match contraction {
            Some(c)
                if self.near
                    && c.monotone
                    && c.factor <= MAX_EXTRAPOLATED_CONTRACTION
                    && !self.extrapolation_rejected =>
            {
                self.relaxation
                    .extrapolate(&mut self.temperature, increment, c.factor)
            }
            _ => {
                self.relaxation.apply(&mut self.temperature, increment);
                false
            }
        };
        let measured = if self.near {
            self.relaxation.along_increment()
        } else {
            plain
        };
        self.last_update = measured.then(|| LastUpdate {
            iterate,
            rise_scale: self.rise_scale(&step.target),
            target: step.target,
            extrapolated,
        });
        self.prev_tau = Some(step.adhesion.limit);
        self.dry_previous = Some(DryIterate {
            materials: step.mats,
            dry: step.local.dry,
        });
        self.film = step.local.film;
        if self.setup.steady.is_some() {
            self.traction_start = Some(step.traction.traction);
        }
    }

    /// The final iterate, with the temperature produced by its traction field (equal to the iterate within
    /// the tolerance when the temperature feeds back; the only temperature when it does not).
    fn finish(self, step: Step) -> Iterate {
        Iterate {
            local: step.local,
            adhesion: step.adhesion,
            traction: step.traction,
            heat_flux_wheel: step.heat_flux_wheel,
            temperature: step.target,
            report: self.report,
        }
    }
}

/// max_k |a_k − b_k|.
fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0, |m: f64, (x, y)| m.max((x - y).abs()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Tangential;
    use crate::solver::WarmStart;

    /// The set-up of a solve of `params` at `point`.
    fn setup_of<'s>(
        params: &'s Params,
        point: &'s OperatingPoint,
        cache: &SetupCache,
    ) -> Setup<'s> {
        let (hertz, mat0, kalker, creep) = contact_of(params, point, cache).unwrap();
        Setup::new(params, point, hertz, &mat0, &kalker, creep, cache).unwrap()
    }

    /// A cell whose material is the same as at the last iterate keeps that iterate's dry state (marked
    /// here by a shifted separation it would not solve to); a cell whose material changed solves again.
    #[test]
    fn the_dry_state_is_kept_where_the_material_is_unchanged() {
        let params = Params::default();
        let point = OperatingPoint {
            creepage_x: 0.004,
            ..OperatingPoint::default()
        };
        let cache = SetupCache::default();
        let setup = setup_of(&params, &point, &cache);
        let n = setup.grid.len();
        let cold = vec![params.material.at(params.material.bulk_temperature); n];
        let mut report = SolverReport::start();
        let solve = |mats: &[MaterialState], previous: Option<&DryIterate>, report: &mut _| {
            setup
                .local(mats, None, previous, None, 1e-10, true, report)
                .unwrap()
                .dry
        };
        let first = solve(&cold, None, &mut report);
        let mut marked = first.clone();
        marked.separation.iter_mut().for_each(|d| *d *= 1.5);
        let previous = DryIterate {
            materials: cold.clone(),
            dry: marked.clone(),
        };
        let mut hot = cold.clone();
        hot[n / 2] = params.material.at(params.material.bulk_temperature + 50.0);
        let again = solve(&hot, Some(&previous), &mut report);
        for c in 0..n {
            if c == n / 2 {
                // solved at its new material: the asperities carry p_n at another separation
                assert_ne!(again.separation[c], marked.separation[c]);
                assert_ne!(again.separation[c], first.separation[c]);
                assert!(
                    (again.metal_load[c] - first.metal_load[c]).abs()
                        <= 1e-12 * first.metal_load[c]
                );
            } else {
                assert_eq!(again.separation[c], marked.separation[c], "cell {c}");
                assert_eq!(again.area_fraction[c], first.area_fraction[c], "cell {c}");
            }
        }
    }

    /// The solve of `params` at `point` with every exact tangential solve limited to `max_sweeps`.
    fn limited(params: &Params, point: &OperatingPoint, max_sweeps: usize) -> Iterate {
        let cache = SetupCache::default();
        let mut setup = setup_of(params, point, &cache);
        setup.exact.max_sweeps = max_sweeps;
        Coupled::start(&setup, None).run().unwrap()
    }

    /// As [`solve_cached`] without extrapolation: every update relaxed ([`Relaxation::apply`]).
    fn solve_unextrapolated(
        params: &Params,
        point: &OperatingPoint,
        warm: Option<&WarmStart>,
        cache: &SetupCache,
    ) -> Solution {
        let setup = setup_of(params, point, cache);
        let mut coupled = Coupled::start(&setup, warm);
        coupled.extrapolation_rejected = true;
        assemble(&setup, coupled.run().unwrap())
    }

    /// The step `k` of an MBS-like run at 1 kHz on a 9 × 9 grid (load ±1 % at 23 Hz, braking 0.5 m/s²,
    /// ξ oscillating, the lateral curvature growing into a curve): its parameters (the geometry) and point.
    fn mbs_step(k: usize, wetness: f64) -> (Params, OperatingPoint) {
        let mut p = Params::default();
        p.grid.nx = 9;
        p.grid.ny = 9;
        p.geometry.curvature_y *= 1.0 + 0.002 * k as f64;
        let t = k as f64 * 1e-3;
        let wave = (2.0 * std::f64::consts::PI * 23.0 * t).sin();
        let point = OperatingPoint {
            creepage_x: 0.004 * (1.0 + 0.01 * wave),
            creepage_y: -0.002,
            spin: 0.3,
            normal_force: 100e3 * (1.0 + 0.01 * wave),
            speed: 25.0 - 0.5 * t,
            wetness,
        };
        (p, point)
    }

    /// The step `k` of a curve of an MBS run at 1 kHz on the exact fallback's grids (24 × 6 dry, 24 × 8
    /// wet): gap curvatures A 0.905 1/m, B 5.43 1/m falling by 0.06 % per step, the load 126 kN falling by
    /// 0.35 % per step, ξ 6.5e-4, η −6.3e-3, φ 0.80 1/m, V 23.4 m/s, drifting.
    fn curve_step(k: usize, wetness: f64) -> (Params, OperatingPoint) {
        let mut p = Params::default();
        p.grid.nx = 24;
        p.grid.ny = if wetness > 0.0 { 8 } else { 6 };
        let s = k as f64;
        p.geometry = crate::params::Geometry::of_inputs(0.905, 5.43 * (1.0 - 6e-4 * s), [0.0; 2]);
        let point = OperatingPoint {
            creepage_x: 6.5e-4 + 4.8e-6 * s,
            creepage_y: -6.3e-3 + 2.4e-6 * s,
            spin: 0.80 - 1.6e-4 * s,
            normal_force: 126e3 * (1.0 - 3.5e-3 * s),
            speed: 23.4 - 5e-4 * s,
            wetness,
        };
        (p, point)
    }

    /// The largest relative difference of two solutions: forces over F_N, temperature rises over the
    /// largest rise.
    fn difference(a: &Solution, b: &Solution) -> f64 {
        let (ga, gb) = (&a.global, &b.global);
        let force = (ga.force_x - gb.force_x).hypot(ga.force_y - gb.force_y) / ga.normal_force;
        let (fa, fb) = (a.fields.as_ref().unwrap(), b.fields.as_ref().unwrap());
        let t0 = Params::default().material.bulk_temperature;
        let rise = fa.temperature.iter().fold(1.0_f64, |m, t| m.max(t - t0));
        force.max(max_abs_diff(&fa.temperature, &fb.temperature) / rise)
    }

    /// Warm MBS steps: each ends after 2 or 3 outer iterations, stopped by the a-posteriori
    /// estimate of the contraction (without it, 3 or 4), and agrees with the cold solve and with a
    /// solve converged to 1e-12 within the solver tolerance 1e-6 (forces over F_N, temperatures over
    /// the largest rise), dry and wet.
    #[test]
    fn warm_mbs_steps_take_at_most_three_iterations_and_agree_with_cold_ones() {
        for wetness in [0.0, 1.0] {
            let cache = SetupCache::default();
            let mut warm: Option<WarmStart> = None;
            let mut iterations = Vec::new();
            for k in 0..12 {
                let (p, point) = mbs_step(k, wetness);
                let s = solve_cached(&p, &point, warm.as_ref(), &cache).unwrap();
                assert!(s.report.converged, "step {k}");
                if k > 0 {
                    iterations.push(s.report.iterations);
                    let cold = solve_cached(&p, &point, None, &cache).unwrap();
                    let mut tight_params = p.clone();
                    tight_params.solver.tolerance = 1e-12;
                    let tight = solve_cached(&tight_params, &point, None, &cache).unwrap();
                    for (what, other) in [("cold", &cold), ("converged", &tight)] {
                        let d = difference(&s, other);
                        assert!(
                            d <= p.solver.tolerance,
                            "w {wetness}, step {k}, {what}: {d:.2e}"
                        );
                    }
                }
                warm = s.warm_start();
            }
            let most = *iterations.iter().max().unwrap();
            let mean = iterations.iter().sum::<usize>() as f64 / iterations.len() as f64;
            assert!(most <= 3 && mean <= 2.5, "w {wetness}: {iterations:?}");
        }
    }

    /// The steps of a curve ([`curve_step`]), each warm-started from its predecessor, with and without
    /// Aitken's extrapolation: every step converges, both chains agree with each other and with solves
    /// converged to 1e-12 within the solver tolerance 1e-6 (forces over F_N, temperatures over the
    /// largest rise), and the extrapolation saves an outer iteration per dry step (3 instead of 4) and
    /// costs none wet.
    #[test]
    fn extrapolation_saves_iterations_of_warm_steps_at_the_same_fixed_point() {
        for wetness in [0.0, 1.0] {
            let cache = SetupCache::default();
            let (mut warm, mut warm_plain): (Option<WarmStart>, Option<WarmStart>) = (None, None);
            let (mut iterations, mut plain_iterations) = (0, 0);
            for k in 0..12 {
                let (p, point) = curve_step(k, wetness);
                let s = solve_cached(&p, &point, warm.as_ref(), &cache).unwrap();
                let plain = solve_unextrapolated(&p, &point, warm_plain.as_ref(), &cache);
                assert!(s.report.converged && plain.report.converged, "step {k}");
                if k > 0 {
                    iterations += s.report.iterations;
                    plain_iterations += plain.report.iterations;
                    let mut tight_params = p.clone();
                    tight_params.solver.tolerance = 1e-12;
                    let tight = solve_cached(&tight_params, &point, None, &cache).unwrap();
                    for (what, d) in [
                        ("plain", difference(&s, &plain)),
                        ("converged", difference(&s, &tight)),
                        ("plain converged", difference(&plain, &tight)),
                    ] {
                        assert!(
                            d <= p.solver.tolerance,
                            "w {wetness}, step {k}, {what}: {d:.2e}"
                        );
                    }
                }
                warm = s.warm_start();
                warm_plain = plain.warm_start();
            }
            // dry: 3 iterations per step instead of 4; wet: 4 either way
            if wetness == 0.0 {
                assert!(
                    iterations < plain_iterations,
                    "{iterations} vs {plain_iterations}"
                );
            } else {
                assert!(
                    iterations <= plain_iterations,
                    "{iterations} vs {plain_iterations}"
                );
            }
        }
    }

    /// An extrapolated update whose iterate does not reduce the temperature increment is taken back: the
    /// next iterate is the plain step from the iterate the update started from, no later update
    /// extrapolates, and the solve converges to the fixed point of the plain iteration. (A warm curve step
    /// whose first extrapolation, after its second iteration, is made 4 times as long: its increment then
    /// does not shrink.)
    #[test]
    fn an_extrapolation_that_does_not_reduce_the_increment_is_taken_back() {
        let cache = SetupCache::default();
        let (p0, point0) = curve_step(0, 0.0);
        let warm = solve_cached(&p0, &point0, None, &cache)
            .unwrap()
            .warm_start();
        let (p, point) = curve_step(1, 0.0);
        let plain = solve_unextrapolated(&p, &point, warm.as_ref(), &cache);
        let setup = setup_of(&p, &point, &cache);
        let mut coupled = Coupled::start(&setup, warm.as_ref());
        for _ in 0..2 {
            assert!(coupled.iteration().unwrap().is_none());
        }
        let last = coupled.last_update.as_ref().unwrap();
        assert!(last.extrapolated, "the second update extrapolates");
        let (from, plain_step) = (last.iterate.clone(), last.target.clone());
        for (t, f) in coupled.temperature.iter_mut().zip(&from) {
            *t = f + 4.0 * (*t - f);
        }
        let change = coupled.temperature_change;
        assert!(coupled.iteration().unwrap().is_none());
        assert!(coupled.extrapolation_rejected);
        assert_eq!(coupled.temperature, plain_step);
        assert_eq!(coupled.temperature_change, change);
        let s = assemble(&setup, coupled.run().unwrap());
        assert!(s.report.converged);
        let d = difference(&s, &plain);
        assert!(d <= p.solver.tolerance, "{d:.2e}");
        // the iteration taken back counts
        assert!(s.report.iterations > plain.report.iterations);
    }

    /// A tangential solve that does not converge keeps the outer iteration going from its tractions (one
    /// more sweep per iteration here: the bound is fixed, constant μ and heat off), and at the iteration
    /// limit leaves the point unconverged, limited by the tangential solve.
    #[test]
    fn an_unconverged_tangential_solve_is_continued_and_else_named() {
        let mut p = Params {
            tangential: Tangential::Exact,
            ..Params::default()
        };
        p.friction.law = FrictionLaw::Constant;
        p.solver.heat = false;
        p.grid.nx = 12;
        p.grid.ny = 12;
        let point = OperatingPoint {
            creepage_x: 0.001,
            ..OperatingPoint::default()
        };
        p.solver.max_iterations = 3;
        let short = limited(&p, &point, 1);
        assert_eq!(
            short.report.termination,
            Termination::MaxIterationsReached {
                limited_by: Limiter::Tangential
            }
        );
        assert!(!short.report.converged);
        assert_eq!(short.report.iterations, 3);
        assert!(short.report.tangential_residual > p.solver.tolerance.min(1e-7));
        // with enough outer iterations the sweeps add up to the converged solve
        p.solver.max_iterations = 200;
        let continued = limited(&p, &point, 1);
        assert!(continued.report.converged && continued.report.iterations > 3);
        let full = limited(&p, &point, 500);
        assert_eq!(full.report.iterations, 1);
        let f = continued.traction.force_x;
        assert!((f - full.traction.force_x).abs() <= 1e-6 * f.abs(), "{f}");
    }
}
