//! `wheelrail reproduce`: the paper's result figures (Figs. 5, 7, 10–21) as CSV, PNG and SVG.

use super::grid_arg;
use anyhow::{Context, Result};
use clap::Args;
use std::path::PathBuf;
use std::time::Instant;
use wheelrail::Params;
use wheelrail_cli::reproduce::{FigureId, Settings, compute};

/// Arguments of `wheelrail reproduce`.
#[derive(Debug, Args)]
pub struct ReproduceArgs {
    /// Directory for the figures (fig05.csv, fig05.png, fig05.svg, ...); created if missing.
    #[arg(long, value_name = "DIR", default_value = "paper-figures")]
    out: PathBuf,
    /// Only these figures (repeatable or comma-separated: 5, 7, 10 ..= 21, or fig16).
    #[arg(long, value_name = "FIG", value_delimiter = ',')]
    only: Vec<String>,
    /// Grid cells NX,NY of every solve (coarse by default: the f_max sweeps take about two thousand solves).
    #[arg(long, value_name = "NX,NY", default_value = "20,20")]
    grid: String,
    /// Parameter file (TOML) replacing the project defaults (its grid is overridden by --grid).
    #[arg(long, value_name = "FILE.toml")]
    params: Option<PathBuf>,
}

/// Runs `wheelrail reproduce`, printing progress on stderr and the written files on stdout.
pub fn run(a: &ReproduceArgs) -> Result<()> {
    let figures = if a.only.is_empty() {
        FigureId::ALL.to_vec()
    } else {
        let mut f = a
            .only
            .iter()
            .map(|s| FigureId::parse(s))
            .collect::<wheelrail::Result<Vec<_>>>()?;
        f.sort();
        f.dedup();
        f
    };
    let mut settings = Settings::default();
    if let Some(path) = &a.params {
        settings.params = Params::from_toml_file(path)?;
    }
    let (nx, ny) = grid_arg(&a.grid)?;
    settings.params.grid.nx = nx;
    settings.params.grid.ny = ny;
    let start = Instant::now();
    let progress = |msg: &str| eprintln!("[{:7.1} s] {msg}", start.elapsed().as_secs_f64());
    for id in figures {
        let t = Instant::now();
        progress(&format!("{id}: computing"));
        let fig = compute(id, &settings, &progress).with_context(|| format!("computing {id}"))?;
        for path in fig.write(&a.out).with_context(|| format!("writing {id}"))? {
            println!("{}", path.display());
        }
        progress(&format!("{id}: done in {:.1} s", t.elapsed().as_secs_f64()));
    }
    progress("all figures written");
    Ok(())
}
