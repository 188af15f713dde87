//! Influence coefficients of a half-space moving under the contact (docs/model.md §7, paper §2.3): the surface
//! temperature rise at a cell centre per unit heat flux density on a source cell.
//!
//! The moving point source (Carslaw & Jaeger §10.7, Rosenthal) gives ΔT = Q·exp(−p(r + ζ))/(2πλr) with
//! p = v/(2κ), r = sqrt(ζ² + η²), (ζ, η) = field point − source point. Its integral along ζ is closed-form,
//!   ∫_{ζ1}^{ζ2} exp(−p(r + ζ))/r dζ = E1(p(r1 + ζ1)) − E1(p(r2 + ζ2))   (d/dζ of −E1(p(r + ζ)) is the kernel),
//! so a rectangle needs only a one-dimensional integral over η. That one is done adaptively with break
//! points at the thermal wake's width sqrt(2|ζ|/p + 1/p²) (tens of µm at 30 m/s, far below a cell width) and
//! with the 1/r singularity's logarithm subtracted and integrated analytically.

use super::expint::exp_integral_e1;
use crate::contact::ContactGrid;
use crate::error::{Error, Result, Stage, check_finite, check_positive};
use crate::params::Material;
use crate::quadrature::gauss_kronrod::{
    Quadrature, integrate_adaptive, kronrod_nodes, kronrod_sum,
};
use std::f64::consts::PI;

/// Relative accuracy asked of each influence coefficient (relative to the coefficient scale of the grid).
const RELATIVE_TOLERANCE: f64 = 1e-9;
/// Panel budget of one lateral integral.
const MAX_PANELS: usize = 400;
/// Part of the tolerance below which a lateral interval, or its tail, counts as negligible and is skipped
/// (1e-15 of the grid's coefficient scale for the table's tolerance).
const NEGLIGIBLE_FRACTION: f64 = 1e-6;

/// One body as a half-space whose surface moves at speed v in −x under a fixed heat source.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MovingHalfSpace {
    /// Surface speed v [m/s].
    speed: f64,
    /// Thermal conductivity λ [W/(m·K)].
    conductivity: f64,
    /// Thermal diffusivity κ [m²/s].
    diffusivity: f64,
}

/// ζ + r with r = sqrt(ζ² + η²), without cancellation for ζ < 0 (there ζ + r = η²/(r − ζ)). Offsets are
/// contact-sized lengths, so ζ² + η² neither overflows nor underflows (no need for the slower `hypot`).
fn zeta_plus_r(zeta: f64, eta: f64) -> f64 {
    let r = (zeta * zeta + eta * eta).sqrt();
    if zeta >= 0.0 {
        r + zeta
    } else {
        eta * eta / (r - zeta)
    }
}

/// Number of sides of ζ = 0 that a lateral interval starting at η = 0 has next to the 1/r singularity
/// (each adds ln(1/η) to the lateral integrand; subtracted as s·ln(η/η_end), whose integral over
/// [0, η_end] is −s·η_end); 0 if the rectangle does not touch the origin.
fn singularity_strength(zeta1: f64, zeta2: f64, eta_a: f64) -> f64 {
    if eta_a == 0.0 && zeta1 <= 0.0 && zeta2 >= 0.0 {
        f64::from(u8::from(zeta1 < 0.0) + u8::from(zeta2 > 0.0))
    } else {
        0.0
    }
}

impl MovingHalfSpace {
    /// Half-space of `material` (λ, κ = λ/(ρc)) whose surface moves at `speed` [m/s] (> 0).
    pub fn new(speed: f64, material: &Material) -> Result<Self> {
        check_positive("surface speed", speed, "m/s")?;
        check_positive("conductivity", material.conductivity, "W/(m·K)")?;
        check_positive("density", material.density, "kg/m³")?;
        check_positive("specific_heat", material.specific_heat, "J/(kg·K)")?;
        Ok(Self {
            speed,
            conductivity: material.conductivity,
            diffusivity: material.diffusivity(),
        })
    }

    /// Surface speed v [m/s].
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// Decay rate p = v/(2κ) [1/m] of the moving-source kernel; p·h is the cell Péclet number.
    pub fn decay_rate(&self) -> f64 {
        self.speed / (2.0 * self.diffusivity)
    }

