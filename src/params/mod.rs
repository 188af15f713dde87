//! The parameter set of the model (docs/model.md §2–8, 12) and the operating point.
//!
//! Every default is the value of docs/model.md or a documented project default; every field is a TOML key. The names, units,
//! allowed ranges and defaults of the scalar parameters and inputs are the rows of [`spec`]. A parameter
//! set is validated by [`Params::validate`] (called by [`Params::from_toml_str`] and by the solver), whose
//! error carries the offending row's [`Key`] and its allowed range.

pub mod spec;

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
pub use spec::{Input, Key, Param};

/// Kelvin offset of the Celsius scale.
pub const CELSIUS_ZERO: f64 = 273.15;

/// Contact geometry: curvatures of the undeformed gap h = A·x² + B·y² (docs/model.md §2), or prescribed semi-axes.
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

impl Geometry {
    /// The geometry of per-evaluation inputs (the FMU's, the command line's): gap curvatures A, B [1/m]
    /// and semi-axes a, b [m], where a = b = 0 means "not prescribed" (the curvatures define the ellipse)
    /// and any other pair is prescribed (and must lie in [`spec::SEMI_AXIS_RANGE`], checked by
    /// [`Geometry::validate`]).
    pub fn of_inputs(curvature_x: f64, curvature_y: f64, semi_axes: [f64; 2]) -> Geometry {
        Geometry {
            curvature_x,
            curvature_y,
            semi_axes: (semi_axes != [0.0, 0.0]).then_some(semi_axes),
        }
    }

    /// Checks prescribed semi-axes against [`spec::SEMI_AXIS_RANGE`], else the curvatures against their
    /// rows of the specification (unused curvatures are not checked); the error carries the key.
    pub fn validate(&self) -> Result<()> {
        match self.semi_axes {
            Some([a, b]) => {
                for (key, x) in [(Key::SemiAxisA, a), (Key::SemiAxisB, b)] {
                    if !spec::SEMI_AXIS_RANGE.contains(x) {
                        return Err(
                            key.invalid(x, spec::SEMI_AXIS_RANGE.describe(spec::Unit::Metre))
                        );
                    }
                }
                Ok(())
            }
            None => {
                Param::CurvatureX.spec().check(self.curvature_x)?;
                Param::CurvatureY.spec().check(self.curvature_y)
            }
        }
    }
}

impl Default for Geometry {
    fn default() -> Self {
        Self {
            curvature_x: Param::CurvatureX.default_value(),
            curvature_y: Param::CurvatureY.default_value(),
            semi_axes: None,
        }
    }
}

/// Temperature-dependent steel of wheel and rail (identical bodies; docs/model.md §3).
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
            youngs_modulus: Param::YoungsModulus.default_value(),
            youngs_slope: Param::YoungsSlope.default_value(),
            youngs_floor: Param::YoungsFloor.default_value(),
            poisson: Param::Poisson.default_value(),
            yield_stress: Param::YieldStress.default_value(),
            yield_span: Param::YieldSpan.default_value(),
            yield_floor: Param::YieldFloor.default_value(),
            anomaly_amplitude: Param::AnomalyAmplitude.default_value(),
            anomaly_temperature: Param::AnomalyTemperature.default_value(),
            anomaly_width: Param::AnomalyWidth.default_value(),
            hardness: Param::Hardness.default_value(),
            hardness_span: Param::HardnessSpan.default_value(),
            hardness_floor: Param::HardnessFloor.default_value(),
            reference_temperature: Param::ReferenceTemperature.default_value(),
            conductivity: Param::Conductivity.default_value(),
            density: Param::Density.default_value(),
            specific_heat: Param::SpecificHeat.default_value(),
            bulk_temperature: Param::BulkTemperature.default_value(),
        }
    }
}

/// Surface roughness: the roughness parameter k_r and its mapping to GW parameters (docs/model.md §4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Roughness {
    /// Roughness parameter k_r ∈ [0, 1]: 0 smooth, 1 rough.
    pub k_r: f64,
    /// z_s at k_r = 0 [m]. Project default 2.5 µm (recalibrated from the first guess 0.5 µm of docs/model.md §4.4 for the fluid model,
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
            k_r: Param::RoughnessKr.default_value(),
            z_s_smooth: Param::ZsSmooth.default_value(),
            z_s_span: Param::ZsSpan.default_value(),
            ratio_smooth: Param::RatioSmooth.default_value(),
            ratio_span: Param::RatioSpan.default_value(),
            beta: Param::Beta.default_value(),
        }
    }
}

