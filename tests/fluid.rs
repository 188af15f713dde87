//! The interfacial fluid in the coupled solver: conservation, complementarity, compatibility (P17), and the
//! paper's qualitative findings (docs/model.md §8, §11).

use wheelrail::fluid::Regime;
use wheelrail::{OperatingPoint, Params, Solution, solve};

fn small() -> Params {
    let mut p = Params::default();
    p.grid.nx = 20;
    p.grid.ny = 20;
    p
}

fn wet(xi: f64, speed: f64, wetness: f64) -> OperatingPoint {
    OperatingPoint {
        creepage_x: xi,
        speed,
        wetness,
        ..Default::default()
    }
}

fn solved(p: &Params, pt: &OperatingPoint) -> Solution {
    let s = solve(p, pt).unwrap();
    assert!(s.report.converged, "not converged: {:?}", s.report);
    s
}

#[test]
fn wetness_zero_reproduces_the_dry_solver_exactly() {
    let p = small();
    let dry = solved(&p, &wet(0.01, 30.0, 0.0));
    let mut p2 = p.clone();
    p2.fluid.flow_resistance = 1.0; // fluid parameters must not matter when dry
    p2.fluid.k_wet = 0.1;
    let dry2 = solved(&p2, &wet(0.01, 30.0, 0.0));
    assert_eq!(dry.global, dry2.global);
    let f = dry.fields.unwrap();
    assert!(f.regime.iter().all(|r| *r == Regime::Dry));
    assert!(f.fluid_pressure.iter().all(|p| *p == 0.0));
    // and a vanishing film is continuous with it
    let tiny = solved(&p, &wet(0.01, 30.0, 1e-9));
    let rel = (tiny.global.traction_coefficient - dry.global.traction_coefficient).abs()
        / dry.global.traction_coefficient;
    assert!(rel < 1e-3, "w = 1e-9 changes f by {rel}");
}

#[test]
fn film_conserves_volume_and_satisfies_complementarity_and_p17() {
    let p = small();
    let s = solved(&p, &wet(0.0, 30.0, 1.0));
    assert!(
        s.global.fluid_mass_balance_error.unwrap().abs() < 1e-6,
        "mass balance {}",
        s.global.fluid_mass_balance_error.unwrap()
    );
    let f = s.fields.unwrap();
    for k in 0..f.grid.len() {
        let pf = f.fluid_pressure[k];
        let a = f.area_fraction[k];
        let void = f.cell_height[k] - f.metal_height[k];
        assert!(pf >= 0.0);
        assert!(f.fluid_height[k] <= void * (1.0 + 1e-9) + 1e-18);
        if f.fluid_height[k] < void * (1.0 - 1e-6) {
            assert_eq!(pf, 0.0, "a cell that is not full carries no pressure");
        }
        // compatibility P17: p_f (1 − A_m/A_n) + p_m A_m/A_n = p_n
        let lhs = pf * (1.0 - a) + f.nominal_metal_pressure[k];
        assert!(
            (lhs - f.nominal_pressure[k]).abs() <= 1e-6 * f.nominal_pressure[k],
            "P17 violated in cell {k}: {lhs} vs {}",
            f.nominal_pressure[k]
        );
    }
}

#[test]
fn pure_rolling_has_inlet_pressure_and_outlet_boundary_lubrication() {
    let s = solved(&small(), &wet(0.0, 30.0, 1.0));
    let f = s.fields.unwrap();
    // the centre strip, leading edge first
    let strip = f
        .grid
        .strips
        .iter()
        .min_by(|a, b| a.y.abs().total_cmp(&b.y.abs()))
        .unwrap();
    let cells: Vec<usize> = strip.cells.clone().collect();
    let half = cells.len() / 2;
    let inlet_mixed = cells[..half]
        .iter()
        .filter(|k| f.regime[**k] == Regime::Mixed)
        .count();
    assert!(inlet_mixed > 0, "no fluid pressure in the inlet half");
    let last = *cells.last().unwrap();
    assert_eq!(
        f.regime[last],
        Regime::Boundary,
        "outlet must be boundary lubricated"
    );
    assert_eq!(f.fluid_pressure[last], 0.0);
    assert!(s.global.fluid_load_fraction.unwrap() > 0.0);
}

