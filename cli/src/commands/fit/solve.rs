//! The least-squares problem of `wheelrail fit`: the model at every data row for a parameter set (curves
//! in parallel, warm starts along each curve), the weighted residuals, their Jacobian by central
//! differences, bounded Levenberg–Marquardt (MINPACK's method, the `levenberg-marquardt` crate) in the
//! mapped variables of [`super::free`] (the uncertainty at the solution: [`super::stats`]).

use super::data::{Data, Row};
use super::free::Free;
use anyhow::{Context, Result};
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt, TerminationReason};
use nalgebra::{DMatrix, DVector, Dyn, Owned};
use rayon::prelude::*;
use std::cell::RefCell;
use wheelrail::model::{DERIVATIVE_TOLERANCE, Evaluated, Evaluator, Mode, Policy};
use wheelrail::{Model, Params};

/// The relative reduction of the sum of squares, predicted and actual, below which the fit has converged
/// (MINPACK's ftol). The solves behind each residual are converged to [`DERIVATIVE_TOLERANCE`], which
/// leaves a noise of the order of 1e-8 in each model value and so of 1e-5 of the sum of squares of
/// residuals of order 1e-3: a smaller criterion would only chase that noise.
const FTOL: f64 = 1e-5;
/// The relative change of the (mapped, scaled) parameters below which the fit has converged (xtol).
const XTOL: f64 = 1e-6;
/// The limit of residual evaluations per parameter (MINPACK's patience: (p + 1)·PATIENCE in all).
const PATIENCE: usize = 30;

/// How the model values are computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Solves {
    /// For the least squares: each curve in order, each solve starting from its neighbour's state, the
    /// solver tolerance tightened to [`DERIVATIVE_TOLERANCE`] (the finite differences need values
    /// converged well below their step).
    Chained,
    /// As `wheelrail point` evaluates each row: a cold start at the parameter set's own tolerance (so
    /// that the fitted parameter file reproduces them).
    AsPoint,
}

/// The model's values at one row: one per measured column, and whether its solve converged.
#[derive(Debug, Clone, PartialEq)]
pub struct Modelled {
    /// The model's values of the measured columns ([`Data::measured`], same order).
    pub values: Vec<f64>,
    /// Whether the coupled iteration met its tolerance (true for a closed form or a lifted wheel).
    pub converged: bool,
}

/// The fit: the parameter set it starts from, the free parameters, the data and its curves.
pub struct Fit<'a> {
    /// The parameter set (defaults ← file ← flags) whose free keys are fitted.
    pub base: &'a Params,
    /// The free parameters.
    pub free: &'a [Free],
    /// The measurements.
    pub data: &'a Data,
    /// The rows' indices per curve, ordered for warm starts ([`super::data::curves`]).
    pub curves: Vec<Vec<usize>>,
    /// The evaluation policy: `wheelrail point`'s.
    pub policy: Policy,
}

/// The central-difference step in the mapped variables u: it balances the truncation error (≈ h²/6 of
/// the third derivative) against the solver noise (≈ tolerance/h), h = (3·tolerance)^(1/3) ≈ 3e-3 at
/// [`DERIVATIVE_TOLERANCE`]. A step of u changes θ − lo (and hi − θ) by about that fraction.
fn difference_step() -> f64 {
    (3.0 * DERIVATIVE_TOLERANCE).cbrt()
}

impl Fit<'_> {
    /// The parameter set at the mapped variables `u`.
    pub fn params_at(&self, u: &[f64]) -> Params {
        let mut p = self.base.clone();
        for (f, &x) in self.free.iter().zip(u) {
            p.set(f.param, f.value(x));
        }
        p
    }

    /// The model's values at every row for each parameter set (the sets and the curves in parallel).
    pub fn evaluate(&self, sets: &[Params], solves: Solves) -> Result<Vec<Vec<Modelled>>> {
        let evaluators = sets
            .iter()
            .map(|p| Evaluator::new(Model::new(p.clone())?, Mode::ExactOnly, None, self.policy))
            .collect::<wheelrail::Result<Vec<_>>>()?;
        let tasks: Vec<(usize, &Vec<usize>)> = (0..sets.len())
            .flat_map(|s| self.curves.iter().map(move |c| (s, c)))
            .collect();
        let solved = tasks
            .par_iter()
            .map(|&(s, curve)| {
                let mut warm = None;
                curve
                    .iter()
                    .map(|&k| {
                        let row = &self.data.rows[k];
                        let m = match solves {
                            Solves::Chained => model_at(
                                &evaluators[s],
                                row,
                                &self.data.measured,
                                Some(DERIVATIVE_TOLERANCE),
                                &mut warm,
                            ),
                            Solves::AsPoint => {
                                model_at(&evaluators[s], row, &self.data.measured, None, &mut None)
                            }
                        };
                        m.map(|m| (k, m))
                            .with_context(|| format!("solving the data's line {}", row.line))
                    })
                    .collect::<Result<Vec<_>>>()
                    .map(|rows| (s, rows))
            })
            .collect::<Result<Vec<_>>>()?;
        let mut out = vec![vec![None; self.data.rows.len()]; sets.len()];
        for (s, rows) in solved {
            for (k, m) in rows {
                out[s][k] = Some(m);
            }
        }
        Ok(out
            .into_iter()
            .map(|set| {
                set.into_iter()
                    .map(|m| m.expect("every row solved"))
                    .collect()
            })
            .collect())
    }

    /// The weighted, dimensionless residuals √w·(model − measured)/scale of the model values `m`, row by
    /// row, each row's measured columns in order ([`super::data::Measured::scale`]).
    pub fn residuals(&self, m: &[Modelled]) -> DVector<f64> {
        let d = self.data;
        DVector::from_iterator(
            d.rows.len() * d.measured.len(),
            d.rows.iter().zip(m).flat_map(|(row, m)| {
                d.measured.iter().zip(row.values.iter().zip(&m.values)).map(
                    |(q, (measured, model))| {
                        row.weight.sqrt() * (model - measured) / q.scale(&row.point)
                    },
                )
            }),
        )
    }

    /// The residuals at `u` (chained solves).
    fn residuals_at(&self, u: &[f64]) -> Result<DVector<f64>> {
        let m = self.evaluate(&[self.params_at(u)], Solves::Chained)?;
        Ok(self.residuals(&m[0]))
    }

    /// The Jacobian of the residuals with respect to u by central differences ([`difference_step`]),
    /// all 2p parameter sets solved in parallel.
    pub fn jacobian_at(&self, u: &[f64]) -> Result<DMatrix<f64>> {
        let h = difference_step();
        let sets: Vec<Params> = (0..u.len())
            .flat_map(|k| {
                [h, -h].map(|d| {
                    let mut v = u.to_vec();
                    v[k] += d;
                    self.params_at(&v)
                })
            })
            .collect();
        let m = self.evaluate(&sets, Solves::Chained)?;
        let n = self.data.rows.len() * self.data.measured.len();
        let mut j = DMatrix::zeros(n, u.len());
        for k in 0..u.len() {
            let diff = (self.residuals(&m[2 * k]) - self.residuals(&m[2 * k + 1])) / (2.0 * h);
            j.set_column(k, &diff);
        }
        Ok(j)
    }
}

