//! Tangential contact (docs/model.md §6): Kalker's creepage coefficients and FASTSIM with a locally varying
//! adhesion limit.

pub mod exact;
pub mod fastsim;
pub mod kalker;

pub use fastsim::{Creepages, Flexibilities, TractionField, fastsim};
pub use kalker::{KalkerCoefficients, kalker_coefficients};
