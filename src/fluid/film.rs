//! Mass-conserving film solve with cavitation/boundary-lubrication complementarity (paper eqs. P12–P17,
//! docs/model.md §8).
//!
//! Per cell the unknown is the separation d ≥ d_dry (d_dry: the separation at which the asperities alone
//! carry p_n). The compatibility condition P17, p_f·(1 − A_m/A_n) + p_m·A_m/A_n = p_n, turns d into the
//! fluid pressure p_f(d) = (p_n − p_m A_m/A_n(d))/(1 − A_m/A_n(d)), so p_f ≥ 0 ⇔ d ≥ d_dry. A cell is either
//! full and pressurised (l_f = l_v(d), d > d_dry) or unpressurised (d = d_dry, l_f ≤ l_v): the complementarity
//! p_f ≥ 0, l_f ≤ l_v, p_f·(l_v − l_f) = 0. Volume balance per cell (P14 with P12, P13, P15, P16):
//!
//!   Σ_faces G·(p_neighbour − p_cell) + Q_in − Q_out = 0,
//!
//! face conductance G = (h_⊥/h_∥)·H(g_cell, g_neighbour)/ξ_f, H the harmonic mean (the two half-cells are
//! resistances in series), g = l_v³ (A·l_f²/h_⊥ of P12 for a filled channel: pressure-driven flow only
//! crosses faces next to a full cell, and fluid pushed into an unpressurised cell spreads into the void it
//! enters); p = 0 beyond the contact edge (inlet, outlet, sides), reached over half a cell.
//!
//! Transport: the surfaces carry the film through the face between a cell and its downstream neighbour at
//! the mean speed v_m, Q = v_m·h_y·l_face, one flux for both cells so that the discrete balance conserves
//! volume exactly (the paper's P16 writes the inflow with v_r,x for every cell, which loses volume at the
//! rate (v_m − v_r)·h_y·l_f per face whenever ξ ≠ 0). The face height l_face is the second-order upwind
//! value l_f + (l_f − l_f,up)/2 extrapolated from the cell and its upstream neighbour to the face (see
//! [`face_height`]). First-order upwind (l_face = l_f of the cell) puts the transport source
//! v_m·∂l_f/∂x of a cell half a cell upstream (its truncation error is the numerical diffusion
//! (v_m·h_x/2)·∂²l_f/∂x²): in the pressurised zone, where l_f = l_v(d) falls steeply from the inlet, that
//! made the fluid load and the traction converge only as O(h^1.3) (f 3 % low on the default 30 × 30 grid).
//!
//! Inlet: the rail brings the film h_f0 at v_r, v_r·h_y·h_f0 per strip. The leading cell takes in at most
//! what its void holds, Q_in = min(v_r·h_y·h_f0, v_m·h_y·l_v): a flooded inlet fills the gap at the contact
//! edge, where p_f = 0, and the rest of the film is pushed aside ahead of the contact (reported as
//! `rejected`). (Taking the whole film into the leading cell made that cell expel the excess over its half
//! cell to the edge, at a pressure proportional to the cell length: an O(h) error that made the results of
//! a flooded inlet depend on h_f0.) A starved inlet (v_r·h_f0 < v_m·l_v) enters completely.
//!
//! Solution: a global semismooth Newton method. (The paper's Gauss–Seidel relaxation needs over a hundred
//! sweeps on the 30 × 30 grid because pressure spreads about one cell per sweep; it remains as the fallback
//! and as the reference of the tests.) One unknown u per cell covers both states, so that the
//! complementarity is part of the parametrisation:
//!
//!   u ≤ 0: unpressurised, d = d_dry, p_f = 0, l_f = (1 + u)·l_v(d_dry);
//!   u > 0: full, d = d_dry + u·z_s, p_f = p_f(d) (P17), l_f = l_v(d).
//!
//! Both branches meet at u = 0 (just full, no pressure): the map is continuous with a kink. The equations are
//! the cell volume balances R(u) = 0, smooth functions of the cells' (p_f, l_f, g) (but for the inlet's
//! min). A Newton step linearises them at the current film (five-point stencil and the second cell
//! upstream; analytic derivatives of P17, of l_v, of the harmonic conductances and of the face heights)
//! and lets each cell's (p_f, l_f, g) follow the affine model of the branch on which its new u falls
//! (exact on the unpressurised branch, the tangent on the full one). The branches are found by
//! active-set passes (Hintermüller, Ito & Kunisch, SIAM J. Optim. 13 (2003) 865), each a band LU
//! factorisation of the model Jacobian (cells strip by strip: bandwidth about one strip). The step is capped
//! at one unit of u in its largest component (z_s in d, the whole void in l_f) and damped by the natural
//! monotonicity test (Deuflhard, Newton Methods for Nonlinear Problems, 2004, ch. 3). Should Newton stall,
//! Gauss–Seidel sweeps (each cell solved exactly for its state, marching with the flow) take over. Both
//! iterations solve the same discrete equations; a unit test checks that they reach the same film.
//!
//! At high pressure (docs/model.md §8.5, §8.7) two kinds of cells need more: where GW's metallic area
//! covers the cell (A_m/A_n(d_dry) ≥ 1) P17 leaves the fluid no free area, and the cell is a wall that
//! holds and takes in no fluid (cells nearly covered take in part of the film carried to them, the rest
//! is pushed aside); where the dry separation lies below the base height with A_m/A_n < 1 the cell is
//! closed: it holds nothing until fluid carried in lifts it above d_b, and its full branch is
//! parametrised by its void height. Unpressurised walls and closed cells have balances independent of
//! their unknown: their Newton rows are pinned.

use std::cell::OnceCell;

use crate::contact::ContactGrid;
use crate::error::{Error, Result, Stage};
use crate::fluid::CellHeights;
use crate::fluid::band::Band;
use crate::fluid::cell_geometry::separation_for_void;
use crate::materials::MaterialState;
use crate::microcontact::{Integrator, Microcontact};