#[test]
fn standstill_limit_is_boundary_lubrication_everywhere() {
    let s = solved(&small(), &wet(0.0, 1e-3, 1.0));
    assert!(
        s.global.mixed_lubrication_area_fraction.unwrap() == 0.0,
        "mixed share {} at V → 0",
        s.global.mixed_lubrication_area_fraction.unwrap()
    );
    assert!(s.global.fluid_load_fraction.unwrap() < 1e-3);
    let f = s.fields.unwrap();
    assert!(f.regime.iter().all(|r| *r == Regime::Boundary));
}

#[test]
fn traction_falls_monotonically_with_wetness_at_30_m_s() {
    let p = small();
    let mut last = f64::INFINITY;
    for w in [0.0, 0.001, 0.01, 0.1, 0.5, 1.0] {
        let f = solved(&p, &wet(0.01, 30.0, w)).global.traction_coefficient;
        assert!(
            f <= last * (1.0 + 1e-9),
            "f rose to {f} at w = {w} (was {last})"
        );
        last = f;
    }
}

/// Grid convergence of the wet model: on the default 30 × 30 grid the traction lies within 0.5 % and the
/// fluid's load share within 1 % of their grid-converged values, Richardson-extrapolated from 60 × 60 and
/// 120 × 120 for a second-order discretisation, and the two fine grids agree to 0.5 %. (With first-order
/// upwind transport of the film the Table 1 water point had f 2.6 % low and the load share 11 % high at
/// 30 × 30 against that extrapolation, and f differed by 0.7 %, the load share by 3 % between 60 × 60 and
/// 120 × 120: convergence as h^1.3.) Two points: Table 1 water (30 m/s, ξ = 1 %, flooded) and a slower,
/// half-wet one.
#[test]
fn wet_results_on_the_default_grid_are_close_to_the_grid_converged_ones() {
    for pt in [wet(0.01, 30.0, 1.0), wet(0.003, 10.0, 0.5)] {
        let at = |n: usize| {
            let mut p = Params::default();
            p.grid.nx = n;
            p.grid.ny = n;
            solved(&p, &pt).global
        };
        let (coarse, fine, finer) = (at(30), at(60), at(120));
        for (name, c, f, ff, tol) in [
            (
                "f",
                coarse.traction_coefficient,
                fine.traction_coefficient,
                finer.traction_coefficient,
                5e-3,
            ),
            (
                "fluid load fraction",
                coarse.fluid_load_fraction.unwrap(),
                fine.fluid_load_fraction.unwrap(),
                finer.fluid_load_fraction.unwrap(),
                1e-2,
            ),
        ] {
            let converged = ff + (ff - f) / 3.0;
            assert!(
                (f - ff).abs() <= 5e-3 * converged,
                "{pt:?}: {name} {f} on 60 x 60, {ff} on 120 x 120"
            );
            assert!(
                (c - converged).abs() <= tol * converged,
                "{pt:?}: {name} {c} on 30 x 30, grid-converged {converged}"
            );
        }
    }
}

/// A hot, heavily loaded, barely wet point (ξ = 10 %, 200 kN, 100 m/s, w = 0.0015): the first, unrelaxed
/// temperature update overshoots to ~1800 K where the film has no solution; the outer iteration steps back
/// (temperature_backtracks) and converges to a wet solution no more frictional than the dry one.
#[test]
fn a_hot_heavily_loaded_barely_wet_point_converges() {
    let p = Params::default();
    // ξ = 10 %, 200 kN, 100 m/s, w = 0.0015: points of the default table's corner (the film fails at the
    // first, unrelaxed temperature update; the last two also needed the film's cold Newton restart when
    // the warm start from the previous outer iteration stalled)
    for (creepage_y, spin) in [
        (0.006938319246036665, 1.0),
        (0.00232756897959015, -0.7146615558812911),
        (0.02, -0.14637769565849473),
    ] {
        let pt = OperatingPoint {
            creepage_x: 0.1,
            creepage_y,
            spin,
            normal_force: 200e3,
            speed: 100.0,
            wetness: 0.0015,
        };
        let wet = solve(&p, &pt).unwrap();
        let dry = solve(&p, &OperatingPoint { wetness: 0.0, ..pt }).unwrap();
        assert!(
            wet.report.converged && dry.report.converged,
            "{:?}",
            wet.report
        );
        let g = &wet.global;
        assert!(g.traction_coefficient <= dry.global.traction_coefficient + 1e-6);
        assert!((0.0..1.0).contains(&g.fluid_load_fraction.unwrap()));
        assert!(g.fluid_mass_balance_error.unwrap().abs() < 1e-6);
    }
}

