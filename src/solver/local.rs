//! The per-cell state of one outer iteration at a temperature field: microcontact and fluid film
//! (separation, p_f, A_m/A_n), then failure stress and adhesion limit.

use super::report::SolverReport;
use super::setup::{Setup, surface_speeds};
use crate::error::{Error, Result, Stage};
use crate::fluid::{FilmProblem, FilmSolution, FilmStart, Regime, solve_film, solve_film_newton};
use crate::friction;
use crate::materials::MaterialState;
use crate::params::FrictionLaw;

/// The microcontact and fluid state of every cell for one temperature field.
pub(super) struct Local {
    /// The asperities alone carrying p_n in every cell (equal to the state below when dry).
    pub dry: Dry,
    /// The largest A_m/A_n at the dry separation over the cells [-] (where the walls of the film begin,
    /// `fluid::takes_in_all`).
    pub max_dry_area_fraction: f64,
    /// Separation d of the mean planes [m].
    pub separation: Vec<f64>,
    /// Metallic contact area ratio A_m/A_n [-].
    pub area_fraction: Vec<f64>,
    /// Nominal metallic pressure p_m·A_m/A_n [Pa].
    pub metal_load: Vec<f64>,
    /// Fluid pressure p_f [Pa].
    pub fluid_pressure: Vec<f64>,
    /// Fluid height l_f [m].
    pub fluid_height: Vec<f64>,
    /// Lubrication regime.
    pub regime: Vec<Regime>,
    /// The film solution (None without fluid).
    pub film: Option<FilmSolution>,
}

/// The adhesion limit of every cell and the failure-stress factor it came from.
pub(super) struct Adhesion {
    /// Tangential adhesion limit τ_l (P6) [Pa].
    pub limit: Vec<f64>,
    /// Failure-stress factor k [-] (k_dry for the laws without failure stress).
    pub failure_stress_factor: Vec<f64>,
}

/// The asperity contact alone carrying p_n in every cell: the dry state the film starts from.
#[derive(Clone)]
pub(super) struct Dry {
    /// Separation d_dry [m].
    pub separation: Vec<f64>,
    /// A_m/A_n at d_dry [-].
    pub area_fraction: Vec<f64>,
    /// p_m·A_m/A_n at d_dry (p_n, or the microcontact model's load floor) [Pa].
    pub metal_load: Vec<f64>,
}

/// The dry state of an earlier iterate of the same solve (the same nominal pressures) and the materials
/// it was solved at: a cell whose material is the same again (its temperature unchanged, e.g. ahead of
/// the heat in the adhesion zone) keeps its state instead of solving the same separation again.
pub(super) struct DryIterate {
    /// The materials per cell the state was solved at.
    pub materials: Vec<MaterialState>,
    /// The state.
    pub dry: Dry,
}

