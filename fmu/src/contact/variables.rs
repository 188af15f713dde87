//! The variable table of WheelRailFriction.fmu: the single source of `modelDescription.xml`, of get/set by
//! value reference and of the documentation's variable list. The value reference of each variable is its
//! index in [`VARIABLES`].
//!
//! Frame and signs (MODEL.md §1): x along the track in the direction of travel for positive
//! `rolling_speed`, y lateral, z normal into the rail. Creepages are the rigid slip velocity of the wheel
//! relative to the rail divided by |V|: w = |V|·(ξ − φ·y, η + φ·x). Forces act on the wheel and follow
//! Kalker's convention (they oppose the slip: F_x = −G·c²·C11·ξ in the linear range).

use crate::fmi2::model::{DefaultExperiment, ModelInfo, Unit};
use crate::fmi2::variables::{Causality, Kind, Variability, Variable};

/// `creepage_longitudinal` ξ [-].
pub const CREEPAGE_LONGITUDINAL: usize = 0;
/// `creepage_lateral` η [-].
pub const CREEPAGE_LATERAL: usize = 1;
/// `spin_creepage` φ [1/m].
pub const SPIN_CREEPAGE: usize = 2;
/// `normal_force` F_N [N].
pub const NORMAL_FORCE: usize = 3;
/// `rolling_speed` V [m/s].
pub const ROLLING_SPEED: usize = 4;
/// `wetness` w [-].
pub const WETNESS: usize = 5;
/// `force_longitudinal` F_x [N].
pub const FORCE_LONGITUDINAL: usize = 6;
/// `force_lateral` F_y [N].
pub const FORCE_LATERAL: usize = 7;
/// `spin_moment` M_z [N·m].
pub const SPIN_MOMENT: usize = 8;
/// `traction_coefficient` f [-].
pub const TRACTION_COEFFICIENT: usize = 9;
/// `max_temperature` [K].
pub const MAX_TEMPERATURE: usize = 10;
/// `fluid_load_fraction` [-].
pub const FLUID_LOAD_FRACTION: usize = 11;
/// `evaluation_mode` (1 table, 2 exact).
pub const EVALUATION_MODE: usize = 12;
/// `converged`.
pub const CONVERGED: usize = 13;
/// `roughness` k_r [-].
pub const ROUGHNESS: usize = 14;
/// `curvature_longitudinal` A [1/m].
pub const CURVATURE_LONGITUDINAL: usize = 15;
/// `curvature_lateral` B [1/m].
pub const CURVATURE_LATERAL: usize = 16;
/// `bulk_temperature` T0 [K].
pub const BULK_TEMPERATURE: usize = 17;
/// `k_wet` [-].
pub const K_WET: usize = 18;
/// `flow_resistance` ξ_f [Pa·s].
pub const FLOW_RESISTANCE: usize = 19;
/// `psi_b` ψ_b [-].
pub const PSI_B: usize = 20;
/// `h_f_max` [m].
pub const H_F_MAX: usize = 21;
/// `grid_size` (cells per axis).
pub const GRID_SIZE: usize = 22;
/// `mode` (0 auto, 1 table only, 2 exact only).
pub const MODE: usize = 23;
/// `table_file` (empty: the bundled table).
pub const TABLE_FILE: usize = 24;
/// `minimum_speed` [m/s].
pub const MINIMUM_SPEED: usize = 25;

/// `warm_start`: start each exact solve from the previous one's state.
pub const WARM_START: usize = 26;

/// Default of `minimum_speed`: below this |V| the contact is solved at this speed [m/s].
pub const DEFAULT_MINIMUM_SPEED: f64 = wheelrail::model::DEFAULT_MINIMUM_SPEED;
/// Default of `grid_size` (MODEL.md §2 project default, 30 × 30 cells).
pub const DEFAULT_GRID_SIZE: i32 = 30;