/// Second-order upwind face height of src/fluid/film.rs: l + (l − l_up)/2 where the film rises or is
/// level, l/2 + l_up·l²/(2·((l_up − l)² + l_up²)) where it falls; the leading cell carries its own height.
fn face_height(l: f64, up: Option<f64>) -> f64 {
    match up {
        None => l,
        Some(a) if l >= a => 1.5 * l - 0.5 * a,
        Some(a) => 0.5 * l + 0.5 * a * l * l / ((a - l) * (a - l) + a * a),
    }
}

/// The film's volume balance per cell [m³/s] recomputed from the fields by the discrete equations of the
/// film (P12–P16, docs/model.md §8): carried in − carried out at the mean speed v_m through faces of width
/// h_y (the leading cell takes in min(v_r·h_y·h_f0, v_m·h_y·l_v)), plus the pressure-driven flow
/// c·H(g, g_nb)·(p_nb − p) from each neighbour (H the harmonic mean of g = l_v³, c = h_⊥/(h_∥·ξ_f)),
/// minus 2·c·g·p through each face on the contact edge.
fn volume_balance(f: &wheelrail::solver::Fields, p: &Params, pt: &OperatingPoint) -> Vec<f64> {
    let (v_w, v_r) = wheelrail::solver::surface_speeds(pt);
    let vh = 0.5 * (v_w + v_r) * f.grid.hy;
    let supply = v_r * f.grid.hy * pt.wetness * p.fluid.h_f_max;
    let xi_f = p.fluid.flow_resistance;
    let (cx, cy) = (
        f.grid.hy / (f.grid.hx * xi_f),
        f.grid.hx / (f.grid.hy * xi_f),
    );
    let g = |k: usize| f.void_height[k].powi(3);
    let up = |k: usize| {
        let c = f.grid.cells[k];
        f.grid.cell_at(c.i as isize + 1, c.j as isize)
    };
    let out = |k: usize| vh * face_height(f.fluid_height[k], up(k).map(|u| f.fluid_height[u]));
    (0..f.grid.len())
        .map(|k| {
            let c = f.grid.cells[k];
            let (i, j) = (c.i as isize, c.j as isize);
            let inflow = match up(k) {
                Some(u) => out(u),
                None => supply.min(vh * f.void_height[k]),
            };
            let mut balance = inflow - out(k);
            for (nb, cf) in [
                (f.grid.cell_at(i + 1, j), cx),
                (f.grid.cell_at(i - 1, j), cx),
                (f.grid.cell_at(i, j - 1), cy),
                (f.grid.cell_at(i, j + 1), cy),
            ] {
                let pk = f.fluid_pressure[k];
                balance += match nb {
                    Some(n) if g(k) > 0.0 && g(n) > 0.0 => {
                        cf * 2.0 * g(k) * g(n) / (g(k) + g(n)) * (f.fluid_pressure[n] - pk)
                    }
                    Some(_) => 0.0,
                    None => -2.0 * cf * g(k) * pk,
                };
            }
            balance
        })
        .collect()
}

