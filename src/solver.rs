//! The coupled fixed-point solution of the model (paper Fig. 1, MODEL.md §9).
//!
//! Start at T = T0, p_f = 0. Repeat: materials at T → fluid film + microcontact (separation, p_f, A_m/A_n) →
//! failure stress and local friction μ_ij →
//! FASTSIM (traction, slip) → frictional heat → surface temperature, until the adhesion limit and the
//! temperatures change less than the tolerance. The temperature update is relaxed with Aitken's Δ²
//! (Irons–Tuck) factor, which damps the oscillation that the temperature ↔ failure-stress feedback
//! produces at high slip power.

use crate::baselines::polach;
use crate::contact::{ContactGrid, HertzContact};
use crate::error::{Error, Result};
use crate::fluid::{
    CellGeometry, FilmProblem, FilmSolution, FilmStart, Regime, base_height, solve_film,
};
use crate::friction;
use crate::materials::MaterialState;
use crate::microcontact::Microcontact;
use crate::params::{FrictionLaw, OperatingPoint, Params};
use crate::tangential::{Creepages, Flexibilities, TractionField, fastsim, kalker_coefficients};
use crate::thermal::{HeatModel, HeatSolution};
use serde::Serialize;

/// Most halvings of temperature updates in one solve (see [`SolverReport::temperature_backtracks`]).
const MAX_BACKTRACKS: usize = 20;

/// Why the outer iteration stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Termination {
    /// The residual fell below the tolerance.
    Converged,
    /// The iteration limit was reached first: the result is NOT converged.
    MaxIterationsReached,
    /// A closed-form law (Polach) needs no iteration.
    ClosedForm,
}

/// How the coupled solve went.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SolverReport {
    /// Outer iterations performed.
    pub iterations: usize,
    /// Final residual: the larger of the relative change of the adhesion limit and of the temperature rise.
    pub residual: f64,
    /// Whether the residual met the tolerance.
    pub converged: bool,
    /// Why the iteration stopped.
    pub termination: Termination,
    /// Largest number of root-finder iterations of one microcontact separation solve.
    pub max_microcontact_iterations: usize,
    /// Iterations of the last fluid film solve (0 without fluid).
    pub fluid_sweeps: usize,
    /// Residual of the last fluid film solve (0 without fluid).
    pub fluid_residual: f64,
    /// Times the fluid film had no solution at a temperature update, so that the update was halved back
    /// and the film restarted cold (or, from a warm start, just restarted cold).
    pub temperature_backtracks: usize,
}

/// Global results of one operating point (SI units, kelvin).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GlobalResults {
    /// Longitudinal tangential force on the wheel F_x [N] (Kalker's sign convention).
    pub force_x: f64,
    /// Lateral tangential force on the wheel F_y [N].
    pub force_y: f64,
    /// Spin moment M_z [N·m].
    pub spin_moment: f64,
    /// Traction coefficient f = |F_T|/F_N (P2) [-].
    pub traction_coefficient: f64,
    /// Normal force F_N [N].
    pub normal_force: f64,
    /// Semi-axis along x [m].
    pub semi_axis_a: f64,
    /// Semi-axis along y [m].
    pub semi_axis_b: f64,
    /// Hertz peak pressure p0 [Pa].
    pub peak_pressure: f64,
    /// Highest surface temperature in the contact [K].
    pub max_temperature: f64,
    /// Mean surface temperature over the contact [K].
    pub mean_temperature: f64,
    /// Total frictional power [W].
    pub frictional_power: f64,
    /// Share of the contact area in slip [-] (None for the closed-form Polach law).
    pub slip_area_fraction: Option<f64>,
    /// Share of the normal force carried by fluid pressure, Σ p_f(1 − A_m/A_n) / Σ p_n [-].
    pub fluid_load_fraction: f64,
    /// Share of the contact area in mixed lubrication [-].
    pub mixed_lubrication_area_fraction: f64,
    /// Share of the contact area in boundary lubrication [-].
    pub boundary_lubrication_area_fraction: f64,
    /// Smallest separation of the mean planes in the contact [m] (None without microcontact).
    pub min_separation: Option<f64>,
    /// Fluid volume balance: inlet flow minus carried-out and expelled flow, relative to the inlet flow [-].
    pub fluid_mass_balance_error: f64,
}

