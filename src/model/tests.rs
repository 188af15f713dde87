//! The model and its evaluation policy: validation, routing and its notices, clamping, lift-off, the frame
//! turn, the minimum speed, the wetness clamp, the chained table Jacobian, the tightened exact solve.

use super::frame::Solved;
use super::*;
use crate::Error;
use crate::params::Geometry;
use crate::table::{Table, TableOutput, small_axes};
use std::sync::{Arc, OnceLock};

/// The default parameters on a coarse 6 × 6 grid (cheap exact solves).
fn params() -> Params {
    let mut p = Params::default();
    p.grid.nx = 6;
    p.grid.ny = 6;
    p
}

/// A small table for [`params`] ([`small_axes`]), built once in memory.
fn table() -> Arc<Table> {
    static TABLE: OnceLock<Arc<Table>> = OnceLock::new();
    TABLE
        .get_or_init(|| {
            let files = crate::table::build(&params(), &small_axes(), None, &|| ()).unwrap();
            Arc::new(Table::from_files(files, None).unwrap())
        })
        .clone()
}

fn evaluator(mode: Mode, params: Params) -> Evaluator {
    Evaluator::new(
        Model::new(params).unwrap(),
        mode,
        Some(table()),
        Policy::default(),
    )
    .unwrap()
}

/// A point inside the small table's ranges.
fn inside() -> OperatingPoint {
    OperatingPoint {
        creepage_x: 0.003,
        creepage_y: -0.001,
        spin: 0.2,
        normal_force: 100e3,
        speed: 30.0,
        wetness: 0.1,
    }
}

fn eval(e: &Evaluator, p: &OperatingPoint) -> Evaluation {
    e.evaluate(p, None, &mut None).unwrap()
}

/// The six outputs an MBS contact gives (without the frictional power).
fn values(o: &TableOutput) -> [f64; 6] {
    let v = o.values();
    std::array::from_fn(|k| v[k])
}

fn notice_list(e: &Evaluation) -> Vec<Notice> {
    e.notices.iter().collect()
}

#[test]
fn a_model_validates_once_and_solves_as_the_solver() {
    let mut bad = params();
    bad.roughness.k_r = 1.5;
    let e = Model::new(bad).unwrap_err();
    assert!(e.to_string().contains("roughness.k_r"), "{e}");
    let m = Model::new(params()).unwrap();
    assert_eq!(m.params(), &params());
    let points = [0.001, 0.002, 0.004].map(|xi| OperatingPoint {
        creepage_x: xi,
        ..Default::default()
    });
    assert_eq!(
        m.solve(&points[0]).unwrap(),
        crate::solve(&params(), &points[0]).unwrap()
    );
    let warm = m.solve(&points[0]).unwrap().warm_start();
    assert_eq!(
        m.solve_from(&points[1], warm.as_ref()).unwrap(),
        crate::solve_from(&params(), &points[1], warm.as_ref()).unwrap()
    );
    let swept: Vec<_> = m.sweep(&points).into_iter().map(Result::unwrap).collect();
    let want: Vec<_> = crate::solver::solve_sweep(&params(), &points)
        .into_iter()
        .map(Result::unwrap)
        .collect();
    assert_eq!(swept, want);
}

#[test]
fn settings_and_modes_are_checked_when_the_evaluator_is_made() {
    let model = || Model::new(params()).unwrap();
    let slow = Policy {
        minimum_speed: 0.0,
        ..Policy::default()
    };
    let e = Evaluator::new(model(), Mode::ExactOnly, None, slow).unwrap_err();
    assert!(e.to_string().contains("minimum_speed: 0"), "{e}");
    let e = Evaluator::new(model(), Mode::TableOnly, None, Policy::default()).unwrap_err();
    assert!(
        matches!(
            e,
            Error::NoTable {
                mode: Mode::TableOnly
            }
        ),
        "{e}"
    );
    assert_eq!(e.to_string(), "evaluation mode table needs a lookup table");
    // exact only ignores a table; auto without one solves every point, with nothing to report
    let e = Evaluator::new(model(), Mode::ExactOnly, Some(table()), Policy::default()).unwrap();
    assert!(e.table().is_none() && !e.matches());
    let e = Evaluator::new(model(), Mode::Auto, None, Policy::default()).unwrap();
    let r = eval(&e, &inside());
    assert!(matches!(r.by, Evaluated::Exact(_)) && r.notices.is_empty());
}

