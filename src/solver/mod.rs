//! The solution of one operating point (paper Fig. 1, docs/model.md §9).
//!
//! The coupled laws (Tomberger, constant μ) are solved as one fixed point (`coupled.rs`): start at T = T0,
//! p_f = 0; repeat materials at T → fluid film + microcontact (separation, p_f, A_m/A_n, `local.rs`) →
//! failure stress and local friction μ_ij → FASTSIM (traction, slip) → frictional heat → surface
//! temperature, until the adhesion limit and the temperatures change less than the tolerance and the film
//! and the heat partition have converged. The temperature update is relaxed with Aitken's Δ² (Irons–Tuck)
//! factor (`relaxation.rs`), which damps the oscillation that the temperature ↔ failure-stress feedback
//! produces at high slip power, and backtracked where the film has no solution (`backtracking.rs`); the
//! final iterate gives the global results and the local fields (`assembly.rs`). The closed-form Polach law
//! needs no iteration (`closed_form.rs`). A solve can start from a nearby solution ([`WarmStart`]); sweeps
//! chain such starts ([`solve_sweep`]). What the set-up makes from the geometry, the grid, the surface
//! speeds and the parameters alone can be kept between solves ([`SetupCache`], pure functions of their
//! inputs). Every solve reports how it went ([`SolverReport`], [`Termination`]).

mod assembly;
mod backtracking;
mod cache;
mod closed_form;
/// The outer iteration; `coupled::solve_cached` solves with parameters validated beforehand and a
/// [`SetupCache`].
pub(crate) mod coupled;
mod local;
mod relaxation;
mod report;
mod setup;
mod solution;
mod sweep;
mod warm;

pub use cache::SetupCache;
pub use coupled::{solve, solve_from};
pub use report::{Limiter, SolverReport, Termination};
pub use setup::{ContactShape, normal_contact, surface_speeds};
pub use solution::{Fields, GlobalResults, Solution};
pub use sweep::solve_sweep;
pub use warm::WarmStart;
