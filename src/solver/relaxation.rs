//! Relaxation of the temperature update of the outer iteration.
//!
//! The temperature ↔ failure-stress feedback makes the plain fixed point T ← T_target oscillate at high
//! slip power; the update T ← T + ω·ΔT is relaxed with Aitken's Δ² factor in the vector form of Irons and
//! Tuck (Int. J. Numer. Methods Eng. 1 (1969) 275): ω ← −ω·(Δ₀·(Δ₁ − Δ₀))/|Δ₁ − Δ₀|², clamped to
//! [0.02, 1], with Δ₀, Δ₁ the previous and the current increment (docs/model.md §9).

/// Smallest and largest relaxation factor.
const OMEGA_RANGE: (f64, f64) = (0.02, 1.0);

/// The relaxation factor and the previous increment.
pub(super) struct Relaxation {
    /// The current factor ω [-].
    omega: f64,
    /// The increment T_target − T of the previous update [K].
    previous: Option<Vec<f64>>,
}

impl Relaxation {
    /// Starts with the factor `omega` (`solver.relaxation`).
    pub fn new(omega: f64) -> Self {
        Self {
            omega,
            previous: None,
        }
    }

    /// Whether the updates so far were plain fixed-point steps T ← T_target (ω = 1): then successive
    /// increments shrink by the contraction factor of the fixed-point map.
    pub fn is_plain(&self) -> bool {
        self.omega == 1.0
    }

    /// Halves the factor (after a backtracked update).
    pub fn damp(&mut self) {
        self.omega *= 0.5;
    }

    /// Updates ω by Aitken's Δ² from the previous increment (if any; ω is kept when the increments
    /// agree), then moves `temperature` by ω·`increment` [K].
    pub fn apply(&mut self, temperature: &mut [f64], increment: Vec<f64>) {
        if let Some(prev) = &self.previous {
            let mut num = 0.0;
            let mut den = 0.0;
            for (r1, r0) in increment.iter().zip(prev) {
                let d = r1 - r0;
                num += r0 * d;
                den += d * d;
            }
            if den > 0.0 {
                self.omega = (-self.omega * num / den).clamp(OMEGA_RANGE.0, OMEGA_RANGE.1);
            }
        }
        for (t, d) in temperature.iter_mut().zip(&increment) {
            *t += self.omega * d;
        }
        self.previous = Some(increment);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a linear fixed point T = a·T + b the Aitken factor after two updates is the exact 1/(1 − a),
    /// which lands on the fixed point b/(1 − a) in one step; a factor beyond the range is clamped.
    #[test]
    fn aitken_solves_a_linear_fixed_point_and_is_clamped() {
        let (a, b) = (-0.6, 10.0);
        let fixed = b / (1.0 - a);
        let mut r = Relaxation::new(1.0);
        let mut t = vec![0.0];
        for _ in 0..2 {
            let increment = vec![a * t[0] + b - t[0]];
            r.apply(&mut t, increment);
        }
        assert!((r.omega - 1.0 / (1.0 - a)).abs() < 1e-12, "{}", r.omega);
        assert!((t[0] - fixed).abs() < 1e-12 * fixed, "{} vs {fixed}", t[0]);
        // a = 0.9: the ideal factor 10 is clamped to 1; a = −100: 1/101 is clamped to 0.02
        for (a, want) in [(0.9, 1.0), (-100.0, 0.02)] {
            let mut r = Relaxation::new(1.0);
            let mut t = vec![0.0];
            for _ in 0..2 {
                let increment = vec![a * t[0] + b - t[0]];
                r.apply(&mut t, increment);
            }
            assert_eq!(r.omega, want, "a = {a}");
        }
        r.damp();
        assert!((r.omega - 0.5 / (1.0 - a)).abs() < 1e-12);
    }
}
