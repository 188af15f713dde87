//! The maximum of a traction–creepage curve, f_max (docs/model.md §9: "f_max is its maximum"; the paper's
//! Figs. 16–21 plot it): a coarse, logarithmically spaced creepage sweep finds the bracket of the global
//! maximum, golden-section search in ln ξ refines it.
//!
//! Every solve must converge; an unconverged point is an error, never a silently wrong maximum.

use rayon::prelude::*;
use wheelrail::error::{Error, Result, Stage};
use wheelrail::params::{OperatingPoint, Params};
use wheelrail::solver::{Solution, solve};

/// How the maximum is searched.
#[derive(Debug, Clone, PartialEq)]
pub struct MaxSearch {
    /// Longitudinal creepages ξ of the coarse sweep, ascending and positive [-].
    pub coarse: Vec<f64>,
    /// Golden-section search stops when the bracket is narrower than this in ln ξ [-]
    /// (0.1 ≙ the creepage of the maximum known to about ±5 %).
    pub ln_tolerance: f64,
}

impl Default for MaxSearch {
    /// Eight creepages from 0.1 % to 12.8 % (doubling): the dry maximum of the paper sits near 1 %; water
    /// lowers the adhesion limit, so wet curves saturate, and peak, at a few tenths of a per cent.
    fn default() -> Self {
        Self {
            coarse: vec![0.001, 0.002, 0.004, 0.008, 0.016, 0.032, 0.064, 0.128],
            ln_tolerance: 0.1,
        }
    }
}

impl MaxSearch {
    /// Checks the sweep: at least two finite, positive, strictly ascending creepages below the solver's limit,
    /// and a positive tolerance.
    pub fn validate(&self) -> Result<()> {
        let ok = self.coarse.len() >= 2
            && self
                .coarse
                .iter()
                .all(|x| x.is_finite() && *x > 0.0 && *x < 1.9)
            && self.coarse.windows(2).all(|w| w[1] > w[0]);
        if !ok {
            return Err(Error::OutOfRange {
                name: "f_max coarse creepages".into(),
                value: format!("{:?}", self.coarse),
                allowed: "at least two ascending creepages in (0, 1.9)".into(),
            });
        }
        wheelrail::error::check_range("f_max ln tolerance", self.ln_tolerance, 1e-6, 10.0, "")
    }
}

/// The maximum of one traction–creepage curve.
#[derive(Debug, Clone)]
pub struct TractionMaximum {
    /// Longitudinal creepage ξ at the maximum [-].
    pub creepage: f64,
    /// f_max = max over ξ of the traction coefficient f (P2) [-].
    pub traction: f64,
    /// The solution at the maximum.
    pub solution: Solution,
    /// Every evaluated (ξ, f), in evaluation order (coarse sweep first).
    pub evaluations: Vec<(f64, f64)>,
    /// True when the largest coarse creepage gave the largest f: the curve still rises at the end of the
    /// sweep and the value is the maximum over the swept range only.
    pub at_range_end: bool,
}

/// Solves one operating point and insists on convergence: an unconverged solution is an error naming the
/// point, never a silently wrong number.
pub fn solve_converged(params: &Params, point: &OperatingPoint) -> Result<Solution> {
    let s = solve(params, point)?;
    if let Some(limiter) = s.report.termination.limited_by() {
        return Err(Error::Numerical {
            stage: Stage::Reproduction,
            reason: format!(
                "solver not converged at ξ = {}, V = {} m/s, F_N = {} N, w = {}, k_r = {}: \
                 {} iterations, residual {:.3e}, fluid residual {:.3e}, limited by the {} solver",
                point.creepage_x,
                point.speed,
                point.normal_force,
                point.wetness,
                params.roughness.k_r,
                s.report.iterations,
                s.report.residual,
                s.report.fluid_residual,
                limiter
            ),
        });
    }
    Ok(s)
}

/// Solves the operating point `base` at longitudinal creepage `xi` and returns f (P2) with the solution.
fn traction_at(params: &Params, base: &OperatingPoint, xi: f64) -> Result<(f64, Solution)> {
    let point = OperatingPoint {
        creepage_x: xi,
        ..*base
    };
    let s = solve_converged(params, &point)?;
    Ok((s.global.traction_coefficient, s))
}

