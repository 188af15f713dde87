//! The eight axes of a table: the creepages ξ, η, φ, the normal force F_N, the speed V, the wetness w and
//! the contact geometry (ellipse ratio a/b, reference pressure p_ref), their points and how they are
//! generated.
//!
//! **Creepage coordinates** are normalised by Kalker's linear theory (docs/model.md §6): the coordinate of
//! ξ is ξ̂ = k_x·ξ, the traction coefficient F_x/F_N that the linear theory would give, with
//! k_x = G·c²·C11/F_N = 3·G·C11/(2π·p0); likewise η̂ = k_y·η (C22) and φ̂ = k_φ·φ, k_φ = 3·G·C23·c/(2π·p0),
//! c = sqrt(a·b). In these coordinates the creep curves of contacts of any size, shape and pressure nearly
//! coincide up to saturation (they differ by the local friction, which depends on the pressure, and by the
//! temperature), so one set of points serves every geometry. Each creepage axis also has a **raw limit**:
//! the largest |ξ|, |η|, |φ| the table serves (points beyond are outside its range whatever their
//! normalised coordinate). Tables of format version 1 have raw creepage axes (no normalisation) and a
//! single geometry.
//!
//! **Geometry coordinates**: a/b of the contact ellipse, and p_ref = p0·(F_ref/F_N)^(1/3), the Hertz peak
//! pressure the contact would have at the reference load F_ref (a contact of fixed curvatures keeps its
//! p_ref at every load, since a, b ∝ F_N^(1/3)); p0 = 3·F_N/(2π·a·b). A geometry axis with a single point
//! is a table of that geometry only.
//!
//! Creepage axes are interpolated by cubic Hermite splines, the others linearly (see `interp.rs`). A
//! **mirrored** creepage axis stores only values ≥ 0 and starts at 0; the negative half follows from a
//! symmetry of the model, which pairs the creepage with the spin:
//!
//! - η (always mirrored, exact): mirroring the contact in y maps (η, φ) → (−η, −φ) and
//!   (F_x, F_y, M_z) → (F_x, −F_y, −M_z); temperature and fluid load are unchanged.
//! - ξ (mirrored by default, approximate): ξ → −ξ (η, φ unchanged) maps (F_x, F_y, M_z) → (−F_x, F_y, M_z):
//!   it is the y-mirror composed with the reversal of all creepages, under which FASTSIM's traction field
//!   changes sign. Exact for the dry model (wheel and rail of the same steel swap their surface speeds
//!   V(1 ± ξ/2)); with fluid the film enters at the rail speed V(1 − ξ/2): within 1e-3·F_N deep in the film,
//!   but up to about 1e-2·F_N (and 17 K) at the onset of boundary lubrication in full slip (w ≈ 0.003,
//!   ξ ≈ 0.09; `cli/tests/table.rs` measures both), the size of the whole interpolation budget. Tables for
//!   wet running therefore store both signs of ξ (`mirrored = false`, e.g. `tools/running-surface-axes.toml`).
//!
//! The η mirror needs a spin axis symmetric about 0. Generated points are computed with `libm`, so every
//! platform produces the same bits (shards built on different machines merge).

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// Number of table dimensions.
pub const DIMS: usize = 8;

/// Number of linearly interpolated dimensions (F_N, V, w, a/b, p_ref).
pub const LINEAR_DIMS: usize = DIMS - 3;

/// The reference load F_ref of the reference pressure p_ref [N].
pub const REFERENCE_FORCE: f64 = 100e3;

/// Interpolation along one axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Interpolation {
    /// C¹ cubic Hermite spline with three-point (parabola) node derivatives on the non-uniform points.
    Cubic,
    /// Piecewise linear.
    Linear,
    /// Piecewise linear in ln x (all points > 0): exact for data linear in the logarithm; measured the
    /// better interpolant for the load (the contact grows like F_N^(1/3)), the ellipse ratio and the
    /// reference pressure, whose points are log-spaced (docs/model.md §12.3).
    Log,
}

/// What one dimension is: name (as in [`crate::OperatingPoint`]), symbol, unit, interpolation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dimension {
    /// Field name of the operating point.
    pub name: &'static str,
    /// Symbol.
    pub symbol: &'static str,
    /// SI unit.
    pub unit: &'static str,
    /// Interpolation along the axis.
    pub interpolation: Interpolation,
}

/// The dimensions in storage order (slowest first): ξ, η, φ, F_N, V, w, a/b, p_ref. The creepage axes
/// hold normalised coordinates (see the module documentation) in the unit of the normalisation, the
/// traction coefficient (format version 1: raw creepages, unit as named).
pub const DIMENSIONS: [Dimension; DIMS] = [
    Dimension {
        name: "creepage_x",
        symbol: "ξ",
        unit: "-",
        interpolation: Interpolation::Cubic,
    },
    Dimension {
        name: "creepage_y",
        symbol: "η",
        unit: "-",
        interpolation: Interpolation::Cubic,
    },
    Dimension {
        name: "spin",
        symbol: "φ",
        unit: "1/m",
        interpolation: Interpolation::Cubic,
    },
    Dimension {
        name: "normal_force",
        symbol: "F_N",
        unit: "N",
        interpolation: Interpolation::Linear,
    },
    Dimension {
        name: "speed",
        symbol: "V",
        unit: "m/s",
        interpolation: Interpolation::Linear,
    },
    Dimension {
        name: "wetness",
        symbol: "w",
        unit: "-",
        interpolation: Interpolation::Linear,
    },
    Dimension {
        name: "semi_axis_ratio",
        symbol: "a/b",
        unit: "-",
        interpolation: Interpolation::Linear,
    },
    Dimension {
        name: "reference_pressure",
        symbol: "p_ref",
        unit: "Pa",
        interpolation: Interpolation::Linear,
    },
];