/// Local fields on the grid (one value per active cell, in the order of `grid.cells`).
#[derive(Debug, Clone, PartialEq)]
pub struct Fields {
    /// The contact grid.
    pub grid: ContactGrid,
    /// Nominal normal pressure p_n [Pa].
    pub nominal_pressure: Vec<f64>,
    /// Separation d of the mean planes [m].
    pub separation: Vec<f64>,
    /// Metallic contact area ratio A_m/A_n [-].
    pub area_fraction: Vec<f64>,
    /// Local friction coefficient μ (P1) [-].
    pub friction_coefficient: Vec<f64>,
    /// Tangential adhesion limit τ_l (P6) [Pa].
    pub adhesion_limit: Vec<f64>,
    /// Tangential traction on the wheel [Pa].
    pub traction: Vec<[f64; 2]>,
    /// Slip velocity of the wheel relative to the rail [m/s].
    pub slip_velocity: Vec<[f64; 2]>,
    /// Frictional heat flux q = |p|·s [W/m²].
    pub heat_flux: Vec<f64>,
    /// Share of the heat flux entering the wheel [W/m²].
    pub heat_flux_wheel: Vec<f64>,
    /// Surface temperature [K].
    pub temperature: Vec<f64>,
    /// Stick (false) / slip (true).
    pub slipping: Vec<bool>,
    /// Fluid pressure p_f [Pa] (zero when dry).
    pub fluid_pressure: Vec<f64>,
    /// Nominal metallic pressure p_m·A_m/A_n [Pa].
    pub nominal_metal_pressure: Vec<f64>,
    /// Metallic contact pressure p_m on the real contact area [Pa].
    pub metal_pressure: Vec<f64>,
    /// Cell height l_c = d − d_b [m].
    pub cell_height: Vec<f64>,
    /// Equivalent metallic volume height l_m [m].
    pub metal_height: Vec<f64>,
    /// Fluid height l_f [m].
    pub fluid_height: Vec<f64>,
    /// Failure-stress factor k [-].
    pub failure_stress_factor: Vec<f64>,
    /// Lubrication regime.
    pub regime: Vec<Regime>,
}

/// A solved operating point.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Global results.
    pub global: GlobalResults,
    /// Local fields (None for the closed-form Polach law).
    pub fields: Option<Fields>,
    /// Convergence report.
    pub report: SolverReport,
}

/// The nominal normal contact for a parameter set and a load: Hertz from the curvatures (E* at the bulk
/// temperature), or the prescribed semi-axes.
pub fn normal_contact(params: &Params, normal_force: f64) -> Result<HertzContact> {
    match params.geometry.semi_axes {
        Some([a, b]) => HertzContact::from_semi_axes(a, b, normal_force),
        None => {
            let m = params.material.at(params.material.bulk_temperature);
            HertzContact::from_curvatures(
                params.geometry.curvature_x,
                params.geometry.curvature_y,
                normal_force,
                m.e_star,
            )
        }
    }
}

/// The microcontact and fluid state of every cell for one temperature field.
struct Local {
    /// Separation at which the asperities alone carry p_n (equal to `separation` when dry) [m].
    dry_separation: Vec<f64>,
    separation: Vec<f64>,
    area_fraction: Vec<f64>,
    metal_load: Vec<f64>,
    fluid_pressure: Vec<f64>,
    fluid_height: Vec<f64>,
    regime: Vec<Regime>,
    film: Option<FilmSolution>,
}

/// Everything fixed for one operating point.
struct Setup<'a> {
    params: &'a Params,
    point: &'a OperatingPoint,
    grid: ContactGrid,
    p_n: Vec<f64>,
    micro: Microcontact,
    base_height: f64,
}