/// The film's reported balance residual is the largest volume balance of a cell of the returned fields,
/// relative to v_m·h_y·h_f0, for a converged film and for one cut short after a single sweep; its rejected
/// share is the rail's film that the leading cells' voids do not take in: most of a flooded inlet's, none
/// of a thin film's.
#[test]
fn the_film_reports_the_balance_and_the_rejected_inflow_of_its_fields() {
    let mut p = small();
    for (w, sweeps) in [(1.0, 100), (1.0, 1), (0.2, 1), (0.005, 100)] {
        p.solver.max_fluid_sweeps = sweeps;
        p.solver.max_iterations = if sweeps == 1 { 1 } else { 100 };
        let pt = wet(0.01, 30.0, w);
        let s = solve(&p, &pt).unwrap();
        assert_eq!(s.report.converged, sweeps > 1, "{:?}", s.report);
        let f = s.fields.as_ref().unwrap();
        let (v_w, v_r) = wheelrail::solver::surface_speeds(&pt);
        let h_f0 = w * p.fluid.h_f_max;
        let scale = 0.5 * (v_w + v_r) * f.grid.hy * h_f0;
        let recomputed = volume_balance(f, &p, &pt)
            .iter()
            .fold(0.0, |m: f64, r| m.max(r.abs()))
            / scale;
        let reported = s.report.fluid_balance_residual;
        assert!(
            (recomputed - reported).abs() <= 1e-9 * reported + 1e-12,
            "w = {w}, {sweeps} sweeps: reported {reported}, recomputed {recomputed}"
        );
        if sweeps == 1 {
            assert!(reported > 1e-3, "{reported}");
        } else {
            assert!(reported < 1e-9, "{reported}");
        }
        // rejected: the rail's film per strip minus what the leading cell's void takes in
        let per_strip = v_r * f.grid.hy * h_f0;
        let taken: f64 = f
            .grid
            .strips
            .iter()
            .map(|st| per_strip.min(0.5 * (v_w + v_r) * f.grid.hy * f.void_height[st.cells.start]))
            .sum();
        let want = 1.0 - taken / (per_strip * f.grid.strips.len() as f64);
        let rejected = s.global.fluid_rejected_fraction.unwrap();
        assert!((rejected - want).abs() <= 1e-12, "{rejected} vs {want}");
        if w == 1.0 {
            assert!(rejected > 0.5, "{rejected}");
        }
        if w == 0.005 {
            assert_eq!(rejected, 0.0);
        }
    }
    // dry: no film, nothing rejected, no balance to report
    let s = solved(&small(), &wet(0.01, 30.0, 0.0));
    assert_eq!(s.global.fluid_rejected_fraction, Some(0.0));
    assert_eq!(s.report.fluid_balance_residual, 0.0);
}

/// A small, hard, wet contact (10 kN on a = b = 1.38 mm, p0 = 2.5 GPa): GW's metallic area covers the
/// nominal area at the centre (A_m/A_n ≥ 1), where P17 leaves the fluid no free area (docs/model.md §8.5).
/// The point reported as "no separation balances the cell" solves, and so does a creepage line started
/// point by point from its predecessor, as a table line is built; no fluid lies where the metal covers
/// the cell, and the volume balance holds.
#[test]
fn a_small_hard_wet_contact_solves() {
    let mut p = Params::default();
    p.geometry.semi_axes = Some([0.001381976597885342; 2]);
    let reported = OperatingPoint {
        creepage_x: 1e-6,
        normal_force: 1e4,
        wetness: 0.3,
        ..Default::default()
    };
    let points: Vec<OperatingPoint> = [0.0, 1e-3, 3e-3, 1e-2, 3e-2, 0.1]
        .iter()
        .map(|xi| OperatingPoint {
            creepage_x: *xi,
            creepage_y: 0.005,
            spin: 0.5,
            wetness: 1.0,
            ..reported
        })
        .collect();
    let line = wheelrail::solver::solve_sweep(&p, &points);
    for s in std::iter::once(solve(&p, &reported)).chain(line) {
        let s = s.unwrap();
        assert!(s.report.converged, "{:?}", s.report);
        let g = &s.global;
        assert!((0.0..1.0).contains(&g.fluid_load_fraction.unwrap()));
        assert!(g.fluid_mass_balance_error.unwrap().abs() < 1e-6);
        let f = s.fields.unwrap();
        let covered = (0..f.grid.len()).filter(|k| f.area_fraction[*k] >= 1.0);
        assert!(covered.clone().count() > 0);
        for k in covered {
            assert_eq!(f.fluid_height[k], 0.0);
            assert_eq!(f.fluid_pressure[k], 0.0);
        }
    }
}

