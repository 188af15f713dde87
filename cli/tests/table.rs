//! Tabulation mode: the symmetries the table relies on, deterministic and sharded builds, the
//! file checks, verification against the exact solver, and evaluation by table on the command line.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use wheelrail::table::{FilmIntake, Table, TableFiles};
use wheelrail::{OperatingPoint, Params, solve};

fn wheelrail(args: &[&str], threads: Option<&str>) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_wheelrail"));
    c.args(args);
    if let Some(t) = threads {
        c.env("RAYON_NUM_THREADS", t);
    }
    c.output().expect("run wheelrail")
}

fn ok(o: &Output) -> String {
    assert!(
        o.status.success(),
        "exit {:?}: {}",
        o.status.code(),
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8(o.stdout.clone()).unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("wheelrail-table-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let p = d.join(name);
    let _ = std::fs::remove_dir_all(&p);
    p
}

/// Removes this test's directories and files (names starting with `prefix`).
fn cleanup(prefix: &str) {
    let d = std::env::temp_dir().join(format!("wheelrail-table-{}", std::process::id()));
    for e in std::fs::read_dir(&d).into_iter().flatten().flatten() {
        if e.file_name().to_string_lossy().starts_with(prefix) {
            let p = e.path();
            let _ = std::fs::remove_dir_all(&p).or_else(|_| std::fs::remove_file(&p));
        }
    }
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// A coarse grid keeps the exact solves cheap; every other parameter is the default.
const SMALL_GRID: &str = "[grid]\nnx = 8\nny = 8\n";

/// The creepage axes of [`SMALL_AXES`] and [`ONSET_AXES`].
macro_rules! small_creepages {
    () => {
        r#"
[creepage_x]
points = [0.0, 0.2, 0.6, 1.8]
mirrored = true
raw_limit = 0.008
[creepage_y]
points = [0.0, 0.17, 0.6]
raw_limit = 0.003
[spin]
points = [-0.1, -0.02, 0.02, 0.1]
raw_limit = 0.2
"#
    };
}

/// Small axes around the Table 1 point and the default contact (a/b = 0.558, p_ref = 0.771 GPa), both dry
/// and wet: |ξ| ≤ 0.8 %, |η| ≤ 0.3 %, |φ| ≤ 0.2 /m (normalised creepages: k_x ≈ 190, k_y ≈ 170, k_φ ≈ 0.4 m
/// for the default contact).
const SMALL_AXES: &str = concat!(
    small_creepages!(),
    r#"[normal_force]
points = [80e3, 120e3]
[speed]
points = [20.0, 40.0]
[wetness]
points = [0.0, 0.3]
[semi_axis_ratio]
points = [0.5, 0.6]
[reference_pressure]
points = [0.7e9, 0.85e9]
"#
);

/// Axes that resolve the wet creep curves: they saturate near 0.05 % creepage (ξ̂ ≈ 0.1, the wet friction;
/// spin: c·φ with c ≈ 8 mm), so the points are dense there. Wet only: friction falls from dry to boundary
/// lubrication within w < 0.02 (h_f0 = w·20 µm against h_bl = 0.1 µm), far too steeply for two points;
/// above w = 0.3 it is nearly flat. The wet forces and the fluid load depend strongly on V, F_N and the
/// contact: narrow bands for two points each.
const VERIFY_AXES: &str = r#"
[creepage_x]
points = [0.0, 0.03, 0.06, 0.12, 0.24, 0.6]
mirrored = true
raw_limit = 0.003
[creepage_y]
points = [0.0, 0.035, 0.085, 0.18]
raw_limit = 0.001
[spin]
points = [-0.025, -0.008, 0.0, 0.008, 0.025]
raw_limit = 0.06
[normal_force]
interpolation = "log"
points = [90e3, 110e3]
[speed]
points = [27.0, 33.0]
[wetness]
points = [0.3, 1.0]
[semi_axis_ratio]
points = [0.55, 0.57]
[reference_pressure]
points = [0.76e9, 0.78e9]
"#;

fn files(name: &str, params: &str, axes: &str) -> (PathBuf, PathBuf) {
    let p = tmp(&format!("{name}-params.toml"));
    std::fs::write(&p, params).unwrap();
    let a = tmp(&format!("{name}-axes.toml"));
    std::fs::write(&a, axes).unwrap();
    (p, a)
}

fn build(params: &Path, axes: &Path, out: &Path, extra: &[&str], threads: &str) {
    let mut args = vec![
        "table",
        "build",
        "--params",
        s(params),
        "--axes",
        s(axes),
        "--out",
        s(out),
    ];
    args.extend_from_slice(extra);
    ok(&wheelrail(&args, Some(threads)));
}

fn array_files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut v: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().is_some_and(|x| x != "table.json"))
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect();
    v.sort();
    v
}

fn sidecar(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("table.json")).unwrap()).unwrap()
}

fn params_grid(n: usize) -> Params {
    let mut p = Params::default();
    p.grid.nx = n;
    p.grid.ny = n;
    p
}

/// Mirroring the contact in y, (η, φ) → (−η, −φ), gives (F_x, F_y, M_z) → (F_x, −F_y, −M_z) with the same
/// temperature and fluid load: the table stores η ≥ 0 only.
#[test]
fn y_mirror_symmetry_holds_dry_and_wet() {
    let p = params_grid(10);
    for (w, v) in [(0.0, 30.0), (0.6, 60.0)] {
        let a = OperatingPoint {
            creepage_x: 0.004,
            creepage_y: 0.003,
            spin: 0.4,
            normal_force: 90e3,
            speed: v,
            wetness: w,
        };
        let b = OperatingPoint {
            creepage_y: -a.creepage_y,
            spin: -a.spin,
            ..a
        };
        let (sa, sb) = (solve(&p, &a).unwrap(), solve(&p, &b).unwrap());
        assert!(sa.report.converged && sb.report.converged);
        let (ga, gb) = (&sa.global, &sb.global);
        let tol = 1e-7 * a.normal_force;
        assert!(ga.force_y.abs() > 100.0 * tol && ga.spin_moment.unwrap().abs() > 1e-3);
        assert!((ga.force_x - gb.force_x).abs() < tol, "w {w}");
        assert!((ga.force_y + gb.force_y).abs() < tol, "w {w}");
        assert!(
            (ga.spin_moment.unwrap() + gb.spin_moment.unwrap()).abs() < tol * 1e-2,
            "w {w}"
        );
        assert!((ga.max_temperature.unwrap() - gb.max_temperature.unwrap()).abs() < 1e-6);
        assert!((ga.fluid_load_fraction.unwrap() - gb.fluid_load_fraction.unwrap()).abs() < 1e-7);
    }
}

/// Reversing ξ alone gives (F_x, F_y, M_z) → (−F_x, F_y, M_z): exact for the dry model (wheel and rail of
/// the same steel swap their surface speeds V(1 ± ξ/2)). With fluid the film enters at the rail's speed
/// V(1 − ξ/2), so the mirror is approximate: deep in the film (w ≥ 0.1) within 1e-3·F_N even at ξ = 0.1 and
/// 100 m/s, but at the onset of boundary lubrication (inlet film h_f = w·h_f,max near h_bl, w ≈ 0.003) in
/// full slip, where the failure stress follows the film height steeply, the ±4.5 % in rail speed at
/// ξ = ±0.09 move the force by about 1e-2·F_N (measured 9.9e-3) and T_max by 17 K — the size of the whole
/// interpolation budget, which is why tables for wet running store both signs of ξ (docs/model.md §1).
#[test]
fn xi_mirror_is_exact_dry_and_approximate_wet() {
    let p = params_grid(10);
    let mut onset: f64 = 0.0;
    for (xi, w, v, f) in [
        (0.006, 0.0, 30.0, 100e3),
        (0.1, 0.0, 100.0, 200e3),
        (0.1, 0.1, 100.0, 200e3),
        (0.1, 1.0, 100.0, 100e3),
        (0.02, 1.0, 30.0, 10e3),
        (0.0915, 0.003, 30.0, 100e3),
    ] {
        let a = OperatingPoint {
            creepage_x: xi,
            creepage_y: 0.002,
            spin: 0.3,
            normal_force: f,
            speed: v,
            wetness: w,
        };
        let b = OperatingPoint {
            creepage_x: -xi,
            ..a
        };
        let (sa, sb) = (solve(&p, &a).unwrap(), solve(&p, &b).unwrap());
        assert!(sa.report.converged && sb.report.converged);
        let (ga, gb) = (&sa.global, &sb.global);
        let dx = (ga.force_x + gb.force_x).abs() / f;
        let dy = (ga.force_y - gb.force_y).abs() / f;
        if w == 0.0 {
            assert!(dx < 1e-9 && dy < 1e-9, "dry ξ {xi}: {dx:e} {dy:e}");
            assert!((ga.max_temperature.unwrap() - gb.max_temperature.unwrap()).abs() < 1e-6);
        } else if w >= 0.1 {
            assert!(dx.hypot(dy) < 1e-3, "wet ξ {xi} w {w}: {dx:e} {dy:e}");
        } else {
            onset = dx.hypot(dy);
        }
    }
    // at the onset of boundary lubrication the asymmetry is as large as the table's error budget
    assert!((5e-3..2e-2).contains(&onset), "{onset:e}");
}

