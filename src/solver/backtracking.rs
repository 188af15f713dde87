//! Backtracking of the temperature update when the fluid film has no solution.
//!
//! The film can have no solution at the temperature of an overshooting update (e.g. above 1800 K after
//! the first, unrelaxed step of a hot point). The outer iteration then steps back halfway towards the
//! temperature before the update, halves the relaxation factor and restarts the film cold: a backtracking
//! line search on the fixed point.

use crate::error::{Error, Result, Stage};

/// Most halvings of temperature updates in one solve (see [`super::SolverReport::temperature_backtracks`]).
const MAX_BACKTRACKS: usize = 20;

/// The temperature before the last update, to step back towards.
#[derive(Default)]
pub(super) struct Backtracking {
    /// Temperature per cell before the last update [K] (None before the first update).
    last_temperature: Option<Vec<f64>>,
}

impl Backtracking {
    /// Remembers the temperature before an update.
    pub fn remember(&mut self, temperature: &[f64]) {
        self.last_temperature = Some(temperature.to_vec());
    }

    /// Handles `error` of an outer iteration after `backtracks` earlier backtracks: a fluid film failure
    /// after a temperature update, fewer than MAX_BACKTRACKS times, moves `temperature` halfway back to the
    /// temperature before the update (T ← (T + T_last)/2) and returns Ok; any other error is returned.
    pub fn step_back(
        &self,
        error: Error,
        backtracks: usize,
        temperature: &mut [f64],
    ) -> Result<()> {
        match (&error, &self.last_temperature) {
            (
                Error::Numerical {
                    stage: Stage::Fluid,
                    ..
                },
                Some(last),
            ) if backtracks < MAX_BACKTRACKS => {
                for (t, l) in temperature.iter_mut().zip(last) {
                    *t = 0.5 * (*t + l);
                }
                Ok(())
            }
            _ => Err(error),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn film_failure() -> Error {
        Error::Numerical {
            stage: Stage::Fluid,
            reason: "no film".into(),
        }
    }

    #[test]
    fn only_a_film_failure_after_an_update_steps_back_and_only_so_often() {
        let mut b = Backtracking::default();
        let mut t = vec![500.0, 400.0];
        // before any update there is nothing to step back to
        assert!(b.step_back(film_failure(), 0, &mut t).is_err());
        b.remember(&[300.0, 300.0]);
        b.step_back(film_failure(), 0, &mut t).unwrap();
        assert_eq!(t, [400.0, 350.0]);
        let other = Error::Numerical {
            stage: Stage::Microcontact,
            reason: "x".into(),
        };
        assert!(matches!(
            b.step_back(other, 0, &mut t),
            Err(Error::Numerical {
                stage: Stage::Microcontact,
                ..
            })
        ));
        assert!(b.step_back(film_failure(), MAX_BACKTRACKS, &mut t).is_err());
        assert_eq!(t, [400.0, 350.0]);
    }
}
