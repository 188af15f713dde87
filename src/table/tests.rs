use super::axes::*;
use super::build::tabulate;
use super::flags::*;
use super::interp::Corners;
use super::kernel::*;
use super::layout::*;
use super::testing::*;
use super::*;
use crate::params::FrictionLaw;
use std::sync::Arc;

/// A function with the model's symmetries, linear in each creepage coordinate and affine in the linear
/// ones: the interpolant reproduces it exactly. Monomials x^a·y^b·φ^c: the ξ mirror multiplies them by
/// (−1)^a, the (η, φ) mirror by (−1)^(b+c). F_x: odd, even; F_y and M_z: even, odd; T: even, even.
fn symmetric_multilinear(c: &[f64; DIMS]) -> [f64; OUTPUTS] {
    let [x, y, p, f, v, w, r, pr] = *c;
    let lin = 1.0 + 2e-6 * f - 0.003 * v + 0.5 * w + 0.2 * r - 1e-10 * pr;
    [
        lin * (-0.03 * x + 0.04 * x * y * p),
        lin * (-0.02 * y + 0.01 * p),
        lin * (0.02 * p - 0.007 * y),
        300.0 + 50.0 * lin * (1.0 + 0.04 * y * p),
        0.3 * w + 0.001 * v,
        lin * (0.01 + 0.002 * x * x + 0.003 * y * p),
    ]
}

/// A smooth function with the symmetries and creep-curve-like saturation (not reproduced exactly).
fn symmetric_saturating(c: &[f64; DIMS]) -> [f64; OUTPUTS] {
    let [x, y, p, f, v, w, r, pr] = *c;
    let lin = (1.0 + 2e-6 * f) * (1.0 - 0.003 * v) * (1.0 + 0.5 * w) * (1.0 + 0.1 * r)
        / (1.0 + 1e-10 * pr);
    let sat = |u: f64| (u / 0.5).tanh();
    [
        -lin * sat(x) * (1.0 + 0.3 * y * p),
        -lin * (sat(y) + 0.02 * p),
        lin * (0.02 * p - sat(y) * (1.0 + 0.01 * x * x)),
        300.0 + 50.0 * lin * (0.01 * x * x + y * p),
        0.3 * w * (1.0 - 0.002 * v),
        0.05 * lin * sat(x).abs(),
    ]
}

/// Random table coordinates inside [`tiny_axes`] whose raw creepages lie within its raw limits.
fn random_coordinates(rng: &mut verify::SplitMix64) -> [f64; DIMS] {
    let mut u = || rng.uniform();
    [
        -8.0 + 16.0 * u(),
        -3.0 + 6.0 * u(),
        -0.4 + 0.8 * u(),
        50e3 + 50e3 * u(),
        10.0 + 20.0 * u(),
        u(),
        0.5 + 0.1 * u(),
        0.7e9 + 0.15e9 * u(),
    ]
}

/// `axes` (with one normal force point, F_ref among them) as a table by similarity: the normal force
/// axis F_ref alone, the speed points equivalent speeds.
fn similar(mut axes: Axes) -> Axes {
    axes.0[FORCE].points = vec![axes::REFERENCE_FORCE];
    axes.0[FORCE].logarithmic = false;
    axes.0[SPEED].similarity = true;
    axes.validate().unwrap();
    axes
}

/// The operating point and contact of table coordinates `q`, the contact's semi-axes growing with the
/// load like F_N^e.
fn at(t: &Table, q: &[f64; DIMS], e: f64) -> (OperatingPoint, Ellipse) {
    let (p, mut el) = t.coordinates().point(q).unwrap();
    el.load_exponent = e;
    (p, el)
}

/// The point and contact with input d (ξ, η, φ, F_N, V, w) moved by h (the semi-axes follow F_N).
fn moved(p: &OperatingPoint, e: &Ellipse, d: usize, h: f64) -> (OperatingPoint, Ellipse) {
    let mut p = *p;
    let mut e = *e;
    match d {
        0 => p.creepage_x += h,
        1 => p.creepage_y += h,
        2 => p.spin += h,
        3 => {
            let s = ((p.normal_force + h) / p.normal_force).powf(e.load_exponent);
            p.normal_force += h;
            e.a *= s;
            e.b *= s;
        }
        4 => p.speed += h,
        _ => p.wetness += h,
    }
    (p, e)
}

/// The six outputs of normalised values `v` at point `p` with contact `e`.
fn physical(p: &OperatingPoint, e: &Ellipse, v: &[f64; OUTPUTS]) -> [f64; JACOBIAN_ROWS] {
    let f = p.normal_force;
    [
        f * v[0],
        f * v[1],
        f * e.radius() * v[2],
        v[0].hypot(v[1]),
        v[3],
        v[4],
    ]
}

/// [`tiny_axes`] with knee-blended creepage coordinates (raw scales near the default contact's k).
fn blended(mut axes: Axes) -> Axes {
    for (d, k) in [200.0, 170.0, 0.4].into_iter().enumerate() {
        axes.0[d].raw_scale = Some(k);
    }
    axes.validate().unwrap();
    axes
}

/// `axes` (knee-blended) with the spin's raw scale in proportion to the contact's size sqrt(a² + b²),
/// 0.4 m at 6 mm: k_r moves with the contact's shape, size and (similarity) load.
fn sized(mut axes: Axes) -> Axes {
    axes.0[PHI].raw_length = Some(6e-3);
    axes.validate().unwrap();
    axes
}

/// The linear dimensions of [`tiny_axes`] that can be interpolated in ln x (all but w), with a point
/// of each axis.
const LOG_DIMS: [(usize, f64); 4] = [
    (FORCE, 50e3),
    (SPEED, 10.0),
    (RATIO, 0.5),
    (PRESSURE, 0.7e9),
];

/// `axes` with F_N, V, a/b and p_ref interpolated in ln x.
fn logarithmic(mut axes: Axes) -> Axes {
    for (d, _) in LOG_DIMS {
        axes.0[d].logarithmic = true;
    }
    axes.validate().unwrap();
    axes
}

/// [`symmetric_multilinear`] of x0·(1 + ln(x/x0)) instead of x along F_N, V, a/b, p_ref: multilinear
/// in their logarithms, the data class log axes reproduce.
fn symmetric_multilinear_in_logs(c: &[f64; DIMS]) -> [f64; OUTPUTS] {
    let mut l = *c;
    for (d, x0) in LOG_DIMS {
        l[d] = x0 * (1.0 + (c[d] / x0).ln());
    }
    symmetric_multilinear(&l)
}

/// [`tiny_axes`] with a third speed point, 20 m/s, and the cell 20–30 m/s interpolated in √V if `sqrt`.
fn sqrt_speeds(sqrt: bool) -> Axes {
    let mut axes = tiny_axes();
    axes.0[SPEED].points = vec![10.0, 20.0, 30.0];
    axes.0[SPEED].sqrt_from = sqrt.then_some(20.0);
    axes.validate().unwrap();
    axes
}

