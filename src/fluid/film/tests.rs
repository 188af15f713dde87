use super::*;
use crate::fluid::base_height;
use crate::params::{OperatingPoint, Params};
use crate::solver::{normal_contact, surface_speeds};

/// Everything a [`FilmProblem`] borrows, for one operating point with the default parameters and grid.
/// The temperature rises linearly from the leading to the trailing edge of each strip, by 2000 K·|ξ|
/// (about what frictional heating gives: 20 K at ξ = 0.01), so that the materials differ per cell.
struct Case {
    grid: ContactGrid,
    p_n: Vec<f64>,
    mats: Vec<MaterialState>,
    dry_d: Vec<f64>,
    dry_area: Vec<f64>,
    dry_load: Vec<f64>,
    micro: Microcontact,
    base_height: f64,
    flow_resistance: f64,
    rail_speed: f64,
    mean_speed: f64,
    inlet_film: f64,
}

impl Case {
    fn new(pt: &OperatingPoint) -> Self {
        Self::heated(pt, 2000.0 * pt.creepage_x.abs())
    }

    /// As [`Case::new`] with a trailing-edge temperature rise `rise` [K].
    fn heated(pt: &OperatingPoint, rise: f64) -> Self {
        Self::of(&Params::default(), pt, rise)
    }

    /// As [`Case::heated`] with the parameters `params`.
    fn of(params: &Params, pt: &OperatingPoint, rise: f64) -> Self {
        let hertz = normal_contact(params, pt.normal_force).unwrap();
        let grid = ContactGrid::for_contact(&hertz, params.grid.nx, params.grid.ny);
        let p_n: Vec<f64> = grid
            .cells
            .iter()
            .map(|c| hertz.parabolic_pressure(c.x, c.y))
            .collect();
        let mut mats = Vec::new();
        for s in &grid.strips {
            for c in &grid.cells[s.cells.clone()] {
                let along = (s.half_length - c.x) / (2.0 * s.half_length);
                mats.push(
                    params
                        .material
                        .at(params.material.bulk_temperature + rise * along),
                );
            }
        }
        let micro = Microcontact::new(&params.roughness).unwrap();
        let dry: Vec<_> = p_n
            .iter()
            .zip(&mats)
            .map(|(p, m)| micro.separation_for_load(*p, m).unwrap().state)
            .collect();
        let (v_w, v_r) = surface_speeds(pt);
        Self {
            p_n,
            mats,
            dry_d: dry.iter().map(|s| s.separation).collect(),
            dry_area: dry.iter().map(|s| s.area_fraction).collect(),
            dry_load: dry.iter().map(|s| s.load).collect(),
            base_height: base_height(micro.surface().z_s, params.fluid.psi_b),
            micro,
            grid,
            flow_resistance: params.fluid.flow_resistance,
            rail_speed: v_r,
            mean_speed: 0.5 * (v_w + v_r),
            inlet_film: pt.wetness * params.fluid.h_f_max,
        }
    }

    fn problem(&self, tolerance: f64, max_iterations: usize) -> FilmProblem<'_> {
        FilmProblem {
            grid: &self.grid,
            nominal_pressure: &self.p_n,
            materials: &self.mats,
            dry_separation: &self.dry_d,
            dry_area_fraction: &self.dry_area,
            dry_metal_load: &self.dry_load,
            micro: &self.micro,
            base_height: self.base_height,
            flow_resistance: self.flow_resistance,
            rail_speed: self.rail_speed,
            mean_speed: self.mean_speed,
            inlet_film: self.inlet_film,
            tolerance,
            max_iterations,
        }
    }
}

fn point(xi: f64, speed: f64, wetness: f64, normal_force: f64) -> OperatingPoint {
    OperatingPoint {
        creepage_x: xi,
        speed,
        wetness,
        normal_force,
        ..Default::default()
    }
}

