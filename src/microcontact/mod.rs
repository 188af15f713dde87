//! Microcontact: Greenwood–Williamson asperity statistics with the Zhao–Maietta–Chang single-asperity law
//! (docs/model.md §4; paper eqs. (P4), (P5)).
//!
//! The two rough surfaces are replaced by one equivalent rough surface against a rigid flat: asperity
//! summits of radius R_a, heights z ~ N(0, z_s²) (P4), areal density η_s. At separation d (mean summit
//! plane to flat, paper Fig. 3) an asperity of height z has interference ω = z − d, and per unit nominal
//! area
//!
//! - A_m/A_n = η_s·∫_d^∞ A(z − d)·φ(z) dz,   p_m·A_m/A_n = η_s·∫_d^∞ P(z − d)·φ(z) dz,
//!
//! with A, P the ZMC law ([`asperity_contact`]) at the local E*, H, ν. [`Microcontact::evaluate`] is the
//! fast evaluation (dimensionless form in `gw`, interpolated from the table of `gw_table` where it covers
//! ω_c/z_s and d/z_s, direct quadrature elsewhere), [`Microcontact::separation_for_load`] its inverse.

mod gw;
mod gw_table;
mod table;

use crate::error::{Error, Result, Stage, check_finite, check_positive, check_range};
use crate::materials::MaterialState;
use crate::params::{Param, Roughness};
use gw::{Integrals, Law, PLASTIC_RATIO, Scheme};
use gw_table::{GwTable, Interpolant, IntervalNodes, Stencil};
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Gauss–Legendre nodes on each sub-interval of the elasto-plastic band.
const BAND_NODES: usize = 16;
/// Sub-intervals of the elasto-plastic band (equal in √ω).
const BAND_PIECES: usize = 2;
/// Gauss–Legendre nodes of the direct elastic piece [0, ω_c] used when ω_c is small.
const ELASTIC_NODES: usize = 8;
/// ω_c/z_s below which the elastic part is integrated directly instead of as F_1.5 minus its tail.
const DIRECT_BELOW: f64 = 0.25;
/// Loads below this fraction of the load scale L0 = β·E*·sqrt(z_s/R_a) count as "no contact".
pub const LOAD_FLOOR: f64 = 1e-12;
/// Search range of the separation in units of z_s for [`Microcontact::separation_for_load`].
pub const SEPARATION_RANGE: (f64, f64) = (-50.0, 12.0);
/// Iteration limit of [`Microcontact::separation_for_load`].
const MAX_ITERATIONS: usize = 100;
/// Largest |ln(load/target)| at which the last Newton step is taken without a further evaluation.
const TERMINAL_RESIDUAL: f64 = 1e-7;

/// Asperity statistics of the equivalent rough surface (docs/model.md §4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// Standard deviation of the summit heights z_s [m].
    pub z_s: f64,
    /// Summit radius R_a [m].
    pub r_a: f64,
    /// Areal density of summits η_s [1/m²].
    pub eta_s: f64,
}

impl Surface {
    /// The surface of a roughness parameter set (docs/model.md §4 mapping of k_r).
    pub fn from_roughness(r: &Roughness) -> Self {
        Self {
            z_s: r.z_s(),
            r_a: r.r_a(),
            eta_s: r.eta_s(),
        }
    }

    /// Greenwood–Williamson parameter β = η_s·R_a·z_s [-].
    pub fn beta(&self) -> f64 {
        self.eta_s * self.r_a * self.z_s
    }
}

/// Fraction of asperities in contact at separation d [m]: ψ(d) = ½·erfc(d/(√2·z_s)) (P5; docs/model.md §4, §8
/// where ψ(z) is also the metallic surface fraction at height z, P9).
pub fn contact_probability(d: f64, z_s: f64) -> f64 {
    gw::upper_tail(d / z_s)
}

/// ZMC factor K = 0.454 + 0.41·ν (hardness-to-yield relation at the onset of yield).
pub fn zmc_k(poisson: f64) -> f64 {
    0.454 + 0.41 * poisson
}

/// Critical interference at the onset of yield ω_c = (π·K·H/(2E*))²·R_a [m] (ZMC; docs/model.md §4).
pub fn critical_interference(r_a: f64, e_star: f64, hardness: f64, poisson: f64) -> f64 {
    let x = PI * zmc_k(poisson) * hardness / (2.0 * e_star);
    x * x * r_a
}

/// Single-asperity Zhao–Maietta–Chang law (Zhao, Maietta & Chang, J. Tribol. 122 (2000); docs/model.md §4):
/// contact area A [m²] and load P [N] of a summit of radius `r_a` [m] at interference `omega` [m], composite
/// modulus `e_star` [Pa], hardness [Pa], Poisson's ratio.
/// - elastic, ω ≤ ω_c: A = π·R_a·ω, P = (4/3)·E*·sqrt(R_a)·ω^1.5;
/// - elasto-plastic, ω_c < ω < ω_p = 54·ω_c, t = (ω − ω_c)/(ω_p − ω_c): A = π·R_a·ω·(1 − 2t³ + 3t²),
///   P = A·H·[1 − (1 − 2K/3)·(ln ω_p − ln ω)/(ln ω_p − ln ω_c)];
/// - fully plastic, ω ≥ ω_p: A = 2π·R_a·ω, P = H·A.
///
/// Returns (0, 0) for ω ≤ 0 (no contact).
pub fn asperity_contact(
    omega: f64,
    r_a: f64,
    e_star: f64,
    hardness: f64,
    poisson: f64,
) -> (f64, f64) {
    if omega <= 0.0 {
        return (0.0, 0.0);
    }
    let omega_c = critical_interference(r_a, e_star, hardness, poisson);
    let omega_p = PLASTIC_RATIO * omega_c;
    if omega <= omega_c {
        (
            PI * r_a * omega,
            4.0 / 3.0 * e_star * r_a.sqrt() * omega.powf(1.5),
        )
    } else if omega < omega_p {
        let t = (omega - omega_c) / (omega_p - omega_c);
        let area = PI * r_a * omega * (1.0 - 2.0 * t * t * t + 3.0 * t * t);
        let lambda = (omega_p.ln() - omega.ln()) / (omega_p.ln() - omega_c.ln());
        let k = zmc_k(poisson);
        (
            area,
            area * hardness * (1.0 - (1.0 - 2.0 * k / 3.0) * lambda),
        )
    } else {
        let area = 2.0 * PI * r_a * omega;
        (area, hardness * area)
    }
}

