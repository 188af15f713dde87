//! Set-up reused between solves: the parts of a solve's set-up that depend only on the geometry, the
//! grid, the surface speeds and the parameters, kept with the inputs they were made from.
//!
//! Each entry is a pure function of its key (the complete inputs of its constructor, floats compared bit
//! for bit), so a solve with a cached set-up gives the same bits as one without, whatever was solved
//! before: the cache changes no result and is part of no state. One entry per kind (the last one made):
//! the contact shape of a geometry (docs/model.md §2), the microcontact model of the roughness (§4) and
//! the heat model of a grid and a pair of surface speeds (§7), which is most of the fixed cost of a
//! solve. A heat model is reused only while the contact ellipse (so the grid), the rolling speed and the
//! longitudinal creepage (so the surface speeds V·(1 ± ξ/2)) are unchanged: the influence coefficients
//! depend on the Péclet number v·h_x/(2κ) and the aspect h_y/h_x through quadratures with no exact
//! rescaling, so any other speed or ellipse needs new tables.

use crate::contact::ContactGrid;
use crate::error::Result;
use crate::microcontact::Microcontact;
use crate::params::{Geometry, Material, Roughness};
use crate::thermal::HeatModel;
use std::sync::{Arc, Mutex, PoisonError};

use super::setup::ContactShape;

/// The inputs of a heat model: grid (semi-axes as bits, cell counts), surface speeds (bits), material.
#[derive(Debug, PartialEq)]
struct HeatKey {
    semi_axes: [u64; 2],
    cells: [usize; 2],
    speeds: [u64; 2],
    material: Material,
}

impl HeatKey {
    fn new(grid: &ContactGrid, v_wheel: f64, v_rail: f64, material: &Material) -> Self {
        Self {
            semi_axes: [grid.a.to_bits(), grid.b.to_bits()],
            cells: [grid.nx, grid.ny],
            speeds: [v_wheel.to_bits(), v_rail.to_bits()],
            material: material.clone(),
        }
    }
}

/// The entries, each with the inputs it was made from.
#[derive(Debug, Default)]
struct Entries {
    shape: Option<((Geometry, Material), ContactShape)>,
    micro: Option<(Roughness, Arc<Microcontact>)>,
    heat: Option<(HeatKey, Arc<HeatModel>)>,
    /// How many set-ups were taken from the cache (shape, microcontact and heat model counted alike).
    hits: usize,
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
    pub(super) fn shape(&self, geometry: &Geometry, material: &Material) -> Result<ContactShape> {
        get_or_make(
            self,
            |e| &mut e.shape,
            (geometry.clone(), material.clone()),
            || ContactShape::of(geometry, material),
        )
    }

    /// [`Microcontact::new`] of `roughness`.
    pub(super) fn microcontact(&self, roughness: &Roughness) -> Result<Arc<Microcontact>> {
        get_or_make(
            self,
            |e| &mut e.micro,
            roughness.clone(),
            || Microcontact::new(roughness).map(Arc::new),
        )
    }

    /// [`HeatModel::new`] of `grid` at the surface speeds `v_wheel`, `v_rail` [m/s] for `material`.
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
            || HeatModel::new(grid, v_wheel, v_rail, material).map(Arc::new),
        )
    }

    /// How many set-up parts solves have taken from the cache so far.
    pub fn hits(&self) -> usize {
        self.lock().hits
    }
}