/// Index of ξ.
pub const XI: usize = 0;
/// Index of η.
pub const ETA: usize = 1;
/// Index of φ.
pub const PHI: usize = 2;
/// Index of F_N.
pub const FORCE: usize = 3;
/// Index of V.
pub const SPEED: usize = 4;
/// Index of w.
pub const WET: usize = 5;
/// Index of a/b.
pub const RATIO: usize = 6;
/// Index of p_ref.
pub const PRESSURE: usize = 7;

/// The points of one axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// Strictly increasing points, in the axis' unit.
    pub points: Vec<f64>,
    /// Only values ≥ 0 are stored (first point 0); the negative half follows by symmetry.
    pub mirrored: bool,
    /// Normalised creepage axes: the largest raw |creepage| served (ξ, η [-], φ [1/m]); None for raw
    /// creepage axes (format version 1) and the other dimensions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raw_limit: Option<f64>,
    /// Normalised creepage axes: the raw scale k_r of knee-blended coordinates (see `coords`), None for
    /// ξ̂ = k·ξ [-, -, m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raw_scale: Option<f64>,
    /// The spin axis of knee-blended coordinates: the contact size L_r [m] at which the raw scale is
    /// `raw_scale`; a contact of size L = sqrt(a² + b²) takes k_r·L/L_r, so that the raw part of the
    /// coordinate measures the spin's slip φ·L at the contact's edge (see `coords`). None: k_r for every
    /// contact.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raw_length: Option<f64>,
    /// Linear axes: interpolated linearly in ln x ([`Interpolation::Log`]) instead of x.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub logarithmic: bool,
    /// The speed axis of a table built by the model's similarity (docs/model.md §9.1): its points are
    /// equivalent speeds V·sqrt(F_N/F_ref) at the reference load F_ref, the normal force axis is F_ref
    /// alone, and the table serves every load (a contact maps to its equivalent at F_ref).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub similarity: bool,
    /// Linear axes: the point from which on the cells are interpolated linearly in √x instead of x — the
    /// speed cells where T_max rises like the flash temperature, ∝ √V (docs/model.md §12.3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sqrt_from: Option<f64>,
}

impl Axis {
    /// A linear axis of `points` (not mirrored, no creepage limits, interpolated in x).
    pub fn linear(points: Vec<f64>) -> Axis {
        Axis {
            points,
            mirrored: false,
            raw_limit: None,
            raw_scale: None,
            raw_length: None,
            logarithmic: false,
            similarity: false,
            sqrt_from: None,
        }
    }

    /// Whether cell `i` (between points i and i + 1) is interpolated linearly in √x ([`Axis::sqrt_from`]).
    pub fn cell_in_sqrt(&self, i: usize) -> bool {
        self.sqrt_from.is_some_and(|x0| self.points[i] >= x0)
    }

    /// How the axis of dimension `dim` is interpolated: the dimension's kind, or [`Interpolation::Log`] for
    /// a logarithmic linear axis.
    pub fn interpolation(&self, dim: usize) -> Interpolation {
        if self.logarithmic {
            Interpolation::Log
        } else {
            DIMENSIONS[dim].interpolation
        }
    }

    /// Smallest coordinate covered (−max for a mirrored axis).
    pub fn min(&self) -> f64 {
        if self.mirrored {
            -self.max()
        } else {
            self.points[0]
        }
    }

    /// Largest coordinate covered.
    pub fn max(&self) -> f64 {
        self.points[self.points.len() - 1]
    }
}

/// How generated points are spaced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Spacing {
    /// Uniform.
    Linear,
    /// Uniform in ln x (x > 0).
    Log,
    /// x = s·sinh(u) with u uniform: spacing ≈ s·Δu near 0, growing exponentially beyond |x| ≈ s — dense
    /// where the creep curves bend, coarse where they saturate.
    Sinh,
}

/// One axis as written in an axes file: explicit `points`, or `min`, `max`, `count`, `spacing` (and
/// `scale` for sinh). `mirrored` (creepage_x only; creepage_y is always mirrored) stores values ≥ 0 only.
/// Creepage axes are given in normalised coordinates and take `raw_limit`, the largest raw |creepage|
/// served.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisSpec {
    /// Explicit points (replace the generator).
    pub points: Option<Vec<f64>>,
    /// First point.
    pub min: Option<f64>,
    /// Last point.
    pub max: Option<f64>,
    /// Number of points.
    pub count: Option<usize>,
    /// Spacing of generated points.
    pub spacing: Option<Spacing>,
    /// Scale s of the sinh spacing, in the axis' unit.
    pub scale: Option<f64>,
    /// Whether only values ≥ 0 are stored.
    pub mirrored: Option<bool>,
    /// Creepage axes: the largest raw |creepage| served.
    pub raw_limit: Option<f64>,
    /// Creepage axes: the raw scale k_r of knee-blended coordinates (see `coords`) [-, -, m].
    pub raw_scale: Option<f64>,
    /// The spin axis with a `raw_scale`: the contact size sqrt(a² + b²) [m] the raw scale applies to;
    /// other contacts take it in proportion to their size (see `coords`).
    pub raw_length: Option<f64>,
    /// Linear axes: `"log"` interpolates linearly in ln x (points > 0), `"linear"` (the default) in x;
    /// creepage axes are always `"cubic"`.
    pub interpolation: Option<Interpolation>,
    /// The speed axis only: `true` builds the table by the model's similarity (docs/model.md §9.1): the
    /// points are equivalent speeds V·sqrt(F_N/F_ref) at F_ref = 100 kN, the normal_force axis must be
    /// `points = [100e3]`, and the table serves every load whose equivalent speed lies on the axis.
    pub similarity: Option<bool>,
    /// Linear axes (not `"log"`): one of the points, from which on the cells are interpolated linearly in
    /// √x (points > 0): the speed cells from ≈ 11 m/s on, where T_max rises like the flash temperature
    /// (docs/model.md §12.3).
    pub sqrt_from: Option<f64>,
}