/// Lubrication regime of a cell (docs/model.md §8).
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
    /// Metallic contact area ratio A_m/A_n per cell at the dry separation [-].
    pub dry_area_fraction: &'a [f64],
    /// Nominal metallic pressure p_m·A_m/A_n per cell at the dry separation (p_n, or the microcontact
    /// model's load floor) [Pa].
    pub dry_metal_load: &'a [f64],
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
    /// Convergence tolerance on the largest change per iteration of d (in z_s) and l_f (in h_f0) [-].
    pub tolerance: f64,
    /// Iteration limit (Newton iterations and fallback sweeps together).
    pub max_iterations: usize,
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
    /// Iterations performed (Newton steps and fallback Gauss–Seidel sweeps).
    pub iterations: usize,
    /// Largest change (of d in z_s, of l_f in h_f0) made by the last iteration, or of the Newton
    /// correction at the returned film when that met the tolerance [-].
    pub residual: f64,
    /// Largest volume-balance residual of a cell at the returned film, relative to the flow
    /// v_m·h_y·h_f0 of the inlet film through one cell width [-].
    pub balance_residual: f64,
    /// Whether the residual met the tolerance (for Newton: with a full step or correction).
    pub converged: bool,
    /// Volume flow taken in by the leading cells at the inlet [m³/s].
    pub inflow: f64,
    /// Inlet film that the leading cells do not take in, pushed aside ahead of the contact [m³/s]
    /// (inflow + rejected = v_r·h_f0 times the width of the strips).
    pub rejected: f64,
    /// Volume flow carried out at the trailing edge [m³/s].
    pub outflow: f64,
    /// Volume flow expelled by pressure across the contact edges (inlet, sides, outlet), and pushed aside
    /// in front of cells that take in only part of the film carried to them (where the metallic area
    /// nearly or fully covers the cell, docs/model.md §8.5) [m³/s].
    pub expelled: f64,
}

/// Faces of a cell: existing neighbours with their geometric factor c = h_⊥/(h_∥·ξ_f) (the first `count`
/// entries of `list`), the summed factor of the faces on the contact edge, and the upstream and downstream
/// cells of the strip.
#[derive(Clone)]
struct Faces {
    up: Option<usize>,
    down: Option<usize>,
    list: [(usize, f64); 4],
    count: usize,
    edge: f64,
}

impl Faces {
    fn of(grid: &ContactGrid, k: usize, cx: f64, cy: f64) -> Self {
        let c = grid.cells[k];
        let (i, j) = (c.i as isize, c.j as isize);
        let mut f = Self {
            up: grid.cell_at(i + 1, j),
            down: grid.cell_at(i - 1, j),
            list: [(0, 0.0); 4],
            count: 0,
            edge: 0.0,
        };
        for (n, cf) in [
            (f.up, cx),
            (f.down, cx),
            (grid.cell_at(i, j - 1), cy),
            (grid.cell_at(i, j + 1), cy),
        ] {
            match n {
                Some(k) => {
                    f.list[f.count] = (k, cf);
                    f.count += 1;
                }
                // half a cell to the edge, where the gap is open: conductance 2·c·g_cell
                None => f.edge += 2.0 * cf,
            }
        }
        f
    }

    /// The neighbouring cells with their factors c.
    fn neighbours(&self) -> &[(usize, f64)] {
        &self.list[..self.count]
    }
}

/// Fluid height carried through the downstream face of a cell holding `l` [m], reconstructed with the
/// height `l_up` of its upstream neighbour in the strip (None for the leading cell, which carries its own
/// height: first-order upwind), with its derivatives with respect to l and l_up.
///
/// Second-order upwind reconstruction l + (l − l_up)/2: the film extrapolated linearly from the cell and
/// its upstream neighbour to the face, half a cell downstream of the centre (the upwind slope of the
/// Beam–Warming scheme: Warming & Beam, AIAA J. 14 (1976) 1241; LeVeque, Finite Volume Methods for
/// Hyperbolic Problems, 2002, ch. 6). It is exact for a film that rises linearly along the strip, and a
/// constant film (an unpressurised region without pressure-driven inflow) is carried unchanged. Where the
/// film falls (l < l_up, x = (l_up − l)/l > 0) the linear value l·(1 − x/2), which would turn negative
/// beyond x = 2, is replaced by l·(1 + ψ)/2 with ψ = (1 + x)/(1 + 2x + 2x²) = 1 − x + O(x³):
///
///   l_face = l/2 + l_up·l²/(2·((l_up − l)² + l_up²)),
///
/// equal to the linear value to O(x³) (O(h³) where the film is smooth) and twice continuously
/// differentiable across l = l_up (the Newton iteration meets no switch), but between l/2 and l however
/// steeply the film falls, so that the surfaces never carry fluid against the rolling direction. The face
/// height grows with l (slope ≥ 1/2: the Gauss–Seidel cell solve stays well posed).
fn face_height(l: f64, l_up: Option<f64>) -> (f64, f64, f64) {
    match l_up {
        None => (l, 1.0, 0.0),
        Some(a) if l >= a => (1.5 * l - 0.5 * a, 1.5, -0.5),
        Some(a) => {
            let q = (a - l) * (a - l) + a * a;
            (
                0.5 * l + 0.5 * a * l * l / q,
                0.5 + a * a * l * (2.0 * a - l) / (q * q),
                0.5 * l * l * (l * l - 2.0 * a * a) / (q * q),
            )
        }
    }
}

