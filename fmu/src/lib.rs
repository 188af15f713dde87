//! FMI 2.0 Co-Simulation boundary of the wheelrail friction model (issue 4).
#![allow(non_snake_case)] // the library name is the FMI modelIdentifier WheelRailFriction

pub mod fmi2;