impl Setup<'_> {
    /// Microcontact (and, when wet, the fluid film) at the cells' material states.
    /// `fluid_tolerance` is the film sweep tolerance for this outer iteration.
    /// `dry_guess`: per-cell separations to start the microcontact Newton from (the previous iterate).
    fn local(
        &self,
        mats: &[MaterialState],
        dry_guess: Option<&[f64]>,
        warm: Option<FilmStart>,
        fluid_tolerance: f64,
        report: &mut SolverReport,
    ) -> Result<Local> {
        let n = self.grid.len();
        let mut dry_d = vec![0.0; n];
        let mut area = vec![0.0; n];
        let mut load = vec![0.0; n];
        for c in 0..n {
            // the last iterate of this cell, else the neighbour just solved in the same strip
            let guess = match dry_guess {
                Some(g) => g[c],
                None if c > 0 && self.grid.cells[c - 1].j == self.grid.cells[c].j => dry_d[c - 1],
                None => f64::NAN,
            };
            let s = self
                .micro
                .separation_for_load_from(self.p_n[c], &mats[c], guess)?;
            if !s.converged {
                return Err(Error::Numerical {
                    stage: "microcontact",
                    reason: format!(
                        "separation for p_n = {} Pa did not converge (residual {})",
                        self.p_n[c], s.residual
                    ),
                });
            }
            report.max_microcontact_iterations =
                report.max_microcontact_iterations.max(s.iterations);
            dry_d[c] = s.state.separation;
            area[c] = s.state.area_fraction;
            load[c] = s.state.load;
        }
        // the fluid acts through the failure stress and the metallic area: only the Tomberger law has them
        let h_f0 = match self.params.friction.law {
            FrictionLaw::Tomberger => self.point.wetness * self.params.fluid.h_f_max,
            _ => 0.0,
        };
        if h_f0 <= 0.0 {
            return Ok(Local {
                dry_separation: dry_d.clone(),
                separation: dry_d,
                area_fraction: area,
                metal_load: load,
                fluid_pressure: vec![0.0; n],
                fluid_height: vec![0.0; n],
                regime: vec![Regime::Dry; n],
                film: None,
            });
        }
        let (v_w, v_r) = surface_speeds(self.point);
        let film = solve_film(
            &FilmProblem {
                grid: &self.grid,
                nominal_pressure: &self.p_n,
                materials: mats,
                dry_separation: &dry_d,
                dry_area_fraction: &area,
                dry_metal_load: &load,
                micro: &self.micro,
                base_height: self.base_height,
                flow_resistance: self.params.fluid.flow_resistance,
                rail_speed: v_r,
                mean_speed: 0.5 * (v_w + v_r),
                inlet_film: h_f0,
                tolerance: fluid_tolerance,
                max_iterations: self.params.solver.max_fluid_sweeps,
            },
            warm,
        )?;
        report.fluid_sweeps = film.iterations;
        report.fluid_residual = film.residual;
        Ok(Local {
            dry_separation: dry_d,
            separation: film.separation.clone(),
            area_fraction: film.area_fraction.clone(),
            metal_load: film.metal_load.clone(),
            fluid_pressure: film.fluid_pressure.clone(),
            fluid_height: film.fluid_height.clone(),
            regime: film.regime.clone(),
            film: Some(film),
        })
    }
}

/// Wheel and rail surface speeds through the contact, V·(1 ± ξ/2) [m/s] (MODEL.md §1).
pub fn surface_speeds(point: &OperatingPoint) -> (f64, f64) {
    (
        point.speed * (1.0 + point.creepage_x / 2.0),
        point.speed * (1.0 - point.creepage_x / 2.0),
    )
}

/// Solves one operating point with the exact (coupled) model from a cold start (T = T0, no fluid); see
/// the module documentation.
pub fn solve(params: &Params, point: &OperatingPoint) -> Result<Solution> {
    solve_from(params, point, None)
}

/// Where a solve can start from: the state of a nearby solution (the previous point of a traction–creepage
/// sweep, the previous FMU step, a neighbouring table point), one value per active cell of its grid.
#[derive(Debug, Clone, PartialEq)]
pub struct WarmStart {
    /// Grid cells along x and y of the solution.
    pub nx: usize,
    /// Grid cells along y.
    pub ny: usize,
    /// Surface temperature [K].
    pub temperature: Vec<f64>,
    /// Separation d of the mean planes [m].
    pub separation: Vec<f64>,
    /// Fluid pressure p_f [Pa].
    pub fluid_pressure: Vec<f64>,
    /// Fluid height l_f [m].
    pub fluid_height: Vec<f64>,
}