/// The fluid height l ≥ 0 with [`face_height`]`(l, l_up) = t` for t ≥ 0 (the face height increases with
/// l and equals l_up at l = l_up; below, the root of a cubic, found by safeguarded Newton).
fn face_height_inverse(t: f64, l_up: Option<f64>) -> Result<f64> {
    match l_up {
        None => Ok(t),
        Some(a) if t >= a => Ok((t + 0.5 * a) / 1.5),
        Some(a) => root_decreasing(
            |l| {
                let (v, dv, _) = face_height(l, l_up);
                (t - v, -dv)
            },
            0.0,
            t,
            a,
            1e-15 * a,
        ),
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

/// A full cell at separation d: fluid pressure from P17 and its d-derivative, void height (P8–P11) and its
/// slope, and the microcontact state.
#[derive(Debug, Clone, Copy)]
struct Full {
    /// p_f(d) = (p_n − p_m A_m/A_n)/(1 − A_m/A_n), ≥ 0 [Pa].
    p: f64,
    /// dp_f/dd [Pa/m].
    dp: f64,
    /// l_v(d) [m].
    lv: f64,
    /// dl_v/dd [-].
    dlv: f64,
    /// A_m/A_n [-].
    area: f64,
    /// p_m·A_m/A_n [Pa].
    load: f64,
}

/// A cell at its unknown u: state and the derivatives of p_f, l_f and g = l_v³ with respect to u.
#[derive(Debug, Clone, Copy, Default)]
struct CellState {
    d: f64,
    p: f64,
    lf: f64,
    lv: f64,
    g: f64,
    dp: f64,
    dlf: f64,
    dg: f64,
    /// A_m/A_n at d [-].
    area: f64,
    /// p_m·A_m/A_n at d [Pa].
    load: f64,
    /// dd/du in z_s [-]: 1 on the full branch of an open cell, 0 on the unpressurised branch.
    rise: f64,
}

impl CellState {
    /// Full cell (u > 0, or u = 0 approached from above) at separation d, where d grows with u at
    /// `rise`·z_s per unit of u: at d = d_dry + u·z_s (rise 1), or for a closed cell at the separation
    /// where l_v(d) = u·F (rise F/(z_s·dl_v/dd), [`System::state`]).
    fn full(d: f64, f: &Full, z_s: f64, rise: f64) -> Self {
        let lv2 = f.lv * f.lv;
        let dd = z_s * rise;
        Self {
            d,
            p: f.p,
            lf: f.lv,
            lv: f.lv,
            g: lv2 * f.lv,
            dp: f.dp * dd,
            dlf: f.dlv * dd,
            dg: 3.0 * lv2 * f.dlv * dd,
            rise,
            area: f.area,
            load: f.load,
        }
    }
}

/// Affine model q(u) = a + b·u of a cell's (p_f, l_f, g = l_v³) on one branch.
#[derive(Debug, Clone, Copy)]
struct Branch {
    a: [f64; 3],
    b: [f64; 3],
}

/// Newton iterations before Gauss–Seidel sweeps take over.
const NEWTON_LIMIT: usize = 30;
/// Most active-set passes of one Newton step.
const MAX_PASSES: usize = 16;
/// Largest step component of a Newton step (u is in z_s for d, in l_v(d_dry) for l_f).
const MAX_STEP: f64 = 1.0;
/// Smallest damping factor before Gauss–Seidel sweeps take over.
const MIN_ALPHA: f64 = 1.0 / 1024.0;

/// How a cell takes up fluid, from its dry state (the asperities alone carrying p_n, docs/model.md §8.7).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// A_m/A_n(d_dry) < 1 and l_v(d_dry) > 0: pressurised, the fluid lifts the surfaces above d_dry.
    Open,
    /// A_m/A_n(d_dry) < 1 but d_dry ≤ d_b: the voids lie below the base height, l_v(d_dry) = 0 (P8–P11).
    /// Fluid carried in must lift the surfaces above d_b, at p_f(d_b) > 0 (P17).
    Closed,
    /// A_m/A_n(d_dry) ≥ 1: GW's metallic area, which overlapping asperity contacts let exceed the nominal
    /// area at high pressure, covers the cell. No free area is left on which fluid could carry load (P17
    /// has no solution with p_f ≥ 0 just above d_dry) or lie: the cell holds no fluid and takes in none
    /// of the film carried to it ([`System::intake`]).
    Wall,
}

/// The linearised balance of a pinned Newton row ([`System::newton_target`]): R ≈ Σ_m J_km·u_m − rhs.
struct PinnedRow {
    /// The cell k.
    cell: usize,
    /// Its stencil coefficients (m, J_km).
    row: Vec<(usize, f64)>,
    /// The right-hand side of the row.
    rhs: f64,
}

impl PinnedRow {
    /// The linearised balance of the cell (its inflow, the cell holding nothing) at the unknowns `u`
    /// [m³/s].
    fn inflow(&self, u: &[f64]) -> f64 {
        self.row.iter().map(|(m, j)| j * u[*m]).sum::<f64>() - self.rhs
    }
}

/// Band of A_m/A_n(d_dry) below 1 over which a cell's intake of the film carried to it falls from all to
/// none ([`System::intake`]).
const INTAKE_BAND: f64 = 0.005;

/// The share θ = clamp((1 − A_m/A_n(d_dry))/0.005, 0, 1) of the film carried to a cell that the cell takes
/// in (docs/model.md §8.5, project extension): 1 where GW's metallic area at the dry separation leaves free
/// area, 0 for a wall (A_m/A_n(d_dry) ≥ 1) [-].
pub fn intake_share(dry_area_fraction: f64) -> f64 {
    ((1.0 - dry_area_fraction) / INTAKE_BAND).clamp(0.0, 1.0)
}

/// Whether a contact whose largest A_m/A_n(d_dry) is `max_dry_area_fraction` takes in all the film carried
/// to each cell (θ = 1 everywhere, [`intake_share`]): false once the metal begins to cover a cell, where a
/// wet contact begins to lose its film downstream of the covered cells, its friction rising steeply
/// towards the dry value (docs/model.md §8.5).
pub fn takes_in_all(max_dry_area_fraction: f64) -> bool {
    intake_share(max_dry_area_fraction) >= 1.0
}

/// The discrete film system of one problem, with the per-cell quantities that do not change in a solve.
struct System<'a> {
    pr: &'a FilmProblem<'a>,
    z_s: f64,
    /// The cell heights of the surface and base height (P8–P11).
    heights: CellHeights,
    /// The microcontact of each cell at its material state.
    contact: Vec<Integrator<'a>>,
    hy: f64,
    vm: f64,
    /// Inlet film brought by the rail per strip, v_r·h_y·h_f0 [m³/s].
    supply: f64,
    /// Scale of the fluid height in the convergence test: h_f0, at least 10⁻³·z_s [m].
    film_scale: f64,
    /// The faces of each cell, their factors c scaled by the smaller intake share θ of the two cells
    /// ([`System::intake`]).
    faces: Vec<Faces>,
    /// l_v(d_dry) per cell [m].
    dry_void: Vec<f64>,
    /// How each cell takes up fluid.
    kind: Vec<Kind>,
    /// Share of the film carried to a cell that it takes in ([`System::intake`]).
    intake: Vec<f64>,
    /// The full state at the opening separation ([`System::opening`]) per cell, computed when first
    /// needed.
    open: Vec<OnceCell<Full>>,
}