    /// Quasi-steady surface temperature rise per unit power of a point source, docs/model.md §7 [K/W]:
    /// exp(−p(r + ζ))/(2πλr), with (ζ, η) = field point − source point [m]; downstream (ζ = −r) points
    /// see exp(0), upstream ones decay like exp(−2p·r).
    pub fn point_source(&self, zeta: f64, eta: f64) -> f64 {
        let r = zeta.hypot(eta);
        (-self.decay_rate() * zeta_plus_r(zeta, eta)).exp() / (2.0 * PI * self.conductivity * r)
    }

    /// ∫_{ζ1}^{ζ2} exp(−p(r + ζ))/r dζ at lateral offset η = E1(p(r1 + ζ1)) − E1(p(r2 + ζ2)) [-].
    fn along_x(&self, zeta1: f64, zeta2: f64, eta: f64) -> f64 {
        let p = self.decay_rate();
        exp_integral_e1(p * zeta_plus_r(zeta1, eta)) - exp_integral_e1(p * zeta_plus_r(zeta2, eta))
    }

    /// The |η| [m] beyond which the lateral integrand of an offset rectangle starting at ζ1 is negligible
    /// over an interval of length `length` [m]: where p(r1 + ζ1) reaches z* = ln(length/ε), so that
    /// length·E1(z*) < length·e^(−z*)/z* ≤ ε (A&S 5.1.20); ∞ if ε is too coarse for that bound. Solving
    /// p(sqrt(ζ1² + η²) + ζ1) = z* gives η² = c(c − 2ζ1) with c = z*/p; for ζ1 > 0 with c < 2ζ1 the
    /// integrand is negligible everywhere (0).
    fn negligible_beyond(&self, zeta1: f64, length: f64, negligible: f64) -> f64 {
        let z_cut = (length / negligible).ln();
        if z_cut < 1.0 {
            return f64::INFINITY;
        }
        let c = z_cut / self.decay_rate();
        (c * (c - 2.0 * zeta1)).max(0.0).sqrt()
    }

    /// Break points of the lateral integral over [ηa, η_end] (ends included): the wake's structure behind
    /// each downstream edge ζ < 0 (half-width sqrt(2|ζ|/p + 1/p²), where p(r + ζ) = 1, and 3 and 8 times
    /// that), merged when within a factor 1.5 of each other: the adaptive bisection resolves the rest.
    fn lateral_breaks(&self, zeta1: f64, zeta2: f64, eta_a: f64, eta_end: f64) -> Vec<f64> {
        let p = self.decay_rate();
        let mut candidates: Vec<f64> = [zeta1, zeta2]
            .into_iter()
            .filter(|z| *z < 0.0)
            .flat_map(|zeta| {
                let width = (2.0 * zeta.abs() / p + 1.0 / (p * p)).sqrt();
                [width, 3.0 * width, 8.0 * width]
            })
            .filter(|eta| *eta > eta_a && *eta < eta_end)
            .collect();
        candidates.sort_by(f64::total_cmp);
        let mut breaks = vec![eta_a];
        for eta in candidates {
            if eta > 1.5 * breaks[breaks.len() - 1] {
                breaks.push(eta);
            }
        }
        breaks.push(eta_end);
        breaks
    }

    /// ∫_{ηa}^{ηb} ∫_{ζ1}^{ζ2} exp(−p(r + ζ))/r dζ dη for 0 ≤ ηa < ηb [m], to absolute tolerance `tol` [m].
    ///
    /// The lateral integrand E1(p(r1 + ζ1)) − E1(p(r2 + ζ2)) lies between 0 and E1(p(r1 + ζ1)), which falls
    /// with |η| (ζ + r grows with |η|). Beyond the η where p(r1 + ζ1) reaches z* = ln((ηb − ηa)/ε) the
    /// rest of the interval contributes less than (ηb − ηa)·e^(−z*)/z* ≤ ε = 1e-6·tol (E1(z) < e^(−z)/z,
    /// A&S 5.1.20), so the integral stops there, and an interval that starts beyond it is zero without a
    /// single integrand evaluation: upstream of the source at high Péclet number and laterally outside
    /// the thermal wake most offsets are skipped this way.
    fn lateral_interval(
        &self,
        zeta1: f64,
        zeta2: f64,
        eta_a: f64,
        eta_b: f64,
        tol: f64,
    ) -> Quadrature {
        let negligible = NEGLIGIBLE_FRACTION * tol;
        let eta_cut = self.negligible_beyond(zeta1, eta_b - eta_a, negligible);
        if eta_cut <= eta_a {
            return Quadrature {
                value: 0.0,
                error: negligible,
                panels: 0,
                converged: true,
            };
        }
        let (eta_end, cut_error) = if eta_cut < eta_b {
            (eta_cut, negligible)
        } else {
            (eta_b, 0.0)
        };
        let strength = singularity_strength(zeta1, zeta2, eta_a);
        let breaks = self.lateral_breaks(zeta1, zeta2, eta_a, eta_end);
        let integrand = |eta: f64| {
            let regular = self.along_x(zeta1, zeta2, eta);
            if strength > 0.0 {
                regular + strength * (eta / eta_end).ln()
            } else {
                regular
            }
        };
        let mut q = integrate_adaptive(integrand, &breaks, tol, MAX_PANELS);
        q.value += strength * eta_end;
        q.error += cut_error;
        q
    }