impl WarmStart {
    /// The warm start of a solution's fields.
    pub fn of(fields: &Fields) -> Self {
        Self {
            nx: fields.grid.nx,
            ny: fields.grid.ny,
            temperature: fields.temperature.clone(),
            separation: fields.separation.clone(),
            fluid_pressure: fields.fluid_pressure.clone(),
            fluid_height: fields.fluid_height.clone(),
        }
    }

    /// Whether it fits `grid`: same nx × ny and as many cells (the grid is normalised by the semi-axes,
    /// so the active cells are the same whatever the load).
    fn fits(&self, grid: &ContactGrid) -> bool {
        let n = grid.len();
        self.nx == grid.nx
            && self.ny == grid.ny
            && [
                &self.temperature,
                &self.separation,
                &self.fluid_pressure,
                &self.fluid_height,
            ]
            .iter()
            .all(|v| v.len() == n)
    }

    /// The film as the film solver's starting iterate (None without fluid).
    fn film(&self) -> Option<FilmStart<'_>> {
        self.fluid_height
            .iter()
            .any(|h| *h > 0.0)
            .then_some(FilmStart {
                separation: &self.separation,
                fluid_pressure: &self.fluid_pressure,
                fluid_height: &self.fluid_height,
            })
    }
}

impl Solution {
    /// The state to start a nearby solve from (None for the closed-form Polach law).
    pub fn warm_start(&self) -> Option<WarmStart> {
        self.fields.as_ref().map(WarmStart::of)
    }
}