impl<'a> System<'a> {
    fn new(pr: &'a FilmProblem<'a>) -> Result<Self> {
        let grid = pr.grid;
        let n = grid.len();
        if [
            pr.nominal_pressure.len(),
            pr.materials.len(),
            pr.dry_separation.len(),
            pr.dry_area_fraction.len(),
            pr.dry_metal_load.len(),
        ]
        .iter()
        .any(|l| *l != n)
        {
            return Err(Error::Numerical {
                stage: Stage::Fluid,
                reason: "field lengths do not match the grid".into(),
            });
        }
        let z_s = pr.micro.surface().z_s;
        let heights = CellHeights::new(z_s, pr.base_height);
        let cx = grid.hy / (grid.hx * pr.flow_resistance);
        let cy = grid.hx / (grid.hy * pr.flow_resistance);
        let mut dry_void: Vec<f64> = pr
            .dry_separation
            .iter()
            .map(|d| heights.void(*d).0)
            .collect();
        let kind: Vec<Kind> = (0..n)
            .map(
                |k| match (pr.dry_area_fraction[k] >= 1.0, dry_void[k] > 0.0) {
                    (true, _) => Kind::Wall,
                    (false, true) => Kind::Open,
                    (false, false) => Kind::Closed,
                },
            )
            .collect();
        for (lv, kind) in dry_void.iter_mut().zip(&kind) {
            if *kind == Kind::Wall {
                *lv = 0.0;
            }
        }
        let intake: Vec<f64> = pr
            .dry_area_fraction
            .iter()
            .map(|a| intake_share(*a))
            .collect();
        // the pressure-driven flow through a face scales with the share of the more nearly covered of its
        // two cells (symmetric: what leaves one cell enters the other)
        let faces = (0..n)
            .map(|k| {
                let mut f = Faces::of(grid, k, cx, cy);
                for (nb, cf) in f.list[..f.count].iter_mut() {
                    *cf *= intake[k].min(intake[*nb]);
                }
                f
            })
            .collect();
        Ok(Self {
            pr,
            z_s,
            heights,
            contact: pr
                .materials
                .iter()
                .map(|m| pr.micro.integrator(m))
                .collect(),
            hy: grid.hy,
            vm: pr.mean_speed,
            supply: pr.rail_speed * grid.hy * pr.inlet_film,
            film_scale: pr.inlet_film.max(1e-3 * z_s),
            faces,
            dry_void,
            intake,
            kind,
            open: vec![OnceCell::new(); n],
        })
    }

    fn len(&self) -> usize {
        self.faces.len()
    }

    /// Full state of cell k at separation d (P17 for p_f, P8–P11 for l_v, docs/model.md §4 for the asperities).
    fn full(&self, k: usize, d: f64) -> Full {
        let pr = self.pr;
        let m = self.contact[k].state(d);
        let (lv, dlv) = self.heights.void(d);
        let open = (1.0 - m.area_fraction).max(1e-12);
        let p = ((pr.nominal_pressure[k] - m.load) / open).max(0.0);
        Full {
            p,
            // dp/dd = (−dL/dd + p·dA/dd)/(1 − A)
            dp: (-m.d_load_d_separation + p * m.d_area_d_separation) / open,
            lv,
            dlv,
            area: m.area_fraction,
            load: m.load,
        }
    }

    /// The void l_v(d_dry) of cell k open to the fluid (0 for a wall) [m].
    fn dry_void(&self, k: usize) -> f64 {
        self.dry_void[k]
    }

    /// Whether cell k is a wall ([`Kind::Wall`]).
    fn wall(&self, k: usize) -> bool {
        self.kind[k] == Kind::Wall
    }

    /// Whether cell k holds no fluid on its unpressurised branch ([`Kind::Closed`], [`Kind::Wall`]),
    /// whatever its u.
    fn closed(&self, k: usize) -> bool {
        self.kind[k] != Kind::Open
    }

    /// The share θ of the film the surfaces carry to cell k that it takes in: 1 up to A_m/A_n(d_dry) =
    /// 1 − [`INTAKE_BAND`], falling linearly to 0 at A_m/A_n(d_dry) = 1 (a wall takes none). The rest is
    /// pushed aside in front of the cell and leaves the contact (counted as expelled), as the film that
    /// a flooded inlet cannot take in is pushed aside ahead of the contact. The pressure-driven flow
    /// through a face scales with the smaller θ of its two cells, so that a cell turns into a wall
    /// continuously as A_m/A_n(d_dry) reaches 1: it takes in nothing from any side there.
    fn intake(&self, k: usize) -> f64 {
        self.intake[k]
    }

    /// The separation at which cell k opens to the fluid, the kink u = 0 of its unknown [m]: d_dry, or
    /// for a closed cell the base height d_b, where its void opens (docs/model.md §8.7). Between d_dry
    /// and d_b a closed cell holds no fluid and no flow depends on its separation (g = l_v³ = 0), so its
    /// full branch starts at d_b: there p_f(d_b) > 0 (P17) is the pressure the fluid needs to lift the
    /// asperities to the base height, and the flows stay continuous across the kink (they carry p_f only
    /// with g = 0 there).
    fn opening(&self, k: usize) -> f64 {
        let d_dry = self.pr.dry_separation[k];
        match self.kind[k] {
            Kind::Closed => d_dry.max(self.pr.base_height),
            _ => d_dry,
        }
    }

    /// Full state of cell k at its opening separation (cached).
    fn open_full(&self, k: usize) -> &Full {
        self.open[k].get_or_init(|| self.full(k, self.opening(k)))
    }

    /// The full state of an open or closed cell k at separation d (at or above its opening separation),
    /// with the derivatives along its unknown u.
    fn full_state(&self, k: usize, d: f64) -> CellState {
        let f = self.full(k, d);
        CellState::full(d, &f, self.z_s, self.rise(k, &f))
    }

    /// dd/du in z_s of an open or closed cell k full in the state `f`: 1, or for a closed cell, whose
    /// unknown is its void height in F, F/(z_s·dl_v/dd).
    fn rise(&self, k: usize, f: &Full) -> f64 {
        if self.closed(k) {
            self.film_scale / (self.z_s * f.dlv)
        } else {
            1.0
        }
    }

