//! The parameter set of the model (MODEL.md §2–8, 12) and the operating point.
//!
//! Every default is the MODEL.md value or project default; every field is a TOML key. A parameter set is
//! validated by [`Params::validate`] (called by [`Params::from_toml_str`] and by the solver), which names
//! the offending key and its allowed range.

use crate::error::{Error, Result, check_positive, check_range};
use serde::{Deserialize, Serialize};

/// Kelvin offset of the Celsius scale.
pub const CELSIUS_ZERO: f64 = 273.15;

/// Contact geometry: curvatures of the undeformed gap h = A·x² + B·y² (MODEL.md §2), or prescribed semi-axes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Geometry {
    /// A = ½(1/R_wx + 1/R_rx) [1/m], along the rolling direction x.
    pub curvature_x: f64,
    /// B = ½(1/R_wy + 1/R_ry) [1/m], lateral.
    pub curvature_y: f64,
    /// Prescribed semi-axes [a, b] [m]; when set, they replace the Hertz solution from the curvatures
    /// (p0 then follows from the normal force, p0 = 3·F_N/(2π·a·b)).
    pub semi_axes: Option<[f64; 2]>,
}

impl Default for Geometry {
    fn default() -> Self {
        Self {
            curvature_x: 1.015,
            curvature_y: 0.4215,
            semi_axes: None,
        }
    }
}

/// Temperature-dependent steel of wheel and rail (identical bodies; MODEL.md §3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Material {
    /// Young's modulus at the reference temperature [Pa].
    pub youngs_modulus: f64,
    /// Relative fall of E per kelvin above the reference temperature [1/K].
    pub youngs_slope: f64,
    /// Lower bound of E(T)/E(T_ref) [-].
    pub youngs_floor: f64,
    /// Poisson's ratio [-].
    pub poisson: f64,
    /// Bulk yield stress at the reference temperature [Pa].
    pub yield_stress: f64,
    /// Temperature span over which σ_y falls linearly to zero [K].
    pub yield_span: f64,
    /// Lower bound of the linear σ_y factor [-].
    pub yield_floor: f64,
    /// Relative height of the yield-stress anomaly bump (dynamic strain ageing) [-].
    pub anomaly_amplitude: f64,
    /// Temperature of the anomaly's peak [K].
    pub anomaly_temperature: f64,
    /// Width of the anomaly's Gaussian bump [K].
    pub anomaly_width: f64,
    /// Asperity hardness at the reference temperature [Pa].
    pub hardness: f64,
    /// Temperature span over which H falls linearly to zero [K].
    pub hardness_span: f64,
    /// Lower bound of H(T)/H(T_ref) [-].
    pub hardness_floor: f64,
    /// Reference temperature of the material curves [K] (20 °C).
    pub reference_temperature: f64,
    /// Thermal conductivity λ [W/(m·K)].
    pub conductivity: f64,
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Specific heat c [J/(kg·K)].
    pub specific_heat: f64,
    /// Bulk temperature T0 of wheel and rail [K].
    pub bulk_temperature: f64,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            youngs_modulus: 210e9,
            youngs_slope: 4.0e-4,
            youngs_floor: 0.1,
            poisson: 0.28,
            yield_stress: 600e6,
            yield_span: 975.0,
            yield_floor: 0.05,
            anomaly_amplitude: 0.3,
            anomaly_temperature: 450.0 + CELSIUS_ZERO,
            anomaly_width: 80.0,
            hardness: 4e9,
            hardness_span: 1200.0,
            hardness_floor: 0.05,
            reference_temperature: 20.0 + CELSIUS_ZERO,
            conductivity: 50.0,
            density: 7850.0,
            specific_heat: 450.0,
            bulk_temperature: 20.0 + CELSIUS_ZERO,
        }
    }
}

