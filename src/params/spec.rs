//! The parameter specification: one row per scalar parameter of [`Params`] and per input of
//! [`OperatingPoint`], the single source of names, units, allowed ranges and defaults.
//!
//! Everything else is derived from these rows: the `Default` impls of the parameter structs and of the
//! operating point, [`Params::validate`] and [`OperatingPoint::validate`] (and so the errors, which carry a
//! typed [`Key`]), the command line's value flags and `wheelrail parameters` (whose `--markdown` output is
//! `docs/parameters.md`), and the FMU's parameters and inputs in `modelDescription.xml`.
//!
//! **Adding a scalar parameter:** add its field (with a doc comment) to its struct in `params/mod.rs`, let
//! the struct's `Default` read [`Param::default_value`], and add one row to the `Param` table below. A
//! `cli` name gives it a flag `--name` of every model subcommand; an `fmu` entry exposes it as an FMU
//! parameter under that name and value reference (a contract: never reuse or change one; the FMU's table
//! fails to compile on a clash or a gap). Then regenerate `docs/parameters.md` (`make parameter-docs`) and,
//! with an `fmu` entry, `modelDescription/modelDescription.xml` (`make model-description`).
//!
//! Parameters that are not scalars stay special-cased where they are used: the friction law
//! (`friction.law`), the tangential solver and the normal pressure (`tangential`, `pressure`), frictional
//! heating on/off (`solver.heat`), the prescribed semi-axes
//! (`geometry.semi_axes`, range [`SEMI_AXIS_RANGE`], keys [`Key::SemiAxisA`] and [`Key::SemiAxisB`]) and
//! the pairs of the command line (`--curvatures A,B`, `--semi-axes a,b`, `--grid NX,NY`, whose ranges are
//! those of the rows they set).

use super::{CELSIUS_ZERO, OperatingPoint, Params};
use crate::error::{Error, Result};

/// One end of an allowed range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bound {
    /// No limit on this side (the value must still be finite).
    Unbounded,
    /// The limit belongs to the range (≤, ≥).
    Closed(f64),
    /// The limit does not belong to the range (<, >).
    Open(f64),
}

impl Bound {
    /// The limit when it belongs to the range, as FMI's inclusive `min`/`max` can state it.
    pub const fn closed(self) -> Option<f64> {
        match self {
            Bound::Closed(x) => Some(x),
            Bound::Unbounded | Bound::Open(_) => None,
        }
    }
}

/// The allowed values of a parameter or input: finite numbers between two bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Lower end.
    pub lo: Bound,
    /// Upper end.
    pub hi: Bound,
}

impl Range {
    /// `lo ..= hi`.
    pub const fn closed(lo: f64, hi: f64) -> Range {
        Range {
            lo: Bound::Closed(lo),
            hi: Bound::Closed(hi),
        }
    }

    /// `> 0`: strictly positive, no upper limit.
    pub const POSITIVE: Range = Range {
        lo: Bound::Open(0.0),
        hi: Bound::Unbounded,
    };

    /// Whether `x` is finite and inside the range (NaN and infinities never are).
    pub fn contains(&self, x: f64) -> bool {
        let above = match self.lo {
            Bound::Unbounded => true,
            Bound::Closed(lo) => x >= lo,
            Bound::Open(lo) => x > lo,
        };
        let below = match self.hi {
            Bound::Unbounded => true,
            Bound::Closed(hi) => x <= hi,
            Bound::Open(hi) => x < hi,
        };
        x.is_finite() && above && below
    }

    /// The bounds as text: `0 ..= 1`, `> 0`, `>= 0 and < 1`; empty without bounds.
    pub fn bounds(&self) -> String {
        self.bounds_with(|x| x.to_string())
    }

    /// The bounds as text with the numbers formatted by `number`.
    pub fn bounds_with(&self, number: impl Fn(f64) -> String) -> String {
        match (self.lo, self.hi) {
            (Bound::Closed(lo), Bound::Closed(hi)) => format!("{} ..= {}", number(lo), number(hi)),
            (lo, hi) => {
                let lo = match lo {
                    Bound::Unbounded => None,
                    Bound::Closed(x) => Some(format!(">= {}", number(x))),
                    Bound::Open(x) => Some(format!("> {}", number(x))),
                };
                let hi = match hi {
                    Bound::Unbounded => None,
                    Bound::Closed(x) => Some(format!("<= {}", number(x))),
                    Bound::Open(x) => Some(format!("< {}", number(x))),
                };
                lo.into_iter().chain(hi).collect::<Vec<_>>().join(" and ")
            }
        }
    }