impl Roughness {
    /// Standard deviation of asperity heights z_s(k_r) [m] (docs/model.md §4, project default mapping).
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
    /// Polach (2005) closed-form creep forces (docs/model.md §12).
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

/// The tangential contact solver of the coupled model (docs/model.md §6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Tangential {
    /// Kalker's simplified theory, FASTSIM with the local adhesion limit (docs/model.md §6.2).
    #[default]
    Fastsim,
    /// Kalker's exact theory of steady rolling with the local adhesion limit as the traction bound
    /// (docs/model.md §6.5 and §6.6).
    Exact,
}

impl std::fmt::Display for Tangential {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Tangential::Fastsim => "fastsim",
            Tangential::Exact => "exact",
        })
    }
}

/// The nominal normal pressure over the contact ellipse (docs/model.md §2), as asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Pressure {
    /// Hertz's ellipsoid with the exact tangential solver, the parabola with FASTSIM.
    #[default]
    Auto,
    /// Hertz's ellipsoidal pressure p0·sqrt(1 − x²/a² − y²/b²).
    Hertz,
    /// The parabola with the same force, (2F_N/(πab))·(1 − x²/a² − y²/b²) (paper §3, FASTSIM's).
    Parabolic,
}

impl std::fmt::Display for Pressure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Pressure::Auto => "auto",
            Pressure::Hertz => "hertz",
            Pressure::Parabolic => "parabolic",
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
            mu0: Param::PolachMu0.default_value(),
            a_ratio: Param::PolachARatio.default_value(),
            b_rate: Param::PolachBRate.default_value(),
            k_a: Param::PolachKA.default_value(),
            k_s: Param::PolachKS.default_value(),
        }
    }
}

/// Local friction (docs/model.md §5) and the choice of law.
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
            k_dry: Param::KDry.default_value(),
            mu: Param::Mu.default_value(),
            polach: Polach::default(),
        }
    }
}

/// Interfacial fluid (docs/model.md §8, paper Table 1).
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
            flow_resistance: Param::FlowResistance.default_value(),
            k_wet: Param::KWet.default_value(),
            psi_b: Param::PsiB.default_value(),
            h_f_max: Param::HFMax.default_value(),
            h_bl: Param::HBl.default_value(),
        }
    }
}

/// The interfacial (third-body) layer between wheel and rail in the tangential problem (docs/model.md
/// §6.7, an extension of the paper): a thin elastic layer whose shear adds h·τ/G₃ to the tangential
/// displacement difference of the two bodies at each point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Layer {
    /// Layer thickness h [m]; 0: no layer (the half-spaces' contact of the paper).
    pub thickness: f64,
    /// Shear modulus of the layer G₃ [Pa].
    pub shear_modulus: f64,
}

impl Default for Layer {
    fn default() -> Self {
        Self {
            thickness: Param::LayerThickness.default_value(),
            shear_modulus: Param::LayerShearModulus.default_value(),
        }
    }
}

impl Layer {
    /// The layer's tangential compliance h/G₃ [m/Pa]: its shear displacement per unit traction
    /// (docs/model.md §6.7); 0 without a layer.
    pub fn compliance(&self) -> f64 {
        self.thickness / self.shear_modulus
    }
}

/// Discretisation of the contact ellipse (docs/model.md §2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GridParams {
    /// Cells along x over [−a, a].
    pub nx: usize,
    /// Cells along y over [−b, b].
    pub ny: usize,
    /// Target discretisation error |ΔF|/F_N [-]: > 0 chooses the cells ([`GridParams::cells`]); 0 keeps
    /// `nx` × `ny` (written only when set, so that earlier parameter sets keep their fingerprints).
    #[serde(skip_serializing_if = "is_default")]
    pub accuracy: f64,
}

impl Default for GridParams {
    fn default() -> Self {
        Self {
            nx: Param::GridNx.default_value() as usize,
            ny: Param::GridNy.default_value() as usize,
            accuracy: Param::GridAccuracy.default_value(),
        }
    }
}

