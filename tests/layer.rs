//! The interfacial (third-body) layer of the tangential problem (docs/model.md §6.7): FASTSIM's slope
//! reduction L/(L + h/G₃) of the linear theory, the exact solver's brush (Winkler) limit of a compliant
//! layer, full slip unchanged, the two methods' reductions alike, grid convergence, and the layer reaching
//! both tangential solvers of the full model.

use crate::tangential::{converged, point};
use wheelrail::Params;
use wheelrail::contact::{ContactGrid, HertzContact};
use wheelrail::params::{FrictionLaw, Layer, Tangential};
use wheelrail::solver::normal_contact;
use wheelrail::tangential::exact::{ExactSettings, SteadyRolling};
use wheelrail::tangential::{Creepages, Flexibilities, fastsim, kalker_coefficients};

/// Friction coefficient of the traction bound μ·p_n of the direct solves [-].
const MU: f64 = 0.3;
/// Rolling speed of the direct solves [m/s].
const SPEED: f64 = 30.0;
/// A creepage deep in the linear theory (full stick on every grid here, with and without a layer) [-].
const SMALL: f64 = 1e-7;

/// The default contact (100 kN) with G and ν of the default steel at its bulk temperature.
struct Contact {
    hertz: HertzContact,
    shear_modulus: f64,
    poisson: f64,
}

fn contact() -> Contact {
    let p = Params::default();
    let mat = p.material.at(p.material.bulk_temperature);
    Contact {
        hertz: normal_contact(&p, 100e3).unwrap(),
        shear_modulus: mat.shear_modulus,
        poisson: mat.poisson,
    }
}

/// The layer compliance h/G₃ [m/Pa] of thickness `h` [m] with the default G₃.
fn compliance(h: f64) -> f64 {
    Layer {
        thickness: h,
        ..Layer::default()
    }
    .compliance()
}

impl Contact {
    fn grid(&self, n: usize) -> ContactGrid {
        ContactGrid::for_contact(&self.hertz, n, n)
    }

    /// FASTSIM's flexibilities of the half-spaces (docs/model.md §6.2).
    fn flexibilities(&self) -> Flexibilities {
        let k = kalker_coefficients(self.hertz.a, self.hertz.b, self.poisson).unwrap();
        Flexibilities::new(self.hertz.a, self.hertz.b, self.shear_modulus, &k)
    }

    /// The traction bound μ·p_n [Pa] per cell of `grid` with the nominal pressure `pressure`.
    fn bound(&self, grid: &ContactGrid, pressure: fn(&HertzContact, f64, f64) -> f64) -> Vec<f64> {
        grid.cells
            .iter()
            .map(|c| MU * pressure(&self.hertz, c.x, c.y))
            .collect()
    }

    /// FASTSIM under μ·p_parabolic with a layer of compliance `layer` [m/Pa].
    fn fastsim(&self, grid: &ContactGrid, creep: Creepages, layer: f64) -> [f64; 3] {
        let bound = self.bound(grid, HertzContact::parabolic_pressure);
        let flex = self.flexibilities().with_layer(layer);
        let f = fastsim(grid, creep, SPEED, &flex, &bound).unwrap();
        [f.force_x, f.force_y, f.spin_moment]
    }

    /// Kalker's exact steady rolling under μ·p_Hertz with a layer of compliance `layer` [m/Pa]:
    /// forces, moment and whether every cell slips.
    fn exact(&self, grid: &ContactGrid, creep: Creepages, layer: f64) -> ([f64; 3], bool) {
        let op = SteadyRolling::with_layer(grid, self.shear_modulus, self.poisson, layer).unwrap();
        let bound = self.bound(grid, HertzContact::hertz_pressure);
        let settings = ExactSettings {
            tolerance: 1e-10,
            max_sweeps: 5000,
            ..ExactSettings::default()
        };
        let s = op
            .solve(grid, creep, SPEED, &bound, None, settings)
            .unwrap();
        assert!(s.converged, "{} sweeps, residual {}", s.sweeps, s.residual);
        let f = s.field;
        (
            [f.force_x, f.force_y, f.spin_moment],
            f.slipping.iter().all(|x| *x),
        )
    }
}

fn xi(x: f64) -> Creepages {
    Creepages {
        xi: x,
        eta: 0.0,
        phi: 0.0,
    }
}