/// An axes file (TOML): one optional table per dimension; a missing one takes the default axis.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxesSpec {
    /// ξ.
    pub creepage_x: Option<AxisSpec>,
    /// η.
    pub creepage_y: Option<AxisSpec>,
    /// φ.
    pub spin: Option<AxisSpec>,
    /// F_N.
    pub normal_force: Option<AxisSpec>,
    /// V.
    pub speed: Option<AxisSpec>,
    /// w.
    pub wetness: Option<AxisSpec>,
    /// a/b.
    pub semi_axis_ratio: Option<AxisSpec>,
    /// p_ref.
    pub reference_pressure: Option<AxisSpec>,
}

/// The eight axes of a table, in storage order.
#[derive(Debug, Clone, PartialEq)]
pub struct Axes(pub [Axis; DIMS]);

impl Default for Axes {
    /// The default axes (see [`default_spec`]).
    fn default() -> Self {
        Self::from_spec(&AxesSpec::default()).expect("default axes are valid")
    }
}

/// The default generator of each dimension.
///
/// - ξ̂, η̂, φ̂ (normalised, see the module documentation): sinh spacing with scale 0.25 (the linear
///   theory's traction coefficient at which the creep curves bend: they saturate at the local friction,
///   0.1–0.6), up to the normalised coordinate of the raw limit (|ξ| ≤ 0.1, |η| ≤ 0.02, |φ| ≤ 1 /m) in
///   the softest contact of the geometry range (p0 ≈ 70 MPa at 10 kN: k_x ≈ 3200, k_y ≈ 3000, k_φ ≈ 6
///   m): the log-like spacing beyond saturation keeps the count low.
/// - F_N, V: log spacing; F_N interpolated linearly in ln F_N, V in V (measured on the bundled table, 2000
///   samples: |ΔF|/F_N p99 4.1e-3 against 5.4e-3 linear in F_N, T_max p99 5.6 K against 10.4 K; V in ln V
///   as well lowers the mean force error further but doubles T_max's p99).
/// - w: dense below 0.07 where the friction falls from dry to boundary lubrication (a kink at w =
///   h_bl/h_f,max = 0.005 for the default parameters) and from the onset of mixed lubrication (w ≈
///   0.01–0.05).
/// - a/b from 0.2 (worn, conformal treads) to 5 (flange root), p_ref from 0.15 GPa (conformal) to 2.5 GPa
///   (flange root, gauge corner): log spacing, interpolated in ln x.
fn default_spec(dim: usize) -> AxisSpec {
    let gen_ = |min: f64, max: f64, count: usize, spacing: Spacing, scale: Option<f64>| AxisSpec {
        min: Some(min),
        max: Some(max),
        count: Some(count),
        spacing: Some(spacing),
        scale,
        ..Default::default()
    };
    let log = |spec: AxisSpec| AxisSpec {
        interpolation: Some(Interpolation::Log),
        ..spec
    };
    let creepage = |max: f64, count: usize, raw_limit: f64, mirrored: Option<bool>| AxisSpec {
        mirrored,
        raw_limit: Some(raw_limit),
        ..gen_(
            if mirrored.is_some() { 0.0 } else { -max },
            max,
            count,
            Spacing::Sinh,
            Some(0.25),
        )
    };
    match dim {
        XI => creepage(320.0, 14, 0.1, Some(true)),
        ETA => creepage(64.0, 10, 0.02, Some(true)),
        PHI => creepage(6.0, 13, 1.0, None),
        FORCE => log(gen_(10e3, 250e3, 5, Spacing::Log, None)),
        SPEED => gen_(1.0, 100.0, 6, Spacing::Log, None),
        WET => AxisSpec {
            points: Some(vec![
                0.0, 0.0015, 0.003, 0.005, 0.0085, 0.013, 0.02, 0.03, 0.045, 0.07, 0.11, 0.2, 0.4,
                1.0,
            ]),
            ..Default::default()
        },
        RATIO => log(gen_(0.2, 5.0, 4, Spacing::Log, None)),
        _ => log(gen_(0.15e9, 2.5e9, 5, Spacing::Log, None)),
    }
}

/// Allowed coordinate range of each dimension (what the exact solver accepts; normalised creepage axes:
/// a generous bound on the traction coefficient of the linear theory).
fn physical_range(dim: usize, normalised: bool) -> (f64, f64) {
    match dim {
        XI | ETA | PHI if normalised => (-1e5, 1e5),
        XI | ETA => (-1.9, 1.9),
        PHI => (-1e4, 1e4),
        FORCE => (1e-3, 1e8),
        SPEED => (1e-6, 1e3),
        RATIO => (0.01, 100.0),
        PRESSURE => (1e6, 1e11),
        _ => (0.0, 1.0),
    }
}

/// Allowed raw limit of a normalised creepage axis (what the exact solver accepts).
fn raw_limit_range(dim: usize) -> (f64, f64) {
    match dim {
        PHI => (0.0, 1e4),
        _ => (0.0, 1.9),
    }
}

fn bad(dim: usize, what: impl std::fmt::Display) -> Error {
    Error::ParameterFile {
        path: "<axes>".into(),
        reason: format!("axis {}: {what}", DIMENSIONS[dim].name),
    }
}