/// Result of one microcontact evaluation at a separation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MicroState {
    /// Separation d of the mean summit plane from the flat [m].
    pub separation: f64,
    /// Real contact area fraction A_m/A_n [-]. Not capped at 1 (GW assumes a small fraction): at 20 °C
    /// with k_r = 0 it is 0.79 at the centre of the 100 kN default contact and 0.93 at 200 kN.
    pub area_fraction: f64,
    /// Metallic load per nominal area p_m·A_m/A_n [Pa].
    pub load: f64,
    /// d(p_m·A_m/A_n)/dd [Pa/m] (< 0 while in contact).
    pub d_load_d_separation: f64,
    /// d(A_m/A_n)/dd [1/m] (< 0 while in contact).
    pub d_area_d_separation: f64,
}

/// Result of [`Microcontact::separation_for_load`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeparationSolve {
    /// The microcontact state at the separation found.
    pub state: MicroState,
    /// Newton/bisection iterations (evaluations) used.
    pub iterations: usize,
    /// Relative load residual |load(d) − target|/target, target = max(load, LOAD_FLOOR·L0) (after a terminal
    /// Newton step, its quadratic estimate r², r the log-load residual before the step).
    pub residual: f64,
    /// Whether the residual and the last step met the tolerances.
    pub converged: bool,
    /// The requested load was below LOAD_FLOOR·L0 (practically no metallic contact): the separation
    /// returned is the one that carries that floor load, and state.load is the floor, not the request.
    pub below_floor: bool,
}

/// The microcontact submodel of one rough surface: the tabulated integrals, the direct quadrature and the
/// F_1.5 table.
#[derive(Debug, Clone)]
pub struct Microcontact {
    surface: Surface,
    /// sqrt(z_s/R_a).
    sqrt_ratio: f64,
    scheme: Scheme,
    /// The table of the first K = 0.454 + 0.41ν met (the process-wide table of each K is shared).
    table: OnceLock<&'static GwTable>,
}

/// The microcontact of one surface and material state (one c = ω_c/z_s and K): the dimensionless
/// integrals from the table's stencil at c when the table covers c and h, else by the direct quadrature,
/// and their scales. Made by [`Microcontact::integrator`] for many evaluations at one material state
/// ([`Integrator::state`]).
#[derive(Debug, Clone, Copy)]
pub struct Integrator<'a> {
    stencil: Option<Stencil>,
    c: f64,
    k: f64,
    scheme: &'a Scheme,
    z_s: f64,
    /// A_m/A_n = πβ·𝒜.
    area_scale: f64,
    /// p_m·A_m/A_n = L0·𝒫.
    load_scale: f64,
}

/// The dimensionless integrals at one h, from the table or the direct quadrature, with 𝒜 (and its
/// derivative) evaluated only when asked for: the root finding of [`Microcontact::separation_for_load`]
/// needs the area of its last iterate only.
enum Evaluation {
    /// Interpolated in the table.
    Table(Interpolant),
    /// By the direct quadrature (all four at once).
    Direct(Integrals),
}

impl Evaluation {
    /// 𝒫 and d𝒫/dh.
    #[inline]
    fn load(&self) -> (f64, f64) {
        match self {
            Evaluation::Table(i) => i.load(),
            Evaluation::Direct(q) => (q.load, q.dload),
        }
    }

    /// 𝒜 and d𝒜/dh.
    #[inline]
    fn area(&self) -> (f64, f64) {
        match self {
            Evaluation::Table(i) => i.area(),
            Evaluation::Direct(q) => (q.area, q.darea),
        }
    }
}

/// The load part of a [`MicroState`] at a separation, with what completes it ([`Integrator::complete`]).
struct LoadState {
    /// Separation d [m].
    separation: f64,
    /// p_m·A_m/A_n [Pa].
    load: f64,
    /// d(p_m·A_m/A_n)/dd [Pa/m].
    d_load_d_separation: f64,
    evaluation: Evaluation,
}

impl Integrator<'_> {
    /// 𝒜, 𝒫 and their h-derivatives at h = d/z_s, 𝒜 when asked for.
    #[inline]
    fn evaluation(&self, h: f64) -> Evaluation {
        match self.stencil.and_then(|s| s.interpolant(h)) {
            Some(i) => Evaluation::Table(i),
            None => Evaluation::Direct(self.scheme.integrals(h, &Law::new(self.c, self.k))),
        }
    }

    /// ln 𝒫 and d(ln 𝒫)/dh at h = d/z_s, with the evaluation there ([`Self::load_state_of`]): no
    /// exponential or logarithm when tabulated, the nodes of h's interval kept in `nodes` for the next
    /// call (the root finding of [`Microcontact::separation_for_load`] works on ln(load)). Where 𝒫 = 0
    /// (beyond the asperities' reach): ln 𝒫 = −∞ and a NaN derivative.
    #[inline]
    fn ln_load(&self, h: f64, nodes: &mut Option<IntervalNodes>) -> (f64, f64, Evaluation) {
        match self.stencil.and_then(|s| s.interpolant_reusing(h, nodes)) {
            Some(i) => {
                let (ln, dln) = i.ln_load();
                (ln, dln, Evaluation::Table(i))
            }
            None => {
                let q = self.scheme.integrals(h, &Law::new(self.c, self.k));
                let (ln, dln) = if q.load > 0.0 {
                    (q.load.ln(), q.dload / q.load)
                } else {
                    (f64::NEG_INFINITY, f64::NAN)
                };
                (ln, dln, Evaluation::Direct(q))
            }
        }
    }

    /// The load and its derivative at separation `d` [m] (those of [`Self::state`]).
    #[inline]
    fn load_state(&self, d: f64) -> LoadState {
        self.load_state_of(d, self.evaluation(d / self.z_s))
    }

    /// The load state at separation `d` [m] of the evaluation at h = d/z_s.
    #[inline]
    fn load_state_of(&self, d: f64, evaluation: Evaluation) -> LoadState {
        let (load, dload) = evaluation.load();
        LoadState {
            separation: d,
            load: self.load_scale * load,
            d_load_d_separation: self.load_scale * dload / self.z_s,
            evaluation,
        }
    }

    /// The microcontact state of a load state: its area fraction and derivative added.
    #[inline]
    fn complete(&self, s: &LoadState) -> MicroState {
        let (area, darea) = s.evaluation.area();
        MicroState {
            separation: s.separation,
            area_fraction: self.area_scale * area,
            load: s.load,
            d_load_d_separation: s.d_load_d_separation,
            d_area_d_separation: self.area_scale * darea / self.z_s,
        }
    }

    /// The microcontact state at separation `d` [m]: [`Microcontact::evaluate`] at the integrator's
    /// material state, bit for bit.
    #[inline]
    pub fn state(&self, d: f64) -> MicroState {
        self.complete(&self.load_state(d))
    }
}

