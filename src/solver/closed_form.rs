//! The closed-form Polach law (docs/model.md §12): global forces without iteration and without local
//! fields; what it does not model (spin moment, temperature, fluid) is absent.

use super::report::SolverReport;
use super::solution::{GlobalResults, Solution};
use crate::baselines::polach;
use crate::contact::HertzContact;
use crate::error::Result;
use crate::params::{OperatingPoint, Params};
use crate::tangential::{Creepages, KalkerCoefficients};

/// Polach's creep forces for the contact `hertz` (shear modulus at the bulk temperature) and the global
/// dissipation, force times rigid slip velocity [W].
pub(super) fn solve_polach(
    params: &Params,
    point: &OperatingPoint,
    hertz: &HertzContact,
    kalker: &KalkerCoefficients,
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
    Ok(Solution {
        global: GlobalResults {
            force_x: f.force_x,
            force_y: f.force_y,
            spin_moment: None,
            traction_coefficient: f.force_x.hypot(f.force_y) / point.normal_force,
            normal_force: point.normal_force,
            semi_axis_a: hertz.a,
            semi_axis_b: hertz.b,
            peak_pressure: hertz.p0,
            max_temperature: None,
            mean_temperature: None,
            frictional_power: -(f.force_x * creep.xi + f.force_y * creep.eta) * point.speed,
            slip_area_fraction: None,
            fluid_load_fraction: None,
            mixed_lubrication_area_fraction: None,
            boundary_lubrication_area_fraction: None,
            min_separation: None,
            fluid_mass_balance_error: None,
            fluid_rejected_fraction: None,
            max_dry_area_fraction: None,
        },
        fields: None,
        report: SolverReport::closed_form(),
    })
}