#[test]
fn auto_uses_the_table_where_usable_and_else_the_exact_solver_with_the_reason() {
    let auto = evaluator(Mode::Auto, params());
    assert!(auto.matches());
    let r = eval(&auto, &inside());
    assert!(matches!(r.by, Evaluated::Table(_)));
    assert!(r.notices.is_empty());
    let h = crate::solver::normal_contact(&params(), inside().normal_force).unwrap();
    let e = crate::table::Ellipse {
        a: h.a,
        b: h.b,
        load_exponent: crate::table::Ellipse::HERTZ,
    };
    assert_eq!(
        r.outputs().unwrap(),
        table().evaluate(&inside(), &e).unwrap()
    );
    // outside the speed range
    let fast = OperatingPoint {
        speed: 60.0,
        ..inside()
    };
    let r = eval(&auto, &fast);
    assert!(matches!(r.by, Evaluated::Exact(_)));
    assert_eq!(notice_list(&r), [Notice::FellBack(Fallback::OutsideRanges)]);
    let s = crate::solve(&params(), &fast).unwrap();
    assert_eq!(r.outputs().unwrap().force_x, s.global.force_x);
    assert_eq!(r.by.report(), Some(&s.report));
    // other parameters
    let mut rough = params();
    rough.roughness.k_r = 0.6;
    let other = evaluator(Mode::Auto, rough.clone());
    assert!(!other.matches());
    let r = eval(&other, &inside());
    assert!(matches!(r.by, Evaluated::Exact(_)));
    assert_eq!(
        notice_list(&r),
        [Notice::FellBack(Fallback::OtherParameters)]
    );
    assert_eq!(
        r.outputs().unwrap().force_x,
        crate::solve(&rough, &inside()).unwrap().global.force_x
    );
    // the table agrees with the exact solver at a table point (wet, η < 0 by the mirror): the contact
    // a/b = 0.5, p_ref = 0.7 GPa as prescribed semi-axes
    let (node, e) = table()
        .coordinates()
        .point(&[0.4, -0.4, -0.05, 80e3, 40.0, 0.2, 0.5, 0.7e9])
        .unwrap();
    let at_node = Geometry::of_inputs(1.0, 1.0, [e.a, e.b]);
    let exact = evaluator(Mode::ExactOnly, params());
    let at = |ev: &Evaluator| ev.evaluate_at(&node, &at_node, None, &mut None).unwrap();
    let (a, b) = (at(&auto), at(&exact));
    assert!(matches!(a.by, Evaluated::Table(_)));
    for k in 0..3 {
        let (x, y) = (
            values(&a.outputs().unwrap())[k],
            values(&b.outputs().unwrap())[k],
        );
        assert!((x - y).abs() < 1e-6 * 80e3, "{k}: {x} vs {y}");
    }
    // the frictional power, stored as P_f/(F_N·V) in f32
    let (pa, pb) = (a.frictional_power().unwrap(), b.frictional_power().unwrap());
    assert!(pb > 0.0 && (pa / pb - 1.0).abs() < 1e-5, "{pa} vs {pb}");
}

#[test]
fn table_only_clamps_with_a_notice_and_refuses_other_parameters() {
    let only = evaluator(Mode::TableOnly, params());
    let r = eval(
        &only,
        &OperatingPoint {
            speed: 60.0,
            ..inside()
        },
    );
    assert!(matches!(r.by, Evaluated::Table(_)));
    assert_eq!(notice_list(&r), [Notice::Clamped]);
    assert!(!r.outputs().unwrap().in_range);
    // clamped to the largest speed of the table
    let edge = eval(
        &only,
        &OperatingPoint {
            speed: 40.0,
            ..inside()
        },
    );
    assert!(edge.notices.is_empty());
    assert_eq!(
        values(&r.outputs().unwrap()),
        values(&edge.outputs().unwrap())
    );
    let mut rough = params();
    rough.roughness.k_r = 0.6;
    let e = evaluator(Mode::TableOnly, rough)
        .evaluate(&inside(), None, &mut None)
        .unwrap_err();
    assert!(matches!(e, Error::TableParameters { .. }), "{e}");
    assert!(e.to_string().contains("other parameters"), "{e}");
}

#[test]
fn a_lifted_wheel_needs_no_solve_and_no_check() {
    let mut hot = params();
    hot.material.bulk_temperature = 300.0;
    let mut rough = params();
    rough.roughness.k_r = 0.6;
    // table only with other parameters: an error once the wheel is down, not while it is lifted
    for e in [
        evaluator(Mode::ExactOnly, hot),
        evaluator(Mode::TableOnly, rough),
    ] {
        for load in [LIFT_OFF_LOAD, 0.0, -5e3] {
            let lifted = OperatingPoint {
                normal_force: load,
                creepage_x: 2.5,
                wetness: 1.5,
                ..inside()
            };
            let mut warm = None;
            let r = e.evaluate(&lifted, None, &mut warm).unwrap();
            assert!(matches!(r.by, Evaluated::Lifted(_)));
            assert!(r.notices.is_empty() && warm.is_none());
            assert_eq!(values(&r.outputs().unwrap())[..4], [0.0; 4]);
            assert_eq!(
                r.outputs().unwrap().max_temperature,
                e.model().params().material.bulk_temperature
            );
            assert_eq!(r.outputs().unwrap().fluid_load_fraction, 0.0);
            assert!(r.outputs().unwrap().converged && r.outputs().unwrap().in_range);
            assert_eq!(
                e.table_jacobian(&lifted).unwrap(),
                (None, Notices::default())
            );
        }
    }
}

#[test]
fn rolling_backwards_is_the_turned_point_rolling_forwards() {
    for mode in [Mode::Auto, Mode::ExactOnly] {
        let e = evaluator(mode, params());
        let back = OperatingPoint {
            speed: -30.0,
            ..inside()
        };
        let turned = OperatingPoint {
            creepage_x: -back.creepage_x,
            creepage_y: -back.creepage_y,
            speed: 30.0,
            ..back
        };
        let (b, f) = (eval(&e, &back), eval(&e, &turned));
        assert_eq!(matches!(b.by, Evaluated::Table(_)), mode == Mode::Auto);
        let [fx, fy, mz, rest @ ..] = values(&f.outputs().unwrap());
        assert_eq!(
            values(&b.outputs().unwrap()),
            [-fx, -fy, mz, rest[0], rest[1], rest[2]]
        );
        if let (Evaluated::Exact(b), Evaluated::Exact(f)) = (&b.by, &f.by) {
            assert_eq!(b.global.force_x, -f.global.force_x);
            assert_eq!(b.global.force_y, -f.global.force_y);
            assert_eq!(b.global.spin_moment, f.global.spin_moment);
        }
    }
}

