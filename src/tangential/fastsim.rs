//! FASTSIM (Kalker, Vehicle System Dynamics 11, 1982) with a locally varying adhesion limit τ_l per cell
//! (paper §2.4, docs/model.md §6).

use super::kalker::KalkerCoefficients;
use crate::contact::ContactGrid;
use crate::error::{Error, Result, check_finite, check_positive};
use std::f64::consts::PI;

/// Flexibilities of Kalker's simplified theory (displacement per traction) [m/Pa], chosen so that the
/// simplified theory reproduces Kalker's linear creep law (docs/model.md §6, Kalker 1982):
/// L1 = 8a/(3·G·C11), L2 = 8a/(3·G·C22), L3 = π·a²/(4·G·c·C23), c = sqrt(a·b).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flexibilities {
    /// Longitudinal flexibility L1 [m/Pa].
    pub l1: f64,
    /// Lateral flexibility L2 [m/Pa].
    pub l2: f64,
    /// Spin flexibility L3 [m/Pa].
    pub l3: f64,
}

impl Flexibilities {
    /// Flexibilities for semi-axes `a`, `b` [m], shear modulus `shear_modulus` [Pa] and Kalker's
    /// coefficients `k` (docs/model.md §6).
    pub fn new(a: f64, b: f64, shear_modulus: f64, k: &KalkerCoefficients) -> Self {
        let c = (a * b).sqrt();
        Self {
            l1: 8.0 * a / (3.0 * shear_modulus * k.c11),
            l2: 8.0 * a / (3.0 * shear_modulus * k.c22),
            l3: PI * a * a / (4.0 * shear_modulus * c * k.c23),
        }
    }

    /// The flexibilities with an interfacial layer of compliance h/G₃ = `compliance` [m/Pa] in series
    /// with the half-spaces' (docs/model.md §6.7): L_i' = L_i + h/G₃ for i = 1, 2, 3. The layer's shear
    /// h·τ/G₃ is a local (Winkler) displacement, so it adds to the simplified theory's u = L·τ alike for
    /// every traction component; for spin too, since it has no spin-specific part. 0: unchanged (bit for
    /// bit).
    pub fn with_layer(self, compliance: f64) -> Self {
        Self {
            l1: self.l1 + compliance,
            l2: self.l2 + compliance,
            l3: self.l3 + compliance,
        }
    }

    /// Combined flexibility L = (|ξ|·L1 + |η|·L2 + c·|φ|·L3)/sqrt(ξ² + η² + c²·φ²) [m/Pa] that converts the
    /// traction excess of a slipping cell into slip (docs/model.md §6); exact for a single creepage. Zero when
    /// all creepages vanish (no cell can slip then).
    pub fn combined(&self, creep: Creepages, c: f64) -> f64 {
        let norm = (creep.xi * creep.xi + creep.eta * creep.eta + (c * creep.phi).powi(2)).sqrt();
        if norm > 0.0 {
            (creep.xi.abs() * self.l1 + creep.eta.abs() * self.l2 + c * creep.phi.abs() * self.l3)
                / norm
        } else {
            0.0
        }
    }
}

/// Kalker's creepages (docs/model.md §1): the rigid slip of the wheel relative to the rail at (x, y) is
/// V·(ξ − φ·y, η + φ·x).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Creepages {
    /// Longitudinal creepage ξ [-].
    pub xi: f64,
    /// Lateral creepage η [-].
    pub eta: f64,
    /// Spin creepage φ [1/m].
    pub phi: f64,
}

/// Result of [`fastsim`]: resultants and per-cell fields (cells in [`ContactGrid::cells`] order).
///
/// Sign convention (Kalker, docs/model.md §1): tractions and forces act on the wheel and oppose the rigid slip,
/// e.g. F_x = −G·c²·C11·ξ in the linear limit.
#[derive(Debug, Clone, PartialEq)]
pub struct TractionField {
    /// Longitudinal force F_x = Σ p_x·h_x·h_y [N].
    pub force_x: f64,
    /// Lateral force F_y = Σ p_y·h_x·h_y [N].
    pub force_y: f64,
    /// Spin moment M_z = Σ (x·p_y − y·p_x)·h_x·h_y [N·m].
    pub spin_moment: f64,
    /// Tangential traction [p_x, p_y] per cell [Pa].
    pub traction: Vec<[f64; 2]>,
    /// Slip velocity of the wheel relative to the rail per cell [m/s]; zero in stick, opposite to the
    /// traction on the wheel in slip.
    pub slip_velocity: Vec<[f64; 2]>,
    /// Frictional power density q = |p|·|s| per cell [W/m²].
    pub power_density: Vec<f64>,
    /// True where the cell slips (the stick predictor exceeded τ_l).
    pub slipping: Vec<bool>,
}

impl TractionField {
    /// Total frictional power Σ q·h_x·h_y [W] (the heat source of docs/model.md §7).
    pub fn frictional_power(&self, grid: &ContactGrid) -> f64 {
        grid.integrate(&self.power_density)
    }
}