/// Surface roughness: the roughness parameter k_r and its mapping to GW parameters (MODEL.md §4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Roughness {
    /// Roughness parameter k_r ∈ [0, 1]: 0 smooth, 1 rough.
    pub k_r: f64,
    /// z_s at k_r = 0 [m]. Project default 2.5 µm (recalibrated from MODEL.md's 0.5 µm for the fluid model,
    /// see docs/calibration.md; dry friction depends only on z_s/R_a and β, not on z_s).
    pub z_s_smooth: f64,
    /// Increase of z_s from k_r = 0 to k_r = 1 [m].
    pub z_s_span: f64,
    /// z_s/R_a at k_r = 0 [-].
    pub ratio_smooth: f64,
    /// Increase of z_s/R_a from k_r = 0 to k_r = 1 [-].
    pub ratio_span: f64,
    /// GW parameter β = η_s·R_a·z_s [-].
    pub beta: f64,
}

impl Default for Roughness {
    fn default() -> Self {
        Self {
            k_r: 0.5,
            z_s_smooth: 2.5e-6,
            z_s_span: 5.0e-6,
            ratio_smooth: 3e-4,
            ratio_span: 9e-4,
            beta: 0.12,
        }
    }
}

impl Roughness {
    /// Standard deviation of asperity heights z_s(k_r) [m] (MODEL.md §4, project default mapping).
    pub fn z_s(&self) -> f64 {
        self.z_s_smooth + self.z_s_span * self.k_r
    }
    /// Asperity summit radius R_a(k_r) = z_s/(z_s/R_a) [m].
    pub fn r_a(&self) -> f64 {
        self.z_s() / (self.ratio_smooth + self.ratio_span * self.k_r)
    }
    /// Areal density of asperities η_s = β/(R_a·z_s) [1/m²].
    pub fn eta_s(&self) -> f64 {
        self.beta / (self.r_a() * self.z_s())
    }
}

/// Which local friction law limits the tangential stress.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum FrictionLaw {
    /// The Tomberger et al. model: τ_l = k·σ_y(T)·A_m/A_n (P3, P6).
    #[default]
    Tomberger,
    /// Classic FASTSIM with constant μ: τ_l = μ·p_n; temperature computed and reported only.
    Constant,
    /// Polach (2005) closed-form creep forces (MODEL.md §12).
    Polach,
}

impl std::fmt::Display for FrictionLaw {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FrictionLaw::Tomberger => "tomberger",
            FrictionLaw::Constant => "constant",
            FrictionLaw::Polach => "polach",
        })
    }
}

/// Polach's parameters (Wear 258, 2005), defaults: his dry set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Polach {
    /// Maximum friction coefficient at zero slip velocity μ0 [-].
    pub mu0: f64,
    /// Ratio of limit friction at infinite slip velocity to μ0, A [-].
    pub a_ratio: f64,
    /// Exponential friction decrease rate B [s/m].
    pub b_rate: f64,
    /// Reduction factor in the area of adhesion k_A [-].
    pub k_a: f64,
    /// Reduction factor in the area of slip k_S [-].
    pub k_s: f64,
}

impl Default for Polach {
    fn default() -> Self {
        Self {
            mu0: 0.55,
            a_ratio: 0.4,
            b_rate: 0.6,
            k_a: 1.0,
            k_s: 0.4,
        }
    }
}

/// Local friction (MODEL.md §5) and the choice of law.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Friction {
    /// Friction law.
    pub law: FrictionLaw,
    /// Failure-stress factor k in τ_m = k·σ_y for dry metallic contact (P3) [-].
    pub k_dry: f64,
    /// Constant friction coefficient for the `constant` law [-].
    pub mu: f64,
    /// Polach's parameters for the `polach` law.
    pub polach: Polach,
}

impl Default for Friction {
    fn default() -> Self {
        Self {
            law: FrictionLaw::Tomberger,
            k_dry: 1.0,
            mu: 0.4,
            polach: Polach::default(),
        }
    }
}

