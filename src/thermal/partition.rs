//! Heat partition between wheel and rail and the resulting surface temperature (paper §2.3, docs/model.md §7).
//!
//! The frictional power density q of each cell splits into q_w into the wheel and q_r = q − q_w into the
//! rail such that both surfaces have the same temperature in every cell: G_w·q_w = G_r·(q − q_w), i.e.
//! (G_w + G_r)·q_w = G_r·q; the temperature rise over the bulk is G_w·q_w. The influence matrices are
//! never formed: each is a convolution with an offset table ([`OffsetKernel`]), and the partition is
//! solved by GMRES ([`gmres`]) preconditioned with the exact strip-by-strip inverse of G_w + G_r
//! ([`StripSolver`]), started from the one-dimensional high-Péclet partition or from a previous solution.

use super::convolution::{OffsetKernel, StripLayout, StripSolver};
use super::influence::{InfluenceTable, MovingHalfSpace};
use super::krylov::{GmresSettings, gmres};
use super::lattice::{RecentNodes, interpolated_table_with};
use crate::contact::ContactGrid;
use crate::error::{Error, Result, Stage};
use crate::params::Material;

/// GMRES limits of the partition solve: relative residual 1e-12 of G_r·q.
const SETTINGS: GmresSettings = GmresSettings {
    tolerance: 1e-12,
    restart: 60,
    max_iterations: 600,
};

/// Which body of the contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Body {
    /// The wheel (surface speed v_w,x).
    Wheel,
    /// The rail (surface speed v_r,x).
    Rail,
}

/// Precomputed heat model for one grid and one pair of surface speeds.
#[derive(Debug, Clone)]
pub struct HeatModel {
    /// The grid's strips.
    layout: StripLayout,
    /// Offset kernel of the wheel G_w [K·m²/W].
    wheel: OffsetKernel,
    /// Offset kernel of the rail G_r [K·m²/W].
    rail: OffsetKernel,
    /// G_w + G_r [K·m²/W].
    sum: OffsetKernel,
    /// Strip-by-strip inverse of G_w + G_r (the preconditioner).
    strips: StripSolver,
    /// One-dimensional high-Péclet wheel share sqrt(v_w)/(sqrt(v_w) + sqrt(v_r)) (docs/model.md §7).
    share: f64,
    /// Largest estimated quadrature error of an influence coefficient [K·m²/W].
    quadrature_error: f64,
}

/// Heat partition and surface temperature for one heat source distribution.
#[derive(Debug, Clone, PartialEq)]
pub struct HeatSolution {
    /// Surface temperature rise over the bulk temperature T0, per cell [K] (equal for both bodies).
    pub temperature_rise: Vec<f64>,
    /// Heat flux density into the wheel, per cell [W/m²].
    pub q_wheel: Vec<f64>,
    /// Heat flux density into the rail, per cell [W/m²] (q − q_wheel).
    pub q_rail: Vec<f64>,
    /// max over cells of |G_w·q_w − G_r·q_r|: how well the two surface temperatures agree [K].
    pub mismatch: f64,
    /// GMRES steps of the partition solve (0 if the starting guess already satisfied the tolerance).
    pub iterations: usize,
    /// Relative residual ‖G_r·q − (G_w + G_r)·q_w‖₂/‖G_r·q‖₂ of the returned q_w.
    pub residual: f64,
    /// True if the residual reached 1e-12; false means q_w is only the last iterate of an exhausted
    /// iteration budget and must not be used as a solution.
    pub converged: bool,
}

impl HeatModel {
    /// `v_wheel`, `v_rail`: surface speeds [m/s] of wheel and rail through the contact (both > 0; each
    /// body moves in −x of the contact frame), `material`: conductivity λ and diffusivity κ of both bodies.
    /// Tabulates the moving-source influence coefficients of both bodies (docs/model.md §7) and factorises the
    /// strip-diagonal part of G_w + G_r.
    pub fn new(grid: &ContactGrid, v_wheel: f64, v_rail: f64, material: &Material) -> Result<Self> {
        Self::with_tables(grid, v_wheel, v_rail, material, InfluenceTable::for_grid)
    }