#[test]
fn speeds_below_the_minimum_are_raised_to_it() {
    for mode in [Mode::TableOnly, Mode::ExactOnly] {
        let e = evaluator(mode, params());
        let at = |speed: f64| {
            eval(&e, &OperatingPoint { speed, ..inside() })
                .outputs()
                .unwrap()
        };
        // V = 0 counts as forwards
        let forwards = at(DEFAULT_MINIMUM_SPEED);
        for v in [0.0, 1e-9, DEFAULT_MINIMUM_SPEED / 2.0] {
            assert_eq!(at(v), forwards, "{v}");
        }
        let backwards = at(-DEFAULT_MINIMUM_SPEED);
        assert_ne!(backwards, forwards);
        for v in [-1e-9, -DEFAULT_MINIMUM_SPEED / 2.0] {
            assert_eq!(at(v), backwards, "{v}");
        }
    }
}

#[test]
fn wetness_outside_the_unit_interval_is_clamped_with_a_notice() {
    let e = evaluator(Mode::ExactOnly, params());
    for (given, used) in [(1.5, 1.0), (-0.5, 0.0)] {
        let r = eval(
            &e,
            &OperatingPoint {
                wetness: given,
                ..inside()
            },
        );
        assert_eq!(notice_list(&r), [Notice::WetnessClamped { given, used }]);
        let want = eval(
            &e,
            &OperatingPoint {
                wetness: used,
                ..inside()
            },
        );
        assert!(want.notices.is_empty());
        assert_eq!(r.outputs().unwrap(), want.outputs().unwrap());
    }
}

#[test]
fn errors_name_the_values_the_caller_gave() {
    let e = evaluator(Mode::Auto, params());
    for speed in [30.0, -30.0] {
        let err = e
            .evaluate(
                &OperatingPoint {
                    creepage_x: 2.5,
                    speed,
                    ..inside()
                },
                None,
                &mut None,
            )
            .unwrap_err();
        assert!(err.to_string().contains("creepage-x: 2.5 "), "{err}");
    }
    // a NaN speed is not raised to the minimum speed
    let err = e
        .evaluate(
            &OperatingPoint {
                speed: f64::NAN,
                ..inside()
            },
            None,
            &mut None,
        )
        .unwrap_err();
    assert!(err.to_string().contains("speed: NaN"), "{err}");
}

#[test]
fn exact_solves_take_a_warm_start_and_a_tightened_tolerance() {
    let e = evaluator(Mode::ExactOnly, params());
    let p = OperatingPoint {
        creepage_x: 0.01,
        wetness: 0.0,
        ..inside()
    };
    let mut warm = None;
    let loose = e.evaluate(&p, None, &mut warm).unwrap();
    let loose = *loose.by.report().unwrap();
    assert!(warm.is_some());
    assert!(
        loose.converged && loose.residual > DERIVATIVE_TOLERANCE,
        "{loose:?}"
    );
    let tight = e
        .evaluate(&p, Some(DERIVATIVE_TOLERANCE), &mut None)
        .unwrap();
    let tight = *tight.by.report().unwrap();
    assert!(
        tight.converged && tight.residual <= DERIVATIVE_TOLERANCE,
        "{tight:?}"
    );
    // from the state of a nearby solution: the same fixed point, fewer iterations
    let near = OperatingPoint {
        creepage_x: 0.0101,
        ..p
    };
    let cold = e.evaluate(&near, None, &mut None).unwrap();
    let hot = e.evaluate(&near, None, &mut warm).unwrap();
    assert!(hot.by.report().unwrap().iterations < cold.by.report().unwrap().iterations);
    assert!(
        (hot.outputs().unwrap().force_x - cold.outputs().unwrap().force_x).abs()
            < 1e-5 * cold.outputs().unwrap().force_x.abs()
    );
    // a table evaluation leaves the warm start alone
    let before = warm.clone();
    let r = evaluator(Mode::TableOnly, params())
        .evaluate(&inside(), None, &mut warm)
        .unwrap();
    assert!(matches!(r.by, Evaluated::Table(_)));
    assert_eq!(warm, before);
}