    /// The unknown u ≥ 0 of cell k full at separation d with void height `lv` [m] (0 for a wall).
    fn full_unknown(&self, k: usize, d: f64, lv: f64) -> f64 {
        match self.kind[k] {
            Kind::Open => ((d - self.pr.dry_separation[k]) / self.z_s).max(0.0),
            Kind::Closed => lv / self.film_scale,
            Kind::Wall => 0.0,
        }
    }

    /// State of cell k at unknown u (left derivative at u = 0). Full (u > 0): d = d_dry + u·z_s for an
    /// open cell; for a closed one the separation above d_b with l_v(d) = u·F, F the film scale (its void
    /// height grows from zero at the kink; in d, whose l_v is flat at the kink, the linearised branch
    /// would ask for separations many z_s too large). Unpressurised (u ≤ 0, and a wall at any u):
    /// l_f = (1 + u)·l_v(d_dry).
    fn state(&self, k: usize, u: f64) -> CellState {
        let d_dry = self.pr.dry_separation[k];
        match self.kind[k] {
            Kind::Open if u > 0.0 => self.full_state(k, d_dry + u * self.z_s),
            Kind::Closed if u > 0.0 => self.full_state(
                k,
                separation_for_void(u * self.film_scale, self.z_s, self.pr.base_height),
            ),
            _ => {
                let lv = self.dry_void(k);
                CellState {
                    d: d_dry,
                    p: 0.0,
                    lf: (1.0 + u) * lv,
                    lv,
                    g: lv * lv * lv,
                    dp: 0.0,
                    dlf: lv,
                    dg: 0.0,
                    area: self.pr.dry_area_fraction[k],
                    load: self.pr.dry_metal_load[k],
                    rise: 0.0,
                }
            }
        }
    }

    fn states(&self, u: &[f64], s: &mut [CellState]) {
        for (k, (sk, uk)) in s.iter_mut().zip(u).enumerate() {
            *sk = self.state(k, *uk);
        }
    }

    /// Unknown u of cell k for a film (d, p_f, l_f), e.g. a previous solution (0 for an unpressurised
    /// closed cell, which holds nothing).
    fn unknown(&self, k: usize, d: f64, p: f64, lf: f64) -> f64 {
        if p > 0.0 {
            let lv = self.heights.void(d).0;
            self.full_unknown(k, d, lv)
        } else if self.closed(k) {
            0.0
        } else {
            (lf / self.dry_void(k) - 1.0).min(0.0)
        }
    }

    /// Volume flow carried by the surfaces out of cell k through its downstream face,
    /// v_m·h_y·[`face_height`] [m³/s].
    fn carried_out(&self, k: usize, s: &[CellState]) -> f64 {
        let f = &self.faces[k];
        self.vm * self.hy * face_height(s[k].lf, f.up.map(|u| s[u].lf)).0
    }

    /// Volume flow carried by the surfaces into cell k: out of the upstream cell, or for the leading cell
    /// the inlet film up to what its void holds, min(v_r·h_y·h_f0, v_m·h_y·l_v) [m³/s].
    fn carried_in(&self, k: usize, s: &[CellState]) -> f64 {
        match self.faces[k].up {
            Some(u) => self.intake(k) * self.carried_out(u, s),
            None => self.supply.min(self.vm * self.hy * s[k].lv),
        }
    }

    /// Volume balance of every cell (inflow − outflow) [m³/s].
    fn residual(&self, s: &[CellState], r: &mut [f64]) {
        for (k, rk) in r.iter_mut().enumerate() {
            let f = &self.faces[k];
            let c = &s[k];
            let mut v = self.carried_in(k, s) - self.carried_out(k, s) - f.edge * c.g * c.p;
            for &(nb, cf) in f.neighbours() {
                v += cf * harmonic(c.g, s[nb].g) * (s[nb].p - c.p);
            }
            *rk = v;
        }
    }

    /// The unpressurised branch of cell k, exact: p_f = 0, l_f = (1 + u)·l_v(d_dry), g = l_v(d_dry)³.
    fn left(&self, k: usize) -> Branch {
        let lv = self.dry_void(k);
        Branch {
            a: [0.0, lv, lv * lv * lv],
            b: [0.0, lv, 0.0],
        }
    }

    /// The full branch of cell k linearised at its current state `c` (u > 0) or at the kink (u ≤ 0).
    fn right(&self, k: usize, u: f64, c: &CellState) -> Branch {
        if u > 0.0 {
            let b = [c.dp, c.dlf, c.dg];
            Branch {
                a: [c.p - b[0] * u, c.lf - b[1] * u, c.g - b[2] * u],
                b,
            }
        } else {
            let f = self.open_full(k);
            let at = CellState::full(self.opening(k), f, self.z_s, self.rise(k, f));
            Branch {
                a: [at.p, at.lf, at.g],
                b: [at.dp, at.dlf, at.dg],
            }
        }
    }

    /// Partial derivatives of the balance of cell k with respect to (p_f, l_f, g) of the cells m of its
    /// stencil, passed to `visit(m, ∂R_k/∂(p_f, l_f, g)_m)` (a cell may be visited more than once).
    fn coefficients(&self, k: usize, s: &[CellState], mut visit: impl FnMut(usize, [f64; 3])) {
        let f = &self.faces[k];
        let c = &s[k];
        let vh = self.vm * self.hy;
        let mut own = [-f.edge * c.g, 0.0, -f.edge * c.p];
        // carried out through the downstream face
        let (_, dl, dl_up) = face_height(c.lf, f.up.map(|u| s[u].lf));
        own[1] -= vh * dl;
        match f.up {
            Some(up) => {
                // carried in: out of the upstream cell, reconstructed with the one upstream of that
                let up2 = self.faces[up].up;
                let (_, dl_in, dl_up2) = face_height(s[up].lf, up2.map(|u| s[u].lf));
                let intake = self.intake(k);
                visit(up, [0.0, vh * (intake * dl_in - dl_up), 0.0]);
                if let Some(up2) = up2 {
                    visit(up2, [0.0, vh * (intake * dl_up2), 0.0]);
                }
            }
            // the leading cell takes in v_m·h_y·l_v = v_m·h_y·g^(1/3) while that is below the supply
            None if vh * c.lv < self.supply => own[2] += vh / (3.0 * c.lv * c.lv),
            None => {}
        }
        for &(nb, cf) in f.neighbours() {
            let o = &s[nb];
            let (h, dh_own) = harmonic_with_slope(c.g, o.g);
            let dh_nb = harmonic_with_slope(o.g, c.g).1;
            let dp = o.p - c.p;
            own[0] -= cf * h;
            own[2] += cf * dh_own * dp;
            visit(nb, [cf * h, 0.0, cf * dh_nb * dp]);
        }
        visit(k, own);
    }