/// The measured grid convergence of the full model (docs/model.md §6.4): per n × n grid, the largest
/// |ΔF|/F_N against 120 × 120 over the sixteen cases of the full-model table there (default contact and
/// the flange-root shape a/b = 5; ξ = 1 %, spin 1 and 3 /m, ξ = η = 0.2 % with 3 /m; dry and wet; 100 kN,
/// 30 m/s).
pub const GRID_CONVERGENCE: [(usize, f64); 8] = [
    (6, 4.0e-2),
    (8, 1.65e-2),
    (10, 5.3e-3),
    (12, 3.2e-3),
    (16, 2.1e-3),
    (20, 1.35e-3),
    (30, 1.22e-3),
    (60, 3.3e-4),
];

/// The grid of the convergence reference, used for accuracies finer than any measured grid reached.
pub const GRID_REFERENCE: usize = 120;

impl GridParams {
    /// The cells [nx, ny]: `nx`, `ny` without an accuracy target; with one, n × n for the smallest
    /// measured n whose worst force error ([`GRID_CONVERGENCE`]) is within it (the reference grid 120 ×
    /// 120 below the finest measured error).
    pub fn cells(&self) -> [usize; 2] {
        if self.accuracy <= 0.0 {
            return [self.nx, self.ny];
        }
        let n = GRID_CONVERGENCE
            .iter()
            .find(|(_, e)| *e <= self.accuracy)
            .map_or(GRID_REFERENCE, |(n, _)| *n);
        [n, n]
    }
}

/// Cells along the rolling direction x of the per-contact fallback grid ([`fallback_cells`]): what the
/// peak temperature needs (docs/model.md §6.4). A coarse grid underestimates T_max mostly through the cells
/// along x (the frictional heat of a cell lags its centre by up to half a cell), not across: T_max within
/// 10 K of 30 × 30 needs about 24 cells along x at the flange root, however few across.
pub const FALLBACK_CELLS_X: usize = 24;
/// Cells along x of the per-contact fallback grid on a wet contact shorter than [`FALLBACK_LONG_CONTACT`]:
/// the film carries part of the load and lowers the friction, the temperature rises less, and fewer cells
/// along x keep T_max within 10 K (docs/model.md §6.4).
pub const FALLBACK_CELLS_X_WET_SHORT: usize = 16;
/// Fewest lateral cells of the per-contact fallback grid on a dry contact (the forces within 1 % of F_N of
/// 30 × 30; docs/model.md §6.4).
pub const FALLBACK_MIN_CELLS_Y_DRY: usize = 6;
/// Fewest lateral cells of the per-contact fallback grid on a wet contact shorter than
/// [`FALLBACK_LONG_CONTACT`] (the film's forces need more lateral cells than the dry ones).
pub const FALLBACK_MIN_CELLS_Y_WET: usize = 8;
/// Fewest lateral cells of the per-contact fallback grid on a wet contact with a/b ≥ [`FALLBACK_LONG_CONTACT`]
/// (a flange-root contact: the film across its narrow width needs them).
pub const FALLBACK_MIN_CELLS_Y_WET_LONG: usize = 12;
/// a/b from which a wet contact counts as long ([`FALLBACK_MIN_CELLS_Y_WET_LONG`]) [-].
pub const FALLBACK_LONG_CONTACT: f64 = 2.0;
/// Largest cell aspect h_y/h_x of the per-contact fallback grid: a wide contact (a/b < 1) gets the lateral
/// cells that keep its cells within it [-].
pub const FALLBACK_MAX_CELL_ASPECT: f64 = 6.0;

/// The per-contact fallback grid [nx, ny] of a contact ellipse with semi-axes a (along x) and b [m], dry or
/// `wet` (a film is modelled: wetness > 0 under the Tomberger law): [`FALLBACK_CELLS_X`] along x
/// ([`FALLBACK_CELLS_X_WET_SHORT`] on a wet contact shorter than [`FALLBACK_LONG_CONTACT`]); across, the
/// fewest lateral cells of its kind ([`FALLBACK_MIN_CELLS_Y_DRY`], [`FALLBACK_MIN_CELLS_Y_WET`],
/// [`FALLBACK_MIN_CELLS_Y_WET_LONG`]), or more where cells of that many would be longer across than
/// [`FALLBACK_MAX_CELL_ASPECT`] times along x (h_y/h_x = (b/a)·nx/ny), at most [`GRID_REFERENCE`]. The cheapest
/// grids measured to meet the bundled table's accuracy against 30 × 30 (|ΔF|/F_N ≤ 1 %, T_max within 10 K;
/// docs/model.md §6.4). Mode auto's exact solves take it where the parameters keep the default grid
/// (the evaluation policy's `FallbackGrid`).
pub fn fallback_cells(a: f64, b: f64, wet: bool) -> [usize; 2] {
    let long = a >= FALLBACK_LONG_CONTACT * b;
    let (nx, fewest) = match (wet, long) {
        (false, _) => (FALLBACK_CELLS_X, FALLBACK_MIN_CELLS_Y_DRY),
        (true, true) => (FALLBACK_CELLS_X, FALLBACK_MIN_CELLS_Y_WET_LONG),
        (true, false) => (FALLBACK_CELLS_X_WET_SHORT, FALLBACK_MIN_CELLS_Y_WET),
    };
    // cells across that keep h_y/h_x = (b/a)·nx/ny within the aspect bound (a NaN ratio keeps the fewest)
    let for_aspect = (b / a * nx as f64 / FALLBACK_MAX_CELL_ASPECT).ceil();
    let ny = if for_aspect > fewest as f64 {
        for_aspect.min(GRID_REFERENCE as f64) as usize
    } else {
        fewest
    };
    [nx, ny]
}

