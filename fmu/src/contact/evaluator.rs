//! How one operating point is evaluated: by the exact coupled solver of the `wheelrail` library or (issue 5)
//! by interpolation in a lookup table. This file is the only place where the FMU calls the library's solver.

use std::path::{Path, PathBuf};
use wheelrail::{OperatingPoint, Params};

/// The `mode` parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// The lookup table where usable, else the exact solver (with one logged warning).
    Auto,
    /// Only the lookup table; without a usable table, initialization fails.
    TableOnly,
    /// Only the exact solver.
    ExactOnly,
}

impl Mode {
    /// The mode of a `mode` parameter value (0, 1, 2).
    pub fn from_code(code: i32) -> Result<Mode, String> {
        match code {
            0 => Ok(Mode::Auto),
            1 => Ok(Mode::TableOnly),
            2 => Ok(Mode::ExactOnly),
            _ => Err(format!(
                "invalid value for mode: {code} (allowed: 0 auto, 1 table only, 2 exact only)"
            )),
        }
    }
}

/// The global results of one operating point, in the solved (forward-rolling) frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluation {
    /// F_x [N].
    pub force_x: f64,
    /// F_y [N].
    pub force_y: f64,
    /// M_z [N·m].
    pub spin_moment: f64,
    /// |F_T|/F_N [-].
    pub traction_coefficient: f64,
    /// Highest surface temperature [K].
    pub max_temperature: f64,
    /// Share of the load carried by the fluid [-].
    pub fluid_load_fraction: f64,
    /// Whether the coupled iteration met its tolerance.
    pub converged: bool,
    /// Outer iterations of the coupled solver.
    pub iterations: usize,
    /// Final residual of the coupled solver.
    pub residual: f64,
}

/// An evaluator of operating points.
#[derive(Debug, Clone, PartialEq)]
pub enum Evaluator {
    /// The exact coupled solver, `wheelrail::solve`.
    Exact,
    // Issue 5 adds `Table(Arc<Table>)`: interpolation in a table loaded once and shared read-only between
    // instances, with exact derivatives from the interpolant.
}

impl Evaluator {
    /// The `evaluation_mode` output: 1 table, 2 exact.
    pub fn code(&self) -> i32 {
        match self {
            Evaluator::Exact => 2,
        }
    }

    /// Evaluates one operating point; `Err` carries the library's message.
    pub fn evaluate(
        &self,
        params: &Params,
        point: &OperatingPoint,
    ) -> wheelrail::Result<Evaluation> {
        match self {
            Evaluator::Exact => {
                let s = wheelrail::solve(params, point)?;
                let g = &s.global;
                Ok(Evaluation {
                    force_x: g.force_x,
                    force_y: g.force_y,
                    spin_moment: g.spin_moment,
                    traction_coefficient: g.traction_coefficient,
                    max_temperature: g.max_temperature,
                    fluid_load_fraction: g.fluid_load_fraction,
                    converged: s.report.converged,
                    iterations: s.report.iterations,
                    residual: s.report.residual,
                })
            }
        }
    }
}

/// Where the lookup table is: `table_file` if given, else `resources/table` of the unpacked FMU.
pub fn table_location(table_file: &str, resources: Option<&Path>) -> Option<PathBuf> {
    if table_file.is_empty() {
        resources.map(|r| r.join("table"))
    } else {
        Some(PathBuf::from(table_file))
    }
}

/// The evaluator for `mode` and a table location, and the warning to log once if auto mode falls back to
/// the exact solver. In table-only mode, no usable table is an error.
pub fn resolve(mode: Mode, table: Option<&Path>) -> Result<(Evaluator, Option<String>), String> {
    match mode {
        Mode::ExactOnly => Ok((Evaluator::Exact, None)),
        Mode::Auto => Ok((
            Evaluator::Exact,
            Some(format!("{}; using the exact solver", no_table(table))),
        )),
        Mode::TableOnly => Err(format!(
            "mode 1 (table only) needs a usable lookup table, but {}",
            no_table(table)
        )),
    }
}

/// Why no lookup table is usable. Table evaluation arrives with issue 5; until then no table is readable.
fn no_table(location: Option<&Path>) -> String {
    match location {
        None => "table_file is empty and the FMU's resources directory is unknown".into(),
        Some(p) if !p.exists() => format!("there is no lookup table at {}", p.display()),
        Some(p) => format!(
            "the lookup table at {} cannot be read by this build (no table support yet)",
            p.display()
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_and_table_resolution() {
        assert_eq!(Mode::from_code(1), Ok(Mode::TableOnly));
        assert!(Mode::from_code(3).unwrap_err().contains("mode: 3"));
        let res = Path::new("/nonexistent/resources");
        let loc = table_location("", Some(res)).unwrap();
        assert_eq!(loc, res.join("table"));
        assert_eq!(
            table_location("/x/t", Some(res)).unwrap(),
            PathBuf::from("/x/t")
        );
        assert_eq!(table_location("", None), None);
        assert_eq!(
            resolve(Mode::ExactOnly, None).unwrap(),
            (Evaluator::Exact, None)
        );
        let (e, warning) = resolve(Mode::Auto, Some(&loc)).unwrap();
        assert_eq!(e.code(), 2);
        assert!(
            warning
                .unwrap()
                .contains("no lookup table at /nonexistent/resources/table")
        );
        let err = resolve(Mode::TableOnly, Some(&loc)).unwrap_err();
        assert!(
            err.contains("table only") && err.contains("/nonexistent"),
            "{err}"
        );
        assert!(
            resolve(Mode::TableOnly, None)
                .unwrap_err()
                .contains("resources directory is unknown")
        );
    }
}