    /// The allowed values as error messages state them: `finite, 0 ..= 1 m`, `finite, > 0 Pa s`.
    pub fn describe(&self, unit: Unit) -> String {
        let bounds = self.bounds();
        let text = if bounds.is_empty() {
            format!("finite {}", unit.symbol())
        } else {
            format!("finite, {bounds} {}", unit.symbol())
        };
        text.trim_end().to_string()
    }
}

/// The allowed range of each prescribed semi-axis `geometry.semi_axes` [m].
pub const SEMI_AXIS_RANGE: Range = Range::closed(1e-6, 1.0);

/// Units of the parameters and inputs (SI, kelvin).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unit {
    /// Dimensionless.
    One,
    /// A number of grid cells.
    Cells,
    /// 1/m.
    PerMetre,
    /// m.
    Metre,
    /// m/s.
    MetrePerSecond,
    /// s/m.
    SecondPerMetre,
    /// N.
    Newton,
    /// Pa.
    Pascal,
    /// Pa·s.
    PascalSecond,
    /// K.
    Kelvin,
    /// 1/K.
    PerKelvin,
    /// W/(m·K).
    WattPerMetreKelvin,
    /// kg/m³.
    KilogramPerCubicMetre,
    /// J/(kg·K).
    JoulePerKilogramKelvin,
}

impl Unit {
    /// The FMI unit name (`modelDescription.xml`'s `UnitDefinitions`).
    pub const fn fmi(self) -> &'static str {
        match self {
            Unit::One | Unit::Cells => "1",
            Unit::PerMetre => "1/m",
            Unit::Metre => "m",
            Unit::MetrePerSecond => "m/s",
            Unit::SecondPerMetre => "s/m",
            Unit::Newton => "N",
            Unit::Pascal => "Pa",
            Unit::PascalSecond => "Pa.s",
            Unit::Kelvin => "K",
            Unit::PerKelvin => "1/K",
            Unit::WattPerMetreKelvin => "W/(m.K)",
            Unit::KilogramPerCubicMetre => "kg/m3",
            Unit::JoulePerKilogramKelvin => "J/(kg.K)",
        }
    }

    /// The unit as messages and tables show it (ASCII; empty when dimensionless).
    pub const fn symbol(self) -> &'static str {
        match self {
            Unit::One => "",
            Unit::Cells => "cells",
            Unit::PerMetre => "1/m",
            Unit::Metre => "m",
            Unit::MetrePerSecond => "m/s",
            Unit::SecondPerMetre => "s/m",
            Unit::Newton => "N",
            Unit::Pascal => "Pa",
            Unit::PascalSecond => "Pa s",
            Unit::Kelvin => "K",
            Unit::PerKelvin => "1/K",
            Unit::WattPerMetreKelvin => "W/(m K)",
            Unit::KilogramPerCubicMetre => "kg/m^3",
            Unit::JoulePerKilogramKelvin => "J/(kg K)",
        }
    }
}

/// How the FMU exposes a parameter or input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fmu {
    /// The FMU variable's name.
    pub name: &'static str,
    /// Its value reference (a contract of the FMU: never reused or changed).
    pub value_reference: u32,
}

/// A parameter or operating-point input, as errors name it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Key {
    /// A scalar parameter of [`Params`].
    Param(Param),
    /// An input of [`OperatingPoint`].
    Input(Input),
    /// The prescribed semi-axis a along x, `geometry.semi_axes[0]`.
    SemiAxisA,
    /// The prescribed semi-axis b along y, `geometry.semi_axes[1]`.
    SemiAxisB,
}

impl Key {
    /// The specification row of a scalar parameter or input (None for the semi-axes).
    pub const fn spec(self) -> Option<&'static Spec> {
        match self {
            Key::Param(p) => Some(p.spec()),
            Key::Input(i) => Some(i.spec()),
            Key::SemiAxisA | Key::SemiAxisB => None,
        }
    }
}