/// A point whose film finds no solution (a large hard contact, p0 = 2.47 GPa, flooded at 64.5 m/s, pure
/// spin): Newton stalls next to the cells covered by metal and the Gauss–Seidel fallback finds no root
/// of a cell. The solve no longer fails: it keeps Newton's last film and, once the temperature has
/// settled, stops and reports the point unconverged, stalled on the film (docs/model.md §9); its forces
/// are finite. (The same line converges at ξ = 1 %.)
#[test]
fn a_point_whose_film_has_no_solution_is_reported_unconverged() {
    let mut p = Params::default();
    let (a_over_b, p0, normal_force) = (1.4534352169838594, 2472334359.8720284, 110397.04039006485);
    let ab = 3.0 * normal_force / (2.0 * std::f64::consts::PI * p0);
    p.geometry.semi_axes = Some([(ab * a_over_b).sqrt(), (ab / a_over_b).sqrt()]);
    let pt = OperatingPoint {
        creepage_x: 0.0,
        creepage_y: 0.0,
        spin: 0.5738333081387637,
        normal_force,
        speed: 64.51293676475127,
        wetness: 0.8269545995236826,
    };
    let s = solve(&p, &pt).unwrap();
    assert_eq!(
        s.report.termination,
        wheelrail::solver::Termination::Stalled {
            limited_by: wheelrail::solver::Limiter::Film
        }
    );
    assert!(!s.report.converged && s.report.iterations < p.solver.max_iterations);
    let g = &s.global;
    assert!(g.force_x.is_finite() && g.force_y.is_finite() && g.max_temperature.unwrap() > 293.0);
    // a table build does not retry a stalled point: more iterations would solve the same film
    let built = wheelrail::table::solve_with_retry(&p, &pt, None).unwrap();
    assert_eq!(built.report.iterations, s.report.iterations);
    assert_eq!(built.global.force_x.to_bits(), g.force_x.to_bits());
    let converged = solve(
        &p,
        &OperatingPoint {
            creepage_x: 0.01,
            ..pt
        },
    )
    .unwrap();
    assert!(converged.report.converged, "{:?}", converged.report);
}

/// `max_dry_area_fraction` is GW's metallic area ratio at the dry separation, largest over the contact:
/// dry, the separation is the dry one, so it is the largest A_m/A_n of the fields; wet, it marks the onset
/// of the walls (docs/model.md §8.5). Below the onset every cell takes in the film carried to it and none
/// runs dry; past it (A_m/A_n(d_dry) ≥ 1 at the centre) the covered cells and the cells downstream of them
/// hold no fluid, and the friction rises towards the dry value over a few per cent of p0 — the steep
/// transition the table marks unresolved. Default contact shape (a/b 0.72) at 100 kN, V = 11 m/s, ξ = 0.9 %,
/// w = 0.0085, 20 × 20 cells.
#[test]
fn the_walls_begin_where_the_metal_covers_the_centre_at_the_dry_separation() {
    use wheelrail::fluid::takes_in_all;
    let at = |p0: f64, wetness: f64| {
        let mut p = small();
        let ab = 3.0 * 100e3 / (2.0 * std::f64::consts::PI * p0);
        let ratio = 0.7247796636776956;
        p.geometry.semi_axes = Some([(ab * ratio).sqrt(), (ab / ratio).sqrt()]);
        solved(&p, &wet(-0.009, 11.0, wetness))
    };
    // dry: the largest A_m/A_n of the fields, rising with p0 through 1
    let mut last = 0.0;
    for p0 in [1.0e9, 1.4e9, 1.6e9] {
        let s = at(p0, 0.0);
        let m = s.global.max_dry_area_fraction.unwrap();
        let f = s.fields.unwrap();
        assert_eq!(m, f.area_fraction.iter().cloned().fold(0.0, f64::max));
        assert!(m > last, "{p0}: {m} after {last}");
        last = m;
    }
    assert!(last > 1.0, "{last}");
    // wet: find the onset by bisection on p0 between a point that takes in all and one that does not
    let onset = |p0: f64| !takes_in_all(at(p0, 0.0085).global.max_dry_area_fraction.unwrap());
    let (mut lo, mut hi) = (1.2e9, 1.8e9);
    assert!(!onset(lo) && onset(hi));
    while hi - lo > 2e6 {
        let mid = 0.5 * (lo + hi);
        if onset(mid) { hi = mid } else { lo = mid }
    }
    let (below, above) = (at(lo, 0.0085), at(hi + 0.02 * hi, 0.0085));
    let dry_cells = |s: &Solution| {
        let f = s.fields.as_ref().unwrap();
        (0..f.grid.len())
            .filter(|k| f.regime[*k] == Regime::Dry)
            .count()
    };
    assert_eq!(dry_cells(&below), 0);
    assert!(dry_cells(&above) > 0);
    // where the metal covers a cell (A_m/A_n(d_dry) ≥ 1: d = d_dry, so A_m/A_n ≥ 1 in the fields) it holds
    // no fluid
    let f = above.fields.as_ref().unwrap();
    let covered: Vec<usize> = (0..f.grid.len())
        .filter(|k| f.area_fraction[*k] >= 1.0)
        .collect();
    assert!(!covered.is_empty());
    assert!(covered.iter().all(|k| f.fluid_height[*k] == 0.0));
    // 2 % of p0 past the onset the friction has risen by more than the whole variation over the 2 % below
    // it: the steep transition
    let before = at(lo / 1.02, 0.0085).global.traction_coefficient;
    let (f_lo, f_hi) = (
        below.global.traction_coefficient,
        above.global.traction_coefficient,
    );
    assert!(
        f_hi - f_lo > 5.0 * (f_lo - before).abs() && f_hi - f_lo > 0.005,
        "{before} {f_lo} {f_hi}"
    );
}