#[test]
fn the_table_jacobian_is_that_of_evaluate_in_the_callers_frame() {
    // a minimum speed inside the table's speed range, so that raised speeds are still evaluated by table
    let e = Evaluator::new(
        Model::new(params()).unwrap(),
        Mode::Auto,
        Some(table()),
        Policy {
            minimum_speed: 25.0,
            ..Policy::default()
        },
    )
    .unwrap();
    // output and input scales for an absolute floor of the comparison
    let out_scale = [1e5, 1e5, 1e3, 1.0, 300.0, 1.0];
    let in_scale = [1e-2, 1e-2, 1.0, 1e5, 30.0, 1.0];
    let steps = [1e-7, 1e-7, 1e-6, 1.0, 1e-5, 1e-7];
    let set = |p: &mut OperatingPoint, c: usize, x: f64| match c {
        0 => p.creepage_x = x,
        1 => p.creepage_y = x,
        2 => p.spin = x,
        3 => p.normal_force = x,
        4 => p.speed = x,
        _ => p.wetness = x,
    };
    let get = |p: &OperatingPoint, c: usize| {
        [
            p.creepage_x,
            p.creepage_y,
            p.spin,
            p.normal_force,
            p.speed,
            p.wetness,
        ][c]
    };
    // rolling backwards (the creepages, F_x and F_y turn); below the minimum speed with a clamped wetness
    // (the columns of V and w vanish). Off the faces of the simplices (where fractions along two linear
    // axes are equal, the derivative of the interpolant jumps): V = 31, w = 0.13.
    let backwards = OperatingPoint {
        speed: -31.0,
        wetness: 0.13,
        ..inside()
    };
    let slow = OperatingPoint {
        speed: -10.0,
        wetness: -0.5,
        ..inside()
    };
    for p in [backwards, slow] {
        let (jac, _) = e.table_jacobian(&p).unwrap();
        let jac = jac.expect("by table");
        for c in 0..6 {
            let at = |x: f64| {
                let mut q = p;
                set(&mut q, c, get(&p, c) + x);
                let r = eval(&e, &q);
                assert!(matches!(r.by, Evaluated::Table(_)));
                values(&r.outputs().unwrap())
            };
            let (hi, lo) = (at(steps[c]), at(-steps[c]));
            for r in 0..6 {
                let fd = (hi[r] - lo[r]) / (2.0 * steps[c]);
                let floor = 1e-6 * out_scale[r] / in_scale[c];
                assert!(
                    (jac[r][c] - fd).abs() <= 1e-4 * fd.abs() + floor,
                    "{p:?}: output {r}, input {c}: {} vs {fd}",
                    jac[r][c]
                );
            }
        }
        assert!(jac.iter().flatten().any(|d| *d != 0.0));
    }
    let (jac, _) = e.table_jacobian(&slow).unwrap();
    let jac = jac.unwrap();
    assert!(jac.iter().all(|row| row[4] == 0.0 && row[5] == 0.0));
    let (jac, _) = e.table_jacobian(&backwards).unwrap();
    assert!(jac.unwrap().iter().any(|row| row[4] != 0.0));
    // where the exact solver evaluates there is no table Jacobian; the notices are evaluate's
    let fast = OperatingPoint {
        speed: 60.0,
        wetness: -1.0,
        ..inside()
    };
    let (jac, notices) = e.table_jacobian(&fast).unwrap();
    assert!(jac.is_none());
    assert_eq!(notices, eval(&e, &fast).notices);
    assert_eq!(notices.iter().count(), 2);
}

/// A geometry other than the default's: curvatures of a flange-root contact (a/b > 1).
fn flange_root() -> Geometry {
    Geometry::of_inputs(4.0, 0.8, [0.0, 0.0])
}

#[test]
fn a_geometry_per_evaluation_is_the_model_with_that_geometry_bit_for_bit() {
    let exact = evaluator(Mode::ExactOnly, params());
    let backwards = OperatingPoint {
        speed: -20.0,
        ..inside()
    };
    for geometry in [
        flange_root(),
        Geometry::of_inputs(4.0, 0.8, [4e-3, 7e-3]),
        params().geometry,
    ] {
        let mut with = params();
        with.geometry = geometry.clone();
        let want = evaluator(Mode::ExactOnly, with.clone());
        for point in [inside(), backwards] {
            let (got, want) = (
                exact
                    .evaluate_at(&point, &geometry, None, &mut None)
                    .unwrap(),
                want.evaluate(&point, None, &mut None).unwrap(),
            );
            assert_eq!(got, want);
            let s = crate::solve(&with, &Solved::of(&point, 0.01).point).unwrap();
            assert_eq!(
                got.patch,
                Patch {
                    semi_axis_a: s.global.semi_axis_a,
                    semi_axis_b: s.global.semi_axis_b,
                    peak_pressure: s.global.peak_pressure,
                }
            );
            assert_eq!(got.frictional_power(), Some(s.global.frictional_power));
        }
    }
    // the model's own geometry is evaluate's
    let g = params().geometry;
    assert_eq!(
        exact.evaluate_at(&inside(), &g, None, &mut None).unwrap(),
        eval(&exact, &inside())
    );
}

#[test]
fn prescribed_semi_axes_win_over_the_curvatures() {
    let exact = evaluator(Mode::ExactOnly, params());
    let axes = [4e-3, 7e-3];
    let with_flange = exact
        .evaluate_at(
            &inside(),
            &Geometry::of_inputs(4.0, 0.8, axes),
            None,
            &mut None,
        )
        .unwrap();
    let with_default = exact
        .evaluate_at(
            &inside(),
            &Geometry::of_inputs(1.015, 0.4215, axes),
            None,
            &mut None,
        )
        .unwrap();
    assert_eq!(with_flange, with_default);
    let p = &with_flange.patch;
    assert_eq!((p.semi_axis_a, p.semi_axis_b), (axes[0], axes[1]));
    let p0 = 3.0 * inside().normal_force / (2.0 * std::f64::consts::PI * axes[0] * axes[1]);
    assert_eq!(p.peak_pressure, p0);
    // unused curvatures are not checked; no semi-axes (0, 0) means the curvatures
    assert!(
        exact
            .evaluate_at(
                &inside(),
                &Geometry::of_inputs(0.0, -1.0, axes),
                None,
                &mut None
            )
            .is_ok()
    );
    let by_curvatures = exact
        .evaluate_at(&inside(), &flange_root(), None, &mut None)
        .unwrap();
    assert_ne!(by_curvatures.patch, with_flange.patch);
}