#[test]
fn builds_are_identical_whatever_the_thread_count_and_shards_merge_to_the_same_arrays() {
    let (params, axes) = files("det", SMALL_GRID, SMALL_AXES);
    let one = tmp("det-1");
    let two = tmp("det-2");
    build(&params, &axes, &one, &[], "1");
    build(&params, &axes, &two, &[], "2");
    let arrays = array_files(&one);
    // six outputs, the converged flags, the film-intake codes
    assert_eq!(arrays.len(), 8);
    assert_eq!(arrays, array_files(&two));
    let (mut s1, mut s2) = (sidecar(&one), sidecar(&two));
    assert_eq!(s1["build"]["threads"], 1);
    assert_eq!(s2["build"]["threads"], 2);
    s1.as_object_mut().unwrap().remove("build");
    s2.as_object_mut().unwrap().remove("build");
    assert_eq!(s1, s2);

    let shards: Vec<PathBuf> = (1..=3).map(|k| tmp(&format!("det-shard{k}"))).collect();
    for (k, d) in shards.iter().enumerate() {
        build(
            &params,
            &axes,
            d,
            &["--shard", &format!("{}/3", k + 1)],
            "2",
        );
    }
    let info = ok(&wheelrail(&["table", "info", s(&shards[1])], None));
    assert!(info.contains("shard           2/3"), "{info}");
    // a shard is not a usable table
    let e = Table::load(&shards[0]).unwrap_err().to_string();
    assert!(e.contains("shard 1/3") && e.contains("merge"), "{e}");
    let merged = tmp("det-merged");
    let mut args = vec!["table", "merge", s(&merged)];
    // any order of the shard directories
    args.extend(shards.iter().rev().map(|p| s(p)));
    ok(&wheelrail(&args, None));
    assert_eq!(array_files(&merged), arrays);
    assert_eq!(sidecar(&merged)["build"]["merged_shards"], 3);
    // missing or repeated shards are refused
    let o = wheelrail(
        &[
            "table",
            "merge",
            s(&tmp("det-bad-merge")),
            s(&shards[0]),
            s(&shards[1]),
        ],
        None,
    );
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("exactly once"));
    let o = wheelrail(
        &[
            "table",
            "merge",
            s(&tmp("det-bad-merge")),
            s(&shards[0]),
            s(&shards[0]),
            s(&shards[1]),
        ],
        None,
    );
    assert!(!o.status.success());
    let o = wheelrail(
        &[
            "table",
            "build",
            "--shard",
            "4/3",
            "--out",
            s(&tmp("det-x")),
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(2));

    // the table reproduces the exact solver at its own points (η < 0 and ξ < 0 by mirroring), to the
    // stored f32
    let t = Table::load(&one).unwrap();
    let p = Params::from_toml_str(SMALL_GRID).unwrap();
    assert!(t.matches(&p) && !t.matches(&Params::default()));
    for q in [
        [0.6, -0.17, 0.02, 80e3, 40.0, 0.3, 0.5, 0.85e9],
        [-0.6, 0.17, -0.02, 120e3, 20.0, 0.0, 0.6, 0.7e9],
    ] {
        let (pt, e) = t.coordinates().point(&q).unwrap();
        let mut exact = p.clone();
        exact.geometry.semi_axes = Some([e.a, e.b]);
        let g = solve(&exact, &pt).unwrap().global;
        let o = t.evaluate(&pt, &e).unwrap();
        assert!(o.in_range && o.converged);
        let f = pt.normal_force;
        // the ξ mirror is exact dry and within 1e-3 F_N wet
        assert!((o.force_x - g.force_x).abs() < 1e-3 * f, "{pt:?}");
        assert!((o.force_y - g.force_y).abs() < 1e-6 * f, "{pt:?}");
        assert!((o.max_temperature - g.max_temperature.unwrap()).abs() < 0.5);
    }
    cleanup("det-");
}

/// `table build --resume` keeps a directory that holds this very build (nothing computed: the sidecar,
/// build date included, stays as it was) and builds anew where the directory holds another shard, other
/// parameters or storage, or a damaged array; the rebuilt arrays are those of the first build.
#[test]
fn a_resumed_build_keeps_its_built_shard_and_rebuilds_a_missing_other_or_damaged_one() {
    let (params, axes) = files("resume", SMALL_GRID, SMALL_AXES);
    let dir = tmp("resume-shard");
    let resume = |shard: &str, extra: &[&str]| {
        let mut args = vec![
            "table",
            "build",
            "--params",
            s(&params),
            "--axes",
            s(&axes),
            "--out",
            s(&dir),
            "--shard",
            shard,
            "--resume",
        ];
        args.extend_from_slice(extra);
        let o = wheelrail(&args, Some("2"));
        ok(&o);
        let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
        let kept = stderr.contains("already holds this build");
        assert_eq!(kept, !stderr.contains("wrote "), "{stderr}");
        kept
    };
    // missing: built
    assert!(!resume("2/8", &[]));
    let (arrays, side) = (
        array_files(&dir),
        std::fs::read(dir.join("table.json")).unwrap(),
    );
    // the same build: kept as it is
    assert!(resume("2/8", &[]));
    assert_eq!(array_files(&dir), arrays);
    assert_eq!(std::fs::read(dir.join("table.json")).unwrap(), side);
    // another shard, another storage, other parameters: built
    assert!(!resume("3/8", &[]));
    assert_eq!(sidecar(&dir)["shard"]["index"], 3);
    assert!(!resume("3/8", &["--storage", "u16"]));
    assert!(resume("3/8", &["--storage", "u16"]));
    std::fs::write(&params, "[grid]\nnx = 7\nny = 7\n").unwrap();
    assert!(!resume("3/8", &["--storage", "u16"]));
    std::fs::write(&params, SMALL_GRID).unwrap();
    // a damaged array (or a build killed while writing): built again, to the first build's bytes
    assert!(!resume("2/8", &[]));
    let mut flags = std::fs::read(dir.join("converged.npy")).unwrap();
    *flags.last_mut().unwrap() ^= 1;
    std::fs::write(dir.join("converged.npy"), flags).unwrap();
    assert!(!resume("2/8", &[]));
    assert_eq!(array_files(&dir), arrays);
    std::fs::remove_file(dir.join("force_x_per_normal_force.npy")).unwrap();
    assert!(!resume("2/8", &[]));
    assert_eq!(array_files(&dir), arrays);
    cleanup("resume");
}

/// Axes across the onset of the walls on the 8 × 8 grid (the default contact shape a/b 0.55 at 100 kN, 30
/// m/s, |ξ| ≤ 0.8 %): GW's metallic area at the dry separation covers the centre from p0 ≈ 1.55 GPa on
/// (A_m/A_n(d_dry) 0.97 at 1.5, 1.03 at 1.6 GPa), where a wet contact's friction jumps (0.085 → 0.106).
const ONSET_AXES: &str = concat!(
    small_creepages!(),
    r#"[normal_force]
points = [100e3]
[speed]
points = [30.0]
[wetness]
points = [0.0, 0.3]
[semi_axis_ratio]
points = [0.55]
[reference_pressure]
points = [1.3e9, 1.4e9, 1.7e9]
"#
);

/// A build records per node whether the film enters every cell (docs/model.md §8.5): dry nodes are dry,
/// wet nodes below the onset take in all their film and above it the metal covers part of the contact, as
/// an independent exact solve at the node says; the cells between a wet node of each kind (p_ref 1.4 to
/// 1.7 GPa) are unresolved (mode auto solves them exactly), the others are served by the table.
#[test]
fn a_build_records_where_the_metal_covers_the_contact_and_the_cells_across_the_onset_are_unresolved()
 {
    let (params, axes) = files("onset", SMALL_GRID, ONSET_AXES);
    let dir = tmp("onset-table");
    build(&params, &axes, &dir, &[], "2");
    let files = TableFiles::read(&dir).unwrap();
    let codes = files
        .film_intake
        .clone()
        .expect("the build records the film intake");
    let t = Table::load(&dir).unwrap();
    let p = Params::from_toml_str(SMALL_GRID).unwrap();
    let mut checked = 0;
    for (i, code) in codes.iter().enumerate() {
        let q = files.axes.coordinates(i);
        let want = match (q[5] > 0.0, q[7] > 1.5e9) {
            (false, _) => FilmIntake::Dry,
            (true, false) => FilmIntake::All,
            (true, true) => FilmIntake::Limited,
        };
        assert_eq!(*code, want as u8, "node {q:?}");
        // the stored code is that of the exact solution at the node (a few nodes: 8 × 8 solves)
        if i % 37 == 0 {
            let (pt, e) = t.coordinates().point(&q).unwrap();
            let mut exact = p.clone();
            exact.geometry.semi_axes = Some([e.a, e.b]);
            let g = solve(&exact, &pt).unwrap().global;
            assert_eq!(
                FilmIntake::of(pt.wetness, g.max_dry_area_fraction) as u8,
                *code
            );
            checked += 1;
        }
    }
    assert!(checked >= 3);
    for (p_ref, resolved) in [(1.35e9, true), (1.5e9, false), (1.65e9, false)] {
        for w in [0.0, 0.15, 0.3] {
            let (pt, e) = t
                .coordinates()
                .point(&[0.4, 0.1, 0.0, 100e3, 30.0, w, 0.55, p_ref])
                .unwrap();
            let o = t.evaluate(&pt, &e).unwrap();
            assert!(o.in_range);
            assert_eq!(o.resolved, resolved, "p_ref {p_ref}, w {w}");
        }
    }
    cleanup("onset-");
}

