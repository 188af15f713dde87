//! Relaxation of the temperature update of the outer iteration.
//!
//! The temperature ↔ failure-stress feedback makes the plain fixed point T ← T_target oscillate at high
//! slip power; the update T ← T + ω·ΔT is relaxed with Aitken's Δ² factor in the vector form of Irons and
//! Tuck (Int. J. Numer. Methods Eng. 1 (1969) 275): ω ← −ω·(Δ₀·(Δ₁ − Δ₀))/|Δ₁ − Δ₀|², clamped to
//! [0.02, 1], with Δ₀, Δ₁ the previous and the current increment (docs/model.md §9). Where a solve started
//! near its fixed point has measured a fast, monotone contraction q of it along its increments, the coupled
//! solver extrapolates instead ([`Relaxation::extrapolate`]): ω = 1/(1 − q), Aitken's factor for
//! increments that shrink by q, which moves an iterate whose error lies along the increment onto the fixed
//! point.
//!
//! One factor for the whole field cannot settle a few cells whose target is far steeper than the rest:
//! where a wet contact's metal just covers a cell (the onset of the walls, §8.5) the film downstream
//! switches within a few kelvin of that cell's temperature, its adhesion limit with it, and the global factor
//! that suits the field (near 1) throws these cells across the switch at every update: the iteration
//! settles into a cycle of period 2–4. Once the iteration stalls, the coupled solver therefore switches on
//! **per-cell damping** ([`Relaxation::damp_cells`]): T_i ← T_i + ω·c_i·Δ_i with a factor c_i per cell that
//! halves (down to 0.02) whenever the cell's increment reverses its sign and exceeds a tenth of the largest,
//! and otherwise grows by 1.2 back up to 1. Aitken's factor is then estimated over the undamped cells
//! (c_i = 1) only: the damped cells' reversals would otherwise pull ω to its floor and leave the rest of the
//! field creeping at 2 % of its increment per update.

/// Smallest and largest relaxation factor.
const OMEGA_RANGE: (f64, f64) = (0.02, 1.0);

/// Per-cell damping: a cell's increment reversing its sign counts as an oscillation where it exceeds this
/// fraction of the largest increment.
const REVERSAL_SHARE: f64 = 0.1;
/// Per-cell damping: the factor by which an oscillating cell's factor is multiplied.
const DAMPING: f64 = 0.5;
/// Per-cell damping: growth of a cell's factor per update while the cell does not oscillate.
const RECOVERY: f64 = 1.2;

/// The relaxation factor and the previous increment.
pub(super) struct Relaxation {
    /// The current factor ω [-].
    omega: f64,
    /// The increment T_target − T of the previous update [K].
    previous: Option<Vec<f64>>,
    /// The per-cell damping factors c_i ∈ [0.02, 1], once switched on ([`Relaxation::damp_cells`]).
    cells: Option<Vec<f64>>,
}

impl Relaxation {
    /// Starts with the factor `omega` (`solver.relaxation`).
    pub fn new(omega: f64) -> Self {
        Self {
            omega,
            previous: None,
            cells: None,
        }
    }

    /// Whether the updates so far were plain fixed-point steps T ← T_target (ω = 1, every per-cell factor
    /// 1): then successive increments shrink by the contraction factor of the fixed-point map.
    pub fn is_plain(&self) -> bool {
        self.omega == 1.0 && self.along_increment()
    }

    /// Whether every per-cell factor is 1 (or per-cell damping is off): the last update moved the
    /// temperature along its increment, T ← T + ω·Δ, so that the change of the target over its step
    /// measures the contraction of the fixed-point map along the increment.
    pub fn along_increment(&self) -> bool {
        self.cells.iter().flatten().all(|c| *c == 1.0)
    }

    /// Takes back an extrapolated update: the iteration continues from the plain step T ← T_target of
    /// the previous iterate (the caller sets that temperature), so the factor is 1 and the previous
    /// increment stays that of the previous iterate.
    pub fn reject(&mut self) {
        self.omega = OMEGA_RANGE.1;
    }

    /// Switches on per-cell damping from the next update on (every factor starting at 1); see the module
    /// documentation.
    pub fn damp_cells(&mut self) {
        if self.cells.is_none() {
            self.cells = Some(Vec::new());
        }
    }

    /// Halves the factor (after a backtracked update).
    pub fn damp(&mut self) {
        self.omega *= 0.5;
    }

    /// Extrapolates along `increment` [K] for the measured contraction factor `q` ∈ [0, 1) of the fixed
    /// point (increments shrinking by q along it, from one side): Aitken's ω = 1/(1 − q), `temperature`
    /// moved by ω·`increment`. While per-cell damping is on, the plain [`Relaxation::apply`] instead (the
    /// damped cells do not contract); returns whether it extrapolated.
    pub fn extrapolate(&mut self, temperature: &mut [f64], increment: Vec<f64>, q: f64) -> bool {
        if self.cells.is_some() {
            self.apply(temperature, increment);
            return false;
        }
        self.omega = 1.0 / (1.0 - q);
        for (t, d) in temperature.iter_mut().zip(&increment) {
            *t += self.omega * d;
        }
        self.previous = Some(increment);
        true
    }