impl Microcontact {
    /// Validates the roughness (z_s, R_a, η_s finite and positive) and prepares the quadrature. The
    /// process-wide tables (the GW table of `gw_table` and the F_1.5 table of the direct quadrature) are
    /// built on first use, the GW table block by block.
    pub fn new(roughness: &Roughness) -> Result<Self> {
        Param::RoughnessKr.spec().check(roughness.k_r)?;
        let surface = Surface::from_roughness(roughness);
        check_positive("roughness z_s", surface.z_s, "m")?;
        check_positive("roughness R_a", surface.r_a, "m")?;
        check_positive("roughness eta_s", surface.eta_s, "1/m^2")?;
        Ok(Self {
            surface,
            sqrt_ratio: (surface.z_s / surface.r_a).sqrt(),
            scheme: Scheme::new(BAND_NODES, BAND_PIECES, ELASTIC_NODES, DIRECT_BELOW),
            table: OnceLock::new(),
        })
    }

    /// The asperity statistics.
    pub fn surface(&self) -> &Surface {
        &self.surface
    }

    /// Load scale L0 = β·E*·sqrt(z_s/R_a) [Pa]: p_m·A_m/A_n = L0·𝒫(d/z_s) with 𝒫 = (4/3)·F_1.5 when elastic.
    pub fn load_scale(&self, mat: &MaterialState) -> f64 {
        self.surface.beta() * mat.e_star * self.sqrt_ratio
    }