/// `--storage u16` stores each output as 16-bit codes (offset + step·code): half the bytes of the f32
/// table, every value within half a step of the f32 build's, the probe nodes still pass against the exact
/// solver, shards merge to the same bytes, and a record without its code or with a negative step is refused.
#[test]
fn a_u16_table_holds_the_f32_values_to_half_a_step_in_half_the_bytes() {
    let (params, axes) = files("u16", SMALL_GRID, SMALL_AXES);
    let (f32_dir, u16_dir) = (tmp("u16-f32"), tmp("u16-one"));
    build(&params, &axes, &f32_dir, &[], "2");
    build(&params, &axes, &u16_dir, &["--storage", "u16"], "2");
    let (a, b) = (
        TableFiles::read(&f32_dir).unwrap(),
        TableFiles::read(&u16_dir).unwrap(),
    );
    let side = sidecar(&u16_dir);
    assert_eq!(side["storage"], "u16");
    assert!(sidecar(&f32_dir).get("storage").is_none());
    for (o, rec) in b.sidecar.outputs.iter().enumerate() {
        let q = rec.quantization.expect("a quantised record");
        let (lo, hi) = a.outputs[o]
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                (l.min(f64::from(*v)), h.max(f64::from(*v)))
            });
        assert_eq!(q.offset, lo, "{}", rec.name);
        assert!((q.step * 65535.0 - (hi - lo)).abs() <= 1e-12 * (hi - lo).abs().max(1.0));
        let worst = a.outputs[o]
            .iter()
            .zip(&b.outputs[o])
            .map(|(x, y)| (f64::from(*x) - f64::from(*y)).abs())
            .fold(0.0, f64::max);
        // half a step, plus the f32 rounding of the value
        assert!(
            worst <= 0.5 * q.step + 1e-7 * hi.abs().max(lo.abs()),
            "{}: {worst:e} > step/2 = {:e}",
            rec.name,
            0.5 * q.step
        );
        assert!(worst > 0.0 || q.step == 0.0, "{}", rec.name);
        let bytes = |d: &Path| std::fs::metadata(d.join(&rec.file)).unwrap().len() as f64;
        let ratio = bytes(&u16_dir) / bytes(&f32_dir);
        assert!((0.5..0.55).contains(&ratio), "{}: {ratio}", rec.name);
    }
    assert_eq!(a.converged, b.converged);
    // the probe nodes pass against the exact solver, within half a step more than an f32 table
    // (loading checks them)
    Table::load(&u16_dir).unwrap();
    let info = ok(&wheelrail(&["table", "info", s(&u16_dir)], None));
    assert!(info.contains("storage         u16"), "{info}");

    // shards store f32, record the storage, and merge to the same bytes as one build
    let shards: Vec<PathBuf> = (1..=2).map(|k| tmp(&format!("u16-shard{k}"))).collect();
    for (k, d) in shards.iter().enumerate() {
        build(
            &params,
            &axes,
            d,
            &["--storage", "u16", "--shard", &format!("{}/2", k + 1)],
            "2",
        );
        assert_eq!(sidecar(d)["storage"], "u16");
        assert!(sidecar(d)["outputs"][0].get("quantization").is_none());
    }
    let merged = tmp("u16-merged");
    ok(&wheelrail(
        &["table", "merge", s(&merged), s(&shards[0]), s(&shards[1])],
        None,
    ));
    assert_eq!(array_files(&merged), array_files(&u16_dir));
    // shards of another storage do not merge
    let f32_shard = tmp("u16-f32-shard");
    build(&params, &axes, &f32_shard, &["--shard", "2/2"], "2");
    let o = wheelrail(
        &[
            "table",
            "merge",
            s(&tmp("u16-mixed")),
            s(&shards[0]),
            s(&f32_shard),
        ],
        None,
    );
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("storage"));

    // a quantised table whose record lost its code, or has a negative step, is refused
    let broken = |name: &str, edit: &dyn Fn(&mut serde_json::Value)| {
        let d = tmp(name);
        std::fs::create_dir_all(&d).unwrap();
        for e in std::fs::read_dir(&u16_dir).unwrap() {
            let p = e.unwrap().path();
            std::fs::copy(&p, d.join(p.file_name().unwrap())).unwrap();
        }
        let mut v = sidecar(&d);
        edit(&mut v);
        std::fs::write(d.join("table.json"), v.to_string()).unwrap();
        Table::load(&d).unwrap_err().to_string()
    };
    let e = broken("u16-no-code", &|v| {
        v["outputs"][3]
            .as_object_mut()
            .unwrap()
            .remove("quantization");
    });
    assert!(e.contains("max_temperature") && e.contains("u16"), "{e}");
    let e = broken("u16-negative", &|v| {
        v["outputs"][0]["quantization"]["step"] = (-1e-5).into();
    });
    assert!(e.contains("invalid quantisation"), "{e}");
    let e = broken("u16-as-f32", &|v| {
        v.as_object_mut().unwrap().remove("storage");
    });
    assert!(e.contains("an f32 array"), "{e}");

    // u16z, u16x: the same codes compressed (zlib, xz), read back to the u16 table's values bit for bit in
    // fewer bytes; shards merge to the bytes of one build; a stream that holds too few codes is refused
    let size = |d: &Path, f: &str| std::fs::metadata(d.join(f)).unwrap().len() as f64;
    for (storage, stream) in [("u16z", "zlib"), ("u16x", "xz")] {
        let letter = &storage[3..];
        let z_dir = tmp(&format!("u16-{storage}"));
        build(&params, &axes, &z_dir, &["--storage", storage], "2");
        let z = TableFiles::read(&z_dir).unwrap();
        assert_eq!(sidecar(&z_dir)["storage"], storage);
        assert_eq!((&z.outputs, &z.converged), (&b.outputs, &b.converged));
        for (rz, ru) in z.sidecar.outputs.iter().zip(&b.sidecar.outputs) {
            assert_eq!(rz.quantization, ru.quantization);
            assert_eq!(rz.file, format!("{}.u16{letter}", ru.name));
            let ratio = size(&z_dir, &rz.file) / size(&u16_dir, &ru.file);
            assert!(ratio < 0.75, "{storage} {}: {ratio}", rz.name);
        }
        assert_eq!(z.sidecar.converged.file, format!("converged.u8{letter}"));
        Table::load(&z_dir).unwrap(); // (loading checks the probes)
        let z_shards: Vec<PathBuf> = (1..=2)
            .map(|k| tmp(&format!("u16-{storage}shard{k}")))
            .collect();
        for (k, d) in z_shards.iter().enumerate() {
            let shard = format!("{}/2", k + 1);
            build(
                &params,
                &axes,
                d,
                &["--storage", storage, "--shard", &shard],
                "2",
            );
        }
        let z_merged = tmp(&format!("u16-{storage}merged"));
        ok(&wheelrail(
            &[
                "table",
                "merge",
                s(&z_merged),
                s(&z_shards[0]),
                s(&z_shards[1]),
            ],
            None,
        ));
        assert_eq!(array_files(&z_merged), array_files(&z_dir));
        let cut = tmp(&format!("u16-{storage}cut"));
        std::fs::create_dir_all(&cut).unwrap();
        for (name, bytes) in array_files(&z_dir) {
            std::fs::write(cut.join(name), bytes).unwrap();
        }
        let mut v = sidecar(&z_dir);
        let file = z.sidecar.outputs[1].file.clone();
        let bytes = std::fs::read(z_dir.join(&file)).unwrap();
        let short = &bytes[..bytes.len() / 2];
        std::fs::write(cut.join(&file), short).unwrap();
        v["outputs"][1]["sha256"] = wheelrail::table::file::sha256_hex(short).into();
        std::fs::write(cut.join("table.json"), v.to_string()).unwrap();
        let e = Table::load(&cut).unwrap_err().to_string();
        assert!(e.contains(&file) && e.contains(stream), "{e}");
    }

    // --resolution F,T: codes step by max(range/65 535, F) (T for T_max), every value within half of that
    // of the f32 build's, exact zeros kept, fewer bytes than the finest codes, the probes still pass
    let coarse = tmp("u16-coarse");
    let coarse_args = ["--storage", "u16x", "--resolution", "1e-3,0.5"];
    build(&params, &axes, &coarse, &coarse_args, "2");
    let c = TableFiles::read(&coarse).unwrap();
    let res = &sidecar(&coarse)["resolution"];
    assert_eq!(
        (
            res["per_normal_force"].as_f64(),
            res["temperature"].as_f64()
        ),
        (Some(1e-3), Some(0.5))
    );
    let mut zeros = 0;
    for (o, (rc, ru)) in c.sidecar.outputs.iter().zip(&b.sidecar.outputs).enumerate() {
        let (q, fine) = (rc.quantization.unwrap(), ru.quantization.unwrap());
        let floor = if rc.name == "max_temperature" {
            0.5
        } else {
            1e-3
        };
        assert_eq!(q.step, fine.step.max(floor), "{}", rc.name);
        for (x, y) in a.outputs[o].iter().zip(&c.outputs[o]) {
            let err = (f64::from(*x) - f64::from(*y)).abs();
            assert!(
                err <= 0.5 * q.step + 1e-7 * f64::from(x.abs()),
                "{}: {x} {y}",
                rc.name
            );
            if *x == 0.0 {
                zeros += 1;
                assert_eq!(*y, 0.0, "{}", rc.name);
            }
        }
        // the coarser codes compress to fewer bytes (the f32 table varies by more than F over its range)
        let fine_x = size(
            &u16_dir.with_file_name("u16-u16x"),
            &ru.file.replace(".npy", ".u16x"),
        );
        assert!(size(&coarse, &rc.file) < 0.8 * fine_x, "{}", rc.name);
    }
    // F_x/F_N at zero creepage and the dry fluid load fraction
    assert!(zeros > 10, "{zeros}");
    Table::load(&coarse).unwrap(); // (loading checks the probes)
    let info = ok(&wheelrail(&["table", "info", s(&coarse)], None));
    assert!(
        info.contains("resolution      codes step by at least 0.001"),
        "{info}"
    );
    // a build with another resolution (or none) is not the one --resume keeps
    let resumed = |extra: &[&str]| {
        let mut args = vec!["table", "build", "--params", s(&params), "--axes", s(&axes)];
        args.extend(["--out", s(&coarse), "--resume"]);
        args.extend(extra);
        String::from_utf8_lossy(&wheelrail(&args, Some("2")).stderr).into_owned()
    };
    assert!(resumed(&coarse_args).contains("already holds this build"));
    assert!(
        !resumed(&["--storage", "u16x", "--resolution", "1e-3,0.25"]).contains("already holds")
    );
    // shards record the resolution and merge to the bytes of one build; other resolutions do not merge
    let res_shards: Vec<PathBuf> = (1..=2).map(|k| tmp(&format!("u16-res-shard{k}"))).collect();
    for (k, d) in res_shards.iter().enumerate() {
        let shard = format!("{}/2", k + 1);
        let args = [
            "--storage",
            "u16x",
            "--resolution",
            "1e-3,0.5",
            "--shard",
            &shard,
        ];
        build(&params, &axes, d, &args, "2");
    }
    let res_merged = tmp("u16-res-merged");
    let merge = |out: &Path, second: &Path| {
        let args = ["table", "merge", s(out), s(&res_shards[0]), s(second)];
        wheelrail(&args, None)
    };
    ok(&merge(&res_merged, &res_shards[1]));
    build(&params, &axes, &coarse, &coarse_args, "2");
    assert_eq!(array_files(&res_merged), array_files(&coarse));
    let other = tmp("u16-res-other");
    let args = [
        "--storage",
        "u16x",
        "--resolution",
        "2e-3,0.5",
        "--shard",
        "2/2",
    ];
    build(&params, &axes, &other, &args, "2");
    let o = merge(&tmp("u16-res-mixed"), &other);
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("resolution"));
    // the merge may store the f32 values of the shards otherwise: f32 as the f32 build, another resolution
    let remerge = |name: &str, extra: &[&str]| {
        let out = tmp(name);
        let mut args = vec![
            "table",
            "merge",
            s(&out),
            s(&res_shards[0]),
            s(&res_shards[1]),
        ];
        args.extend(extra);
        let o = wheelrail(&args, None);
        (out, o)
    };
    let (as_f32, o) = remerge("u16-res-as-f32", &["--storage", "f32"]);
    ok(&o);
    assert_eq!(array_files(&as_f32), array_files(&f32_dir));
    assert!(sidecar(&as_f32).get("resolution").is_none());
    let (finer, o) = remerge("u16-res-finer", &["--resolution", "2e-4,0.1"]);
    ok(&o);
    let side = sidecar(&finer);
    assert_eq!(
        (
            side["storage"].as_str(),
            side["resolution"]["per_normal_force"].as_f64()
        ),
        (Some("u16x"), Some(2e-4))
    );
    assert!(
        size(&finer, "force_x_per_normal_force.u16x")
            > size(&coarse, "force_x_per_normal_force.u16x")
    );
    let (_, o) = remerge(
        "u16-res-bad",
        &["--storage", "f32", "--resolution", "1e-4,0.1"],
    );
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("resolution"));
    // refused: a resolution without u16 storage, a malformed one, one recorded in an f32 table
    for bad in [
        &["--resolution", "1e-4,0.1"][..],
        &["--storage", "u16", "--resolution", "1e-4"],
    ] {
        let mut args = vec!["table", "build", "--axes", s(&axes), "--out", s(&other)];
        args.extend(bad);
        let o = wheelrail(&args, None);
        assert!(!o.status.success(), "{bad:?}");
        assert!(
            String::from_utf8_lossy(&o.stderr).contains("resolution"),
            "{bad:?}"
        );
    }
    let e = broken("u16-res-f32", &|v| {
        v["resolution"] = serde_json::json!({"per_normal_force": 1e-4, "temperature": 0.1});
        v.as_object_mut().unwrap().remove("storage");
    });
    assert!(e.contains("resolution") && e.contains("u16 storage"), "{e}");
    cleanup("u16-");
}