/// The model's values of the `measured` columns at one row.
fn model_at(
    evaluator: &Evaluator,
    row: &Row,
    measured: &[super::data::Measured],
    tolerance: Option<f64>,
    warm: &mut Option<wheelrail::model::WarmStart>,
) -> Result<Modelled> {
    let geometry = row.geometry.of(evaluator.model().params());
    let e = evaluator.evaluate_at(&row.point, &geometry, tolerance, warm)?;
    Ok(match &e.by {
        Evaluated::Exact(x) => Modelled {
            values: measured.iter().map(|q| q.of(&x.global)).collect(),
            converged: x.report.converged,
        },
        // a lifted wheel (a load at the lift-off load) carries no force
        Evaluated::Table(_) | Evaluated::Lifted(_) => Modelled {
            values: vec![0.0; measured.len()],
            converged: true,
        },
    })
}

/// The least-squares problem as the Levenberg–Marquardt crate sees it; the first model failure is kept.
struct Problem<'a, 'b> {
    fit: &'a Fit<'b>,
    u: DVector<f64>,
    failure: RefCell<Option<anyhow::Error>>,
}

impl Problem<'_, '_> {
    fn keep<T>(&self, r: Result<T>) -> Option<T> {
        r.map_err(|e| {
            self.failure.borrow_mut().get_or_insert(e);
        })
        .ok()
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_, '_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, u: &DVector<f64>) {
        self.u.copy_from(u);
    }

    fn params(&self) -> DVector<f64> {
        self.u.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        self.keep(self.fit.residuals_at(self.u.as_slice()))
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        self.keep(self.fit.jacobian_at(self.u.as_slice()))
    }
}

/// How the least squares ended.
#[derive(Debug)]
pub struct Outcome {
    /// The mapped variables at the end.
    pub u: Vec<f64>,
    /// Whether the method met a convergence criterion.
    pub converged: bool,
    /// Why it stopped, in words.
    pub reason: String,
    /// The residual evaluations it made (each one solve of every row; a Jacobian is 2p of them).
    pub evaluations: usize,
}

/// Minimises the sum of squared residuals from `u0`. A model failure at the start is an error; a later
/// one ends the fit unconverged, with the failure as its reason.
pub fn minimise(fit: &Fit, u0: &[f64]) -> Result<Outcome> {
    fit.residuals_at(u0)
        .context("evaluating the model at the start values")?;
    let problem = Problem {
        fit,
        u: DVector::from_column_slice(u0),
        failure: RefCell::new(None),
    };
    let (problem, report) = LevenbergMarquardt::new()
        .with_ftol(FTOL)
        .with_xtol(XTOL)
        .with_patience(PATIENCE)
        .minimize(problem);
    let reason = match &report.termination {
        TerminationReason::User(_) => match problem.failure.borrow().as_ref() {
            Some(e) => format!("the model failed: {e:#}"),
            None => "the model failed".into(),
        },
        TerminationReason::Numerical(what) => format!("a {what} was not finite"),
        TerminationReason::ResidualsZero => "the residuals are zero".into(),
        TerminationReason::Orthogonal => {
            "the residuals are orthogonal to the Jacobian's columns (gtol)".into()
        }
        TerminationReason::Converged { ftol, xtol } => match (ftol, xtol) {
            (true, true) => "the relative reduction of the sum of squares is below ftol and the relative change of the parameters below xtol".into(),
            (true, false) => "the relative reduction of the sum of squares is below ftol".into(),
            _ => "the relative change of the parameters is below xtol".into(),
        },
        TerminationReason::NoImprovementPossible(what) => {
            format!("no further improvement possible in floating point ({what})")
        }
        TerminationReason::LostPatience => format!(
            "the limit of {} residual evaluations was reached",
            PATIENCE * (u0.len() + 1)
        ),
        other => format!("{other:?}"),
    };
    Ok(Outcome {
        u: problem.u.as_slice().to_vec(),
        converged: report.termination.was_successful(),
        reason,
        evaluations: report.number_of_evaluations,
    })
}