/// [`symmetric_multilinear`] of s(V) = V up to 20 m/s, 20 + 2√20·(√V − √20) above (C¹ at 20 m/s)
/// instead of V: the data class of [`sqrt_speeds`] (linear in V in the first cell, in √V in the second).
fn symmetric_multilinear_in_sqrt_speed(c: &[f64; DIMS]) -> [f64; OUTPUTS] {
    let mut l = *c;
    let r = 20f64.sqrt();
    if c[SPEED] > 20.0 {
        l[SPEED] = 20.0 + 2.0 * r * (c[SPEED].sqrt() - r);
    }
    symmetric_multilinear(&l)
}

/// `f` with its heat outputs read as what tables of `params` with `axes` interpolate: T_max's as the
/// variable G ([`rise`]) and both T_max's and P_f/(F_N·V)'s per unit of the direction factor Λ of the
/// point ([`heating`]). The table of the wrapped function stores T_max = G⁻¹(Λ·f's value) and Λ·f's
/// P_f, so f's values are the data class the interpolant reproduces (f's values 300–400 K as G are T_max
/// of about 600–700 K, through the yield-stress anomaly; Λ puts FASTSIM's kinks at η = 0, φ = 0 into
/// the data).
fn in_rise(
    params: &Params,
    axes: &Axes,
    f: impl Fn(&[f64; DIMS]) -> [f64; OUTPUTS],
) -> impl Fn(&[f64; DIMS]) -> [f64; OUTPUTS] {
    let rise = RiseVariable::new(&params.material);
    let coordinates = Coordinates::new(params, axes);
    move |c| {
        let (p, e) = coordinates.point(c).unwrap();
        let lambda = coordinates.of(&p, &e).unwrap().heating;
        let mut v = f(c);
        v[3] = rise.temperature(lambda * v[3]);
        v[5] *= lambda;
        v
    }
}

#[test]
fn interpolant_reproduces_symmetric_multilinear_functions_and_their_derivatives() {
    let params = coarse_params();
    for axes in [
        tiny_axes(),
        blended(tiny_axes()),
        sized(blended(tiny_axes())),
    ] {
        let f = in_rise(&params, &axes, symmetric_multilinear);
        reproduces(&synthetic(&axes, &params, &f), &f);
    }
    // log axes: exact for data multilinear in the logarithms (and not for data multilinear in x)
    let log_axes = logarithmic(tiny_axes());
    let f_log = in_rise(&params, &log_axes, symmetric_multilinear_in_logs);
    let log = synthetic(&log_axes, &params, &f_log);
    reproduces(&log, &f_log);
    let f = in_rise(&params, &log_axes, symmetric_multilinear);
    let t = synthetic(&log_axes, &params, &f);
    let c = [0.0, 0.0, 0.0, 75e3, 10.0, 0.5, 0.5, 0.7e9];
    let (p, e) = at(&t, &c, 0.0);
    // G = 300 + 50·(1 + 2e-6·F_N + …): F_N interpolated at ln(1.5)/ln(2) of its cell, not at 1/2
    let off = t.rise.of(t.evaluate(&p, &e).unwrap().max_temperature) - symmetric_multilinear(&c)[3];
    assert!(
        (off - 50.0 * 2e-6 * 50e3 * (1.5f64.ln() / 2f64.ln() - 0.5)).abs() < 1e-4,
        "{off}"
    );
    // speed cells in √V from sqrt_from on: exact for data linear in V below and in √V above; the
    // same nodes interpolated in V miss them in the √V cell
    let axes = sqrt_speeds(true);
    let f_sqrt = in_rise(&params, &axes, symmetric_multilinear_in_sqrt_speed);
    reproduces(&synthetic(&axes, &params, &f_sqrt), &f_sqrt);
    let axes = sqrt_speeds(false);
    let f_sqrt = in_rise(&params, &axes, symmetric_multilinear_in_sqrt_speed);
    let t = synthetic(&axes, &params, &f_sqrt);
    let c = [0.0, 0.0, 0.0, 75e3, 25.0, 0.5, 0.5, 0.7e9];
    let (p, e) = at(&t, &c, 0.0);
    let off = t.rise.of(t.evaluate(&p, &e).unwrap().max_temperature)
        - symmetric_multilinear_in_sqrt_speed(&c)[3];
    // G's speed term −0.15·s: s(25) = 20 + 2·(√500 − 20), the cell's middle in V (s(20) + s(30))/2 = √600
    let missed = 20.0 + 2.0 * (500f64.sqrt() - 20.0) - 600f64.sqrt();
    assert!((off - 0.15 * missed).abs() < 1e-4, "{off} {missed}");
}

/// The interpolant of `f` (a function the table reproduces exactly) and its Jacobian (through the
/// table's coordinates, plain or knee-blended) at 500 random points.
fn reproduces(t: &Table, f: &dyn Fn(&[f64; DIMS]) -> [f64; OUTPUTS]) {
    let mut rng = verify::SplitMix64::new(7);
    for n in 0..500 {
        let c = random_coordinates(&mut rng);
        let exponent = if n % 2 == 0 { 0.0 } else { Ellipse::HERTZ };
        let (pt, e) = at(t, &c, exponent);
        let (o, j) = t.evaluate_with_jacobian(&pt, &e).unwrap();
        let want = f(&c);
        let force = c[FORCE];
        assert!(o.in_range && o.converged, "{c:?}");
        assert!((o.force_x / force - want[0]).abs() < 1e-6, "{c:?}");
        assert!((o.force_y / force - want[1]).abs() < 1e-6, "{c:?}");
        assert!(
            (o.spin_moment / (force * e.radius()) - want[2]).abs() < 1e-6,
            "{c:?}"
        );
        assert!((o.max_temperature - want[3]).abs() < 1e-4, "{c:?}");
        assert!((o.fluid_load_fraction - want[4]).abs() < 1e-6);
        let power = o.frictional_power.unwrap() / (force * pt.speed);
        assert!((power - want[5]).abs() < 1e-6, "{c:?}");
        // Jacobian against central differences of the exact function through the coordinates
        for d in 0..INPUTS {
            let h = [1e-8, 1e-8, 1e-6, 1.0, 1e-4, 1e-6][d];
            let exact = |h: f64| {
                let (p, e) = moved(&pt, &e, d, h);
                let q = t.coordinates().of(&p, &e).unwrap().q;
                physical(&p, &e, &f(&q))
            };
            let (pp, pm) = (exact(h), exact(-h));
            for o in 0..JACOBIAN_ROWS {
                let fd = (pp[o] - pm[o]) / (2.0 * h);
                let scale = [force, force, force * e.radius(), 1.0, 700.0, 1.0][o]
                    / [0.05, 0.02, 1.0, 1e5, 20.0, 1.0][d];
                // the node values are stored in f32: their rounding (relative 6e-8) over node
                // spacings; T_max (650–800 K) rounded as stored (6e-5 K) becomes G with dG/dT up
                // to 3.2 in the yield-stress anomaly
                let tolerance = if o == 4 { 1e-3 } else { 1e-4 };
                assert!(
                    (j[o][d] - fd).abs() < tolerance * (fd.abs() + 1e-2 * scale),
                    "∂{o}/∂{d} at {c:?} (e {exponent}): {} vs {fd}",
                    j[o][d]
                );
            }
        }
    }
}