#[test]
fn corrupt_or_mismatched_tables_are_refused_with_clear_errors() {
    let (params, axes) = files("bad", SMALL_GRID, SMALL_AXES);
    let good = tmp("bad-good");
    build(&params, &axes, &good, &[], "2");
    Table::load(&good).unwrap();
    let copy = |name: &str| {
        let d = tmp(name);
        std::fs::create_dir_all(&d).unwrap();
        for e in std::fs::read_dir(&good).unwrap() {
            let p = e.unwrap().path();
            std::fs::copy(&p, d.join(p.file_name().unwrap())).unwrap();
        }
        d
    };
    let err = |d: &Path| Table::load(d).unwrap_err().to_string();
    let array = "force_x_per_normal_force.npy";

    let d = copy("bad-flip");
    let mut b = std::fs::read(d.join(array)).unwrap();
    let n = b.len();
    b[n - 3] ^= 0x10;
    std::fs::write(d.join(array), &b).unwrap();
    let e = err(&d);
    assert!(e.contains("SHA-256 mismatch") && e.contains(array), "{e}");
    // the CLI reports it on one line and exits non-zero
    let o = wheelrail(&["point", "--table", s(&d), "--params", s(&params)], None);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("SHA-256 mismatch"));

    let d = copy("bad-truncated");
    std::fs::write(d.join(array), &b[..n / 2]).unwrap();
    assert!(err(&d).contains("SHA-256 mismatch"));

    let d = copy("bad-missing");
    std::fs::remove_file(d.join("converged.npy")).unwrap();
    let e = err(&d);
    assert!(
        e.contains("converged.npy") && e.contains("cannot read"),
        "{e}"
    );

    let d = copy("bad-fingerprint");
    let mut v = sidecar(&d);
    v["fingerprint"] = "0".repeat(64).into();
    std::fs::write(d.join("table.json"), v.to_string()).unwrap();
    assert!(err(&d).contains("fingerprint mismatch"));

    // a changed parameter is caught even with the array hashes intact
    let d = copy("bad-params");
    let mut v = sidecar(&d);
    v["params"]["roughness"]["k_r"] = 0.6.into();
    std::fs::write(d.join("table.json"), v.to_string()).unwrap();
    assert!(err(&d).contains("fingerprint mismatch"));

    let d = copy("bad-version");
    let mut v = sidecar(&d);
    v["format_version"] = 99.into();
    std::fs::write(d.join("table.json"), v.to_string()).unwrap();
    assert!(err(&d).contains("format version 99"));
    let mut v = sidecar(&d);
    v["format_version"] = 1.into();
    v["model_version"] = "0.0.1".into();
    std::fs::write(d.join("table.json"), v.to_string()).unwrap();
    assert!(err(&d).contains("model version 0.0.1"));

    let d = copy("bad-json");
    std::fs::write(d.join("table.json"), "{ not json").unwrap();
    assert!(err(&d).contains("malformed sidecar"));
    assert!(err(&tmp("bad-no-such-table")).contains("cannot read the sidecar"));

    // point --table with parameters other than the table's
    let o = wheelrail(&["point", "--table", s(&good)], None);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("other parameters"));
    cleanup("bad-");
}

/// The spot check of a table against the exact solver: a table built here passes `table verify`; the same
/// arrays relabelled as computed for other parameters (a stale table with a consistent sidecar) fail it.
/// `wheelrail table verify DIR --samples N --json --csv CSV`: the JSON report, and the CSV's header and rows.
fn verify_with_csv(
    dir: &Path,
    csv: &Path,
    samples: usize,
) -> (serde_json::Value, Vec<String>, Vec<Vec<f64>>) {
    let n = samples.to_string();
    let o = wheelrail(
        &[
            "table",
            "verify",
            s(dir),
            "--samples",
            &n,
            "--json",
            "--csv",
            s(csv),
        ],
        None,
    );
    let r: serde_json::Value = serde_json::from_str(ok(&o).trim()).unwrap();
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (r, header, rows)
}

