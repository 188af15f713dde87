//! Mode auto's per-contact fallback grid against the default 30 × 30 grid (docs/model.md §6.4): the
//! bundled table's accuracy, |ΔF|/F_N ≤ 1 % and T_max within 10 K, at the hardest contacts of the grid
//! study — dry at the flange root with the largest temperature error, a wide contact under spin with the
//! largest force error, wet at the flange root, on a round contact and on the wet grid with fewer cells
//! along x where it had its largest force error.

use wheelrail::model::{Evaluated, Evaluator, FallbackGrid, Mode, Policy};
use wheelrail::params::Geometry;
use wheelrail::{Model, OperatingPoint, Params};

/// The force accuracy the bundled table promises, |ΔF|/F_N [-].
const FORCE_ACCURACY: f64 = 0.01;
/// The peak-temperature accuracy it promises [K].
const TEMPERATURE_ACCURACY: f64 = 10.0;

/// (gap curvatures A, B [1/m], point, what the case is).
fn cases() -> Vec<([f64; 2], OperatingPoint, &'static str)> {
    let point = |creepage_x, creepage_y, spin, normal_force, speed, wetness| OperatingPoint {
        creepage_x,
        creepage_y,
        spin,
        normal_force,
        speed,
        wetness,
    };
    vec![
        (
            [0.9247, 6.9276],
            point(-0.01944, 0.00529, 0.7685, 105_907.0, 24.3, 0.0),
            "dry flange root at 1.9 % creepage",
        ),
        (
            [0.8823, 0.3236],
            point(-0.0004169, 0.00052, 0.902, 43_245.0, 15.96, 0.0),
            "dry wide contact under spin",
        ),
        (
            [0.92, 3.5],
            point(0.003, 0.0, 0.6, 139_000.0, 22.0, 1.0),
            "wet flange root",
        ),
        (
            [0.9826, 0.8945],
            point(0.014, 0.0006, 0.28, 93_551.0, 25.0, 1.0),
            "wet round contact at 1.4 % creepage",
        ),
        (
            [1.0116, 2.6235],
            point(0.002515, 0.00074, -0.673, 123_214.0, 6.61, 0.879),
            "wet contact just short of a/b = 2 under spin (16 along x)",
        ),
    ]
}

#[test]
fn the_fallback_grid_meets_the_tables_accuracy_against_the_default_grid() {
    let params = Params::default();
    let auto = Evaluator::new(
        Model::new(params.clone()).unwrap(),
        Mode::Auto,
        None,
        Policy {
            fallback_grid: FallbackGrid::PerContact,
            ..Policy::default()
        },
    )
    .unwrap();
    let reference = Evaluator::new(
        Model::new(params).unwrap(),
        Mode::ExactOnly,
        None,
        Policy::default(),
    )
    .unwrap();
    for ([a, b], point, what) in cases() {
        let geometry = Geometry::of_inputs(a, b, [0.0, 0.0]);
        let solve = |e: &Evaluator| {
            let r = e.evaluate_at(&point, &geometry, None, &mut None).unwrap();
            let Evaluated::Exact(x) = r.by else {
                panic!("{what}: the exact solver evaluates")
            };
            assert!(x.report.converged, "{what}: {:?}", x.report);
            *x
        };
        let (fast, full) = (solve(&auto), solve(&reference));
        assert_eq!(full.cells, [30, 30]);
        assert!(
            fast.cells[0] * fast.cells[1] < 400,
            "{what}: {:?} is a coarse grid",
            fast.cells
        );
        let (f, g) = (&fast.global, &full.global);
        let force = (f.force_x - g.force_x).hypot(f.force_y - g.force_y) / point.normal_force;
        let temperature = (f.max_temperature.unwrap() - g.max_temperature.unwrap()).abs();
        eprintln!(
            "{what}: {:?} |ΔF|/F_N = {force:.2e}, |ΔT_max| = {temperature:.1} K",
            fast.cells
        );
        assert!(force <= FORCE_ACCURACY, "{what}: |ΔF|/F_N = {force}");
        assert!(
            temperature <= TEMPERATURE_ACCURACY,
            "{what}: |ΔT_max| = {temperature} K"
        );
    }
}