/// FASTSIM's frictional heat has kinks at η = 0 and φ = 0 (its combined flexibility, `heating`): T_max
/// and P_f rise like |η| and |φ| from there on both sides. A table built by the exact solver (a/b 0.72,
/// p0 1.51 GPa, 158 m/s, dry, ξ 0.2 %) follows them a third into the cells beside η̂ = 0 and φ̂ = 0
/// (T_max rising by 20 and 54 K over them): measured 0.07 and −2.2 K off, P_f 6e-5 and 1.6 % — where
/// the heat itself interpolated (Λ ≡ 1) lags by −2.4 and −7.4 K, P_f by 8.5 and 13 % (the spline's
/// slope is 0 at those nodes: the η mirror's ghost nodes, Steffen's limit where the secants change
/// sign).
#[test]
fn the_heat_follows_fastsims_kinks_across_zero_lateral_and_spin_creepage() {
    let mut params = Params::default();
    params.grid.nx = 10;
    params.grid.ny = 10;
    let axes = explicit_axes(
        [
            &[0.0, 0.2, 0.4, 0.8],
            &[0.0, 0.1, 0.2, 0.4],
            &[-0.2, -0.1, 0.0, 0.1, 0.2],
            &[100e3],
            &[158.0],
            &[0.0],
            &[0.72],
            &[1.51e9],
        ],
        [0.1, 0.1, 10.0],
    );
    let coords = Coordinates::new(&params, &axes);
    let exact = |q: &[f64; DIMS]| {
        let (point, e) = coords.point(q).unwrap();
        let mut p = params.clone();
        p.geometry.semi_axes = Some([e.a, e.b]);
        let s = crate::solver::solve(&p, &point).unwrap();
        assert!(s.report.converged);
        (build::normalised(&s, &point, e.radius()).unwrap(), point, e)
    };
    let t = synthetic(&axes, &params, &|q| exact(q).0.map(f64::from));
    for (d, h) in [(ETA, 0.1), (PHI, 0.1)] {
        let mut q = [0.2, 0.0, 0.0, 100e3, 158.0, 0.0, 0.72, 1.51e9];
        let t0 = exact(&q).0[3];
        q[d] = h;
        let rise = f64::from(exact(&q).0[3] - t0);
        q[d] = h / 3.0;
        let (want, point, e) = exact(&q);
        let got = t.evaluate(&point, &e).unwrap();
        let err = got.max_temperature - f64::from(want[3]);
        let power = got.frictional_power.unwrap() / (point.normal_force * point.speed);
        let power_err = power / f64::from(want[5]) - 1.0;
        assert!(
            rise > 15.0 && err.abs() < 0.06 * rise && power_err.abs() < 0.03,
            "along {d}: T_max rises by {rise:.1} K over the cell; a third into it {err:.2} K off, \
             P_f {power_err:.1e}"
        );
    }
}

#[test]
fn cells_across_which_t_max_jumps_are_not_resolved() {
    let params = coarse_params();
    let smooth = synthetic(&tiny_axes(), &params, &symmetric_saturating);
    assert!(smooth.cell_flags.is_empty());
    // T_max 400 K higher at the last ξ̂ node (10): the cells between ξ̂ = 1 and 10 hold the jump, for
    // both signs of ξ (the axis is mirrored); the smooth variation spreads by < 100 K across any cell
    let jump = |c: &[f64; DIMS]| {
        let mut o = symmetric_saturating(c);
        o[3] += if c[XI].abs() > 5.0 { 400.0 } else { 0.0 };
        o
    };
    let t = synthetic(&tiny_axes(), &params, &jump);
    let mut rng = verify::SplitMix64::new(17);
    let mut seen = [0; 2];
    for _ in 0..500 {
        let c = random_coordinates(&mut rng);
        let (p, e) = at(&t, &c, Ellipse::HERTZ);
        let o = t.evaluate(&p, &e).unwrap();
        assert!(o.in_range);
        assert_eq!(o.resolved, c[XI].abs() < 1.0, "{c:?}");
        assert!(smooth.evaluate(&p, &e).unwrap().resolved);
        seen[usize::from(o.resolved)] += 1;
    }
    assert!(seen.iter().all(|n| *n > 20), "{seen:?}");
}

/// A table over `axes` of `f` with the film-intake code `film(c)` at each node c.
fn with_film_intake(
    axes: &Axes,
    f: &dyn Fn(&[f64; DIMS]) -> [f64; OUTPUTS],
    film: &dyn Fn(&[f64; DIMS]) -> FilmIntake,
) -> Table {
    let mut files = tabulate(&coarse_params(), axes, f);
    files.film_intake = Some(
        (0..axes.len())
            .map(|i| film(&axes.coordinates(i)) as u8)
            .collect(),
    );
    Table::from_files(files, None).unwrap()
}

#[test]
fn cells_straddling_the_onset_of_the_walls_are_not_resolved() {
    // wet nodes: the metal covers part of the contact at the high p_ref node where |ξ̂| = 10 (a hot
    // contact reaches the onset first); dry nodes: no film. Only the cells between ξ̂ = 1 and 10 have a
    // corner of each wet kind; the T_max of `symmetric_saturating` spreads by < 100 K (no jump)
    let wet_onset = |c: &[f64; DIMS]| match (c[WET] > 0.0, c[XI].abs() > 5.0 && c[PRESSURE] > 0.8e9)
    {
        (false, _) => FilmIntake::Dry,
        (true, true) => FilmIntake::Limited,
        (true, false) => FilmIntake::All,
    };
    let t = with_film_intake(&tiny_axes(), &symmetric_saturating, &wet_onset);
    // every wet node covered: dry and covered corners straddle nothing
    let covered = |c: &[f64; DIMS]| {
        if c[WET] > 0.0 {
            FilmIntake::Limited
        } else {
            FilmIntake::Dry
        }
    };
    let all = with_film_intake(&tiny_axes(), &symmetric_saturating, &covered);
    assert!(all.cell_flags.is_empty());
    let mut rng = verify::SplitMix64::new(5);
    let mut seen = [0; 2];
    for _ in 0..500 {
        let c = random_coordinates(&mut rng);
        let (p, e) = at(&t, &c, Ellipse::HERTZ);
        let o = t.evaluate(&p, &e).unwrap();
        assert_eq!(o.resolved, c[XI].abs() < 1.0, "{c:?}");
        assert!(all.evaluate(&p, &e).unwrap().resolved);
        seen[usize::from(o.resolved)] += 1;
    }
    assert!(seen.iter().all(|n| *n > 20), "{seen:?}");
}