#[test]
fn verify_passes_a_good_table_and_fails_a_stale_one() {
    let (params, axes) = files("ver", SMALL_GRID, VERIFY_AXES);
    let dir = tmp("ver-table");
    build(&params, &axes, &dir, &[], "2");
    let (r, header, rows) = verify_with_csv(&dir, &tmp("ver-samples.csv"), 60);
    assert_eq!(r["compared"], 60, "{r}");
    let p99 = r["force"]["p99"].as_f64().unwrap();
    let max = r["force"]["max"].as_f64().unwrap();
    assert!(p99 <= 0.01 && max <= 0.03, "{r}");
    // not trivially zero: the samples fall between the points
    assert!(r["force"]["mean"].as_f64().unwrap() > 1e-6, "{r}");
    // the errors per cell of each axis: every compared sample in one cell per axis, the largest error in
    // one of them; p_ref's two points make one cell, which holds them all
    let cells = r["cells"].as_array().unwrap();
    for axis in ["creepage_x", "spin", "normal_force", "reference_pressure"] {
        let of: Vec<&serde_json::Value> = cells.iter().filter(|c| c["axis"] == axis).collect();
        let count: u64 = of.iter().map(|c| c["compared"].as_u64().unwrap()).sum();
        assert_eq!(count, 60, "{axis}");
        let top = of
            .iter()
            .map(|c| c["force"]["max"].as_f64().unwrap())
            .fold(0.0, f64::max);
        assert_eq!(top, max, "{axis}");
    }
    let p_ref: Vec<&serde_json::Value> = cells
        .iter()
        .filter(|c| c["axis"] == "reference_pressure")
        .collect();
    assert_eq!(p_ref.len(), 1);
    assert_eq!(p_ref[0]["force"], r["force"]);
    assert_eq!(p_ref[0]["max_temperature"], r["max_temperature"]);

    // --csv: one row per compared sample; its columns give the report's force errors, and its exact
    // columns are what `wheelrail point` gives at the row's operating point and contact
    assert_eq!(rows.len(), 60);
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let force_error = |row: &[f64]| {
        (row[col("table_force_x")] - row[col("exact_force_x")])
            .hypot(row[col("table_force_y")] - row[col("exact_force_y")])
            / row[col("normal_force")]
    };
    let largest = rows.iter().map(|row| force_error(row)).fold(0.0, f64::max);
    assert!((largest - max).abs() <= 1e-12 * max, "{largest} {max}");
    for row in &rows {
        assert!((force_error(row) - row[col("force_error")]).abs() <= 1e-15);
    }
    // and the flags of the samples mode auto solves exactly, as the report counts them
    for (flag, key) in [
        ("table_resolved", "unresolved"),
        ("table_converged", "table_unconverged"),
    ] {
        let not = rows.iter().filter(|row| row[col(flag)] == 0.0).count();
        assert_eq!(Some(not as u64), r[key].as_u64(), "{flag}");
    }
    let row = &rows[7];
    let arg = |name: &str| format!("{:e}", row[col(name)]);
    let exact = ok(&wheelrail(
        &[
            "point",
            "--params",
            s(&params),
            "--creepage-x",
            &arg("creepage_x"),
            "--creepage-y",
            &arg("creepage_y"),
            "--spin",
            &arg("spin"),
            "--normal-force",
            &arg("normal_force"),
            "--speed",
            &arg("speed"),
            "--wetness",
            &arg("wetness"),
            "--semi-axes",
            &format!("{},{}", arg("semi_axis_a"), arg("semi_axis_b")),
            "--json",
        ],
        None,
    ));
    let exact: serde_json::Value = serde_json::from_str(exact.trim()).unwrap();
    for (key, name) in [
        ("force_x", "exact_force_x"),
        ("max_temperature", "exact_max_temperature"),
    ] {
        let v = exact[key].as_f64().unwrap();
        assert!(
            (v - row[col(name)]).abs() <= 1e-9 * v.abs().max(1.0),
            "{key}: {v} vs {}",
            row[col(name)]
        );
    }
    let info = ok(&wheelrail(&["table", "info", s(&dir)], None));
    assert!(
        info.contains("3840 = ξ 6 × η 4 × φ 5 × F_N 2 × V 2 × w 2 × a/b 2 × p_ref 2"),
        "{info}"
    );
    // the interpolation of each axis as the table records it (F_N in ln F_N here)
    assert!(
        info.contains("[N] Log") && info.contains("[m/s] Linear") && info.contains("[-] Cubic"),
        "{info}"
    );
    // and the variable T_max is interpolated in (the default steel's)
    assert!(
        info.contains("T_max           interpolated as G = (T - T0)/sqrt(sigma_y(T)/sigma_y(T0))"),
        "{info}"
    );
    assert!(
        info.contains("interpolated per unit of FASTSIM's direction factor L/L1"),
        "{info}"
    );

    // stale: the arrays of k_wet = 0.4 presented as k_wet = 0.3 (boundary-lubrication failure stress),
    // sidecar consistent (fingerprint recomputed)
    let mut v = sidecar(&dir);
    let mut p = Params::from_toml_str(SMALL_GRID).unwrap();
    p.fluid.k_wet = 0.3;
    v["params"] = serde_json::to_value(&p).unwrap();
    v["fingerprint"] = wheelrail::table::fingerprint(&p).into();
    std::fs::write(dir.join("table.json"), v.to_string()).unwrap();
    // loading refuses it (its probe nodes no longer match the exact solver) …
    let e = Table::load(&dir).unwrap_err().to_string();
    assert!(e.contains("computed by another model"), "{e}");
    // … and `table verify` measures how far off it is
    let o = wheelrail(&["table", "verify", s(&dir), "--samples", "20"], None);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    assert!(String::from_utf8_lossy(&o.stderr).contains("accuracy target missed"));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("MISSED"));
    // the cells that miss the target are marked
    assert!(
        text.contains("by cell of each axis") && text.contains(" *\n"),
        "{text}"
    );
    assert!(
        text.contains("T_max target (p99 <= 10 K, reported only): "),
        "{text}"
    );
    cleanup("ver-");
}

/// A table built by the model's similarity (docs/model.md §9.1: `[speed] similarity = true`, the normal
/// force axis 100 kN alone, the speed points equivalent speeds V·sqrt(F_N/100 kN)) serves contacts of every
/// load: `table verify` samples loads 10–250 kN and meets the target there (the same bands as
/// `verify_passes_a_good_table_and_fails_a_stale_one`'s table, whose F_N axis is 90–110 kN), each sample
/// row is a real contact at its load (its exact columns are `wheelrail point`'s there) and `point --table`
/// at a row gives the row's table columns; `table info` says so.
#[test]
fn a_table_by_similarity_serves_every_load() {
    let axes = VERIFY_AXES
        .replace(
            "interpolation = \"log\"\npoints = [90e3, 110e3]",
            "points = [100e3]",
        )
        .replace(
            "[speed]\npoints = [27.0, 33.0]",
            "[speed]\nsimilarity = true\npoints = [27.0, 33.0]\nsqrt_from = 27.0",
        );
    assert!(axes.contains("similarity = true") && axes.contains("[100e3]"));
    let (params, axes) = files("sim", SMALL_GRID, &axes);
    let dir = tmp("sim-table");
    build(&params, &axes, &dir, &[], "2");
    let info = ok(&wheelrail(&["table", "info", s(&dir)], None));
    assert!(
        info.contains("similarity: equivalent speeds")
            && info.contains("F_N 1 × V 2")
            && info.contains("(in sqrt(V) from 27 on)"),
        "{info}"
    );
    let (r, header, rows) = verify_with_csv(&dir, &tmp("sim-samples.csv"), 60);
    assert_eq!(r["compared"], 60, "{r}");
    let (p99, max) = (
        r["force"]["p99"].as_f64().unwrap(),
        r["force"]["max"].as_f64().unwrap(),
    );
    assert!(p99 <= 0.01 && max <= 0.03, "{r}");
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let loads: Vec<f64> = rows.iter().map(|row| row[col("normal_force")]).collect();
    let (lo, hi) = loads
        .iter()
        .fold((f64::MAX, 0.0f64), |(a, b), f| (a.min(*f), b.max(*f)));
    assert!(
        (10e3..40e3).contains(&lo) && (160e3..=250e3).contains(&hi),
        "{lo} {hi}"
    );
    // the speed cell is interpolated in √V: verify's cell midpoints are equivalent speeds at the middle
    // of √V, ((√27 + √33)/2)² = 29.95 m/s, not 30 m/s
    let equivalent = |r: &Vec<f64>| r[col("speed")] * (r[col("normal_force")] / 100e3).sqrt();
    let middle = (0.5 * (27f64.sqrt() + 33f64.sqrt())).powi(2);
    let at = |v: f64| {
        rows.iter()
            .filter(|r| (equivalent(r) - v).abs() < 1e-9)
            .count()
    };
    assert!(
        at(middle) > 5 && at(30.0) == 0,
        "{} {}",
        at(middle),
        at(30.0)
    );
    // the row of the load farthest from 100 kN
    let row = rows
        .iter()
        .max_by(|a, b| {
            let far = |r: &Vec<f64>| (r[col("normal_force")] / 100e3).ln().abs();
            far(a).total_cmp(&far(b))
        })
        .unwrap();
    let arg = |name: &str| format!("{:e}", row[col(name)]);
    let point = |table: bool| {
        let semi_axes = format!("{},{}", arg("semi_axis_a"), arg("semi_axis_b"));
        let mut args = vec![
            "point".to_string(),
            "--params".into(),
            s(&params).into(),
            "--semi-axes".into(),
            semi_axes,
            "--json".into(),
        ];
        for (flag, name) in [
            ("--creepage-x", "creepage_x"),
            ("--creepage-y", "creepage_y"),
            ("--spin", "spin"),
            ("--normal-force", "normal_force"),
            ("--speed", "speed"),
            ("--wetness", "wetness"),
        ] {
            args.push(flag.into());
            args.push(arg(name));
        }
        if table {
            args.push("--table".into());
            args.push(s(&dir).into());
        }
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let v: serde_json::Value =
            serde_json::from_str(ok(&wheelrail(&args, None)).trim()).unwrap();
        v
    };
    for (table, prefix) in [(false, "exact_"), (true, "table_")] {
        let v = point(table);
        if table {
            assert_eq!(
                (&v["evaluation"], &v["in_range"]),
                (&"table".into(), &true.into()),
                "{v}"
            );
        }
        for key in ["force_x", "max_temperature"] {
            let (x, want) = (
                v[key].as_f64().unwrap(),
                row[col(&format!("{prefix}{key}"))],
            );
            // the command line's numbers pass through `{:e}` text: 1e-9 of the scale
            assert!(
                (x - want).abs() <= 1e-9 * want.abs().max(1.0),
                "{prefix}{key}: {x} vs {want}"
            );
        }
    }
    cleanup("sim-");
}

