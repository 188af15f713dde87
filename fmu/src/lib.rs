//! # WheelRailFriction FMU
//!
//! The wheel–rail friction model of the `wheelrail` library as an FMI 2.0 FMU for Co-Simulation and Model
//! Exchange (one binary, modelIdentifier `WheelRailFriction`): one instance per wheel–rail contact,
//! quasi-static (the outputs are a function of the current inputs and parameters), any number of
//! instances per process on any threads. The same binary is the FMI 3.0 FMU: one instance holds any number
//! of contacts, evaluated in parallel.
//!
//! - [`fmi2`]: a generic FMI 2.0 Co-Simulation and Model Exchange layer (C types, state machines,
//!   instance, logging, FMU states, finite-difference derivatives, `modelDescription.xml`), independent
//!   of this model;
//! - [`contact`]: the variable table and the mapping to the library (no physics of its own);
//! - [`fmi3`]: a generic FMI 3.0 layer over the same model contract: one instance holds any number of
//!   contacts (structural parameter `contacts`), every input and output an array over them, evaluated on
//!   `threads` threads;
//! - `exports`, `exports_fmi3`: the exported C functions, one call each into [`fmi2::api`] and
//!   [`fmi3::api`] (one binary serves both versions).
//!
//! `package-fmu` (in `src/bin`) writes `modelDescription.xml` and packs `WheelRailFriction.fmu`.
#![allow(non_snake_case)] // the library name is the FMI modelIdentifier WheelRailFriction

pub mod contact;
pub mod exports;
pub mod exports_fmi3;
pub mod fmi2;
pub mod fmi3;

/// The `modelDescription.xml` of this FMU.
pub fn model_description() -> String {
    fmi2::description::model_description(&contact::variables::INFO)
}

/// The `modelDescription.xml` of the FMI 3.0 FMU (`WheelRailFriction-fmi3.fmu`).
pub fn model_description_fmi3() -> String {
    fmi3::description::model_description(&contact::variables::INFO, &contact::variables::ARRAYS)
}
