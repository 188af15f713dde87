//! Mass-conserving film solve with cavitation/boundary-lubrication complementarity (paper eqs. P12–P17,
//! MODEL.md §8).
//!
//! Per cell the unknown is the separation d ≥ d_dry (d_dry: the separation at which the asperities alone
//! carry p_n). The compatibility condition P17, p_f·(1 − A_m/A_n) + p_m·A_m/A_n = p_n, turns d into the
//! fluid pressure p_f(d) = (p_n − p_m A_m/A_n(d))/(1 − A_m/A_n(d)), so p_f ≥ 0 ⇔ d ≥ d_dry. A cell is either
//! full and pressurised (l_f = l_v(d), d > d_dry) or unpressurised (d = d_dry, l_f ≤ l_v): the complementarity
//! p_f ≥ 0, l_f ≤ l_v, p_f·(l_v − l_f) = 0. Volume balance per cell (P14 with P12, P13, P15, P16):
//!
//!   Σ_faces G·(p_neighbour − p_cell) + Q_in − v_m·h_y·l_f = 0,
//!
//! face conductance G = (h_⊥/h_∥)·H(g_cell, g_neighbour)/ξ_f, H the harmonic mean (the two half-cells are
//! resistances in series), g = l_v³ (A·l_f²/h_⊥ of P12 for a filled channel: pressure-driven flow only
//! crosses faces next to a full cell, and fluid pushed into an unpressurised cell spreads into the void it
//! enters); p = 0 beyond the contact edge (inlet, outlet, sides), reached over half a cell. Q_in is the film carried in from the upstream
//! cell at the mean speed v_m, or for the leading cell of a strip the inlet film h_f0 on the rail at the rail
//! speed v_r. Transport between cells uses one speed (v_m) on both sides of each face so that the discrete
//! balance conserves volume exactly (the paper's P16 writes the inflow with v_r,x for every cell, which loses
//! volume at the rate (v_m − v_r)·h_y·l_f per face whenever ξ ≠ 0). The system is solved by nonlinear
//! Gauss–Seidel sweeps (as in the paper) marching with the flow, each cell solved exactly for its state.

use crate::contact::ContactGrid;
use crate::error::{Error, Result};
use crate::fluid::CellGeometry;
use crate::materials::MaterialState;
use crate::microcontact::Microcontact;

/// Lubrication regime of a cell (MODEL.md §8).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Regime {
    /// No fluid in the cell.
    Dry,
    /// Fluid present, fluid pressure carries less than 1 % of the local nominal load.
    Boundary,
    /// Fluid pressure carries at least 1 % of the local nominal load.
    Mixed,
}

impl Regime {
    /// Numeric code for CSV and maps: 0 dry, 1 boundary, 2 mixed.
    pub fn code(self) -> u8 {
        match self {
            Regime::Dry => 0,
            Regime::Boundary => 1,
            Regime::Mixed => 2,
        }
    }
}

/// Everything the film solve needs for one outer iteration.
pub struct FilmProblem<'a> {
    /// The contact grid.
    pub grid: &'a ContactGrid,
    /// Nominal pressure p_n per cell [Pa].
    pub nominal_pressure: &'a [f64],
    /// Material state per cell (local temperature).
    pub materials: &'a [MaterialState],
    /// Separation per cell at which the asperities alone carry p_n [m].
    pub dry_separation: &'a [f64],
    /// The microcontact model.
    pub micro: &'a Microcontact,
    /// Cell base height d_b [m] (P7).
    pub base_height: f64,
    /// Flow-resistance factor ξ_f [Pa·s].
    pub flow_resistance: f64,
    /// Rail surface speed v_r,x [m/s].
    pub rail_speed: f64,
    /// Mean surface speed v_m = (v_r,x + v_w,x)/2 [m/s].
    pub mean_speed: f64,
    /// Inlet film height h_f0 [m].
    pub inlet_film: f64,
    /// Convergence tolerance on the largest change per sweep of d (in z_s) and l_f (in h_f0) [-].
    pub tolerance: f64,
    /// Sweep limit.
    pub max_sweeps: usize,
}

/// The solved film.
#[derive(Debug, Clone, PartialEq)]
pub struct FilmSolution {
    /// Separation d per cell [m].
    pub separation: Vec<f64>,
    /// Fluid pressure p_f [Pa].
    pub fluid_pressure: Vec<f64>,
    /// Fluid height l_f [m].
    pub fluid_height: Vec<f64>,
    /// Void height l_v = l_c − l_m [m].
    pub void_height: Vec<f64>,
    /// Metallic contact area ratio A_m/A_n at d [-].
    pub area_fraction: Vec<f64>,
    /// Nominal metallic pressure p_m·A_m/A_n [Pa].
    pub metal_load: Vec<f64>,
    /// Regime per cell.
    pub regime: Vec<Regime>,
    /// Gauss–Seidel sweeps performed.
    pub sweeps: usize,
    /// Largest relative change in the last sweep.
    pub residual: f64,
    /// Whether the residual met the tolerance.
    pub converged: bool,
    /// Volume flow entering at the inlet [m³/s].
    pub inflow: f64,
    /// Volume flow carried out at the trailing edge [m³/s].
    pub outflow: f64,
    /// Volume flow expelled by pressure across the contact edges (inlet, sides, outlet) [m³/s].
    pub expelled: f64,
}