#[test]
fn auto_falls_back_for_another_geometry_and_uses_the_table_for_its_own() {
    let auto = evaluator(Mode::Auto, params());
    let r = auto
        .evaluate_at(&inside(), &flange_root(), None, &mut None)
        .unwrap();
    assert!(matches!(r.by, Evaluated::Exact(_)));
    assert_eq!(notice_list(&r), [Notice::FellBack(Fallback::OtherGeometry)]);
    assert!(
        auto.table_jacobian_at(&inside(), &flange_root())
            .unwrap()
            .0
            .is_none()
    );
    // the table's geometry by table, with the exact solver's normal contact and the interpolated
    // frictional power
    let g = table().params().geometry.clone();
    let r = auto.evaluate_at(&inside(), &g, None, &mut None).unwrap();
    assert!(matches!(r.by, Evaluated::Table(_)));
    assert!(r.notices.is_empty());
    assert_eq!(r, eval(&auto, &inside()));
    let s = crate::solve(&params(), &inside()).unwrap();
    // (interpolated on this coarse table's points; at a table point it is the exact solver's, see
    // auto_uses_the_table_where_usable_and_else_the_exact_solver_with_the_reason)
    let power = r.frictional_power().expect("a format 2 table stores it");
    assert!(power > 0.0 && s.global.frictional_power > 0.0);
    assert_eq!(r.patch.semi_axis_a, s.global.semi_axis_a);
    assert_eq!(r.patch.semi_axis_b, s.global.semi_axis_b);
    assert_eq!(r.patch.peak_pressure, s.global.peak_pressure);
    // a model of another geometry uses the table at the table's geometry
    let mut other = params();
    other.geometry = flange_root();
    let auto_other = evaluator(Mode::Auto, other);
    assert!(!auto_other.matches());
    let r = eval(&auto_other, &inside());
    assert_eq!(notice_list(&r), [Notice::FellBack(Fallback::OtherGeometry)]);
    let r = auto_other
        .evaluate_at(&inside(), &g, None, &mut None)
        .unwrap();
    assert_eq!(r, eval(&auto, &inside()));
    // other parameters are named before another geometry
    let mut rough = params();
    rough.roughness.k_r = 0.6;
    let r = evaluator(Mode::Auto, rough)
        .evaluate_at(&inside(), &flange_root(), None, &mut None)
        .unwrap();
    assert_eq!(
        notice_list(&r),
        [Notice::FellBack(Fallback::OtherParameters)]
    );
    // table-only refuses another geometry
    let only = evaluator(Mode::TableOnly, params());
    let e = only
        .evaluate_at(&inside(), &flange_root(), None, &mut None)
        .unwrap_err();
    assert!(matches!(e, Error::TableGeometry { .. }), "{e}");
    assert_eq!(
        only.evaluate_at(&inside(), &g, None, &mut None).unwrap(),
        eval(&only, &inside())
    );
}

#[test]
fn an_invalid_geometry_is_an_error_naming_it() {
    let auto = evaluator(Mode::Auto, params());
    let err = |g: Geometry| {
        auto.evaluate_at(&inside(), &g, None, &mut None)
            .unwrap_err()
            .to_string()
    };
    let e = err(Geometry::of_inputs(f64::NAN, 0.4, [0.0, 0.0]));
    assert!(e.contains("geometry.curvature_x: NaN"), "{e}");
    let e = err(Geometry::of_inputs(1.0, 2e3, [0.0, 0.0]));
    assert!(e.contains("geometry.curvature_y: 2000"), "{e}");
    // one semi-axis alone is not a prescribed ellipse
    let e = err(Geometry::of_inputs(1.0, 0.4, [5e-3, 0.0]));
    assert!(e.contains("geometry.semi_axes[1]: 0"), "{e}");
    let e = err(Geometry::of_inputs(1.0, 0.4, [-5e-3, 6e-3]));
    assert!(e.contains("geometry.semi_axes[0]: -0.005"), "{e}");
    // a lifted wheel checks nothing
    let lifted = OperatingPoint {
        normal_force: 0.0,
        ..inside()
    };
    let r = auto
        .evaluate_at(
            &lifted,
            &Geometry::of_inputs(f64::NAN, 0.4, [0.0, 0.0]),
            None,
            &mut None,
        )
        .unwrap();
    assert!(matches!(r.by, Evaluated::Lifted(_)));
    assert_eq!(r.patch.semi_axis_a, 0.0);
    assert_eq!(r.frictional_power(), Some(0.0));
}

/// A solution's every number, bit for bit: Rust's `Debug` prints each f64 as the shortest decimal that
/// reads back to the same bits, so equal strings are equal bits (global results, every field, report).
fn all_bits(s: &crate::Solution) -> String {
    format!("{s:?}")
}

#[test]
fn a_reused_setup_gives_the_bits_of_a_fresh_one() {
    let model = Model::new(params()).unwrap();
    let dry = OperatingPoint {
        wetness: 0.0,
        ..inside()
    };
    let other_eta = OperatingPoint {
        creepage_y: 0.002,
        ..dry
    };
    let wet = OperatingPoint {
        wetness: 0.8,
        ..other_eta
    };
    let other_xi = OperatingPoint {
        creepage_x: 0.004,
        ..wet
    };
    let other_load = OperatingPoint {
        normal_force: 90e3,
        ..other_xi
    };
    // (point, geometry, set-up parts reused: shape, microcontact and heat model when the contact and
    // the surface speeds are the last solve's; shape and microcontact when only the speeds or the load
    // changed; only the microcontact for another geometry)
    let steps = [
        (dry, params().geometry, 0),
        (other_eta, params().geometry, 3),
        (wet, params().geometry, 3),
        (other_xi, params().geometry, 2),
        (other_load, params().geometry, 2),
        (other_load, flange_root(), 1),
        (other_load, flange_root(), 3),
        (dry, params().geometry, 1),
    ];
    let mut warm = None;
    for (k, (point, geometry, reused)) in steps.into_iter().enumerate() {
        let before = model.setup_reuses();
        let with = model.with(&geometry, None, None);
        let cached = with.solve_from(&point, warm.as_ref()).unwrap();
        assert_eq!(model.setup_reuses() - before, reused, "step {k}");
        let mut fresh = params();
        fresh.geometry = geometry;
        let uncached = crate::solver::solve_from(&fresh, &point, warm.as_ref()).unwrap();
        assert_eq!(all_bits(&cached), all_bits(&uncached), "step {k}");
        // and a cold solve is the same whatever the cache holds
        let cold = crate::solver::solve(&fresh, &point).unwrap();
        assert_eq!(
            all_bits(&with.solve(&point).unwrap()),
            all_bits(&cold),
            "step {k}"
        );
        warm = cached.warm_start();
    }
}

