//! Directional derivatives by one directional finite difference, for models without analytic Jacobians.

use super::variables::{Value, Values};

/// The directional derivative of the Real outputs `unknowns` along the direction `seed` of the Real inputs
/// `knowns` (table indices), by one forward difference (f(u + h·v) − f(u))/h.
///
/// The step is scaled per input: with s_j = max(|u_j|, nominal_j), h = `relative_step` / max_j(|v_j|/s_j),
/// so that no input moves by more than `relative_step`·s_j. If the perturbed point cannot be evaluated
/// (outside the model's domain), the backward difference (f(u) − f(u − h·v))/h is used instead. A zero
/// direction gives zeros without evaluating. `evaluate` computes all outputs for given values.
///
/// Reference: Nocedal & Wright, Numerical Optimization (2006), §8.1: the truncation error is O(h) and the
/// rounding/solver-noise error O(δ/h) for evaluation noise δ, so h ≈ √δ balances them.
pub fn forward_difference(
    values: &Values,
    unknowns: &[usize],
    knowns: &[usize],
    seed: &[f64],
    relative_step: f64,
    mut evaluate: impl FnMut(&Values) -> Result<Values, String>,
) -> Result<Vec<f64>, String> {
    let table = values.table();
    let inverse_step = knowns
        .iter()
        .zip(seed)
        .map(|(&j, v)| v.abs() / values.real(j).abs().max(table[j].nominal()))
        .fold(0.0, f64::max);
    if inverse_step == 0.0 {
        return Ok(vec![0.0; unknowns.len()]);
    }
    let h = relative_step / inverse_step;
    let shifted = |sign: f64| {
        let mut v = values.clone();
        for (&j, s) in knowns.iter().zip(seed) {
            v.set(j, Value::Real(values.real(j) + sign * h * s));
        }
        v
    };
    let base = evaluate(values)?;
    let (upper, lower) = match evaluate(&shifted(1.0)) {
        Ok(up) => (up, base),
        Err(forward_error) => match evaluate(&shifted(-1.0)) {
            Ok(down) => (base, down),
            Err(_) => return Err(forward_error),
        },
    };
    Ok(unknowns
        .iter()
        .map(|&i| (upper.real(i) - lower.real(i)) / h)
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fmi2::variables::{Causality, Kind, Variability, Variable};

    const fn real(name: &'static str, causality: Causality, nominal: f64) -> Variable {
        Variable {
            name,
            vr: 0,
            causality,
            variability: Variability::Continuous,
            kind: Kind::Real {
                unit: "1",
                start: Some(0.0),
                min: None,
                max: None,
                nominal: Some(nominal),
            },
            description: "",
        }
    }

    static TABLE: [Variable; 3] = [
        real("a", Causality::Input, 1.0),
        real("b", Causality::Input, 1e-3),
        real("y", Causality::Output, 1.0),
    ];

    /// y = a² + 1000·b, defined for a ≤ 1 only.
    fn model(v: &Values) -> Result<Values, String> {
        if v.real(0) > 1.0 {
            return Err("a > 1".into());
        }
        let mut out = v.clone();
        out.set(2, Value::Real(v.real(0).powi(2) + 1000.0 * v.real(1)));
        Ok(out)
    }

    #[test]
    fn matches_the_analytic_derivative_and_steps_back_at_the_domain_edge() {
        let mut v = Values::start(&TABLE);
        v.set(0, Value::Real(0.5));
        v.set(1, Value::Real(2e-3));
        // d/da a² = 1 at a = 0.5; d/db = 1000; direction (1, 2): 1 + 2000
        let d = forward_difference(&v, &[2], &[0, 1], &[1.0, 2.0], 1e-7, model).unwrap();
        assert!((d[0] - 2001.0).abs() < 1e-3, "{d:?}");
        // at a = 1 the forward point is outside the domain: backward difference, 2a = 2
        v.set(0, Value::Real(1.0));
        let d = forward_difference(&v, &[2], &[0], &[1.0], 1e-7, model).unwrap();
        assert!((d[0] - 2.0).abs() < 1e-5, "{d:?}");
        let d = forward_difference(&v, &[2], &[0, 1], &[0.0, 0.0], 1e-7, |_| {
            Err("not called".into())
        });
        assert_eq!(d.unwrap(), vec![0.0]);
    }
}
