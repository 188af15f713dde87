//! Fast creep-force laws users compare the model against (MODEL.md §12).

pub mod polach;

pub use polach::{PolachForces, polach};