    /// As [`HeatModel::new`] with the influence coefficients interpolated in the lattice of unit-cell
    /// tables ([`interpolated_table_with`], docs/model.md §7.2): each within
    /// [`super::lattice::INTERPOLATION_ERROR`] of the coefficient scale of the direct ones, and cheap
    /// whenever the process has made the lattice nodes around this grid's cell Péclet numbers and aspect
    /// before (the coupled solver's heat model).
    pub fn interpolated(
        grid: &ContactGrid,
        v_wheel: f64,
        v_rail: f64,
        material: &Material,
    ) -> Result<Self> {
        Self::interpolated_with(grid, v_wheel, v_rail, material, &mut RecentNodes::default())
    }

    /// [`Self::interpolated`] with the lattice nodes of `recent` (kept by the caller between heat models:
    /// the same model, bit for bit).
    pub fn interpolated_with(
        grid: &ContactGrid,
        v_wheel: f64,
        v_rail: f64,
        material: &Material,
        recent: &mut RecentNodes,
    ) -> Result<Self> {
        Self::with_tables(grid, v_wheel, v_rail, material, |body, grid| {
            interpolated_table_with(body, material, grid.nx, grid.ny, grid.hx, grid.hy, recent)
        })
    }

    /// The heat model with the influence tables `table` makes of each body on `grid`.
    fn with_tables(
        grid: &ContactGrid,
        v_wheel: f64,
        v_rail: f64,
        material: &Material,
        mut table: impl FnMut(&MovingHalfSpace, &ContactGrid) -> Result<InfluenceTable>,
    ) -> Result<Self> {
        if grid.is_empty() {
            return Err(Error::Numerical {
                stage: Stage::ThermalModel,
                reason: "the contact grid has no active cell".to_string(),
            });
        }
        let layout = StripLayout::new(grid)?;
        let wheel_table = table(&MovingHalfSpace::new(v_wheel, material)?, grid)?;
        let rail_table = if v_rail == v_wheel {
            wheel_table.clone()
        } else {
            table(&MovingHalfSpace::new(v_rail, material)?, grid)?
        };
        let sum = OffsetKernel::sum(&layout, &[&wheel_table, &rail_table])?;
        let strips = StripSolver::new(&sum, &layout)?;
        Ok(Self {
            wheel: OffsetKernel::sum(&layout, &[&wheel_table])?,
            rail: OffsetKernel::sum(&layout, &[&rail_table])?,
            sum,
            strips,
            layout,
            share: v_wheel.sqrt() / (v_wheel.sqrt() + v_rail.sqrt()),
            quadrature_error: wheel_table
                .error_estimate()
                .max(rail_table.error_estimate()),
        })
    }

    /// Number of active cells N.
    pub fn len(&self) -> usize {
        self.layout.len()
    }

    /// True if the model has no cell (never: [`HeatModel::new`] refuses an empty grid).
    pub fn is_empty(&self) -> bool {
        self.layout.is_empty()
    }

    /// Largest estimated quadrature error of an influence coefficient [K·m²/W].
    pub fn quadrature_error(&self) -> f64 {
        self.quadrature_error
    }

    /// Offset kernel of `body`.
    fn kernel(&self, body: Body) -> &OffsetKernel {
        match body {
            Body::Wheel => &self.wheel,
            Body::Rail => &self.rail,
        }
    }

