//! Integration tests of the library and of the FMU's shared library (one binary; those of the command line
//! are in cli/tests).

mod architecture;
mod fluid;
mod fmu;
mod solver;
mod tangential;
