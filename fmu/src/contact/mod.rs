//! WheelRailFriction: the wheel–rail contact model as an FMU (variable table, translation to and from the
//! library's evaluation policy, the `mode` parameter and its lookup table).

pub mod mode;
pub mod model;
pub mod state;
pub mod variables;

pub use model::WheelRailModel;