impl AxisSpec {
    /// The points this spec describes for dimension `dim`.
    fn resolve(&self, dim: usize) -> Result<Axis> {
        let mirrored = match (dim, self.mirrored) {
            (ETA, Some(false)) => {
                return Err(bad(
                    dim,
                    "is always mirrored (the y-mirror symmetry is exact)",
                ));
            }
            (ETA, _) => true,
            (XI, m) => m.unwrap_or(false),
            (_, Some(true)) => return Err(bad(dim, "only creepage axes can be mirrored")),
            _ => false,
        };
        let points = match &self.points {
            Some(p) => {
                if self.min.is_some() || self.count.is_some() || self.spacing.is_some() {
                    return Err(bad(dim, "give either points or min/max/count/spacing"));
                }
                p.clone()
            }
            None => {
                let (Some(min), Some(max), Some(count)) = (self.min, self.max, self.count) else {
                    return Err(bad(dim, "needs points, or min, max and count"));
                };
                generate(
                    dim,
                    min,
                    max,
                    count,
                    self.spacing.unwrap_or(Spacing::Linear),
                    self.scale,
                )?
            }
        };
        let raw_limit = match (dim, self.raw_limit) {
            (XI | ETA | PHI, None) => {
                return Err(bad(
                    dim,
                    "needs raw_limit, the largest raw |creepage| the table serves (its points are \
                     normalised creepages)",
                ));
            }
            (XI | ETA | PHI, limit) => limit,
            (_, Some(_)) => return Err(bad(dim, "only creepage axes take a raw_limit")),
            (_, None) => None,
        };
        let logarithmic = match (DIMENSIONS[dim].interpolation, self.interpolation) {
            (_, None) => false,
            (Interpolation::Linear, Some(Interpolation::Log)) => true,
            (kind, Some(i)) if i == kind => false,
            _ => {
                return Err(bad(
                    dim,
                    "interpolation: creepage axes are \"cubic\", the others \"linear\" or \"log\"",
                ));
            }
        };
        let similarity = self.similarity.unwrap_or(false);
        let axis = Axis {
            points,
            mirrored,
            raw_limit,
            raw_scale: self.raw_scale,
            raw_length: self.raw_length,
            logarithmic,
            similarity,
            sqrt_from: self.sqrt_from,
        };
        validate_axis(dim, &axis)?;
        Ok(axis)
    }
}

/// Generated points from `min` to `max` (both exact).
fn generate(
    dim: usize,
    min: f64,
    max: f64,
    count: usize,
    spacing: Spacing,
    scale: Option<f64>,
) -> Result<Vec<f64>> {
    if !(min.is_finite() && max.is_finite() && min < max) {
        return Err(bad(
            dim,
            format!("needs finite min < max (got {min}, {max})"),
        ));
    }
    if count < 2 {
        return Err(bad(dim, "needs at least 2 points"));
    }
    let frac = |k: usize| k as f64 / (count - 1) as f64;
    let mut p: Vec<f64> = match spacing {
        Spacing::Linear => (0..count).map(|k| min + (max - min) * frac(k)).collect(),
        Spacing::Log => {
            if min <= 0.0 {
                return Err(bad(dim, "log spacing needs min > 0"));
            }
            let (l0, l1) = (libm::log(min), libm::log(max));
            (0..count)
                .map(|k| libm::exp(l0 + (l1 - l0) * frac(k)))
                .collect()
        }
        Spacing::Sinh => {
            let s = match scale {
                Some(s) if s.is_finite() && s > 0.0 => s,
                _ => return Err(bad(dim, "sinh spacing needs a scale > 0")),
            };
            if min < 0.0 {
                // symmetric about 0: generate the positive half and mirror it exactly
                if min != -max || count.is_multiple_of(2) {
                    return Err(bad(
                        dim,
                        "sinh spacing across 0 needs min = -max and an odd count",
                    ));
                }
                let half = generate(dim, 0.0, max, count / 2 + 1, spacing, scale)?;
                let mut all: Vec<f64> = half[1..].iter().rev().map(|x| -x).collect();
                all.extend_from_slice(&half);
                return Ok(all);
            }
            let (u0, u1) = (libm::asinh(min / s), libm::asinh(max / s));
            (0..count)
                .map(|k| s * libm::sinh(u0 + (u1 - u0) * frac(k)))
                .collect()
        }
    };
    p[0] = min;
    p[count - 1] = max;
    Ok(p)
}

