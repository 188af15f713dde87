//! Reproduction of the paper's computed results (Tomberger et al., Wear 271 (2011), §3; docs/model.md §11):
//! each of Figs. 5, 7 and 10–21 as data (a table, written as CSV) and a plot (PNG and SVG) with the paper's
//! axes, legend and units, computed with the exact solver at the paper's conditions (Table 1 unless the
//! figure says otherwise).
//!
//! The paper's material curves and roughness mapping are not published; the project defaults of docs/model.md
//! (with the recalibrated z_s(k_r) of `docs/calibration.md`) stand in, so trends are comparable, numbers are
//! not. `docs/paper-comparison.md` holds each figure against the paper's statement.

mod figures;
pub mod fmax;

pub use figures::boundary_lubrication_wetness;
pub use fmax::{MaxSearch, TractionMaximum, solve_converged, traction_maximum};

use crate::plot::{Chart, Series, heat_map, line_chart};
use std::path::{Path, PathBuf};
use wheelrail::contact::ContactGrid;
use wheelrail::error::{Error, Result};
use wheelrail::params::Params;

/// The paper's result figures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FigureId {
    /// A_m/A_n and d/z_s against k_r at ambient temperature and constant load.
    Fig5,
    /// Surface-fraction curves A_m,z/A_n of a smooth and a rough surface.
    Fig7,
    /// Void height l_c − l_m and fluid height l_f at y = 0, pure rolling, water.
    Fig10,
    /// Fluid pressure p_f over the contact, pure rolling, water.
    Fig11,
    /// Nominal metallic pressure over the contact, pure rolling, water.
    Fig12,
    /// A_m/A_n and μ at y = 0, pure rolling, water.
    Fig13,
    /// Adhesion limit τ_l at y = 0 at 30 m/s and V → 0, pure rolling, water.
    Fig14,
    /// Traction–creepage curves, dry and water, two speeds.
    Fig15,
    /// f_max against V, dry, several k_r.
    Fig16,
    /// f_max against V, water, several k_r and a boundary-lubricated contact.
    Fig17,
    /// f_max against k_r, dry, several V.
    Fig18,
    /// f_max against k_r, water, several V.
    Fig19,
    /// f_max against F_N, dry, several k_r.
    Fig20,
    /// f_max against F_N, water, boundary and mixed lubrication.
    Fig21,
}

impl FigureId {
    /// Every figure, in the paper's order.
    pub const ALL: [FigureId; 14] = [
        FigureId::Fig5,
        FigureId::Fig7,
        FigureId::Fig10,
        FigureId::Fig11,
        FigureId::Fig12,
        FigureId::Fig13,
        FigureId::Fig14,
        FigureId::Fig15,
        FigureId::Fig16,
        FigureId::Fig17,
        FigureId::Fig18,
        FigureId::Fig19,
        FigureId::Fig20,
        FigureId::Fig21,
    ];

    /// The paper's figure number.
    pub fn number(self) -> u32 {
        match self {
            FigureId::Fig5 => 5,
            FigureId::Fig7 => 7,
            FigureId::Fig10 => 10,
            FigureId::Fig11 => 11,
            FigureId::Fig12 => 12,
            FigureId::Fig13 => 13,
            FigureId::Fig14 => 14,
            FigureId::Fig15 => 15,
            FigureId::Fig16 => 16,
            FigureId::Fig17 => 17,
            FigureId::Fig18 => 18,
            FigureId::Fig19 => 19,
            FigureId::Fig20 => 20,
            FigureId::Fig21 => 21,
        }
    }

    /// Parses "16", "fig16", "Fig. 16" or "fig16" (case-insensitive).
    pub fn parse(text: &str) -> Result<Self> {
        let t = text.trim().to_ascii_lowercase();
        let digits = t
            .strip_prefix("fig")
            .map(|r| r.trim_start_matches('.').trim())
            .unwrap_or(&t);
        digits
            .parse::<u32>()
            .ok()
            .and_then(|n| Self::ALL.into_iter().find(|f| f.number() == n))
            .ok_or_else(|| Error::OutOfRange {
                name: "figure".into(),
                value: text.into(),
                allowed: "one of 5, 7, 10 ..= 21".into(),
            })
    }

    /// File stem of the figure's outputs, e.g. `fig05`.
    pub fn stem(self) -> String {
        format!("fig{:02}", self.number())
    }
}

impl std::fmt::Display for FigureId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Fig. {}", self.number())
    }
}

/// Settings of a reproduction run.
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// The base parameter set (project defaults; its grid is the grid of every solve).
    pub params: Params,
    /// How f_max is searched (Figs. 16–21).
    pub search: MaxSearch,
}

impl Default for Settings {
    /// Project defaults on a 20 × 20 grid (coarse: the f_max sweeps need about two thousand solves).
    fn default() -> Self {
        let mut params = Params::default();
        params.grid.nx = 20;
        params.grid.ny = 20;
        Self {
            params,
            search: MaxSearch::default(),
        }
    }
}

