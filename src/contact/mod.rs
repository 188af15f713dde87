//! Nominal normal contact: Hertz ellipse from curvatures, parabolic pressure, and the contact grid.

pub(crate) mod grid;
pub(crate) mod hertz;

pub use grid::{Cell, ContactGrid, Strip};
pub use hertz::{HertzContact, HertzShape, complete_elliptic_integrals};
