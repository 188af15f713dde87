//! The free parameters of `wheelrail fit`: scalar keys of the parameter specification, their bounds and
//! the smooth map from an unbounded variable u onto the bounds, on which the least-squares method works.

use super::data::FitInputError;
use wheelrail::params::spec::{Bound, Range, Spec};
use wheelrail::params::{Input, Param};

/// How far inside its bounds a start on (or outside) a bound is moved, as a fraction of the bounded
/// interval (absolute above a lower bound only): the map reaches a bound only at infinite u.
const START_INSIDE: f64 = 0.01;

/// The map of an unbounded variable u onto a parameter's bounds (and back).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Map {
    /// θ = lo + (hi − lo)·σ(u), σ the logistic function: a finite interval.
    Logistic { lo: f64, hi: f64 },
    /// θ = lo + exp(u): a lower bound only (θ − lo changes by the same fraction for the same step of u).
    Above { lo: f64 },
}

impl Map {
    /// The parameter's value θ at u, kept inside `range` (the ends of an open range are excluded).
    pub fn value(&self, u: f64, range: &Range) -> f64 {
        let theta = match *self {
            Map::Logistic { lo, hi } => lo + (hi - lo) / (1.0 + (-u).exp()),
            Map::Above { lo } => lo + u.exp(),
        };
        let (lo, hi) = match *self {
            Map::Logistic { lo, hi } => (lo, hi),
            Map::Above { lo } => (lo, f64::INFINITY),
        };
        let theta = theta.clamp(lo, hi);
        // σ(u) and exp(u) round onto the bounds for large |u|: step inside an open end
        match (range.lo, range.hi) {
            (Bound::Open(l), _) if theta <= l => l.next_up(),
            (_, Bound::Open(h)) if theta >= h => h.next_down(),
            _ => theta,
        }
    }

    /// dθ/du at u (0 where the map has saturated onto a bound).
    pub fn slope(&self, u: f64) -> f64 {
        match *self {
            Map::Logistic { lo, hi } => {
                let s = 1.0 / (1.0 + (-u).exp());
                (hi - lo) * s * (1.0 - s)
            }
            Map::Above { .. } => u.exp(),
        }
    }

    /// The u of a start value θ₀, moved to [`START_INSIDE`] of the interval inside the bounds if it lies on
    /// or beyond one (near a bound the map is as the exponential one: θ − lo changes by the same fraction
    /// for the same step of u); with whether it was moved.
    pub fn start(&self, theta: f64) -> (f64, bool) {
        match *self {
            Map::Logistic { lo, hi } if theta > lo && theta < hi => {
                (((theta - lo) / (hi - theta)).ln(), false)
            }
            Map::Logistic { lo, hi } => {
                let margin = START_INSIDE * (hi - lo);
                let t = theta.clamp(lo + margin, hi - margin);
                (((t - lo) / (hi - t)).ln(), true)
            }
            Map::Above { lo } if theta > lo => ((theta - lo).ln(), false),
            Map::Above { .. } => (START_INSIDE.ln(), true),
        }
    }

    /// The bounds [lo, hi] (hi infinite above a lower bound only).
    pub fn bounds(&self) -> (f64, f64) {
        match *self {
            Map::Logistic { lo, hi } => (lo, hi),
            Map::Above { lo } => (lo, f64::INFINITY),
        }
    }
}

/// One free parameter: its row and its map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Free {
    /// The parameter.
    pub param: Param,
    /// Its map from u onto the bounds.
    pub map: Map,
}

impl Free {
    /// The specification row.
    pub fn spec(&self) -> &'static Spec {
        self.param.spec()
    }

    /// The parameter's value at u.
    pub fn value(&self, u: f64) -> f64 {
        self.map.value(u, &self.spec().range)
    }
}

/// The finite number at an end of a range, or None when the side is unbounded.
fn finite(b: Bound) -> Option<f64> {
    match b {
        Bound::Closed(x) | Bound::Open(x) => Some(x),
        Bound::Unbounded => None,
    }
}