impl Setup<'_> {
    /// Microcontact (and, when wet, the fluid film) at the cells' material states.
    /// `fluid_tolerance` is the film sweep tolerance for this outer iteration.
    /// `dry_guess`: per-cell separations to start the microcontact Newton from (a warm start's);
    /// `previous`: the dry state of the last iterate, kept where a cell's material is unchanged and
    /// otherwise the start of its Newton ([`Setup::dry`]).
    /// `fallback`: whether the film falls back to Gauss–Seidel sweeps where Newton stalls
    /// ([`solve_film`]), or keeps Newton's last film ([`solve_film_newton`]).
    #[allow(clippy::too_many_arguments)]
    pub fn local(
        &self,
        mats: &[MaterialState],
        dry_guess: Option<&[f64]>,
        previous: Option<&DryIterate>,
        warm: Option<FilmStart>,
        fluid_tolerance: f64,
        fallback: bool,
        report: &mut SolverReport,
    ) -> Result<Local> {
        let dry = self.dry(mats, dry_guess, previous, report)?;
        let max_dry_area_fraction = dry
            .area_fraction
            .iter()
            .cloned()
            .fold(f64::NEG_INFINITY, f64::max);
        let h_f0 = self.inlet_film();
        if h_f0 <= 0.0 {
            let n = self.grid.len();
            return Ok(Local {
                separation: dry.separation.clone(),
                max_dry_area_fraction,
                area_fraction: dry.area_fraction.clone(),
                metal_load: dry.metal_load.clone(),
                dry,
                fluid_pressure: vec![0.0; n],
                fluid_height: vec![0.0; n],
                regime: vec![Regime::Dry; n],
                film: None,
            });
        }
        let film = self.film(mats, &dry, h_f0, warm, fluid_tolerance, fallback)?;
        report.fluid_sweeps = film.iterations;
        report.fluid_residual = film.residual;
        report.fluid_balance_residual = film.balance_residual;
        Ok(Local {
            dry,
            max_dry_area_fraction,
            separation: film.separation.clone(),
            area_fraction: film.area_fraction.clone(),
            metal_load: film.metal_load.clone(),
            fluid_pressure: film.fluid_pressure.clone(),
            fluid_height: film.fluid_height.clone(),
            regime: film.regime.clone(),
            film: Some(film),
        })
    }

    /// The separation at which the asperities alone carry p_n in each cell (docs/model.md §4): the
    /// `previous` iterate's state where the cell's material is the same (the same inputs: the solve's
    /// p_n and the material), else a Newton solve started from the previous iterate's separation,
    /// `dry_guess` (a warm start's) or else from the neighbour just solved in the same strip; an
    /// unconverged one is an error.
    fn dry(
        &self,
        mats: &[MaterialState],
        dry_guess: Option<&[f64]>,
        previous: Option<&DryIterate>,
        report: &mut SolverReport,
    ) -> Result<Dry> {
        let n = self.grid.len();
        let mut dry_d = vec![0.0; n];
        let mut area = vec![0.0; n];
        let mut load = vec![0.0; n];
        let dry_guess = previous.map(|p| &p.dry.separation[..]).or(dry_guess);
        for c in 0..n {
            if let Some(p) = previous.filter(|p| p.materials[c] == mats[c]) {
                dry_d[c] = p.dry.separation[c];
                area[c] = p.dry.area_fraction[c];
                load[c] = p.dry.metal_load[c];
                continue;
            }
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
                    stage: Stage::Microcontact,
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
        Ok(Dry {
            separation: dry_d,
            area_fraction: area,
            metal_load: load,
        })
    }

    /// The inlet film h_f0 = w·h_f,max [m] (docs/model.md §8); 0 for the laws without fluid, which
    /// ignore the wetness.
    fn inlet_film(&self) -> f64 {
        if self.models_fluid() {
            self.point.wetness * self.params.fluid.h_f_max
        } else {
            0.0
        }
    }

    /// The film (P12–P17, docs/model.md §8) on the dry state at the inlet film `h_f0` [m], started from
    /// `warm`, to `tolerance`, with or without the Gauss–Seidel `fallback`.
    fn film(
        &self,
        mats: &[MaterialState],
        dry: &Dry,
        h_f0: f64,
        warm: Option<FilmStart>,
        tolerance: f64,
        fallback: bool,
    ) -> Result<FilmSolution> {
        let (v_w, v_r) = surface_speeds(self.point);
        let solve = if fallback {
            solve_film
        } else {
            solve_film_newton
        };
        solve(
            &FilmProblem {
                grid: &self.grid,
                nominal_pressure: &self.p_n,
                materials: mats,
                dry_separation: &dry.separation,
                dry_area_fraction: &dry.area_fraction,
                dry_metal_load: &dry.metal_load,
                micro: &self.micro,
                base_height: self.base_height,
                flow_resistance: self.params.fluid.flow_resistance,
                rail_speed: v_r,
                mean_speed: 0.5 * (v_w + v_r),
                inlet_film: h_f0,
                tolerance,
                max_iterations: self.params.solver.max_fluid_sweeps,
            },
            warm,
        )
    }

    /// The adhesion limit of every cell: for the Tomberger law τ_l = τ_m·A_m/A_n with the failure stress
    /// τ_m = k·σ_y(T) and k blended from k_dry to k_wet by the fluid height (P1, P3, P6; docs/model.md §5);
    /// for the constant law τ_l = μ·p_n.
    pub fn adhesion(&self, local: &Local, mats: &[MaterialState]) -> Adhesion {
        let p = self.params;
        let n = self.grid.len();
        // (Polach's closed form never reaches the local solve: `coupled::solve_from`)
        let tomberger = match p.friction.law {
            FrictionLaw::Tomberger => true,
            FrictionLaw::Constant | FrictionLaw::Polach => false,
        };
        let mut limit = vec![0.0; n];
        let mut k_fail = vec![p.friction.k_dry; n];
        for c in 0..n {
            limit[c] = if tomberger {
                k_fail[c] = friction::failure_stress_factor(
                    p.friction.k_dry,
                    p.fluid.k_wet,
                    local.fluid_height[c],
                    p.fluid.h_bl,
                );
                let tau_m = friction::failure_stress(k_fail[c], mats[c].yield_stress);
                friction::adhesion_limit(tau_m, local.area_fraction[c])
            } else {
                p.friction.mu * self.p_n[c]
            };
        }
        Adhesion {
            limit,
            failure_stress_factor: k_fail,
        }
    }
}