    /// The integrator of a material state: c = ω_c/z_s and K, and the table stencil at c if tabulated
    /// (what [`Self::evaluate`] makes on every call; the film solve, which evaluates each cell at its
    /// material state many times, makes it once per cell).
    pub fn integrator(&self, mat: &MaterialState) -> Integrator<'_> {
        let omega_c =
            critical_interference(self.surface.r_a, mat.e_star, mat.hardness, mat.poisson);
        let (c, k) = (omega_c / self.surface.z_s, zmc_k(mat.poisson));
        let table = match self.table.get() {
            Some(t) if t.k().to_bits() == k.to_bits() => *t,
            Some(_) => GwTable::for_k(k),
            None => *self.table.get_or_init(|| GwTable::for_k(k)),
        };
        Integrator {
            stencil: table.stencil(c),
            c,
            k,
            scheme: &self.scheme,
            z_s: self.surface.z_s,
            area_scale: PI * self.surface.beta(),
            load_scale: self.load_scale(mat),
        }
    }

    /// A_m/A_n and p_m·A_m/A_n (docs/model.md §4, GW integrals with the ZMC law) and their derivatives with
    /// respect to d, at separation `d` [m] for the material at the local temperature (E*, H, ν > 0 as
    /// given by `Material::at`). `d` must be finite (NaN propagates); for d ≥ 38.5·z_s all results are 0.
    /// Inside the table (2e−3 ≤ ω_c/z_s ≤ 10, −10 ≤ d/z_s < 38.5) interpolated: relative accuracy ≤ 5e−10
    /// for the values and ≤ 1e−8 for the derivatives (see `gw_table`), about 50 ns per call. Elsewhere the
    /// direct quadrature: relative accuracy better than 1e−6 (measured ≤ 3e−7) against adaptive quadrature
    /// for −7 ≤ d/z_s ≤ 8 and any ω_c/z_s, about 0.4 µs per call.
    pub fn evaluate(&self, d: f64, mat: &MaterialState) -> MicroState {
        self.integrator(mat).state(d)
    }

    /// The separation d [m] at which p_m·A_m/A_n equals `load` [Pa] (inverse of [`Self::evaluate`]), by
    /// Newton's method on ln(load) safeguarded by bisection, starting from an estimate.
    /// Loads below LOAD_FLOOR·L0 return the separation of the floor load with `below_floor` set; a load
    /// above what the surface carries at d = −50·z_s is an error, as are negative or non-finite loads.
    pub fn separation_for_load(&self, load: f64, mat: &MaterialState) -> Result<SeparationSolve> {
        self.separation_for_load_from(load, mat, f64::NAN)
    }

    /// As [`Self::separation_for_load`], starting Newton from `guess` [m] (e.g. the previous iterate of a
    /// cell); a non-finite guess means "no guess".
    pub fn separation_for_load_from(
        &self,
        load: f64,
        mat: &MaterialState,
        guess: f64,
    ) -> Result<SeparationSolve> {
        check_finite("microcontact load", load, "Pa")?;
        if load < 0.0 {
            return Err(Error::out_of_range(
                "microcontact load",
                load,
                "finite, >= 0 Pa",
            ));
        }
        check_positive("E*", mat.e_star, "Pa")?;
        check_positive("hardness", mat.hardness, "Pa")?;
        check_range("poisson", mat.poisson, -1.0, 0.5, "")?;
        let z_s = self.surface.z_s;
        let integrator = self.integrator(mat);
        let scale = integrator.load_scale;
        let below_floor = load < LOAD_FLOOR * scale;
        let target = load.max(LOAD_FLOOR * scale);
        // Newton on the log-load residual r = ln(L0·𝒫(h)) − ln(target) = ln 𝒫(h) − ln(target/L0)
        let ln_relative_target = (target / scale).ln();
        let (mut lo, mut hi) = SEPARATION_RANGE;
        let mut lo_checked = false;
        let mut h = if guess.is_finite() {
            (guess / z_s).clamp(lo, hi)
        } else {
            initial_guess(target / scale)
        };
        let mut iterations = 0;
        let mut nodes = None;
        loop {
            iterations += 1;
            let (ln_p, slope, evaluation) = integrator.ln_load(h, &mut nodes);
            let r = ln_p - ln_relative_target;
            if r > 0.0 {
                lo = h;
                lo_checked = true;
            } else {
                hi = h;
            }
            // Newton step on ln(load): Δh = −r/(d ln 𝒫/dh)
            let mut step = if r.is_finite() && slope < 0.0 {
                -r / slope
            } else {
                f64::NAN
            };
            let converged = r.abs() <= 1e-13 && step.abs() <= 1e-12 * h.abs().max(1.0);
            // terminal Newton step: with |r| ≤ 1e-7 the step leaves an error O(r²) ≤ 1e-14, below the
            // tolerance, so it is taken and the state carried along to first order instead of being
            // evaluated again (one evaluation saved per solve, and a warm start that is already within
            // 1e-7 costs a single evaluation)
            if !converged && r.abs() <= TERMINAL_RESIDUAL && h + step > lo && h + step < hi {
                let mut state = integrator.complete(&integrator.load_state_of(h * z_s, evaluation));
                let dd = step * z_s;
                state.separation += dd;
                state.load += state.d_load_d_separation * dd;
                state.area_fraction += state.d_area_d_separation * dd;
                return Ok(SeparationSolve {
                    state,
                    iterations,
                    // the Newton error estimate: quadratic in the last residual
                    residual: r * r,
                    converged: true,
                    below_floor,
                });
            }
            if converged || iterations >= MAX_ITERATIONS {
                let state = integrator.complete(&integrator.load_state_of(h * z_s, evaluation));
                let residual = (state.load - target).abs() / target;
                return Ok(SeparationSolve {
                    state,
                    iterations,
                    residual,
                    converged: converged || (residual <= 1e-12 && hi - lo <= 1e-12),
                    below_floor,
                });
            }
            if !(h + step > lo && h + step < hi) {
                if !lo_checked {
                    // the root lies below the current iterate: make sure the range holds it at all
                    let bottom = integrator.load_state(lo * z_s);
                    iterations += 1;
                    if bottom.load < target {
                        return Err(Error::Numerical {
                            stage: Stage::Microcontact,
                            reason: format!(
                                "metallic load {load:.6e} Pa exceeds the {:.6e} Pa the surface carries at \
                                 d = {} z_s",
                                bottom.load, lo
                            ),
                        });
                    }
                    lo_checked = true;
                }
                step = 0.5 * (lo + hi) - h;
            }
            h += step;
        }
    }
}

