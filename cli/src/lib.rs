//! # wheelrail-cli
//!
//! The tools around the `wheelrail` library: plots (`plot`), the reproduction of the paper's figures
//! (`reproduce`), the Slurm array-job scripts of sharded table builds (`slurm`), the `wheelrail` command line (`src/main.rs`, `src/commands/`) and the FMU packager
//! (`src/bin/package-fmu.rs`). The model itself — and nothing of clap, plotters or anyhow — is in `wheelrail`.

pub mod plot;
pub mod reproduce;
pub mod slurm;