/// FASTSIM's stick solution p = −(w/L_i')·(a(y) − x) is exact at the cell centres, so with the layer's
/// flexibilities L_i' = L_i + h/G₃ each force of the linear theory falls by exactly L_i/(L_i + h/G₃), and
/// F_x = −8a²b·ξ/(3·L1') (∫∫(a(y) − x) dA = 8a²b/3 over the ellipse) within the grid's quadrature error.
#[test]
fn fastsim_linear_slopes_fall_by_the_flexibility_over_the_flexibility_plus_the_layer() {
    let c = contact();
    let grid = c.grid(60);
    let l = c.flexibilities();
    let (a, b) = (c.hertz.a, c.hertz.b);
    let cc = (a * b).sqrt();
    for h in [10e-6, 100e-6, 400e-6, 2e-3] {
        let layer = compliance(h);
        for (creep, component, flexibility) in [
            (xi(SMALL), 0, l.l1),
            (
                Creepages {
                    xi: 0.0,
                    eta: SMALL,
                    phi: 0.0,
                },
                1,
                l.l2,
            ),
            (
                Creepages {
                    xi: 0.0,
                    eta: 0.0,
                    phi: SMALL / cc,
                },
                1,
                l.l3,
            ),
        ] {
            let without = c.fastsim(&grid, creep, 0.0)[component];
            let with = c.fastsim(&grid, creep, layer)[component];
            let want = flexibility / (flexibility + layer);
            assert!(
                (with / without - want).abs() <= 1e-12,
                "h {h}: {} vs {want}",
                with / without
            );
        }
        let fx = c.fastsim(&grid, xi(SMALL), layer)[0];
        let closed = -8.0 * a * a * b * SMALL / (3.0 * (l.l1 + layer));
        assert!(
            (fx - closed).abs() <= 2e-3 * closed.abs(),
            "h {h}: {fx} vs {closed}"
        );
    }
}

/// The exact scheme's brush: with the layer alone (h/G₃ ≫ L) the steady-state condition
/// 0 = ξ + (h/G₃)·(p_I − p_(I+1))/h_x gives p = −(ξ·G₃/h)·k·h_x in the k-th cell from a strip's leading
/// edge (k = 1, 2, …): F_x [N] per unit creepage ξ and unit compliance h/G₃ of `grid`.
fn discrete_brush(grid: &ContactGrid) -> f64 {
    let cells: usize = grid
        .strips
        .iter()
        .map(|s| (1..=s.cells.len()).sum::<usize>())
        .sum();
    -(cells as f64) * grid.hx * grid.cell_area()
}

/// A layer far more compliant than the half-spaces (h/G₃ ≫ L) makes steady rolling the brush (Winkler)
/// problem of flexibility h/G₃, whose linear slope for the ellipse is F_x/ξ = −8a²b·G₃/(3h). The exact
/// solver tends to it as h/G₃ grows: on one grid to the scheme's own brush (the sum above), the
/// half-spaces adding about L1 to the layer's compliance, brush/exact − 1 = κ·L1/(h/G₃) with κ near 1
/// (measured 1.084–1.086 on 30 × 30 from h/G₃ = 5·L1 to 2e5·L1); and that brush tends to the ellipse's as the
/// grid is refined (first order: +5.2, +2.3, +1.2 % on 32, 64, 128 cells per axis).
#[test]
fn exact_linear_slope_tends_to_the_brush_model_of_a_compliant_layer() {
    let c = contact();
    let (a, b) = (c.hertz.a, c.hertz.b);
    let l1 = c.flexibilities().l1;
    let grid = c.grid(30);
    let mut last = f64::INFINITY;
    // h/G₃ from 5 to 2e5 times L1: the thickest layer of the range, ever softer
    for g3 in [4e10, 8.2e9, 8.2e7, 1e6] {
        let layer = compliance(1e-2) * 8.2e9 / g3;
        let (f, _) = c.exact(&grid, xi(SMALL), layer);
        let excess = discrete_brush(&grid) * SMALL / layer / f[0] - 1.0;
        let kappa = excess / (l1 / layer);
        assert!(
            (1.0..1.2).contains(&kappa) && excess < last,
            "G3 {g3}: brush/exact - 1 = {excess}, kappa {kappa}"
        );
        last = excess;
    }
    let layer = compliance(1e-2) * 8.2e9 / 1e6;
    let brush = -8.0 * a * a * b * SMALL / (3.0 * layer);
    let mut last = f64::INFINITY;
    for (n, tolerance) in [(32, 0.06), (64, 0.03), (128, 0.015)] {
        let (f, _) = c.exact(&c.grid(n), xi(SMALL), layer);
        let error = (f[0] / brush - 1.0).abs();
        assert!(
            error < tolerance && error < 0.6 * last,
            "{n} cells: {error}"
        );
        last = error;
    }
}