/// Checks one axis: enough points for its interpolation (a linear axis may have a single point: a table of
/// that value only), strictly increasing, finite, inside the physical range of the dimension; a mirrored
/// axis starts at 0; a logarithmic axis is a linear one with points > 0; `sqrt_from` is a point > 0 (not the
/// last) of a linear axis; a raw limit (creepage axes only) inside the solver's range.
fn validate_axis(dim: usize, axis: &Axis) -> Result<()> {
    let p = &axis.points;
    let needed = match (axis.interpolation(dim), axis.mirrored) {
        (Interpolation::Cubic, true) => 3,
        (Interpolation::Cubic, false) => 4,
        (Interpolation::Linear | Interpolation::Log, _) => 1,
    };
    if p.len() < needed {
        return Err(bad(
            dim,
            format!("needs at least {needed} points (has {})", p.len()),
        ));
    }
    if axis.logarithmic && (DIMENSIONS[dim].interpolation != Interpolation::Linear || p[0] <= 0.0) {
        return Err(bad(
            dim,
            "log interpolation needs a linear axis with points > 0",
        ));
    }
    if p.iter().any(|x| !x.is_finite()) || p.windows(2).any(|w| w[0] >= w[1]) {
        return Err(bad(dim, "points must be finite and strictly increasing"));
    }
    if let Some(x0) = axis.sqrt_from
        && !(axis.interpolation(dim) == Interpolation::Linear
            && x0 > 0.0
            && p[..p.len() - 1].contains(&x0))
    {
        return Err(bad(
            dim,
            format!(
                "sqrt_from {x0} must be one of the points before the last, > 0, on a linear axis (not \
                 \"log\"); the points are {p:?}"
            ),
        ));
    }
    let (lo, hi) = physical_range(dim, axis.raw_limit.is_some());
    if axis.min() < lo || axis.max() > hi {
        return Err(bad(
            dim,
            format!("points must lie in [{lo}, {hi}] {}", DIMENSIONS[dim].unit),
        ));
    }
    if axis.mirrored && p[0] != 0.0 {
        return Err(bad(dim, "a mirrored axis starts at 0"));
    }
    if let Some(k) = axis.raw_scale
        && !(axis.raw_limit.is_some() && k > 0.0 && k.is_finite())
    {
        return Err(bad(
            dim,
            format!("raw_scale {k} must be finite and > 0, on a creepage axis with a raw_limit"),
        ));
    }
    if let Some(l) = axis.raw_length
        && !(dim == PHI && axis.raw_scale.is_some() && l > 0.0 && l.is_finite())
    {
        return Err(bad(
            dim,
            format!("raw_length {l} must be finite and > 0, on the spin axis with a raw_scale"),
        ));
    }
    if let Some(limit) = axis.raw_limit {
        let (lo, hi) = raw_limit_range(dim);
        if !(limit > lo && limit <= hi && matches!(dim, XI | ETA | PHI)) {
            return Err(bad(
                dim,
                format!("raw_limit {limit} must lie in ({lo}, {hi}] (creepage axes only)"),
            ));
        }
    }
    Ok(())
}

impl Axes {
    /// The axes of an axes file's spec; missing dimensions take the defaults.
    pub fn from_spec(spec: &AxesSpec) -> Result<Axes> {
        let given = [
            &spec.creepage_x,
            &spec.creepage_y,
            &spec.spin,
            &spec.normal_force,
            &spec.speed,
            &spec.wetness,
            &spec.semi_axis_ratio,
            &spec.reference_pressure,
        ];
        let mut axes = Vec::with_capacity(DIMS);
        for (dim, g) in given.iter().enumerate() {
            let s = match g {
                Some(s) => (*s).clone(),
                None => default_spec(dim),
            };
            axes.push(s.resolve(dim)?);
        }
        let axes = Axes(axes.try_into().expect("eight axes"));
        axes.validate()?;
        Ok(axes)
    }

    /// Reads an axes file (TOML, see [`AxesSpec`]).
    pub fn from_toml_file(path: &std::path::Path) -> Result<Axes> {
        let err = |reason: String| Error::ParameterFile {
            path: path.display().to_string(),
            reason,
        };
        let text = std::fs::read_to_string(path).map_err(|e| err(e.to_string()))?;
        let spec: AxesSpec = toml::from_str(&text).map_err(|e| err(e.to_string()))?;
        Axes::from_spec(&spec).map_err(|e| match e {
            Error::ParameterFile { reason, .. } => err(reason),
            other => other,
        })
    }

    /// Checks every axis and the cross-axis rules (η mirrored; φ symmetric about 0, which the η mirror
    /// needs; the creepage axes all normalised or all raw).
    pub fn validate(&self) -> Result<()> {
        for (dim, a) in self.0.iter().enumerate() {
            validate_axis(dim, a)?;
            if a.mirrored && !matches!(dim, XI | ETA) {
                return Err(bad(dim, "only creepage axes can be mirrored"));
            }
        }
        if self.0[ETA].raw_limit.is_some() != self.normalised()
            || self.0[PHI].raw_limit.is_some() != self.normalised()
        {
            return Err(bad(
                XI,
                "the creepage axes must all be normalised (with a raw_limit) or all raw",
            ));
        }
        if !self.0[ETA].mirrored {
            return Err(bad(ETA, "must be mirrored"));
        }
        if let Some(d) = (0..DIMS).find(|d| self.0[*d].similarity && *d != SPEED) {
            return Err(bad(d, "only the speed axis takes similarity"));
        }
        if self.similarity() && (self.0[FORCE].points != [REFERENCE_FORCE] || !self.normalised()) {
            return Err(bad(
                FORCE,
                format!(
                    "a table built by similarity (speed axis similarity = true) has the one normal \
                     force point {REFERENCE_FORCE} N and normalised creepage axes"
                ),
            ));
        }
        let phi = &self.0[PHI].points;
        if phi.iter().zip(phi.iter().rev()).any(|(a, b)| *a != -*b) {
            return Err(bad(
                PHI,
                "points must be symmetric about 0 (φ_k = -φ_(n-1-k)) for the η mirror",
            ));
        }
        Ok(())
    }

    /// Whether the creepage axes are normalised by Kalker's linear theory (format version 1: raw).
    pub fn normalised(&self) -> bool {
        self.0[XI].raw_limit.is_some()
    }

    /// Whether the table is built by the model's similarity (docs/model.md §9.1): the speed axis holds
    /// equivalent speeds at the reference load, which is the one normal force point.
    pub fn similarity(&self) -> bool {
        self.0[SPEED].similarity
    }

    /// Stored points per dimension.
    pub fn shape(&self) -> [usize; DIMS] {
        std::array::from_fn(|d| self.0[d].points.len())
    }

    /// Total number of stored points.
    pub fn len(&self) -> usize {
        self.shape().iter().product()
    }

