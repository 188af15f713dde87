//! Integration tests of the library and of the FMU's shared library (one binary; those of the command line
//! are in cli/tests).

mod architecture;
mod fallback_grid;
mod fluid;
mod fmu;
mod layer;
mod solver;
mod tangential;
