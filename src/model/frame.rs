//! The caller's operating point in the frame the model is solved in, and the results turned back
//! (docs/model.md §1).
//!
//! - **Rolling backwards** (V < 0): the material enters the patch at x = −a instead of +a. The contact is
//!   solved in the frame turned by 180° about z (x' = −x, y' = −y), in which it rolls forwards at |V|. A
//!   rotation about z leaves spin and moment unchanged and reverses in-plane vectors, so the creepages there
//!   are ξ' = −ξ, η' = −η, φ' = φ, and the results turn back as F_x = −F'_x, F_y = −F'_y, M_z = M'_z.
//!   Consequence: without spin the forces depend on the slip direction only (same F for ±V), while the
//!   lateral force due to spin and the spin moment due to creepage (from the slip zone at the trailing
//!   edge) change sign with the rolling direction, as in Kalker's theory.
//! - **Standstill:** |V| below the minimum speed is raised to it, so a creepage still means a slip
//!   velocity and nothing divides by zero; V = 0 counts as forwards.
//! - **Wetness** outside [0, 1] is clamped to it.

use crate::error::Result;
use crate::params::OperatingPoint;
use crate::table::{INPUTS, Jacobian};

/// The caller's operating point in the solved frame.
#[derive(Debug, Clone, Copy)]
pub(super) struct Solved {
    /// The point the model evaluates: rolling forwards at |V| ≥ the minimum speed, wetness in [0, 1].
    pub point: OperatingPoint,
    /// −1 rolling backwards (the creepages ξ, η and the forces F_x, F_y turn), else 1.
    turn: f64,
    /// ∂point/∂input per coordinate (ξ, η, φ, F_N, V, w), a diagonal: the turn for ξ and η, the sign of V
    /// unless raised to the minimum speed, 0 for a clamped wetness.
    chain: [f64; INPUTS],
}

impl Solved {
    /// The point of `input` (any sign of speed, any wetness) in the solved frame, with |V| raised to
    /// `minimum_speed` [m/s].
    pub fn of(input: &OperatingPoint, minimum_speed: f64) -> Solved {
        let wetness = input.wetness.clamp(0.0, 1.0);
        let speed = input.speed;
        // rolling backwards: solve in the frame turned by 180° about z (module documentation)
        let turn = if speed < 0.0 { -1.0 } else { 1.0 };
        Solved {
            point: OperatingPoint {
                creepage_x: turn * input.creepage_x,
                creepage_y: turn * input.creepage_y,
                spin: input.spin,
                normal_force: input.normal_force,
                // not f64::max, which would turn a NaN speed into the minimum speed
                speed: if speed.abs() < minimum_speed {
                    minimum_speed
                } else {
                    speed.abs()
                },
                wetness,
            },
            turn,
            chain: [
                turn,
                turn,
                1.0,
                1.0,
                if speed.abs() > minimum_speed {
                    turn
                } else {
                    0.0
                },
                if wetness == input.wetness { 1.0 } else { 0.0 },
            ],
        }
    }

    /// Whether the wetness was clamped to [0, 1].
    pub fn wetness_clamped(&self) -> bool {
        self.chain[5] == 0.0
    }

    /// Checks the solved point with the creepages of `input` (the caller's point it was made of), so that
    /// an error names the values the caller gave (the allowed creepage ranges are symmetric: the turned
    /// point passes exactly when this does). Forwards there is nothing to turn and the evaluation's own
    /// check suffices.
    pub fn check(&self, input: &OperatingPoint) -> Result<()> {
        if self.turn > 0.0 {
            return Ok(());
        }
        OperatingPoint {
            creepage_x: input.creepage_x,
            creepage_y: input.creepage_y,
            ..self.point
        }
        .validate()
    }

    /// Turns forces (F'_x, F'_y) of the solved frame back into the caller's: F_x = −F'_x, F_y = −F'_y
    /// rolling backwards [N].
    pub fn turn_back(&self, force_x: &mut f64, force_y: &mut f64) {
        *force_x *= self.turn;
        *force_y *= self.turn;
    }

    /// The Jacobian of the outputs with respect to the caller's inputs from the one in the solved frame:
    /// F_x and F_y turn back with the frame, the inputs enter through the chain factors.
    pub fn jacobian_back(&self, jac: &Jacobian) -> Jacobian {
        let out_turn = [self.turn, self.turn, 1.0, 1.0, 1.0, 1.0];
        std::array::from_fn(|r| std::array::from_fn(|c| out_turn[r] * jac[r][c] * self.chain[c]))
    }
}
