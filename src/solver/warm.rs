//! Warm starts: a nearby solution's state as the starting point of a solve.

use super::solution::{Fields, Solution};
use crate::contact::ContactGrid;
use crate::fluid::FilmStart;

/// Where a solve can start from: the state of a nearby solution (the previous point of a traction–creepage
/// sweep, the previous FMU step, a neighbouring table point), one value per active cell of its grid.
#[derive(Debug, Clone, PartialEq)]
pub struct WarmStart {
    /// Grid cells along x of the solution.
    pub nx: usize,
    /// Grid cells along y.
    pub ny: usize,
    /// Surface temperature [K].
    pub temperature: Vec<f64>,
    /// Separation d of the mean planes [m].
    pub separation: Vec<f64>,
    /// Fluid pressure p_f [Pa].
    pub fluid_pressure: Vec<f64>,
    /// Fluid height l_f [m].
    pub fluid_height: Vec<f64>,
    /// Tangential traction on the wheel [Pa]: the start of the exact tangential solve (docs/model.md
    /// §6.5; FASTSIM needs none).
    pub traction: Vec<[f64; 2]>,
}

impl WarmStart {
    /// The warm start of a solution's fields.
    pub fn of(fields: &Fields) -> Self {
        Self {
            nx: fields.grid.nx,
            ny: fields.grid.ny,
            temperature: fields.temperature.clone(),
            separation: fields.separation.clone(),
            fluid_pressure: fields.fluid_pressure.clone(),
            fluid_height: fields.fluid_height.clone(),
            traction: fields.traction.clone(),
        }
    }

    /// Whether it fits `grid`: same nx × ny and as many cells (the grid is normalised by the semi-axes,
    /// so the active cells are the same whatever the load).
    pub(super) fn fits(&self, grid: &ContactGrid) -> bool {
        let n = grid.len();
        self.nx == grid.nx
            && self.ny == grid.ny
            && [
                &self.temperature,
                &self.separation,
                &self.fluid_pressure,
                &self.fluid_height,
            ]
            .iter()
            .all(|v| v.len() == n)
            && self.traction.len() == n
    }

    /// The film as the film solver's starting iterate (None without fluid).
    pub(super) fn film(&self) -> Option<FilmStart<'_>> {
        self.fluid_height
            .iter()
            .any(|h| *h > 0.0)
            .then_some(FilmStart {
                separation: &self.separation,
                fluid_pressure: &self.fluid_pressure,
                fluid_height: &self.fluid_height,
            })
    }
}

impl Solution {
    /// The state to start a nearby solve from (None for the closed-form Polach law).
    pub fn warm_start(&self) -> Option<WarmStart> {
        self.fields.as_ref().map(WarmStart::of)
    }
}