/// The parameter of a TOML key given to `--free` or `--bounds`; keys that are no scalar parameter (the
/// friction law, an input, a whole-number setting) are errors naming the key.
pub fn param_of(key: &str, flag: &str) -> Result<Param, FitInputError> {
    if let Some(p) = Param::ALL.into_iter().find(|p| p.spec().toml == key) {
        if p.spec().integer {
            return Err(FitInputError(format!(
                "{flag} {key}: a whole number (a grid or iteration count) cannot be fitted"
            )));
        }
        return Ok(p);
    }
    if Input::ALL
        .into_iter()
        .any(|i| i.spec().toml == key || i.spec().cli == Some(key))
    {
        return Err(FitInputError(format!(
            "{flag} {key}: an operating-point input, not a parameter (give it as a column of the data)"
        )));
    }
    Err(FitInputError(format!(
        "{flag} {key}: not a scalar parameter key (the keys are the TOML keys of `wheelrail parameters`, \
         e.g. roughness.k_r; the friction law, the tangential solver, the pressure and the semi-axes are \
         not scalars)"
    )))
}

/// Parses one `--bounds KEY=LO:HI`.
fn bound_arg(text: &str) -> Result<(Param, f64, f64), FitInputError> {
    let bad = || {
        FitInputError(format!(
            "--bounds {text}: expected KEY=LO:HI, e.g. roughness.k_r=0.1:0.9"
        ))
    };
    let (key, range) = text.split_once('=').ok_or_else(bad)?;
    let (lo, hi) = range.split_once(':').ok_or_else(bad)?;
    let number = |s: &str| s.trim().parse::<f64>().ok().filter(|x| x.is_finite());
    let (Some(lo), Some(hi)) = (number(lo), number(hi)) else {
        return Err(bad());
    };
    Ok((param_of(key.trim(), "--bounds")?, lo, hi))
}