/// The name as the user spells it: the TOML key of a parameter, the command-line flag of an input.
impl std::fmt::Display for Key {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Key::Param(p) => f.write_str(p.spec().toml),
            Key::Input(i) => f.write_str(i.spec().cli.unwrap_or(i.spec().toml)),
            Key::SemiAxisA => f.write_str("geometry.semi_axes[0]"),
            Key::SemiAxisB => f.write_str("geometry.semi_axes[1]"),
        }
    }
}

impl Key {
    /// The error for a `value` of this key outside the `allowed` values (as text, with the unit).
    pub fn invalid(self, value: f64, allowed: String) -> Error {
        Error::Invalid {
            key: self,
            value,
            allowed,
        }
    }
}

/// One row of the specification.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spec {
    /// The row's key.
    pub key: Key,
    /// The TOML key of a parameter (`roughness.k_r`), the field name of an input (`creepage_x`).
    pub toml: &'static str,
    /// Unit.
    pub unit: Unit,
    /// Allowed values.
    pub range: Range,
    /// Default value (the one source of the `Default` impls).
    pub default: f64,
    /// Whether the field is a whole number (`usize`): [`Params::set`] truncates toward zero.
    pub integer: bool,
    /// The command-line flag without its leading `--` (`k-wet`), if there is one.
    pub cli: Option<&'static str>,
    /// The FMU variable, if the FMU exposes the value.
    pub fmu: Option<Fmu>,
    /// What the value means, with its symbol and the `docs/model.md` section (ASCII: it is also the FMU
    /// variable's description).
    pub description: &'static str,
}

impl Spec {
    /// The allowed values as errors state them (`finite, 0 ..= 1`).
    pub fn allowed(&self) -> String {
        self.range.describe(self.unit)
    }

    /// Checks `value` against the range; the error carries the key.
    pub fn check(&self, value: f64) -> Result<()> {
        if self.range.contains(value) {
            Ok(())
        } else {
            Err(self.key.invalid(value, self.allowed()))
        }
    }
}

/// Every row: the parameters, then the operating-point inputs.
pub fn specs() -> impl Iterator<Item = &'static Spec> {
    PARAMS.iter().chain(INPUTS.iter())
}

/// A field type that a row can hold: `f64` or `usize`.
trait Scalar: Copy {
    /// Whether the type holds whole numbers only.
    const INTEGER: bool;
    fn to_f64(self) -> f64;
    fn from_f64(x: f64) -> Self;
}

impl Scalar for f64 {
    const INTEGER: bool = false;
    fn to_f64(self) -> f64 {
        self
    }
    fn from_f64(x: f64) -> f64 {
        x
    }
}

impl Scalar for usize {
    const INTEGER: bool = true;
    fn to_f64(self) -> f64 {
        self as f64
    }
    /// Truncates toward zero; negative values and NaN give 0 (which every integer row's range rejects).
    fn from_f64(x: f64) -> usize {
        x as usize
    }
}

/// Whether the field a getter reads is a whole number.
const fn is_integer<T: Scalar, S>(_: fn(&S) -> T) -> bool {
    T::INTEGER
}