/// A table of computed values: column names with units, rows of text cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Column headers, units in brackets-free snake case suffixes (e.g. `speed_m_s`).
    pub columns: Vec<String>,
    /// Rows, one text cell per column.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// The values of one numeric column (NaN where a cell does not parse).
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let k = self.columns.iter().position(|c| c == name)?;
        Some(
            self.rows
                .iter()
                .map(|r| r[k].parse().unwrap_or(f64::NAN))
                .collect(),
        )
    }

    /// The table as CSV text (cells with commas or quotes are quoted).
    pub fn to_csv(&self) -> String {
        let quote = |s: &str| {
            if s.contains([',', '"', '\n']) {
                format!("\"{}\"", s.replace('"', "\"\""))
            } else {
                s.to_string()
            }
        };
        let mut out = String::new();
        for row in std::iter::once(&self.columns).chain(&self.rows) {
            let cells: Vec<String> = row.iter().map(|c| quote(c)).collect();
            out.push_str(&cells.join(","));
            out.push('\n');
        }
        out
    }
}

/// How a figure is drawn.
#[derive(Debug, Clone)]
pub enum Plot {
    /// Curves y(x).
    Lines {
        /// x-axis label with unit.
        x_label: String,
        /// y-axis label with unit.
        y_label: String,
        /// The curves.
        series: Vec<Series>,
    },
    /// One value per cell of the contact grid.
    Map {
        /// Unit of the colour scale.
        unit: String,
        /// The grid.
        grid: ContactGrid,
        /// One value per active cell.
        values: Vec<f64>,
    },
}

/// One reproduced figure: data and plot.
#[derive(Debug, Clone)]
pub struct Figure {
    /// Which figure.
    pub id: FigureId,
    /// Title above the plot.
    pub title: String,
    /// The computed data.
    pub table: Table,
    /// The plot.
    pub plot: Plot,
}

impl Figure {
    /// Writes `<stem>.csv`, `<stem>.png` and `<stem>.svg` into `dir` (created if missing) and returns their
    /// paths.
    pub fn write(&self, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
        std::fs::create_dir_all(dir)?;
        let stem = self.id.stem();
        let csv = dir.join(format!("{stem}.csv"));
        std::fs::write(&csv, self.table.to_csv())?;
        let mut written = vec![csv];
        for ext in ["png", "svg"] {
            let path = dir.join(format!("{stem}.{ext}"));
            match &self.plot {
                Plot::Lines {
                    x_label,
                    y_label,
                    series,
                } => line_chart(
                    &path,
                    &Chart {
                        title: &self.title,
                        x_label,
                        y_label,
                    },
                    series,
                )?,
                Plot::Map { unit, grid, values } => {
                    heat_map(&path, &self.title, unit, grid, values)?
                }
            }
            written.push(path);
        }
        Ok(written)
    }
}

/// Progress messages of a long computation (the CLI prints them on stderr).
pub type Progress<'a> = &'a (dyn Fn(&str) + Sync);

/// Computes one figure with the exact solver. `progress` receives a line per finished operating point or
/// f_max search.
pub fn compute(id: FigureId, settings: &Settings, progress: Progress) -> Result<Figure> {
    settings.params.validate()?;
    match settings.params.friction.law {
        wheelrail::params::FrictionLaw::Tomberger => {}
        wheelrail::params::FrictionLaw::Constant | wheelrail::params::FrictionLaw::Polach => {
            return Err(Error::OutOfRange {
                name: "friction.law".into(),
                value: settings.params.friction.law.to_string(),
                allowed: "tomberger (the paper's figures are of its model)".into(),
            });
        }
    }
    settings.search.validate()?;
    figures::compute(id, settings, progress)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figure_names_parse_in_every_spelling() {
        for f in FigureId::ALL {
            let n = f.number();
            for s in [
                format!("{n}"),
                format!("fig{n}"),
                format!("Fig. {n}"),
                format!("FIG{n:02}"),
            ] {
                assert_eq!(FigureId::parse(&s).unwrap(), f, "{s}");
            }
        }
        for bad in ["6", "fig", "22", "x", ""] {
            assert!(FigureId::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn only_the_papers_model_is_reproduced() {
        let mut s = Settings::default();
        s.params.friction.law = wheelrail::params::FrictionLaw::Polach;
        let e = compute(FigureId::Fig10, &s, &|_| {}).unwrap_err();
        assert!(e.to_string().contains("friction.law"), "{e}");
    }

    #[test]
    fn csv_quotes_cells_with_commas() {
        let t = Table {
            columns: vec!["a".into(), "b".into()],
            rows: vec![vec!["x, y".into(), "1.5".into()]],
        };
        assert_eq!(t.to_csv(), "a,b\n\"x, y\",1.5\n");
        assert_eq!(t.column("b").unwrap(), vec![1.5]);
        assert!(t.column("c").is_none());
    }
}