/// FASTSIM with a locally varying adhesion limit `tau_limit` = τ_l per cell [Pa] (paper §2.4, docs/model.md §6;
/// Kalker 1982). `speed` is the rolling speed V [m/s].
///
/// Every strip of `grid` is marched from zero traction at its leading edge x = +a(y) backwards. The step Δ
/// is a(y) − x for the first cell (so the stick solution is exact at cell centres) and h_x afterwards.
/// Stick predictor
///   p_x ← p_x − (ξ/L1 − φ·y/L3)·Δ,  p_y ← p_y − (η/L2 + φ·x_m/L3)·Δ,
/// with x_m the **midpoint of the step** (as in Kalker's FASTSIM): the exact integral of the linear spin
/// term over the step, so the stick solution p_y = −φ·(a(y)² − x²)/(2·L3) is exact at cell centres and the
/// pure-spin linear limit F_y = −G·c³·C23·φ is reproduced. (Taking x_m at the end of the step biases the
/// spin force by O(h_x/a): measured −11 % on a 30 × 30 grid, −3.4 % on 100 × 100.)
/// If |p_trial| > τ_l the cell slips and |p| = τ_l. Without spin the direction e of p is that of p_trial
/// (FASTSIM's projection, exact there: e = −w/|w| throughout). Under spin the rigid slip
/// w = (ξ/L1 − φ·y/L3, η/L2 + φ·x/L3) turns along the strip and projecting (a backward-Euler step of the
/// slip-zone equation de/dt = −(w − (w·e)·e)/τ) made F_y, M_z converge at first order (F_y +3.4 % at
/// φ = 1 /m, +9.9 % at φ = 3 /m on 30 × 30 for the reference contact); instead the equation is solved from
/// the onset of slip within the step ([`slip_onset`], where the stick march reaches the limit) to its end
/// ([`slip_direction`], w and τ linear): second order in h_x, and continuous in the creepages across every
/// stick/slip switch (docs/model.md §6.3).
/// The slip velocity is s = −V·L·max(0, (p_trial − p)·e)/Δ·e, the step's mean elastic slip along −e
/// (magnitude V·L·(|p_trial| − τ_l)/Δ where e ∥ p_trial), with the combined flexibility L of
/// [`Flexibilities::combined`], and q = |p|·|s|. τ_l = 0 is allowed (no traction).
pub fn fastsim(
    grid: &ContactGrid,
    creep: Creepages,
    speed: f64,
    flex: &Flexibilities,
    tau_limit: &[f64],
) -> Result<TractionField> {
    check_finite("creepage xi", creep.xi, "")?;
    check_finite("creepage eta", creep.eta, "")?;
    check_finite("spin creepage phi", creep.phi, "1/m")?;
    check_positive("speed", speed, "m/s")?;
    check_positive("flexibility L1", flex.l1, "m/Pa")?;
    check_positive("flexibility L2", flex.l2, "m/Pa")?;
    check_positive("flexibility L3", flex.l3, "m/Pa")?;
    if tau_limit.len() != grid.len() {
        return Err(Error::OutOfRange {
            name: "adhesion limit tau_l (number of values)".to_string(),
            value: tau_limit.len().to_string(),
            allowed: format!("one value per grid cell ({})", grid.len()),
        });
    }
    if let Some(&bad) = tau_limit.iter().find(|t| !(t.is_finite() && **t >= 0.0)) {
        return Err(Error::out_of_range(
            "adhesion limit tau_l",
            bad,
            "finite, >= 0 Pa",
        ));
    }

    let n = grid.len();
    let c = (grid.a * grid.b).sqrt();
    let slip_factor = speed * flex.combined(creep, c);
    let mut field = TractionField {
        force_x: 0.0,
        force_y: 0.0,
        spin_moment: 0.0,
        traction: vec![[0.0; 2]; n],
        slip_velocity: vec![[0.0; 2]; n],
        power_density: vec![0.0; n],
        slipping: vec![false; n],
    };
    let rate_x_base = creep.xi / flex.l1;
    let rate_y_base = creep.eta / flex.l2;
    let spin_rate = creep.phi / flex.l3;
    // Without spin the rigid slip does not turn along a strip: the traction stays along −w, the projection
    // is then exact and the direction needs no integration.
    let turning = creep.phi != 0.0;
    for strip in &grid.strips {
        let y = strip.y;
        let rate_x = rate_x_base - spin_rate * y;
        let (mut px, mut py) = (0.0_f64, 0.0_f64);
        let mut x_prev = strip.half_length;
        // Adhesion limit at the start of the step: the previous cell's (the first cell's own at the
        // leading edge).
        let mut tau_prev = strip.cells.clone().next().map_or(0.0, |k| tau_limit[k]);
        for idx in strip.cells.clone() {
            let x = grid.cells[idx].x;
            // Centres lie strictly inside the ellipse; max() only guards against rounding.
            let step = (x_prev - x).max(0.0);
            let rate_y = rate_y_base + spin_rate * 0.5 * (x_prev + x);
            let trial_x = px - rate_x * step;
            let trial_y = py - rate_y * step;
            let tau = tau_limit[idx];
            let magnitude = (trial_x * trial_x + trial_y * trial_y).sqrt();
            if magnitude > tau {
                let (traction, slip, velocity) = if turning {
                    // The step's stick march p(s) = p − s·(p − p_trial) reaches the limit at s* (the
                    // onset of slip in the step); from there the slip-zone equation turns the direction.
                    let onset = slip_onset([px, py], [trial_x, trial_y], tau_prev, tau);
                    let tau_onset = tau_prev + onset * (tau - tau_prev);
                    let at_onset = [px + onset * (trial_x - px), py + onset * (trial_y - py)];
                    let norm = at_onset[0].hypot(at_onset[1]);
                    let rigid_at = |x: f64| [rate_x, rate_y_base + spin_rate * x];
                    let w_onset = rigid_at(x_prev - onset * step);
                    let w_end = rigid_at(x);
                    let dir = slip_direction(
                        if norm > 0.0 {
                            [at_onset[0] / norm, at_onset[1] / norm]
                        } else {
                            // slip from zero traction: along −w
                            let m = w_onset[0].hypot(w_onset[1]).max(f64::MIN_POSITIVE);
                            [-w_onset[0] / m, -w_onset[1] / m]
                        },
                        w_onset,
                        w_end,
                        (1.0 - onset) * step * inverse_log_mean(tau_onset, tau),
                    );
                    // The step's mean elastic slip V·L·(p_trial − p)/Δ along −dir.
                    let excess = (trial_x * dir[0] + trial_y * dir[1]) - tau;
                    let slip = slip_factor * excess.max(0.0) / step;
                    let traction = [tau * dir[0], tau * dir[1]];
                    (traction, slip, [-slip * dir[0], -slip * dir[1]])
                } else {
                    // Projection p = p_trial·τ/|p_trial|: s = V·L·(p − p_trial)/Δ has magnitude
                    // V·L·(|p_trial| − τ)/Δ and points along −p_trial.
                    let inv_magnitude = 1.0 / magnitude;
                    let scale = tau * inv_magnitude;
                    let slip = slip_factor * (magnitude - tau) / step;
                    let along = -slip * inv_magnitude;
                    (
                        [trial_x * scale, trial_y * scale],
                        slip,
                        [along * trial_x, along * trial_y],
                    )
                };
                [px, py] = traction;
                field.slip_velocity[idx] = velocity;
                field.power_density[idx] = tau * slip;
                field.slipping[idx] = true;
            } else {
                px = trial_x;
                py = trial_y;
            }
            field.traction[idx] = [px, py];
            field.force_x += px;
            field.force_y += py;
            field.spin_moment += x * py - y * px;
            x_prev = x;
            tau_prev = tau;
        }
    }
    let area = grid.cell_area();
    field.force_x *= area;
    field.force_y *= area;
    field.spin_moment *= area;
    Ok(field)
}