/// The 30 × 30 parameters and the wet point (w = 0.0085, 100 kN) with creepages `[ξ, η, φ]` and speed `speed`
/// [m/s] of a node of the 1.105× p0 slice past the onset of the walls: the contact a/b 0.72 at p0 1.67 GPa
/// (docs/model.md §12.3).
fn past_the_onset(creepages: [f64; 3], speed: f64) -> (Params, OperatingPoint) {
    let mut p = Params::default();
    p.geometry.semi_axes = Some([4.54860892424718e-3, 6.275850651171021e-3]);
    let [creepage_x, creepage_y, spin] = creepages;
    let pt = OperatingPoint {
        creepage_x,
        creepage_y,
        spin,
        normal_force: 1e5,
        speed,
        wetness: 0.0085,
    };
    (p, pt)
}

/// Past the onset of the walls a hot wet contact's film switches within a few kelvin of one cell's
/// temperature (the metal covers the cell or leaves it a film), and with it that cell's adhesion limit by a
/// factor of 2.5: one relaxation factor for the whole field kept the cell in a cycle of period 4 (200
/// iterations, residual 0.21, forces varying by 2e-3·F_N between its states). The outer iteration damps such
/// cells one by one once it stalls (docs/model.md §9): it converges, to a fixed point of the coupled model —
/// restarted from its own state, the iteration stays there (a few iterations, the same forces).
#[test]
fn a_hot_wet_contact_past_the_onset_of_the_walls_converges() {
    use wheelrail::fluid::takes_in_all;
    let (p, pt) = past_the_onset(
        [
            0.04599881715888574,
            0.021805602777608353,
            -0.48385494361032017,
        ],
        11.022233191647608,
    );
    let s = solved(&p, &pt);
    assert!(!takes_in_all(s.global.max_dry_area_fraction.unwrap()));
    assert!(s.global.max_temperature.unwrap() > 600.0);
    assert!(s.report.residual <= p.solver.tolerance);
    let again = wheelrail::solve_from(&p, &pt, s.warm_start().as_ref()).unwrap();
    assert!(again.report.converged, "{:?}", again.report);
    assert!(again.report.iterations <= 6, "{:?}", again.report);
    let f = |s: &Solution| [s.global.force_x, s.global.force_y].map(|x| x / pt.normal_force);
    for (a, b) in f(&s).iter().zip(f(&again)) {
        assert!((a - b).abs() < 1e-5, "{a} vs {b}");
    }
}

/// A table build retries a point that does not converge within the iteration limit cold with four times
/// the limit and the same initial relaxation: this node of a 30 × 30 slice past the onset of the walls
/// (a/b 0.72, 1.67 GPa, V 4.5 m/s, w 0.0085, full slip under spin) needs about 300 iterations from a cold
/// start. The retry used to halve the initial relaxation, which left it (and 30 hot nodes) unconverged.
#[test]
fn a_table_build_retries_a_slow_point_to_convergence() {
    let (p, pt) = past_the_onset(
        [
            0.07353413584592298,
            0.021805602777608353,
            -0.9933723592015623,
        ],
        4.535487421721594,
    );
    let first = solve(&p, &pt).unwrap();
    assert!(!first.report.converged, "{:?}", first.report);
    let retried = wheelrail::table::solve_with_retry(&p, &pt, None).unwrap();
    assert!(retried.report.converged, "{:?}", retried.report);
    assert!(retried.report.iterations > p.solver.max_iterations);
}
