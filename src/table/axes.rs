//! The six axes of a table (issue 5 §1): ξ, η, φ, F_N, V, w, their points and how they are generated.
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
//!   V(1 ± ξ/2)); with fluid the film sees the rail speed, and the forces differ by at most about 5e-4·F_N
//!   (tests/table.rs measures it).
//!
//! The η mirror needs a spin axis symmetric about 0. Generated points are computed with `libm`, so every
//! platform produces the same bits (shards built on different machines merge).

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// Number of table dimensions.
pub const DIMS: usize = 6;

/// Interpolation along one axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Interpolation {
    /// C¹ cubic Hermite spline with three-point (parabola) node derivatives on the non-uniform points.
    Cubic,
    /// Piecewise linear.
    Linear,
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

/// The dimensions in storage order (slowest first): ξ, η, φ, F_N, V, w.
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

/// The points of one axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// Strictly increasing points, in the axis' unit.
    pub points: Vec<f64>,
    /// Only values ≥ 0 are stored (first point 0); the negative half follows by symmetry.
    pub mirrored: bool,
}

impl Axis {
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
}

/// The six axes of a table, in storage order.
#[derive(Debug, Clone, PartialEq)]
pub struct Axes(pub [Axis; DIMS]);

impl Default for Axes {
    /// The default axes: |ξ| ≤ 0.1 and |η| ≤ 0.02 sinh-spaced about the creep-curve knees (≈ 0.05–1 %),
    /// |φ| ≤ 1 1/m, F_N 10–200 kN and V 1–100 m/s log-spaced, w 0–1 denser near dry. See
    /// `docs`-level justification in the module's report: each count was chosen by the accuracy it gives.
    fn default() -> Self {
        Self::from_spec(&AxesSpec::default()).expect("default axes are valid")
    }
}

/// The default generator of each dimension.
fn default_spec(dim: usize) -> AxisSpec {
    let gen_ = |min: f64, max: f64, count: usize, spacing: Spacing, scale: Option<f64>| AxisSpec {
        min: Some(min),
        max: Some(max),
        count: Some(count),
        spacing: Some(spacing),
        scale,
        ..Default::default()
    };
    match dim {
        XI => AxisSpec {
            mirrored: Some(true),
            ..gen_(0.0, 0.1, 12, Spacing::Sinh, Some(1.5e-3))
        },
        ETA => AxisSpec {
            mirrored: Some(true),
            ..gen_(0.0, 0.02, 9, Spacing::Sinh, Some(1.5e-3))
        },
        PHI => gen_(-1.0, 1.0, 11, Spacing::Sinh, Some(0.2)),
        FORCE => gen_(10e3, 200e3, 6, Spacing::Log, None),
        SPEED => gen_(1.0, 100.0, 7, Spacing::Log, None),
        _ => AxisSpec {
            points: Some(vec![0.0, 0.05, 0.15, 0.3, 0.5, 0.75, 1.0]),
            ..Default::default()
        },
    }
}

/// Allowed coordinate range of each dimension (what the exact solver accepts).
fn physical_range(dim: usize) -> (f64, f64) {
    match dim {
        XI | ETA => (-1.9, 1.9),
        PHI => (-1e4, 1e4),
        FORCE => (1e-3, 1e8),
        SPEED => (1e-6, 1e3),
        _ => (0.0, 1.0),
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
        let axis = Axis { points, mirrored };
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
                if min != -max || count % 2 == 0 {
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

/// Checks one axis: enough points for its interpolation, strictly increasing, finite, inside the physical
/// range of the dimension; a mirrored axis starts at 0.
fn validate_axis(dim: usize, axis: &Axis) -> Result<()> {
    let p = &axis.points;
    let needed = match (DIMENSIONS[dim].interpolation, axis.mirrored) {
        (Interpolation::Cubic, true) => 3,
        (Interpolation::Cubic, false) => 4,
        (Interpolation::Linear, _) => 2,
    };
    if p.len() < needed {
        return Err(bad(
            dim,
            format!("needs at least {needed} points (has {})", p.len()),
        ));
    }
    if p.iter().any(|x| !x.is_finite()) || p.windows(2).any(|w| w[0] >= w[1]) {
        return Err(bad(dim, "points must be finite and strictly increasing"));
    }
    let (lo, hi) = physical_range(dim);
    if axis.min() < lo || axis.max() > hi {
        return Err(bad(
            dim,
            format!("points must lie in [{lo}, {hi}] {}", DIMENSIONS[dim].unit),
        ));
    }
    if axis.mirrored && p[0] != 0.0 {
        return Err(bad(dim, "a mirrored axis starts at 0"));
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
        ];
        let mut axes = Vec::with_capacity(DIMS);
        for (dim, g) in given.iter().enumerate() {
            let s = match g {
                Some(s) => (*s).clone(),
                None => default_spec(dim),
            };
            axes.push(s.resolve(dim)?);
        }
        let axes = Axes(axes.try_into().expect("six axes"));
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

    /// Checks every axis and the cross-axis rules (η mirrored; φ symmetric about 0, which the η mirror needs).
    pub fn validate(&self) -> Result<()> {
        for (dim, a) in self.0.iter().enumerate() {
            validate_axis(dim, a)?;
            if a.mirrored && !matches!(dim, XI | ETA) {
                return Err(bad(dim, "only creepage axes can be mirrored"));
            }
        }
        if !self.0[ETA].mirrored {
            return Err(bad(ETA, "must be mirrored"));
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

    #[test]
    fn default_axes_cover_the_issue_ranges() {
        let a = Axes::default();
        let want = [
            (-0.1, 0.1),
            (-0.02, 0.02),
            (-1.0, 1.0),
            (10e3, 200e3),
            (1.0, 100.0),
            (0.0, 1.0),
        ];
        for (d, (lo, hi)) in want.iter().enumerate() {
            assert_eq!((a.0[d].min(), a.0[d].max()), (*lo, *hi), "{}", d);
        }
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

    #[test]
    fn bad_axes_are_rejected_with_the_axis_name() {
        let spec = AxesSpec {
            spin: Some(AxisSpec {
                points: Some(vec![-1.0, 0.0, 0.5, 1.0]),
                ..Default::default()
            }),
            ..Default::default()
        };
        let e = Axes::from_spec(&spec).unwrap_err().to_string();
        assert!(e.contains("spin") && e.contains("symmetric"), "{e}");
        let spec = AxesSpec {
            creepage_y: Some(AxisSpec {
                points: Some(vec![0.001, 0.01, 0.02]),
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
    }

    #[test]
    fn flat_index_coordinates_follow_c_order() {
        let a = Axes::default();
        let s = a.shape();
        let flat = 1 + s[5] * (2 + s[4] * 3);
        let c = a.coordinates(flat);
        assert_eq!(c[WET], a.0[WET].points[1]);
        assert_eq!(c[SPEED], a.0[SPEED].points[2]);
        assert_eq!(c[FORCE], a.0[FORCE].points[3]);
        assert_eq!(c[XI], 0.0);
    }
}