/// Onset of slip within a step, s* ∈ [0, 1] [-]: where the stick march p(s) = p0 + s·(p1 − p0) from the
/// traction `p0` [Pa] at the step's start to the stick trial `p1` at its end last reaches the adhesion
/// limit τ(s) = τ0 + s·(τ1 − τ0) [Pa] (linear between the cells), i.e. the largest root in [0, 1] of
/// g(s) = |p(s)|² − τ(s)², given g(1) > 0 (the cell slips). s* = 0 where the step starts in slip (|p0| = τ0),
/// s* → 1 where the cell only just slips, so the march is continuous across every stick/slip switch.
fn slip_onset(p0: [f64; 2], p1: [f64; 2], tau0: f64, tau1: f64) -> f64 {
    let d = [p1[0] - p0[0], p1[1] - p0[1]];
    let dtau = tau1 - tau0;
    // g(s) = a·s² + 2·h·s + c
    let a = d[0] * d[0] + d[1] * d[1] - dtau * dtau;
    let h = p0[0] * d[0] + p0[1] * d[1] - tau0 * dtau;
    let c = p0[0] * p0[0] + p0[1] * p0[1] - tau0 * tau0;
    let disc = h * h - a * c;
    let root = if disc < 0.0 {
        // No crossing: g > 0 throughout (a rounding-level start on the limit) or, impossible given g(1) > 0,
        // g < 0 throughout.
        if a > 0.0 { 0.0 } else { 1.0 }
    } else {
        // Roots (−h ± √disc)/a, the larger where g rises through it (a > 0), the smaller where g is
        // concave; q = −(h + sign(h)·√disc) gives both without cancellation: q/a and c/q.
        let q = -(h + disc.sqrt().copysign(h));
        let (r1, r2) = if q == 0.0 {
            (0.0, 0.0)
        } else if a == 0.0 {
            (c / q, c / q)
        } else {
            let (u, v) = (q / a, c / q);
            (u.min(v), u.max(v))
        };
        if a >= 0.0 { r2 } else { r1 }
    };
    root.clamp(0.0, 1.0)
}

/// Reciprocal of the logarithmic mean of two adhesion limits, ln(τ1/τ0)/(τ1 − τ0) [1/Pa]: (1/Δ)·∫dt/τ(t) for τ
/// linear over a step of length Δ. Infinite if either is zero. Near τ0 = τ1 by its series
/// (2/(τ0 + τ1))·(1 + δ²/3 + δ⁴/5 + δ⁶/7 + δ⁸/9), δ = (τ1 − τ0)/(τ1 + τ0), truncation < δ¹⁰/11 ≤ 1e-11.
fn inverse_log_mean(tau0: f64, tau1: f64) -> f64 {
    if tau0 <= 0.0 || tau1 <= 0.0 {
        return f64::INFINITY;
    }
    let sum = tau0 + tau1;
    let d = (tau1 - tau0) / sum;
    if d.abs() <= 0.1 {
        let d2 = d * d;
        2.0 / sum * (1.0 + d2 * (1.0 / 3.0 + d2 * (0.2 + d2 * (1.0 / 7.0 + d2 / 9.0))))
    } else {
        (tau1 / tau0).ln() / (tau1 - tau0)
    }
}

/// Angle [rad] in (−π, π] from `from` to `to` (vectors of any length, `cross` = from × to, `dot` = from·to);
/// for small angles (|cross| ≤ 0.1·dot) by the series of atan (truncation < t¹¹/11 ≤ 1e-12).
fn turn_angle(cross: f64, dot: f64) -> f64 {
    if dot > 0.0 && cross.abs() <= 0.1 * dot {
        let t = cross / dot;
        let t2 = t * t;
        t * (1.0 - t2 * (1.0 / 3.0 - t2 * (0.2 - t2 * (1.0 / 7.0 - t2 / 9.0))))
    } else {
        cross.atan2(dot)
    }
}

/// Direction e of the traction after a slipping step of length Δ, from `dir` = e0 [-], where the rigid slip
/// w [Pa/m] goes linearly from `w_start` to `w_end` and `step_over_tau` = ∫dt/τ over the step [m/Pa]: the
/// slip-zone equation de/dt = −(w − (w·e)·e)/τ (docs/model.md §6.3), solved by [`relax_turning`] in a frame
/// that turns uniformly by ψ about the step's mean direction ū = −w_m/|w_m| (w_m = w at the midpoint), with
/// the relaxation k·Δ = |w_m|·∫dt/τ.
///
/// ψ = Δθ·cos²(Δθ/2), Δθ ∈ (−π, π] the turn of −w over the step. Where the rigid slip turns little
/// (every step once the grid resolves the turn) ψ = Δθ − O(Δθ³): the frame follows the target and the
/// step keeps the exact lag of a turning target (second order). Where w passes close to zero within the
/// step, Δθ approaches ±π with a sign that flips with the side w passes on, while the real turn is
/// concentrated where |w| ≈ 0 and relaxation is weak; there ψ → 0 from both sides and the step relaxes
/// towards ū in a fixed frame (exact where w keeps its line, the limit w_x → 0), so e is continuous in the
/// creepages. w_m = 0 leaves e unchanged (no relaxation).
fn slip_direction(
    dir: [f64; 2],
    w_start: [f64; 2],
    w_end: [f64; 2],
    step_over_tau: f64,
) -> [f64; 2] {
    let w_mid = [0.5 * (w_start[0] + w_end[0]), 0.5 * (w_start[1] + w_end[1])];
    let norm = w_mid[0].hypot(w_mid[1]);
    if norm == 0.0 {
        return dir;
    }
    let mean = [-w_mid[0] / norm, -w_mid[1] / norm];
    let turn = turn_angle(
        w_start[0] * w_end[1] - w_start[1] * w_end[0],
        w_start[0] * w_end[0] + w_start[1] * w_end[1],
    );
    let half = 0.5 * turn * (0.5 * turn).cos().powi(2);
    let (sin, cos) = half.sin_cos();
    relax_turning(
        dir,
        [cos * mean[0] + sin * mean[1], cos * mean[1] - sin * mean[0]],
        [cos * mean[0] - sin * mean[1], cos * mean[1] + sin * mean[0]],
        norm * step_over_tau,
    )
}

