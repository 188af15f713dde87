//! How one operating point is evaluated: by the exact coupled solver of the `wheelrail` library or (issue 5)
//! by interpolation in a lookup table. This file is the only place where the FMU calls the library's solver.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use wheelrail::solver::WarmStart;
use wheelrail::table::{Table, TableOutput};
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
    /// The outputs in the table's form, from the table or from the exact solution (`in_range` true).
    pub output: TableOutput,
    /// Outer iterations of the coupled solver (0 by table).
    pub iterations: usize,
    /// Final residual of the coupled solver (0 by table).
    pub residual: f64,
}

/// An evaluator of operating points.
#[derive(Debug, Clone)]
pub enum Evaluator {
    /// The exact coupled solver, `wheelrail::solve`.
    Exact,
    /// Interpolation in a lookup table loaded once per process and file and shared read-only between
    /// instances ([`Table::load_shared`]). In mode auto, points outside the table's ranges or parameters
    /// other than the table's go to the exact solver; in mode table-only, points are clamped to the ranges
    /// and other parameters are an error.
    Table {
        /// The shared table.
        table: Arc<Table>,
        /// Auto or table-only.
        mode: Mode,
    },
}

impl PartialEq for Evaluator {
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (Evaluator::Exact, Evaluator::Exact) => true,
            (Evaluator::Table { table: a, mode: m }, Evaluator::Table { table: b, mode: n }) => {
                Arc::ptr_eq(a, b) && m == n
            }
            _ => false,
        }
    }
}

/// What a table evaluator did with one point, for the model to log once per instance.
#[derive(Debug, Clone, PartialEq)]
pub enum Notice {
    /// Mode auto used the exact solver (the reason).
    FellBack(String),
    /// Mode table-only clamped the point to the table's ranges.
    Clamped,
}

/// How one point is evaluated by an evaluator.
pub enum Route<'a> {
    /// By the exact solver.
    Exact,
    /// By this table (possibly clamped).
    Table(&'a Table),
}

/// The exact solver's results as an [`Evaluation`], started from `warm` (if any), which then holds the
/// new solution's state.
fn exact(
    params: &Params,
    point: &OperatingPoint,
    warm: &mut Option<WarmStart>,
) -> wheelrail::Result<Evaluation> {
    let s = wheelrail::solve_from(params, point, warm.as_ref())?;
    *warm = s.warm_start();
    Ok(Evaluation {
        output: TableOutput::from_solution(&s)?,
        iterations: s.report.iterations,
        residual: s.report.residual,
    })
}

impl Evaluator {
    /// The `evaluation_mode` output when no point is evaluated (a lifted wheel): 1 table, 2 exact.
    pub fn code(&self) -> i32 {
        match self {
            Evaluator::Exact => 2,
            Evaluator::Table { .. } => 1,
        }
    }

    /// Whether a table evaluator's table was built for `params` (an exact evaluator: false).
    pub fn matches(&self, params: &Params) -> bool {
        match self {
            Evaluator::Exact => false,
            Evaluator::Table { table, .. } => table.matches(params),
        }
    }

    /// Which way `point` goes, and what to log about it (once per instance), given whether the table was
    /// built for the current parameters (`matches`, [`Evaluator::matches`]). Table-only mode with other
    /// parameters than the table's is an error.
    pub fn route(
        &self,
        matches: bool,
        point: &OperatingPoint,
    ) -> Result<(Route<'_>, Option<Notice>), String> {
        let (table, mode) = match self {
            Evaluator::Exact => return Ok((Route::Exact, None)),
            Evaluator::Table { table, mode } => (table.as_ref(), *mode),
        };
        let inside = table.in_range(point);
        match mode {
            Mode::TableOnly if !matches => Err(format!(
                "mode 1 (table only): the parameters differ from those the lookup table at {} was built for",
                table.location()
            )),
            Mode::TableOnly => Ok((Route::Table(table), (!inside).then_some(Notice::Clamped))),
            _ if !matches => Ok((
                Route::Exact,
                Some(Notice::FellBack(format!(
                    "the parameters differ from those the lookup table at {} was built for",
                    table.location()
                ))),
            )),
            _ if !inside => Ok((
                Route::Exact,
                Some(Notice::FellBack(
                    "an operating point lies outside the lookup table's ranges".into(),
                )),
            )),
            _ => Ok((Route::Table(table), None)),
        }
    }

    /// Evaluates one operating point: (results, evaluation_mode code 1 table / 2 exact, notice). `matches`
    /// tells whether the table was built for `params` ([`Evaluator::matches`]). An exact solve uses the
    /// solver tolerance tightened to `tolerance` if given (the table is chosen by `params` as they are),
    /// starts from `warm` if it holds a state and leaves its own state there.
    pub fn evaluate(
        &self,
        (params, matches): (&Params, bool),
        point: &OperatingPoint,
        tolerance: Option<f64>,
        warm: &mut Option<WarmStart>,
    ) -> Result<(Evaluation, i32, Option<Notice>), EvalError> {
        let (route, notice) = self.route(matches, point).map_err(EvalError::Mode)?;
        match route {
            Route::Exact => {
                let mut p = params.clone();
                if let Some(t) = tolerance {
                    p.solver.tolerance = p.solver.tolerance.min(t);
                }
                Ok((exact(&p, point, warm)?, 2, notice))
            }
            Route::Table(t) => {
                let output = t.evaluate(point)?;
                Ok((
                    Evaluation {
                        output,
                        iterations: 0,
                        residual: 0.0,
                    },
                    1,
                    notice,
                ))
            }
        }
    }
}

/// Why an evaluation failed: the library's error, or the evaluation mode's.
#[derive(Debug)]
pub enum EvalError {
    /// From the library (named by the library's parameter names).
    Library(wheelrail::Error),
    /// From the evaluation mode.
    Mode(String),
}

impl From<wheelrail::Error> for EvalError {
    fn from(e: wheelrail::Error) -> Self {
        EvalError::Library(e)
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
/// the exact solver for lack of a usable table. In table-only mode, no usable table is an error.
pub fn resolve(mode: Mode, table: Option<&Path>) -> Result<(Evaluator, Option<String>), String> {
    if mode == Mode::ExactOnly {
        return Ok((Evaluator::Exact, None));
    }
    let loaded = match table {
        None => Err("table_file is empty and the FMU's resources directory is unknown".into()),
        Some(p) if !p.exists() => Err(format!("there is no lookup table at {}", p.display())),
        Some(p) => {
            Table::load_shared(p).map_err(|e| format!("the lookup table cannot be used: {e}"))
        }
    };
    match (mode, loaded) {
        (_, Ok(table)) => Ok((Evaluator::Table { table, mode }, None)),
        (Mode::TableOnly, Err(why)) => Err(format!(
            "mode 1 (table only) needs a usable lookup table, but {why}"
        )),
        (_, Err(why)) => Ok((
            Evaluator::Exact,
            Some(format!("{why}; using the exact solver")),
        )),
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