    /// Newton step of the piecewise-linear model: the smooth dependence of the balances on (p_f, l_f, g)
    /// is linearised at the current film, each cell's (p_f, l_f, g) follows the affine model of the branch
    /// its new u falls on. The branches are found by active-set passes (start: the current ones; a cell
    /// exactly on the kink starts on the branch its balance asks for), each a band LU of the model
    /// Jacobian. Writes the new unknowns to `target`; false if a factorisation fails.
    ///
    /// A closed cell ([`System::closed`]) on the unpressurised branch holds nothing whatever its u: its
    /// balance is the inflow alone and does not depend on u, so its row is pinned (u kept, `pinned` set)
    /// and it joins the full branch when the linearised inflow at the new film is positive (the
    /// complementarity min(u, −R) = 0 of such a cell: it stays dry only while nothing flows in).
    fn newton_target(
        &self,
        u: &[f64],
        s: &[CellState],
        r: &[f64],
        jac: &mut Band,
        target: &mut [f64],
        pinned: &mut [bool],
    ) -> bool {
        let n = self.len();
        let mut full: Vec<bool> = (0..n)
            .map(|k| {
                !self.wall(k) && (u[k] > 0.0 || ((u[k] == 0.0 || self.closed(k)) && r[k] > 0.0))
            })
            .collect();
        let mut pinned_rows: Vec<PinnedRow> = Vec::new();
        for _ in 0..MAX_PASSES {
            let model: Vec<Branch> = (0..n)
                .map(|k| {
                    if full[k] {
                        self.right(k, u[k], &s[k])
                    } else {
                        self.left(k)
                    }
                })
                .collect();
            jac.clear();
            pinned_rows.clear();
            for k in 0..n {
                pinned[k] = !full[k] && self.closed(k);
                let mut rhs = -r[k];
                let mut row = Vec::new();
                self.coefficients(k, s, |m, c| {
                    let (br, q) = (&model[m], &s[m]);
                    let j = c[0] * br.b[0] + c[1] * br.b[1] + c[2] * br.b[2];
                    if pinned[k] {
                        row.push((m, j));
                    } else {
                        jac.add(k, m, j);
                    }
                    rhs -=
                        c[0] * (br.a[0] - q.p) + c[1] * (br.a[1] - q.lf) + c[2] * (br.a[2] - q.g);
                });
                if pinned[k] {
                    jac.add(k, k, 1.0);
                    target[k] = u[k];
                    pinned_rows.push(PinnedRow { cell: k, row, rhs });
                } else {
                    target[k] = rhs;
                }
            }
            if !jac.factor() {
                return false;
            }
            jac.solve(target);
            let mut same = true;
            let mut pinned_row = pinned_rows.iter().peekable();
            for k in 0..n {
                let f = match pinned_row.next_if(|p| p.cell == k) {
                    // the linearised inflow of a pinned cell at the new film (a wall stays)
                    Some(p) => !self.wall(k) && p.inflow(target) > 0.0,
                    None => target[k] > 0.0,
                };
                if f != full[k] {
                    same = false;
                    full[k] = f;
                }
            }
            if same {
                break;
            }
        }
        target.iter().all(|t| t.is_finite())
    }

    /// The change (as in [`Self::change`]) that `step` makes to the linearised film at `u` with the balances
    /// `r`; None when a cell would change branch (no linear estimate then), also a closed cell into which
    /// fluid flows ([`Self::opens`]).
    fn predicted_change(&self, u: &[f64], s: &[CellState], r: &[f64], step: &[f64]) -> Option<f64> {
        if self.opens(u, r) {
            return None;
        }
        let mut m: f64 = 0.0;
        for ((uk, c), du) in u.iter().zip(s).zip(step) {
            let full = *uk > 0.0;
            if full != (uk + du > 0.0) {
                return None;
            }
            let dd = if full { (c.rise * du).abs() } else { 0.0 };
            m = m.max(dd).max((c.dlf * du).abs() / self.film_scale);
        }
        Some(m)
    }

    /// Whether fluid flows into a closed cell on the unpressurised branch (balance `r` > 0 at `u` ≤ 0): the
    /// film is not a solution yet, however small the step, as that cell must open.
    fn opens(&self, u: &[f64], r: &[f64]) -> bool {
        (0..self.len()).any(|k| u[k] <= 0.0 && r[k] > 0.0 && self.closed(k))
    }

    /// Largest change between two films: of d in z_s and of l_f in the film scale [-].
    fn change(&self, a: &[CellState], b: &[CellState]) -> f64 {
        a.iter().zip(b).fold(0.0, |m: f64, (x, y)| {
            m.max((x.d - y.d).abs() / self.z_s)
                .max((x.lf - y.lf).abs() / self.film_scale)
        })
    }