    /// Always false: every axis has points.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The coordinates of the stored point with flat (C-order) index `flat`.
    pub fn coordinates(&self, flat: usize) -> [f64; DIMS] {
        let shape = self.shape();
        let mut rest = flat;
        let mut idx = [0usize; DIMS];
        for d in (0..DIMS).rev() {
            idx[d] = rest % shape[d];
            rest /= shape[d];
        }
        std::array::from_fn(|d| self.0[d].points[idx[d]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Params;
    use crate::table::coords::{Coordinates, Ellipse, semi_axes};

    #[test]
    fn default_axes_cover_the_issue_ranges() {
        let a = Axes::default();
        // normalised creepages, then F_N, V, w, a/b, p_ref
        let want = [
            (-320.0, 320.0),
            (-64.0, 64.0),
            (-6.0, 6.0),
            (10e3, 250e3),
            (1.0, 100.0),
            (0.0, 1.0),
            (0.2, 5.0),
            (0.15e9, 2.5e9),
        ];
        for (d, (lo, hi)) in want.iter().enumerate() {
            assert_eq!((a.0[d].min(), a.0[d].max()), (*lo, *hi), "{}", d);
        }
        let limits: Vec<_> = a.0.iter().map(|x| x.raw_limit).collect();
        assert_eq!(limits[..3], [Some(0.1), Some(0.02), Some(1.0)]);
        assert!(limits[3..].iter().all(Option::is_none));
        assert!(a.normalised());
        a.validate().unwrap();
    }

    #[test]
    fn sinh_spacing_is_dense_near_zero_and_symmetric() {
        let p = generate(PHI, -1.0, 1.0, 9, Spacing::Sinh, Some(0.1)).unwrap();
        assert_eq!(p.len(), 9);
        assert_eq!(p[4], 0.0);
        for k in 0..9 {
            assert_eq!(p[k], -p[8 - k]);
        }
        // spacing grows monotonically away from 0
        let h: Vec<f64> = p[4..].windows(2).map(|w| w[1] - w[0]).collect();
        assert!(h.windows(2).all(|w| w[1] > w[0]), "{h:?}");
        // near 0 the step is about s·Δu with Δu = asinh(10)/4
        assert!((h[0] - 0.1 * (libm::asinh(10.0) / 4.0).sinh()).abs() < 1e-15);
    }

    #[test]
    fn log_spacing_has_constant_ratio() {
        let p = generate(FORCE, 10.0, 1000.0, 5, Spacing::Log, None).unwrap();
        for w in p.windows(2) {
            assert!((w[1] / w[0] - 10f64.sqrt()).abs() < 1e-12);
        }
        assert_eq!((p[0], p[4]), (10.0, 1000.0));
    }

    /// The error of an axes file (TOML) that must be refused.
    fn refusal(toml: &str) -> String {
        let spec: AxesSpec = toml::from_str(toml).unwrap();
        Axes::from_spec(&spec).unwrap_err().to_string()
    }

    #[test]
    fn bad_axes_are_rejected_with_the_axis_name() {
        let spec = AxesSpec {
            spin: Some(AxisSpec {
                points: Some(vec![-1.0, 0.0, 0.5, 1.0]),
                raw_limit: Some(1.0),
                ..Default::default()
            }),
            ..Default::default()
        };
        let e = Axes::from_spec(&spec).unwrap_err().to_string();
        assert!(e.contains("spin") && e.contains("symmetric"), "{e}");
        let spec = AxesSpec {
            creepage_y: Some(AxisSpec {
                points: Some(vec![0.001, 0.01, 0.02]),
                raw_limit: Some(0.02),
                ..Default::default()
            }),
            ..Default::default()
        };
        let e = Axes::from_spec(&spec).unwrap_err().to_string();
        assert!(e.contains("creepage_y") && e.contains("starts at 0"), "{e}");
        let spec = AxesSpec {
            wetness: Some(AxisSpec {
                points: Some(vec![0.0, 1.5]),
                ..Default::default()
            }),
            ..Default::default()
        };
        assert!(Axes::from_spec(&spec).is_err());
        let spec = AxesSpec {
            speed: Some(AxisSpec {
                mirrored: Some(true),
                ..default_spec(SPEED)
            }),
            ..Default::default()
        };
        assert!(Axes::from_spec(&spec).is_err());
        // a raw scale: creepage axes only, finite and > 0
        for (spec, name) in [
            (
                AxesSpec {
                    speed: Some(AxisSpec {
                        raw_scale: Some(1.0),
                        ..default_spec(SPEED)
                    }),
                    ..Default::default()
                },
                "speed",
            ),
            (
                AxesSpec {
                    creepage_x: Some(AxisSpec {
                        raw_scale: Some(-193.0),
                        ..default_spec(XI)
                    }),
                    ..Default::default()
                },
                "creepage_x",
            ),
        ] {
            let e = Axes::from_spec(&spec).unwrap_err().to_string();
            assert!(e.contains(name) && e.contains("raw_scale"), "{e}");
        }
        let spec = AxesSpec {
            spin: Some(AxisSpec {
                raw_scale: Some(0.4),
                ..default_spec(PHI)
            }),
            ..Default::default()
        };
        assert_eq!(Axes::from_spec(&spec).unwrap().0[PHI].raw_scale, Some(0.4));
        // a raw length: the spin axis with a raw scale only, finite and > 0
        let with_length = |dim: usize, raw_scale: Option<f64>, raw_length: f64| {
            let axis = AxisSpec {
                raw_scale,
                raw_length: Some(raw_length),
                ..default_spec(dim)
            };
            let spec = match dim {
                XI => AxesSpec {
                    creepage_x: Some(axis),
                    ..Default::default()
                },
                _ => AxesSpec {
                    spin: Some(axis),
                    ..Default::default()
                },
            };
            Axes::from_spec(&spec)
        };
        for (dim, raw_scale, raw_length) in [
            (XI, Some(193.0), 0.012),
            (PHI, None, 0.012),
            (PHI, Some(0.4), 0.0),
            (PHI, Some(0.4), f64::INFINITY),
        ] {
            let e = with_length(dim, raw_scale, raw_length)
                .unwrap_err()
                .to_string();
            assert!(e.contains("raw_length"), "{e}");
        }
        assert_eq!(
            with_length(PHI, Some(0.4), 0.012).unwrap().0[PHI].raw_length,
            Some(0.012)
        );
    }

    #[test]
    fn linear_axes_with_positive_points_may_be_interpolated_in_logarithms() {
        let spec: AxesSpec = toml::from_str(
            "[normal_force]\ninterpolation = \"log\"\npoints = [10e3, 100e3]\n\
             [speed]\ninterpolation = \"linear\"\npoints = [1.0, 30.0]",
        )
        .unwrap();
        let a = Axes::from_spec(&spec).unwrap();
        assert!(a.0[FORCE].logarithmic && !a.0[SPEED].logarithmic);
        assert_eq!(a.0[FORCE].interpolation(FORCE), Interpolation::Log);
        assert_eq!(a.0[SPEED].interpolation(SPEED), Interpolation::Linear);
        assert_eq!(a.0[XI].interpolation(XI), Interpolation::Cubic);
        // the sidecar records it (the command line's verify test reads a built table's back)
        let records = crate::table::file::axis_records(&a);
        assert_eq!(records[FORCE].interpolation, Interpolation::Log);
        assert_eq!(records[SPEED].interpolation, Interpolation::Linear);
        // the defaults: F_N, a/b, p_ref in logarithms, V and w (from 0) linear
        let d = Axes::default();
        let logs: Vec<bool> = d.0.iter().map(|x| x.logarithmic).collect();
        assert_eq!(logs, [false, false, false, true, false, false, true, true]);
        // not on creepage axes, not on points ≤ 0, no other kind on a linear axis
        for (toml, name) in [
            (
                "[creepage_x]\ninterpolation = \"log\"\nmin = 0.0\nmax = 4.0\ncount = 5\n\
                 raw_limit = 0.1",
                "creepage_x",
            ),
            (
                "[wetness]\ninterpolation = \"log\"\npoints = [0.0, 1.0]",
                "wetness",
            ),
            (
                "[speed]\ninterpolation = \"cubic\"\npoints = [1.0, 2.0, 3.0, 4.0]",
                "speed",
            ),
        ] {
            let e = refusal(toml);
            assert!(e.contains(name) && e.contains("log"), "{e}");
        }
    }

    #[test]
    fn linear_axes_may_be_interpolated_in_square_roots_from_one_of_their_points_on() {
        let spec: AxesSpec =
            toml::from_str("[speed]\npoints = [1.0, 4.0, 26.8, 65.0, 158.0]\nsqrt_from = 26.8")
                .unwrap();
        let a = Axes::from_spec(&spec).unwrap();
        let cells: Vec<bool> = (0..4).map(|i| a.0[SPEED].cell_in_sqrt(i)).collect();
        assert_eq!(cells, [false, false, true, true]);
        assert_eq!(a.0[SPEED].interpolation(SPEED), Interpolation::Linear);
        assert!(!Axes::default().0[SPEED].cell_in_sqrt(0));
        // the sidecar records it
        let records = crate::table::file::axis_records(&a);
        assert_eq!(records[SPEED].sqrt_from, Some(26.8));
        assert_eq!(records[WET].sqrt_from, None);
        // a point (not the last, > 0) of a linear axis, not a log or creepage axis
        for toml in [
            "[speed]\npoints = [1.0, 4.0, 26.8]\nsqrt_from = 26.0",
            "[speed]\npoints = [1.0, 4.0, 26.8]\nsqrt_from = 26.8",
            "[speed]\ninterpolation = \"log\"\npoints = [1.0, 4.0, 26.8]\nsqrt_from = 4.0",
            "[wetness]\npoints = [0.0, 0.5, 1.0]\nsqrt_from = 0.0",
            "[spin]\nmin = -1.6\nmax = 1.6\ncount = 5\nraw_limit = 1.0\nsqrt_from = 0.0",
        ] {
            let e = refusal(toml);
            assert!(e.contains("sqrt_from"), "{toml}: {e}");
        }
    }

    #[test]
    fn a_table_by_similarity_has_the_reference_load_alone_and_says_so_in_its_sidecar() {
        let spec: AxesSpec = toml::from_str(
            "[normal_force]\npoints = [100e3]\n[speed]\nsimilarity = true\npoints = [0.3, 3.0, 30.0]",
        )
        .unwrap();
        let a = Axes::from_spec(&spec).unwrap();
        assert!(a.similarity() && a.0[SPEED].similarity);
        assert!(!Axes::default().similarity());
        let records = crate::table::file::axis_records(&a);
        assert!(records[SPEED].similarity && !records[FORCE].similarity);
        // only on the speed axis, only with the one normal force point F_ref
        for (toml, name) in [
            (
                "[wetness]\nsimilarity = true\npoints = [0.0, 1.0]",
                "wetness",
            ),
            (
                "[normal_force]\npoints = [50e3, 100e3]\n[speed]\nsimilarity = true\npoints = [1.0, 30.0]",
                "normal_force",
            ),
            (
                "[normal_force]\npoints = [50e3]\n[speed]\nsimilarity = true\npoints = [1.0, 30.0]",
                "normal_force",
            ),
        ] {
            let e = refusal(toml);
            assert!(e.contains(name) && e.contains("similarity"), "{e}");
        }
    }

    /// The axes files under `tools/` are valid: the committed default table's, and the running-surface and
    /// the whole-range contacts' by similarity (docs/model.md §12.3), with the point counts and ranges their
    /// comments give (the whole range: a/b 0.2–5 and p0 0.15–2.5 GPa, 1.5× per p0 cell up to
    /// 0.76 GPa and at most 1.105× above).
    #[test]
    fn the_axes_files_of_the_tools_folder_are_valid() {
        let tools = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tools");
        let default = Axes::from_toml_file(&tools.join("default-contact-axes.toml")).unwrap();
        assert_eq!((default.len(), default.similarity()), (693_000, false));
        let surface = Axes::from_toml_file(&tools.join("running-surface-axes.toml")).unwrap();
        assert_eq!((surface.len(), surface.similarity()), (4_596_480, true));
        assert_eq!(surface.0[FORCE].points, [REFERENCE_FORCE]);
        let whole = Axes::from_toml_file(&tools.join("whole-range-axes.toml")).unwrap();
        assert_eq!((whole.len(), whole.similarity()), (46_139_904, true));
        assert_eq!((whole.0[RATIO].min(), whole.0[RATIO].max()), (0.2, 5.0));
        let p0 = &whole.0[PRESSURE].points;
        assert_eq!((p0[0], p0[p0.len() - 1]), (0.15e9, 2.5e9));
        for w in p0.windows(2) {
            let limit = if w[1] <= 0.76e9 { 1.5 + 1e-9 } else { 1.105 };
            assert!(w[1] / w[0] <= limit, "{w:?}");
        }
        // the same η̂, speed and wetness axes as the running surface's; ξ̂ the same but for 31 nodes instead
        // of 21 (the knee of large dry contacts' creep curves); the spin's: the same count, raw limit and raw
        // scale, that in proportion to the contact's size (the default contact's 12 mm keeps 0.4 m), so the
        // axis reaches ±2.4, where the largest contacts' raw limit lies; denser near 0 (the whole range's
        // small contacts, a/b 0.2, reach only |φ̂| ≤ 0.15 at the raw limit)
        for d in [ETA, SPEED, WET] {
            assert_eq!(whole.0[d], surface.0[d], "{d}");
        }
        let (wx, sx) = (&whole.0[XI], &surface.0[XI]);
        assert_eq!((wx.points.len(), sx.points.len()), (31, 21));
        assert_eq!(
            (wx.min(), wx.max(), wx.raw_limit, wx.raw_scale, wx.mirrored),
            (sx.min(), sx.max(), sx.raw_limit, sx.raw_scale, sx.mirrored)
        );
        let (w, s) = (&whole.0[PHI], &surface.0[PHI]);
        assert_eq!(
            (w.points.len(), w.raw_limit, w.raw_scale),
            (s.points.len(), s.raw_limit, s.raw_scale)
        );
        assert_eq!((w.min(), w.max(), w.raw_length), (-2.4, 2.4, Some(0.012)));
        let coords = Coordinates::new(&Params::default(), &whole);
        let limit_at = |ratio: f64, p0: f64| {
            let [a, b] = semi_axes(ratio, p0, REFERENCE_FORCE);
            let e = Ellipse {
                a,
                b,
                load_exponent: 0.0,
            };
            coords.scales(&e, REFERENCE_FORCE).unwrap()[PHI].map(1.0).q
        };
        for ratio in [0.2, 5.0] {
            let top = limit_at(ratio, 0.15e9);
            // (beyond the ±1.6 of one raw scale for all)
            assert!(top > 1.8 && top < w.max(), "a/b {ratio}: {top}");
        }
        let near_zero = |a: &Axis| a.points.iter().filter(|x| (0.0..0.12).contains(*x)).count();
        assert_eq!((near_zero(s), near_zero(w)), (2, 3));
        assert!(limit_at(0.2, 1.13e9) < 0.15);
    }

    #[test]
    fn creepage_axes_need_a_raw_limit_and_linear_axes_may_have_one_point() {
        let mut spec = AxesSpec {
            creepage_y: Some(AxisSpec {
                raw_limit: None,
                ..default_spec(ETA)
            }),
            ..Default::default()
        };
        let e = Axes::from_spec(&spec).unwrap_err().to_string();
        assert!(e.contains("creepage_y") && e.contains("raw_limit"), "{e}");
        spec.creepage_y = Some(AxisSpec {
            raw_limit: Some(2.5),
            ..default_spec(ETA)
        });
        assert!(Axes::from_spec(&spec).is_err(), "beyond the solver's range");
        spec.creepage_y = None;
        spec.speed = Some(AxisSpec {
            raw_limit: Some(0.1),
            ..default_spec(SPEED)
        });
        assert!(Axes::from_spec(&spec).is_err(), "not a creepage axis");
        spec.speed = None;
        spec.semi_axis_ratio = Some(AxisSpec {
            points: Some(vec![0.56]),
            ..Default::default()
        });
        let a = Axes::from_spec(&spec).unwrap();
        assert_eq!(a.shape()[RATIO], 1);
        spec.spin = Some(AxisSpec {
            points: Some(vec![0.0]),
            raw_limit: Some(1.0),
            ..Default::default()
        });
        assert!(
            Axes::from_spec(&spec).is_err(),
            "a cubic axis needs 4 points"
        );
    }

    #[test]
    fn flat_index_coordinates_follow_c_order() {
        let a = Axes::default();
        let s = a.shape();
        let flat = 1 + s[7] * (2 + s[6] * (3 + s[5] * (4 + s[4] * 2)));
        let c = a.coordinates(flat);
        assert_eq!(c[PRESSURE], a.0[PRESSURE].points[1]);
        assert_eq!(c[RATIO], a.0[RATIO].points[2]);
        assert_eq!(c[WET], a.0[WET].points[3]);
        assert_eq!(c[SPEED], a.0[SPEED].points[4]);
        assert_eq!(c[FORCE], a.0[FORCE].points[2]);
        assert_eq!(c[XI], 0.0);
    }
}