/// As [`solve`], starting the fixed point from a nearby solution's state ([`WarmStart`]): its temperature,
/// its separations as the microcontact Newton's starting points and its film as the film solver's start.
/// The start is used only if it fits the grid (same nx × ny); otherwise the solve starts cold. The
/// converged result is the same fixed point to within the solver tolerance.
pub fn solve_from(
    params: &Params,
    point: &OperatingPoint,
    warm: Option<&WarmStart>,
) -> Result<Solution> {
    params.validate()?;
    point.validate()?;
    let hertz = normal_contact(params, point.normal_force)?;
    let mat0 = params.material.at(params.material.bulk_temperature);
    let kalker = kalker_coefficients(hertz.a, hertz.b, mat0.poisson)?;
    let creep = Creepages {
        xi: point.creepage_x,
        eta: point.creepage_y,
        phi: point.spin,
    };
    if params.friction.law == FrictionLaw::Polach {
        return solve_polach(params, point, &hertz, &kalker, creep);
    }
    let grid = ContactGrid::for_contact(&hertz, params.grid.nx, params.grid.ny);
    let flex = Flexibilities::new(hertz.a, hertz.b, mat0.shear_modulus, &kalker);
    let p_n: Vec<f64> = grid
        .cells
        .iter()
        .map(|c| hertz.parabolic_pressure(c.x, c.y))
        .collect();
    let n = grid.len();
    let t0 = params.material.bulk_temperature;
    let rolling = creep.xi == 0.0 && creep.eta == 0.0 && creep.phi == 0.0;
    let heat = if params.solver.heat && !rolling {
        let (v_wheel, v_rail) = surface_speeds(point);
        Some(HeatModel::new(&grid, v_wheel, v_rail, &params.material)?)
    } else {
        None
    };
    let tomberger = params.friction.law == FrictionLaw::Tomberger;
    let micro = Microcontact::new(&params.roughness)?;
    let setup = Setup {
        params,
        point,
        base_height: base_height(micro.surface().z_s, params.fluid.psi_b),
        grid,
        p_n,
        micro,
    };

    let warm = warm.filter(|w| w.fits(&setup.grid));
    // a warm temperature only helps when it feeds back (heat on, Tomberger law)
    let mut temperature = match warm {
        Some(w) if heat.is_some() && tomberger => w.temperature.clone(),
        _ => vec![t0; n],
    };
    let mut dry_guess: Option<Vec<f64>> = warm.map(|w| w.separation.clone());
    let mut tau_l = vec![0.0; n];
    let mut k_fail = vec![params.friction.k_dry; n];
    let mut prev_tau: Option<Vec<f64>> = None;
    let mut prev_increment: Option<Vec<f64>> = None;
    let mut omega = params.solver.relaxation;
    // the film of the last outer iteration, or before the first the warm start's (dropped on a restart)
    let mut film: Option<FilmSolution> = None;
    let mut warm_film: Option<FilmStart> = warm.and_then(WarmStart::film);
    // the temperature before the last update, to step back to if the film fails at the new one
    let mut last_temperature: Option<Vec<f64>> = None;
    // last heat partition: warm start of the next one
    let mut heat_solution: Option<HeatSolution> = None;
    let mut report = SolverReport {
        iterations: 0,
        residual: f64::INFINITY,
        converged: false,
        termination: Termination::MaxIterationsReached,
        max_microcontact_iterations: 0,
        fluid_sweeps: 0,
        fluid_residual: 0.0,
        temperature_backtracks: 0,
    };
    let (local, traction, heat_wheel) = loop {
        report.iterations += 1;
        // materials at T → microcontact and fluid → failure stress → adhesion limit
        let mats: Vec<MaterialState> = temperature.iter().map(|t| params.material.at(*t)).collect();
        // inexact inner solve: while the temperature still moves, the film need only be as accurate as
        // the outer iteration; once the outer residual is within 100× the tolerance (the next iteration
        // may be the last) the film is solved to the full fluid tolerance
        let fluid_tol = params.solver.fluid_tolerance;
        let inner_tol =
            if heat.is_some() && tomberger && report.residual > 1e2 * params.solver.tolerance {
                (1e-2 * report.residual).clamp(fluid_tol, fluid_tol.max(1e-5))
            } else {
                fluid_tol
            };
        let local = match setup.local(
            &mats,
            dry_guess.as_deref(),
            film.as_ref().map(FilmSolution::as_start).or(warm_film),
            inner_tol,
            &mut report,
        ) {
            Ok(l) => l,
            // the film has no solution at the temperature of an overshooting update (e.g. above 1800 K
            // after the first, unrelaxed step of a hot point): step back halfway towards the previous
            // temperature and damp the relaxation (a backtracking line search on the fixed point)
            // (from a warm start, before any update: the film restarts cold at the same temperature)
            Err(Error::Numerical { stage: "fluid", .. })
                if report.temperature_backtracks < MAX_BACKTRACKS
                    && (last_temperature.is_some() || film.is_some()) =>
            {
                if let Some(last) = &last_temperature {
                    for (t, l) in temperature.iter_mut().zip(last) {
                        *t = 0.5 * (*t + l);
                    }
                }
                omega *= 0.5;
                film = None;
                warm_film = None;
                report.temperature_backtracks += 1;
                if report.iterations >= params.solver.max_iterations {
                    return Err(Error::Numerical {
                        stage: "coupled solver",
                        reason: "the fluid film has no solution along the temperature iteration"
                            .into(),
                    });
                }
                continue;
            }
            Err(e) => return Err(e),
        };
        for c in 0..n {
            tau_l[c] = if tomberger {
                k_fail[c] = friction::failure_stress_factor(
                    params.friction.k_dry,
                    params.fluid.k_wet,
                    local.fluid_height[c],
                    params.fluid.h_bl,
                );
                let tau_m = friction::failure_stress(k_fail[c], mats[c].yield_stress);
                friction::adhesion_limit(tau_m, local.area_fraction[c])
            } else {
                params.friction.mu * setup.p_n[c]
            };
        }
        let field = fastsim(&setup.grid, creep, point.speed, &flex, &tau_l)?;
        let (target, q_wheel) = match &heat {
            Some(h) => {
                let hs = match &heat_solution {
                    Some(previous) => h.solve_from(&field.power_density, previous)?,
                    None => h.solve(&field.power_density)?,
                };
                let t: Vec<f64> = hs.temperature_rise.iter().map(|r| t0 + r).collect();
                let q_wheel = hs.q_wheel.clone();
                heat_solution = Some(hs);
                (t, q_wheel)
            }
            None => (vec![t0; n], vec![0.0; n]),
        };
        // residuals: relative change of τ_l since the last iteration, relative temperature increment
        let tau_scale = tau_l
            .iter()
            .cloned()
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        let tau_change = match &prev_tau {
            Some(pt) => max_abs_diff(pt, &tau_l) / tau_scale,
            None => f64::INFINITY,
        };
        let increment: Vec<f64> = target
            .iter()
            .zip(&temperature)
            .map(|(t, tc)| t - tc)
            .collect();
        let rise_scale = target.iter().map(|t| t - t0).fold(1.0, f64::max);
        let t_change = increment.iter().fold(0.0, |m: f64, d| m.max(d.abs())) / rise_scale;
        let fluid_ok = local
            .film
            .as_ref()
            .is_none_or(|f| f.converged && f.residual <= fluid_tol);
        report.residual = if heat.is_some() && tomberger {
            t_change.max(tau_change)
        } else {
            // the temperature does not feed back: one pass is the solution
            0.0
        };
        let done = report.residual <= params.solver.tolerance;
        let heat_ok = heat_solution.as_ref().is_none_or(|hs| hs.converged);
        if (done && fluid_ok && heat_ok) || report.iterations >= params.solver.max_iterations {
            report.converged = done && fluid_ok && heat_ok;
            if report.converged {
                report.termination = Termination::Converged;
            }
            // report the temperature produced by this traction field (equal to the iterate within the
            // tolerance when the temperature feeds back; the only temperature when it does not)
            temperature = target;
            break (local, field, q_wheel);
        }
        // Aitken Δ² relaxation of the temperature update (Irons & Tuck 1969)
        if let Some(prev) = &prev_increment {
            let mut num = 0.0;
            let mut den = 0.0;
            for (r1, r0) in increment.iter().zip(prev) {
                let d = r1 - r0;
                num += r0 * d;
                den += d * d;
            }
            if den > 0.0 {
                omega = (-omega * num / den).clamp(0.02, 1.0);
            }
        }
        last_temperature = Some(temperature.clone());
        for (t, d) in temperature.iter_mut().zip(&increment) {
            *t += omega * d;
        }
        prev_increment = Some(increment);
        prev_tau = Some(tau_l.clone());
        dry_guess = Some(local.dry_separation);
        film = local.film;
        warm_film = None;
    };
    Ok(assemble(
        &hertz,
        &setup,
        local,
        tau_l,
        k_fail,
        traction,
        heat_wheel,
        temperature,
        report,
    ))
}