/// Coupled fixed-point iteration (docs/model.md §9).
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
            tolerance: Param::Tolerance.default_value(),
            max_iterations: Param::MaxIterations.default_value() as usize,
            relaxation: Param::Relaxation.default_value(),
            heat: true,
            fluid_tolerance: Param::FluidTolerance.default_value(),
            max_fluid_sweeps: Param::MaxFluidSweeps.default_value() as usize,
        }
    }
}

/// Whether a value is its type's default (the new keys `tangential`, `pressure` and `layer` are written
/// only when set, so that the parameters of earlier versions keep their text and their tables' fingerprints).
fn is_default<T: Default + PartialEq>(x: &T) -> bool {
    *x == T::default()
}

/// The complete parameter set of one wheel–rail contact.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Params {
    /// The tangential solver (TOML `tangential = "fastsim" | "exact"`; written only when exact).
    #[serde(skip_serializing_if = "is_default")]
    pub tangential: Tangential,
    /// The nominal normal pressure (TOML `pressure = "auto" | "hertz" | "parabolic"`; written only when
    /// not auto); [`Params::pressure_shape`] resolves auto.
    #[serde(skip_serializing_if = "is_default")]
    pub pressure: Pressure,
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
    /// The interfacial layer of the tangential problem (TOML `[layer]`; written only when not the
    /// default, so that the parameters without a layer keep their text and table fingerprints).
    #[serde(skip_serializing_if = "is_default")]
    pub layer: Layer,
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

    /// The pressure used: [`Pressure::Hertz`] or [`Pressure::Parabolic`] as set, and for
    /// [`Pressure::Auto`] Hertz's with the exact tangential solver, the parabola with FASTSIM.
    pub fn pressure_shape(&self) -> Pressure {
        match (self.pressure, self.tangential) {
            (Pressure::Auto, Tangential::Exact) => Pressure::Hertz,
            (Pressure::Auto, Tangential::Fastsim) => Pressure::Parabolic,
            (set, _) => set,
        }
    }

    /// Checks the geometry ([`Geometry::validate`]: the semi-axes against [`spec::SEMI_AXIS_RANGE`], the
    /// curvatures only when no semi-axes are prescribed, since they are not used then), then every other
    /// value against its row of the specification ([`Param`]); the error carries the key.
    pub fn validate(&self) -> Result<()> {
        self.geometry.validate()?;
        for p in Param::ALL {
            if !matches!(p, Param::CurvatureX | Param::CurvatureY) {
                p.spec().check(self.get(p))?;
            }
        }
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
            creepage_x: Input::CreepageX.default_value(),
            creepage_y: Input::CreepageY.default_value(),
            spin: Input::Spin.default_value(),
            normal_force: Input::NormalForce.default_value(),
            speed: Input::Speed.default_value(),
            wetness: Input::Wetness.default_value(),
        }
    }
}