    /// Temperature rise at a field point per unit flux density of a uniform source covering every point
    /// whose offset (field − source) lies in [ζ1, ζ2] × [η1, η2] [K·m²/W]: the rectangle integral of
    /// [`Self::point_source`], accurate to about `tol` [K·m²/W] (the error estimate is returned).
    pub fn offset_rectangle(&self, zeta: [f64; 2], eta: [f64; 2], tol: f64) -> Result<Quadrature> {
        for (name, v) in [
            ("zeta1", zeta[0]),
            ("zeta2", zeta[1]),
            ("eta1", eta[0]),
            ("eta2", eta[1]),
        ] {
            check_finite(name, v, "m")?;
        }
        check_positive("rectangle length zeta2 - zeta1", zeta[1] - zeta[0], "m")?;
        check_positive("rectangle width eta2 - eta1", eta[1] - eta[0], "m")?;
        check_positive("quadrature tolerance", tol, "K·m²/W")?;
        let q = self.rectangle(zeta, eta, tol);
        if !q.value.is_finite() {
            return Err(Error::Numerical {
                stage: Stage::ThermalInfluenceCoefficient,
                reason: format!("non-finite rectangle integral for offsets {zeta:?} x {eta:?}"),
            });
        }
        Ok(q)
    }

    /// [`Self::offset_rectangle`] for checked input (finite, ζ1 < ζ2, η1 < η2, tol > 0). A result with no
    /// panel is a rectangle skipped as negligible (see [`Self::lateral_interval`]).
    fn rectangle(&self, zeta: [f64; 2], eta: [f64; 2], tol: f64) -> Quadrature {
        let scale = 1.0 / (2.0 * PI * self.conductivity);
        let tol_m = tol / scale;
        let [z1, z2] = zeta;
        // The kernel is even in η: fold the lateral range onto η ≥ 0.
        let [e1, e2] = eta;
        let mut q = if e1 >= 0.0 {
            self.lateral_interval(z1, z2, e1, e2, tol_m)
        } else if e2 <= 0.0 {
            self.lateral_interval(z1, z2, -e2, -e1, tol_m)
        } else if -e1 == e2 {
            let mut half = self.lateral_interval(z1, z2, 0.0, e2, 0.5 * tol_m);
            half.value *= 2.0;
            half.error *= 2.0;
            half
        } else {
            let lower = self.lateral_interval(z1, z2, 0.0, -e1, 0.5 * tol_m);
            let upper = self.lateral_interval(z1, z2, 0.0, e2, 0.5 * tol_m);
            Quadrature {
                value: lower.value + upper.value,
                error: lower.error + upper.error,
                panels: lower.panels + upper.panels,
                converged: lower.converged && upper.converged,
            }
        };
        q.value *= scale;
        q.error *= scale;
        q
    }
}

/// One row Δj of an influence table: the lateral range of its rectangles folded onto η ≥ 0 (as
/// [`MovingHalfSpace::rectangle`] folds it), the Kronrod nodes on that range and, per cell edge ζ_k, the
/// values E1(p(r + ζ_k)) at those nodes, each evaluated once and shared by the two rectangles meeting at
/// the edge: most coefficients at low Péclet number are a single panel of the difference of two edges.
struct TableRow<'a> {
    body: &'a MovingHalfSpace,
    edges: &'a [f64],
    /// Folded lateral interval [ηa, ηb] [m].
    eta: [f64; 2],
    /// 2 if the rectangles straddle η = 0 (both halves alike), else 1.
    fold: f64,
    /// Lateral tolerance [m] (that of [`MovingHalfSpace::lateral_interval`]).
    tol: f64,
    nodes: [f64; 15],
    values: Vec<Option<[f64; 15]>>,
}

