//! Integration tests of the command line, the FMU packager, the paper reproduction and table building
//! through the CLI (one binary).

mod cli;
mod fit;
mod package;
mod paper;
mod table;