impl OperatingPoint {
    /// Checks the point against the rows of [`Input`]: finite creepages (|ξ|, |η| < 2, since surface
    /// speeds V·(1 ± ξ/2) must stay positive), positive load and speed, wetness in [0, 1].
    pub fn validate(&self) -> Result<()> {
        for i in Input::ALL {
            i.spec().check(self.get(i))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fallback_grid_follows_the_contact_shape_and_the_film() {
        // a dry flange-root contact (a/b = 3.8) and a dry round one: the fewest lateral cells
        assert_eq!(fallback_cells(7.6e-3, 2e-3, false), [24, 6]);
        assert_eq!(fallback_cells(5e-3, 5e-3, false), [24, 6]);
        // wet: more lateral cells, most on a long contact (from a/b = 2 on); fewer along x on a short one
        assert_eq!(fallback_cells(5e-3, 5e-3, true), [16, 8]);
        assert_eq!(fallback_cells(3.99e-3, 2e-3, true), [16, 8]);
        assert_eq!(fallback_cells(4e-3, 2e-3, true), [24, 12]);
        assert_eq!(fallback_cells(7.6e-3, 2e-3, true), [24, 12]);
        // a wide contact: cells no longer across than six times along x, h_y/h_x = (b/a)·nx/ny
        assert_eq!(fallback_cells(2e-3, 4e-3, false), [24, 8]);
        assert_eq!(fallback_cells(1e-3, 1e-2, true), [16, 27]);
        for (a, b, wet) in [(2e-3, 4e-3, false), (1e-3, 1e-2, true), (3e-3, 7e-3, false)] {
            let [nx, ny] = fallback_cells(a, b, wet);
            let aspect = (b / a) * nx as f64 / ny as f64;
            assert!(aspect <= FALLBACK_MAX_CELL_ASPECT, "{a} {b}: {aspect}");
            // one lateral cell fewer would exceed the bound
            assert!((b / a) * nx as f64 / (ny - 1) as f64 > FALLBACK_MAX_CELL_ASPECT);
        }
        // at most the reference grid across, and a non-finite ratio keeps the fewest cells
        assert_eq!(fallback_cells(1e-6, 1.0, false), [24, GRID_REFERENCE]);
        assert_eq!(fallback_cells(f64::NAN, 1e-3, false), [24, 6]);
    }

    #[test]
    fn an_accuracy_target_chooses_the_smallest_measured_grid_meeting_it() {
        let mut g = GridParams {
            nx: 17,
            ny: 23,
            ..GridParams::default()
        };
        assert_eq!(g.cells(), [17, 23]);
        for (accuracy, n) in [
            (0.1, 6),
            (0.04, 6),
            (0.01, 10),
            (0.005, 12),
            (0.002, 20),
            (1.3e-3, 30),
            (1e-3, 60),
            (1e-4, GRID_REFERENCE),
        ] {
            g.accuracy = accuracy;
            assert_eq!(g.cells(), [n, n], "{accuracy}");
        }
        // the measured errors fall with n
        assert!(
            GRID_CONVERGENCE
                .windows(2)
                .all(|w| w[0].0 < w[1].0 && w[0].1 > w[1].1)
        );
        // not written when unset: default parameter sets keep their text and fingerprints
        assert!(!Params::default().to_toml_string().contains("accuracy"));
    }

    #[test]
    fn defaults_are_valid_and_round_trip_through_toml() {
        let p = Params::default();
        p.validate().unwrap();
        let back = Params::from_toml_str(&p.to_toml_string()).unwrap();
        assert_eq!(p, back);
    }

    /// A valid value of a row other than its default (whole for integer rows).
    fn other_value(s: &spec::Spec) -> f64 {
        use spec::Bound;
        let (lo, hi) = match (s.range.lo, s.range.hi) {
            (Bound::Closed(lo) | Bound::Open(lo), Bound::Closed(hi) | Bound::Open(hi)) => (lo, hi),
            _ => (s.default, 3.0 * s.default),
        };
        let x = lo
            + (hi - lo)
                * if s.default == 0.5 * (lo + hi) {
                    0.25
                } else {
                    0.5
                };
        let x = if s.integer { x.round() } else { x };
        assert!(s.range.contains(x) && x != s.default, "{}", s.toml);
        x
    }

    /// The value at a dotted key of a TOML document.
    fn at_key(doc: &str, key: &str) -> f64 {
        let table: toml::Table = toml::from_str(doc).unwrap();
        let mut v = &toml::Value::Table(table);
        for part in key.split('.') {
            v = v
                .get(part)
                .unwrap_or_else(|| panic!("no key {key} in\n{doc}"));
        }
        v.as_float()
            .or_else(|| v.as_integer().map(|i| i as f64))
            .unwrap()
    }

    #[test]
    fn every_row_is_its_field_default_toml_key_and_validation() {
        let defaults = Params::default();
        for p in Param::ALL {
            let s = p.spec();
            assert_eq!(defaults.get(p), s.default, "{}", s.toml);
            let x = other_value(s);
            let mut q = Params::default();
            q.set(p, x);
            assert_eq!(q.get(p), x, "{}", s.toml);
            let text = q.to_toml_string();
            assert_eq!(at_key(&text, s.toml), x, "{}", s.toml);
            assert_eq!(Params::from_toml_str(&text).unwrap(), q);
            q.set(p, f64::NAN);
            match q.validate() {
                Err(Error::Invalid { key, .. }) => assert_eq!(key, Key::Param(p)),
                other => panic!("{}: {other:?}", s.toml),
            }
        }
        let defaults = OperatingPoint::default();
        for i in Input::ALL {
            let s = i.spec();
            assert_eq!(defaults.get(i), s.default, "{}", s.toml);
            let x = other_value(s);
            let mut q = OperatingPoint::default();
            q.set(i, x);
            let text = toml::to_string(&q).unwrap();
            assert_eq!(at_key(&text, s.toml), x, "{}", s.toml);
            assert_eq!(toml::from_str::<OperatingPoint>(&text).unwrap(), q);
            q.set(i, f64::INFINITY);
            match q.validate() {
                Err(Error::Invalid { key, .. }) => assert_eq!(key, Key::Input(i)),
                other => panic!("{}: {other:?}", s.toml),
            }
        }
    }

    #[test]
    fn curvatures_are_not_checked_with_prescribed_semi_axes_which_are() {
        let mut p = Params::default();
        p.geometry.curvature_x = 0.0;
        assert!(p.validate().is_err());
        p.geometry.semi_axes = Some([5e-3, 2.0]);
        let e = p.validate().unwrap_err();
        assert!(
            matches!(
                e,
                Error::Invalid {
                    key: Key::SemiAxisB,
                    ..
                }
            ),
            "{e:?}"
        );
        assert_eq!(
            e.to_string(),
            "invalid value for geometry.semi_axes[1]: 2 (allowed: finite, 0.000001 ..= 1 m)"
        );
        p.geometry.semi_axes = Some([5e-3, 1e-2]);
        p.validate().unwrap();
    }

    /// `tangential` and `pressure` are TOML keys; written only when not their defaults, so that the
    /// default parameters keep the text (and so the table fingerprint) of earlier versions.
    #[test]
    fn tangential_and_pressure_are_keys_written_only_when_set() {
        let p = Params::default();
        let text = p.to_toml_string();
        assert!(
            !text.contains("tangential") && !text.contains("pressure"),
            "{text}"
        );
        assert_eq!(p.pressure_shape(), Pressure::Parabolic);
        let q = Params::from_toml_str("tangential = \"exact\"\n").unwrap();
        assert_eq!(q.tangential, Tangential::Exact);
        assert_eq!(q.pressure_shape(), Pressure::Hertz);
        assert_eq!(Params::from_toml_str(&q.to_toml_string()).unwrap(), q);
        let json = serde_json::to_value(&q).unwrap();
        assert_eq!(json["tangential"], "exact");
        assert!(json.get("pressure").is_none());
        let r =
            Params::from_toml_str("tangential = \"exact\"\npressure = \"parabolic\"\n").unwrap();
        assert_eq!(r.pressure_shape(), Pressure::Parabolic);
        let f = Params::from_toml_str("pressure = \"hertz\"\n").unwrap();
        assert_eq!(
            (f.tangential, f.pressure_shape()),
            (Tangential::Fastsim, Pressure::Hertz)
        );
        assert!(Params::from_toml_str("tangential = \"kalker\"\n").is_err());
    }

    /// `[layer]` is written only when not the default, so that parameter sets without a layer keep their
    /// text and table fingerprints; a set layer is written and read back, and its compliance is h/G₃.
    #[test]
    fn the_layer_is_written_only_when_set() {
        let p = Params::default();
        assert!(!p.to_toml_string().contains("layer"));
        assert_eq!(p.layer.compliance(), 0.0);
        let q = Params::from_toml_str("[layer]\nthickness = 4.1e-4\n").unwrap();
        assert_eq!(q.layer.compliance(), 4.1e-4 / 8.2e9);
        let text = q.to_toml_string();
        assert!(text.contains("[layer]"), "{text}");
        assert_eq!(Params::from_toml_str(&text).unwrap(), q);
        assert!(Params::from_toml_str("[layer]\nthickness = -1e-4\n").is_err());
        assert!(Params::from_toml_str("[layer]\nshear_modulus = 0\n").is_err());
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