#[test]
fn film_intake_codes_round_trip_through_every_storage_and_bad_codes_are_refused() {
    let axes = tiny_axes();
    let mut files = tabulate(&coarse_params(), &axes, &symmetric_saturating);
    let codes: Vec<u8> = (0..axes.len()).map(|i| (i % 3) as u8).collect();
    let dir = std::env::temp_dir().join(format!("wheelrail-film-intake-{}", std::process::id()));
    // a table without the codes (built before they were recorded) reads without them
    files.write(&dir.join("none")).unwrap();
    assert_eq!(
        TableFiles::read(&dir.join("none")).unwrap().film_intake,
        None
    );
    files.film_intake = Some(codes.clone());
    for storage in [Storage::F32, Storage::U16, Storage::U16z, Storage::U16x] {
        let mut f = files.clone();
        f.sidecar.storage = storage;
        let d = dir.join(storage.to_string());
        f.write(&d).unwrap();
        let back = TableFiles::read(&d).unwrap();
        assert_eq!(back.film_intake.as_deref(), Some(&codes[..]), "{storage}");
        assert_eq!(back.sidecar.film_intake.unwrap().name, "film_intake");
    }
    // a code beyond 2 (with a matching hash) is refused naming the file
    let mut bad = files.clone();
    bad.film_intake.as_mut().unwrap()[7] = 3;
    bad.write(&dir.join("bad")).unwrap();
    let e = TableFiles::read(&dir.join("bad")).unwrap_err().to_string();
    assert!(
        e.contains("film_intake.npy") && e.contains("holds 3"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_kernel_this_cpu_runs_agrees_with_the_portable_one() {
    let params = coarse_params();
    let mut t = synthetic(&tiny_axes(), &params, &symmetric_saturating);
    assert_eq!(t.kernel(), Kernel::detect());
    assert!(t.set_kernel(Kernel::Portable).is_ok());
    let mut rng = verify::SplitMix64::new(5);
    let points: Vec<(OperatingPoint, Ellipse)> = (0..500)
        .map(|_| at(&t, &random_coordinates(&mut rng), Ellipse::HERTZ))
        .collect();
    let reference: Vec<(TableOutput, Jacobian)> = points
        .iter()
        .map(|(p, e)| {
            (
                t.evaluate(p, e).unwrap(),
                t.evaluate_with_jacobian(p, e).unwrap().1,
            )
        })
        .collect();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (a.abs() + b.abs());
    let mut compared = 0;
    for kernel in Kernel::ALL {
        if t.set_kernel(kernel).is_err() {
            assert!(!kernel.supported());
            continue;
        }
        compared += 1;
        for ((p, e), (o, j)) in points.iter().zip(&reference) {
            let ok = t.evaluate(p, e).unwrap();
            let jk = t.evaluate_with_jacobian(p, e).unwrap().1;
            for (x, y) in [
                (ok.force_x, o.force_x),
                (ok.force_y, o.force_y),
                (ok.spin_moment, o.spin_moment),
                (ok.traction_coefficient, o.traction_coefficient),
                (ok.max_temperature, o.max_temperature),
                (ok.fluid_load_fraction, o.fluid_load_fraction),
            ] {
                assert!(close(x, y), "{kernel:?} at {p:?}: {x} vs {y}");
            }
            assert_eq!((ok.in_range, ok.converged), (o.in_range, o.converged));
            // derivatives are differences of values over node spacings down to 1e-4 or so: the
            // values' rounding differences grow by that factor
            for (rk, r) in jk.iter().zip(j) {
                let scale = r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                for (x, y) in rk.iter().zip(r) {
                    assert!((x - y).abs() <= 1e-9 * scale, "{kernel:?}: {x} vs {y}");
                }
            }
        }
    }
    assert!(compared >= 1);
}

/// The AVX-512 kernel's values and Jacobians are the AVX2 kernel's bit for bit (where this CPU runs
/// both): on a table with 16 linear corners and one by similarity (12), at random points (ghost window
/// points of both mirrors among them), dry ones (the wetness on its first node: half the corners), on
/// the last speed node, and beside cells across which T_max jumps (one-sided slopes).
#[test]
fn the_avx512_kernel_is_the_avx2_kernel_bit_for_bit() {
    if !Kernel::Avx512.supported() {
        eprintln!("this CPU has no AVX-512: nothing to compare");
        return;
    }
    let params = coarse_params();
    let mut axes = tiny_axes();
    axes.0[XI].points = vec![0.0, 1.0, 2.0, 4.0, 10.0];
    let jump = |c: &[f64; DIMS]| {
        let mut o = symmetric_saturating(c);
        o[3] += if c[XI].abs() >= 10.0 { 800.0 } else { 0.0 };
        o
    };
    let tables = [
        synthetic(&tiny_axes(), &params, &symmetric_saturating),
        synthetic(&similar(tiny_axes()), &params, &symmetric_saturating),
        synthetic(&axes, &params, &jump),
    ];
    let mut rng = verify::SplitMix64::new(31);
    let mut kinds = [0; 3];
    for mut t in tables {
        let speeds = t.axes().0[SPEED].points.clone();
        let dry = t.axes().0[WET].points[0];
        for n in 0..400 {
            let mut c = random_coordinates(&mut rng);
            match n % 4 {
                1 => c[WET] = dry,
                2 => c[SPEED] = speeds[speeds.len() - 1],
                _ => {}
            }
            let (p, e) = at(&t, &c, Ellipse::HERTZ);
            let mut results = Vec::new();
            for kernel in [Kernel::Avx2Fma, Kernel::Avx512] {
                t.set_kernel(kernel).unwrap();
                let o = t.evaluate(&p, &e).unwrap();
                let (oj, j) = t.evaluate_with_jacobian(&p, &e).unwrap();
                let bits = |o: &TableOutput| o.values().map(f64::to_bits);
                let flags = (o.in_range, o.converged, o.resolved);
                results.push((bits(&o), bits(&oj), flags, j.map(|r| r.map(f64::to_bits))));
            }
            assert_eq!(results[0], results[1], "{c:?}");
            kinds[0] += usize::from(c[XI] < 0.0 && c[ETA] < 0.0);
            kinds[1] += usize::from(!results[0].2.2);
            kinds[2] += usize::from(results[0].0[0] != 0);
        }
    }
    // both mirrors, unresolved cells and non-zero values among the points
    assert!(kinds.iter().all(|k| *k > 10), "{kinds:?}");
}

/// Timing files load (their probe nodes hold the exact solutions), a synthetic table without them does
/// not.
#[test]
fn timing_files_pass_the_probes_a_synthetic_table_does_not() {
    let params = coarse_params();
    let axes = tiny_axes();
    let dir = std::env::temp_dir().join(format!("wheelrail-timing-{}", std::process::id()));
    let mut files = build::timing_files(&params, &axes).unwrap();
    files.write(&dir).unwrap();
    let loaded = Table::load(&dir);
    let mut plain = build::tabulate(&params, &axes, &|_| [0.1, 0.0, 0.0, 300.0, 0.0, 0.0]);
    plain.write(&dir).unwrap();
    let refused = Table::load(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(loaded.is_ok(), "{loaded:?}");
    let reason = refused.unwrap_err().to_string();
    assert!(reason.contains("another model"), "{reason}");
}

#[test]
fn jacobian_is_the_derivative_of_the_interpolant() {
    let params = coarse_params();
    let mut axes = tiny_axes();
    axes.0[XI].points = vec![0.0, 0.2, 0.6, 2.0, 6.0, 10.0];
    for axes in [
        axes.clone(),
        similar(axes.clone()),
        similar(blended(axes.clone())),
        sized(blended(axes.clone())),
        similar(sized(blended(axes))),
    ] {
        jacobian_is_the_derivative_of(&synthetic(&axes, &params, &symmetric_saturating));
    }
}

/// [`jacobian_is_the_derivative_of_the_interpolant`] for table `t`; in a table by similarity at
/// contacts carried from F_ref to loads 0.3–2 × F_ref (their equivalents at random coordinates).
fn jacobian_is_the_derivative_of(t: &Table) {
    let mut rng = verify::SplitMix64::new(11);
    for n in 0..300 {
        let mut c = random_coordinates(&mut rng);
        let exponent = if n % 2 == 0 { 0.0 } else { Ellipse::HERTZ };
        let (pt, e) = if t.axes().similarity() {
            c[FORCE] = axes::REFERENCE_FORCE;
            let (p, e) = at(t, &c, exponent);
            coords::carried(&p, &e, 0.3 + 1.7 * rng.uniform())
        } else {
            at(t, &c, exponent)
        };
        let (_, j) = t.evaluate_with_jacobian(&pt, &e).unwrap();
        for d in 0..INPUTS {
            let h = [1e-9, 1e-9, 1e-7, 0.1, 1e-5, 1e-7][d];
            let value = |h: f64| {
                let (p, e) = moved(&pt, &e, d, h);
                t.evaluate(&p, &e).unwrap()
            };
            let (p, m) = (value(h), value(-h));
            let fd = [
                (p.force_x - m.force_x) / (2.0 * h),
                (p.force_y - m.force_y) / (2.0 * h),
                (p.spin_moment - m.spin_moment) / (2.0 * h),
                (p.traction_coefficient - m.traction_coefficient) / (2.0 * h),
                (p.max_temperature - m.max_temperature) / (2.0 * h),
                (p.fluid_load_fraction - m.fluid_load_fraction) / (2.0 * h),
            ];
            for o in 0..JACOBIAN_ROWS {
                let f = pt.normal_force;
                let scale =
                    [f, f, f * 0.01, 1.0, 50.0, 0.3][o] / [0.05, 0.02, 1.0, 1e5, 20.0, 1.0][d];
                assert!(
                    (j[o][d] - fd[o]).abs() < 1e-5 * scale.max(fd[o].abs()),
                    "∂{o}/∂{d} at {c:?}: {} vs {}",
                    j[o][d],
                    fd[o]
                );
            }
        }
    }
}

/// The in-memory row layout (values and φ slopes interleaved, f32, linear corners) against a direct
/// evaluation of the node values in C order: Steffen slopes along φ per corner fibre (mirror images for
/// ghost η nodes), Hermite along φ, the linear corners, then the η and ξ fibres with their weights.
#[test]
fn row_layout_matches_a_direct_evaluation_of_the_node_values() {
    let params = coarse_params();
    let mut axes = tiny_axes();
    axes.0[XI].points = vec![0.0, 0.2, 0.6, 2.0, 6.0, 10.0];
    let t = synthetic(&axes, &params, &symmetric_saturating);
    let shape = axes.shape();
    // the stored (f32) node values, T_max as G(T_max) (`rise`), the heat per unit of the node's Λ
    // (`heating`), in f32
    let vals: Vec<[f64; OUTPUTS]> = (0..axes.len())
        .map(|k| {
            let c = axes.coordinates(k);
            let (p, e) = t.coordinates.point(&c).unwrap();
            let lambda = t.coordinates.of(&p, &e).unwrap().heating;
            let mut v = symmetric_saturating(&c).map(|v| f64::from(v as f32));
            v[3] = f64::from((t.rise.of(v[3]) / lambda) as f32);
            v[5] = f64::from((v[5] / lambda) as f32);
            v
        })
        .collect();
    let idx = |m: [usize; DIMS]| m.iter().zip(&shape).fold(0, |a, (i, s)| a * s + i);
    let phi = &axes.0[PHI].points;
    let np = phi.len();
    let mut rng = verify::SplitMix64::new(5);
    for _ in 0..300 {
        let mut q = random_coordinates(&mut rng);
        q[XI] = q[XI].abs();
        q[ETA] = q[ETA].abs();
        let cx = t.interp[XI].cubic(q[XI]);
        let cy = t.interp[ETA].cubic(q[ETA]);
        let (k0, hw, _) = t.interp[PHI].cubic(q[PHI]).hermite();
        let k0 = k0 as usize;
        let sx = Corners::of(&std::array::from_fn(|k| {
            t.interp[FORCE + k].fraction(q[FORCE + k])
        }));
        // the corners' node indices along the linear dimensions
        let corners: Vec<[usize; LINEAR_DIMS]> = (0..sx.n)
            .map(|c| std::array::from_fn(|k| sx.start[k] + sx.step[c][k]))
            .collect();
        let want: [f64; OUTPUTS] = std::array::from_fn(|o| {
            let along_eta: [f64; 4] = std::array::from_fn(|i| {
                let gi = cx.start + i as isize;
                let along_phi: [f64; 4] = std::array::from_fn(|j| {
                    let gj = cy.start + j as isize;
                    let sign = if (gi < 0 && o == 0) != (gj < 0 && (o == 1 || o == 2)) {
                        -1.0
                    } else {
                        1.0
                    };
                    corners
                        .iter()
                        .zip(sx.w)
                        .map(|(corner, w)| {
                            let fibre: Vec<f64> = (0..np)
                                .map(|k| {
                                    let kk = if gj < 0 { np - 1 - k } else { k };
                                    let mut m =
                                        [gi.unsigned_abs(), gj.unsigned_abs(), kk, 0, 0, 0, 0, 0];
                                    m[FORCE..].copy_from_slice(corner);
                                    sign * vals[idx(m)][o]
                                })
                                .collect();
                            let mut d = vec![0.0; np];
                            interp::node_slopes(phi, &fibre, &mut d);
                            // slopes are stored in f32 too
                            let d: Vec<f64> = d.iter().map(|x| f64::from(*x as f32)).collect();
                            w * (hw[0] * fibre[k0]
                                + hw[1] * d[k0]
                                + hw[2] * fibre[k0 + 1]
                                + hw[3] * d[k0 + 1])
                        })
                        .sum()
                });
                cy.eval(&along_phi).v
            });
            cx.eval(&along_eta).v
        });
        let got = t.core::<false, PORTABLE>(&q).v;
        for o in 0..OUTPUTS {
            let scale = [1.0, 1.0, 0.1, 300.0, 0.3, 0.05][o];
            assert!(
                (got[o] - want[o]).abs() < 1e-12 * scale,
                "output {o} at {q:?}: {} vs {}",
                got[o],
                want[o]
            );
        }
    }
}

#[test]
fn mirrored_points_obey_the_symmetries() {
    // node values of a non-symmetric function: the table still returns mirror images for η < 0, ξ < 0
    let params = coarse_params();
    let t = synthetic(&tiny_axes(), &params, &|c| {
        [
            c[0] + c[1] + c[2],
            c[1] * 2.0 + c[2],
            c[2] + c[0],
            300.0 + c[0],
            0.1,
            0.01 + c[0] * c[0],
        ]
    });
    let (pt, e) = at(&t, &[2.0, 0.8, 0.3, 70e3, 20.0, 0.5, 0.55, 0.8e9], 0.0);
    let a = t.evaluate(&pt, &e).unwrap();
    let b = t
        .evaluate(
            &OperatingPoint {
                creepage_y: -pt.creepage_y,
                spin: -pt.spin,
                ..pt
            },
            &e,
        )
        .unwrap();
    assert_eq!(
        (b.force_x, b.force_y, b.spin_moment),
        (a.force_x, -a.force_y, -a.spin_moment)
    );
    assert_eq!(b.max_temperature, a.max_temperature);
    let c = t
        .evaluate(
            &OperatingPoint {
                creepage_x: -pt.creepage_x,
                ..pt
            },
            &e,
        )
        .unwrap();
    assert_eq!(
        (c.force_x, c.force_y, c.spin_moment),
        (-a.force_x, a.force_y, a.spin_moment)
    );
}

#[test]
fn out_of_range_is_clamped_and_flagged_bad_input_is_an_error() {
    let t = synthetic(&tiny_axes(), &coarse_params(), &symmetric_multilinear);
    let (pt, e) = at(&t, &[4.0, 0.2, 0.1, 100e3, 30.0, 1.0, 0.55, 0.8e9], 0.0);
    let inside = t.evaluate(&pt, &e).unwrap();
    assert!(inside.in_range && t.in_range(&pt, &e) && t.covers(&e, pt.normal_force));
    let fast = OperatingPoint { speed: 60.0, ..pt };
    let (o, j) = t.evaluate_with_jacobian(&fast, &e).unwrap();
    assert!(!o.in_range && !t.in_range(&fast, &e));
    // V = 30 is the top of the speed axis: clamped to it
    assert!((o.force_x - inside.force_x).abs() < 1e-12 * inside.force_x.abs());
    assert_eq!(j[0][4], 0.0);
    // above the load range the normalised values are held, the force scales with F_N (the contact
    // held: its p_ref and the creepage scales change, so compare at the same coordinates)
    let (heavy, eh) = at(&t, &[4.0, 0.2, 0.1, 200e3, 30.0, 1.0, 0.55, 0.8e9], 0.0);
    let h = t.evaluate(&heavy, &eh).unwrap();
    assert!(!h.in_range);
    assert!((h.force_x / 200e3 - inside.force_x / 100e3).abs() < 1e-15);
    // a raw creepage beyond its raw limit is out of range even where its coordinate is on the axis
    let mut narrow = tiny_axes();
    narrow.0[XI].raw_limit = Some(0.5 * pt.creepage_x);
    let steep = synthetic(&narrow, &coarse_params(), &symmetric_multilinear);
    assert!(!steep.in_range(&pt, &e) && !steep.evaluate(&pt, &e).unwrap().in_range);
    // another contact: outside the geometry axes
    let flat = Ellipse {
        a: e.b,
        b: e.a,
        ..e
    };
    assert!(!t.covers(&flat, pt.normal_force) && !t.in_range(&pt, &flat));
    let err = t.outside_geometry(&flat, pt.normal_force).to_string();
    assert!(
        err.contains("a/b 0.5 to 0.6") && err.contains("p_ref"),
        "{err}"
    );
    for bad in [
        OperatingPoint {
            creepage_x: f64::NAN,
            ..pt
        },
        OperatingPoint {
            normal_force: -1.0,
            ..pt
        },
    ] {
        assert!(t.evaluate(&bad, &e).is_err() && !t.in_range(&bad, &e));
    }
    assert!(t.evaluate(&pt, &Ellipse { a: 0.0, ..e }).is_err());
}

/// [`synthetic`] with the points of flat (C-order, the files') indices `unconverged` not converged.
fn synthetic_unconverged(
    axes: &Axes,
    params: &Params,
    f: &dyn Fn(&[f64; DIMS]) -> [f64; OUTPUTS],
    unconverged: &[usize],
) -> Table {
    let mut files = build::tabulate(params, axes, f);
    for i in unconverged {
        files.converged[*i] = 0;
    }
    Table::from_files(files, None).unwrap()
}

#[test]
fn unconverged_nodes_taint_only_nearby_evaluations() {
    let mut axes = tiny_axes();
    axes.0[XI].points = vec![0.0, 0.2, 0.6, 2.0, 6.0, 10.0];
    let params = coarse_params();
    // flag the node at the largest coordinates
    let t = synthetic_unconverged(&axes, &params, &symmetric_multilinear, &[axes.len() - 1]);
    let near = [8.0, 3.5, 0.38, 90e3, 25.0, 0.9, 0.58, 0.83e9];
    let (p, e) = at(&t, &near, 0.0);
    assert!(!t.evaluate(&p, &e).unwrap().converged);
    // the cubic stencil at ξ̂ = 0.4 spans the points −0.2 (ghost) … 2
    let mut far = near;
    far[XI] = 0.4;
    let (p, e) = at(&t, &far, 0.0);
    assert!(t.evaluate(&p, &e).unwrap().converged);
}

#[test]
fn a_cell_next_to_an_unresolved_cell_takes_one_sided_slopes_at_their_shared_node() {
    // data linear in ξ̂ (η̂) on the stored side, T_max's variable G too, but for a jump of G at the last
    // node, which makes the last cell unresolved: the cell before it reproduces the data exactly (its
    // spline no longer takes up to twice its secant as the slope at the shared node), values and
    // Jacobian
    let params = coarse_params();
    for (axis, points, last, cell) in [
        (XI, &[0.0, 1.0, 2.0, 4.0, 10.0][..], 10.0, [2.0, 4.0]),
        (ETA, &[0.0, 0.6, 1.5, 4.0, 9.0][..], 9.0, [1.5, 4.0]),
    ] {
        let mut axes = tiny_axes();
        axes.0[axis].points = points.to_vec();
        axes.validate().unwrap();
        let linear = move |c: &[f64; DIMS]| {
            let mut o = symmetric_multilinear(c);
            o[3] += 5.0 * c[axis].abs();
            o
        };
        let jump = move |c: &[f64; DIMS]| {
            let mut o = linear(c);
            o[3] += if c[axis].abs() >= last { 800.0 } else { 0.0 };
            o
        };
        let t = synthetic(&axes, &params, &in_rise(&params, &axes, jump));
        let want = in_rise(&params, &axes, linear);
        let mut rng = verify::SplitMix64::new(23);
        for n in 0..200 {
            let mut c = random_coordinates(&mut rng);
            c[axis] = cell[0] + (cell[1] - cell[0]) * rng.uniform();
            let (p, e) = at(&t, &c, 0.0);
            let (o, j) = t.evaluate_with_jacobian(&p, &e).unwrap();
            assert!(o.resolved, "{c:?}");
            let w = want(&c);
            let f = c[FORCE];
            assert!((o.force_x / f - w[0]).abs() < 1e-6, "{axis} {c:?}");
            assert!((o.force_y / f - w[1]).abs() < 1e-6, "{axis} {c:?}");
            assert!(
                (o.max_temperature - w[3]).abs() < 1e-3,
                "{axis} {c:?}: {} vs {}",
                o.max_temperature,
                w[3]
            );
            // the Jacobian's T_max column along the axis: the derivative of the same linear data
            if n % 10 == 0 {
                let d = if axis == XI { 0 } else { 1 };
                let h = 1e-8;
                let value = |h: f64| {
                    let (p, e) = moved(&p, &e, d, h);
                    t.evaluate(&p, &e).unwrap().max_temperature
                };
                let fd = (value(h) - value(-h)) / (2.0 * h);
                assert!(
                    (j[4][d] - fd).abs() < 1e-4 * fd.abs().max(1.0),
                    "{} vs {fd}",
                    j[4][d]
                );
            }
        }
        // the cell beyond holds the jump
        let mut c = random_coordinates(&mut rng);
        c[axis] = 0.5 * (cell[1] + last);
        let (p, e) = at(&t, &c, 0.0);
        assert!(!t.evaluate(&p, &e).unwrap().resolved);
    }
}

#[test]
fn xi_slabs_are_padded_so_that_no_l1_set_holds_more_of_a_lookup_than_its_ways() {
    // the whole-range table: 1 488 384 rows of 48 bytes per ξ̂ slab, a multiple of 4 KB (17 442 pages)
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/whole-range-axes.toml");
    let shape = Axes::from_toml_file(&file).unwrap().shape();
    let (padded, unpadded) = (memory_strides(&shape), unpadded_strides(&shape));
    assert_eq!(unpadded[XI], 1_488_384);
    assert_eq!(unpadded[XI] * std::mem::size_of::<Row>() % 4096, 0);
    // unpadded, the four ξ̂ window nodes of every row share a set: lines beyond the ways
    assert!(
        l1_crowding(&shape, &unpadded) > 100,
        "{}",
        l1_crowding(&shape, &unpadded)
    );
    let pad = padded[XI] - unpadded[XI];
    assert_eq!(pad % shape[PHI], 0, "whole fibres");
    assert!(pad > 0 && 16 * pad <= unpadded[XI], "{pad}");
    assert_eq!(l1_crowding(&shape, &padded), 0);
    // the test tables are padded too (fewer lines beyond the ways), so every test of lookups runs on
    // a padded layout
    for axes in [tiny_axes(), small_axes()] {
        let shape = axes.shape();
        let (padded, unpadded) = (memory_strides(&shape), unpadded_strides(&shape));
        assert!(padded[XI] > unpadded[XI]);
        assert!(l1_crowding(&shape, &padded) < l1_crowding(&shape, &unpadded));
    }
}

/// The cells flagged at loading as near an unconverged point ([`near_unconverged`]) hold every
/// evaluation that reads one: with four points unconverged, random evaluations (values and Jacobians,
/// both mirrors, every kind of cell) report `converged` as when every cell is checked corner by
/// corner — and the flags spare most cells that check.
#[test]
fn cells_near_unconverged_points_are_flagged_at_loading_as_every_evaluation_finds_them() {
    let mut axes = tiny_axes();
    axes.0[XI].points = vec![0.0, 0.2, 0.6, 2.0, 6.0, 10.0];
    axes.0[ETA].points = vec![0.0, 0.3, 1.0, 2.0, 4.0];
    axes.0[PHI].points = vec![-0.5, -0.3, -0.1, 0.0, 0.1, 0.3, 0.5];
    axes.validate().unwrap();
    let params = coarse_params();
    let mut rng = verify::SplitMix64::new(11);
    let mut bad: Vec<usize> = (0..3).map(|_| rng.below(axes.len())).collect();
    // and one that only the ghost η̂ point −1 reads, where φ̂ runs backwards (η̂ 1, φ̂'s last point: in
    // the window of η̂'s first cell, read at the φ̂ rows of its first cell)
    let shape = axes.shape();
    let creepage = shape[XI] * shape[ETA] * shape[PHI];
    bad.push(((2 * shape[ETA] + 1) * shape[PHI] + shape[PHI] - 1) * (axes.len() / creepage));
    let t = synthetic_unconverged(&axes, &params, &symmetric_multilinear, &bad);
    let mut every = synthetic_unconverged(&axes, &params, &symmetric_multilinear, &bad);
    every
        .cell_flags
        .iter_mut()
        .for_each(|f| *f |= NEAR_UNCONVERGED);
    let flagged = t
        .cell_flags
        .iter()
        .filter(|f| **f & NEAR_UNCONVERGED != 0)
        .count();
    assert!(flagged > 0 && flagged < t.cell_flags.len() / 2, "{flagged}");
    let mut tainted = [0, 0];
    for n in 0..20000 {
        let mut c = random_coordinates(&mut rng);
        // the nodes themselves and the cells' faces too (weights exactly 0)
        if n % 4 == 0 {
            for (x, a) in c.iter_mut().zip(&axes.0).skip(FORCE) {
                *x = a.points[rng.below(2)];
            }
        }
        let (p, e) = at(&t, &c, 0.0);
        let fast = t.evaluate(&p, &e).unwrap().converged;
        assert_eq!(fast, every.evaluate(&p, &e).unwrap().converged, "{c:?}");
        let (o, _) = t.evaluate_with_jacobian(&p, &e).unwrap();
        let (o_every, _) = every.evaluate_with_jacobian(&p, &e).unwrap();
        assert_eq!(o.converged, o_every.converged, "{c:?}");
        tainted[usize::from(fast)] += 1;
    }
    // both kinds occur
    assert!(
        tainted[0] > 100 && tainted[1] > 100,
        "{tainted:?} of {flagged}"
    );
}

/// A table stores quantities only the Tomberger law models: other laws are refused before any solve,
/// and an exact solution of them has no table form.
#[test]
fn tables_are_of_the_tomberger_law_only() {
    for (law, missing) in [
        (FrictionLaw::Polach, "spin moment"),
        (FrictionLaw::Constant, "fluid load fraction"),
    ] {
        let mut p = coarse_params();
        p.friction.law = law;
        let e = build::build(&p, &tiny_axes(), None, &|| ()).unwrap_err();
        assert!(
            matches!(&e, Error::OutOfRange { name, .. } if name == "friction.law"),
            "{e}"
        );
        let s = crate::solve(&p, &OperatingPoint::default()).unwrap();
        let e = TableOutput::from_solution(&s).unwrap_err().to_string();
        assert!(e.contains(&format!("has no {missing}")), "{e}");
    }
    let s = crate::solve(&coarse_params(), &OperatingPoint::default()).unwrap();
    let o = TableOutput::from_solution(&s).unwrap();
    let g = &s.global;
    assert_eq!(
        [o.force_x, o.force_y, o.traction_coefficient],
        [g.force_x, g.force_y, g.traction_coefficient]
    );
    assert_eq!(
        [
            Some(o.spin_moment),
            Some(o.max_temperature),
            Some(o.fluid_load_fraction)
        ],
        [g.spin_moment, g.max_temperature, g.fluid_load_fraction]
    );
    assert!(o.in_range && o.converged);
}

#[test]
fn shared_loading_returns_one_copy_per_directory() {
    let dir = std::env::temp_dir().join(format!("wheelrail-table-shared-{}", std::process::id()));
    let mut files = build::build(&coarse_params(), &tiny_axes(), None, &|| ()).unwrap();
    files.write(&dir).unwrap();
    let a = Table::load_shared(&dir).unwrap();
    let b = Table::load_shared(&dir.join(".")).unwrap();
    assert!(Arc::ptr_eq(&a, &b));
    assert!(a.matches(&coarse_params()) && !a.matches(&Params::default()));
    assert!(not_matching(&a, &Params::default()).is_some());
    drop((a, b));
    // released when the last user drops it, loaded again afterwards
    let c = Table::load_shared(&dir).unwrap();
    assert_eq!(c.axes(), &tiny_axes());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A table whose values another model computed is refused at loading: its probe nodes no
/// longer match the exact solver. Here the "other model" is the present one with the forces 1e-4·F_N
/// larger (as a change of the friction model would make them), the files otherwise consistent.
#[test]
fn a_table_of_another_model_is_refused_by_its_probe_nodes() {
    let dir = std::env::temp_dir().join(format!("wheelrail-table-probe-{}", std::process::id()));
    let mut files = build::build(&coarse_params(), &tiny_axes(), None, &|| ()).unwrap();
    files.write(&dir.join("good")).unwrap();
    let good = Table::load(&dir.join("good")).unwrap();
    assert_eq!(good.probe_nodes().len(), PROBES);
    let probes = good.probe_nodes();
    // the probes lie in different cubes and are solved nodes
    assert!(probes.windows(2).all(|w| w[0] < w[1]));
    for (k, o) in [(0usize, 1e-4f32), (3, 0.01)] {
        let mut stale = files.clone();
        for n in &probes {
            stale.outputs[k][*n] += o;
        }
        let d = dir.join(format!("stale-{k}"));
        stale.write(&d).unwrap();
        let e = Table::load(&d).unwrap_err().to_string();
        assert!(
            e.contains("computed by another model")
                && e.contains(OUTPUT_INFO[k].name)
                && e.contains("rebuild"),
            "{e}"
        );
    }
    // below the tolerance (f32 rounding, solver noise) it loads
    let mut close = files.clone();
    for n in &probes {
        close.outputs[0][*n] += 2e-8;
    }
    close.write(&dir.join("close")).unwrap();
    Table::load(&dir.join("close")).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A built table agrees with the exact solver at its nodes (they are the solutions, in f32) and between
/// them within the interpolation error, for contacts across its geometry axes; the nodes a cube did not
/// solve (beyond its coverage window) hold the nearest solved node's values.
#[test]
fn built_nodes_are_the_exact_solutions_of_their_contacts() {
    for axes in [
        tiny_axes(),
        blended(tiny_axes()),
        similar(tiny_axes()),
        similar(blended(tiny_axes())),
        similar(sized(blended(tiny_axes()))),
    ] {
        built_nodes_are_exact(&axes);
    }
}

/// Where the coupled thermal problem has two steady states, a node holds the one the exact solver
/// finds from a cold start (what `table verify`, `wheelrail point` and a fresh FMU instance compute),
/// whatever the continuation line it was solved on. Hot, fast, high-pressure contact at the onset of
/// boundary lubrication (equivalent speed 65 m/s, p0 1.2 GPa, a/b 1.2, w 0.013, 10 × 10 cells): the line
/// of ξ comes from ξ = −0.116 (T_max 1049 K) to −0.070, where a warm temperature led to the hot state
/// (898 K, F_x/F_N 0.117) and the cold start to 579 K (0.0925); at +0.116, from +0.070 (583 K), the warm
/// temperature gave 727 K and the cold start 1050 K.
#[test]
fn built_nodes_are_the_cold_start_solutions_where_the_heat_has_two_steady_states() {
    let spec: axes::AxesSpec = toml::from_str(
        r#"
        [creepage_x]
        points = [-22.0, -13.117, 0.0, 13.117, 22.0]
        raw_limit = 0.1
        raw_scale = 193.0
        [creepage_y]
        points = [0.0, 0.9531, 1.6077]
        raw_limit = 0.02
        raw_scale = 170.0
        [spin]
        points = [-0.349, -0.1097, 0.1097, 0.349]
        raw_limit = 1.0
        raw_scale = 0.4
        [normal_force]
        points = [100e3]
        [speed]
        similarity = true
        points = [65.097]
        [wetness]
        points = [0.013]
        [semi_axis_ratio]
        points = [1.2]
        [reference_pressure]
        points = [1.2e9]
        "#,
    )
    .unwrap();
    let axes = Axes::from_spec(&spec).unwrap();
    let mut params = Params::default();
    params.grid.nx = 10;
    params.grid.ny = 10;
    let files = build::build(&params, &axes, None, &|| ()).unwrap();
    let mut hottest: f64 = 0.0;
    for k in 0..axes.len() {
        let (p, e) = Coordinates::new(&params, &axes)
            .point(&axes.coordinates(k))
            .unwrap();
        let mut exact = params.clone();
        exact.geometry.semi_axes = Some([e.a, e.b]);
        let s = crate::solve(&exact, &p).unwrap();
        let t = s.global.max_temperature.unwrap();
        hottest = hottest.max(t);
        let stored = [files.outputs[0][k], files.outputs[3][k]].map(f64::from);
        let want = [s.global.force_x / p.normal_force, t];
        assert!(
            (stored[0] - want[0]).abs() < 1e-5 && (stored[1] - want[1]).abs() < 1e-2,
            "node {k} {p:?}: stored F_x/F_N {}, T_max {} against the cold start's {}, {}",
            stored[0],
            stored[1],
            want[0],
            want[1]
        );
    }
    // the hot state is reached: the test runs where the two steady states are
    assert!(hottest > 1000.0, "{hottest}");
}

/// A table over `axes` holds the exact solutions at 20 random nodes, and evaluates to them there; a
/// table by similarity at contacts carried from the nodes' (at F_ref) to 0.1–2.5 × F_ref, whose exact
/// solutions are compared.
fn built_nodes_are_exact(axes: &Axes) {
    let params = coarse_params();
    let files = build::build(&params, axes, None, &|| ()).unwrap();
    let t = Table::from_files(files.clone(), None).unwrap();
    let mut rng = verify::SplitMix64::new(17);
    for _ in 0..20 {
        let k = rng.below(axes.len());
        let q = axes.coordinates(k);
        let node = t.coordinates().point(&q).unwrap();
        let (p, e) = if axes.similarity() {
            coords::carried(&node.0, &node.1, 0.1 * 25f64.powf(rng.uniform()))
        } else {
            node
        };
        let mut exact = params.clone();
        exact.geometry.semi_axes = Some([e.a, e.b]);
        let s = crate::solve(&exact, &p).unwrap();
        let f = p.normal_force;
        let stored = f64::from(files.outputs[0][k]);
        assert!(
            (stored - s.global.force_x / f).abs() < 1e-3,
            "node {q:?}: {stored} vs {}",
            s.global.force_x / f
        );
        let o = t.evaluate(&p, &e).unwrap();
        assert!((o.force_x / f - stored).abs() < 1e-6);
    }
}