/// Largest difference of two films: separation in z_s, pressure in the peak nominal pressure, fluid
/// height in h_f0.
fn distance(a: &FilmSolution, b: &FilmSolution, c: &Case) -> f64 {
    let z_s = c.micro.surface().z_s;
    let p0 = c.p_n.iter().cloned().fold(0.0, f64::max);
    let mut m: f64 = 0.0;
    for k in 0..c.grid.len() {
        m = m
            .max((a.separation[k] - b.separation[k]).abs() / z_s)
            .max((a.fluid_pressure[k] - b.fluid_pressure[k]).abs() / p0)
            .max((a.fluid_height[k] - b.fluid_height[k]).abs() / c.inlet_film);
    }
    m
}

/// The film equations checked from the solution fields: complementarity, compatibility P17 and the
/// global volume balance (inflow = outflow + expelled, the sum of all cell balances).
fn check_equations(sol: &FilmSolution, c: &Case) {
    for k in 0..c.grid.len() {
        let (p, lf, lv) = (
            sol.fluid_pressure[k],
            sol.fluid_height[k],
            sol.void_height[k],
        );
        assert!(p >= 0.0 && lf >= 0.0 && lf <= lv, "cell {k}: {p} {lf} {lv}");
        if p > 0.0 {
            assert!(lf == lv, "a pressurised cell is full (cell {k})");
        } else {
            assert_eq!(sol.separation[k], c.dry_d[k]);
        }
        let lhs = p * (1.0 - sol.area_fraction[k]) + sol.metal_load[k];
        assert!(
            (lhs - c.p_n[k]).abs() <= 1e-9 * c.p_n[k],
            "P17 in cell {k}: {lhs} vs {}",
            c.p_n[k]
        );
    }
    let balance = sol.inflow - sol.outflow - sol.expelled;
    assert!(
        balance.abs() <= 1e-9 * sol.inflow,
        "volume balance {balance:e} of {:e}",
        sol.inflow
    );
    assert!(sol.balance_residual <= 1e-9, "{}", sol.balance_residual);
}

#[test]
fn newton_reaches_the_gauss_seidel_film() {
    let cases = [
        point(0.01, 30.0, 1.0, 100e3),
        point(0.01, 30.0, 0.3, 100e3),
        point(0.0, 30.0, 1.0, 100e3),
        point(0.05, 30.0, 1.0, 100e3),
        point(0.01, 1.0, 1.0, 100e3),
        point(0.01, 100.0, 1.0, 100e3),
        point(0.01, 30.0, 1.0, 10e3),
        point(0.01, 30.0, 1.0, 200e3),
    ];
    for pt in cases {
        let c = Case::new(&pt);
        let newton = solve_film(&c.problem(1e-10, 100), None).unwrap();
        // converged by Newton alone, without the Gauss–Seidel fallback
        assert!(
            newton.converged && newton.iterations < NEWTON_LIMIT,
            "{pt:?}: {} iterations",
            newton.iterations
        );
        check_equations(&newton, &c);
        let pr = c.problem(1e-12, 100_000);
        let reference = System::new(&pr)
            .unwrap()
            .gauss_seidel(vec![-1.0; c.grid.len()], 100_000)
            .unwrap();
        assert!(reference.converged, "reference at {pt:?}");
        let dist = distance(&newton, &reference, &c);
        assert!(dist < 1e-8, "{pt:?}: films differ by {dist:e}");
        // the fluid carries part of the load somewhere, and many times fewer iterations than sweeps
        assert!(newton.fluid_pressure.iter().any(|p| *p > 0.0));
        assert!(
            newton.iterations * 5 < reference.iterations,
            "{pt:?}: {} Newton iterations, {} sweeps",
            newton.iterations,
            reference.iterations
        );
    }
}