/// Interfacial fluid (MODEL.md §8, paper Table 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Fluid {
    /// Flow-resistance factor ξ_f (12·viscosity for a Newtonian fluid) [Pa·s].
    pub flow_resistance: f64,
    /// Failure-stress factor k under boundary lubrication [-].
    pub k_wet: f64,
    /// Probability of asperity occurrence at the cell base height ψ_b [-].
    pub psi_b: f64,
    /// Inlet film height at wetness 1 [m].
    pub h_f_max: f64,
    /// Fluid height over which k blends from k_dry to k_wet [m].
    pub h_bl: f64,
}

impl Default for Fluid {
    fn default() -> Self {
        Self {
            flow_resistance: 0.012,
            k_wet: 0.4,
            psi_b: 0.9995,
            h_f_max: 20e-6,
            h_bl: 0.1e-6,
        }
    }
}

/// Discretisation of the contact ellipse (MODEL.md §2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GridParams {
    /// Cells along x over [−a, a].
    pub nx: usize,
    /// Cells along y over [−b, b].
    pub ny: usize,
}

impl Default for GridParams {
    fn default() -> Self {
        Self { nx: 30, ny: 30 }
    }
}

/// Coupled fixed-point iteration (MODEL.md §9).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverParams {
    /// Convergence tolerance on the relative change of the adhesion limit and temperature [-].
    pub tolerance: f64,
    /// Maximum number of outer iterations.
    pub max_iterations: usize,
    /// Initial relaxation factor of the temperature update (adapted downwards on divergence) [-].
    pub relaxation: f64,
    /// Whether frictional heating is computed (false: T = T0 everywhere).
    pub heat: bool,
    /// Convergence tolerance of the fluid film solve: largest remaining (Newton) correction of the
    /// separation (in z_s) and of the fluid height (in h_f0) [-].
    pub fluid_tolerance: f64,
    /// Iteration limit of the fluid film solve (Newton iterations plus any Gauss–Seidel fallback sweeps;
    /// the parameter keeps its historical name).
    pub max_fluid_sweeps: usize,
}

impl Default for SolverParams {
    fn default() -> Self {
        Self {
            tolerance: 1e-6,
            max_iterations: 200,
            relaxation: 1.0,
            heat: true,
            fluid_tolerance: 1e-10,
            max_fluid_sweeps: 20_000,
        }
    }
}

/// The complete parameter set of one wheel–rail contact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Params {
    /// Contact geometry.
    pub geometry: Geometry,
    /// Steel of wheel and rail.
    pub material: Material,
    /// Surface roughness.
    pub roughness: Roughness,
    /// Local friction law.
    pub friction: Friction,
    /// Interfacial fluid.
    pub fluid: Fluid,
    /// Contact grid.
    pub grid: GridParams,
    /// Coupled solver controls.
    pub solver: SolverParams,
}

impl Params {
    /// Parses a TOML parameter file's text (missing keys take their defaults) and validates it.
    pub fn from_toml_str(text: &str) -> Result<Self> {
        let p: Params = toml::from_str(text).map_err(|e| Error::ParameterFile {
            path: "<toml>".into(),
            reason: e.to_string().replace('\n', " "),
        })?;
        p.validate()?;
        Ok(p)
    }