/// The key enum, its rows and the typed getter and setter of one target struct.
macro_rules! spec_table {
    (
        $(#[$meta:meta])*
        enum $Enum:ident of $Target:ident in $TABLE:ident as $wrap:path;
        $(
            $Variant:ident: $($field:ident).+ {
                toml: $toml:literal,
                unit: $unit:ident,
                range: $range:expr,
                default: $default:expr,
                cli: $cli:expr,
                fmu: $fmu:expr,
                $description:literal $(,)?
            }
        )*
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $Enum {
            $(
                #[doc = $description]
                $Variant,
            )*
        }

        impl $Enum {
            /// Every row, in table order (the order of validation).
            pub const ALL: [$Enum; [$(stringify!($Variant)),*].len()] = [$($Enum::$Variant),*];

            /// The specification row.
            pub const fn spec(self) -> &'static Spec {
                &$TABLE[self as usize]
            }

            /// The default value.
            pub const fn default_value(self) -> f64 {
                self.spec().default
            }
        }

        static $TABLE: [Spec; $Enum::ALL.len()] = [$(
            Spec {
                key: $wrap($Enum::$Variant),
                toml: $toml,
                unit: Unit::$unit,
                range: $range,
                default: $default,
                integer: is_integer(|t: &$Target| t.$($field).+),
                cli: $cli,
                fmu: $fmu,
                description: $description,
            },
        )*];

        impl $Target {
            #[doc = concat!("The value of a [`", stringify!($Enum), "`] row.")]
            pub fn get(&self, key: $Enum) -> f64 {
                match key {
                    $($Enum::$Variant => Scalar::to_f64(self.$($field).+),)*
                }
            }

            #[doc = concat!("Sets a [`", stringify!($Enum), "`] row (not validated; whole-number rows truncate).")]
            pub fn set(&mut self, key: $Enum, value: f64) {
                match key {
                    $($Enum::$Variant => self.$($field).+ = Scalar::from_f64(value),)*
                }
            }
        }
    };
}

/// An FMU exposure.
const fn fmu(name: &'static str, value_reference: u32) -> Option<Fmu> {
    Some(Fmu {
        name,
        value_reference,
    })
}