#[test]
fn warm_start_from_a_neighbouring_temperature_field_converges_to_the_cold_solution() {
    let pt = point(0.01, 30.0, 1.0, 100e3);
    let before = Case::heated(&pt, 10.0);
    let after = Case::heated(&pt, 20.0);
    let old = solve_film(&before.problem(1e-10, 100), None).unwrap();
    let cold = solve_film(&after.problem(1e-10, 100), None).unwrap();
    let warm = solve_film(&after.problem(1e-10, 100), Some(old.as_start())).unwrap();
    assert!(cold.converged && warm.converged);
    assert!(
        distance(&old, &cold, &after) > 1e-6,
        "the problems must differ"
    );
    assert!(distance(&warm, &cold, &after) < 1e-9);
    assert!(warm.iterations < cold.iterations);
    // restarting from the solution itself: one step, no change
    let again = solve_film(&after.problem(1e-10, 100), Some(warm.as_start())).unwrap();
    assert_eq!(again.iterations, 1);
    assert!(again.converged && distance(&again, &warm, &after) < 1e-10);
}

#[test]
fn an_unconverged_solve_says_so() {
    let c = Case::new(&point(0.01, 30.0, 1.0, 100e3));
    let sol = solve_film(&c.problem(1e-10, 2), None).unwrap();
    assert_eq!(sol.iterations, 2);
    assert!(!sol.converged && sol.residual > 1e-10);
}

/// The transport reconstruction at a face is second-order: exact for a film that rises linearly along
/// the strip, its error falling as h² for curved films that rise or fall (first-order upwind's falls as
/// h), a constant film carried unchanged; the face value stays positive and grows with the cell's own
/// height however steeply the film falls, and the inverse used by the Gauss–Seidel cell solve inverts it.
#[test]
fn face_reconstruction_is_second_order_positive_and_invertible() {
    // the film moves towards −x: the upstream neighbour of the cell at x is at x + h, the face at x − h/2
    let error = |l: &dyn Fn(f64) -> f64, h: f64| {
        let x = 1e-3;
        (face_height(l(x), Some(l(x + h))).0 - l(x - 0.5 * h)).abs()
    };
    let linear = |x: f64| 2e-6 - 3e-4 * x;
    assert!(error(&linear, 2e-4) < 1e-15);
    assert!((face_height(1e-6, Some(1e-6)).0 - 1e-6).abs() < 1e-21);
    let falling = |x: f64| 1e-6 * (x / 2e-3).exp();
    let rising = |x: f64| 1e-6 * (-x / 2e-3).exp();
    for film in [&falling as &dyn Fn(f64) -> f64, &rising] {
        let ratio = error(film, 5e-5) / error(film, 2.5e-5);
        assert!((3.6..4.4).contains(&ratio), "{ratio}");
    }
    for ratio in [0.0, 0.3, 1.0, 2.0, 3.0, 10.0, 100.0] {
        let (l, l_up) = (1e-6, ratio * 1e-6);
        let (v, dl, _) = face_height(l, Some(l_up));
        assert!(v > 0.0 && dl > 0.0, "ratio {ratio}");
        assert!(
            (face_height_inverse(v, Some(l_up)).unwrap() - l).abs() < 1e-18,
            "ratio {ratio}"
        );
    }
    assert_eq!(face_height_inverse(3e-6, None).unwrap(), 3e-6);
}

