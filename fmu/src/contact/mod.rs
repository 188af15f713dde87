//! WheelRailFriction: the wheel–rail contact model as an FMU (variable table, mapping, evaluator).

pub mod evaluator;
pub mod model;
pub mod variables;

pub use model::WheelRailModel;