/// Number of warm-started chains a sweep is cut into (fixed, so that the results do not depend on the
/// thread count).
const SWEEP_CHAINS: usize = 8;

/// Solves a sequence of nearby operating points (a traction–creepage sweep, a line of a table) with
/// continuation: each point starts from its predecessor's solution ([`solve_from`]). The sequence is cut
/// into at most 8 contiguous chains solved in parallel (rayon); the first point of a chain, and a point
/// after a failed one, start cold. The cut does not depend on the thread count, so neither do the results.
pub fn solve_sweep(params: &Params, points: &[OperatingPoint]) -> Vec<Result<Solution>> {
    use rayon::prelude::*;
    let chain = points.len().div_ceil(SWEEP_CHAINS).max(1);
    points
        .par_chunks(chain)
        .flat_map_iter(|chunk| {
            let mut prev: Option<WarmStart> = None;
            chunk
                .iter()
                .map(|pt| {
                    let r = solve_from(params, pt, prev.as_ref());
                    prev = r.as_ref().ok().and_then(Solution::warm_start);
                    r
                })
                .collect::<Vec<_>>()
        })
        .collect()
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0, |m: f64, (x, y)| m.max((x - y).abs()))
}

#[allow(clippy::too_many_arguments)]
fn assemble(
    hertz: &HertzContact,
    setup: &Setup,
    local: Local,
    tau_l: Vec<f64>,
    k_fail: Vec<f64>,
    field: TractionField,
    heat_flux_wheel: Vec<f64>,
    temperature: Vec<f64>,
    report: SolverReport,
) -> Solution {
    let grid = setup.grid.clone();
    let p_n = setup.p_n.clone();
    let n = grid.len() as f64;
    let tomberger = setup.params.friction.law == FrictionLaw::Tomberger;
    let friction_coefficient = tau_l
        .iter()
        .zip(&p_n)
        .map(|(t, p)| friction::local_friction(*t, *p))
        .collect();
    let force_t = field.force_x.hypot(field.force_y);
    let share = |r: Regime| local.regime.iter().filter(|x| **x == r).count() as f64 / n;
    let fluid_load: f64 = local
        .fluid_pressure
        .iter()
        .zip(&local.area_fraction)
        .map(|(p, a)| p * (1.0 - a))
        .sum();
    let z_s = setup.micro.surface().z_s;
    let geo: Vec<CellGeometry> = local
        .separation
        .iter()
        .map(|d| CellGeometry::at(*d, z_s, setup.base_height))
        .collect();
    let global = GlobalResults {
        force_x: field.force_x,
        force_y: field.force_y,
        spin_moment: field.spin_moment,
        traction_coefficient: force_t / hertz.normal_force,
        normal_force: hertz.normal_force,
        semi_axis_a: hertz.a,
        semi_axis_b: hertz.b,
        peak_pressure: hertz.p0,
        max_temperature: temperature.iter().cloned().fold(f64::MIN, f64::max),
        mean_temperature: temperature.iter().sum::<f64>() / n,
        frictional_power: field.frictional_power(&grid),
        slip_area_fraction: Some(field.slipping.iter().filter(|s| **s).count() as f64 / n),
        fluid_load_fraction: fluid_load / p_n.iter().sum::<f64>(),
        mixed_lubrication_area_fraction: share(Regime::Mixed),
        boundary_lubrication_area_fraction: share(Regime::Boundary),
        min_separation: tomberger.then(|| {
            local
                .separation
                .iter()
                .cloned()
                .fold(f64::INFINITY, f64::min)
        }),
        fluid_mass_balance_error: local
            .film
            .as_ref()
            .map_or(0.0, |f| (f.inflow - f.outflow - f.expelled) / f.inflow),
    };
    let metal_pressure = local
        .metal_load
        .iter()
        .zip(&local.area_fraction)
        .map(|(l, a)| if *a > 0.0 { l / a } else { 0.0 })
        .collect();
    Solution {
        global,
        fields: Some(Fields {
            grid,
            nominal_pressure: p_n,
            separation: local.separation,
            area_fraction: local.area_fraction,
            friction_coefficient,
            adhesion_limit: tau_l,
            traction: field.traction,
            slip_velocity: field.slip_velocity,
            heat_flux: field.power_density,
            heat_flux_wheel,
            temperature,
            slipping: field.slipping,
            fluid_pressure: local.fluid_pressure,
            nominal_metal_pressure: local.metal_load,
            metal_pressure,
            cell_height: geo.iter().map(|g| g.cell_height).collect(),
            metal_height: geo.iter().map(|g| g.metal_height).collect(),
            fluid_height: local.fluid_height,
            failure_stress_factor: k_fail,
            regime: local.regime,
        }),
        report,
    }
}

