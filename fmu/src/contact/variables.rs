//! The variable table of WheelRailFriction.fmu: the single source of `modelDescription.xml`, of get/set by
//! value reference and of the documentation's variable list. The value reference of each variable is its
//! index in [`VARIABLES`]. The inputs and the model's parameters are rows of the library's parameter
//! specification (`wheelrail::params::spec`: name, value reference, unit, start, range and, for the
//! parameters, description); the FMU adds its own variables (outputs, `grid_size`, `mode`, `table_file`,
//! `minimum_speed`, `warm_start`, `tangential`, the prescribed semi-axes `semi_axis_a`, `semi_axis_b`) and its
//! inputs'
//! conventions (ranges, nominal values, descriptions).
//!
//! **Contact geometry** is an input of every step (docs/model.md §2): the gap curvatures
//! `curvature_longitudinal` A and `curvature_lateral` B (rows of the specification, inputs rather than
//! parameters), or the semi-axes `semi_axis_a`, `semi_axis_b` of an ellipse the MBS tool computes itself:
//! both 0 (the start) means "not prescribed", both > 0 define the ellipse and the curvatures are then
//! ignored; one alone is an error. The contact's ellipse and peak pressure are outputs under other names
//! (`contact_semi_axis_a`, `contact_semi_axis_b`, `peak_pressure`; an FMI name exists once). The frictional
//! power `frictional_power` comes from the exact solver or from the table (format version 2 stores it; a
//! table of format 1 is not used, see [`super::mode::resolve`]).
//!
//! Frame and signs (docs/model.md §1): x along the track in the direction of travel for positive
//! `rolling_speed`, y lateral, z normal into the rail. Creepages are the rigid slip velocity of the wheel
//! relative to the rail divided by |V|: w = |V|·(ξ − φ·y, η + φ·x). Forces act on the wheel and follow
//! Kalker's convention (they oppose the slip: F_x = −G·c²·C11·ξ in the linear range).

use crate::fmi2::model::{DefaultExperiment, DisplayUnit, ModelInfo, Unit};
use crate::fmi2::variables::{Causality, Kind, Variability, Variable};
use crate::fmi3::arrays::{ArrayInfo, Count};
use wheelrail::params::spec::{Bound, Fmu, SEMI_AXIS_RANGE, Spec};
use wheelrail::params::{Input, Param};

/// The FMU variable of a specification row (a compile-time error for a row without one).
const fn exposed(s: &Spec) -> Fmu {
    match s.fmu {
        Some(f) => f,
        None => panic!("the specification row has no FMU variable"),
    }
}

/// The value reference of an input's variable.
const fn input_vr(i: Input) -> usize {
    exposed(i.spec()).value_reference as usize
}

/// The value reference of a parameter's variable.
const fn parameter_vr(p: Param) -> usize {
    exposed(p.spec()).value_reference as usize
}

/// `creepage_longitudinal` ξ [-].
pub const CREEPAGE_LONGITUDINAL: usize = input_vr(Input::CreepageX);
/// `creepage_lateral` η [-].
pub const CREEPAGE_LATERAL: usize = input_vr(Input::CreepageY);
/// `spin_creepage` φ [1/m].
pub const SPIN_CREEPAGE: usize = input_vr(Input::Spin);
/// `normal_force` F_N [N].
pub const NORMAL_FORCE: usize = input_vr(Input::NormalForce);
/// `rolling_speed` V [m/s].
pub const ROLLING_SPEED: usize = input_vr(Input::Speed);
/// `wetness` w [-].
pub const WETNESS: usize = input_vr(Input::Wetness);
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
pub const ROUGHNESS: usize = parameter_vr(Param::RoughnessKr);
/// `curvature_longitudinal` A [1/m] (an input).
pub const CURVATURE_LONGITUDINAL: usize = parameter_vr(Param::CurvatureX);
/// `curvature_lateral` B [1/m] (an input).
pub const CURVATURE_LATERAL: usize = parameter_vr(Param::CurvatureY);
/// `bulk_temperature` T0 [K].
pub const BULK_TEMPERATURE: usize = parameter_vr(Param::BulkTemperature);
/// `k_wet` [-].
pub const K_WET: usize = parameter_vr(Param::KWet);
/// `flow_resistance` ξ_f [Pa·s].
pub const FLOW_RESISTANCE: usize = parameter_vr(Param::FlowResistance);
/// `psi_b` ψ_b [-].
pub const PSI_B: usize = parameter_vr(Param::PsiB);
/// `h_f_max` [m].
pub const H_F_MAX: usize = parameter_vr(Param::HFMax);
/// `grid_size` (cells per axis).
pub const GRID_SIZE: usize = 22;
/// `mode` (0 auto, 1 table only, 2 exact only).
pub const MODE: usize = 23;
/// `table_file` (one or several table directories separated by `;`; empty: the bundled table).
pub const TABLE_FILE: usize = 24;
/// `minimum_speed` [m/s].
pub const MINIMUM_SPEED: usize = 25;