spec_table! {
    /// A scalar parameter of [`Params`]: its row in the specification ([`Param::spec`]).
    enum Param of Params in PARAMS as Key::Param;

    CurvatureX: geometry.curvature_x {
        toml: "geometry.curvature_x", unit: PerMetre, range: Range::closed(1e-3, 1e3), default: 1.015,
        cli: None, fmu: fmu("curvature_longitudinal", 15),
        "Gap curvature A = (1/R_wx + 1/R_rx)/2 along the rolling direction x (Hertz, docs/model.md §2)",
    }
    CurvatureY: geometry.curvature_y {
        toml: "geometry.curvature_y", unit: PerMetre, range: Range::closed(1e-3, 1e3), default: 0.4215,
        cli: None, fmu: fmu("curvature_lateral", 16),
        "Gap curvature B = (1/R_wy + 1/R_ry)/2 along y (Hertz, docs/model.md §2)",
    }
    YoungsModulus: material.youngs_modulus {
        toml: "material.youngs_modulus", unit: Pascal, range: Range::closed(1e9, 1e12), default: 210e9,
        cli: None, fmu: None,
        "Young's modulus E of wheel and rail at the reference temperature (docs/model.md §3)",
    }
    YoungsSlope: material.youngs_slope {
        toml: "material.youngs_slope", unit: PerKelvin, range: Range::closed(0.0, 1e-2), default: 4.0e-4,
        cli: None, fmu: None,
        "Relative fall of E per kelvin above the reference temperature (docs/model.md §3)",
    }
    YoungsFloor: material.youngs_floor {
        toml: "material.youngs_floor", unit: One, range: Range::closed(1e-3, 1.0), default: 0.1,
        cli: None, fmu: None,
        "Lower bound of E(T)/E(T_ref) (docs/model.md §3)",
    }
    Poisson: material.poisson {
        toml: "material.poisson", unit: One, range: Range::closed(0.0, 0.5), default: 0.28,
        cli: None, fmu: None,
        "Poisson's ratio nu of wheel and rail (docs/model.md §3)",
    }
    YieldStress: material.yield_stress {
        toml: "material.yield_stress", unit: Pascal, range: Range::closed(1e6, 1e10), default: 600e6,
        cli: None, fmu: None,
        "Bulk yield stress sigma_y at the reference temperature (docs/model.md §3)",
    }
    YieldSpan: material.yield_span {
        toml: "material.yield_span", unit: Kelvin, range: Range::closed(1.0, 1e5), default: 975.0,
        cli: None, fmu: None,
        "Temperature span over which sigma_y falls linearly to zero (docs/model.md §3)",
    }
    YieldFloor: material.yield_floor {
        toml: "material.yield_floor", unit: One, range: Range::closed(1e-3, 1.0), default: 0.05,
        cli: None, fmu: None,
        "Lower bound of the linear sigma_y factor (docs/model.md §3)",
    }
    AnomalyAmplitude: material.anomaly_amplitude {
        toml: "material.anomaly_amplitude", unit: One, range: Range::closed(0.0, 10.0), default: 0.3,
        cli: None, fmu: None,
        "Relative height of the yield-stress anomaly bump, dynamic strain ageing (docs/model.md §3)",
    }
    AnomalyTemperature: material.anomaly_temperature {
        toml: "material.anomaly_temperature", unit: Kelvin, range: Range::closed(0.0, 5000.0),
        default: 450.0 + CELSIUS_ZERO, cli: None, fmu: None,
        "Temperature of the yield-stress anomaly's peak (docs/model.md §3)",
    }
    AnomalyWidth: material.anomaly_width {
        toml: "material.anomaly_width", unit: Kelvin, range: Range::closed(1e-3, 1e4), default: 80.0,
        cli: None, fmu: None,
        "Width of the yield-stress anomaly's Gaussian bump (docs/model.md §3)",
    }
    Hardness: material.hardness {
        toml: "material.hardness", unit: Pascal, range: Range::closed(1e7, 1e11), default: 4e9,
        cli: None, fmu: None,
        "Asperity hardness H at the reference temperature (docs/model.md §3)",
    }
    HardnessSpan: material.hardness_span {
        toml: "material.hardness_span", unit: Kelvin, range: Range::closed(1.0, 1e5), default: 1200.0,
        cli: None, fmu: None,
        "Temperature span over which H falls linearly to zero (docs/model.md §3)",
    }
    HardnessFloor: material.hardness_floor {
        toml: "material.hardness_floor", unit: One, range: Range::closed(1e-3, 1.0), default: 0.05,
        cli: None, fmu: None,
        "Lower bound of H(T)/H(T_ref) (docs/model.md §3)",
    }
    ReferenceTemperature: material.reference_temperature {
        toml: "material.reference_temperature", unit: Kelvin, range: Range::closed(1.0, 2000.0),
        default: 20.0 + CELSIUS_ZERO, cli: None, fmu: None,
        "Reference temperature T_ref of the material curves, 20 C (docs/model.md §3)",
    }
    Conductivity: material.conductivity {
        toml: "material.conductivity", unit: WattPerMetreKelvin, range: Range::POSITIVE, default: 50.0,
        cli: None, fmu: None,
        "Thermal conductivity lambda of wheel and rail (docs/model.md §7)",
    }
    Density: material.density {
        toml: "material.density", unit: KilogramPerCubicMetre, range: Range::POSITIVE, default: 7850.0,
        cli: None, fmu: None,
        "Density rho of wheel and rail (docs/model.md §7)",
    }
    SpecificHeat: material.specific_heat {
        toml: "material.specific_heat", unit: JoulePerKilogramKelvin, range: Range::POSITIVE,
        default: 450.0, cli: None, fmu: None,
        "Specific heat c of wheel and rail (docs/model.md §7)",
    }
    BulkTemperature: material.bulk_temperature {
        toml: "material.bulk_temperature", unit: Kelvin, range: Range::closed(1.0, 2000.0),
        default: 20.0 + CELSIUS_ZERO, cli: Some("bulk-temperature"), fmu: fmu("bulk_temperature", 17),
        "Bulk temperature T0 of wheel and rail (docs/model.md §7)",
    }
    RoughnessKr: roughness.k_r {
        toml: "roughness.k_r", unit: One, range: Range::closed(0.0, 1.0), default: 0.5,
        cli: Some("roughness"), fmu: fmu("roughness", 14),
        "Surface roughness parameter k_r: 0 smooth, 1 rough (docs/model.md §4)",
    }
    ZsSmooth: roughness.z_s_smooth {
        toml: "roughness.z_s_smooth", unit: Metre, range: Range::POSITIVE, default: 2.5e-6,
        cli: None, fmu: None,
        "Standard deviation of asperity heights z_s at k_r = 0, project default (docs/model.md §4, docs/calibration.md)",
    }
    ZsSpan: roughness.z_s_span {
        toml: "roughness.z_s_span", unit: Metre, range: Range::closed(0.0, 1e-3), default: 5.0e-6,
        cli: None, fmu: None,
        "Increase of z_s from k_r = 0 to k_r = 1 (docs/model.md §4)",
    }
    RatioSmooth: roughness.ratio_smooth {
        toml: "roughness.ratio_smooth", unit: One, range: Range::closed(1e-7, 1.0), default: 3e-4,
        cli: None, fmu: None,
        "Ratio z_s/R_a of height deviation to summit radius at k_r = 0 (docs/model.md §4)",
    }
    RatioSpan: roughness.ratio_span {
        toml: "roughness.ratio_span", unit: One, range: Range::closed(0.0, 1.0), default: 9e-4,
        cli: None, fmu: None,
        "Increase of z_s/R_a from k_r = 0 to k_r = 1 (docs/model.md §4)",
    }
    Beta: roughness.beta {
        toml: "roughness.beta", unit: One, range: Range::closed(1e-4, 10.0), default: 0.12,
        cli: None, fmu: None,
        "Greenwood-Williamson parameter beta = eta_s R_a z_s (docs/model.md §4)",
    }
    KDry: friction.k_dry {
        toml: "friction.k_dry", unit: One, range: Range::closed(0.0, 10.0), default: 1.0,
        cli: None, fmu: None,
        "Failure-stress factor k in tau_m = k sigma_y for dry metallic contact, paper eq. P3 (docs/model.md §5)",
    }
    Mu: friction.mu {
        toml: "friction.mu", unit: One, range: Range::closed(0.0, 10.0), default: 0.4,
        cli: Some("mu"), fmu: None,
        "Friction coefficient of the constant law (friction.law = \"constant\")",
    }
    PolachMu0: friction.polach.mu0 {
        toml: "friction.polach.mu0", unit: One, range: Range::closed(0.0, 10.0), default: 0.55,
        cli: None, fmu: None,
        "Polach: maximum friction coefficient mu0 at zero slip velocity (docs/model.md §12)",
    }
    PolachARatio: friction.polach.a_ratio {
        toml: "friction.polach.a_ratio", unit: One, range: Range::closed(0.0, 10.0), default: 0.4,
        cli: None, fmu: None,
        "Polach: ratio A of the limit friction at infinite slip velocity to mu0 (docs/model.md §12)",
    }
    PolachBRate: friction.polach.b_rate {
        toml: "friction.polach.b_rate", unit: SecondPerMetre, range: Range::closed(0.0, 1e3), default: 0.6,
        cli: None, fmu: None,
        "Polach: exponential friction decrease rate B (docs/model.md §12)",
    }
    PolachKA: friction.polach.k_a {
        toml: "friction.polach.k_a", unit: One, range: Range::closed(0.0, 10.0), default: 1.0,
        cli: None, fmu: None,
        "Polach: reduction factor k_A in the area of adhesion (docs/model.md §12)",
    }
    PolachKS: friction.polach.k_s {
        toml: "friction.polach.k_s", unit: One, range: Range::closed(0.0, 10.0), default: 0.4,
        cli: None, fmu: None,
        "Polach: reduction factor k_S in the area of slip (docs/model.md §12)",
    }
    FlowResistance: fluid.flow_resistance {
        toml: "fluid.flow_resistance", unit: PascalSecond, range: Range::POSITIVE, default: 0.012,
        cli: Some("flow-resistance"), fmu: fmu("flow_resistance", 19),
        "Fluid flow-resistance factor xi_f, 12 x viscosity for a Newtonian fluid (water: 0.012; docs/model.md §8)",
    }
    KWet: fluid.k_wet {
        toml: "fluid.k_wet", unit: One, range: Range::closed(0.0, 10.0), default: 0.4,
        cli: Some("k-wet"), fmu: fmu("k_wet", 18),
        "Failure-stress factor k under boundary lubrication (paper Table 1; docs/model.md §8)",
    }
    PsiB: fluid.psi_b {
        toml: "fluid.psi_b", unit: One, range: Range::closed(0.5, 1.0 - 1e-15), default: 0.9995,
        cli: Some("psi-b"), fmu: fmu("psi_b", 20),
        "Probability psi_b of asperity occurrence at the cell base height (paper Table 1; docs/model.md §8)",
    }
    HFMax: fluid.h_f_max {
        toml: "fluid.h_f_max", unit: Metre, range: Range::closed(0.0, 1e-2), default: 20e-6,
        cli: Some("h-f-max"), fmu: fmu("h_f_max", 21),
        "Inlet fluid film height h_f,max at wetness 1 (docs/model.md §8)",
    }
    HBl: fluid.h_bl {
        toml: "fluid.h_bl", unit: Metre, range: Range::POSITIVE, default: 0.1e-6,
        cli: Some("h-bl"), fmu: None,
        "Fluid height h_bl over which k blends from k_dry to k_wet (docs/model.md §8)",
    }
    LayerThickness: layer.thickness {
        toml: "layer.thickness", unit: Metre, range: Range::closed(0.0, 1e-2), default: 0.0,
        cli: Some("layer-thickness"), fmu: fmu("layer_thickness", 35),
        "Thickness h of the interfacial (third-body) layer, whose shear h tau/G_3 adds to the tangential displacement; 0: no layer (docs/model.md §6.7)",
    }
    LayerShearModulus: layer.shear_modulus {
        toml: "layer.shear_modulus", unit: Pascal, range: Range::closed(1e6, 1e12), default: 8.2e9,
        cli: Some("layer-shear-modulus"), fmu: fmu("layer_shear_modulus", 36),
        "Shear modulus G_3 of the interfacial layer (docs/model.md §6.7)",
    }
    GridNx: grid.nx {
        toml: "grid.nx", unit: Cells, range: Range::closed(4.0, 400.0), default: 30.0,
        cli: None, fmu: None,
        "Grid cells along x over [-a, a] (docs/model.md §2)",
    }
    GridNy: grid.ny {
        toml: "grid.ny", unit: Cells, range: Range::closed(4.0, 400.0), default: 30.0,
        cli: None, fmu: None,
        "Grid cells along y over [-b, b] (docs/model.md §2)",
    }
    GridAccuracy: grid.accuracy {
        toml: "grid.accuracy", unit: One, range: Range::closed(0.0, 0.1), default: 0.0,
        cli: Some("grid-accuracy"), fmu: fmu("grid_accuracy", 34),
        "Target discretisation error |dF|/F_N of the forces: > 0 chooses n x n cells from the measured grid convergence (docs/model.md §6.4) instead of the set grid; 0 keeps the set grid",
    }
    Tolerance: solver.tolerance {
        toml: "solver.tolerance", unit: One, range: Range::closed(1e-14, 1e-1), default: 1e-6,
        cli: None, fmu: None,
        "Convergence tolerance of the coupled iteration on the relative change of the adhesion limit and temperature (docs/model.md §9)",
    }
    MaxIterations: solver.max_iterations {
        toml: "solver.max_iterations", unit: One, range: Range::closed(1.0, 1e6), default: 200.0,
        cli: None, fmu: None,
        "Maximum number of outer iterations of the coupled solver (docs/model.md §9)",
    }
    Relaxation: solver.relaxation {
        toml: "solver.relaxation", unit: One, range: Range::closed(1e-3, 1.0), default: 1.0,
        cli: None, fmu: None,
        "Initial relaxation factor of the temperature update, adapted downwards on divergence (docs/model.md §9)",
    }
    FluidTolerance: solver.fluid_tolerance {
        toml: "solver.fluid_tolerance", unit: One, range: Range::closed(1e-15, 1e-2), default: 1e-10,
        cli: None, fmu: None,
        "Convergence tolerance of the fluid film solve: largest remaining correction of the separation (in z_s) and of the fluid height (in h_f0) (docs/model.md §8)",
    }
    MaxFluidSweeps: solver.max_fluid_sweeps {
        toml: "solver.max_fluid_sweeps", unit: One, range: Range::closed(1.0, 1e7), default: 20_000.0,
        cli: None, fmu: None,
        "Iteration limit of the fluid film solve: Newton iterations plus any Gauss-Seidel fallback sweeps (docs/model.md §8)",
    }
}