/// A flooded inlet fills the gap at the contact edge and the rest of the rail's film is pushed aside:
/// the film does not depend on the surplus (h_f0 = 20 µm or 15 µm, leading cells' voids up to 11 µm), and
/// taken in plus rejected is the rail's film v_r·h_y·h_f0 per strip. A thin film (0.1 µm) enters
/// completely.
#[test]
fn a_flooded_inlet_takes_in_what_the_gap_holds() {
    let solved = |w: f64| {
        let c = Case::new(&point(0.01, 30.0, w, 100e3));
        let sol = solve_film(&c.problem(1e-10, 100), None).unwrap();
        assert!(sol.converged, "w = {w}");
        check_equations(&sol, &c);
        let per_strip = c.rail_speed * c.grid.hy * c.inlet_film;
        let supply = per_strip * c.grid.strips.len() as f64;
        assert!((sol.inflow + sol.rejected - supply).abs() <= 1e-12 * supply);
        // whether every leading cell's void holds less than the rail brings
        let flooded = c
            .grid
            .strips
            .iter()
            .all(|s| c.mean_speed * c.grid.hy * sol.void_height[s.cells.start] < per_strip);
        (c, sol, supply, flooded)
    };
    let (c, full, supply, flooded) = solved(1.0);
    let (_, less, _, also) = solved(0.75);
    assert!(flooded && also);
    assert!(full.rejected > 0.5 * supply);
    assert!(distance(&full, &less, &c) < 1e-8);
    let (_, thin, supply, flooded) = solved(0.005);
    assert!(!flooded && thin.rejected == 0.0);
    assert!((thin.inflow - supply).abs() <= 1e-12 * supply);
}

/// Newton's film, converged without the Gauss–Seidel fallback, checked against the equations and
/// against the Gauss–Seidel reference (to 1e-8).
fn newton_film_matching_the_reference(c: &Case) -> FilmSolution {
    let newton = solve_film(&c.problem(1e-10, 100), None).unwrap();
    assert!(
        newton.converged && newton.iterations < NEWTON_LIMIT,
        "{} iterations, residual {:e}",
        newton.iterations,
        newton.residual
    );
    check_equations(&newton, c);
    let pr = c.problem(1e-12, 100_000);
    let reference = System::new(&pr)
        .unwrap()
        .gauss_seidel(vec![-1.0; c.grid.len()], 100_000)
        .unwrap();
    assert!(reference.converged);
    let dist = distance(&newton, &reference, c);
    assert!(dist < 1e-8, "films differ by {dist:e}");
    newton
}

/// A small contact at p0 = 2.5 GPa (10 kN on a = b = 1.38 mm): GW's metallic area exceeds the nominal
/// area at the centre (A_m/A_n(d_dry) up to 1.5, d_dry below d_b), where P17 has no solution with
/// p_f ≥ 0 just above d_dry. Those cells hold no fluid and take none in; the cells around them take in
/// less as A_m/A_n(d_dry) nears 1; what they do not take in is pushed aside (expelled). The film
/// solves (it failed with "no separation balances the cell" before, docs/model.md §8.5).
#[test]
fn cells_covered_by_metal_take_in_no_film() {
    let mut params = Params::default();
    params.geometry.semi_axes = Some([1.381976597885342e-3; 2]);
    for (xi, w) in [(1e-6, 0.3), (0.01, 1.0), (0.02, 0.05)] {
        let c = Case::of(&params, &point(xi, 30.0, w, 10e3), 2000.0 * xi);
        let covered: Vec<usize> = (0..c.grid.len())
            .filter(|k| c.dry_area[*k] >= 1.0)
            .collect();
        assert!(covered.len() > 100, "{} covered cells", covered.len());
        let sol = newton_film_matching_the_reference(&c);
        for &k in &covered {
            assert_eq!(sol.fluid_height[k], 0.0, "cell {k} holds fluid");
            assert_eq!(sol.fluid_pressure[k], 0.0);
        }
        // fluid reaches the covered cells' fronts and is pushed aside there
        let pr = c.problem(1e-10, 100);
        let system = System::new(&pr).unwrap();
        let pushed: f64 = (0..c.grid.len())
            .filter(|k| system.intake(*k) < 1.0)
            .filter_map(|k| {
                c.grid
                    .cell_at(c.grid.cells[k].i as isize + 1, c.grid.cells[k].j as isize)
            })
            .map(|up| sol.fluid_height[up])
            .sum();
        assert!(pushed > 0.0);
        assert!(sol.expelled > 0.0 && sol.inflow > 0.0);
        assert!(sol.fluid_pressure.iter().any(|p| *p > 0.0));
    }
}