#[test]
fn point_by_table_has_the_exact_keys_and_agrees_at_table_points() {
    let (params, axes) = files("pt", SMALL_GRID, SMALL_AXES);
    let dir = tmp("pt-table");
    build(&params, &axes, &dir, &[], "2");
    // a table point: its raw creepages and contact (prescribed semi-axes) in full precision
    let t = Table::load(&dir).unwrap();
    let (pt, e) = t
        .coordinates()
        .point(&[0.6, 0.17, -0.02, 120e3, 20.0, 0.0, 0.6, 0.7e9])
        .unwrap();
    let text = [
        format!("{:?}", pt.creepage_x),
        format!("{:?}", pt.creepage_y),
        format!("{:?}", pt.spin),
        format!("{:?},{:?}", e.a, e.b),
    ];
    let args = |table: bool| {
        let mut a = vec![
            "point",
            "--json",
            "--params",
            s(&params),
            "--creepage-x",
            &text[0],
            "--creepage-y",
            &text[1],
            "--spin",
            &text[2],
            "--semi-axes",
            &text[3],
            "--normal-force",
            "120000",
            "--speed",
            "20",
            "--wetness",
            "0",
        ];
        if table {
            a.extend(["--table", s(&dir)]);
        }
        a
    };
    let t: serde_json::Value = serde_json::from_str(&ok(&wheelrail(&args(true), None))).unwrap();
    let e: serde_json::Value = serde_json::from_str(&ok(&wheelrail(&args(false), None))).unwrap();
    assert_eq!(t["evaluation"], "table");
    assert_eq!(e["evaluation"], "exact");
    assert_eq!(t["in_range"], true);
    // the stored values are f32 (relative 6e-8)
    for k in [
        "force_x",
        "force_y",
        "spin_moment",
        "traction_coefficient",
        "max_temperature",
        "fluid_load_fraction",
        "semi_axis_a",
        "semi_axis_b",
        "peak_pressure",
        "normal_force",
        "frictional_power",
    ] {
        let (a, b) = (t[k].as_f64().unwrap(), e[k].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-6 * b.abs().max(1.0), "{k}: {a} vs {b}");
    }
    assert_eq!(t["converged"], true);
    assert_eq!(t["friction_law"], e["friction_law"]);
    // outside the ranges: clamped, flagged, warned
    let mut a = args(true);
    let speed = a.iter().position(|x| *x == "20").unwrap();
    a[speed] = "90";
    let o = wheelrail(&a, None);
    let v: serde_json::Value = serde_json::from_str(&ok(&o)).unwrap();
    assert_eq!(v["in_range"], false);
    assert!(String::from_utf8_lossy(&o.stderr).contains("outside the table's ranges"));
    cleanup("pt-");
}

/// The default table committed under fmu/resources/table (bundled in the FMU) is for the default
/// parameters and agrees with the present exact solver: a table left stale by a model change fails here.
#[test]
fn the_bundled_default_table_agrees_with_the_exact_solver() {
    use wheelrail::table::verify::{sample_points, verify};
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fmu/resources/table");
    let t = Table::load(&dir).unwrap_or_else(|e| {
        panic!(
            "the default table must be committed at {} (`make table`): {e}",
            dir.display()
        )
    });
    assert!(
        t.matches(&Params::default()),
        "the bundled table was built for other parameters than the defaults"
    );
    assert!(t.sidecar().unconverged.is_empty());
    // random points over the whole ranges and cell midpoints
    let report = verify(&t, &sample_points(&t, 200, 2026), &|| ()).unwrap();
    assert_eq!(report.compared, 200, "{report:?}");
    assert!(
        report.meets_target(),
        "table against the exact solver: |ΔF|/F_N p99 {:.2e}, max {:.2e} (target 0.01, 0.03)",
        report.force.p99,
        report.force.max
    );
}

/// `table slurm` writes scripts whose tasks, run as Slurm runs them (`SLURM_ARRAY_TASK_ID` = 1..N, from
/// another working directory), build the shards and merge them to the one-process table: relative paths
/// become absolute, paths with spaces and quotes survive. `tools/slurm-test.sh` submits them to a real Slurm.
#[test]
fn slurm_scripts_run_task_by_task_merge_to_the_one_process_table() {
    let (params, axes) = files("slurm it's", SMALL_GRID, SMALL_AXES);
    let job = tmp("slurm job dir");
    let dir = job.parent().unwrap();
    let name = |p: &Path| p.file_name().unwrap().to_str().unwrap().to_string();
    let generate = |shards: &str| {
        Command::new(env!("CARGO_BIN_EXE_wheelrail"))
            .current_dir(dir)
            .args(["table", "slurm", "--shards", shards, "--out", &name(&job)])
            .args(["--params", &name(&params), "--axes", &name(&axes)])
            .args(["--cpus-per-task", "2", "--verify-samples", "0"])
            .output()
            .unwrap()
    };
    // 2·2·2·2·2 = 32 creepage cubes (F_N, V, w, a/b, p_ref): at most 32 shards
    let o = generate("33");
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("1 ..= 32"));
    let out = ok(&generate("3"));
    assert!(out.contains("submit.sh"), "{out}");
    let script = std::fs::read_to_string(job.join("build.sbatch")).unwrap();
    for line in [
        "#SBATCH --array=1-3\n".to_string(),
        "#SBATCH --cpus-per-task=2\n".to_string(),
        format!("OUT='{}'\n", s(&job)),
        format!("PARAMS='{}'\n", s(&params).replace('\'', r"'\''")),
        format!("AXES='{}'\n", s(&axes).replace('\'', r"'\''")),
    ] {
        assert!(script.contains(&line), "missing {line:?} in\n{script}");
    }
    let run = |file: &str, task: Option<usize>| {
        let mut c = Command::new("bash");
        c.arg(job.join(file))
            .current_dir("/")
            .env("SLURM_CPUS_PER_TASK", "1");
        if let Some(k) = task {
            c.env("SLURM_ARRAY_TASK_ID", k.to_string());
        }
        ok(&c.output().unwrap());
    };
    for k in 1..=3 {
        run("build.sbatch", Some(k));
    }
    run("merge.sbatch", None);
    let one = tmp("slurm-one");
    build(&params, &axes, &one, &[], "2");
    assert_eq!(array_files(&job.join("table")), array_files(&one));
    assert_eq!(sidecar(&job.join("shards/2"))["shard"]["index"], 2);
    assert_eq!(sidecar(&job.join("table"))["build"]["merged_shards"], 3);
    cleanup("slurm");
}

/// Tiny axes around the default contact for a table of the exact tangential solver.
const TINY_AXES: &str = r#"
[creepage_x]
points = [0.0, 0.2, 0.6, 1.8]
raw_limit = 0.008
[creepage_y]
points = [0.0, 0.17, 0.6, 1.8]
raw_limit = 0.003
[spin]
points = [-0.1, -0.02, 0.02, 0.1]
raw_limit = 0.2
[normal_force]
points = [100e3]
[speed]
points = [30.0]
[wetness]
points = [0.0]
[semi_axis_ratio]
points = [0.5, 0.6]
[reference_pressure]
points = [0.7e9, 0.85e9]
"#;