    /// Reads, parses and validates a TOML parameter file.
    pub fn from_toml_file(path: &std::path::Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::ParameterFile {
            path: path.display().to_string(),
            reason: e.to_string(),
        })?;
        Self::from_toml_str(&text).map_err(|e| match e {
            Error::ParameterFile { reason, .. } => Error::ParameterFile {
                path: path.display().to_string(),
                reason,
            },
            other => other,
        })
    }

    /// The parameter set as TOML text.
    pub fn to_toml_string(&self) -> String {
        toml::to_string(self).expect("parameter set always serialises")
    }

    /// Checks every value against its physical range; the error names the TOML key.
    pub fn validate(&self) -> Result<()> {
        let g = &self.geometry;
        match g.semi_axes {
            Some([a, b]) => {
                check_range("geometry.semi_axes[0]", a, 1e-6, 1.0, "m")?;
                check_range("geometry.semi_axes[1]", b, 1e-6, 1.0, "m")?;
            }
            None => {
                check_range("geometry.curvature_x", g.curvature_x, 1e-3, 1e3, "1/m")?;
                check_range("geometry.curvature_y", g.curvature_y, 1e-3, 1e3, "1/m")?;
            }
        }
        let m = &self.material;
        check_range("material.youngs_modulus", m.youngs_modulus, 1e9, 1e12, "Pa")?;
        check_range("material.youngs_slope", m.youngs_slope, 0.0, 1e-2, "1/K")?;
        check_range("material.youngs_floor", m.youngs_floor, 1e-3, 1.0, "")?;
        check_range("material.poisson", m.poisson, 0.0, 0.5, "")?;
        check_range("material.yield_stress", m.yield_stress, 1e6, 1e10, "Pa")?;
        check_range("material.yield_span", m.yield_span, 1.0, 1e5, "K")?;
        check_range("material.yield_floor", m.yield_floor, 1e-3, 1.0, "")?;
        check_range(
            "material.anomaly_amplitude",
            m.anomaly_amplitude,
            0.0,
            10.0,
            "",
        )?;
        check_range(
            "material.anomaly_temperature",
            m.anomaly_temperature,
            0.0,
            5000.0,
            "K",
        )?;
        check_range("material.anomaly_width", m.anomaly_width, 1e-3, 1e4, "K")?;
        check_range("material.hardness", m.hardness, 1e7, 1e11, "Pa")?;
        check_range("material.hardness_span", m.hardness_span, 1.0, 1e5, "K")?;
        check_range("material.hardness_floor", m.hardness_floor, 1e-3, 1.0, "")?;
        check_range(
            "material.reference_temperature",
            m.reference_temperature,
            1.0,
            2000.0,
            "K",
        )?;
        check_positive("material.conductivity", m.conductivity, "W/(m K)")?;
        check_positive("material.density", m.density, "kg/m^3")?;
        check_positive("material.specific_heat", m.specific_heat, "J/(kg K)")?;
        check_range(
            "material.bulk_temperature",
            m.bulk_temperature,
            1.0,
            2000.0,
            "K",
        )?;
        let r = &self.roughness;
        check_range("roughness.k_r", r.k_r, 0.0, 1.0, "")?;
        check_positive("roughness.z_s_smooth", r.z_s_smooth, "m")?;
        check_range("roughness.z_s_span", r.z_s_span, 0.0, 1e-3, "m")?;
        check_range("roughness.ratio_smooth", r.ratio_smooth, 1e-7, 1.0, "")?;
        check_range("roughness.ratio_span", r.ratio_span, 0.0, 1.0, "")?;
        check_range("roughness.beta", r.beta, 1e-4, 10.0, "")?;
        let f = &self.friction;
        check_range("friction.k_dry", f.k_dry, 0.0, 10.0, "")?;
        check_range("friction.mu", f.mu, 0.0, 10.0, "")?;
        check_range("friction.polach.mu0", f.polach.mu0, 0.0, 10.0, "")?;
        check_range("friction.polach.a_ratio", f.polach.a_ratio, 0.0, 10.0, "")?;
        check_range("friction.polach.b_rate", f.polach.b_rate, 0.0, 1e3, "s/m")?;
        check_range("friction.polach.k_a", f.polach.k_a, 0.0, 10.0, "")?;
        check_range("friction.polach.k_s", f.polach.k_s, 0.0, 10.0, "")?;
        let fl = &self.fluid;
        check_positive("fluid.flow_resistance", fl.flow_resistance, "Pa s")?;
        check_range("fluid.k_wet", fl.k_wet, 0.0, 10.0, "")?;
        check_range("fluid.psi_b", fl.psi_b, 0.5, 1.0 - 1e-15, "")?;
        check_range("fluid.h_f_max", fl.h_f_max, 0.0, 1e-2, "m")?;
        check_positive("fluid.h_bl", fl.h_bl, "m")?;
        let gr = &self.grid;
        check_range("grid.nx", gr.nx as f64, 4.0, 400.0, "cells")?;
        check_range("grid.ny", gr.ny as f64, 4.0, 400.0, "cells")?;
        let s = &self.solver;
        check_range("solver.tolerance", s.tolerance, 1e-14, 1e-1, "")?;
        check_range(
            "solver.max_iterations",
            s.max_iterations as f64,
            1.0,
            1e6,
            "",
        )?;
        check_range("solver.relaxation", s.relaxation, 1e-3, 1.0, "")?;
        check_range("solver.fluid_tolerance", s.fluid_tolerance, 1e-15, 1e-2, "")?;
        check_range(
            "solver.max_fluid_sweeps",
            s.max_fluid_sweeps as f64,
            1.0,
            1e7,
            "",
        )?;
        Ok(())
    }
}

