//! The uncertainty of fitted parameters: the covariance s²·(JᵀWJ)⁻¹ of linearised least squares at the
//! solution, s² = RSS/(n − p), in the parameters' own units, with the correlations and the parameters the
//! data do not determine.

use nalgebra::DMatrix;

/// The correlation at or above which (in magnitude) two parameters are not determined separately.
pub const CORRELATION_LIMIT: f64 = 0.99;

/// The uncertainty of the free parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Uncertainty {
    /// The standard error of each parameter in its unit (None where the data do not change with it).
    pub std_error: Vec<Option<f64>>,
    /// The correlation matrix (None in the rows and columns of parameters without a standard error).
    pub correlation: Vec<Vec<Option<f64>>>,
    /// Per parameter, why the data cannot determine it (None: determined).
    pub undetermined: Vec<Option<String>>,
}

/// The uncertainty of parameters `values` (named `names`) from the Jacobian `j` of the weighted residuals
/// with respect to them (n × p, columns in the parameters' units) and the residual sum of squares `rss`.
/// A column of zeros (the data do not change with the parameter, or its map has saturated onto a bound)
/// has no standard error; a singular remainder leaves all without one.
pub fn uncertainty(j: &DMatrix<f64>, rss: f64, values: &[f64], names: &[&str]) -> Uncertainty {
    let (n, p) = j.shape();
    let s2 = rss / (n.saturating_sub(p)).max(1) as f64;
    let mut undetermined: Vec<Option<String>> = vec![None; p];
    let live: Vec<usize> = (0..p)
        .filter(|&k| {
            let moves = j.column(k).norm() > 0.0 && j.column(k).iter().all(|x| x.is_finite());
            if !moves {
                undetermined[k] =
                    Some("the data do not change with it (or it lies on its bound)".into());
            }
            moves
        })
        .collect();
    // the normal matrix of the parameters that move, scaled to unit diagonal for its conditioning
    let jl = DMatrix::from_fn(n, live.len(), |r, c| j[(r, live[c])]);
    let m = jl.transpose() * &jl;
    let d: Vec<f64> = (0..live.len()).map(|k| m[(k, k)].sqrt()).collect();
    let scaled = DMatrix::from_fn(live.len(), live.len(), |r, c| m[(r, c)] / (d[r] * d[c]));
    let mut std_error = vec![None; p];
    let mut correlation = vec![vec![None; p]; p];
    match scaled.cholesky() {
        Some(ch) => {
            let inv = ch.inverse();
            for (a, &ka) in live.iter().enumerate() {
                std_error[ka] = Some((s2 * inv[(a, a)]).sqrt() / d[a]);
                for (b, &kb) in live.iter().enumerate() {
                    correlation[ka][kb] = Some(inv[(a, b)] / (inv[(a, a)] * inv[(b, b)]).sqrt());
                }
            }
        }
        None => {
            for &k in &live {
                undetermined[k] = Some(
                    "the data cannot separate the free parameters (their normal matrix is singular)"
                        .into(),
                );
            }
        }
    }
    for &ka in &live {
        if undetermined[ka].is_some() {
            continue;
        }
        let partner = live
            .iter()
            .filter(|&&kb| kb != ka)
            .filter_map(|&kb| correlation[ka][kb].map(|r| (kb, r)))
            .filter(|(_, r)| r.abs() >= CORRELATION_LIMIT)
            .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()));
        if let Some((kb, r)) = partner {
            undetermined[ka] = Some(format!(
                "correlated with {} (correlation {r:.4}, at least {CORRELATION_LIMIT} in magnitude)",
                names[kb]
            ));
        } else if let Some(e) = std_error[ka].filter(|e| *e > values[ka].abs()) {
            undetermined[ka] = Some(format!(
                "its standard error {e:.3e} is larger than its value {:.3e}",
                values[ka]
            ));
        }
    }
    Uncertainty {
        std_error,
        correlation,
        undetermined,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight line y = a + b·x fitted to points: the textbook standard errors.
    #[test]
    fn a_straight_line_has_the_textbook_standard_errors() {
        let x = [0.0, 1.0, 2.0, 3.0, 4.0];
        let j = DMatrix::from_fn(5, 2, |r, c| if c == 0 { 1.0 } else { x[r] });
        let rss = 0.3;
        let u = uncertainty(&j, rss, &[1.0, 2.0], &["a", "b"]);
        // s² = RSS/(n − 2); Var b = s²/Sxx, Var a = s²·Σx²/(n·Sxx), corr = −x̄/sqrt(Σx²/n)
        let s2 = rss / 3.0;
        let sxx = 10.0;
        let sb = (s2 / sxx).sqrt();
        let sa = (s2 * 30.0 / (5.0 * sxx)).sqrt();
        assert!((u.std_error[1].unwrap() / sb - 1.0).abs() < 1e-12);
        assert!((u.std_error[0].unwrap() / sa - 1.0).abs() < 1e-12);
        let r = -2.0 / (30.0f64 / 5.0).sqrt();
        assert!((u.correlation[0][1].unwrap() - r).abs() < 1e-12);
        assert_eq!(u.correlation[0][0], Some(1.0));
        assert_eq!(u.undetermined, vec![None, None]);
    }

    #[test]
    fn parameters_the_data_cannot_determine_are_named() {
        let x = [0.0, 1.0, 2.0, 3.0];
        // a column of zeros: no effect
        let j = DMatrix::from_fn(4, 2, |r, c| if c == 0 { x[r] } else { 0.0 });
        let u = uncertainty(&j, 0.1, &[1.0, 1.0], &["a", "b"]);
        assert!(u.undetermined[0].is_none() && u.std_error[1].is_none());
        assert!(
            u.undetermined[1]
                .as_deref()
                .unwrap()
                .contains("do not change")
        );
        // two nearly proportional columns: correlated
        let j = DMatrix::from_fn(4, 2, |r, c| {
            x[r] + 1.0 + if c == 1 { 1e-4 * x[r] * x[r] } else { 0.0 }
        });
        let u = uncertainty(&j, 0.1, &[1.0, 1.0], &["a", "b"]);
        assert!(
            u.undetermined[0]
                .as_deref()
                .unwrap()
                .contains("correlated with b")
        );
        assert!(
            u.undetermined[1]
                .as_deref()
                .unwrap()
                .contains("correlated with a")
        );
        // exactly proportional: singular
        let j = DMatrix::from_fn(4, 2, |r, c| (c + 1) as f64 * (x[r] + 1.0));
        let u = uncertainty(&j, 0.1, &[1.0, 1.0], &["a", "b"]);
        assert!(u.undetermined.iter().all(|w| w.is_some()), "{u:?}");
        // a standard error larger than the value
        let j = DMatrix::from_fn(4, 1, |r, _| 1e-3 * x[r]);
        let u = uncertainty(&j, 1.0, &[0.5], &["a"]);
        assert!(
            u.undetermined[0]
                .as_deref()
                .unwrap()
                .contains("larger than its value")
        );
    }
}
