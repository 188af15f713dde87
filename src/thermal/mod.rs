//! Macroscopic contact temperature: moving-source influence coefficients and the wheel–rail heat partition (docs/model.md §7, paper §2.3).

pub(crate) mod convolution;
pub(crate) mod expint;
pub(crate) mod influence;
pub(crate) mod krylov;
pub(crate) mod lattice;
pub(crate) mod partition;

pub use influence::{InfluenceTable, MovingHalfSpace};
pub use partition::{Body, HeatModel, HeatSolution};