/// Starting separation h = d/z_s for a dimensionless load T = load/L0, from the elastic asymptotes
/// 𝒫 ≈ (4/3)·|h|^1.5 for h → −∞ and −ln 𝒫 ≈ h²/2 (+ slower terms) for h → +∞, joined at 𝒫(0) ≈ 0.57.
/// Only a start: Newton with bisection does the rest.
fn initial_guess(t: f64) -> f64 {
    if t >= 0.57 {
        0.6 - (0.75 * t).powf(2.0 / 3.0)
    } else {
        0.85 * (2.0 * (0.57 / t).ln()).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::HertzContact;
    use crate::params::{CELSIUS_ZERO, Material};

    /// One G7/K15 panel: (Kronrod value, |Kronrod − Gauss|).
    fn gk15(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
        crate::quadrature::gauss_kronrod::gauss_kronrod_15(&f, a, b)
    }

    /// Globally adaptive Gauss–Kronrod quadrature (slow reference): bisects the interval with the largest
    /// error estimate until the summed estimate is below `rel`·∫|f| (or 4000 intervals).
    pub fn adaptive(f: &dyn Fn(f64) -> f64, a: f64, b: f64, rel: f64) -> f64 {
        let fabs = |u: f64| f(u).abs();
        let mut parts: Vec<(f64, f64, f64, f64, f64)> = vec![];
        let n0 = 16;
        for i in 0..n0 {
            let (x0, x1) = (
                a + (b - a) * i as f64 / n0 as f64,
                a + (b - a) * (i + 1) as f64 / n0 as f64,
            );
            let (v, e) = gk15(f, x0, x1);
            parts.push((x0, x1, v, e, gk15(&fabs, x0, x1).0));
        }
        for _ in 0..4000 {
            let scale: f64 = parts.iter().map(|p| p.4).sum();
            let err: f64 = parts.iter().map(|p| p.3).sum();
            if err <= rel * scale {
                break;
            }
            let (imax, _) = parts
                .iter()
                .enumerate()
                .max_by(|x, y| x.1.3.total_cmp(&y.1.3))
                .unwrap();
            let (x0, x1, ..) = parts.swap_remove(imax);
            let m = 0.5 * (x0 + x1);
            for (p, q) in [(x0, m), (m, x1)] {
                let (v, e) = gk15(f, p, q);
                parts.push((p, q, v, e, gk15(&fabs, p, q).0));
            }
        }
        parts.iter().map(|p| p.2).sum()
    }

    fn roughness(k_r: f64) -> Roughness {
        Roughness {
            k_r,
            ..Roughness::default()
        }
    }

    fn room() -> MaterialState {
        Material::default().at(20.0 + CELSIUS_ZERO)
    }

    /// Material with E*, H, ν chosen directly.
    fn material(e_star: f64, hardness: f64, poisson: f64) -> MaterialState {
        MaterialState {
            e_star,
            hardness,
            poisson,
            ..room()
        }
    }

    /// Independent reference: η_s·∫ A(z − d)·φ(z) dz, η_s·∫ P(z − d)·φ(z) dz and −η_s·∫ P(ω)·φ'(d + ω) dω
    /// by adaptive Gauss–Kronrod over ω, with the dimensional single-asperity law and breaks at ω_c, ω_p.
    fn reference(mc: &Microcontact, d: f64, m: &MaterialState) -> (f64, f64, f64) {
        let s = mc.surface();
        let phi = |z: f64| (-0.5 * (z / s.z_s).powi(2)).exp() / ((2.0 * PI).sqrt() * s.z_s);
        let law = |w: f64| asperity_contact(w, s.r_a, m.e_star, m.hardness, m.poisson);
        let oc = critical_interference(s.r_a, m.e_star, m.hardness, m.poisson);
        let top = (d.max(0.0) + 40.0 * s.z_s) - d;
        let bottom = (-40.0 * s.z_s - d).max(0.0);
        let mut brk = vec![bottom];
        for b in [oc, PLASTIC_RATIO * oc] {
            if b > bottom && b < top {
                brk.push(b);
            }
        }
        brk.push(top);
        let mut out = (0.0, 0.0, 0.0);
        for w in brk.windows(2) {
            let fa = |o: f64| s.eta_s * law(o).0 * phi(d + o);
            let fp = |o: f64| s.eta_s * law(o).1 * phi(d + o);
            let fd = |o: f64| -s.eta_s * law(o).1 * (d + o) / (s.z_s * s.z_s) * phi(d + o);
            out.0 += adaptive(&fa, w[0], w[1], 1e-13);
            out.1 += adaptive(&fp, w[0], w[1], 1e-13);
            out.2 += adaptive(&fd, w[0], w[1], 1e-13);
        }
        out
    }

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn reference_integrals_match_model_md() {
        // docs/model.md §4: F1 and F1.5 at h = 0..3
        let f1_ref = [0.39894, 0.083315, 8.4907e-3, 3.8215e-4];
        let f15_ref = [0.43002, 0.075668, 6.6482e-3, 2.6397e-4];
        let table = table::ReferenceIntegral::f15();
        for h in 0..4 {
            let x = h as f64;
            assert!(rel(gw::f1(x), f1_ref[h]) < 1e-4, "F1({x}) = {}", gw::f1(x));
            assert!(rel(table.value_and_derivative(x).0, f15_ref[h]) < 1e-4);
            // the adaptive reference agrees as well
            let f15 = adaptive(&|u: f64| u.powf(1.5) * gw::phi0(x + u), 0.0, 40.0, 1e-14);
            assert!(rel(f15, f15_ref[h]) < 1e-4, "F1.5({x}) = {f15}");
        }
    }

    #[test]
    fn f15_table_interpolates_to_1e9_between_nodes() {
        let table = table::ReferenceIntegral::f15();
        for i in 0..200 {
            // off-grid points over the range the evaluation uses
            let h = -7.4 + i as f64 * 0.0731 + 1.3e-3;
            let exact = adaptive(
                &|u: f64| u.powf(1.5) * gw::phi0(h + u),
                0.0,
                45.0 + h.abs(),
                1e-14,
            );
            let dexact = -1.5
                * adaptive(
                    &|u: f64| u.sqrt() * gw::phi0(h + u),
                    0.0,
                    45.0 + h.abs(),
                    1e-14,
                );
            let (f, df) = table.value_and_derivative(h);
            assert!(rel(f, exact) < 1e-9, "h={h}: {f} vs {exact}");
            assert!(rel(df, dexact) < 1e-6, "h={h}: {df} vs {dexact}");
        }
    }

    #[test]
    fn asperity_law_is_continuous_at_yield_and_full_plasticity() {
        let (r_a, e, hard, nu) = (1.3e-3, 113.9e9, 4e9, 0.28);
        let oc = critical_interference(r_a, e, hard, nu);
        for w in [oc, PLASTIC_RATIO * oc] {
            let below = asperity_contact(w * (1.0 - 1e-13), r_a, e, hard, nu);
            let above = asperity_contact(w * (1.0 + 1e-13), r_a, e, hard, nu);
            assert!(rel(above.0, below.0) < 1e-9, "area jump at {w}");
            assert!(rel(above.1, below.1) < 1e-9, "load jump at {w}");
        }
        // elastic mean contact pressure at ω_c is (2/3)·K·H (ZMC's yield onset)
        let (a, p) = asperity_contact(oc, r_a, e, hard, nu);
        assert!(rel(p / a, 2.0 / 3.0 * zmc_k(nu) * hard) < 1e-12);
        assert_eq!(asperity_contact(-1e-9, r_a, e, hard, nu), (0.0, 0.0));
    }

    #[test]
    fn contact_probability_values() {
        let z_s = 1e-6;
        assert!((contact_probability(0.0, z_s) - 0.5).abs() < 1e-15);
        // docs/model.md §8: ψ_b = 0.9995 at d_b = −3.2905·z_s
        assert!((contact_probability(-3.2905 * z_s, z_s) - 0.9995).abs() < 1e-6);
        assert!((contact_probability(1.0 * z_s, z_s) - 0.158_655_253_931_457).abs() < 1e-12);
    }

    #[test]
    fn elastic_limit_matches_closed_forms() {
        // Very high hardness: ω_c far beyond the Gaussian window, all contacts elastic.
        let mc = Microcontact::new(&roughness(0.5)).unwrap();
        let s = *mc.surface();
        let m = material(113.9e9, 1e13, 0.28);
        for i in -12..=12 {
            let h = i as f64 * 0.5;
            let st = mc.evaluate(h * s.z_s, &m);
            let f1 = adaptive(&|u: f64| u * gw::phi0(h + u), 0.0, 40.0 + h.abs(), 1e-14);
            let f15 = adaptive(
                &|u: f64| u.powf(1.5) * gw::phi0(h + u),
                0.0,
                40.0 + h.abs(),
                1e-14,
            );
            let area = PI * s.beta() * f1;
            let load = 4.0 / 3.0 * s.eta_s * m.e_star * s.r_a.sqrt() * s.z_s.powf(1.5) * f15;
            assert!(
                rel(st.area_fraction, area) < 1e-8,
                "h={h}: {} vs {area}",
                st.area_fraction
            );
            assert!(rel(st.load, load) < 1e-8, "h={h}: {} vs {load}", st.load);
        }
    }

    #[test]
    fn fully_plastic_limit() {
        // Very low hardness: ω_p ≪ z_s, A → 2πβ·F1(h), load → H·A.
        let mc = Microcontact::new(&roughness(0.5)).unwrap();
        let s = *mc.surface();
        let m = material(113.9e9, 1e5, 0.28);
        let oc = critical_interference(s.r_a, m.e_star, m.hardness, m.poisson);
        assert!(PLASTIC_RATIO * oc < 1e-6 * s.z_s);
        for i in -12..=12 {
            let h = i as f64 * 0.5;
            let st = mc.evaluate(h * s.z_s, &m);
            let area = 2.0 * PI * s.beta() * gw::f1(h);
            assert!(rel(st.area_fraction, area) < 1e-9, "h={h}");
            assert!(rel(st.load, m.hardness * area) < 1e-9, "h={h}");
        }
    }

    #[test]
    fn evaluate_matches_adaptive_quadrature() {
        // c = ω_c/z_s from 1e−6 (fully plastic) to 30 (elastic), h from −7 to 8.
        let mc = Microcontact::new(&roughness(0.5)).unwrap();
        let s = *mc.surface();
        let e_star = 113.9e9;
        let mut worst: f64 = 0.0;
        for c in [
            1e-6, 1e-3, 0.02, 0.1, 0.24, 0.26, 0.5, 0.82, 1.3, 3.3, 10.0, 30.0,
        ] {
            // H from c: ω_c = (πKH/(2E*))²·R_a
            let hard = (c * s.z_s / s.r_a).sqrt() * 2.0 * e_star / (PI * zmc_k(0.28));
            let m = material(e_star, hard, 0.28);
            for i in -28..=32 {
                let h = i as f64 * 0.25 + 0.0123;
                let st = mc.evaluate(h * s.z_s, &m);
                let (a, p, dp) = reference(&mc, h * s.z_s, &m);
                for (x, y, what) in [
                    (st.area_fraction, a, "area"),
                    (st.load, p, "load"),
                    (st.d_load_d_separation, dp, "dload"),
                ] {
                    let e = rel(x, y);
                    worst = worst.max(e);
                    assert!(e < 1e-6, "{what} at h={h}, c={c}: {x} vs {y} ({e:.1e})");
                }
            }
        }
        println!("worst relative error {worst:.2e}");
    }

    #[test]
    fn derivatives_match_central_differences_and_signs() {
        let mc = Microcontact::new(&roughness(0.5)).unwrap();
        let z_s = mc.surface().z_s;
        for t in [20.0, 400.0, 900.0] {
            let m = Material::default().at(t + CELSIUS_ZERO);
            for i in -24..=24 {
                let d = (i as f64 * 0.25 + 0.01) * z_s;
                let st = mc.evaluate(d, &m);
                let eps = 1e-5 * z_s;
                let (up, dn) = (mc.evaluate(d + eps, &m), mc.evaluate(d - eps, &m));
                let fd_load = (up.load - dn.load) / (2.0 * eps);
                let fd_area = (up.area_fraction - dn.area_fraction) / (2.0 * eps);
                assert!(
                    rel(st.d_load_d_separation, fd_load) < 1e-6,
                    "T={t} d/z_s={}",
                    d / z_s
                );
                assert!(
                    rel(st.d_area_d_separation, fd_area) < 1e-6,
                    "T={t} d/z_s={}",
                    d / z_s
                );
                assert!(st.d_load_d_separation < 0.0 && st.d_area_d_separation < 0.0);
            }
        }
    }

    #[test]
    fn load_and_area_fall_monotonically_with_separation() {
        for k_r in [0.0, 0.5, 1.0] {
            let mc = Microcontact::new(&roughness(k_r)).unwrap();
            let z_s = mc.surface().z_s;
            for t in [20.0, 600.0] {
                let m = Material::default().at(t + CELSIUS_ZERO);
                let mut prev = mc.evaluate(-12.0 * z_s, &m);
                for i in 1..=4000 {
                    let d = (-12.0 + i as f64 * 0.005) * z_s;
                    let st = mc.evaluate(d, &m);
                    assert!(
                        st.load < prev.load && st.area_fraction < prev.area_fraction,
                        "k_r={k_r} T={t} d/z_s={}",
                        d / z_s
                    );
                    prev = st;
                }
            }
        }
    }

    #[test]
    fn separation_for_load_round_trips() {
        for k_r in [0.0, 0.5, 1.0] {
            let mc = Microcontact::new(&roughness(k_r)).unwrap();
            let z_s = mc.surface().z_s;
            for t in [20.0, 450.0, 1000.0] {
                let m = Material::default().at(t + CELSIUS_ZERO);
                for i in -32..=26 {
                    let d = (i as f64 * 0.25 + 0.003) * z_s;
                    let load = mc.evaluate(d, &m).load;
                    let sol = mc.separation_for_load(load, &m).unwrap();
                    assert!(
                        sol.converged && !sol.below_floor,
                        "k_r={k_r} T={t} d/z_s={}: {sol:?}",
                        d / z_s
                    );
                    assert!(
                        ((sol.state.separation - d) / z_s).abs() < 1e-10,
                        "k_r={k_r} T={t} d/z_s={}: {sol:?}",
                        d / z_s
                    );
                    assert!(sol.residual < 1e-12 && sol.iterations < 30);
                    // warm start from a nearby separation
                    let warm = mc
                        .separation_for_load_from(load, &m, d + 0.3 * z_s)
                        .unwrap();
                    assert!(((warm.state.separation - d) / z_s).abs() < 1e-10);
                }
            }
        }
    }

    #[test]
    fn separation_for_load_edge_cases() {
        let mc = Microcontact::new(&roughness(0.5)).unwrap();
        let m = room();
        let scale = mc.load_scale(&m);
        for load in [0.0, 1e-20 * scale, 0.5 * LOAD_FLOOR * scale] {
            let sol = mc.separation_for_load(load, &m).unwrap();
            assert!(sol.below_floor && sol.converged);
            assert!(rel(sol.state.load, LOAD_FLOOR * scale) < 1e-12);
            assert!(sol.state.separation > 5.0 * mc.surface().z_s);
        }
        // more than the surface can carry in the search range
        let huge = 10.0 * mc.evaluate(SEPARATION_RANGE.0 * mc.surface().z_s, &m).load;
        assert!(matches!(
            mc.separation_for_load(huge, &m),
            Err(Error::Numerical { .. })
        ));
        assert!(mc.separation_for_load(-1.0, &m).is_err());
        assert!(mc.separation_for_load(f64::NAN, &m).is_err());
        // far outside the window: zero, not NaN
        let far = mc.evaluate(50.0 * mc.surface().z_s, &m);
        assert_eq!(
            (far.load, far.area_fraction, far.d_load_d_separation),
            (0.0, 0.0, 0.0)
        );
        let deep = mc.evaluate(-30.0 * mc.surface().z_s, &m);
        assert!(deep.load.is_finite() && deep.load > 0.0 && deep.d_load_d_separation < 0.0);
        assert!(
            Microcontact::new(&Roughness {
                beta: 0.0,
                ..Roughness::default()
            })
            .is_err()
        );
    }

    /// docs/model.md §4 calibration: saturated dry traction Σ σ_y·(A_m/A_n)(p_n)·dA / F_N over the parabolic
    /// pressure of the 100 kN default contact, and d/z_s at the centre at 200 kN.
    fn saturated_traction(k_r: f64, force: f64) -> (f64, f64) {
        let m = room();
        let geo = crate::params::Geometry::default();
        let hz = HertzContact::from_curvatures(geo.curvature_x, geo.curvature_y, force, m.e_star)
            .unwrap();
        let mc = Microcontact::new(&roughness(k_r)).unwrap();
        let p_peak = 2.0 * force / (PI * hz.a * hz.b);
        let rule = crate::quadrature::gauss_legendre::GaussLegendre::new(48);
        let mut sum = 0.0;
        for (x, w) in rule.nodes.iter().zip(&rule.weights) {
            let rho = 0.5 * (x + 1.0);
            let p = p_peak * (1.0 - rho * rho);
            let sol = mc.separation_for_load(p, &m).unwrap();
            assert!(sol.converged);
            sum +=
                0.5 * w * m.yield_stress * sol.state.area_fraction * 2.0 * PI * hz.a * hz.b * rho;
        }
        let centre =
            mc.separation_for_load(p_peak, &m).unwrap().state.separation / mc.surface().z_s;
        (sum / force, centre)
    }

    #[test]
    fn calibration_of_model_md_section_4() {
        let expected = [(0.0, 0.51), (0.5, 0.37), (1.0, 0.33)];
        let mut prev = f64::INFINITY;
        for (k_r, f) in expected {
            let (traction, _) = saturated_traction(k_r, 100e3);
            let (_, centre) = saturated_traction(k_r, 200e3);
            println!(
                "k_r = {k_r}: saturated dry traction {traction:.4}, d/z_s at the centre at 200 kN {centre:.3}"
            );
            assert!((traction - f).abs() <= 0.02, "k_r={k_r}: {traction}");
            assert!(traction < prev);
            prev = traction;
            assert!(centre >= -2.5, "k_r={k_r}: d/z_s = {centre}");
        }
    }

    /// xorshift64: reproducible uniform numbers in [0, 1).
    fn uniform(state: &mut u64) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn dimensionless_law_is_the_zmc_law() {
        // a(u)·π·R_a·z_s = A(ω) and p(u)·E*·sqrt(R_a)·z_s^1.5 = P(ω) at u = ω/z_s, all three regimes
        let s = *Microcontact::new(&roughness(0.5)).unwrap().surface();
        let m = room();
        let oc = critical_interference(s.r_a, m.e_star, m.hardness, m.poisson);
        let law = Law::new(oc / s.z_s, zmc_k(m.poisson));
        for i in 1..=400 {
            let omega = oc * 80.0 * (i as f64 / 400.0).powi(2);
            let (a, p) = law.asperity(omega / s.z_s);
            let (area, load) = asperity_contact(omega, s.r_a, m.e_star, m.hardness, m.poisson);
            assert!(
                rel(a * PI * s.r_a * s.z_s, area) < 1e-12,
                "ω/ω_c = {}",
                omega / oc
            );
            let p_scale = m.e_star * s.r_a.sqrt() * s.z_s.powf(1.5);
            assert!(rel(p * p_scale, load) < 1e-12, "ω/ω_c = {}", omega / oc);
        }
    }

    #[test]
    fn table_agrees_with_the_direct_quadrature_on_random_samples() {
        // the table (about 1e−9 of the exact integrals) and the direct quadrature it replaces, over the
        // range where the latter is specified (−7 ≤ h ≤ 8, better than 1e−6): the switch between them at
        // the table's edges is continuous to that accuracy
        let scheme = Scheme::new(BAND_NODES, BAND_PIECES, ELASTIC_NODES, DIRECT_BELOW);
        let table = GwTable::for_k(zmc_k(0.28));
        let (lo, hi) = gw_table::C_RANGE;
        let mut state = 0x2545_f491_4f6c_dd1d;
        let (mut worst, mut worst_dry): (f64, f64) = (0.0, 0.0);
        for _ in 0..10_000 {
            let c = (lo.ln() + (hi / lo).ln() * uniform(&mut state)).exp();
            let h = -7.0 + 15.0 * uniform(&mut state);
            let t = table.stencil(c).unwrap().integrals(h).unwrap();
            let d = scheme.integrals(h, &Law::new(c, zmc_k(0.28)));
            let values = rel(t.load, d.load).max(rel(t.area, d.area));
            let e = values.max(rel(t.dload, d.dload)).max(rel(t.darea, d.darea));
            assert!(e < 1e-6, "h = {h}, c = {c}: {t:?} vs {d:?}");
            worst = worst.max(e);
            // where the dry operating points live (c ≥ DIRECT_BELOW, h ≥ −4) the direct values are as
            // accurate as its F_1.5 table, and so is the agreement
            if c >= DIRECT_BELOW && h >= -4.0 {
                assert!(values < 1e-9, "h = {h}, c = {c}: {t:?} vs {d:?}");
                worst_dry = worst_dry.max(values);
            }
        }
        println!(
            "worst relative difference {worst:.1e}, values for c ≥ 0.25, h ≥ −4: {worst_dry:.1e}"
        );
    }

    #[test]
    fn outside_the_table_evaluate_is_the_direct_quadrature() {
        let mc = Microcontact::new(&roughness(0.5)).unwrap();
        let s = *mc.surface();
        let scheme = Scheme::new(BAND_NODES, BAND_PIECES, ELASTIC_NODES, DIRECT_BELOW);
        let (lo, hi) = gw_table::C_RANGE;
        let e_star = 113.9e9;
        // c below, inside and above the table; h below and inside it
        for c in [0.5 * lo, 0.3, 2.0 * hi] {
            let hard = (c * s.z_s / s.r_a).sqrt() * 2.0 * e_star / (PI * zmc_k(0.28));
            let m = material(e_star, hard, 0.28);
            let integrator = mc.integrator(&m);
            assert!(rel(integrator.c, c) < 1e-12);
            assert_eq!(integrator.stencil.is_some(), c == 0.3);
            for h in [-30.0, gw_table::H_MIN - 1e-6, -3.7, 2.2, 40.0] {
                let st = mc.evaluate(h * s.z_s, &m);
                if integrator.stencil.is_some() && (gw_table::H_MIN..gw::H_ZERO).contains(&h) {
                    continue;
                }
                let q =
                    scheme.integrals(st.separation / s.z_s, &Law::new(integrator.c, zmc_k(0.28)));
                let (a, l) = (PI * s.beta(), mc.load_scale(&m));
                assert_eq!(st.area_fraction, a * q.area, "c = {c}, h = {h}");
                assert_eq!(st.load, l * q.load, "c = {c}, h = {h}");
                assert_eq!(st.d_load_d_separation, l * q.dload / s.z_s);
                assert_eq!(st.d_area_d_separation, a * q.darea / s.z_s);
            }
        }
    }

    #[test]
    fn an_integrator_evaluates_as_evaluate_and_the_solve_returns_its_state() {
        // in and outside the table (c and h), bit for bit; a solve started at the root ends on its first
        // evaluation and returns the state evaluated there, area included
        let mc = Microcontact::new(&roughness(0.5)).unwrap();
        let s = *mc.surface();
        let e_star = 113.9e9;
        let (lo, hi) = gw_table::C_RANGE;
        for c in [0.5 * lo, 0.01, 0.3, 2.0, 2.0 * hi] {
            let hard = (c * s.z_s / s.r_a).sqrt() * 2.0 * e_star / (PI * zmc_k(0.28));
            let m = material(e_star, hard, 0.28);
            let integrator = mc.integrator(&m);
            for i in -48..=60 {
                let h = i as f64 * 0.25 + 0.0123;
                let d = h * s.z_s;
                let st = integrator.state(d);
                assert_eq!(st, mc.evaluate(d, &m), "c = {c}, h = {h}");
                if (-6.0..5.0).contains(&h) {
                    let sol = mc.separation_for_load_from(st.load, &m, d).unwrap();
                    assert!(sol.converged && !sol.below_floor && sol.iterations == 1);
                    assert_eq!(
                        sol.state,
                        mc.evaluate(sol.state.separation, &m),
                        "c = {c}, h = {h}"
                    );
                }
            }
        }
    }

    #[test]
    fn separation_for_load_round_trips_through_the_table() {
        // random states of the default steel (200 K … 1800 K) and roughness: all inside the table
        let mut state = 0x1234_5678_9abc_def1;
        for _ in 0..3000 {
            let mc = Microcontact::new(&roughness(uniform(&mut state))).unwrap();
            let z_s = mc.surface().z_s;
            let m = Material::default().at(200.0 + 1600.0 * uniform(&mut state));
            assert!(mc.integrator(&m).stencil.is_some());
            let h = -6.0 + 12.0 * uniform(&mut state);
            let load = mc.evaluate(h * z_s, &m).load;
            let guess = if uniform(&mut state) < 0.5 {
                f64::NAN
            } else {
                (h + 0.2 * (uniform(&mut state) - 0.5)) * z_s
            };
            let sol = mc.separation_for_load_from(load, &m, guess).unwrap();
            assert!(
                sol.converged && !sol.below_floor && sol.iterations < 30,
                "{sol:?}"
            );
            assert!(
                ((sol.state.separation - h * z_s) / z_s).abs() < 1e-10,
                "h = {h}: {sol:?}"
            );
            // the state returned is the evaluation at the separation found
            let back = mc.evaluate(sol.state.separation, &m);
            assert!(rel(sol.state.load, load) < 1e-12 && rel(back.load, load) < 1e-12);
            assert!(rel(sol.state.area_fraction, back.area_fraction) < 1e-12);
        }
    }
}
