//! Macroscopic contact temperature: moving-source influence coefficients and the wheel–rail heat partition (docs/model.md §7, paper §2.3).

pub mod convolution;
pub mod expint;
pub mod influence;
pub mod krylov;
pub mod lattice;
pub mod partition;

pub use influence::{InfluenceTable, MovingHalfSpace};
pub use partition::{Body, HeatModel, HeatSolution};