const fn input(
    name: &'static str,
    vr: usize,
    unit: &'static str,
    start: f64,
    range: (f64, f64),
    nominal: f64,
    description: &'static str,
) -> Variable {
    Variable {
        name,
        vr: vr as u32,
        causality: Causality::Input,
        variability: Variability::Continuous,
        kind: Kind::Real {
            unit,
            start: Some(start),
            min: Some(range.0),
            max: Some(range.1),
            nominal: Some(nominal),
        },
        description,
    }
}

const fn output(
    name: &'static str,
    vr: usize,
    unit: &'static str,
    description: &'static str,
) -> Variable {
    Variable {
        name,
        vr: vr as u32,
        causality: Causality::Output,
        variability: Variability::Continuous,
        kind: Kind::Real {
            unit,
            start: None,
            min: None,
            max: None,
            nominal: None,
        },
        description,
    }
}

const fn parameter(
    name: &'static str,
    vr: usize,
    unit: &'static str,
    start: f64,
    range: (f64, f64),
    description: &'static str,
) -> Variable {
    Variable {
        name,
        vr: vr as u32,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        kind: Kind::Real {
            unit,
            start: Some(start),
            min: Some(range.0),
            max: Some(range.1),
            nominal: None,
        },
        description,
    }
}

const fn integer_parameter(
    name: &'static str,
    vr: usize,
    start: i32,
    range: (i32, i32),
    description: &'static str,
) -> Variable {
    Variable {
        name,
        vr: vr as u32,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        kind: Kind::Integer {
            start: Some(start),
            min: Some(range.0),
            max: Some(range.1),
        },
        description,
    }
}