fn solve_polach(
    params: &Params,
    point: &OperatingPoint,
    hertz: &HertzContact,
    kalker: &crate::tangential::KalkerCoefficients,
    creep: Creepages,
) -> Result<Solution> {
    let mat0 = params.material.at(params.material.bulk_temperature);
    let f = polach(
        &params.friction.polach,
        hertz.a,
        hertz.b,
        point.normal_force,
        mat0.shear_modulus,
        kalker,
        creep,
        point.speed,
    )?;
    let t0 = params.material.bulk_temperature;
    Ok(Solution {
        global: GlobalResults {
            force_x: f.force_x,
            force_y: f.force_y,
            spin_moment: 0.0,
            traction_coefficient: f.force_x.hypot(f.force_y) / point.normal_force,
            normal_force: point.normal_force,
            semi_axis_a: hertz.a,
            semi_axis_b: hertz.b,
            peak_pressure: hertz.p0,
            max_temperature: t0,
            mean_temperature: t0,
            // global dissipation: force times rigid slip velocity
            frictional_power: -(f.force_x * creep.xi + f.force_y * creep.eta) * point.speed,
            slip_area_fraction: None,
            fluid_load_fraction: 0.0,
            mixed_lubrication_area_fraction: 0.0,
            boundary_lubrication_area_fraction: 0.0,
            min_separation: None,
            fluid_mass_balance_error: 0.0,
        },
        fields: None,
        report: SolverReport {
            iterations: 0,
            residual: 0.0,
            converged: true,
            termination: Termination::ClosedForm,
            max_microcontact_iterations: 0,
            fluid_sweeps: 0,
            fluid_residual: 0.0,
            temperature_backtracks: 0,
        },
    })
}