/// In full slip every cell carries its bound along the slip: the layer, which only adds compliance,
/// leaves the forces unchanged (both solvers, pure ξ, far beyond saturation even with the layer:
/// |F| = μ·Σ p_n·dA).
#[test]
fn full_slip_forces_are_unchanged_by_the_layer() {
    let c = contact();
    let grid = c.grid(30);
    let layer = compliance(1e-3);
    let without = c.fastsim(&grid, xi(0.5), 0.0);
    let with = c.fastsim(&grid, xi(0.5), layer);
    let limit = grid.integrate(&c.bound(&grid, HertzContact::parabolic_pressure));
    assert!(
        (with[0] + limit).abs() <= 1e-9 * limit,
        "{with:?} vs {limit}"
    );
    assert!((with[0] - without[0]).abs() <= 1e-12 * limit);
    let (without, slipping) = c.exact(&grid, xi(0.5), 0.0);
    let (with, slipping_with) = c.exact(&grid, xi(0.5), layer);
    assert!(slipping && slipping_with);
    let limit = grid.integrate(&c.bound(&grid, HertzContact::hertz_pressure));
    assert!(
        (with[0] + limit).abs() <= 1e-6 * limit,
        "{with:?} vs {limit}"
    );
    assert!((with[0] - without[0]).abs() <= 1e-9 * limit);
}

/// The same layer lowers the linear slope of both methods alike: FASTSIM by L1/(L1 + h/G₃), the exact
/// solver by its own ratio of slopes with and without the layer, within 0.02 of it (measured on 30 × 30
/// from h = 20 µm to 2 mm: −0.014 … +0.004; docs/model.md §6.7).
#[test]
fn fastsim_and_exact_reduce_the_slope_alike() {
    let c = contact();
    let grid = c.grid(30);
    let l1 = c.flexibilities().l1;
    let (without, _) = c.exact(&grid, xi(SMALL), 0.0);
    for h in [20e-6, 100e-6, 200e-6, 412e-6, 1e-3, 2e-3] {
        let layer = compliance(h);
        let (with, _) = c.exact(&grid, xi(SMALL), layer);
        let exact = with[0] / without[0];
        let fastsim = l1 / (l1 + layer);
        assert!(
            (exact - fastsim).abs() <= 0.02,
            "h {h}: exact {exact}, FASTSIM {fastsim}"
        );
    }
}

/// The exact solver with a layer converges with the grid: the linear slope's change per halving of the
/// cells falls by about half (first order, the steady-state scheme's upwind difference; measured
/// 5.5, 2.0, 0.8 % of the slope from 16 to 128 cells per axis for h = 200 µm).
#[test]
fn exact_solver_with_a_layer_converges_with_the_grid() {
    let c = contact();
    let layer = compliance(200e-6);
    let f = [16, 32, 64, 128].map(|n| c.exact(&c.grid(n), xi(SMALL), layer).0[0]);
    let changes: Vec<f64> = f
        .windows(2)
        .map(|w| (w[1] - w[0]).abs() / f[3].abs())
        .collect();
    assert!(
        changes.windows(2).all(|d| d[1] < 0.6 * d[0]) && changes[2] < 0.015,
        "{changes:?}"
    );
}

/// The full model passes the layer to both tangential solvers: with constant μ and heat off (full stick
/// at ξ = 1e-7) FASTSIM's force falls by exactly L1/(L1 + h/G₃) and the exact solver's is that of
/// `SteadyRolling::with_layer` under μ·p_Hertz; with the Tomberger law and heat the linear slope falls
/// by that ratio within 1 % (a little slip at the trailing edge).
#[test]
fn the_layer_reaches_both_tangential_solvers_of_the_model() {
    let h = 400e-6;
    let pt = point(1e-5, 0.0, 0.0);
    let c = contact();
    let ratio = {
        let l1 = c.flexibilities().l1;
        l1 / (l1 + compliance(h))
    };
    for tangential in [Tangential::Fastsim, Tangential::Exact] {
        let mut p = Params {
            tangential,
            ..Params::default()
        };
        let plain = converged(&p, &pt).global.force_x;
        p.layer.thickness = h;
        let layered = converged(&p, &pt).global.force_x;
        assert!(
            (layered / plain - ratio).abs() <= 0.01 * ratio,
            "{tangential}: {} vs {ratio}",
            layered / plain
        );
        p.friction.law = FrictionLaw::Constant;
        p.friction.mu = MU;
        p.solver.heat = false;
        let s = converged(&p, &point(SMALL, 0.0, 0.0));
        let fields = s.fields.as_ref().unwrap();
        assert!(fields.slipping.iter().all(|x| !x));
        let grid = &fields.grid;
        let direct = match tangential {
            Tangential::Fastsim => c.fastsim(grid, xi(SMALL), compliance(h))[0],
            Tangential::Exact => c.exact(grid, xi(SMALL), compliance(h)).0[0],
        };
        let without = c.fastsim(grid, xi(SMALL), 0.0)[0];
        let want = match tangential {
            Tangential::Fastsim => ratio * without,
            Tangential::Exact => direct,
        };
        assert!(
            (s.global.force_x - want).abs() <= 1e-6 * want.abs()
                && (s.global.force_x - direct).abs() <= 1e-6 * want.abs(),
            "{tangential}: model {} vs {want}",
            s.global.force_x
        );
    }
}