    /// Updates ω by Aitken's Δ² from the previous increment (if any; ω is kept, at most 1, when the
    /// increments agree) and, once switched on, the per-cell factors c_i, then moves `temperature` by
    /// ω·c_i·`increment`_i (c_i = 1 without per-cell damping) [K].
    pub fn apply(&mut self, temperature: &mut [f64], increment: Vec<f64>) {
        if let Some(cells) = &mut self.cells {
            damp_oscillating(cells, &increment, self.previous.as_deref());
        }
        if let Some(prev) = &self.previous {
            // with per-cell damping on, over the undamped cells only: the damped ones oscillate, and
            // their reversals would pull ω to its floor and leave the rest of the field creeping
            let damped = |i: usize| self.cells.as_ref().is_some_and(|c| c[i] < 1.0);
            let mut num = 0.0;
            let mut den = 0.0;
            for (i, (r1, r0)) in increment.iter().zip(prev).enumerate() {
                if damped(i) {
                    continue;
                }
                let d = r1 - r0;
                num += r0 * d;
                den += d * d;
            }
            if den > 0.0 {
                self.omega = (-self.omega * num / den).clamp(OMEGA_RANGE.0, OMEGA_RANGE.1);
            }
        }
        // (after an extrapolation ω > 1 may have been kept: no plain update extrapolates)
        self.omega = self.omega.min(OMEGA_RANGE.1);
        // (without per-cell damping c_i = 1: ω·1·Δ_i is ω·Δ_i to the bit)
        let cells = self.cells.as_deref();
        for (i, (t, d)) in temperature.iter_mut().zip(&increment).enumerate() {
            let c = cells.map_or(1.0, |c| c[i]);
            *t += self.omega * c * d;
        }
        self.previous = Some(increment);
    }
}

/// Updates the per-cell damping factors `cells` (resized to 1 per cell at first) for the increment
/// `increment` after `previous` [K]: halved where the increment reverses its sign and exceeds
/// [`REVERSAL_SHARE`] of the largest, else grown by [`RECOVERY`], within [0.02, 1].
fn damp_oscillating(cells: &mut Vec<f64>, increment: &[f64], previous: Option<&[f64]>) {
    if cells.len() != increment.len() {
        *cells = vec![1.0; increment.len()];
    }
    let Some(previous) = previous else {
        return;
    };
    let largest = increment.iter().fold(0.0, |m: f64, d| m.max(d.abs()));
    for ((c, d), p) in cells.iter_mut().zip(increment).zip(previous) {
        *c = if d * p < 0.0 && d.abs() > REVERSAL_SHARE * largest {
            (*c * DAMPING).max(OMEGA_RANGE.0)
        } else {
            (*c * RECOVERY).min(OMEGA_RANGE.1)
        };
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

    /// A fixed point T = g(T) of three cells: one follows a switch (a step of 16 K smoothed over ±1/4 K,
    /// slope −32 at its fixed point T = 10 K, as a cell whose film switches with its temperature), two
    /// follow smooth contractions. The global factor alone cycles (its Aitken estimate suits the smooth
    /// cells); with per-cell damping the iteration converges to the exact fixed point (10, 10, 2/0.7 K).
    #[test]
    fn per_cell_damping_settles_a_steep_cell_that_the_global_factor_keeps_cycling() {
        let g = |t: &[f64]| {
            vec![
                10.0 - 8.0 * (4.0 * (t[0] - 10.0)).tanh(),
                0.5 * t[1] + 5.0,
                0.3 * t[2] + 0.2 * t[0],
            ]
        };
        let fixed = [10.0, 10.0, 2.0 / 0.7];
        // the temperatures after `n` updates from T = (12, 0, 0), with or without per-cell damping
        let run = |per_cell: bool, n: usize| {
            let mut r = Relaxation::new(1.0);
            if per_cell {
                r.damp_cells();
            }
            let mut t = vec![12.0, 0.0, 0.0];
            for _ in 0..n {
                let increment: Vec<f64> = g(&t).iter().zip(&t).map(|(a, b)| a - b).collect();
                r.apply(&mut t, increment);
            }
            t
        };
        let cycling = run(false, 400);
        assert!((cycling[0] - fixed[0]).abs() > 0.1, "{cycling:?}");
        let settled = run(true, 400);
        for (x, f) in settled.iter().zip(fixed) {
            assert!((x - f).abs() < 1e-9, "{settled:?}");
        }
        // a cell whose increment reverses is damped (c = 1/2), the other moves by ω·Δ; the update is then
        // no plain fixed-point step
        let mut r = Relaxation::new(1.0);
        r.damp_cells();
        let mut t = vec![0.0, 0.0];
        r.apply(&mut t, vec![1.0, 1.0]);
        assert!(r.is_plain());
        r.apply(&mut t, vec![-1.0, 1.0]);
        // Aitken over the undamped cell only, whose increments agree: ω stays 1 (over both cells it would
        // be −1·(1·(−2) + 1·0)/(4 + 0) = 1/2)
        assert_eq!(t, vec![1.0 - 0.5, 1.0 + 1.0]);
        assert!(!r.is_plain());
    }

    /// A damped cell whose increment reverses at every update (±8 K, a cell that keeps switching) next to a
    /// smooth cell contracting by 0.9 per plain step towards 10 K. Counted into Aitken's factor, the
    /// reversals would halve ω at every update down to its floor 0.02 (then the smooth cell creeps: 2.7 K
    /// after 80 updates); estimated over the undamped cells only, ω stays 1 and the smooth cell converges
    /// as under the plain iteration (within 0.9⁸⁰·10 K).
    #[test]
    fn the_global_factor_is_estimated_over_the_undamped_cells() {
        let mut r = Relaxation::new(1.0);
        r.damp_cells();
        let mut t: Vec<f64> = vec![0.0, 0.0];
        for k in 0..80 {
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            let increment = vec![8.0 * sign, 0.9 * t[1] + 1.0 - t[1]];
            r.apply(&mut t, increment);
        }
        assert_eq!(r.omega, 1.0);
        assert!((t[1] - 10.0).abs() < 0.01, "{t:?}");
        assert_eq!(r.cells.as_deref().map(|c| c[0]), Some(OMEGA_RANGE.0));
    }
}