/// `table build --tangential exact` records the method in table.json's parameters; the table serves only
/// points of the same method (with FASTSIM's parameters `point --table` refuses it).
#[test]
fn a_table_of_the_exact_tangential_solver_records_it() {
    let (params, axes) = files("tangential", SMALL_GRID, TINY_AXES);
    let dir = tmp("tangential-table");
    build(&params, &axes, &dir, &["--tangential", "exact"], "2");
    let side = sidecar(&dir);
    assert_eq!(side["params"]["tangential"], "exact", "{}", side["params"]);
    let t = Table::load(&dir).unwrap();
    let mut exact = params_grid(8);
    exact.tangential = wheelrail::Tangential::Exact;
    assert!(t.matches(&exact) && !t.matches(&params_grid(8)));
    let point = |extra: &[&str]| {
        let mut a = vec![
            "point",
            "--json",
            "--params",
            s(&params),
            "--creepage-x",
            "0.001",
            "--table",
            s(&dir),
        ];
        a.extend_from_slice(extra);
        wheelrail(&a, None)
    };
    let v: serde_json::Value =
        serde_json::from_str(&ok(&point(&["--tangential", "exact"]))).unwrap();
    assert_eq!(v["evaluation"], "table");
    assert_eq!(v["tangential"], "exact");
    let o = point(&[]);
    assert!(!o.status.success());
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("other parameters"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    cleanup("tangential-");
}

/// `point` with `--table` repeated: each point by the first table that covers its contact (bit for bit
/// that table's result alone), a contact neither covers by the exact solver in auto mode (the warning
/// names both tables) and refused in table mode.
#[test]
fn point_takes_several_tables_in_order() {
    let flange_axes = SMALL_AXES
        .replace("points = [0.5, 0.6]", "points = [2.0, 2.4]")
        .replace("points = [0.7e9, 0.85e9]", "points = [1.0e9, 1.2e9]");
    let (params, tread_axes) = files("set-tread", SMALL_GRID, SMALL_AXES);
    let (_, flange_axes) = files("set-flange", SMALL_GRID, &flange_axes);
    let (tread, flange) = (tmp("set-tread-table"), tmp("set-flange-table"));
    build(&params, &tread_axes, &tread, &[], "2");
    build(&params, &flange_axes, &flange, &[], "2");
    let ellipse = |ratio: f64, p_ref: f64| {
        let [a, b] = wheelrail::table::coords::semi_axes(ratio, p_ref, 100e3);
        format!("{a:e},{b:e}")
    };
    let point = |tables: &[&PathBuf], mode: &str, semi_axes: &str| {
        let mut args = vec![
            "point",
            "--params",
            s(&params),
            "--creepage-x",
            "0.002",
            "--semi-axes",
            semi_axes,
            "--mode",
            mode,
            "--json",
        ];
        for t in tables {
            args.extend(["--table", s(t)]);
        }
        wheelrail(&args, None)
    };
    let json = |o: &Output| -> serde_json::Value { serde_json::from_str(ok(o).trim()).unwrap() };
    for (semi_axes, alone) in [
        (ellipse(0.55, 0.77e9), &tread),
        (ellipse(2.2, 1.1e9), &flange),
    ] {
        let both = json(&point(&[&tread, &flange], "table", &semi_axes));
        assert_eq!(both["evaluation"], "table", "{both}");
        assert_eq!(both, json(&point(&[alone], "table", &semi_axes)));
    }
    // between the two: exact in auto mode, with a warning naming both; refused in table mode
    let between = ellipse(1.0, 0.9e9);
    let o = point(&[&tread, &flange], "auto", &between);
    assert_eq!(json(&o)["evaluation"], "exact");
    let warning = String::from_utf8_lossy(&o.stderr);
    assert!(
        warning.contains(&format!("{}; {}", s(&tread), s(&flange)))
            && warning.contains("another contact geometry"),
        "{warning}"
    );
    let o = point(&[&tread, &flange], "table", &between);
    assert_eq!(o.status.code(), Some(1));
    cleanup("set-");
}

/// Hertz's ellipse in closed form (docs/model.md §2; K. L. Johnson, *Contact Mechanics*, 1985, §4.2),
/// computed here independently of the library: [a/b, p0] of gap curvatures A (along x), B [1/m] at F_N
/// [N] for steel on steel (E 210 GPa, ν 0.28). The eccentricity e of the major axis m (along the smaller
/// curvature) solves A_l/A_s = (E(e)/(1 − e²) − K(e))/(K(e) − E(e)) (bisection), K and E by the
/// arithmetic–geometric mean; m³ = 3F_N(K − E)/(2π E* e² A_s), n = m·sqrt(1 − e²), p0 = 3F_N/(2π m n);
/// a circle (A = B) m³ = 3F_N/(8E*A).
fn hertz_closed_form(curv_x: f64, curv_y: f64, force: f64) -> [f64; 2] {
    use std::f64::consts::PI;
    let e_star = 210e9 / (2.0 * (1.0 - 0.28f64.powi(2)));
    let (small, large) = (curv_x.min(curv_y), curv_x.max(curv_y));
    let elliptic = |e: f64| {
        // K = π/(2·AGM(1, k')), E = K·(1 − Σ 2^(n−1) c_n²) (Abramowitz & Stegun 17.6)
        let (mut a, mut g, mut sum, mut pow) = (1.0f64, (1.0 - e * e).sqrt(), e * e / 2.0, 0.5);
        while (a - g).abs() > 1e-15 * a {
            let c = 0.5 * (a - g);
            (a, g) = (0.5 * (a + g), (a * g).sqrt());
            pow *= 2.0;
            sum += pow * c * c;
        }
        let k = PI / (2.0 * a);
        (k, k * (1.0 - sum))
    };
    let (major, minor) = if large / small < 1.0 + 1e-12 {
        let m = (3.0 * force / (8.0 * e_star * small)).cbrt();
        (m, m)
    } else {
        let ratio = |e: f64| {
            let (k, ee) = elliptic(e);
            (ee / (1.0 - e * e) - k) / (k - ee)
        };
        let (mut lo, mut hi) = (1e-9, 1.0 - 1e-15);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if ratio(mid) < large / small {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let e = 0.5 * (lo + hi);
        let (k, ee) = elliptic(e);
        let m = (3.0 * force * (k - ee) / (2.0 * PI * e_star * e * e * small)).cbrt();
        (m, m * (1.0 - e * e).sqrt())
    };
    let (a, b) = if curv_x <= curv_y {
        (major, minor)
    } else {
        (minor, major)
    };
    [a / b, 3.0 * force / (2.0 * PI * a * b)]
}

fn plan(args: &[&str]) -> Output {
    let mut all = vec!["table", "plan"];
    all.extend_from_slice(args);
    wheelrail(&all, None)
}

/// `table plan` writes axes whose a/b and p0 nodes cover every contact of the file at every load it names
/// (p0 = p_ref·(F_N/100 kN)^(1/3), p_ref of each row computed here from Hertz's closed forms), in cells no
/// wider than the designs' (1.9× in a/b, 1.5× in p0 below 0.76 GPa, 1.1045× above), with the base's other
/// axes; it prints the points, the cost, the f32 bytes and a `table slurm` command that accepts the axes.
#[test]
fn a_plan_covers_every_contact_of_its_file() {
    // flange-root and running-surface contacts over lateral shift as an MBS tool exports them: curvatures,
    // with a column the plan ignores, a comment and the circle A = B; and semi-axes at a stated load
    let curvatures = "# contact geometry over the lateral shift\n\
        y,A,B\n\
        -0.004, 1.015, 0.4215\n\
        0.000, 1.10, 0.30   # running surface\n\
        0.006, 1.20, 1.20\n\
        0.008, 2.5, 0.9\n";
    let semi_axes = "\"a\",\"b\",\"normal_force\"\n0.004,0.0015,80e3\n\"0.006\",0.003,120e3\n";
    let c = tmp("plan-curvatures.csv");
    std::fs::write(&c, curvatures).unwrap();
    let sa = tmp("plan-semi-axes.csv");
    std::fs::write(&sa, semi_axes).unwrap();
    let rows_curv = [(1.015, 0.4215), (1.10, 0.30), (1.20, 1.20), (2.5, 0.9)];
    let independent: Vec<[f64; 2]> = rows_curv
        .iter()
        .map(|&(x, y)| hertz_closed_form(x, y, 100e3))
        .collect();
    // the closed form against the reference values of the default contact (CONTACT: a 5.87814 mm, b
    // 10.53911 mm; p0 770.5 MPa, docs/model.md §2.2)
    let [r, p] = independent[0];
    assert!((r / (5.87814 / 10.53911) - 1.0).abs() < 1e-3, "{r}");
    assert!((p / 770.5e6 - 1.0).abs() < 1e-3, "{p}");
    let pi = std::f64::consts::PI;
    let independent_sa: Vec<[f64; 2]> = [(0.004, 0.0015, 80e3), (0.006, 0.003, 120e3)]
        .iter()
        .map(|&(a, b, f): &(f64, f64, f64)| {
            [a / b, 3.0 * f / (2.0 * pi * a * b) * (100e3 / f).cbrt()]
        })
        .collect();
    for (file, rows, loads) in [
        (&c, &independent, [10e3f64, 250e3]),
        (&sa, &independent_sa, [40e3, 160e3]),
    ] {
        let out = tmp(&format!(
            "plan-{}-axes.toml",
            file.file_stem().unwrap().to_str().unwrap()
        ));
        let loads_arg = format!("{},{}", loads[0], loads[1]);
        let mut args = vec!["--contacts", s(file), "--out", s(&out)];
        if loads != [10e3, 250e3] {
            args.extend(["--loads", &loads_arg]);
        }
        let text = ok(&plan(&args));
        let axes = wheelrail::table::Axes::from_toml_file(&out).unwrap();
        assert!(axes.similarity());
        let [ratio, pressure] = [&axes.0[6], &axes.0[7]];
        for &[r, p_ref] in rows.iter() {
            assert!(ratio.min() < r && r < ratio.max(), "a/b {r}: {ratio:?}");
            for f in loads {
                let p0 = p_ref * (f / 100e3).cbrt();
                // the library's p_ref within 1e-3 of the closed form's: inside by the margin of that
                let (lo, hi) = (pressure.min() * 1.001, pressure.max() / 1.001);
                assert!(lo < p0 && p0 < hi, "p0 {p0} at {f} N: {pressure:?}");
            }
        }
        for w in ratio.points.windows(2) {
            assert!(w[1] / w[0] <= 1.9 * (1.0 + 1e-12), "{w:?}");
        }
        for w in pressure.points.windows(2) {
            let limit = if w[0] >= 0.759375e9 { 1.1045 } else { 1.5 };
            assert!(w[1] / w[0] <= limit * (1.0 + 1e-12), "{w:?}");
        }
        // the other axes: the running-surface design's
        let base = wheelrail::table::Axes::from_toml_file(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("../tools/running-surface-axes.toml"),
        )
        .unwrap();
        assert_eq!(axes.0[..6], base.0[..6]);
        assert!(text.contains(&format!("points {}", axes.len())), "{text}");
        // 2.6 core-hours per million points on the default grid
        let core_hours = 2.6 * axes.len() as f64 / 1e6;
        let printed: f64 = text
            .split("≈ ")
            .nth(1)
            .and_then(|t| t.split(" core-hours").next())
            .unwrap()
            .parse()
            .unwrap();
        assert!(
            (printed / core_hours - 1.0).abs() < 5e-3,
            "{core_hours}: {text}"
        );
        // the printed slurm command accepts the axes (it reads them as `table build` does)
        let command = text
            .lines()
            .find_map(|l| l.trim().strip_prefix("wheelrail "))
            .unwrap()
            .to_string();
        let job = tmp("plan-job");
        let mut words: Vec<String> = command.split_whitespace().map(String::from).collect();
        let at = words.iter().position(|w| w == "--out").unwrap();
        words[at + 1] = s(&job).into();
        let words: Vec<&str> = words.iter().map(String::as_str).collect();
        assert_eq!(words[..2], ["table", "slurm"]);
        ok(&wheelrail(&words, None));
        assert!(job.join("build.sbatch").exists());
    }
    // a base with a normal-force axis (the bundled table's): the pressure nodes span p_ref itself, the
    // loads are the base's, and --loads is refused
    let tools = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tools");
    let base = tools.join("default-contact-axes.toml");
    let out = tmp("plan-force-axes.toml");
    let args = ["--contacts", s(&c), "--base", s(&base), "--out", s(&out)];
    ok(&plan(&args));
    let axes = wheelrail::table::Axes::from_toml_file(&out).unwrap();
    let given = wheelrail::table::Axes::from_toml_file(&base).unwrap();
    assert!(!axes.similarity());
    assert_eq!(axes.0[..6], given.0[..6]);
    for &[r, p_ref] in &independent {
        assert!(axes.0[6].min() < r && r < axes.0[6].max(), "a/b {r}");
        let (lo, hi) = (axes.0[7].min() * 1.001, axes.0[7].max() / 1.001);
        assert!(lo < p_ref && p_ref < hi, "p_ref {p_ref}: {:?}", axes.0[7]);
    }
    let o = plan(&[&args[..], &["--loads", "20e3,200e3"]].concat());
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("normal-force axis"));
    cleanup("plan-");
}

/// Contacts files that cannot be used: a clear error naming the file and the line, exit code 2.
#[test]
fn bad_contacts_files_are_refused_naming_the_line() {
    let missing = tmp("badplan-missing.csv");
    let o = plan(&["--contacts", s(&missing)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains(s(&missing)));
    for (name, text, line, what) in [
        ("header", "x,y\n1,2\n", 1, "must name the columns"),
        ("both", "a,b,A,B\n1,2,3,4\n", 1, "both"),
        (
            "text",
            "# comment\nA,B\n1.0,0.4\n1.0,abc\n",
            4,
            "not a number",
        ),
        ("inf", "A,B\n1.0,inf\n", 2, "finite and > 0"),
        ("nan", "A,B\nNaN,0.4\n", 2, "finite and > 0"),
        ("zero", "A,B\n1.0,0.4\n\n0,0.4\n", 4, "finite and > 0"),
        (
            "negative",
            "a,b,normal_force\n0.005,0.008,-1e5\n",
            2,
            "finite and > 0",
        ),
        ("short", "A,B\n1.0\n", 2, "no value of B"),
        ("force", "a,b\n0.005,0.008\n", 2, "normal force"),
        ("empty", "# only a comment\n", 0, "no header"),
        ("rows", "A,B\n# none\n", 1, "no contacts"),
    ] {
        let f = tmp(&format!("badplan-{name}.csv"));
        std::fs::write(&f, text).unwrap();
        let o = plan(&["--contacts", s(&f), "--out", s(&tmp("badplan-axes.toml"))]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        let place = if line > 0 {
            format!("contacts file {}, line {line}: ", s(&f))
        } else {
            format!("contacts file {}: ", s(&f))
        };
        assert!(err.contains(&place) && err.contains(what), "{name}: {err}");
        assert!(!tmp("badplan-axes.toml").exists(), "{name}");
    }
    // a row of semi-axes with --normal-force is a contact
    let f = tmp("badplan-force.csv");
    std::fs::write(&f, "a,b\n0.005,0.008\n").unwrap();
    ok(&plan(&[
        "--contacts",
        s(&f),
        "--normal-force",
        "90e3",
        "--out",
        s(&tmp("badplan-ok.toml")),
    ]));
    cleanup("badplan-");
}

/// A small plan — the default contact and a circular one, the loads 60–160 kN (one a/b cell, p0 over
/// 0.65–1.40 GPa in 7 cells across the knee), a base of few creepage, speed and wetness nodes by
/// similarity — builds on 6 × 6 cells into a table that `table verify` passes (|ΔF|/F_N p99 ≤ 0.01,
/// max ≤ 0.03, T_max p99 ≤ 10 K), whose arrays hold the f32 bytes the plan printed.
#[test]
fn a_small_plan_builds_a_table_that_meets_the_targets() {
    let base = VERIFY_AXES
        .replace(
            "interpolation = \"log\"\npoints = [90e3, 110e3]",
            "points = [100e3]",
        )
        .replace(
            "[speed]\npoints = [27.0, 33.0]",
            "[speed]\nsimilarity = true\npoints = [27.0, 33.0]",
        );
    let (params, base) = files("smallplan", "[grid]\nnx = 6\nny = 6\n", &base);
    let contacts = tmp("smallplan.csv");
    std::fs::write(&contacts, "A,B\n1.015,0.4215\n1.3,1.3\n").unwrap();
    let axes = tmp("smallplan-axes.toml");
    let text = ok(&plan(&[
        "--contacts",
        s(&contacts),
        "--base",
        s(&base),
        "--loads",
        "60e3,160e3",
        "--params",
        s(&params),
        "--out",
        s(&axes),
    ]));
    let dir = tmp("smallplan-table");
    build(&params, &axes, &dir, &[], "2");
    let bytes: u64 = array_files(&dir).iter().map(|(_, b)| b.len() as u64).sum();
    assert!(text.contains(&format!("f32 {bytes} (")), "{bytes}: {text}");
    let axes = wheelrail::table::Axes::from_toml_file(&axes).unwrap();
    assert_eq!((axes.0[6].points.len(), axes.0[7].points.len()), (2, 8));
    let (r, _, _) = verify_with_csv(&dir, &tmp("smallplan-samples.csv"), 200);
    assert_eq!(r["compared"], 200, "{r}");
    let (p99, max, t99) = (
        r["force"]["p99"].as_f64().unwrap(),
        r["force"]["max"].as_f64().unwrap(),
        r["max_temperature"]["p99"].as_f64().unwrap(),
    );
    assert!(p99 <= 0.01 && max <= 0.03 && t99 <= 10.0, "{r}");
    assert!(r["force"]["mean"].as_f64().unwrap() > 1e-6, "{r}");
    cleanup("smallplan");
}
