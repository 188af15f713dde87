//! Fast creep-force laws users compare the model against (docs/model.md §12).

pub mod polach;

pub use polach::{PolachForces, polach};