/// Faces of a cell: existing neighbours with their geometric factor c = h_⊥/(h_∥·ξ_f), and the summed
/// factor of the faces on the contact edge.
#[derive(Clone)]
struct Faces {
    up: Option<usize>,
    down: Option<usize>,
    neighbours: Vec<(usize, f64)>,
    edge: f64,
}

impl Faces {
    fn of(grid: &ContactGrid, k: usize, cx: f64, cy: f64) -> Self {
        let c = grid.cells[k];
        let (i, j) = (c.i as isize, c.j as isize);
        let mut f = Self {
            up: grid.cell_at(i + 1, j),
            down: grid.cell_at(i - 1, j),
            neighbours: Vec::with_capacity(4),
            edge: 0.0,
        };
        for (n, cf) in [
            (f.up, cx),
            (f.down, cx),
            (grid.cell_at(i, j - 1), cy),
            (grid.cell_at(i, j + 1), cy),
        ] {
            match n {
                Some(k) => f.neighbours.push((k, cf)),
                // half a cell to the edge, where the gap is open: conductance 2·c·g_cell
                None => f.edge += 2.0 * cf,
            }
        }
        f
    }
}

/// Harmonic mean of two half-cell conductances (series resistances), zero if either is zero.
fn harmonic(a: f64, b: f64) -> f64 {
    harmonic_with_slope(a, b).0
}

/// Harmonic mean H(a, b) = 2ab/(a + b) and its derivative ∂H/∂a = 2b²/(a + b)².
fn harmonic_with_slope(a: f64, b: f64) -> (f64, f64) {
    if a > 0.0 && b > 0.0 {
        let s = a + b;
        (2.0 * a * b / s, 2.0 * b * b / (s * s))
    } else {
        (0.0, 0.0)
    }
}