/// `warm_start`: start each exact solve from the previous one's state.
pub const WARM_START: usize = 26;
/// `semi_axis_a`: prescribed semi-axis a along x [m] (input; 0: not prescribed).
pub const SEMI_AXIS_A: usize = 27;
/// `semi_axis_b`: prescribed semi-axis b along y [m] (input; 0: not prescribed).
pub const SEMI_AXIS_B: usize = 28;
/// `contact_semi_axis_a`: the contact ellipse's semi-axis a [m] (output).
pub const CONTACT_SEMI_AXIS_A: usize = 29;
/// `contact_semi_axis_b`: the contact ellipse's semi-axis b [m] (output).
pub const CONTACT_SEMI_AXIS_B: usize = 30;
/// `peak_pressure` p0 [Pa] (output).
pub const PEAK_PRESSURE: usize = 31;
/// `frictional_power` P_f [W] (output).
pub const FRICTIONAL_POWER: usize = 32;
/// `tangential`: the tangential solver, 0 FASTSIM, 1 Kalker's exact steady rolling.
pub const TANGENTIAL: usize = 33;
/// `parameter_file`: a parameter file (TOML, as every command of the `wheelrail` CLI reads; empty: none).
pub const PARAMETER_FILE: usize = 37;

/// Default of `minimum_speed`: below this |V| the contact is solved at this speed [m/s].
pub const DEFAULT_MINIMUM_SPEED: f64 = wheelrail::model::DEFAULT_MINIMUM_SPEED;
/// The library's default `grid.nx` (docs/model.md §2 project default, 30 × 30 cells): the grid of
/// `grid_size` = [`AUTOMATIC_GRID_SIZE`] in mode 2 and the table's.
pub const DEFAULT_GRID_SIZE: i32 = Param::GridNx.default_value() as i32;
/// Start value of `grid_size`: automatic, the library's default grid ([`DEFAULT_GRID_SIZE`] per axis), on
/// which mode 0 solves the points no table serves on a grid per contact (docs/model.md §6.4).
pub const AUTOMATIC_GRID_SIZE: i32 = 0;

/// A closed bound of the specification as an FMI `min`/`max` (a compile-time error for other bounds).
const fn closed(b: Bound) -> f64 {
    match b.closed() {
        Some(x) => x,
        None => panic!("an FMU input needs a closed range"),
    }
}

/// Which values an FMU input accepts.
enum Accepts {
    /// The library's range.
    Library,
    /// The library's range and its negative (rolling backwards, a lifted wheel).
    Signed,
}

