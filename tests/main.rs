//! All integration tests in one binary (one link on a small machine).

mod cli;
mod fluid;
mod fmu;
mod paper;
mod solver;
mod table;