/// With the exact tangential solver the set-up holds its influence operator too: reused while the grid
/// and the elastic constants are unchanged, and a solve with the cached operator gives the bits of a fresh
/// one (warm or cold).
#[test]
fn a_reused_steady_rolling_operator_gives_the_bits_of_a_fresh_one() {
    let exact = Params {
        tangential: crate::params::Tangential::Exact,
        ..params()
    };
    let model = Model::new(exact.clone()).unwrap();
    let other_xi = OperatingPoint {
        creepage_x: 0.004,
        ..inside()
    };
    let other_load = OperatingPoint {
        normal_force: 90e3,
        ..other_xi
    };
    // (point, set-up parts reused: shape, microcontact, heat model and operator for the same contact and
    // speeds; shape, microcontact and operator for other surface speeds; shape and microcontact for
    // another load, whose ellipse needs another operator)
    let steps = [(inside(), 0), (inside(), 4), (other_xi, 3), (other_load, 2)];
    let mut warm = None;
    for (k, (point, reused)) in steps.into_iter().enumerate() {
        let before = model.setup_reuses();
        let cached = model.solve_from(&point, warm.as_ref()).unwrap();
        assert_eq!(model.setup_reuses() - before, reused, "step {k}");
        assert!(cached.report.tangential_sweeps > 0, "step {k}");
        let uncached = crate::solver::solve_from(&exact, &point, warm.as_ref()).unwrap();
        assert_eq!(all_bits(&cached), all_bits(&uncached), "step {k}");
        warm = cached.warm_start();
    }
}

/// Largest difference of the global results of two solutions: forces relative to F_N, temperature rise
/// and fluid load share relative to themselves.
fn global_difference(a: &crate::Solution, b: &crate::Solution) -> f64 {
    let (a, b) = (&a.global, &b.global);
    let t0 = params().material.bulk_temperature;
    let rise = |x: Option<f64>| x.unwrap() - t0;
    [
        (a.force_x - b.force_x).abs() / a.normal_force,
        (a.force_y - b.force_y).abs() / a.normal_force,
        (rise(a.max_temperature) - rise(b.max_temperature)).abs() / rise(a.max_temperature),
        (a.fluid_load_fraction.unwrap() - b.fluid_load_fraction.unwrap()).abs()
            / a.fluid_load_fraction.unwrap().max(1e-3),
    ]
    .into_iter()
    .fold(0.0, f64::max)
}

#[test]
fn a_warm_step_needs_two_iterations_on_an_unchanged_input_and_agrees_with_a_cold_one() {
    let mut p = params();
    p.grid.nx = 9;
    p.grid.ny = 9;
    let model = Model::new(p).unwrap();
    let tolerance = params().solver.tolerance;
    for wetness in [0.0, 0.5, 1.0] {
        let point = OperatingPoint {
            creepage_x: 0.02,
            wetness,
            ..inside()
        };
        let cold = model.solve(&point).unwrap();
        let same = model
            .solve_from(&point, cold.warm_start().as_ref())
            .unwrap();
        assert!(
            same.report.converged && same.report.iterations <= 2,
            "w = {wetness}: {:?}",
            same.report
        );
        assert!(
            global_difference(&same, &cold) <= tolerance,
            "w = {wetness}"
        );
        // the next step of a 1 kHz MBS run: load, speed and creepage moved a little (the temperature by
        // about 1 %, which the outer iteration's contraction, ~0.02 per iteration here, takes three more
        // iterations to settle to the tolerance)
        let next = OperatingPoint {
            normal_force: point.normal_force * 1.01,
            speed: point.speed - 5e-4,
            creepage_x: point.creepage_x * 1.001,
            ..point
        };
        let warm = model.solve_from(&next, cold.warm_start().as_ref()).unwrap();
        let fresh = model.solve(&next).unwrap();
        assert!(
            warm.report.converged && warm.report.iterations < fresh.report.iterations,
            "w = {wetness}: {:?} from the last step's state, {:?} cold",
            warm.report,
            fresh.report
        );
        assert!(
            global_difference(&warm, &fresh) <= tolerance,
            "w = {wetness}: {}",
            global_difference(&warm, &fresh)
        );
    }
}

/// A small table for [`params`] over [`small_axes`] with the points of some dimensions replaced
/// (`changes`: dimension, points), built once per key in memory.
fn table_with(key: usize, changes: &[(usize, &[f64])]) -> Arc<Table> {
    static TABLES: [OnceLock<Arc<Table>>; 2] = [OnceLock::new(), OnceLock::new()];
    TABLES[key]
        .get_or_init(|| {
            let mut axes = small_axes();
            for (d, points) in changes {
                axes.0[*d].points = points.to_vec();
            }
            let files = crate::table::build(&params(), &axes, None, &|| ()).unwrap();
            Arc::new(Table::from_files(files, None).unwrap())
        })
        .clone()
}