impl<'a> TableRow<'a> {
    /// Row of rectangles [edges[k], edges[k + 1]] × `lateral` (lateral[1] > 0, centred on η = 0 if
    /// lateral[0] < 0) to tolerance `tol` [K·m²/W].
    fn new(body: &'a MovingHalfSpace, edges: &'a [f64], lateral: [f64; 2], tol: f64) -> Self {
        let tol_m = tol * 2.0 * PI * body.conductivity;
        let (eta, fold, tol) = if lateral[0] >= 0.0 {
            (lateral, 1.0, tol_m)
        } else {
            ([0.0, lateral[1]], 2.0, 0.5 * tol_m)
        };
        Self {
            body,
            edges,
            eta,
            fold,
            tol,
            nodes: kronrod_nodes(eta[0], eta[1]),
            values: vec![None; edges.len()],
        }
    }

    /// E1(p(r + ζ_k)) at the row's nodes.
    fn edge(&mut self, k: usize) -> [f64; 15] {
        let (body, zeta, nodes) = (self.body, self.edges[k], &self.nodes);
        *self.values[k].get_or_insert_with(|| {
            let p = body.decay_rate();
            nodes.map(|eta| exp_integral_e1(p * zeta_plus_r(zeta, eta)))
        })
    }

    /// The rectangle between edges k and k + 1 as one Kronrod panel of shared edge values, when that is
    /// all [`MovingHalfSpace::lateral_interval`] would compute (no singular corner, no negligible tail and
    /// no wake break inside the interval, the panel within tolerance), with the same result; None
    /// otherwise.
    fn shared_panel(&mut self, k: usize) -> Option<Quadrature> {
        let (zeta1, zeta2) = (self.edges[k], self.edges[k + 1]);
        let [eta_a, eta_b] = self.eta;
        let negligible = NEGLIGIBLE_FRACTION * self.tol;
        if singularity_strength(zeta1, zeta2, eta_a) > 0.0
            || self
                .body
                .negligible_beyond(zeta1, eta_b - eta_a, negligible)
                < eta_b
            || self.body.lateral_breaks(zeta1, zeta2, eta_a, eta_b).len() > 2
        {
            return None;
        }
        let (upstream, downstream) = (self.edge(k), self.edge(k + 1));
        let along_x: [f64; 15] = std::array::from_fn(|i| upstream[i] - downstream[i]);
        let (value, error) = kronrod_sum(&along_x, eta_a, eta_b);
        if error > self.tol {
            return None;
        }
        let scale = 1.0 / (2.0 * PI * self.body.conductivity);
        Some(Quadrature {
            value: value * self.fold * scale,
            error: error * self.fold * scale,
            panels: 1,
            converged: true,
        })
    }
}

/// Influence coefficients of one body on a uniform grid, by cell offset: translation invariance makes the
/// temperature rise at cell (i, j) per unit flux on cell (i', j') a function G(Δi, Δj) of Δi = i − i',
/// Δj = j − j' alone, and the kernel's symmetry in y gives G(Δi, −Δj) = G(Δi, Δj); so (2nx − 1)·ny values
/// describe the whole N × N matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct InfluenceTable {
    nx: usize,
    ny: usize,
    /// G(Δi, Δj) at index (Δi + nx − 1) + (2nx − 1)·Δj, Δj ≥ 0 [K·m²/W].
    values: Vec<f64>,
    /// Largest estimated absolute quadrature error of a coefficient [K·m²/W].
    error: f64,
    /// Total number of Gauss–Kronrod panels evaluated.
    panels: usize,
}