/// f_max of the traction–creepage curve over the longitudinal creepage ξ at the operating point `base`
/// (its `creepage_x` is ignored; lateral creepage and spin are kept). The coarse sweep runs in parallel;
/// golden-section search in ln ξ then refines the bracket around the best coarse point (both neighbours),
/// or the interval below the first point when that is the best. The result is the best of all evaluations.
pub fn traction_maximum(
    params: &Params,
    base: &OperatingPoint,
    search: &MaxSearch,
) -> Result<TractionMaximum> {
    search.validate()?;
    let coarse: Vec<(f64, Solution)> = search
        .coarse
        .par_iter()
        .map(|&xi| traction_at(params, base, xi))
        .collect::<Result<Vec<_>>>()?;
    let mut evaluations: Vec<(f64, f64)> = search
        .coarse
        .iter()
        .zip(&coarse)
        .map(|(x, (f, _))| (*x, *f))
        .collect();
    let last = coarse.len() - 1;
    let k = (0..coarse.len())
        .max_by(|&i, &j| coarse[i].0.total_cmp(&coarse[j].0))
        .expect("at least two coarse points");
    let (mut best_xi, (mut best_f, mut best_s)) = (search.coarse[k], coarse[k].clone());
    if k == last {
        return Ok(TractionMaximum {
            creepage: best_xi,
            traction: best_f,
            solution: best_s,
            evaluations,
            at_range_end: true,
        });
    }
    // bracket in u = ln ξ; below the first point extend by one coarse step
    let c = &search.coarse;
    let lo = if k == 0 { c[0] * c[0] / c[1] } else { c[k - 1] };
    let (mut a, mut b) = (lo.ln(), c[k + 1].ln());
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let mut eval = |u: f64| -> Result<f64> {
        let xi = u.exp();
        let (f, s) = traction_at(params, base, xi)?;
        evaluations.push((xi, f));
        if f > best_f {
            (best_xi, best_f, best_s) = (xi, f, s);
        }
        Ok(f)
    };
    let mut u1 = b - r * (b - a);
    let mut u2 = a + r * (b - a);
    let mut f1 = eval(u1)?;
    let mut f2 = eval(u2)?;
    while b - a > search.ln_tolerance {
        if f1 >= f2 {
            b = u2;
            (u2, f2) = (u1, f1);
            u1 = b - r * (b - a);
            f1 = eval(u1)?;
        } else {
            a = u1;
            (u1, f1) = (u2, f2);
            u2 = a + r * (b - a);
            f2 = eval(u2)?;
        }
    }
    Ok(TractionMaximum {
        creepage: best_xi,
        traction: best_f,
        solution: best_s,
        evaluations,
        at_range_end: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use wheelrail::params::FrictionLaw;

    /// Polach's closed form (docs/model.md §12) is cheap and has a smooth interior maximum in ξ when its
    /// friction falls with slip velocity: the search must find it to the tolerance, as a dense scan does.
    #[test]
    fn finds_the_interior_maximum_of_a_closed_form_curve() {
        let mut p = Params::default();
        p.friction.law = FrictionLaw::Polach;
        let base = OperatingPoint::default();
        let m = traction_maximum(&p, &base, &MaxSearch::default()).unwrap();
        assert!(!m.at_range_end);
        // dense independent scan in ln ξ
        let (mut sx, mut sf) = (0.0, 0.0);
        for k in 0..=4000 {
            let xi = (0.001f64.ln() + (0.2f64.ln() - 0.001f64.ln()) * k as f64 / 4000.0).exp();
            let f = traction_at(&p, &base, xi).unwrap().0;
            if f > sf {
                (sx, sf) = (xi, f);
            }
        }
        assert!(
            m.traction <= sf * (1.0 + 1e-9),
            "{} > scan {sf}",
            m.traction
        );
        assert!((m.traction - sf) / sf < 1e-3, "{} vs scan {sf}", m.traction);
        assert!(
            (m.creepage / sx).ln().abs() < 0.1,
            "ξ {} vs scan {sx}",
            m.creepage
        );
        // coarse sweep plus a handful of golden steps, not a scan
        assert!(m.evaluations.len() < 20);
    }

    #[test]
    fn a_curve_rising_over_the_whole_sweep_is_flagged() {
        let mut p = Params::default();
        p.friction.law = FrictionLaw::Polach;
        p.friction.polach.b_rate = 0.0; // no fall with slip velocity: f rises monotonically to μ0
        let m = traction_maximum(&p, &OperatingPoint::default(), &MaxSearch::default()).unwrap();
        assert!(m.at_range_end);
        assert_eq!(m.creepage, 0.128);
    }

    #[test]
    fn bad_sweeps_are_rejected() {
        let p = Params::default();
        let pt = OperatingPoint::default();
        for coarse in [
            vec![0.01],
            vec![0.02, 0.01],
            vec![0.0, 0.01],
            vec![0.01, f64::NAN],
        ] {
            let s = MaxSearch {
                coarse,
                ..Default::default()
            };
            assert!(traction_maximum(&p, &pt, &s).is_err());
        }
    }
}