/// The free parameters of `--free` with the bounds of `--bounds` (which must lie inside the row's range,
/// lo < hi, each for a free key) or else the row's range.
pub fn free_parameters(keys: &[String], bounds: &[String]) -> Result<Vec<Free>, FitInputError> {
    let mut params: Vec<Param> = Vec::new();
    for key in keys {
        let p = param_of(key.trim(), "--free")?;
        if params.contains(&p) {
            return Err(FitInputError(format!("--free {key}: given twice")));
        }
        params.push(p);
    }
    if params.is_empty() {
        return Err(FitInputError("--free: give at least one key".into()));
    }
    let mut narrowed: Vec<(Param, f64, f64)> = Vec::new();
    for text in bounds {
        let (p, lo, hi) = bound_arg(text)?;
        let s = p.spec();
        if !params.contains(&p) {
            return Err(FitInputError(format!(
                "--bounds {text}: {} is not a free parameter (give it to --free)",
                s.toml
            )));
        }
        if narrowed.iter().any(|(q, _, _)| *q == p) {
            return Err(FitInputError(format!(
                "--bounds {text}: {} bounded twice",
                s.toml
            )));
        }
        if lo >= hi || !s.range.contains(lo) || !s.range.contains(hi) {
            return Err(FitInputError(format!(
                "--bounds {text}: the bounds of {} must satisfy lo < hi inside its range ({})",
                s.toml,
                s.allowed()
            )));
        }
        narrowed.push((p, lo, hi));
    }
    params
        .into_iter()
        .map(|p| {
            let s = p.spec();
            let map = match narrowed.iter().find(|(q, _, _)| *q == p) {
                Some(&(_, lo, hi)) => Map::Logistic { lo, hi },
                None => match (finite(s.range.lo), finite(s.range.hi)) {
                    (Some(lo), Some(hi)) => Map::Logistic { lo, hi },
                    (Some(lo), None) => Map::Above { lo },
                    (None, _) => {
                        return Err(FitInputError(format!(
                            "--free {}: its range has no lower bound; give --bounds {}=LO:HI",
                            s.toml, s.toml
                        )));
                    }
                },
            };
            Ok(Free { param: p, map })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn maps_take_u_onto_the_bounds_and_back() {
        let kr = Param::RoughnessKr.spec().range;
        let m = Map::Logistic { lo: 0.0, hi: 1.0 };
        for theta in [0.3, 0.5, 0.98] {
            let (u, moved) = m.start(theta);
            assert!(!moved);
            assert!((m.value(u, &kr) - theta).abs() < 1e-15);
            // the slope is the derivative of the map
            let h = 1e-6;
            let fd = (m.value(u + h, &kr) - m.value(u - h, &kr)) / (2.0 * h);
            assert!((m.slope(u) / fd - 1.0).abs() < 1e-8);
        }
        assert_eq!(m.value(1e3, &kr), 1.0);
        assert_eq!(m.value(-1e3, &kr), 0.0);
        // a start on a bound is moved inside
        let (u, moved) = m.start(0.0);
        assert!(moved && (m.value(u, &kr) - START_INSIDE).abs() < 1e-15);
        // an open end is never reached
        let positive = Param::FlowResistance.spec().range;
        let a = Map::Above { lo: 0.0 };
        assert!(a.value(-1e4, &positive) > 0.0);
        let (u, _) = a.start(0.012);
        assert!((a.value(u, &positive) - 0.012).abs() < 1e-17);
        assert_eq!(a.slope(u), a.value(u, &positive));
    }

    #[test]
    fn free_keys_take_their_ranges_or_the_narrower_bounds() {
        let f = free_parameters(
            &strings(&["roughness.k_r", "fluid.flow_resistance"]),
            &strings(&["roughness.k_r=0.1:0.6"]),
        )
        .unwrap();
        assert_eq!(f[0].map, Map::Logistic { lo: 0.1, hi: 0.6 });
        assert_eq!(f[1].map, Map::Above { lo: 0.0 });
        let f = free_parameters(&strings(&["friction.k_dry"]), &[]).unwrap();
        assert_eq!(f[0].map, Map::Logistic { lo: 0.0, hi: 10.0 });
    }

    #[test]
    fn bad_keys_and_bounds_are_named() {
        for (free, bounds, says) in [
            (
                vec!["friction.law"],
                vec![],
                "--free friction.law: not a scalar parameter key",
            ),
            (vec!["no.such"], vec![], "--free no.such: not a scalar"),
            (vec!["creepage-x"], vec![], "an operating-point input"),
            (vec!["grid.nx"], vec![], "--free grid.nx: a whole number"),
            (vec![], vec![], "at least one key"),
            (
                vec!["roughness.k_r", "roughness.k_r"],
                vec![],
                "given twice",
            ),
            (
                vec!["roughness.k_r"],
                vec!["roughness.k_r=0.2:1.5"],
                "inside its range (finite, 0 ..= 1)",
            ),
            (
                vec!["roughness.k_r"],
                vec!["roughness.k_r=0.6:0.2"],
                "lo < hi",
            ),
            (
                vec!["roughness.k_r"],
                vec!["roughness.k_r=a:b"],
                "expected KEY=LO:HI",
            ),
            (
                vec!["roughness.k_r"],
                vec!["roughness.k_r"],
                "expected KEY=LO:HI",
            ),
            (
                vec!["roughness.k_r"],
                vec!["friction.k_dry=1:2"],
                "friction.k_dry is not a free parameter",
            ),
            (
                vec!["roughness.k_r"],
                vec!["roughness.k_r=0.1:0.2", "roughness.k_r=0.1:0.3"],
                "bounded twice",
            ),
        ] {
            let e = free_parameters(&strings(&free), &strings(&bounds)).unwrap_err();
            assert!(e.to_string().contains(says), "{free:?} {bounds:?}: {e}");
        }
    }
}
