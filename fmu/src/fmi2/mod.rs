//! A generic FMI 2.0 Co-Simulation and Model Exchange layer: C types, state machines, instance, logging,
//! FMU states, derivative helper and `modelDescription.xml` generation, for any [`model::Model`].

pub mod api;
pub mod derivative;
pub mod description;
pub mod ffi;
pub mod handles;
pub mod instance;
pub mod logging;
pub mod model;
pub mod resources;
pub mod snapshot;
pub mod state;
pub mod variables;
pub mod x87;

#[cfg(test)]
mod tests;