    /// Checks a per-cell heat flux density: one finite value per cell.
    fn check_flux(&self, q: &[f64]) -> Result<()> {
        if q.len() != self.len() {
            return Err(Error::out_of_range(
                "heat flux length",
                q.len() as f64,
                &format!("one value per active cell ({})", self.len()),
            ));
        }
        if let Some((k, v)) = q.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::out_of_range(
                &format!("heat flux of cell {k}"),
                *v,
                "finite W/m²",
            ));
        }
        Ok(())
    }

    /// Surface temperature rise of `body` if it took all of the heat flux density `q` [W/m²]: G·q [K].
    pub fn one_body_rise(&self, body: Body, q: &[f64]) -> Result<Vec<f64>> {
        self.check_flux(q)?;
        let mut rise = vec![0.0; q.len()];
        self.kernel(body).apply(&self.layout, q, &mut rise);
        Ok(rise)
    }

    /// Heat partition and surface temperature rise for frictional power density `q` per cell [W/m²]:
    /// solves (G_w + G_r)·q_w = G_r·q, q_r = q − q_w, ΔT = G_w·q_w (paper §2.3, docs/model.md §7), starting
    /// from the one-dimensional high-Péclet partition q_w = q·sqrt(v_w)/(sqrt(v_w) + sqrt(v_r)).
    pub fn solve(&self, q: &[f64]) -> Result<HeatSolution> {
        self.check_flux(q)?;
        let guess = q.iter().map(|qk| self.share * qk).collect();
        self.partition(q, guess)
    }

    /// [`Self::solve`] warm-started from the solution `previous` for a nearby flux q_prev = q_w + q_r
    /// (an outer iteration's last): the first guess q_w,prev + s·(q − q_prev), s the one-dimensional
    /// share, leaves a residual of the order of the change in q.
    pub fn solve_from(&self, q: &[f64], previous: &HeatSolution) -> Result<HeatSolution> {
        self.check_flux(q)?;
        if previous.q_wheel.len() != q.len() || previous.q_rail.len() != q.len() {
            return Err(Error::out_of_range(
                "previous heat solution length",
                previous.q_wheel.len() as f64,
                &format!("one value per active cell ({})", self.len()),
            ));
        }
        let guess = q
            .iter()
            .zip(previous.q_wheel.iter().zip(&previous.q_rail))
            .map(|(qk, (w, r))| w + self.share * (qk - (w + r)))
            .collect();
        self.partition(q, guess)
    }

    /// GMRES on (G_w + G_r)·q_w = G_r·q from `q_wheel`; then ΔT = G_w·q_w and the mismatch from the final
    /// residual (G_w·q_w − G_r·q_r = (G_w + G_r)·q_w − G_r·q).
    fn partition(&self, q: &[f64], mut q_wheel: Vec<f64>) -> Result<HeatSolution> {
        let n = q.len();
        let mut rhs = vec![0.0; n];
        self.rail.apply(&self.layout, q, &mut rhs);
        let (report, residual) = gmres(
            |v, out| self.sum.apply(&self.layout, v, out),
            |v| self.strips.apply(&self.layout, v),
            &rhs,
            &mut q_wheel,
            SETTINGS,
        );
        let mut temperature_rise = vec![0.0; n];
        self.wheel
            .apply(&self.layout, &q_wheel, &mut temperature_rise);
        let mismatch = residual.iter().fold(0.0_f64, |m, r| m.max(r.abs()));
        if !(mismatch.is_finite() && temperature_rise.iter().all(|t| t.is_finite())) {
            return Err(Error::Numerical {
                stage: Stage::ThermalPartition,
                reason: "non-finite heat partition".to_string(),
            });
        }
        Ok(HeatSolution {
            temperature_rise,
            q_rail: q.iter().zip(&q_wheel).map(|(qk, w)| qk - w).collect(),
            q_wheel,
            mismatch,
            iterations: report.iterations,
            residual: report.residual,
            converged: report.converged,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn steel() -> Material {
        Material::default()
    }

    /// The project's default Hertz ellipse (docs/model.md §2).
    fn hertz_grid(n: usize) -> ContactGrid {
        ContactGrid::new(5.879e-3, 10.54e-3, n, n)
    }

    /// A single strip of length 2a whose width (60 mm) dwarfs the thermal wake (≲ 0.2 mm at 30 m/s).
    fn strip_grid(a: f64, nx: usize) -> ContactGrid {
        ContactGrid::new(a, 30e-3, nx, 1)
    }

    /// A smooth, non-uniform frictional power density over the ellipse [W/m²].
    fn smooth_flux(grid: &ContactGrid) -> Vec<f64> {
        grid.cells
            .iter()
            .map(|c| {
                1e9 * (1.0 - (c.x / grid.a).powi(2) - (c.y / grid.b).powi(2)) * (1.0 + c.x / grid.a)
            })
            .collect()
    }

    /// 1-D high-Péclet strip solution (docs/model.md §7) with all heat into one body:
    /// T(x) = 1/(β_e·sqrt(π·V))·∫_x^a q(x')/sqrt(x' − x) dx', with x' = x + t² removing the singularity.
    fn strip_reference(q: impl Fn(f64) -> f64, x: f64, a: f64, v: f64) -> f64 {
        let m = steel();
        let upper = (a - x).sqrt();
        let n = 20_000;
        let dt = upper / n as f64;
        let integral: f64 = (0..n)
            .map(|k| {
                let t = (k as f64 + 0.5) * dt;
                2.0 * q(x + t * t) * dt
            })
            .sum();
        integral / (m.effusivity() * (PI * v).sqrt())
    }

    #[test]
    fn identical_bodies_at_equal_speed_share_heat_equally() {
        for v in [30.0, 0.1] {
            let grid = hertz_grid(20);
            let model = HeatModel::new(&grid, v, v, &steel()).unwrap();
            let q = smooth_flux(&grid);
            let qmax = q.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            let s = model.solve(&q).unwrap();
            for (k, (&qk, (&qw, &qr))) in q.iter().zip(s.q_wheel.iter().zip(&s.q_rail)).enumerate()
            {
                assert!((qw - 0.5 * qk).abs() <= 1e-12 * qmax, "v = {v}, cell {k}");
                assert!((qr - 0.5 * qk).abs() <= 1e-12 * qmax, "v = {v}, cell {k}");
            }
            // The common temperature is that of one body taking half the heat.
            let half: Vec<f64> = q.iter().map(|x| 0.5 * x).collect();
            let one = model.one_body_rise(Body::Wheel, &half).unwrap();
            let tmax = one.iter().fold(0.0_f64, |m, x| m.max(*x));
            assert!(tmax > 0.0);
            for (t, o) in s.temperature_rise.iter().zip(&one) {
                assert!((t - o).abs() <= 1e-10 * tmax);
            }
            assert!(s.mismatch <= 1e-10 * tmax);
        }
    }

    #[test]
    fn high_peclet_strip_matches_the_one_dimensional_solution() {
        // Uniform q on a 12 mm strip at 30 m/s (V·a/(2κ) ≈ 6400), identical bodies: share ½.
        let (a, v, q0): (f64, f64, f64) = (6e-3, 30.0, 1e9);
        let grid = strip_grid(a, 60);
        let model = HeatModel::new(&grid, v, v, &steel()).unwrap();
        let s = model.solve(&vec![q0; grid.len()]).unwrap();
        for (c, t) in grid.cells.iter().zip(&s.temperature_rise) {
            let reference = 0.5 * strip_reference(|_| q0, c.x, a, v);
            assert!(
                ((t - reference) / reference).abs() < 0.01,
                "x = {}: {t} vs {reference}",
                c.x
            );
        }
        // Closed form of the trailing-edge maximum, all heat into one body: (2q/λ)·sqrt(2κl/(πV)).
        let m = steel();
        let closed = 2.0 * q0 / m.conductivity * (2.0 * m.diffusivity() * a / (PI * v)).sqrt();
        let edge = strip_reference(|_| q0, -a, a, v);
        assert!(
            ((edge - closed) / closed).abs() < 1e-6,
            "reference quadrature {edge} vs {closed}"
        );
    }

    #[test]
    fn unequal_speeds_share_heat_like_the_one_dimensional_theory() {
        // 1-D theory: equal temperatures everywhere need q_w/q = sqrt(v_w)/(sqrt(v_w) + sqrt(v_r)).
        let (a, v_w, v_r) = (6e-3, 40.0, 20.0);
        let grid = strip_grid(a, 40);
        let model = HeatModel::new(&grid, v_w, v_r, &steel()).unwrap();
        let q: Vec<f64> = grid
            .cells
            .iter()
            .map(|c| 1e9 * (1.0 - (c.x / a).powi(2)))
            .collect();
        let s = model.solve(&q).unwrap();
        let share = v_w.sqrt() / (v_w.sqrt() + v_r.sqrt());
        for (k, (qw, qk)) in s.q_wheel.iter().zip(&q).enumerate() {
            let got = qw / qk;
            assert!(
                (got - share).abs() < 0.01 * share,
                "cell {k}: share {got} vs {share}"
            );
        }
        let tmax = s.temperature_rise.iter().fold(0.0_f64, |m, x| m.max(*x));
        assert!(s.mismatch < 1e-9 * tmax);
    }

    #[test]
    fn peak_factors_converge_to_the_one_dimensional_values() {
        // T_max = q0·sqrt(a)·I/(β_e·sqrt(πV)), all heat into one body (docs/model.md §7).
        let (a, v, q0): (f64, f64, f64) = (6e-3, 30.0, 1e9);
        let m = steel();
        let unit = q0 * a.sqrt() / (m.effusivity() * (PI * v).sqrt());
        type Shape = fn(f64) -> f64;
        let shapes: [(&str, Shape, f64); 3] = [
            ("elliptic", |s| (1.0 - s * s).max(0.0).sqrt(), 2.1883),
            ("parabolic", |s| 1.0 - s * s, 1.9596),
            ("uniform", |_| 1.0, 2.828),
        ];
        for (name, shape, factor) in shapes {
            let mut errors = Vec::new();
            for nx in [20, 40, 80] {
                let grid = strip_grid(a, nx);
                let model = HeatModel::new(&grid, v, v, &m).unwrap();
                let q: Vec<f64> = grid.cells.iter().map(|c| q0 * shape(c.x / a)).collect();
                let t = model.one_body_rise(Body::Rail, &q).unwrap();
                let peak = t.iter().fold(0.0_f64, |p, x| p.max(*x)) / unit;
                errors.push((peak - factor).abs() / factor);
            }
            assert!(errors[2] < errors[0], "{name}: no convergence {errors:?}");
            assert!(errors[2] < 0.01, "{name}: peak factor error {errors:?}");
        }
        // The elliptic peak sits at x ≈ −0.652a.
        let grid = strip_grid(a, 80);
        let model = HeatModel::new(&grid, v, v, &m).unwrap();
        let q: Vec<f64> = grid
            .cells
            .iter()
            .map(|c| q0 * (1.0 - (c.x / a).powi(2)).sqrt())
            .collect();
        let t = model.one_body_rise(Body::Wheel, &q).unwrap();
        let k = (0..t.len()).max_by(|&i, &j| t[i].total_cmp(&t[j])).unwrap();
        assert!(
            (grid.cells[k].x / a + 0.652).abs() < 0.03,
            "peak at {}",
            grid.cells[k].x / a
        );
    }

    #[test]
    fn low_speed_tends_to_the_steady_half_space() {
        // Uniform q over the (staircase) ellipse, field point at the centre cell. Steady reference:
        // Σ over cells of ∫∫ dA/r (corner formula) / (2πλ); first-order correction −p·A/(2πλ) (the ∫X/r
        // term vanishes by the x-symmetry of the cell set).
        let grid = hertz_grid(15);
        let m = steel();
        let corner = |x: f64, y: f64| {
            let (ax, ay) = (x.abs(), y.abs());
            if ax == 0.0 || ay == 0.0 {
                0.0
            } else {
                (ax * (ay / ax).asinh() + ay * (ax / ay).asinh()) * x.signum() * y.signum()
            }
        };
        let steady: f64 = grid
            .cells
            .iter()
            .map(|c| {
                let (x1, x2) = (c.x - 0.5 * grid.hx, c.x + 0.5 * grid.hx);
                let (y1, y2) = (c.y - 0.5 * grid.hy, c.y + 0.5 * grid.hy);
                corner(x2, y2) - corner(x1, y2) - corner(x2, y1) + corner(x1, y1)
            })
            .sum::<f64>()
            / (2.0 * PI * m.conductivity);
        let centre = grid.cell_at(7, 7).unwrap();
        let area = grid.len() as f64 * grid.cell_area();
        let mut errors = Vec::new();
        for v in [1e-3, 1e-5, 1e-7] {
            let model = HeatModel::new(&grid, v, v, &m).unwrap();
            let t = model
                .one_body_rise(Body::Wheel, &vec![1.0; grid.len()])
                .unwrap()[centre];
            errors.push((steady - t) / steady);
            let p = v / (2.0 * m.diffusivity());
            if v == 1e-5 {
                let slope = (steady - t) * 2.0 * PI * m.conductivity / (p * area);
                assert!((slope - 1.0).abs() < 0.01, "first-order slope {slope}");
            }
        }
        assert!(errors.iter().all(|e| *e > 0.0), "{errors:?}");
        assert!(
            errors[2] < 1e-4 && errors[2] < errors[1] && errors[1] < errors[0],
            "{errors:?}"
        );
    }

    #[test]
    fn bad_input_is_an_error() {
        let grid = hertz_grid(8);
        let m = steel();
        for (vw, vr) in [
            (0.0, 1.0),
            (1.0, -1.0),
            (f64::NAN, 1.0),
            (1.0, f64::INFINITY),
        ] {
            assert!(HeatModel::new(&grid, vw, vr, &m).is_err(), "({vw}, {vr})");
        }
        let model = HeatModel::new(&grid, 30.0, 29.0, &m).unwrap();
        assert!(model.solve(&vec![1.0; grid.len() + 1]).is_err());
        let mut q = vec![1.0; grid.len()];
        q[3] = f64::NAN;
        assert!(model.solve(&q).is_err());
        assert!(model.one_body_rise(Body::Rail, &q).is_err());
        assert!(model.solve(&[]).is_err());
        let good = model.solve(&vec![1e9; grid.len()]).unwrap();
        let short = HeatSolution {
            q_wheel: vec![0.0; 3],
            ..good.clone()
        };
        assert!(model.solve_from(&vec![1e9; grid.len()], &short).is_err());
        assert!(model.solve_from(&q, &good).is_err());
    }

    /// Frictional power concentrated in the trailing half, as under partial slip [W/m²].
    fn trailing_flux(grid: &ContactGrid) -> Vec<f64> {
        grid.cells
            .iter()
            .map(|c| {
                let p = (1.0 - (c.x / grid.a).powi(2) - (c.y / grid.b).powi(2)).max(0.0);
                1e9 * p.sqrt() * (-c.x / grid.a).max(0.0)
            })
            .collect()
    }

    fn max_abs(v: impl IntoIterator<Item = f64>) -> f64 {
        v.into_iter().fold(0.0_f64, |m, x| m.max(x.abs()))
    }

    /// The slow reference path: dense G_w, G_r from the same influence tables and a dense LU of G_w + G_r
    /// (the implementation before the convolution and GMRES): (q_w, ΔT).
    fn dense_reference(grid: &ContactGrid, vw: f64, vr: f64, q: &[f64]) -> (Vec<f64>, Vec<f64>) {
        use faer::linalg::solvers::Solve;
        let table = |v| InfluenceTable::for_grid(&MovingHalfSpace::new(v, &steel()).unwrap(), grid);
        let gw = table(vw).unwrap().matrix(grid).unwrap();
        let gr = table(vr).unwrap().matrix(grid).unwrap();
        let q = faer::ColRef::from_slice(q);
        let q_wheel = (&gw + &gr).partial_piv_lu().solve(&gr * q);
        let rise = &gw * &q_wheel;
        (
            q_wheel.iter().copied().collect(),
            rise.iter().copied().collect(),
        )
    }

    /// The solver's heat model with interpolated influence coefficients (docs/model.md §7.2, each within
    /// 2e-5 of the coefficient scale) gives the partition and the temperature of the direct tables to
    /// 1e-5 of their largest values, at speeds from near standstill to 100 m/s and on coarse and
    /// default grids.
    #[test]
    fn interpolated_heat_model_matches_the_direct_one() {
        for n in [7, 30] {
            let grid = hertz_grid(n);
            for (v, xi) in [(0.1, 0.02), (25.0, 0.004), (100.0, -0.1)] {
                let (vw, vr) = (v * (1.0 + 0.5 * xi), v * (1.0 - 0.5 * xi));
                let direct = HeatModel::new(&grid, vw, vr, &steel()).unwrap();
                let interpolated = HeatModel::interpolated(&grid, vw, vr, &steel()).unwrap();
                let q = smooth_flux(&grid);
                let (a, b) = (direct.solve(&q).unwrap(), interpolated.solve(&q).unwrap());
                let (qmax, tmax) = (
                    max_abs(a.q_wheel.clone()),
                    max_abs(a.temperature_rise.clone()),
                );
                let dq = max_abs(a.q_wheel.iter().zip(&b.q_wheel).map(|(x, y)| x - y));
                let dt = max_abs(
                    a.temperature_rise
                        .iter()
                        .zip(&b.temperature_rise)
                        .map(|(x, y)| x - y),
                );
                assert!(
                    dq <= 1e-5 * qmax,
                    "{n}x{n}, V = {v}: q_w off by {:.2e}",
                    dq / qmax
                );
                assert!(
                    dt <= 1e-5 * tmax,
                    "{n}x{n}, V = {v}: ΔT off by {:.2e}",
                    dt / tmax
                );
                assert!(b.converged && interpolated.quadrature_error() > direct.quadrature_error());
            }
        }
    }

    #[test]
    fn fast_partition_matches_the_dense_reference() {
        // Default Hertz grid (30 × 30, docs/model.md §2), v_w,r = V(1 ± ξ/2) (docs/model.md §1).
        let grid = hertz_grid(30);
        for v in [0.1, 1.0, 30.0, 100.0] {
            for xi in [0.0, 0.02, -0.1] {
                let (vw, vr) = (v * (1.0 + 0.5 * xi), v * (1.0 - 0.5 * xi));
                let model = HeatModel::new(&grid, vw, vr, &steel()).unwrap();
                // smooth, trailing (partial slip), and lopsided in y (as with spin)
                let lopsided: Vec<f64> = (grid.cells.iter().zip(smooth_flux(&grid)))
                    .map(|(c, q)| q * (1.0 + 0.8 * c.y / grid.b))
                    .collect();
                for q in [smooth_flux(&grid), trailing_flux(&grid), lopsided] {
                    let s = model.solve(&q).unwrap();
                    assert!(
                        s.converged && s.residual <= 1e-12,
                        "V = {v}, ξ = {xi}: {} iterations, residual {:.2e}",
                        s.iterations,
                        s.residual
                    );
                    let (q_wheel, rise) = dense_reference(&grid, vw, vr, &q);
                    let (qmax, tmax) = (max_abs(q_wheel.clone()), max_abs(rise.clone()));
                    let dq = max_abs(s.q_wheel.iter().zip(&q_wheel).map(|(a, b)| a - b));
                    let dt = max_abs(s.temperature_rise.iter().zip(&rise).map(|(a, b)| a - b));
                    assert!(dq <= 1e-9 * qmax, "V = {v}, ξ = {xi}: q_w off by {dq:.2e}");
                    assert!(dt <= 1e-9 * tmax, "V = {v}, ξ = {xi}: ΔT off by {dt:.2e}");
                }
            }
        }
    }

    #[test]
    fn solution_reports_its_residual_and_warm_starts() {
        let grid = hertz_grid(30);
        for v in [0.1, 30.0] {
            let model = HeatModel::new(&grid, v * 1.05, v * 0.95, &steel()).unwrap();
            let q0 = trailing_flux(&grid);
            let cold0 = model.solve(&q0).unwrap();
            assert!(cold0.converged && cold0.iterations > 0);
            // The mismatch is the temperature difference of the two bodies, recomputed here.
            let wheel = model.one_body_rise(Body::Wheel, &cold0.q_wheel).unwrap();
            let rail = model.one_body_rise(Body::Rail, &cold0.q_rail).unwrap();
            let mismatch = max_abs(wheel.iter().zip(&rail).map(|(w, r)| w - r));
            let tmax = max_abs(cold0.temperature_rise.clone());
            assert!((mismatch - cold0.mismatch).abs() <= 1e-12 * tmax);
            assert!(cold0.mismatch <= 1e-10 * tmax, "{}", cold0.mismatch);
            // A nearby flux (the next outer iteration): same solution, fewer iterations.
            let q1: Vec<f64> = q0
                .iter()
                .zip(smooth_flux(&grid))
                .map(|(a, b)| a + 1e-3 * b)
                .collect();
            let cold = model.solve(&q1).unwrap();
            let warm = model.solve_from(&q1, &cold0).unwrap();
            assert!(
                warm.converged
                    && warm.iterations <= cold.iterations
                    && (v > 1.0 || warm.iterations < cold.iterations),
                "v = {v}: {} warm vs {} cold iterations",
                warm.iterations,
                cold.iterations
            );
            let qmax = max_abs(cold.q_wheel.clone());
            let dq = max_abs(warm.q_wheel.iter().zip(&cold.q_wheel).map(|(a, b)| a - b));
            assert!(dq <= 1e-10 * qmax, "v = {v}: {dq:.2e}");
        }
    }
}