/// One operating point of the contact: kinematics, load and wetness.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OperatingPoint {
    /// Longitudinal creepage ξ [-].
    pub creepage_x: f64,
    /// Lateral creepage η [-].
    pub creepage_y: f64,
    /// Spin creepage φ [1/m].
    pub spin: f64,
    /// Normal force F_N [N].
    pub normal_force: f64,
    /// Rolling speed V [m/s].
    pub speed: f64,
    /// Wetness w ∈ [0, 1] (0 dry, 1 flooded inlet).
    pub wetness: f64,
}

impl Default for OperatingPoint {
    fn default() -> Self {
        Self {
            creepage_x: 0.0,
            creepage_y: 0.0,
            spin: 0.0,
            normal_force: 100e3,
            speed: 30.0,
            wetness: 0.0,
        }
    }
}

impl OperatingPoint {
    /// Checks the point: finite creepages (|ξ|, |η| < 2, since surface speeds V·(1 ± ξ/2) must stay
    /// positive), positive load and speed, wetness in [0, 1].
    pub fn validate(&self) -> Result<()> {
        check_range("creepage-x", self.creepage_x, -1.9, 1.9, "")?;
        check_range("creepage-y", self.creepage_y, -1.9, 1.9, "")?;
        check_range("spin", self.spin, -1e4, 1e4, "1/m")?;
        check_range("normal-force", self.normal_force, 1e-3, 1e8, "N")?;
        check_range("speed", self.speed, 1e-6, 1e3, "m/s")?;
        check_range("wetness", self.wetness, 0.0, 1.0, "")?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_round_trip_through_toml() {
        let p = Params::default();
        p.validate().unwrap();
        let back = Params::from_toml_str(&p.to_toml_string()).unwrap();
        assert_eq!(p, back);
    }

    #[test]
    fn roughness_mapping_matches_model_md() {
        let r = Roughness::default();
        assert!((r.z_s() - 5.0e-6).abs() < 1e-18);
        assert!((r.z_s() / r.r_a() - 7.5e-4).abs() < 1e-15);
        assert!((r.eta_s() * r.r_a() * r.z_s() - 0.12).abs() < 1e-12);
    }

    #[test]
    fn bad_values_are_named() {
        let e = Params::from_toml_str("[roughness]\nk_r = 1.5\n").unwrap_err();
        assert!(e.to_string().contains("roughness.k_r"), "{e}");
        let e = Params::from_toml_str("[grid]\nnx = \"a\"\n").unwrap_err();
        assert!(e.to_string().contains("nx"), "{e}");
        let e = Params::from_toml_str("[nonsense]\n").unwrap_err();
        assert!(e.to_string().contains("nonsense"), "{e}");
        let pt = OperatingPoint {
            normal_force: f64::NAN,
            ..Default::default()
        };
        assert!(
            pt.validate()
                .unwrap_err()
                .to_string()
                .contains("normal-force")
        );
        let pt = OperatingPoint {
            wetness: 1.2,
            ..Default::default()
        };
        assert!(pt.validate().unwrap_err().to_string().contains("wetness"));
    }
}
