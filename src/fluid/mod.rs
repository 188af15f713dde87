//! Interfacial fluid (paper §2.5, docs/model.md §8): cell geometry from the roughness statistics and the
//! mass-conserving boundary/mixed-lubrication film solve.

mod band;
pub(crate) mod cell_geometry;
pub(crate) mod film;

pub use cell_geometry::{CellGeometry, CellHeights, base_height};
pub use film::{
    FilmProblem, FilmSolution, FilmStart, Regime, intake_share, solve_film, solve_film_newton,
    takes_in_all,
};
