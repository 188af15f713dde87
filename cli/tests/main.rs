//! Integration tests of the command line, the paper reproduction and table building through the CLI (one
//! binary).

mod cli;
mod paper;
mod table;
