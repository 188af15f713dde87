//! What a solve returns: global results, local fields and the convergence report.

use super::report::SolverReport;
use crate::contact::ContactGrid;
use crate::fluid::Regime;
use serde::Serialize;

/// Global results of one operating point (SI units, kelvin).
///
/// A quantity that the friction law does not model is None (JSON null), never a made-up number: the
/// closed-form Polach law has no spin moment, no temperature and no fluid; the constant-μ law has no fluid
/// (it ignores the wetness). With heat switched off (`solver.heat = false`) the temperature is the
/// model's answer T = T0, not absent.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GlobalResults {
    /// Longitudinal tangential force on the wheel F_x [N] (Kalker's sign convention).
    pub force_x: f64,
    /// Lateral tangential force on the wheel F_y [N].
    pub force_y: f64,
    /// Spin moment M_z [N·m] (None for the closed-form Polach law).
    pub spin_moment: Option<f64>,
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
    /// Highest surface temperature in the contact [K] (None for the closed-form Polach law).
    pub max_temperature: Option<f64>,
    /// Mean surface temperature over the contact [K] (None for the closed-form Polach law).
    pub mean_temperature: Option<f64>,
    /// Total frictional power [W].
    pub frictional_power: f64,
    /// Share of the contact area in slip [-] (None for the closed-form Polach law).
    pub slip_area_fraction: Option<f64>,
    /// Share of the normal force carried by fluid pressure, Σ p_f(1 − A_m/A_n) / Σ p_n [-] (None unless
    /// the Tomberger law).
    pub fluid_load_fraction: Option<f64>,
    /// Share of the contact area in mixed lubrication [-] (None unless the Tomberger law).
    pub mixed_lubrication_area_fraction: Option<f64>,
    /// Share of the contact area in boundary lubrication [-] (None unless the Tomberger law).
    pub boundary_lubrication_area_fraction: Option<f64>,
    /// Smallest separation of the mean planes in the contact [m] (None unless the Tomberger law).
    pub min_separation: Option<f64>,
    /// Fluid volume balance: inlet flow minus carried-out and expelled flow, relative to the inlet flow [-]
    /// (0 without fluid; None unless the Tomberger law).
    pub fluid_mass_balance_error: Option<f64>,
    /// Share of the rail's film ahead of the contact that the leading cells do not take in and that is
    /// pushed aside, rejected/(taken in + rejected) [-] (0 without fluid, > 0 on a flooded inlet; None
    /// unless the Tomberger law).
    pub fluid_rejected_fraction: Option<f64>,
    /// Largest metallic area ratio A_m/A_n over the contact at the dry separation d_dry, where the asperities
    /// alone carry p_n (docs/model.md §4.3) [-]. GW's area, which ignores overlapping asperity contacts,
    /// exceeds the nominal area at high pressure; from 1 − 0.005 on the film model takes in less of the
    /// carried film and at 1 treats the cell as a wall (§8.5), so the contact's downstream part loses its
    /// film ([`crate::fluid::takes_in_all`] tells where that starts). The same dry or wet (None unless the
    /// Tomberger law).
    pub max_dry_area_fraction: Option<f64>,
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
    /// Void height open to the fluid l_v = l_c − l_m at the separation d [m] (P15; the film's l_v).
    pub void_height: Vec<f64>,
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