/// Parameter defaults are the library's (`wheelrail::Params::default()`; a unit test checks them).
pub static VARIABLES: [Variable; 27] = [
    input(
        "creepage_longitudinal",
        CREEPAGE_LONGITUDINAL,
        "1",
        0.0,
        (-1.9, 1.9),
        1e-3,
        "Longitudinal creepage xi: rigid slip velocity of the wheel relative to the rail along x divided by |rolling_speed|",
    ),
    input(
        "creepage_lateral",
        CREEPAGE_LATERAL,
        "1",
        0.0,
        (-1.9, 1.9),
        1e-3,
        "Lateral creepage eta: rigid slip velocity of the wheel relative to the rail along y divided by |rolling_speed|",
    ),
    input(
        "spin_creepage",
        SPIN_CREEPAGE,
        "1/m",
        0.0,
        (-1e4, 1e4),
        1e-2,
        "Spin creepage phi: relative angular velocity of wheel and rail about the contact normal z divided by |rolling_speed|",
    ),
    input(
        "normal_force",
        NORMAL_FORCE,
        "N",
        100e3,
        (-1e8, 1e8),
        1e5,
        "Normal force F_N pressing wheel and rail together; at or below 1 mN (wheel lifted) all forces are zero",
    ),
    input(
        "rolling_speed",
        ROLLING_SPEED,
        "m/s",
        30.0,
        (-1e3, 1e3),
        10.0,
        "Rolling speed V along +x; negative: rolling backwards (solved by turning the contact frame); |V| below minimum_speed is raised to it",
    ),
    input(
        "wetness",
        WETNESS,
        "1",
        0.0,
        (0.0, 1.0),
        1.0,
        "Wetness w: 0 dry, 1 inlet film height h_f_max; values outside [0, 1] are clamped with one warning",
    ),
    output(
        "force_longitudinal",
        FORCE_LONGITUDINAL,
        "N",
        "Longitudinal tangential force F_x on the wheel, Kalker's sign convention (opposes the slip: F_x = -G c^2 C11 xi for small xi)",
    ),
    output(
        "force_lateral",
        FORCE_LATERAL,
        "N",
        "Lateral tangential force F_y on the wheel, Kalker's sign convention (F_y = -G c^2 (C22 eta + c C23 phi) for small creepages)",
    ),
    output(
        "spin_moment",
        SPIN_MOMENT,
        "N.m",
        "Spin moment M_z of the tangential tractions about the contact centre (z axis)",
    ),
    output(
        "traction_coefficient",
        TRACTION_COEFFICIENT,
        "1",
        "Traction coefficient f = |F_T|/F_N (paper eq. P2), non-negative",
    ),
    output(
        "max_temperature",
        MAX_TEMPERATURE,
        "K",
        "Highest surface temperature in the contact patch",
    ),
    output(
        "fluid_load_fraction",
        FLUID_LOAD_FRACTION,
        "1",
        "Share of the normal load carried by the interfacial fluid",
    ),
    Variable {
        name: "evaluation_mode",
        vr: EVALUATION_MODE as u32,
        causality: Causality::Output,
        variability: Variability::Discrete,
        kind: Kind::Integer {
            start: None,
            min: Some(1),
            max: Some(2),
        },
        description: "How the outputs were evaluated: 1 lookup table, 2 exact coupled solver",
    },
    Variable {
        name: "converged",
        vr: CONVERGED as u32,
        causality: Causality::Output,
        variability: Variability::Discrete,
        kind: Kind::Boolean { start: None },
        description: "Whether the exact solver's coupled iteration met its tolerance; by table, whether every table point used converged when the table was built; true for a lifted wheel",
    },
    parameter(
        "roughness",
        ROUGHNESS,
        "1",
        0.5,
        (0.0, 1.0),
        "Surface roughness parameter k_r: 0 smooth, 1 rough (MODEL.md section 4)",
    ),
    parameter(
        "curvature_longitudinal",
        CURVATURE_LONGITUDINAL,
        "1/m",
        1.015,
        (1e-3, 1e3),
        "Gap curvature A = (1/R_wx + 1/R_rx)/2 along x (Hertz, MODEL.md section 2)",
    ),
    parameter(
        "curvature_lateral",
        CURVATURE_LATERAL,
        "1/m",
        0.4215,
        (1e-3, 1e3),
        "Gap curvature B = (1/R_wy + 1/R_ry)/2 along y",
    ),
    parameter(
        "bulk_temperature",
        BULK_TEMPERATURE,
        "K",
        293.15,
        (1.0, 2000.0),
        "Bulk temperature T0 of wheel and rail",
    ),
    parameter(
        "k_wet",
        K_WET,
        "1",
        0.4,
        (0.0, 10.0),
        "Failure-stress factor k under boundary lubrication (paper Table 1)",
    ),
    parameter(
        "flow_resistance",
        FLOW_RESISTANCE,
        "Pa.s",
        0.012,
        (1e-9, 1e6),
        "Fluid flow-resistance factor xi_f, 12 x viscosity for a Newtonian fluid (water: 0.012)",
    ),
    parameter(
        "psi_b",
        PSI_B,
        "1",
        0.9995,
        (0.5, 0.999999999999999),
        "Probability of asperity occurrence at the cell base height psi_b (paper Table 1)",
    ),
    parameter(
        "h_f_max",
        H_F_MAX,
        "m",
        20e-6,
        (0.0, 1e-2),
        "Inlet fluid film height at wetness 1",
    ),
    integer_parameter(
        "grid_size",
        GRID_SIZE,
        DEFAULT_GRID_SIZE,
        (4, 400),
        "Cells per axis of the contact grid of the exact solver",
    ),
    integer_parameter(
        "mode",
        MODE,
        0,
        (0, 2),
        "Evaluation mode: 0 auto (lookup table where usable, else exact with one warning), 1 table only (error without a usable table), 2 exact only",
    ),
    Variable {
        name: "table_file",
        vr: TABLE_FILE as u32,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        kind: Kind::String { start: Some("") },
        description: "Lookup table location; empty: the table bundled in the FMU's resources/table",
    },
    parameter(
        "minimum_speed",
        MINIMUM_SPEED,
        "m/s",
        DEFAULT_MINIMUM_SPEED,
        (1e-6, 1e3),
        "Standstill regularisation: contacts with |rolling_speed| below this speed are solved at this speed",
    ),
    Variable {
        name: "warm_start",
        vr: WARM_START as u32,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        kind: Kind::Boolean { start: Some(true) },
        description: "Exact solver: start each solve from the previous exact solution of this instance (its temperature, separation and film fields; several times fewer iterations between nearby steps). Results agree with a cold solve to within the solver tolerance; false makes every output a pure function of the current inputs",
    },
];

