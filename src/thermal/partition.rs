//! Heat partition between wheel and rail and the resulting surface temperature (paper §2.3, MODEL.md §7).
//!
//! The frictional power density q of each cell splits into q_w into the wheel and q_r = q − q_w into the
//! rail such that both surfaces have the same temperature in every cell: G_w·q_w = G_r·(q − q_w), i.e.
//! (G_w + G_r)·q_w = G_r·q; the temperature rise over the bulk is G_w·q_w. The matrices depend only on
//! the grid and the two surface speeds, so (G_w + G_r) is factorised once (dense LU, partial pivoting).

use super::influence::{InfluenceTable, MovingHalfSpace};
use crate::contact::ContactGrid;
use crate::error::{Error, Result};
use crate::params::Material;
use faer::col::ColRef;
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{Col, Mat, MatRef};

/// Smallest admissible |pivot| of the LU factors relative to the largest.
const PIVOT_RATIO_MIN: f64 = 1e-13;

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
    /// Influence matrix of the wheel G_w [K·m²/W].
    wheel: Mat<f64>,
    /// Influence matrix of the rail G_r [K·m²/W].
    rail: Mat<f64>,
    /// LU factors of G_w + G_r.
    lu: PartialPivLu<f64>,
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
}

impl HeatModel {
    /// `v_wheel`, `v_rail`: surface speeds [m/s] of wheel and rail through the contact (both > 0; each
    /// body moves in −x of the contact frame), `material`: conductivity λ and diffusivity κ of both bodies.
    /// Builds G_w and G_r from the moving-source influence tables (MODEL.md §7) and factorises G_w + G_r.
    pub fn new(grid: &ContactGrid, v_wheel: f64, v_rail: f64, material: &Material) -> Result<Self> {
        if grid.is_empty() {
            return Err(Error::Numerical {
                stage: "thermal model",
                reason: "the contact grid has no active cell".to_string(),
            });
        }
        let wheel_table =
            InfluenceTable::for_grid(&MovingHalfSpace::new(v_wheel, material)?, grid)?;
        let rail_table = if v_rail == v_wheel {
            wheel_table.clone()
        } else {
            InfluenceTable::for_grid(&MovingHalfSpace::new(v_rail, material)?, grid)?
        };
        let wheel = wheel_table.matrix(grid)?;
        let rail = rail_table.matrix(grid)?;
        let lu = (&wheel + &rail).partial_piv_lu();
        let pivots = lu.U().diagonal().column_vector();
        let (min, max) = pivots.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), u| {
            (lo.min(u.abs()), hi.max(u.abs()))
        });
        if !(max.is_finite() && min > PIVOT_RATIO_MIN * max) {
            return Err(Error::Numerical {
                stage: "thermal partition",
                reason: format!("G_w + G_r is singular (pivots between {min:.3e} and {max:.3e})"),
            });
        }
        Ok(Self {
            wheel,
            rail,
            lu,
            quadrature_error: wheel_table
                .error_estimate()
                .max(rail_table.error_estimate()),
        })
    }

    /// Number of active cells N.
    pub fn len(&self) -> usize {
        self.wheel.nrows()
    }

    /// True if the model has no cell (never: [`HeatModel::new`] refuses an empty grid).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Influence matrix of `body` [K·m²/W]: entry (k, l) is the temperature rise of cell k per unit flux
    /// density on cell l.
    pub fn influence(&self, body: Body) -> MatRef<'_, f64> {
        match body {
            Body::Wheel => self.wheel.as_ref(),
            Body::Rail => self.rail.as_ref(),
        }
    }

    /// Largest estimated quadrature error of an influence coefficient [K·m²/W].
    pub fn quadrature_error(&self) -> f64 {
        self.quadrature_error
    }

    /// Checks a per-cell heat flux density: one finite value per cell.
    fn check_flux<'a>(&self, q: &'a [f64]) -> Result<ColRef<'a, f64>> {
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
        Ok(ColRef::from_slice(q))
    }

    /// Surface temperature rise of `body` if it took all of the heat flux density `q` [W/m²]: G·q [K].
    pub fn one_body_rise(&self, body: Body, q: &[f64]) -> Result<Vec<f64>> {
        let q = self.check_flux(q)?;
        Ok(to_vec(&(self.influence(body) * q)))
    }

    /// Heat partition and surface temperature rise for frictional power density `q` per cell [W/m²]:
    /// solves (G_w + G_r)·q_w = G_r·q, q_r = q − q_w, ΔT = G_w·q_w (paper §2.3, MODEL.md §7).
    pub fn solve(&self, q: &[f64]) -> Result<HeatSolution> {
        let q = self.check_flux(q)?;
        let q_wheel = self.lu.solve(&self.rail * q);
        let q_rail = q - &q_wheel;
        let wheel_rise = &self.wheel * &q_wheel;
        let rail_rise = &self.rail * &q_rail;
        let mismatch = (&wheel_rise - &rail_rise)
            .iter()
            .fold(0.0_f64, |m, d| m.max(d.abs()));
        if !mismatch.is_finite() {
            return Err(Error::Numerical {
                stage: "thermal partition",
                reason: "non-finite heat partition".to_string(),
            });
        }
        Ok(HeatSolution {
            temperature_rise: to_vec(&wheel_rise),
            q_wheel: to_vec(&q_wheel),
            q_rail: to_vec(&q_rail),
            mismatch,
        })
    }
}

/// Copies a faer column into a Vec.
fn to_vec(col: &Col<f64>) -> Vec<f64> {
    col.iter().copied().collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn steel() -> Material {
        Material::default()
    }

    /// The project's default Hertz ellipse (MODEL.md §2).
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

    /// 1-D high-Péclet strip solution (MODEL.md §7) with all heat into one body:
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
        // T_max = q0·sqrt(a)·I/(β_e·sqrt(πV)), all heat into one body (MODEL.md §7).
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
    }
}
