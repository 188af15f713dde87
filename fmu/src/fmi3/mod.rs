//! A generic FMI 3.0 Co-Simulation and Model Exchange layer for a model of one element
//! ([`arrays::ArrayModel`]: the FMI 2.0 layer's [`crate::fmi2::model::Model`] with its arrays): one
//! instance holds any number of elements (a structural parameter), every input and output is an array over
//! them, and a step evaluates the elements on a pool of threads. C types, the state machine, the instance,
//! FMU states, derivatives and `modelDescription.xml`; the variable table, the values, logging and the
//! model contract are the FMI 2.0 layer's.

pub mod api;
pub mod arrays;
pub mod description;
pub mod ffi;
pub mod instance;
pub mod state;
pub mod workers;

#[cfg(test)]
mod tests;