/// Units of the variables.
pub static UNITS: [Unit; 8] = [
    Unit {
        name: "1",
        kg: 0,
        m: 0,
        s: 0,
        k: 0,
    },
    Unit {
        name: "1/m",
        kg: 0,
        m: -1,
        s: 0,
        k: 0,
    },
    Unit {
        name: "N",
        kg: 1,
        m: 1,
        s: -2,
        k: 0,
    },
    Unit {
        name: "N.m",
        kg: 1,
        m: 2,
        s: -2,
        k: 0,
    },
    Unit {
        name: "m/s",
        kg: 0,
        m: 1,
        s: -1,
        k: 0,
    },
    Unit {
        name: "K",
        kg: 0,
        m: 0,
        s: 0,
        k: 1,
    },
    Unit {
        name: "m",
        kg: 0,
        m: 1,
        s: 0,
        k: 0,
    },
    Unit {
        name: "Pa.s",
        kg: 1,
        m: -1,
        s: -1,
        k: 0,
    },
];

/// The model description of WheelRailFriction.fmu.
pub static INFO: ModelInfo = ModelInfo {
    model_name: "WheelRailFriction",
    model_identifier: "WheelRailFriction",
    description: "Wheel-rail friction after Tomberger, Dietmaier, Sextro and Six (Wear 271, 2011): creep forces of one \
                  wheel-rail contact from creepages, load, speed and wetness, with roughness, temperature and \
                  interfacial fluid; quasi-static",
    author: "wheelrail project",
    version: env!("CARGO_PKG_VERSION"),
    license: "MIT OR Apache-2.0",
    generation_tool: concat!("wheelrail-fmu ", env!("CARGO_PKG_VERSION")),
    units: &UNITS,
    variables: &VARIABLES,
    default_experiment: DefaultExperiment {
        start_time: 0.0,
        stop_time: 1.0,
        step_size: 1e-3,
    },
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi2::variables::{Value, Values};
    use wheelrail::Params;

    #[test]
    fn value_references_are_table_indices_and_names_are_unique() {
        for (i, v) in VARIABLES.iter().enumerate() {
            assert_eq!(v.vr as usize, i, "{}", v.name);
            assert!(!v.description.is_empty());
            assert_eq!(
                VARIABLES.iter().filter(|w| w.name == v.name).count(),
                1,
                "{}",
                v.name
            );
            if let Kind::Real { unit, .. } = v.kind {
                assert!(
                    UNITS.iter().any(|u| u.name == unit),
                    "unit {unit} of {} is not defined",
                    v.name
                );
            }
        }
    }

    #[test]
    fn parameter_defaults_are_the_librarys() {
        let p = Params::default();
        let v = Values::start(&VARIABLES);
        assert_eq!(v.real(ROUGHNESS), p.roughness.k_r);
        assert_eq!(v.real(CURVATURE_LONGITUDINAL), p.geometry.curvature_x);
        assert_eq!(v.real(CURVATURE_LATERAL), p.geometry.curvature_y);
        assert_eq!(v.real(BULK_TEMPERATURE), p.material.bulk_temperature);
        assert_eq!(v.real(K_WET), p.fluid.k_wet);
        assert_eq!(v.real(FLOW_RESISTANCE), p.fluid.flow_resistance);
        assert_eq!(v.real(PSI_B), p.fluid.psi_b);
        assert_eq!(v.real(H_F_MAX), p.fluid.h_f_max);
        assert_eq!(v.integer(GRID_SIZE) as usize, p.grid.nx);
        assert_eq!(v.list()[TABLE_FILE], Value::String(String::new()));
    }

    #[test]
    fn committed_model_description_is_current() {
        let committed = include_str!("../../../modelDescription/modelDescription.xml");
        assert!(
            committed == crate::model_description(),
            "modelDescription/modelDescription.xml differs from the variable table: run `make model-description`"
        );
    }
}