impl InfluenceTable {
    /// Coefficients of `body` for every offset of an nx × ny grid of cells h_x × h_y [m]: temperature rise
    /// at a cell centre per unit flux density [W/m²] on a whole source cell (docs/model.md §7). Each coefficient
    /// is accurate to 1e-9 of the grid's coefficient scale h/sqrt(1 + p·h)/(2πλ) (h = min(h_x, h_y));
    /// an integral that misses this within its panel budget is an error. Offsets whose rigorous bound is
    /// below 1e-15 of that scale (upstream at high Péclet number, laterally outside the wake) are exactly
    /// zero and cost no quadrature.
    pub fn new(body: &MovingHalfSpace, nx: usize, ny: usize, hx: f64, hy: f64) -> Result<Self> {
        if nx == 0 || ny == 0 {
            return Err(Error::out_of_range(
                "grid size",
                (nx.min(ny)) as f64,
                "nx, ny >= 1",
            ));
        }
        check_positive("cell length h_x", hx, "m")?;
        check_positive("cell width h_y", hy, "m")?;
        let h = hx.min(hy);
        let scale = h / (1.0 + body.decay_rate() * h).sqrt() / (2.0 * PI * body.conductivity);
        let tol = RELATIVE_TOLERANCE * scale;
        let width = 2 * nx - 1;
        let mut values = vec![0.0; width * ny];
        let mut error = 0.0_f64;
        let mut panels = 0;
        // cell edges along x: offset Δi = di − (nx − 1) spans [edges[di], edges[di + 1]]
        let edges: Vec<f64> = (0..=width)
            .map(|k| (k as f64 - (nx as f64 - 0.5)) * hx)
            .collect();
        // A skipped offset (no panel: its rigorous bound is negligible) ends its row: the bound only grows
        // more negligible upstream (larger Δi, larger ζ1 + r); a row skipped from its most downstream offset
        // on ends the table (larger Δj, larger |η| on the same interval length).
        for dj in 0..ny {
            let eta = dj as f64 * hy;
            let lateral = [eta - 0.5 * hy, eta + 0.5 * hy];
            let mut row = TableRow::new(body, &edges, lateral, tol);
            let mut row_skipped = true;
            for di in 0..width {
                let q = row
                    .shared_panel(di)
                    .unwrap_or_else(|| body.rectangle([edges[di], edges[di + 1]], lateral, tol));
                if q.panels == 0 {
                    break;
                }
                row_skipped = false;
                if !q.converged || !q.value.is_finite() {
                    return Err(Error::Numerical {
                        stage: Stage::ThermalInfluenceCoefficient,
                        reason: format!(
                            "quadrature for offset ({}, {dj}) unconverged: value {:.3e}, error estimate {:.3e} > tolerance {tol:.3e} after {} panels",
                            di as isize - (nx - 1) as isize,
                            q.value,
                            q.error,
                            q.panels
                        ),
                    });
                }
                values[di + width * dj] = q.value;
                error = error.max(q.error);
                panels += q.panels;
            }
            if row_skipped {
                break;
            }
        }
        Ok(Self {
            nx,
            ny,
            values,
            error,
            panels,
        })
    }

    /// A table of given coefficients G(Δi, Δj) at index (Δi + nx − 1) + (2nx − 1)·Δj, Δj ≥ 0
    /// [K·m²/W], with their largest error estimate `error` [K·m²/W] (an interpolated table,
    /// [`super::lattice::interpolated_table_with`]: no quadrature panel of its own).
    pub(super) fn from_values(nx: usize, ny: usize, values: Vec<f64>, error: f64) -> Result<Self> {
        if nx == 0 || ny == 0 || values.len() != (2 * nx - 1) * ny {
            return Err(Error::Numerical {
                stage: Stage::ThermalInfluenceCoefficient,
                reason: format!(
                    "{} coefficients for a {nx}x{ny} grid's offsets",
                    values.len()
                ),
            });
        }
        Ok(Self {
            nx,
            ny,
            values,
            error,
            panels: 0,
        })
    }

    /// The coefficients G(Δi, Δj) at index (Δi + nx − 1) + (2nx − 1)·Δj, Δj ≥ 0 [K·m²/W].
    pub(super) fn values(&self) -> &[f64] {
        &self.values
    }

    /// Table for the cells of `grid`.
    pub fn for_grid(body: &MovingHalfSpace, grid: &ContactGrid) -> Result<Self> {
        Self::new(body, grid.nx, grid.ny, grid.hx, grid.hy)
    }

    /// G(Δi, Δj) [K·m²/W]: temperature rise at a cell per unit flux density on the cell Δi columns (along x)
    /// and Δj rows (along y) before it; None outside the grid's offsets.
    pub fn coefficient(&self, di: isize, dj: isize) -> Option<f64> {
        let (nx, ny) = (self.nx as isize, self.ny as isize);
        if di.abs() >= nx || dj.abs() >= ny {
            return None;
        }
        Some(self.values[(di + nx - 1) as usize + (2 * self.nx - 1) * dj.unsigned_abs()])
    }

    /// Grid size (nx, ny) the table was built for.
    pub fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// Largest estimated absolute quadrature error of a coefficient [K·m²/W].
    pub fn error_estimate(&self) -> f64 {
        self.error
    }

    /// Number of 15-point Gauss–Kronrod panels the table needed (a cost measure).
    pub fn panels(&self) -> usize {
        self.panels
    }

