//! What stays fixed while one operating point is solved: the normal contact, the grid with its nominal
//! pressures, the FASTSIM flexibilities, the microcontact model and the heat model.

use super::cache::SetupCache;
use crate::contact::{ContactGrid, HertzContact, HertzShape};
use crate::error::Result;
use crate::fluid::base_height;
use crate::materials::MaterialState;
use crate::microcontact::Microcontact;
use crate::params::{
    FrictionLaw, Geometry, Material, OperatingPoint, Params, Pressure, Tangential,
};
use crate::tangential::exact::{ExactSettings, SteadyRolling};
use crate::tangential::{Creepages, Flexibilities, KalkerCoefficients};
use crate::thermal::HeatModel;
use std::sync::Arc;

/// The load-independent part of the nominal normal contact of a geometry (docs/model.md §2): the Hertz
/// shape of the curvatures with E* at the bulk temperature, or the prescribed semi-axes. Made once per
/// geometry; [`ContactShape::contact`] is then cheap (a cube root), bit for bit [`normal_contact`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactShape {
    /// Hertz from the curvatures.
    Hertz(HertzShape),
    /// Prescribed semi-axes [a, b] [m].
    Prescribed([f64; 2]),
}

impl ContactShape {
    /// The shape of `geometry` for the steel `material` (E* at its bulk temperature).
    pub fn of(geometry: &Geometry, material: &Material) -> Result<ContactShape> {
        match geometry.semi_axes {
            Some(axes) => Ok(ContactShape::Prescribed(axes)),
            None => {
                let m = material.at(material.bulk_temperature);
                HertzShape::from_curvatures(geometry.curvature_x, geometry.curvature_y, m.e_star)
                    .map(ContactShape::Hertz)
            }
        }
    }

    /// The nominal normal contact at `normal_force` [N]: Hertz (docs/model.md §2), or the prescribed
    /// semi-axes with p0 = 3·F_N/(2π·a·b).
    pub fn contact(&self, normal_force: f64) -> Result<HertzContact> {
        match *self {
            ContactShape::Hertz(h) => h.contact(normal_force),
            ContactShape::Prescribed([a, b]) => HertzContact::from_semi_axes(a, b, normal_force),
        }
    }
}

/// The nominal normal contact for a parameter set and a load: Hertz from the curvatures (E* at the bulk
/// temperature), or the prescribed semi-axes (docs/model.md §2; [`ContactShape`]).
pub fn normal_contact(params: &Params, normal_force: f64) -> Result<HertzContact> {
    ContactShape::of(&params.geometry, &params.material)?.contact(normal_force)
}

/// Wheel and rail surface speeds through the contact, V·(1 ± ξ/2) [m/s] (docs/model.md §1).
pub fn surface_speeds(point: &OperatingPoint) -> (f64, f64) {
    (
        point.speed * (1.0 + point.creepage_x / 2.0),
        point.speed * (1.0 - point.creepage_x / 2.0),
    )
}

/// Everything fixed for one operating point of the coupled (not closed-form) laws.
pub(super) struct Setup<'a> {
    /// The parameters (validated).
    pub params: &'a Params,
    /// The operating point (validated).
    pub point: &'a OperatingPoint,
    /// The nominal normal contact.
    pub hertz: HertzContact,
    /// Creepages (ξ, η, φ) of the point.
    pub creep: Creepages,
    /// FASTSIM flexibilities of the contact, with the interfacial layer's compliance (docs/model.md §6.7).
    pub flex: Flexibilities,
    /// The contact grid.
    pub grid: ContactGrid,
    /// Nominal pressure per cell [Pa]: the parabola with the Hertz force, or Hertz's ellipsoid
    /// ([`Params::pressure_shape`]); the microcontact, fluid, friction and heat models all take it.
    pub p_n: Vec<f64>,
    /// The microcontact model of the roughness.
    pub micro: Arc<Microcontact>,
    /// Cell base height d_b (P7) [m].
    pub base_height: f64,
    /// The heat model (None with heat switched off or in pure rolling, where nothing heats).
    pub heat: Option<Arc<HeatModel>>,
    /// The exact tangential solver's influence operator of the grid (None with FASTSIM).
    pub steady: Option<Arc<SteadyRolling>>,
    /// The settings of every exact tangential solve (the defaults: tolerance 1e-7, 500 sweeps).
    pub exact: ExactSettings,
}

impl<'a> Setup<'a> {
    /// The grid of the contact `hertz` with its nominal pressure ([`Params::pressure_shape`]), the flexibilities from the Kalker
    /// coefficients and the shear modulus of `mat0` (the material at the bulk temperature) with the
    /// interfacial layer's compliance, the heat model at the surface speeds, the microcontact model of
    /// the roughness and, with the exact tangential solver, its influence operator of the grid (G and ν
    /// of `mat0`, the layer), the last three from `cache` when it holds them for these inputs.
    pub fn new(
        params: &'a Params,
        point: &'a OperatingPoint,
        hertz: HertzContact,
        mat0: &MaterialState,
        kalker: &KalkerCoefficients,
        creep: Creepages,
        cache: &SetupCache,
    ) -> Result<Self> {
        let [nx, ny] = params.grid.cells();
        let grid = ContactGrid::for_contact(&hertz, nx, ny);
        let layer = params.layer.compliance();
        let flex =
            Flexibilities::new(hertz.a, hertz.b, mat0.shear_modulus, kalker).with_layer(layer);
        let pressure = match params.pressure_shape() {
            Pressure::Hertz => HertzContact::hertz_pressure,
            Pressure::Parabolic | Pressure::Auto => HertzContact::parabolic_pressure,
        };
        let p_n: Vec<f64> = grid
            .cells
            .iter()
            .map(|c| pressure(&hertz, c.x, c.y))
            .collect();
        let rolling = creep.xi == 0.0 && creep.eta == 0.0 && creep.phi == 0.0;
        let heat = if params.solver.heat && !rolling {
            let (v_wheel, v_rail) = surface_speeds(point);
            Some(cache.heat_model(&grid, v_wheel, v_rail, &params.material)?)
        } else {
            None
        };
        let micro = cache.microcontact(&params.roughness)?;
        let steady = match params.tangential {
            Tangential::Exact => {
                Some(cache.steady_rolling(&grid, mat0.shear_modulus, mat0.poisson, layer)?)
            }
            Tangential::Fastsim => None,
        };
        Ok(Self {
            params,
            point,
            hertz,
            creep,
            flex,
            base_height: base_height(micro.surface().z_s, params.fluid.psi_b),
            grid,
            p_n,
            micro,
            heat,
            steady,
            exact: ExactSettings::default(),
        })
    }

    /// Whether the law models the interfacial fluid: only the Tomberger law, through the failure stress
    /// and the metallic area (the others ignore the wetness).
    pub fn models_fluid(&self) -> bool {
        match self.params.friction.law {
            FrictionLaw::Tomberger => true,
            FrictionLaw::Constant | FrictionLaw::Polach => false,
        }
    }

    /// Whether the temperature feeds back into the traction (heat on and the Tomberger law, whose failure
    /// stress depends on it): only then does the outer iteration iterate.
    pub fn temperature_feeds_back(&self) -> bool {
        self.heat.is_some()
            && match self.params.friction.law {
                FrictionLaw::Tomberger => true,
                FrictionLaw::Constant | FrictionLaw::Polach => false,
            }
    }

    /// The bulk temperature T0 [K].
    pub fn bulk_temperature(&self) -> f64 {
        self.params.material.bulk_temperature
    }
}