/// Solves the film for one outer iteration; `warm` (a previous solution on the same grid) speeds it up.
pub fn solve_film(pr: &FilmProblem, warm: Option<&FilmSolution>) -> Result<FilmSolution> {
    let grid = pr.grid;
    let n = grid.len();
    if pr.nominal_pressure.len() != n || pr.materials.len() != n || pr.dry_separation.len() != n {
        return Err(Error::Numerical {
            stage: "fluid",
            reason: "field lengths do not match the grid".into(),
        });
    }
    let z_s = pr.micro.surface().z_s;
    let hy = grid.hy;
    let cx = grid.hy / (grid.hx * pr.flow_resistance);
    let cy = grid.hx / (grid.hy * pr.flow_resistance);
    let vm = pr.mean_speed;
    let faces: Vec<Faces> = (0..n).map(|k| Faces::of(grid, k, cx, cy)).collect();
    let void = |d: f64| CellGeometry::at(d, z_s, pr.base_height).void_height;
    // separation, pressure, fluid height, conductance g = l_v³ per cell
    let (mut d, mut p, mut lf) = match warm {
        Some(w) if w.separation.len() == n => (
            w.separation
                .iter()
                .zip(pr.dry_separation)
                .map(|(d, dd)| d.max(*dd))
                .collect::<Vec<f64>>(),
            w.fluid_pressure.clone(),
            w.fluid_height.clone(),
        ),
        _ => (pr.dry_separation.to_vec(), vec![0.0; n], vec![0.0; n]),
    };
    let mut g: Vec<f64> = d.iter().map(|x| void(*x).powi(3)).collect();
    // pressure of a full cell at separation d (P17), its d-derivative, void height and its slope
    let full_state = |k: usize, d: f64| {
        let m = pr.micro.evaluate(d, &pr.materials[k]);
        let geo = CellGeometry::at(d, z_s, pr.base_height);
        let open = (1.0 - m.area_fraction).max(1e-12);
        let p = ((pr.nominal_pressure[k] - m.load) / open).max(0.0);
        // dp/dd = (−dL/dd + p·dA/dd)/(1 − A)
        let dp = (-m.d_load_d_separation + p * m.d_area_d_separation) / open;
        (p, dp, geo.void_height, geo.void_slope)
    };
    let film_scale = pr.inlet_film.max(1e-3 * z_s);
    let mut sweeps = 0;
    let mut residual = f64::INFINITY;
    while sweeps < pr.max_sweeps {
        sweeps += 1;
        let mut change: f64 = 0.0;
        // alternate the lateral order so that pressure spreads both ways
        let order: Vec<usize> = if sweeps % 2 == 1 {
            (0..grid.strips.len()).collect()
        } else {
            (0..grid.strips.len()).rev().collect()
        };
        for si in order {
            for k in grid.strips[si].cells.clone() {
                let f = &faces[k];
                let q_in = match f.up {
                    Some(u) => vm * hy * lf[u],
                    None => pr.rail_speed * hy * pr.inlet_film,
                };
                let d_dry = pr.dry_separation[k];
                // volume balance of the cell as a function of its separation, full: l_f = l_v(d)
                // and its derivative in d
                let balance = |dk: f64| {
                    let (pk, dpk, lv, dlv) = full_state(k, dk);
                    let gk = lv * lv * lv;
                    let dgk = 3.0 * lv * lv * dlv;
                    let mut r = q_in - vm * hy * lv - f.edge * gk * pk;
                    let mut dr = -vm * hy * dlv - f.edge * (dgk * pk + gk * dpk);
                    for &(nb, cf) in &f.neighbours {
                        let (h, dh) = harmonic_with_slope(gk, g[nb]);
                        r += cf * h * (p[nb] - pk);
                        dr += cf * (dh * dgk * (p[nb] - pk) - h * dpk);
                    }
                    (r, dr)
                };
                let (d_new, p_new, lf_new) = if balance(d_dry).0 > 0.0 {
                    // more fluid arrives than the cell holds at d_dry: full and pressurised
                    let dk = root_decreasing(balance, d_dry, d[k], z_s, 1e-13 * z_s)?;
                    let (pk, _, lv, _) = full_state(k, dk);
                    (dk, pk, lv)
                } else {
                    // unpressurised: the film height follows from the inflow
                    let gk = void(d_dry).powi(3);
                    let mut inflow = q_in;
                    for &(nb, cf) in &f.neighbours {
                        inflow += cf * harmonic(gk, g[nb]) * p[nb];
                    }
                    (d_dry, 0.0, (inflow / (vm * hy)).min(void(d_dry)))
                };
                change = change
                    .max((d_new - d[k]).abs() / z_s)
                    .max((lf_new - lf[k]).abs() / film_scale);
                d[k] = d_new;
                p[k] = p_new;
                lf[k] = lf_new;
                g[k] = void(d_new).powi(3);
            }
        }
        residual = change;
        if change <= pr.tolerance {
            break;
        }
    }
    let converged = residual <= pr.tolerance;
    // assemble the fields and the volume balance
    let mut sol = FilmSolution {
        separation: d.clone(),
        fluid_pressure: p.clone(),
        fluid_height: lf.clone(),
        void_height: vec![0.0; n],
        area_fraction: vec![0.0; n],
        metal_load: vec![0.0; n],
        regime: vec![Regime::Dry; n],
        sweeps,
        residual,
        converged,
        inflow: 0.0,
        outflow: 0.0,
        expelled: 0.0,
    };
    for k in 0..n {
        let m = pr.micro.evaluate(d[k], &pr.materials[k]);
        sol.void_height[k] = void(d[k]);
        sol.area_fraction[k] = m.area_fraction;
        sol.metal_load[k] = m.load;
        sol.regime[k] = if lf[k] <= 0.0 {
            Regime::Dry
        } else if p[k] * (1.0 - m.area_fraction) >= 0.01 * pr.nominal_pressure[k] {
            Regime::Mixed
        } else {
            Regime::Boundary
        };
        let f = &faces[k];
        if f.up.is_none() {
            sol.inflow += pr.rail_speed * hy * pr.inlet_film;
        }
        if f.down.is_none() {
            sol.outflow += vm * hy * lf[k];
        }
        sol.expelled += f.edge * g[k] * p[k];
    }
    Ok(sol)
}

/// Root of a function that is positive at `lo` and decreases to negative values, given with its derivative:
/// Newton from the warm start `guess` (clipped into the bracket), safeguarded by bisection; the bracket is
/// grown from `lo` in doubling steps of `step` when needed. Converges to `tol` in the argument.
fn root_decreasing(
    f: impl Fn(f64) -> (f64, f64),
    lo: f64,
    guess: f64,
    step: f64,
    tol: f64,
) -> Result<f64> {
    let mut a = lo; // f(a) > 0
    let mut b = f64::INFINITY; // f(b) < 0 once found
    let mut x = if guess > lo { guess } else { lo + 0.01 * step };
    let mut h = step;
    for _ in 0..300 {
        let (fx, dfx) = f(x);
        if !fx.is_finite() {
            break;
        }
        if fx == 0.0 {
            return Ok(x);
        }
        if fx > 0.0 {
            a = x;
        } else {
            b = x;
        }
        let newton = x - fx / dfx;
        let next = if dfx < 0.0 && newton > a && newton < b {
            newton
        } else if b.is_finite() {
            0.5 * (a + b)
        } else {
            // no sign change yet: grow the step from the last positive point
            h *= 2.0;
            a + h
        };
        if (next - x).abs() <= tol || (b - a) <= tol {
            return Ok(next);
        }
        x = next;
    }
    Err(Error::Numerical {
        stage: "fluid",
        reason: format!("no separation balances the cell (bracket {a:e} .. {b:e} m)"),
    })
}