/// As a cell's A_m/A_n(d_dry) rises to 1 it turns into a wall continuously: the share θ of the carried
/// film it takes in and the pressure-driven flow through its faces both vanish with 1 − A_m/A_n(d_dry),
/// so the film approaches the one with the cell a wall, in proportion (docs/model.md §8.5). Before, the
/// flow through the faces did not scale: just below 1 the cell still held fluid pressed in by its
/// neighbours and the film jumped at 1, which kept the outer iteration of hot contacts past the onset
/// of the walls from converging (§9). Here the cell of the highest fluid pressure of a flooded contact is
/// made nearly covered (its dry state otherwise kept).
#[test]
fn a_cell_turns_into_a_wall_continuously() {
    let mut c = Case::new(&point(0.01, 30.0, 1.0, 100e3));
    let flooded = solve_film(&c.problem(1e-12, 200), None).unwrap();
    let k = (0..c.grid.len())
        .max_by(|a, b| flooded.fluid_pressure[*a].total_cmp(&flooded.fluid_pressure[*b]))
        .unwrap();
    assert!(flooded.fluid_pressure[k] > 0.0 && c.dry_area[k] < 0.9);
    let mut at = |area: f64| {
        c.dry_area[k] = area;
        let sol = solve_film(&c.problem(1e-12, 200), None).unwrap();
        assert!(sol.converged, "A_m/A_n(d_dry) = {area}");
        sol
    };
    let wall = at(1.0);
    assert_eq!(wall.fluid_height[k], 0.0);
    let near: Vec<FilmSolution> = [1e-4, 1e-5, 1e-6].iter().map(|e| at(1.0 - e)).collect();
    let gaps: Vec<f64> = near.iter().map(|s| distance(s, &wall, &c)).collect();
    for pair in gaps.windows(2) {
        assert!(pair[1] < 0.2 * pair[0], "{gaps:?}");
    }
    assert!(gaps[2] < 1e-4, "{gaps:?}");
    // the cell's own fluid vanishes with it
    let held: Vec<f64> = near.iter().map(|s| s.fluid_height[k]).collect();
    assert!(
        held[2] < 0.2 * held[1] && held[1] < 0.2 * held[0],
        "{held:?}"
    );
}

/// With a small GW density β = 0.04 the asperities alone carry the centre pressure of the default
/// contact (1.03 GPa) only below the base height, with A_m/A_n(d_dry) < 1: the voids are closed there
/// (l_v(d_dry) = 0). Fluid carried in lifts them above d_b, to a finite pressure p_f(d_b) and more
/// (docs/model.md §8.7); the film solves (it failed before).
#[test]
fn closed_cells_open_above_the_base_height() {
    let mut params = Params::default();
    params.roughness.beta = 0.04;
    let c = Case::of(&params, &point(0.01, 30.0, 1.0, 100e3), 20.0);
    let closed: Vec<usize> = (0..c.grid.len())
        .filter(|k| c.dry_d[*k] <= c.base_height)
        .collect();
    assert!(!closed.is_empty());
    assert!(closed.iter().all(|k| c.dry_area[*k] < 1.0));
    let sol = newton_film_matching_the_reference(&c);
    let mut lifted = 0;
    for &k in &closed {
        if sol.fluid_height[k] > 0.0 {
            assert!(sol.separation[k] > c.base_height && sol.fluid_pressure[k] > 0.0);
            lifted += 1;
        }
    }
    assert!(lifted > 0);
}

#[test]
fn mismatched_field_lengths_are_an_error() {
    let c = Case::new(&point(0.01, 30.0, 1.0, 100e3));
    let mut pr = c.problem(1e-10, 100);
    pr.dry_metal_load = &c.dry_load[1..];
    assert!(solve_film(&pr, None).is_err());
}
