//! Tangential contact (docs/model.md §6): Kalker's creepage coefficients and FASTSIM with a locally varying
//! adhesion limit.

pub mod exact;
pub(crate) mod fastsim;
pub(crate) mod kalker;

pub use fastsim::{Creepages, Flexibilities, TractionField, fastsim};
pub use kalker::{KalkerCoefficients, kalker_coefficients};