    /// The dense N × N influence matrix over the active cells of `grid` (which must be the grid the table was
    /// built for): G[k, l] = temperature rise at cell k per unit flux density on cell l [K·m²/W].
    #[cfg(test)]
    pub(crate) fn matrix(&self, grid: &ContactGrid) -> Result<faer::Mat<f64>> {
        if grid.nx != self.nx || grid.ny != self.ny {
            return Err(Error::Numerical {
                stage: Stage::ThermalInfluenceMatrix,
                reason: format!(
                    "table built for a {}x{} grid, used on a {}x{} grid",
                    self.nx, self.ny, grid.nx, grid.ny
                ),
            });
        }
        let cells = &grid.cells;
        let width = 2 * self.nx - 1;
        let offset = self.nx - 1;
        Ok(faer::Mat::from_fn(cells.len(), cells.len(), |k, l| {
            let (field, source) = (&cells[k], &cells[l]);
            let di = field.i + offset - source.i;
            let dj = field.j.abs_diff(source.j);
            self.values[di + width * dj]
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steel() -> Material {
        Material::default()
    }

    /// ∫∫ dA/r over [0, x] × [0, y] for x, y > 0: x·asinh(y/x) + y·asinh(x/y) (docs/model.md §7 quarter).
    fn quarter_steady(x: f64, y: f64) -> f64 {
        x * (y / x).asinh() + y * (x / y).asinh()
    }

    /// Independent reference for a rectangle that contains the origin: in polar coordinates about the
    /// singular point the radial integral is closed-form,
    /// ∫_0^R exp(−p·r·(1 + cos θ)) dr = (1 − exp(−p·R·(1 + cos θ)))/(p·(1 + cos θ)),
    /// leaving a 1-D integral over θ of the distance R(θ) to the rectangle's edge (composite midpoint rule,
    /// split at the corner angles).
    fn polar_reference(body: &MovingHalfSpace, zeta: [f64; 2], eta: [f64; 2]) -> f64 {
        let p = body.decay_rate();
        let corners = [
            eta[1].atan2(zeta[1]),
            eta[1].atan2(zeta[0]),
            eta[0].atan2(zeta[0]) + 2.0 * PI,
            eta[0].atan2(zeta[1]) + 2.0 * PI,
        ];
        let mut total = 0.0;
        let mut start = corners[3] - 2.0 * PI;
        for &end in &corners {
            let n = 400_000;
            let dt = (end - start) / n as f64;
            for k in 0..n {
                let t = start + (k as f64 + 0.5) * dt;
                let (s, c) = t.sin_cos();
                let mut r = f64::INFINITY;
                for (d, bounds) in [(c, zeta), (s, eta)] {
                    if d > 0.0 {
                        r = r.min(bounds[1] / d);
                    } else if d < 0.0 {
                        r = r.min(bounds[0] / d);
                    }
                }
                let a = p * (1.0 + c);
                let radial = if a * r < 1e-8 {
                    r
                } else {
                    -(-a * r).exp_m1() / a
                };
                total += radial * dt;
            }
            start = end;
        }
        total / (2.0 * PI * body.conductivity)
    }

    /// Independent brute-force reference for a rectangle away from the origin: tensor Gauss–Legendre
    /// (5 points) on a fine uniform sub-grid of the point-source kernel itself.
    fn brute_force(body: &MovingHalfSpace, zeta: [f64; 2], eta: [f64; 2], n: [usize; 2]) -> f64 {
        let nodes = [
            (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
            (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (0.0, 0.568_888_888_888_888_9),
            (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (0.906_179_845_938_664, 0.236_926_885_056_189_1),
        ];
        let (dx, dy) = (
            (zeta[1] - zeta[0]) / n[0] as f64,
            (eta[1] - eta[0]) / n[1] as f64,
        );
        let mut sum = 0.0;
        for a in 0..n[0] {
            for &(u, wu) in &nodes {
                let x = zeta[0] + (a as f64 + 0.5 + 0.5 * u) * dx;
                for b in 0..n[1] {
                    for &(v, wv) in &nodes {
                        let y = eta[0] + (b as f64 + 0.5 + 0.5 * v) * dy;
                        sum += wu * wv * body.point_source(x, y);
                    }
                }
            }
        }
        sum * 0.25 * dx * dy
    }

    #[test]
    fn self_cell_matches_polar_reference_from_low_to_high_peclet() {
        let (hx, hy) = (0.4e-3, 0.7e-3);
        for v in [1e-3, 0.1, 3.0, 30.0, 100.0] {
            let body = MovingHalfSpace::new(v, &steel()).unwrap();
            // Centred self cell and an off-centre rectangle around the origin.
            for (zeta, eta) in [
                ([-0.5 * hx, 0.5 * hx], [-0.5 * hy, 0.5 * hy]),
                ([-0.3 * hx, 0.7 * hx], [-0.2 * hy, 0.8 * hy]),
            ] {
                let q = body.offset_rectangle(zeta, eta, 1e-16).unwrap();
                let reference = polar_reference(&body, zeta, eta);
                let rel = (q.value - reference).abs() / reference;
                assert!(
                    rel < 1e-6,
                    "v = {v}: {} vs polar {reference} (rel {rel:.2e})",
                    q.value
                );
            }
        }
    }

    #[test]
    fn steady_limit_is_the_rectangle_formula() {
        // p → 0: ∫∫ dA/r over a 2α × 2β rectangle centred on the field point = 4[α asinh(β/α) + β asinh(α/β)].
        let (alpha, beta) = (0.2e-3, 0.35e-3);
        let body = MovingHalfSpace::new(1e-9, &steel()).unwrap();
        let q = body
            .offset_rectangle([-alpha, alpha], [-beta, beta], 1e-18)
            .unwrap();
        let steady = 4.0 * quarter_steady(alpha, beta) / (2.0 * PI * 50.0);
        assert!(
            ((q.value - steady) / steady).abs() < 1e-6,
            "{} vs {steady}",
            q.value
        );
    }

    #[test]
    fn distant_rectangles_match_brute_force_and_are_even_in_eta() {
        let (hx, hy) = (0.4e-3, 0.7e-3);
        // Moderate Péclet (p·h ≈ 4): the kernel is smooth on the sub-grid; all offset signs.
        let body = MovingHalfSpace::new(0.3, &steel()).unwrap();
        for (di, dj) in [
            (-3, 0),
            (-3, 2),
            (-3, -2),
            (2, 1),
            (2, -1),
            (0, 3),
            (0, -3),
            (-10, -1),
        ] {
            let zeta = [(di as f64 - 0.5) * hx, (di as f64 + 0.5) * hx];
            let eta = [(dj as f64 - 0.5) * hy, (dj as f64 + 0.5) * hy];
            let q = body.offset_rectangle(zeta, eta, 1e-16).unwrap();
            let reference = brute_force(&body, zeta, eta, [40, 40]);
            let rel = (q.value - reference).abs() / reference;
            assert!(
                rel < 1e-7,
                "offset ({di}, {dj}): {} vs {reference}",
                q.value
            );
        }
        // 30 m/s (p·h_x ≈ 420): the wake behind a source 4 mm upstream is ~0.1 mm wide; the brute-force
        // sub-grid resolves it with 2.3 µm sub-cells laterally.
        let body = MovingHalfSpace::new(30.0, &steel()).unwrap();
        for dj in [0, 1, -1] {
            let (di, eta0) = (-10, dj as f64 * hy);
            let zeta = [(di as f64 - 0.5) * hx, (di as f64 + 0.5) * hx];
            let eta = [eta0 - 0.5 * hy, eta0 + 0.5 * hy];
            let q = body.offset_rectangle(zeta, eta, 1e-18).unwrap();
            let reference = brute_force(&body, zeta, eta, [20, 300]);
            assert!(
                (q.value - reference).abs() < 1e-6 * reference + 1e-20,
                "offset ({di}, {dj}) at 30 m/s: {} vs {reference}",
                q.value
            );
        }
    }

    #[test]
    fn line_integral_is_the_closed_form_of_the_point_kernel() {
        // d/dζ[−E1(p(r + ζ))] = exp(−p(r + ζ))/r: compare with composite Gauss along ζ.
        let body = MovingHalfSpace::new(3.0, &steel()).unwrap();
        let eta = 0.2e-3;
        let (z1, z2) = (-2e-3, 0.5e-3);
        let exact = body.along_x(z1, z2, eta);
        let reference =
            integrate_adaptive(|z| body.point_source(z, eta), &[z1, 0.0, z2], 1e-14, 10_000).value
                * 2.0
                * PI
                * 50.0;
        assert!(
            ((exact - reference) / reference).abs() < 1e-10,
            "{exact} vs {reference}"
        );
    }

    #[test]
    fn table_matrix_uses_offsets_and_y_symmetry() {
        let grid = ContactGrid::new(5.879e-3, 10.54e-3, 9, 7);
        let body = MovingHalfSpace::new(30.0, &steel()).unwrap();
        let table = InfluenceTable::for_grid(&body, &grid).unwrap();
        let g = table.matrix(&grid).unwrap();
        for (k, field) in grid.cells.iter().enumerate() {
            for (l, source) in grid.cells.iter().enumerate() {
                let zeta = field.x - source.x - 0.5 * grid.hx;
                let eta = field.y - source.y;
                let direct = body
                    .offset_rectangle(
                        [zeta, zeta + grid.hx],
                        [eta - 0.5 * grid.hy, eta + 0.5 * grid.hy],
                        1e-14,
                    )
                    .unwrap()
                    .value;
                assert!((g[(k, l)] - direct).abs() <= 1e-9 * g[(k, k)], "({k}, {l})");
                // The mirror cell in y sees the same coefficient.
                let mirror = grid.cell_at(field.i as isize, (grid.ny - 1 - field.j) as isize);
                let mirror_src = grid.cell_at(source.i as isize, (grid.ny - 1 - source.j) as isize);
                if let (Some(mk), Some(ml)) = (mirror, mirror_src) {
                    assert!((g[(mk, ml)] - g[(k, l)]).abs() <= 1e-12 * g[(k, k)]);
                }
            }
        }
        assert_eq!(table.coefficient(9, 0), None);
        assert_eq!(table.coefficient(0, 1), table.coefficient(0, -1));
    }

    #[test]
    fn skipping_negligible_offsets_changes_no_coefficient() {
        // The default Hertz grid (docs/model.md §2, 30 × 30). Reference: every offset integrated by
        // offset_rectangle with a 1000 times tighter tolerance, whose own negligible cut (1e-6 of its
        // tolerance) lies at 1e-18 of the coefficient scale, far below the table's 1e-15.
        let (a, b) = (5.879e-3, 10.54e-3);
        let (n, hx, hy) = (30, 2.0 * a / 30.0, 2.0 * b / 30.0);
        for v in [0.1, 1.0, 30.0, 100.0] {
            let body = MovingHalfSpace::new(v, &steel()).unwrap();
            let table = InfluenceTable::new(&body, n, n, hx, hy).unwrap();
            let h = hx.min(hy);
            let scale = h / (1.0 + body.decay_rate() * h).sqrt() / (2.0 * PI * 50.0);
            let mut skipped = 0;
            for dj in 0..n as isize {
                for di in 1 - n as isize..n as isize {
                    let (zeta, eta) = (di as f64 * hx, dj as f64 * hy);
                    let reference = body
                        .offset_rectangle(
                            [zeta - 0.5 * hx, zeta + 0.5 * hx],
                            [eta - 0.5 * hy, eta + 0.5 * hy],
                            1e-12 * scale,
                        )
                        .unwrap()
                        .value;
                    let fast = table.coefficient(di, dj).unwrap();
                    if fast == 0.0 {
                        skipped += 1;
                        assert!(
                            reference <= 1e-15 * scale,
                            "v = {v}: skipped ({di}, {dj}) is {:.2e} of the scale",
                            reference / scale
                        );
                    } else {
                        assert!(
                            (fast - reference).abs() <= 1e-9 * scale,
                            "v = {v}: ({di}, {dj}) {fast} vs {reference}"
                        );
                    }
                }
            }
            // Upstream offsets (half the table) and the lateral ones outside the wake are skipped.
            let expected = if v < 1.0 { 800 } else { 1500 };
            assert!(
                skipped > expected,
                "v = {v}: only {skipped} offsets skipped"
            );
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(MovingHalfSpace::new(0.0, &steel()).is_err());
        assert!(MovingHalfSpace::new(-1.0, &steel()).is_err());
        assert!(MovingHalfSpace::new(f64::NAN, &steel()).is_err());
        let bad = Material {
            conductivity: f64::NAN,
            ..steel()
        };
        assert!(MovingHalfSpace::new(1.0, &bad).is_err());
        let body = MovingHalfSpace::new(1.0, &steel()).unwrap();
        assert!(body.offset_rectangle([1.0, 0.0], [0.0, 1.0], 1e-9).is_err());
        assert!(
            body.offset_rectangle([0.0, f64::NAN], [0.0, 1.0], 1e-9)
                .is_err()
        );
        assert!(InfluenceTable::new(&body, 0, 3, 1e-3, 1e-3).is_err());
        assert!(InfluenceTable::new(&body, 3, 3, -1e-3, 1e-3).is_err());
        let table = InfluenceTable::new(&body, 3, 3, 1e-3, 1e-3).unwrap();
        assert!(table.matrix(&ContactGrid::new(1e-3, 1e-3, 4, 3)).is_err());
    }
}
