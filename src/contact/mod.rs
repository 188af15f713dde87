//! Nominal normal contact: Hertz ellipse from curvatures, parabolic pressure, and the contact grid.

pub mod grid;
pub mod hertz;

pub use grid::{Cell, ContactGrid, Strip};
pub use hertz::{HertzContact, HertzShape, complete_elliptic_integrals};
