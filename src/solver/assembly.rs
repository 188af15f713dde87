//! Global results and local fields from the final iterate of the coupled solve.

use super::local::{Adhesion, Local};
use super::report::SolverReport;
use super::setup::Setup;
use super::solution::{Fields, GlobalResults, Solution};
use crate::fluid::{CellGeometry, CellHeights, FilmSolution, Regime};
use crate::friction;
use crate::tangential::TractionField;

/// The final iterate of the outer iteration.
pub(super) struct Iterate {
    /// Microcontact and fluid state.
    pub local: Local,
    /// Adhesion limit and failure-stress factor.
    pub adhesion: Adhesion,
    /// FASTSIM's traction field.
    pub traction: TractionField,
    /// Heat flux density into the wheel [W/m²].
    pub heat_flux_wheel: Vec<f64>,
    /// Surface temperature [K].
    pub temperature: Vec<f64>,
    /// How the iteration went.
    pub report: SolverReport,
}

/// The solution of the final iterate: global results (sums over the cells, P2 for the traction
/// coefficient) and the local fields.
pub(super) fn assemble(setup: &Setup, it: Iterate) -> Solution {
    let grid = setup.grid.clone();
    let p_n = setup.p_n.clone();
    let heights = CellHeights::new(setup.micro.surface().z_s, setup.base_height);
    let geo: Vec<CellGeometry> = it.local.separation.iter().map(|d| heights.at(*d)).collect();
    let friction_coefficient = it
        .adhesion
        .limit
        .iter()
        .zip(&p_n)
        .map(|(t, p)| friction::local_friction(*t, *p))
        .collect();
    let metal_pressure = it
        .local
        .metal_load
        .iter()
        .zip(&it.local.area_fraction)
        .map(|(l, a)| if *a > 0.0 { l / a } else { 0.0 })
        .collect();
    let global = global_results(setup, &it);
    let (local, field) = (it.local, it.traction);
    Solution {
        global,
        fields: Some(Fields {
            grid,
            nominal_pressure: p_n,
            separation: local.separation,
            area_fraction: local.area_fraction,
            friction_coefficient,
            adhesion_limit: it.adhesion.limit,
            traction: field.traction,
            slip_velocity: field.slip_velocity,
            heat_flux: field.power_density,
            heat_flux_wheel: it.heat_flux_wheel,
            temperature: it.temperature,
            slipping: field.slipping,
            fluid_pressure: local.fluid_pressure,
            nominal_metal_pressure: local.metal_load,
            metal_pressure,
            cell_height: geo.iter().map(|g| g.cell_height).collect(),
            metal_height: geo.iter().map(|g| g.metal_height).collect(),
            fluid_height: local.fluid_height,
            failure_stress_factor: it.adhesion.failure_stress_factor,
            regime: local.regime,
            void_height: geo.iter().map(|g| g.void_height).collect(),
        }),
        report: it.report,
    }
}

/// The global results of the final iterate; the fluid's only for a law that models it.
fn global_results(setup: &Setup, it: &Iterate) -> GlobalResults {
    let hertz = &setup.hertz;
    let (local, field, temperature) = (&it.local, &it.traction, &it.temperature);
    let n = setup.grid.len() as f64;
    let fluid = setup.models_fluid();
    let force_t = field.force_x.hypot(field.force_y);
    let share = |r: Regime| local.regime.iter().filter(|x| **x == r).count() as f64 / n;
    let film = |f: fn(&FilmSolution) -> f64| fluid.then(|| local.film.as_ref().map_or(0.0, f));
    GlobalResults {
        force_x: field.force_x,
        force_y: field.force_y,
        spin_moment: Some(field.spin_moment),
        traction_coefficient: force_t / hertz.normal_force,
        normal_force: hertz.normal_force,
        semi_axis_a: hertz.a,
        semi_axis_b: hertz.b,
        peak_pressure: hertz.p0,
        max_temperature: Some(temperature.iter().cloned().fold(f64::MIN, f64::max)),
        mean_temperature: Some(temperature.iter().sum::<f64>() / n),
        frictional_power: field.frictional_power(&setup.grid),
        slip_area_fraction: Some(field.slipping.iter().filter(|s| **s).count() as f64 / n),
        fluid_load_fraction: fluid.then(|| fluid_load_fraction(local, &setup.p_n)),
        mixed_lubrication_area_fraction: fluid.then(|| share(Regime::Mixed)),
        boundary_lubrication_area_fraction: fluid.then(|| share(Regime::Boundary)),
        min_separation: fluid.then(|| {
            local
                .separation
                .iter()
                .cloned()
                .fold(f64::INFINITY, f64::min)
        }),
        fluid_mass_balance_error: film(|f| (f.inflow - f.outflow - f.expelled) / f.inflow),
        fluid_rejected_fraction: film(|f| f.rejected / (f.inflow + f.rejected)),
        max_dry_area_fraction: fluid.then_some(local.max_dry_area_fraction),
    }
}

/// Share of the normal force carried by fluid pressure, Σ p_f·(1 − A_m/A_n) / Σ p_n (P17) [-].
fn fluid_load_fraction(local: &Local, p_n: &[f64]) -> f64 {
    let fluid_load: f64 = local
        .fluid_pressure
        .iter()
        .zip(&local.area_fraction)
        .map(|(p, a)| p * (1.0 - a))
        .sum();
    fluid_load / p_n.iter().sum::<f64>()
}