    /// One nonlinear Gauss–Seidel sweep marching with the flow (strips in the given lateral order), each
    /// cell solved exactly for its state with its neighbours fixed. Returns the largest change.
    fn sweep(&self, u: &mut [f64], s: &mut [CellState], forward: bool) -> Result<f64> {
        let strips = &self.pr.grid.strips;
        let vh = self.vm * self.hy;
        let mut change: f64 = 0.0;
        for si in 0..strips.len() {
            let si = if forward { si } else { strips.len() - 1 - si };
            for k in strips[si].cells.clone() {
                let f = &self.faces[k];
                let l_up = f.up.map(|u| s[u].lf);
                // carried in at void height l_v, and its derivative in l_v: out of the upstream cell, or
                // the inlet film up to what the leading cell's void holds
                let carried_in = |lv: f64| match f.up {
                    Some(up) => (self.intake(k) * self.carried_out(up, s), 0.0),
                    None if vh * lv < self.supply => (vh * lv, vh),
                    None => (self.supply, 0.0),
                };
                // volume balance of the cell as a function of its separation when full (l_f = l_v(d)),
                // and its derivative in d
                let balance = |full: &Full| {
                    let gk = full.lv * full.lv * full.lv;
                    let dgk = 3.0 * full.lv * full.lv * full.dlv;
                    let (q_in, dq_in) = carried_in(full.lv);
                    let (l_face, dl_face, _) = face_height(full.lv, l_up);
                    let mut r = q_in - vh * l_face - f.edge * gk * full.p;
                    let mut dr =
                        (dq_in - vh * dl_face) * full.dlv - f.edge * (dgk * full.p + gk * full.dp);
                    for &(nb, cf) in f.neighbours() {
                        let (h, dh) = harmonic_with_slope(gk, s[nb].g);
                        r += cf * h * (s[nb].p - full.p);
                        dr += cf * (dh * dgk * (s[nb].p - full.p) - h * full.dp);
                    }
                    (r, dr)
                };
                let new = match self.kind[k] {
                    // a wall holds nothing
                    Kind::Wall => self.state(k, u[k]),
                    Kind::Open | Kind::Closed if balance(self.open_full(k)).0 > 0.0 => {
                        // more fluid arrives than the cell holds at d_dry (or, closed, at d_b): full
                        // and pressurised
                        let dk = root_decreasing(
                            |d| balance(&self.full(k, d)),
                            self.opening(k),
                            s[k].d,
                            self.z_s,
                            1e-13 * self.z_s,
                        )?;
                        let new = self.full_state(k, dk);
                        u[k] = self.full_unknown(k, dk, new.lv);
                        new
                    }
                    _ => {
                        // unpressurised: the film height follows from the inflow, which it carries out
                        let lv = self.dry_void(k);
                        let gk = lv * lv * lv;
                        let mut inflow = carried_in(lv).0;
                        for &(nb, cf) in f.neighbours() {
                            inflow += cf * harmonic(gk, s[nb].g) * s[nb].p;
                        }
                        u[k] = if lv > 0.0 {
                            let lf = face_height_inverse(inflow / vh, l_up)?;
                            (lf.min(lv) / lv - 1.0).min(0.0)
                        } else {
                            0.0
                        };
                        self.state(k, u[k])
                    }
                };
                change = change
                    .max((new.d - s[k].d).abs() / self.z_s)
                    .max((new.lf - s[k].lf).abs() / self.film_scale);
                s[k] = new;
            }
        }
        Ok(change)
    }

    /// The solution fields, regimes and flows of the film `s`.
    fn solution(
        &self,
        s: &[CellState],
        iterations: usize,
        residual: f64,
        converged: bool,
    ) -> FilmSolution {
        let n = self.len();
        let pr = self.pr;
        let mut r = vec![0.0; n];
        self.residual(s, &mut r);
        let balance_residual =
            r.iter().fold(0.0, |m: f64, x| m.max(x.abs())) / (self.vm * self.hy * self.film_scale);
        let mut sol = FilmSolution {
            separation: s.iter().map(|c| c.d).collect(),
            fluid_pressure: s.iter().map(|c| c.p).collect(),
            fluid_height: s.iter().map(|c| c.lf.clamp(0.0, c.lv)).collect(),
            void_height: s.iter().map(|c| c.lv).collect(),
            area_fraction: vec![0.0; n],
            metal_load: vec![0.0; n],
            regime: vec![Regime::Dry; n],
            iterations,
            residual,
            balance_residual,
            converged,
            inflow: 0.0,
            rejected: 0.0,
            outflow: 0.0,
            expelled: 0.0,
        };
        for (k, c) in s.iter().enumerate() {
            sol.area_fraction[k] = c.area;
            sol.metal_load[k] = c.load;
            sol.regime[k] = if sol.fluid_height[k] <= 0.0 {
                Regime::Dry
            } else if c.p * (1.0 - c.area) >= 0.01 * pr.nominal_pressure[k] {
                Regime::Mixed
            } else {
                Regime::Boundary
            };
            let f = &self.faces[k];
            if f.up.is_none() {
                let taken = self.carried_in(k, s);
                sol.inflow += taken;
                sol.rejected += self.supply - taken;
            }
            if f.down.is_none() {
                sol.outflow += self.carried_out(k, s);
            }
            match f.up {
                Some(up) if self.intake(k) < 1.0 => {
                    sol.expelled += (1.0 - self.intake(k)) * self.carried_out(up, s);
                }
                _ => {}
            }
            sol.expelled += f.edge * c.g * c.p;
        }
        sol
    }
}

/// A starting film for [`solve_film`]: separation [m], fluid pressure [Pa] and fluid height [m] per cell,
/// from a previous film solution or a previous operating point's fields on the same grid.
#[derive(Debug, Clone, Copy)]
pub struct FilmStart<'a> {
    /// Separation d per cell [m].
    pub separation: &'a [f64],
    /// Fluid pressure p_f per cell [Pa].
    pub fluid_pressure: &'a [f64],
    /// Fluid height l_f per cell [m].
    pub fluid_height: &'a [f64],
}

impl FilmSolution {
    /// This film as the start of another solve.
    pub fn as_start(&self) -> FilmStart<'_> {
        FilmStart {
            separation: &self.separation,
            fluid_pressure: &self.fluid_pressure,
            fluid_height: &self.fluid_height,
        }
    }
}

/// Solves the film for one outer iteration by the semismooth Newton method of the module documentation;
/// `warm` (a previous film on the same grid) is the starting film, otherwise every cell starts just
/// full without pressure (u = 0). Should Newton stall (no acceptable damped step, or more than
/// NEWTON_LIMIT iterations), Gauss–Seidel sweeps take over from the same start (from an empty film when
/// cold) with the rest of the iteration budget.
pub fn solve_film(pr: &FilmProblem, warm: Option<FilmStart>) -> Result<FilmSolution> {
    let sys = System::new(pr)?;
    let newton = sys.newton_from(warm);
    if newton.converged || newton.iterations >= pr.max_iterations {
        return Ok(newton);
    }
    let mut sol = sys.gauss_seidel(vec![-1.0; sys.len()], pr.max_iterations - newton.iterations)?;
    sol.iterations += newton.iterations;
    Ok(sol)
}

/// The film of [`solve_film`] without its Gauss–Seidel fallback: Newton's last film, converged or not (its
/// `converged` says which). The coupled solver keeps it, and reports the point unconverged, where the
/// fallback finds no film either (docs/model.md §9).
pub fn solve_film_newton(pr: &FilmProblem, warm: Option<FilmStart>) -> Result<FilmSolution> {
    Ok(System::new(pr)?.newton_from(warm))
}

