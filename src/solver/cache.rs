//! Set-up reused between solves: the parts of a solve's set-up that depend only on the geometry, the
//! grid, the surface speeds and the parameters, kept with the inputs they were made from.
//!
//! Each entry is a pure function of its key (the bit patterns of every number its constructor reads), so
//! a solve with a cached set-up gives the same bits as one without, whatever was solved
//! before: the cache changes no result and is part of no state. One entry per kind (the last one made):
//! the contact shape of a geometry (docs/model.md §2), the microcontact model of the roughness (§4) and
//! the heat model of a grid and a pair of surface speeds (§7), which is most of the fixed cost of a
//! solve, and the exact tangential solver's influence operator of a grid and the elastic constants
//! (§6.5, `tangential = "exact"` only). A heat model is reused only while the contact ellipse (so the grid), the rolling speed and the
//! longitudinal creepage (so the surface speeds V·(1 ± ξ/2)) are unchanged: the influence coefficients
//! depend on the Péclet number v·h_x/(2κ) and the aspect h_y/h_x through quadratures with no exact
//! rescaling, so any other speed or ellipse needs new tables.

use crate::contact::ContactGrid;
use crate::error::Result;
use crate::microcontact::Microcontact;
use crate::params::{Geometry, Material, Roughness};
use crate::tangential::exact::SteadyRolling;
use crate::thermal::HeatModel;
use crate::thermal::lattice::RecentNodes;
use std::sync::{Arc, Mutex, PoisonError};

use super::setup::ContactShape;

/// Bit patterns of floats: equal keys are equal inputs (unlike `==`, which equates 0.0 and −0.0).
fn bits<const N: usize>(values: [f64; N]) -> [u64; N] {
    values.map(f64::to_bits)
}

/// The inputs of a contact shape ([`ContactShape::of`]): curvatures A, B, the prescribed semi-axes (if
/// any) and E* at the bulk temperature.
#[derive(Debug, PartialEq)]
struct ShapeKey {
    curvatures: [u64; 2],
    semi_axes: Option<[u64; 2]>,
    e_star: u64,
}

impl ShapeKey {
    fn new(geometry: &Geometry, material: &Material) -> Self {
        Self {
            curvatures: bits([geometry.curvature_x, geometry.curvature_y]),
            semi_axes: geometry.semi_axes.map(bits),
            e_star: material.at(material.bulk_temperature).e_star.to_bits(),
        }
    }
}

/// The inputs of a microcontact model ([`Microcontact::new`]): every field of the roughness (destructured,
/// so that a new field cannot be left out of the key).
fn roughness_key(r: &Roughness) -> [u64; 6] {
    let Roughness {
        k_r,
        z_s_smooth,
        z_s_span,
        ratio_smooth,
        ratio_span,
        beta,
    } = *r;
    bits([k_r, z_s_smooth, z_s_span, ratio_smooth, ratio_span, beta])
}

/// The inputs of a contact grid ([`ContactGrid::new`]): its semi-axes and cell counts.
#[derive(Debug, PartialEq)]
struct GridKey {
    semi_axes: [u64; 2],
    cells: [usize; 2],
}

impl GridKey {
    fn new(grid: &ContactGrid) -> Self {
        Self {
            semi_axes: bits([grid.a, grid.b]),
            cells: [grid.nx, grid.ny],
        }
    }
}

/// The inputs of a heat model ([`HeatModel::new`]): the grid, the surface speeds and the material's
/// conductivity, density and specific heat.
#[derive(Debug, PartialEq)]
struct HeatKey {
    grid: GridKey,
    speeds: [u64; 2],
    thermal: [u64; 3],
}

impl HeatKey {
    fn new(grid: &ContactGrid, v_wheel: f64, v_rail: f64, material: &Material) -> Self {
        Self {
            grid: GridKey::new(grid),
            speeds: bits([v_wheel, v_rail]),
            thermal: bits([
                material.conductivity,
                material.density,
                material.specific_heat,
            ]),
        }
    }
}

/// The inputs of a steady-rolling operator ([`SteadyRolling::with_layer`]): the grid, the shear modulus,
/// Poisson's ratio and the interfacial layer's compliance h/G₃.
#[derive(Debug, PartialEq)]
struct SteadyKey {
    grid: GridKey,
    elastic: [u64; 3],
}