/// An input from its specification row (name, value reference, unit, start, range) with the FMU's own
/// range rule, nominal magnitude and description (the FMU's conventions: signed speed, lift-off, clamped
/// wetness).
const fn input(i: Input, accepts: Accepts, nominal: f64, description: &'static str) -> Variable {
    let (s, fmu) = (i.spec(), exposed(i.spec()));
    let max = closed(s.range.hi);
    let min = match accepts {
        Accepts::Library => closed(s.range.lo),
        Accepts::Signed => -max,
    };
    Variable {
        name: fmu.name,
        vr: fmu.value_reference,
        causality: Causality::Input,
        variability: Variability::Continuous,
        kind: Kind::Real {
            unit: s.unit.fmi(),
            start: Some(s.default),
            min: Some(min),
            max: Some(max),
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

/// A parameter wholly from its specification row: name, value reference, unit, start (the library's
/// default), range (FMI states closed bounds only: an open or missing bound has no `min`/`max`) and
/// description; a gap curvature is a continuous input instead ([`is_geometry`]).
const fn spec_parameter(p: Param) -> Variable {
    let (s, fmu) = (p.spec(), exposed(p.spec()));
    let (causality, variability) = if is_geometry(p) {
        (Causality::Input, Variability::Continuous)
    } else {
        (Causality::Parameter, Variability::Fixed)
    };
    Variable {
        name: fmu.name,
        vr: fmu.value_reference,
        causality,
        variability,
        kind: Kind::Real {
            unit: s.unit.fmi(),
            start: Some(s.default),
            min: s.range.lo.closed(),
            max: s.range.hi.closed(),
            nominal: None,
        },
        description: s.description,
    }
}

/// Whether a row of the specification is a gap curvature: an input of every step, not a parameter.
pub const fn is_geometry(p: Param) -> bool {
    matches!(p, Param::CurvatureX | Param::CurvatureY)
}

/// A prescribed semi-axis input [m]: 0 (the start) is "not prescribed"; else the library's range
/// (`SEMI_AXIS_RANGE`, checked per step with the error naming the variable).
const fn semi_axis_input(name: &'static str, vr: usize, description: &'static str) -> Variable {
    Variable {
        name,
        vr: vr as u32,
        causality: Causality::Input,
        variability: Variability::Continuous,
        kind: Kind::Real {
            unit: "m",
            start: Some(0.0),
            min: Some(0.0),
            max: Some(closed(SEMI_AXIS_RANGE.hi)),
            nominal: Some(1e-2),
        },
        description,
    }
}

/// A Real parameter of the FMU's own (not a row of the library's specification).
const fn own_parameter(
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

/// The range of the cells per axis `grid_size` sets: that of the library's `grid.nx` (and `grid.ny`).
pub const GRID_CELLS_RANGE: (i32, i32) = {
    let r = Param::GridNx.spec().range;
    (closed(r.lo) as i32, closed(r.hi) as i32)
};
/// The range of `grid_size`: [`AUTOMATIC_GRID_SIZE`] up to the largest of [`GRID_CELLS_RANGE`].
const GRID_RANGE: (i32, i32) = (AUTOMATIC_GRID_SIZE, GRID_CELLS_RANGE.1);

/// The inputs, in the order of the library's operating point.
const INPUT_VARIABLES: [Variable; 6] = [
    input(
        Input::CreepageX,
        Accepts::Library,
        1e-3,
        "Longitudinal creepage xi: rigid slip velocity of the wheel relative to the rail along x divided by |rolling_speed|",
    ),
    input(
        Input::CreepageY,
        Accepts::Library,
        1e-3,
        "Lateral creepage eta: rigid slip velocity of the wheel relative to the rail along y divided by |rolling_speed|",
    ),
    input(
        Input::Spin,
        Accepts::Library,
        1e-2,
        "Spin creepage phi: relative angular velocity of wheel and rail about the contact normal z divided by |rolling_speed|",
    ),
    input(
        Input::NormalForce,
        Accepts::Signed,
        1e5,
        "Normal force F_N pressing wheel and rail together; at or below 1 mN (wheel lifted) all forces are zero",
    ),
    input(
        Input::Speed,
        Accepts::Signed,
        10.0,
        "Rolling speed V along +x; negative: rolling backwards (solved by turning the contact frame); |V| below minimum_speed is raised to it",
    ),
    input(
        Input::Wetness,
        Accepts::Library,
        1.0,
        "Wetness w: 0 dry, 1 inlet film height h_f_max; values outside [0, 1] are clamped with one warning",
    ),
];

/// The FMU's own variables: the outputs, the parameters of its evaluation and the prescribed semi-axes.
const OWN_VARIABLES: [Variable; 21] = [
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
    integer_parameter(
        "grid_size",
        GRID_SIZE,
        AUTOMATIC_GRID_SIZE,
        GRID_RANGE,
        "Cells per axis of the contact grid of the exact solver; 0 (automatic): 30 x 30, and in mode 0 the points the table does not serve on a grid per contact (16 to 24 cells along x, 6 to 12 across, more on a wide contact: forces within 1 % of F_N and T_max within 10 K of 30 x 30)",
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
        description: "Lookup table location, or several separated by ';', tried in order for each step; empty (or an empty entry): the table bundled in the FMU's resources/table",
    },
    own_parameter(
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
    semi_axis_input(
        "semi_axis_a",
        SEMI_AXIS_A,
        "Prescribed contact semi-axis a along x (e.g. from the MBS tool's own normal contact): when semi_axis_a and semi_axis_b are both > 0 they define the ellipse, the curvatures are ignored and peak_pressure = 3 F_N/(2 pi a b); both 0: Hertz from the curvatures; one alone is an error. The contact's semi-axis is the output contact_semi_axis_a",
    ),
    semi_axis_input(
        "semi_axis_b",
        SEMI_AXIS_B,
        "Prescribed contact semi-axis b along y: see semi_axis_a. The contact's semi-axis is the output contact_semi_axis_b",
    ),
    output(
        "contact_semi_axis_a",
        CONTACT_SEMI_AXIS_A,
        "m",
        "Semi-axis a along x of the contact ellipse evaluated (Hertz from the curvatures, or the prescribed semi_axis_a); named apart from the input semi_axis_a; 0 for a lifted wheel",
    ),
    output(
        "contact_semi_axis_b",
        CONTACT_SEMI_AXIS_B,
        "m",
        "Semi-axis b along y of the contact ellipse evaluated (Hertz from the curvatures, or the prescribed semi_axis_b); named apart from the input semi_axis_b; 0 for a lifted wheel",
    ),
    output(
        "peak_pressure",
        PEAK_PRESSURE,
        "Pa",
        "Peak Hertz pressure p0 = 3 F_N/(2 pi a b) of the contact ellipse; 0 for a lifted wheel",
    ),
    output(
        "frictional_power",
        FRICTIONAL_POWER,
        "W",
        "Frictional power P_f = sum of |tau|·|s|·dA over the slipping cells (the heat source, and the work-rate basis of T-gamma wear indices): by the exact solver, or interpolated from the lookup table (P_f/(F_N V) is one of its outputs); 0 for a lifted wheel",
    ),
    Variable {
        name: "tangential",
        vr: TANGENTIAL as u32,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        kind: Kind::Integer {
            start: Some(0),
            min: Some(0),
            max: Some(1),
        },
        description: "Tangential contact solver: 0 FASTSIM with the parabolic pressure, 1 Kalker's exact steady rolling with Hertz's pressure (docs/model.md 6.5, 6.6; slower). A lookup table serves only the method it was built with: otherwise mode 0 solves exactly (one warning) and mode 1 is an error",
    },
    Variable {
        name: "parameter_file",
        vr: PARAMETER_FILE as u32,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        kind: Kind::String { start: Some("") },
        description: "Parameter file (TOML, as the wheelrail CLI reads, e.g. the fitted.toml of wheelrail fit) whose values replace the defaults of every parameter, those without an FMU variable included; a parameter variable set away from its start value overrides the file, and one set to a value that differs from the file's too is an error; empty: no file",
    },
];

/// The number of rows of the library's specification that the FMU exposes (parameters and the gap
/// curvatures, which are inputs).
const EXPOSED_ROWS: usize = {
    let (mut n, mut k) = (0, 0);
    while k < Param::ALL.len() {
        if Param::ALL[k].spec().fmu.is_some() {
            n += 1;
        }
        k += 1;
    }
    n
};

/// The number of parameters of the library's specification that the FMU exposes as parameters.
const EXPOSED: usize = {
    let (mut n, mut k) = (0, 0);
    while k < Param::ALL.len() {
        if Param::ALL[k].spec().fmu.is_some() && !is_geometry(Param::ALL[k]) {
            n += 1;
        }
        k += 1;
    }
    n
};

/// The rows of the library's specification that the FMU exposes (the rows with an FMU variable), with
/// their variables' indices, in the specification's order; `parameters` selects the parameters (else the
/// gap curvatures).
const fn exposed_rows<const N: usize>(parameters: bool) -> [(Param, usize); N] {
    let mut out = [(Param::ALL[0], 0); N];
    let (mut n, mut k) = (0, 0);
    while k < Param::ALL.len() {
        if let Some(f) = Param::ALL[k].spec().fmu
            && is_geometry(Param::ALL[k]) != parameters
        {
            out[n] = (Param::ALL[k], f.value_reference as usize);
            n += 1;
        }
        k += 1;
    }
    out
}

/// The parameters of the library's specification that the FMU exposes as parameters, with their
/// variables' indices, in the specification's order.
pub const EXPOSED_PARAMETERS: [(Param, usize); EXPOSED] = exposed_rows(true);

/// The rows of the specification that the FMU exposes as inputs of every step (the gap curvatures).
const GEOMETRY_ROWS: [(Param, usize); EXPOSED_ROWS - EXPOSED] = exposed_rows(false);

/// The number of variables.
const COUNT: usize = INPUT_VARIABLES.len() + OWN_VARIABLES.len() + EXPOSED_ROWS;

/// Puts a variable at its value reference; a clash or a reference beyond the table is a compile-time
/// error.
const fn place(mut slots: [Option<Variable>; COUNT], v: Variable) -> [Option<Variable>; COUNT] {
    let i = v.vr as usize;
    if i >= COUNT {
        panic!("a value reference lies beyond the variable table");
    }
    if slots[i].is_some() {
        panic!("two variables share a value reference");
    }
    slots[i] = Some(v);
    slots
}

/// The variable table: the inputs, the FMU's own variables and the exposed parameters of the library's
/// specification, each at its value reference (a gap is a compile-time error).
const fn assemble() -> [Variable; COUNT] {
    let mut slots = [None; COUNT];
    let mut k = 0;
    while k < INPUT_VARIABLES.len() {
        slots = place(slots, INPUT_VARIABLES[k]);
        k += 1;
    }
    k = 0;
    while k < OWN_VARIABLES.len() {
        slots = place(slots, OWN_VARIABLES[k]);
        k += 1;
    }
    k = 0;
    while k < EXPOSED {
        slots = place(slots, spec_parameter(EXPOSED_PARAMETERS[k].0));
        k += 1;
    }
    k = 0;
    while k < GEOMETRY_ROWS.len() {
        slots = place(slots, spec_parameter(GEOMETRY_ROWS[k].0));
        k += 1;
    }
    let mut table = [OWN_VARIABLES[0]; COUNT];
    k = 0;
    while k < COUNT {
        table[k] = match slots[k] {
            Some(v) => v,
            None => panic!("a value reference is unused: the variable table has a gap"),
        };
        k += 1;
    }
    table
}

/// The variable table of the FMU; the value reference of each variable is its index. Parameter defaults
/// and ranges are the library's (its specification, `wheelrail::params::spec`).
pub static VARIABLES: [Variable; COUNT] = assemble();

/// Units of the variables, each with the display units an importer may show it in (FMI 2.0 §2.2.2: shown =
/// factor · value + offset).
pub static UNITS: [Unit; 10] = [
    Unit {
        name: "1",
        kg: 0,
        m: 0,
        s: 0,
        k: 0,
        display: &[DisplayUnit {
            name: "%",
            factor: 100.0,
            offset: 0.0,
        }],
    },
    Unit {
        name: "1/m",
        kg: 0,
        m: -1,
        s: 0,
        k: 0,
        display: &[],
    },
    Unit {
        name: "N",
        kg: 1,
        m: 1,
        s: -2,
        k: 0,
        display: &[DisplayUnit {
            name: "kN",
            factor: 0.001,
            offset: 0.0,
        }],
    },
    Unit {
        name: "N.m",
        kg: 1,
        m: 2,
        s: -2,
        k: 0,
        display: &[DisplayUnit {
            name: "kN.m",
            factor: 0.001,
            offset: 0.0,
        }],
    },
    Unit {
        name: "m/s",
        kg: 0,
        m: 1,
        s: -1,
        k: 0,
        display: &[DisplayUnit {
            name: "km/h",
            factor: 3.6,
            offset: 0.0,
        }],
    },
    Unit {
        name: "K",
        kg: 0,
        m: 0,
        s: 0,
        k: 1,
        display: &[DisplayUnit {
            name: "degC",
            factor: 1.0,
            offset: -273.15,
        }],
    },
    Unit {
        name: "m",
        kg: 0,
        m: 1,
        s: 0,
        k: 0,
        display: &[DisplayUnit {
            name: "mm",
            factor: 1000.0,
            offset: 0.0,
        }],
    },
    Unit {
        name: "Pa.s",
        kg: 1,
        m: -1,
        s: -1,
        k: 0,
        display: &[],
    },
    Unit {
        name: "Pa",
        kg: 1,
        m: -1,
        s: -2,
        k: 0,
        display: &[DisplayUnit {
            name: "MPa",
            factor: 1e-06,
            offset: 0.0,
        }],
    },
    Unit {
        name: "W",
        kg: 1,
        m: 2,
        s: -3,
        k: 0,
        display: &[DisplayUnit {
            name: "kW",
            factor: 0.001,
            offset: 0.0,
        }],
    },
];

/// Dimensionless variables shown in percent: the creepages and the fluid's share of the load.
const IN_PERCENT: [&str; 3] = [
    "creepage_longitudinal",
    "creepage_lateral",
    "fluid_load_fraction",
];

/// The display unit a variable is shown in by default: the SI units' display units (kN, kN.m, km/h, degC,
/// mm, MPa, kW), percent for [`IN_PERCENT`], none for the other units.
fn display_unit(v: &Variable) -> Option<&'static str> {
    let Kind::Real { unit, .. } = v.kind else {
        return None;
    };
    let shown = UNITS.iter().find(|u| u.name == unit)?.display.first()?.name;
    (unit != "1" || IN_PERCENT.contains(&v.name)).then_some(shown)
}

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
    display_unit,
    variables: &VARIABLES,
    default_experiment: DefaultExperiment {
        start_time: 0.0,
        stop_time: 1.0,
        step_size: 1e-3,
    },
};

/// The value reference of the FMI 3.0 structural parameter `contacts` (beyond the variable table's).
pub const CONTACTS_VR: u32 = 1000;
/// The value reference of the FMI 3.0 parameter `threads`.
pub const THREADS_VR: u32 = 1001;
/// The value reference of the FMI 3.0 independent variable `time`.
pub const TIME_VR: u32 = 1002;
/// The most contacts one FMI 3.0 instance holds (a vehicle has a few dozen at most; the bound keeps a
/// mistaken value from allocating without limit).
pub const MAX_CONTACTS: u64 = 4096;
/// The most threads one FMI 3.0 instance starts.
pub const MAX_THREADS: u64 = 1024;

/// The FMI 3.0 arrays of WheelRailFriction: every input and output per contact, and `roughness` (each
/// wheel and rail its own surface).
pub static ARRAYS: ArrayInfo = ArrayInfo {
    size: Count {
        name: "contacts",
        vr: CONTACTS_VR,
        start: 1,
        min: 1,
        max: MAX_CONTACTS,
        description: "Number of wheel-rail contacts of this instance: the size of every input and output \
                      array and of roughness (set in configuration mode)",
    },
    threads: Count {
        name: "threads",
        vr: THREADS_VR,
        start: 0,
        min: 0,
        max: MAX_THREADS,
        description: "Threads that evaluate the contacts of a step (0: the cores the process may use; a \
                      step too small to gain from them stays on the calling thread; results are bit for bit \
                      the same for any number)",
    },
    time_vr: TIME_VR,
    element_parameters: &[ROUGHNESS],
    element: "contact",
    description: "Wheel-rail friction after Tomberger, Dietmaier, Sextro and Six (Wear 271, 2011): creep forces of \
                  any number of wheel-rail contacts (structural parameter contacts) from creepages, load, speed \
                  and wetness, with roughness, temperature and interfacial fluid; quasi-static; the contacts \
                  of a step evaluated in parallel",
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi2::variables::{Value, Values};
    use wheelrail::Params;

    /// The value `x` of variable `vr` as an importer shows it in the variable's display unit.
    fn shown(vr: usize, x: f64) -> (f64, &'static str) {
        let v = &VARIABLES[vr];
        let name = display_unit(v).expect("a display unit");
        let Kind::Real { unit, .. } = v.kind else {
            unreachable!()
        };
        let unit = UNITS.iter().find(|u| u.name == unit).unwrap();
        let d = unit.display.iter().find(|d| d.name == name).unwrap();
        (d.factor * x + d.offset, name)
    }

    #[test]
    fn display_units_convert_as_their_definitions_say() {
        // water boils at 373.15 K = 100 degC; 100 kN; 30 m/s = 108 km/h; a creepage of 0.002 = 0.2 %
        let close = |(a, unit): (f64, &str), (b, want): (f64, &str)| {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1.0) && unit == want,
                "{a} {unit}"
            );
        };
        close(shown(MAX_TEMPERATURE, 373.15), (100.0, "degC"));
        close(shown(BULK_TEMPERATURE, 273.15), (0.0, "degC"));
        close(shown(NORMAL_FORCE, 1e5), (100.0, "kN"));
        close(shown(FORCE_LATERAL, -2.5e4), (-25.0, "kN"));
        close(shown(SPIN_MOMENT, 1500.0), (1.5, "kN.m"));
        close(shown(ROLLING_SPEED, 30.0), (108.0, "km/h"));
        close(shown(CREEPAGE_LONGITUDINAL, 0.002), (0.2, "%"));
        close(shown(CONTACT_SEMI_AXIS_A, 5.9e-3), (5.9, "mm"));
        close(shown(PEAK_PRESSURE, 7.7e8), (770.0, "MPa"));
        close(shown(FRICTIONAL_POWER, 2.0e4), (20.0, "kW"));
        // the traction coefficient and the wetness stay as they are (no percent), non-Reals have none
        for vr in [TRACTION_COEFFICIENT, WETNESS, ROUGHNESS, MODE, CONVERGED] {
            assert_eq!(display_unit(&VARIABLES[vr]), None, "{}", VARIABLES[vr].name);
        }
        // every display unit is defined once in its unit
        for u in &UNITS {
            for d in u.display {
                assert_eq!(u.display.iter().filter(|e| e.name == d.name).count(), 1);
            }
        }
    }

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
        // automatic: the library's default grid (the one the bundled table was built on)
        assert_eq!(v.integer(GRID_SIZE), AUTOMATIC_GRID_SIZE);
        assert_eq!(DEFAULT_GRID_SIZE as usize, p.grid.nx);
        assert_eq!(DEFAULT_GRID_SIZE as usize, p.grid.ny);
        assert_eq!(v.integer(TANGENTIAL), 0);
        assert_eq!(p.tangential, wheelrail::params::Tangential::Fastsim);
        assert_eq!(v.list()[TABLE_FILE], Value::String(String::new()));
    }

    #[test]
    fn every_row_with_an_fmu_variable_is_that_variable() {
        let rows = wheelrail::params::spec::specs().filter(|s| s.fmu.is_some());
        for s in rows {
            let f = s.fmu.unwrap();
            let v = &VARIABLES[f.value_reference as usize];
            assert_eq!(v.name, f.name);
            let want = match s.key {
                wheelrail::params::Key::Input(_) => Causality::Input,
                wheelrail::params::Key::Param(p) if is_geometry(p) => Causality::Input,
                _ => Causality::Parameter,
            };
            assert_eq!(v.causality, want, "{}", v.name);
            let Kind::Real {
                unit,
                start,
                min,
                max,
                ..
            } = v.kind
            else {
                panic!("{} is not a Real", v.name)
            };
            assert_eq!((unit, start), (s.unit.fmi(), Some(s.default)), "{}", v.name);
            // the FMU's range holds the library's (inputs may accept more: signed speed, lift-off)
            for x in [min, max].into_iter().flatten() {
                assert!(
                    s.range.contains(x) || want == Causality::Input,
                    "{}",
                    v.name
                );
            }
        }
    }

    #[test]
    fn committed_model_description_is_current() {
        let committed = include_str!("../../../modelDescription/modelDescription.xml");
        assert!(
            committed == crate::model_description(),
            "modelDescription/modelDescription.xml differs from the variable table: run `make model-description`"
        );
    }

    #[test]
    fn committed_fmi3_model_description_is_current() {
        let committed = include_str!("../../../modelDescription/modelDescription-fmi3.xml");
        assert!(
            committed == crate::model_description_fmi3(),
            "modelDescription/modelDescription-fmi3.xml differs from the variable table: run `make model-description`"
        );
    }
}