impl System<'_> {
    /// Newton from `warm` (a previous film on the same grid) or else from every cell just full without
    /// pressure (u = 0), restarted from there if it stalls from the warm start (within the iteration
    /// budget).
    fn newton_from(&self, warm: Option<FilmStart>) -> FilmSolution {
        let n = self.len();
        let start: Option<Vec<f64>> = match warm {
            Some(w)
                if w.separation.len() == n
                    && w.fluid_pressure.len() == n
                    && w.fluid_height.len() == n =>
            {
                Some(
                    (0..n)
                        .map(|k| {
                            self.unknown(k, w.separation[k], w.fluid_pressure[k], w.fluid_height[k])
                        })
                        .collect(),
                )
            }
            _ => None,
        };
        let budget = self.pr.max_iterations;
        let limit = budget.min(NEWTON_LIMIT);
        let mut newton = self.newton(start.clone().unwrap_or_else(|| vec![0.0; n]), limit);
        if !newton.converged && start.is_some() && newton.iterations < budget {
            // a warm start is only a guess: from the film of another temperature (a hot, heavily loaded
            // point whose outer iteration moves the temperature by tens of kelvin) Newton can stall where
            // it converges from the just-full film; restart from there before falling back to
            // Gauss–Seidel
            let used = newton.iterations;
            newton = self.newton(vec![0.0; n], limit.min(budget - used));
            newton.iterations += used;
        }
        newton
    }

    /// Damped semismooth Newton iteration from `u` (at most `limit` iterations). Each step is damped until
    /// the simplified Newton correction at the new film is smaller than the step (natural monotonicity
    /// test: Deuflhard, Newton Methods for Nonlinear Problems, 2004, ch. 3). Converged when the Newton
    /// correction at the current film (estimated by the linear model), or a full step, changes the film by
    /// no more than the tolerance; it stops unconverged when no damped step passes the test.
    fn newton(&self, mut u: Vec<f64>, limit: usize) -> FilmSolution {
        let n = self.len();
        let mut s = vec![CellState::default(); n];
        self.states(&u, &mut s);
        let mut r = vec![0.0; n];
        self.residual(&s, &mut r);
        // the balance of a cell depends on its neighbours and, through the transport reconstruction, on
        // the second cell upstream
        let mut jac = Band::new(self.faces.iter().map(|f| {
            let up2 = f.up.and_then(|u| self.faces[u].up);
            f.neighbours().iter().map(|(k, _)| *k).chain(up2)
        }));
        let (mut step, mut simplified) = (vec![0.0; n], vec![0.0; n]);
        let mut pinned = vec![false; n];
        let (mut u_t, mut s_t, mut r_t) = (u.clone(), s.clone(), r.clone());
        let mut iterations = 0;
        let mut change = f64::INFINITY;
        let mut converged = false;
        while iterations < limit {
            iterations += 1;
            if !self.newton_target(&u, &s, &r, &mut jac, &mut step, &mut pinned) {
                break;
            }
            for (d, uk) in step.iter_mut().zip(&u) {
                *d -= uk;
            }
            // converged where the Newton correction itself is below the tolerance: the film at u is
            // returned, within that correction of the solution
            if let Some(c) = self.predicted_change(&u, &s, &r, &step)
                && c <= self.pr.tolerance
            {
                change = c;
                converged = true;
                break;
            }
            let norm = norm2(&step).sqrt();
            let largest = step.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
            let mut alpha = (MAX_STEP / largest).min(1.0);
            let mut accepted = None;
            while alpha >= MIN_ALPHA {
                for k in 0..n {
                    u_t[k] = u[k] + alpha * step[k];
                }
                self.states(&u_t, &mut s_t);
                self.residual(&s_t, &mut r_t);
                let change_t = self.change(&s, &s_t);
                // a full step below the tolerance is final (the test may sit at rounding level there)
                if alpha == 1.0 && change_t <= self.pr.tolerance && !self.opens(&u_t, &r_t) {
                    accepted = Some((change_t, true));
                    break;
                }
                for ((b, rk), pin) in simplified.iter_mut().zip(&r_t).zip(&pinned) {
                    // a pinned row keeps its u
                    *b = if *pin { 0.0 } else { -rk };
                }
                jac.solve(&mut simplified);
                if norm2(&simplified).sqrt() <= (1.0 - 0.25 * alpha) * norm {
                    // after a full step the simplified correction estimates the next Newton correction:
                    // converged when that is below the tolerance (the error-oriented test of NLEQ-ERR)
                    let next = match alpha == 1.0 {
                        true => self.predicted_change(&u_t, &s_t, &r_t, &simplified),
                        false => None,
                    };
                    accepted = Some(match next {
                        Some(c) if c <= self.pr.tolerance => (c, true),
                        _ => (change_t, false),
                    });
                    break;
                }
                alpha *= 0.5;
            }
            let Some((c, done)) = accepted else {
                break;
            };
            std::mem::swap(&mut u, &mut u_t);
            std::mem::swap(&mut s, &mut s_t);
            std::mem::swap(&mut r, &mut r_t);
            change = c;
            if done {
                converged = true;
                break;
            }
        }
        self.solution(&s, iterations, change, converged)
    }

    /// Nonlinear Gauss–Seidel sweeps (the paper's method) from `u`, alternating the lateral order so that
    /// pressure spreads both ways, until the change of a sweep meets the tolerance or `limit` sweeps.
    fn gauss_seidel(&self, mut u: Vec<f64>, limit: usize) -> Result<FilmSolution> {
        let mut s = vec![CellState::default(); self.len()];
        self.states(&u, &mut s);
        let mut change = f64::INFINITY;
        let mut sweeps = 0;
        while sweeps < limit && change > self.pr.tolerance {
            sweeps += 1;
            change = self.sweep(&mut u, &mut s, sweeps % 2 == 1)?;
        }
        Ok(self.solution(&s, sweeps, change, change <= self.pr.tolerance))
    }
}

/// Squared Euclidean norm.
fn norm2(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum()
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
        stage: Stage::Fluid,
        reason: format!("no separation balances the cell (bracket {a:e} .. {b:e} m)"),
    })
}

#[cfg(test)]
mod tests;