/// The entries, each with the inputs it was made from.
#[derive(Debug, Default)]
struct Entries {
    shape: Option<(ShapeKey, ContactShape)>,
    micro: Option<([u64; 6], Arc<Microcontact>)>,
    heat: Option<(HeatKey, Arc<HeatModel>)>,
    steady: Option<(SteadyKey, Arc<SteadyRolling>)>,
    /// How many set-ups were taken from the cache (shape, microcontact, heat model and steady-rolling
    /// operator counted alike).
    hits: usize,
    /// The lattice nodes of the last heat models made (their next one mostly needs the same).
    nodes: RecentNodes,
}

/// The reusable set-up of one model's solves (see the module documentation). Shared between threads
/// (a lock around the entries; set-ups are made outside it).
#[derive(Debug, Default)]
pub struct SetupCache {
    entries: Mutex<Entries>,
}

/// The entry `slot` if its key equals `key`, else `make()` stored under `key`.
fn get_or_make<K: PartialEq, V: Clone>(
    cache: &SetupCache,
    slot: fn(&mut Entries) -> &mut Option<(K, V)>,
    key: K,
    make: impl FnOnce() -> Result<V>,
) -> Result<V> {
    {
        let mut entries = cache.lock();
        if let Some((k, v)) = slot(&mut entries)
            && *k == key
        {
            let v = v.clone();
            entries.hits += 1;
            return Ok(v);
        }
    }
    let value = make()?;
    *slot(&mut cache.lock()) = Some((key, value.clone()));
    Ok(value)
}

impl SetupCache {
    /// The entries (a panic while holding the lock left them consistent: each is replaced whole).
    fn lock(&self) -> std::sync::MutexGuard<'_, Entries> {
        self.entries.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// [`ContactShape::of`] `geometry` and `material`.
    pub(crate) fn shape(&self, geometry: &Geometry, material: &Material) -> Result<ContactShape> {
        get_or_make(
            self,
            |e| &mut e.shape,
            ShapeKey::new(geometry, material),
            || ContactShape::of(geometry, material),
        )
    }

    /// [`Microcontact::new`] of `roughness`.
    pub(super) fn microcontact(&self, roughness: &Roughness) -> Result<Arc<Microcontact>> {
        get_or_make(
            self,
            |e| &mut e.micro,
            roughness_key(roughness),
            || Microcontact::new(roughness).map(Arc::new),
        )
    }

    /// [`HeatModel::interpolated`] of `grid` at the surface speeds `v_wheel`, `v_rail` [m/s] for `material`.
    pub(super) fn heat_model(
        &self,
        grid: &ContactGrid,
        v_wheel: f64,
        v_rail: f64,
        material: &Material,
    ) -> Result<Arc<HeatModel>> {
        get_or_make(
            self,
            |e| &mut e.heat,
            HeatKey::new(grid, v_wheel, v_rail, material),
            || {
                let mut recent = std::mem::take(&mut self.lock().nodes);
                let model =
                    HeatModel::interpolated_with(grid, v_wheel, v_rail, material, &mut recent);
                self.lock().nodes = recent;
                model.map(Arc::new)
            },
        )
    }

    /// [`SteadyRolling::with_layer`] of `grid` for shear modulus `shear_modulus` [Pa], Poisson's ratio
    /// `poisson` and the interfacial layer's compliance `layer_compliance` = h/G₃ [m/Pa].
    pub(super) fn steady_rolling(
        &self,
        grid: &ContactGrid,
        shear_modulus: f64,
        poisson: f64,
        layer_compliance: f64,
    ) -> Result<Arc<SteadyRolling>> {
        get_or_make(
            self,
            |e| &mut e.steady,
            SteadyKey {
                grid: GridKey::new(grid),
                elastic: bits([shear_modulus, poisson, layer_compliance]),
            },
            || {
                SteadyRolling::with_layer(grid, shear_modulus, poisson, layer_compliance)
                    .map(Arc::new)
            },
        )
    }

    /// How many set-up parts solves have taken from the cache so far.
    pub fn hits(&self) -> usize {
        self.lock().hits
    }
}