spec_table! {
    /// An input of [`OperatingPoint`]: its row in the specification ([`Input::spec`]). Surface speeds
    /// V (1 +- xi/2) must stay positive, hence |xi|, |eta| < 2.
    enum Input of OperatingPoint in INPUTS as Key::Input;

    CreepageX: creepage_x {
        toml: "creepage_x", unit: One, range: Range::closed(-1.9, 1.9), default: 0.0,
        cli: Some("creepage-x"), fmu: fmu("creepage_longitudinal", 0),
        "Longitudinal creepage xi (docs/model.md §1)",
    }
    CreepageY: creepage_y {
        toml: "creepage_y", unit: One, range: Range::closed(-1.9, 1.9), default: 0.0,
        cli: Some("creepage-y"), fmu: fmu("creepage_lateral", 1),
        "Lateral creepage eta (docs/model.md §1)",
    }
    Spin: spin {
        toml: "spin", unit: PerMetre, range: Range::closed(-1e4, 1e4), default: 0.0,
        cli: Some("spin"), fmu: fmu("spin_creepage", 2),
        "Spin creepage phi (docs/model.md §1)",
    }
    NormalForce: normal_force {
        toml: "normal_force", unit: Newton, range: Range::closed(1e-3, 1e8), default: 100e3,
        cli: Some("normal-force"), fmu: fmu("normal_force", 3),
        "Normal force F_N (docs/model.md §2)",
    }
    Speed: speed {
        toml: "speed", unit: MetrePerSecond, range: Range::closed(1e-6, 1e3), default: 30.0,
        cli: Some("speed"), fmu: fmu("rolling_speed", 4),
        "Rolling speed V (docs/model.md §1)",
    }
    Wetness: wetness {
        toml: "wetness", unit: One, range: Range::closed(0.0, 1.0), default: 0.0,
        cli: Some("wetness"), fmu: fmu("wetness", 5),
        "Wetness w: 0 dry, 1 inlet film height h_f,max (docs/model.md §8)",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn names_flags_and_value_references_are_unique_and_defaults_valid() {
        // TOML keys, flags, FMU names and value references: each unique in its namespace
        let mut seen: [HashSet<String>; 4] = Default::default();
        for s in specs() {
            assert!(seen[0].insert(s.toml.into()), "{}", s.toml);
            if let Some(c) = s.cli {
                assert!(seen[1].insert(c.into()), "flag {c}");
            }
            if let Some(f) = s.fmu {
                assert!(seen[2].insert(f.name.into()), "FMU name {}", f.name);
                assert!(seen[3].insert(f.value_reference.to_string()), "{}", f.name);
            }
            s.check(s.default).unwrap();
            assert!(!s.range.contains(f64::NAN) && !s.range.contains(f64::INFINITY));
            // ASCII but for the section sign: the text is also an FMU variable's description
            assert!(s.description.chars().all(|c| c.is_ascii() || c == '§'));
            assert_eq!(s.key.spec(), Some(s), "{}", s.toml);
            // an integer row's bounds and default are whole numbers
            if s.integer {
                assert_eq!(s.default.fract(), 0.0, "{}", s.toml);
            }
        }
        for i in Input::ALL {
            assert!(i.spec().cli.is_some() && i.spec().fmu.is_some(), "{i:?}");
        }
        assert!(Param::GridNx.spec().integer && !Param::RoughnessKr.spec().integer);
    }

    #[test]
    fn ranges_describe_themselves_as_errors_did() {
        assert_eq!(
            Range::closed(0.0, 1.0).describe(Unit::One),
            "finite, 0 ..= 1"
        );
        assert_eq!(
            Range::POSITIVE.describe(Unit::PascalSecond),
            "finite, > 0 Pa s"
        );
        let half_open = Range {
            lo: Bound::Closed(0.0),
            hi: Bound::Open(1.0),
        };
        assert_eq!(half_open.describe(Unit::Metre), "finite, >= 0 and < 1 m");
        assert!(half_open.contains(0.0) && !half_open.contains(1.0));
        let free = Range {
            lo: Bound::Unbounded,
            hi: Bound::Unbounded,
        };
        assert_eq!(free.describe(Unit::One), "finite");
        assert!(free.contains(-1e300) && !free.contains(f64::NEG_INFINITY));
        assert!(!Range::POSITIVE.contains(0.0) && Range::POSITIVE.contains(1e-300));
        assert_eq!(
            Param::PsiB.spec().allowed(),
            "finite, 0.5 ..= 0.999999999999999"
        );
    }
}