/// Direction e of the traction after a slipping step: the exact solution of FASTSIM's slip-zone equation
/// de/dt = −(w − (w·e)·e)/τ (docs/model.md §6.3) over a step of length Δ along the march, from `dir` = e0
/// [-], for a rigid slip w [Pa/m] going linearly along the step, whose target directions u = −w/|w| at the
/// step's ends are `target_start`, `target_end` [-] (zero where w = 0), and `k_step` = k·Δ [-] with the mean
/// relaxation rate k = |w_m|/τ_m (w_m = w at the step's midpoint, 1/τ_m from [`inverse_log_mean`]).
///
/// With χ the angle from u to e, the equation reads χ' = −k·sin χ − Ω, Ω the turning rate of u [rad/m].
/// For constant k and Ω (u turning uniformly by the angle between its ends) this Riccati equation is
/// solved exactly: (sin(χ/2), cos(χ/2)) evolves linearly under exp(M·Δ), M = [[−k/2, −Ω/2], [Ω/2, k/2]].
/// Hence e trails a turning u by its lag asin(Ω/k) where slip relaxes fast (k·Δ ≫ 1) and turns with the
/// step's mean w where it relaxes slowly; both limits are exact and the step is second order in Δ.
fn relax_turning(
    dir: [f64; 2],
    target_start: [f64; 2],
    target_end: [f64; 2],
    k_step: f64,
) -> [f64; 2] {
    let (u_start, u_end) = (target_start, target_end);
    if u_start == [0.0; 2] || u_end == [0.0; 2] {
        // No rigid slip at an end of the step: the direction is kept (a null set of steps).
        return dir;
    }
    if k_step.is_nan() || k_step > 1e100 {
        // Relaxation complete within the step (τ = 0, or e^(−k·Δ) and the lag below 1e-100): e is the target.
        return u_end;
    }
    let turn = turn_angle(
        u_start[0] * u_end[1] - u_start[1] * u_end[0],
        u_start[0] * u_end[0] + u_start[1] * u_end[1],
    );
    // Half-angle vector (sin(χ0/2), cos(χ0/2)) of χ0 = angle from u_start to e0.
    let cos0 = (dir[0] * u_start[0] + dir[1] * u_start[1]).clamp(-1.0, 1.0);
    let sin0 = u_start[0] * dir[1] - u_start[1] * dir[0];
    let half = [
        (0.5 * (1.0 - cos0)).sqrt().copysign(sin0),
        (0.5 * (1.0 + cos0)).sqrt(),
    ];
    // exp(M·Δ) = C·I + S·(M·Δ) up to a positive factor, (s·Δ)² = ((kΔ)² − (ΩΔ)²)/4 choosing cosh/sinh
    // (scaled by e^(−s·Δ) against overflow) or cos/sin.
    let s2 = 0.25 * (k_step * k_step - turn * turn);
    let (c, s) = if s2 >= 0.0 {
        let sr = s2.sqrt();
        // 1 − e^(−x), x = 2·s·Δ, by its series where exp would lose digits (relative truncation < x⁴/120).
        let x = 2.0 * sr;
        let rise = if x > 1e-3 {
            1.0 - (-x).exp()
        } else {
            x * (1.0 - x * (0.5 - x * (1.0 / 6.0 - x / 24.0)))
        };
        (1.0 - 0.5 * rise, if sr > 0.0 { rise / x } else { 1.0 })
    } else {
        let sr = (-s2).sqrt();
        let (sin, cos) = sr.sin_cos();
        (cos, if sr > 1e-8 { sin / sr } else { 1.0 })
    };
    let y1 = (c - 0.5 * s * k_step) * half[0] - 0.5 * s * turn * half[1];
    let y2 = 0.5 * s * turn * half[0] + (c + 0.5 * s * k_step) * half[1];
    let norm2 = y1 * y1 + y2 * y2;
    let (cos1, sin1) = ((y2 * y2 - y1 * y1) / norm2, 2.0 * y1 * y2 / norm2);
    [
        cos1 * u_end[0] - sin1 * u_end[1],
        cos1 * u_end[1] + sin1 * u_end[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::HertzContact;
    use crate::tangential::kalker_coefficients;

    // docs/model.md §2 reference contact: F_N = 100 kN, a = 5.879 mm, b = 10.54 mm, steel ν = 0.28.
    const A: f64 = 5.879e-3;
    const B: f64 = 10.54e-3;
    const FN: f64 = 100e3;
    const NU: f64 = 0.28;
    const G: f64 = 210e9 / (2.0 * 1.28);
    const V: f64 = 30.0;
    const MU: f64 = 0.3;

    struct Case {
        grid: ContactGrid,
        k: KalkerCoefficients,
        flex: Flexibilities,
        tau: Vec<f64>,
    }

    /// Grid n × m over the reference contact with τ_l = μ·p_n (parabolic p_n).
    fn case(n: usize, m: usize) -> Case {
        let hertz = HertzContact::from_semi_axes(A, B, FN).unwrap();
        let grid = ContactGrid::new(A, B, n, m);
        let k = kalker_coefficients(A, B, NU).unwrap();
        let flex = Flexibilities::new(A, B, G, &k);
        let tau = grid
            .cells
            .iter()
            .map(|c| MU * hertz.parabolic_pressure(c.x, c.y))
            .collect();
        Case { grid, k, flex, tau }
    }

    fn run(c: &Case, xi: f64, eta: f64, phi: f64) -> TractionField {
        fastsim(&c.grid, Creepages { xi, eta, phi }, V, &c.flex, &c.tau).unwrap()
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    /// Small creepage reproduces Kalker's linear theory, F_x = −G·c²·C11·ξ, F_y = −G·c²·C22·η and
    /// F_y = −G·c³·C23·φ (docs/model.md §1, §6).
    #[test]
    fn kalker_linear_limit() {
        let c = case(100, 100);
        let c2 = A * B;
        let cc = c2.sqrt();
        let xi = 1e-6;
        let f = run(&c, xi, 0.0, 0.0);
        let want = -G * c2 * c.k.c11 * xi;
        assert!(rel(f.force_x, want) < 0.02, "F_x {} vs {want}", f.force_x);
        assert_eq!(f.force_y, 0.0);
        let f = run(&c, 0.0, xi, 0.0);
        let want = -G * c2 * c.k.c22 * xi;
        assert!(rel(f.force_y, want) < 0.02, "F_y {} vs {want}", f.force_y);
        assert!(f.force_x == 0.0);
        let phi = xi / cc;
        let f = run(&c, 0.0, 0.0, phi);
        let want = -G * c2 * cc * c.k.c23 * phi;
        assert!(
            rel(f.force_y, want) < 0.02,
            "spin F_y {} vs {want}",
            f.force_y
        );
        assert!(f.force_x.abs() < 1e-9 * f.force_y.abs());
        // Simplified theory in stick: p_x = (φ·y/L3)·(a(y) − x) gives M_z = −(φ/L3)·(8/15)·a²·b³.
        let want = -(phi / c.flex.l3) * 8.0 / 15.0 * A * A * B.powi(3);
        assert!(
            rel(f.spin_moment, want) < 0.02,
            "M_z {} vs {want}",
            f.spin_moment
        );
        assert!(f.slipping.iter().filter(|&&s| s).count() < c.grid.len() / 20);
    }

    /// Large creepage: full slip, |F| → Σ τ_l·h_x·h_y, for constant μ and for an arbitrary τ_l field with
    /// zeros; the force points against the creepage direction weighted by 1/L (ξ/L1, η/L2).
    #[test]
    fn saturation_to_full_slip() {
        let mut c = case(60, 60);
        let limit = |c: &Case| c.grid.integrate(&c.tau);
        for (xi, eta) in [(0.05, 0.0), (0.03, -0.04)] {
            let f = run(&c, xi, eta, 0.0);
            assert!(rel(f.force_x.hypot(f.force_y), limit(&c)) < 5e-3);
            let (dx, dy) = (xi / c.flex.l1, eta / c.flex.l2);
            let cross = f.force_x * dy - f.force_y * dx;
            assert!(cross.abs() < 1e-9 * f.force_x.hypot(f.force_y) * dx.hypot(dy));
            assert!(f.force_x * dx + f.force_y * dy < 0.0);
        }
        // Arbitrary field: varying μ between 0.1 and 0.5 and cells without adhesion.
        for (k, cell) in c.grid.cells.iter().enumerate() {
            let wave = (7.0 * cell.x / A + 3.0 * cell.y / B).sin();
            let pn = c.tau[k] / MU;
            c.tau[k] = if wave > 0.8 {
                0.0
            } else {
                (0.3 + 0.2 * wave) * pn
            };
        }
        assert!(c.tau.iter().filter(|&&t| t == 0.0).count() > 50);
        let f = run(&c, 0.5, 0.2, 0.0);
        assert!(rel(f.force_x.hypot(f.force_y), limit(&c)) < 5e-3);
        assert!(f.slipping.iter().all(|&s| s));
        for (p, t) in f.traction.iter().zip(&c.tau) {
            assert!((p[0].hypot(p[1]) - t).abs() <= 1e-9 * t);
        }
        // With spin the traction directions differ: |F| stays below the limit.
        let f = run(&c, 0.0, 0.0, 100.0);
        assert!(f.force_x.hypot(f.force_y) < limit(&c));
    }

    /// Odd symmetry in the creepages, lateral mirror symmetry, and spin producing F_y and M_z.
    #[test]
    fn symmetries() {
        let c = case(40, 40);
        let (xi, eta, phi) = (2e-3, -1e-3, 0.3);
        let f = run(&c, xi, eta, phi);
        let g = run(&c, -xi, -eta, -phi);
        assert_eq!(f.force_x, -g.force_x);
        assert_eq!(f.force_y, -g.force_y);
        assert_eq!(f.spin_moment, -g.spin_moment);
        assert_eq!(f.power_density, g.power_density);
        // Mirror y → −y: (ξ, η, φ) → (ξ, −η, −φ) gives (F_x, −F_y, −M_z).
        let m = run(&c, xi, -eta, -phi);
        let scale = f.force_x.hypot(f.force_y);
        assert!((m.force_x - f.force_x).abs() < 1e-9 * scale);
        assert!((m.force_y + f.force_y).abs() < 1e-9 * scale);
        assert!((m.spin_moment + f.spin_moment).abs() < 1e-9 * f.spin_moment.abs());
        // η → −η without spin flips F_y only.
        let p = run(&c, xi, eta, 0.0);
        let q = run(&c, xi, -eta, 0.0);
        assert!((p.force_x - q.force_x).abs() < 1e-9 * p.force_x.abs());
        assert!((p.force_y + q.force_y).abs() < 1e-9 * p.force_y.abs());
        // Pure ξ: odd in ξ, no lateral force, no moment.
        let p = run(&c, xi, 0.0, 0.0);
        let q = run(&c, -xi, 0.0, 0.0);
        assert!(p.force_x < 0.0 && q.force_x == -p.force_x);
        assert_eq!(p.force_y, 0.0);
        assert!(p.spin_moment.abs() < 1e-9 * p.force_x.abs() * A);
        // Spin alone: lateral force and moment, both opposing φ > 0 (Kalker's convention).
        let s = run(&c, 0.0, 0.0, phi);
        assert!(s.force_y < 0.0 && s.spin_moment < 0.0);
        assert!(s.force_x.abs() < 1e-9 * s.force_y.abs());
    }

    /// Simplified theory on one strip with parabolic limit τ = τ_c·(1 − x²/l²) and pure ξ (a 2-D Carter-type
    /// problem solved analytically): stick for x > x_s = l·(2u − 1), slip behind, with u = ξ·l/(2·L1·τ_c);
    /// strip force / full-slip force = 1 − (1 − u)³ (u < 1), and in slip s = V·(ξ + L1·dτ/dx) =
    /// V·(ξ − 2·L1·τ_c·x/l²).
    #[test]
    fn strip_analytic_solution() {
        let c = case(400, 1);
        let strip = &c.grid.strips[0];
        assert_eq!(strip.y, 0.0);
        let l = strip.half_length;
        let tau_c = MU * 2.0 * FN / (PI * A * B);
        let full: f64 = c.tau.iter().sum();
        for u in [0.05, 0.2, 0.5, 0.8, 0.95, 1.5] {
            let xi = u * 2.0 * c.flex.l1 * tau_c / l;
            let f = run(&c, xi, 0.0, 0.0);
            let ratio = -f.traction.iter().map(|p| p[0]).sum::<f64>() / full;
            let want = 1.0 - (1.0 - u.min(1.0)).powi(3);
            assert!((ratio - want).abs() < 2e-3, "u = {u}: {ratio} vs {want}");
            let x_s = l * (2.0 * u - 1.0);
            let h = c.grid.hx;
            for (k, cell) in c.grid.cells.iter().enumerate() {
                if cell.x > x_s + h {
                    assert!(!f.slipping[k], "u = {u}: stick expected at x = {}", cell.x);
                } else if cell.x < x_s - h {
                    assert!(f.slipping[k], "u = {u}: slip expected at x = {}", cell.x);
                    // dτ/dx taken at the middle of the step (exact difference quotient of the
                    // parabola); the first step starts at the leading edge l.
                    let gradient = 2.0 * c.flex.l1 * tau_c / (l * l);
                    let mid = 0.5 * (cell.x + (cell.x + h).min(l));
                    let want = V * (xi - gradient * mid);
                    let s = f.slip_velocity[k];
                    let scale = V * xi.max(gradient * l);
                    assert!(
                        (s[0] - want).abs() < 1e-6 * scale,
                        "u = {u}, x = {}",
                        cell.x
                    );
                    assert!(s[1] == 0.0 && s[0] * f.traction[k][0] <= 0.0);
                }
            }
        }
    }

    /// Whole ellipse, constant μ, pure ξ: the strip law integrated over y,
    /// F_x/(μ·F_N) = (8/(3π))·∫_{−1}^{1} σ³·[1 − (1 − min(1, u0/σ))³] dY, σ = sqrt(1 − Y²),
    /// u0 = 3·G·C11·ξ/(16·μ·p0) (reference by quadrature, Y = sin θ).
    #[test]
    fn ellipse_traction_creepage_curve() {
        let c = case(200, 200);
        let p0 = 2.0 * FN / (PI * A * B);
        let full = c.grid.integrate(&c.tau);
        let n = 20_000;
        for xi in [2e-4, 1e-3, 2e-3, 3e-3] {
            let u0 = 3.0 * G * c.k.c11 * xi / (16.0 * MU * p0);
            let dtheta = PI / n as f64;
            let integral: f64 = (0..n)
                .map(|i| {
                    let s = (-0.5 * PI + (i as f64 + 0.5) * dtheta).cos();
                    let u = (u0 / s).min(1.0);
                    s.powi(4) * (1.0 - (1.0 - u).powi(3)) * dtheta
                })
                .sum();
            let want = 8.0 / (3.0 * PI) * integral;
            let got = -run(&c, xi, 0.0, 0.0).force_x / full;
            assert!(
                (got - want).abs() < 0.01 * want,
                "ξ = {xi}: {got} vs {want}"
            );
        }
    }

    /// Grid convergence under spin (docs/model.md §6.3): against the Richardson extrapolation of 480 × 480 and
    /// 960 × 960 (order 2), the errors of F_y and M_z on n × n grids stay below 0.5 %·(30/n)² for n = 30 … 240
    /// (a first-order march, such as FASTSIM's projection of every slipping cell, has 10 % at n = 30 and
    /// φ = 3 /m and falls only as 1/n), and under pure spin successive differences shrink by ≥ 3.5 per halving
    /// of the cell (order ≥ 1.8).
    #[test]
    fn spin_converges_at_second_order() {
        for (xi, eta, phi) in [(0.0, 0.0, 1.0), (0.0, 0.0, 3.0), (1e-3, 1e-3, 3.0)] {
            let results: Vec<[f64; 2]> = [30, 60, 120, 240, 480, 960]
                .iter()
                .map(|&n| {
                    let f = run(&case(n, n), xi, eta, phi);
                    [f.force_y, f.spin_moment]
                })
                .collect();
            for (q, name) in ["F_y", "M_z"].into_iter().enumerate() {
                let value = |k: usize| results[k][q];
                let reference = value(5) + (value(5) - value(4)) / 3.0;
                for (k, n) in [30.0_f64, 60.0, 120.0, 240.0].iter().enumerate() {
                    let error = rel(value(k), reference);
                    let bound = 5e-3 * (30.0 / n).powi(2);
                    assert!(
                        error < bound,
                        "(ξ, η, φ) = ({xi}, {eta}, {phi}), {name}, {n} cells: {error:.2e} > {bound:.2e}"
                    );
                }
                if xi == 0.0 {
                    let ratio = (value(3) - value(4)) / (value(4) - value(5));
                    assert!(ratio >= 3.5, "φ = {phi}, {name}: ratio {ratio}");
                }
            }
        }
    }

    /// The march is continuous in the creepages: sweeping ξ (or φ) in steps δ = 1e-6 (1/300 of the
    /// saturation creepage; φ in steps of 3e-4 /m) across hundreds of stick/slip switches and a strip whose
    /// rigid slip w passes through zero, no step of F_x, F_y or M_z exceeds 3 times the median step. (Choosing
    /// per cell between the projection and the slip-direction march, as before, jumped F_y by 4.6 N at
    /// ξ = 0.003001 on 12 × 12, and F_x by 88 N, 27 times the median step, where w_x changes sign on a strip
    /// in slip at (η, φ) = (0.002, 1 /m).)
    #[test]
    fn continuous_in_the_creepages() {
        let c = case(12, 12);
        let delta = 1e-6;
        for (sweep, fixed) in [
            ("xi", [-1e-3, 0.2]),
            ("xi", [2e-3, 1.0]),
            ("phi", [3e-3, -1e-3]),
        ] {
            let forces: Vec<[f64; 3]> = (0..3000)
                .map(|i| {
                    let v = i as f64 * delta;
                    let f = match sweep {
                        "xi" => run(&c, v, fixed[0], fixed[1]),
                        _ => run(&c, fixed[0], fixed[1], v * 300.0),
                    };
                    [f.force_x, f.force_y, f.spin_moment]
                })
                .collect();
            for (q, name) in ["F_x", "F_y", "M_z"].into_iter().enumerate() {
                let mut steps: Vec<f64> = forces
                    .windows(2)
                    .map(|w| (w[1][q] - w[0][q]).abs())
                    .collect();
                let largest = steps.iter().copied().fold(0.0, f64::max);
                steps.sort_by(f64::total_cmp);
                let median = steps[steps.len() / 2];
                assert!(
                    largest <= 3.0 * median,
                    "{sweep} sweep at {fixed:?}, {name}: a step of {largest:.3e}, median {median:.3e}"
                );
            }
        }
    }

    /// `slip_direction` against a Runge–Kutta integration (RK4, 20 000 steps) of de/dt = −(w − (w·e)·e)/τ with
    /// w and τ linear over the step: relaxing (kΔ ≲ 1) the local error of one step falls as Δ³ (a
    /// second-order march); stiff (kΔ up to 16) it stays below 0.01·Δ rad; and where w passes through zero within the step e is
    /// continuous in w_x (the signed turn flips from +π to −π there).
    #[test]
    fn slip_direction_is_second_order_and_continuous() {
        let angle = |t: f64| [t.cos(), t.sin()];
        let rk4 = |e0: [f64; 2], w0: [f64; 2], w1: [f64; 2], tau: [f64; 2]| {
            let n = 20_000;
            let h = 1.0 / n as f64;
            let rate = |t: f64, a: f64| {
                let w = [w0[0] + t * (w1[0] - w0[0]), w0[1] + t * (w1[1] - w0[1])];
                let ta = tau[0] + t * (tau[1] - tau[0]);
                (w[0] * a.sin() - w[1] * a.cos()) / ta
            };
            let mut a = e0[1].atan2(e0[0]);
            for i in 0..n {
                let t = i as f64 * h;
                let k1 = rate(t, a);
                let k2 = rate(t + 0.5 * h, a + 0.5 * h * k1);
                let k3 = rate(t + 0.5 * h, a + 0.5 * h * k2);
                let k4 = rate(t + h, a + h * k3);
                a += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            }
            angle(a)
        };
        let gap = |a: [f64; 2], b: [f64; 2]| {
            (a[0] * b[1] - a[1] * b[0])
                .atan2(a[0] * b[0] + a[1] * b[1])
                .abs()
        };
        // w turning by 0.6 rad per unit length [Pa/m over a step of unit length], τ falling 30 %.
        for (scale, tau0) in [(1.0, 1.0), (40.0, 1.0)] {
            let errors: Vec<f64> = [0.4, 0.2, 0.1, 0.05, 0.025]
                .iter()
                .map(|&h: &f64| {
                    let w0 = [scale, 0.3 * scale];
                    let w1 = [scale, (0.3 + 0.8 * h) * scale];
                    let tau = [tau0, tau0 * (1.0 - 0.3 * h)];
                    // each step of length h: w and ∫dt/τ scale with it (the ODE's time is the step fraction)
                    let (w0, w1) = (w0.map(|v| v * h), w1.map(|v| v * h));
                    let e0 = angle(0.5);
                    let want = rk4(e0, w0, w1, tau);
                    let got = slip_direction(e0, w0, w1, inverse_log_mean(tau[0], tau[1]));
                    gap(got, want)
                })
                .collect();
            for (k, h) in [0.4, 0.2, 0.1, 0.05, 0.025].iter().enumerate() {
                if scale == 1.0 && k < 4 {
                    assert!(
                        errors[k] >= 6.0 * errors[k + 1],
                        "relaxing: errors {errors:?}"
                    );
                }
                // stiff: e sits at the quasi-steady lag behind −w, modelled at the step's mean w; such an
                // error is forgotten at the rate k, it does not accumulate
                assert!(errors[k] <= 0.01 * h, "scale {scale}: errors {errors:?}");
            }
        }
        // w from (±ε, −1) to (±ε, 1): the turn is ±π, the direction is not
        let e0 = angle(2.0);
        let plus = slip_direction(e0, [1e-9, -1.0], [1e-9, 1.0], 0.7);
        let minus = slip_direction(e0, [-1e-9, -1.0], [-1e-9, 1.0], 0.7);
        let zero = slip_direction(e0, [0.0, -1.0], [0.0, 1.0], 0.7);
        assert!(
            gap(plus, minus) < 1e-8 && gap(plus, zero) < 1e-8,
            "{plus:?} {minus:?} {zero:?}"
        );
        // exact there: w keeps the line w_x = 0, the step is the fixed-frame solution
        let want = rk4(e0, [0.0, -1.0], [0.0, 1.0], [1.0 / 0.7, 1.0 / 0.7]);
        assert!(gap(zero, want) < 1e-9, "{zero:?} vs {want:?}");
    }

    /// `relax_turning` against a Runge–Kutta (RK4, 20 000 steps) integration of χ' = −k·sin χ − Ω for a
    /// target turning uniformly by ΩΔ: relaxing (k > |Ω|), overtaken (|Ω| > k), stiff (kΔ = 50: χ1 = the lag
    /// −asin(Ω/k)) and from the unstable side (χ0 near π); without turning tan(χ1/2) = tan(χ0/2)·e^(−kΔ).
    #[test]
    fn slip_direction_solves_the_slip_zone_equation() {
        let angle = |t: f64| [t.cos(), t.sin()];
        for (chi0, k_step, turn) in [
            (1.0, 0.7, 0.3),
            (-2.0, 0.4, -1.5),
            (0.3, 50.0, 0.8),
            (3.1, 2.0, 0.0),
            (-0.5, 0.0, 2.0),
        ] {
            let (u0, u1) = (0.4_f64, 0.4 + turn);
            let e = relax_turning(angle(u0 + chi0), angle(u0), angle(u1), k_step);
            let chi1 = (e[1].atan2(e[0]) - u1 + PI).rem_euclid(2.0 * PI) - PI;
            let n = 20_000;
            let h = 1.0 / n as f64;
            let rate = |c: f64| -k_step * c.sin() - turn;
            let mut c = chi0;
            for _ in 0..n {
                let k1 = rate(c);
                let k2 = rate(c + 0.5 * h * k1);
                let k3 = rate(c + 0.5 * h * k2);
                let k4 = rate(c + h * k3);
                c += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            }
            let want = (c + PI).rem_euclid(2.0 * PI) - PI;
            assert!(
                (chi1 - want).abs() < 1e-9,
                "{chi0}, {k_step}, {turn}: {chi1} vs {want}"
            );
            if turn == 0.0 {
                let closed = 2.0 * ((0.5 * chi0).tan() * (-k_step).exp()).atan();
                assert!((chi1 - closed).abs() < 1e-12);
            }
            if k_step == 50.0 {
                assert!((chi1 + (turn / k_step).asin()).abs() < 1e-12);
            }
        }
        // τ = 0 (infinite k): the target itself.
        assert_eq!(
            relax_turning(angle(2.0), angle(0.0), [0.0, 1.0], f64::INFINITY),
            [0.0, 1.0]
        );
    }

    /// Frictional power: q ≥ 0 everywhere, zero in pure rolling and in stick; at full slip the slip
    /// velocity approaches the rigid slip V·|ξ| and the total power |F_x|·V·|ξ|.
    #[test]
    fn frictional_power() {
        let c = case(60, 60);
        let rolling = run(&c, 0.0, 0.0, 0.0);
        assert_eq!(rolling.frictional_power(&c.grid), 0.0);
        assert_eq!(rolling.force_x, 0.0);
        for (xi, eta, phi) in [(1e-4, 0.0, 0.0), (1e-3, 5e-4, 0.5), (-4e-3, 1e-3, -2.0)] {
            let f = run(&c, xi, eta, phi);
            assert!(f.power_density.iter().all(|&q| q >= 0.0));
            assert!(f.frictional_power(&c.grid) > 0.0);
            for k in 0..c.grid.len() {
                if !f.slipping[k] {
                    assert_eq!(f.slip_velocity[k], [0.0, 0.0]);
                    assert_eq!(f.power_density[k], 0.0);
                } else {
                    let (p, s) = (f.traction[k], f.slip_velocity[k]);
                    assert!(
                        p[0] * s[0] + p[1] * s[1] <= 0.0,
                        "slip not against traction"
                    );
                }
            }
        }
        // Full slip: s = V·(ξ + L1·dτ/dx) deviates from V·ξ by at most V·2·L1·μ·p0/a (about 2.4 % of V·ξ
        // at ξ = 0.2, at the strip ends), and the correction integrates to zero over each strip.
        let xi = 0.2;
        let f = run(&c, xi, 0.0, 0.0);
        let rigid = V * xi;
        assert!(f.slipping.iter().all(|&s| s));
        for s in &f.slip_velocity {
            assert!(
                (s[0] - rigid).abs() < 0.03 * rigid && s[1] == 0.0,
                "{s:?} vs {rigid}"
            );
        }
        let power = f.frictional_power(&c.grid);
        assert!(rel(power, f.force_x.abs() * rigid) < 0.01);
    }

    /// Zero adhesion limit: no traction, no power.
    #[test]
    fn zero_limit_carries_nothing() {
        let mut c = case(20, 20);
        c.tau.iter_mut().for_each(|t| *t = 0.0);
        let f = run(&c, 1e-3, 1e-3, 1.0);
        assert_eq!((f.force_x, f.force_y, f.spin_moment), (0.0, 0.0, 0.0));
        assert_eq!(f.frictional_power(&c.grid), 0.0);
        assert!(f.slipping.iter().all(|&s| s));
    }

    #[test]
    fn bad_input_is_an_error() {
        let c = case(10, 10);
        let ok = Creepages {
            xi: 1e-3,
            eta: 0.0,
            phi: 0.0,
        };
        let bad = Creepages { xi: f64::NAN, ..ok };
        assert!(fastsim(&c.grid, bad, V, &c.flex, &c.tau).is_err());
        let bad = Creepages {
            phi: f64::INFINITY,
            ..ok
        };
        assert!(fastsim(&c.grid, bad, V, &c.flex, &c.tau).is_err());
        assert!(fastsim(&c.grid, ok, 0.0, &c.flex, &c.tau).is_err());
        assert!(fastsim(&c.grid, ok, V, &c.flex, &c.tau[1..]).is_err());
        let mut tau = c.tau.clone();
        tau[3] = -1.0;
        assert!(fastsim(&c.grid, ok, V, &c.flex, &tau).is_err());
        tau[3] = f64::NAN;
        assert!(fastsim(&c.grid, ok, V, &c.flex, &tau).is_err());
        let flex = Flexibilities { l1: 0.0, ..c.flex };
        assert!(fastsim(&c.grid, ok, V, &flex, &c.tau).is_err());
        assert!(fastsim(&c.grid, ok, V, &c.flex, &c.tau).is_ok());
    }
}