#[test]
fn several_tables_take_each_point_to_the_first_that_holds_it() {
    use crate::table::axes::{PRESSURE, RATIO, SPEED};
    // a flange-root region of contact geometry (a/b 2–2.4, p_ref 1.0–1.2 GPa), and the small table's
    // region with a narrower speed range (25–30 m/s against 20–40 m/s)
    let flange = table_with(0, &[(RATIO, &[2.0, 2.4]), (PRESSURE, &[1.0e9, 1.2e9])]);
    let narrow = table_with(1, &[(SPEED, &[25.0, 30.0])]);
    let model = || Model::new(params()).unwrap();
    let with = |mode: Mode, tables: &[&Arc<Table>]| {
        let tables = tables.iter().map(|t| Arc::clone(t)).collect();
        Evaluator::with_tables(model(), mode, tables, Policy::default()).unwrap()
    };
    let set = with(Mode::Auto, &[&narrow, &table(), &flange]);
    assert_eq!(set.tables().len(), 3);
    assert!(Arc::ptr_eq(set.table().unwrap(), &narrow));
    assert!(set.matches());
    let by_table = |e: &Evaluator, p: &OperatingPoint, g: &Geometry| {
        let r = e.evaluate_at(p, g, None, &mut None).unwrap();
        assert!(notice_list(&r).is_empty(), "{:?}", notice_list(&r));
        match r.by {
            Evaluated::Table(o) => values(&o),
            other => panic!("not by table: {other:?}"),
        }
    };
    let own = params().geometry;
    // the model's contact at 27 m/s: the narrow table (first); at 35 m/s, outside its speeds: the small one
    for (speed, first) in [(27.0, &narrow), (35.0, &table())] {
        let p = OperatingPoint { speed, ..inside() };
        let want = by_table(&with(Mode::Auto, &[first]), &p, &own);
        assert_eq!(by_table(&set, &p, &own), want, "{speed}");
        let other = if Arc::ptr_eq(first, &narrow) {
            table()
        } else {
            narrow.clone()
        };
        if speed < 30.0 {
            // both hold it: the values differ by their interpolation (the choice is visible)
            assert_ne!(by_table(&with(Mode::Auto, &[&other]), &p, &own), want);
        }
    }
    // a flange-root contact (a/b 2.2, p_ref 1.1 GPa as prescribed semi-axes): the flange table
    let [a, b] = crate::table::coords::semi_axes(2.2, 1.1e9, inside().normal_force);
    let root = Geometry::of_inputs(1.0, 1.0, [a, b]);
    let want = by_table(&with(Mode::Auto, &[&flange]), &inside(), &root);
    assert_eq!(by_table(&set, &inside(), &root), want);
    // each evaluation names the table that evaluated it by its index in the list (None: exact)
    let served =
        |p: &OperatingPoint, g: &Geometry| set.evaluate_at(p, g, None, &mut None).unwrap().table;
    let at = |speed| OperatingPoint { speed, ..inside() };
    assert_eq!(served(&at(27.0), &own), Some(0));
    assert_eq!(served(&at(35.0), &own), Some(1));
    assert_eq!(served(&inside(), &root), Some(2));
    // a contact no table covers: the exact solver, the reason another geometry
    let [a, b] = crate::table::coords::semi_axes(1.0, 0.9e9, inside().normal_force);
    let between = Geometry::of_inputs(1.0, 1.0, [a, b]);
    let r = set
        .evaluate_at(&inside(), &between, None, &mut None)
        .unwrap();
    assert!(matches!(r.by, Evaluated::Exact(_)));
    assert_eq!(r.table, None);
    assert_eq!(notice_list(&r), [Notice::FellBack(Fallback::OtherGeometry)]);
    // covered but outside every covering table's ranges (60 m/s): the exact solver, outside the ranges
    let fast = OperatingPoint {
        speed: 60.0,
        ..inside()
    };
    let r = eval(&set, &fast);
    assert!(matches!(r.by, Evaluated::Exact(_)));
    assert_eq!(notice_list(&r), [Notice::FellBack(Fallback::OutsideRanges)]);
    // table-only: clamped to the first covering table (the narrow one: 30 m/s), or refused
    let only = with(Mode::TableOnly, &[&narrow, &table(), &flange]);
    let r = eval(&only, &fast);
    assert_eq!(notice_list(&r), [Notice::Clamped]);
    let clamped = |e: &Evaluator| match eval(e, &fast).by {
        Evaluated::Table(o) => values(&o),
        other => panic!("not by table: {other:?}"),
    };
    assert_eq!(clamped(&only), clamped(&with(Mode::TableOnly, &[&narrow])));
    let e = only
        .evaluate_at(&inside(), &between, None, &mut None)
        .unwrap_err();
    assert!(matches!(e, Error::TableGeometry { .. }), "{e}");
    // a table for other parameters is passed over; with none for the model's, that is the reason
    let mut other = params();
    other.fluid.k_wet = 0.3;
    let stale = Evaluator::with_tables(
        Model::new(other.clone()).unwrap(),
        Mode::Auto,
        vec![table()],
        Policy::default(),
    )
    .unwrap();
    let r = eval(&stale, &inside());
    assert_eq!(
        notice_list(&r),
        [Notice::FellBack(Fallback::OtherParameters)]
    );
}

/// Evaluators (by mode) of the model with the small table whose nodes at its last wetness node are changed
/// by `edit(files, node)`.
fn with_last_wetness_nodes(
    edit: impl Fn(&mut crate::table::TableFiles, usize),
) -> impl Fn(Mode) -> Evaluator {
    use crate::table::axes::WET;
    let mut files = crate::table::build(&params(), &small_axes(), None, &|| ()).unwrap();
    let shape = files.axes.shape();
    let stride: usize = shape[WET + 1..].iter().product();
    for i in 0..files.converged.len() {
        if (i / stride) % shape[WET] == shape[WET] - 1 {
            edit(&mut files, i);
        }
    }
    let table = Arc::new(Table::from_files(files, None).unwrap());
    move |mode| {
        Evaluator::new(
            Model::new(params()).unwrap(),
            mode,
            Some(table.clone()),
            Policy::default(),
        )
        .unwrap()
    }
}

/// Mode auto of `with` solves the point inside() exactly, saying `why`; table-only serves it as the table
/// interpolates it, inside the ranges, with nothing to report: its output.
fn auto_solves_inside_exactly(with: &impl Fn(Mode) -> Evaluator, why: Fallback) -> TableOutput {
    let r = eval(&with(Mode::Auto), &inside());
    assert!(matches!(r.by, Evaluated::Exact(_)));
    assert_eq!(notice_list(&r), [Notice::FellBack(why)]);
    let s = crate::solve(&params(), &inside()).unwrap();
    assert_eq!(r.outputs().unwrap().force_x, s.global.force_x);
    assert!(r.outputs().unwrap().converged);
    let r = eval(&with(Mode::TableOnly), &inside());
    let Evaluated::Table(o) = r.by else {
        panic!("table-only evaluated by {:?}", r.by)
    };
    assert!(r.notices.is_empty() && o.in_range);
    o
}

#[test]
fn auto_solves_points_in_cells_the_table_does_not_resolve_and_table_only_serves_them() {
    // T_max 400 K higher at the last wetness node: every cell next to it holds the jump, the point
    // inside() among them
    let jumpy = with_last_wetness_nodes(|f, i| f.outputs[3][i] += 400.0);
    let o = auto_solves_inside_exactly(&jumpy, Fallback::Unresolved);
    assert!(!o.resolved && o.converged);
    // the unchanged table resolves the point
    let r = eval(&evaluator(Mode::Auto, params()), &inside());
    assert!(matches!(r.by, Evaluated::Table(o) if o.resolved));
}

#[test]
fn auto_solves_points_interpolated_from_unconverged_table_points_and_table_only_flags_them() {
    // the nodes at the last wetness node flagged as not converged: the point inside() interpolates from
    // some of them
    let flagged = with_last_wetness_nodes(|f, i| f.converged[i] = 0);
    let o = auto_solves_inside_exactly(&flagged, Fallback::UnconvergedNodes);
    assert!(o.resolved && !o.converged);
}

/// Mode auto solves the points no table serves on the grid of each contact ([`fallback_cells`] of its
/// Hertz ellipse and film) where the model keeps the default grid: the bits of the model solved on that
/// grid, which the results name. The model's grid with [`FallbackGrid::Model`], in mode exact-only and
/// where the parameters set a grid; given cells override both.
#[test]
fn auto_falls_back_on_the_grid_of_each_contact() {
    use crate::params::fallback_cells;
    let default = Params::default();
    let long = Geometry::of_inputs(0.92, 3.5, [0.0, 0.0]);
    let with = |mode, params: Params, fallback_grid| {
        Evaluator::new(
            Model::new(params).unwrap(),
            mode,
            Some(table()),
            Policy {
                fallback_grid,
                ..Policy::default()
            },
        )
        .unwrap()
    };
    let auto = with(Mode::Auto, default.clone(), FallbackGrid::PerContact);
    let dry = OperatingPoint {
        wetness: 0.0,
        ..inside()
    };
    let wet = inside();
    let mut grids = Vec::new();
    for p in [dry, wet] {
        let cells = auto.exact_cells(&p, &long).unwrap();
        let hertz = crate::solver::ContactShape::of(&long, &default.material)
            .unwrap()
            .contact(p.normal_force)
            .unwrap();
        assert!(hertz.a > 2.0 * hertz.b, "a long contact");
        assert_eq!(cells, fallback_cells(hertz.a, hertz.b, p.wetness > 0.0));
        let r = auto.evaluate_at(&p, &long, None, &mut None).unwrap();
        assert_eq!(
            notice_list(&r),
            [Notice::FellBack(Fallback::OtherParameters)]
        );
        let Evaluated::Exact(x) = &r.by else {
            panic!("the exact solver evaluates")
        };
        assert_eq!(x.cells, cells);
        let mut on = default.clone();
        on.geometry = long.clone();
        [on.grid.nx, on.grid.ny] = cells;
        assert_eq!(x.global, crate::solve(&on, &p).unwrap().global);
        grids.push(cells);
    }
    // a film needs more lateral cells on a long contact
    assert_eq!(grids, [[24, 6], [24, 12]]);
    let cells_of = |e: &Evaluator| e.exact_cells(&wet, &long).unwrap();
    assert_eq!(
        cells_of(&with(Mode::Auto, default.clone(), FallbackGrid::Model)),
        [30, 30]
    );
    assert_eq!(
        cells_of(&with(
            Mode::ExactOnly,
            default.clone(),
            FallbackGrid::PerContact
        )),
        [30, 30]
    );
    assert_eq!(
        cells_of(&with(Mode::Auto, params(), FallbackGrid::PerContact)),
        [6, 6]
    );
    let mut by_accuracy = default.clone();
    by_accuracy.grid.accuracy = 0.01;
    assert_eq!(
        cells_of(&with(Mode::Auto, by_accuracy, FallbackGrid::PerContact)),
        [10, 10]
    );
    // given cells, and a lifted wheel (nothing solved: the model's grid)
    let r = auto
        .evaluate_on(&wet, &long, Some([8, 6]), None, &mut None)
        .unwrap();
    let Evaluated::Exact(x) = &r.by else {
        panic!("the exact solver evaluates")
    };
    assert_eq!(x.cells, [8, 6]);
    let lifted = OperatingPoint {
        normal_force: 0.0,
        ..wet
    };
    assert_eq!(auto.exact_cells(&lifted, &long).unwrap(), [30, 30]);
}
