//! The `wheelrail` command line: the JSON contract, curves, fields, and clean errors for bad input.

use std::process::{Command, Output};

fn wheelrail(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wheelrail"))
        .args(args)
        .output()
        .expect("run wheelrail")
}

fn tmp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("wheelrail-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

#[test]
fn point_json_has_the_contract_keys() {
    let o = wheelrail(&["point", "--json", "--creepage-x", "0.01", "--grid", "16,16"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for k in [
        "force_x",
        "force_y",
        "spin_moment",
        "traction_coefficient",
        "normal_force",
        "semi_axis_a",
        "semi_axis_b",
        "max_temperature",
        "mean_temperature",
        "iterations",
        "converged",
        "residual",
    ] {
        assert!(v.get(k).is_some(), "missing key {k} in {v}");
    }
    assert_eq!(v["normal_force"].as_f64(), Some(100e3));
    assert_eq!(v["converged"].as_bool(), Some(true));
    assert!(v["force_x"].as_f64().unwrap() < 0.0);
    // docs/model.md §2 Hertz reference: a = 5.879 mm, b = 10.540 mm
    assert!((v["semi_axis_a"].as_f64().unwrap() - 5.879e-3).abs() < 6e-6);
    assert!((v["semi_axis_b"].as_f64().unwrap() - 10.540e-3).abs() < 1.1e-5);
}

#[test]
fn invalid_input_is_one_line_exit_2() {
    for args in [
        vec!["point", "--normal-force", "-5"],
        vec!["point", "--wetness", "1.5"],
        vec!["point", "--creepage-x", "NaN"],
        vec!["point", "--roughness", "2"],
        vec!["point", "--grid", "3,30"],
        vec!["point", "--curvatures", "1.0"],
    ] {
        let o = wheelrail(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains("allowed"), "{args:?}: {err}");
        assert!(!err.contains("panicked"));
    }
    let o = wheelrail(&["point", "--no-such-flag"]);
    assert_eq!(o.status.code(), Some(2));
    let bad = tmp("bad.toml");
    std::fs::write(&bad, "[grid]\nnx = \"many\"\n").unwrap();
    let o = wheelrail(&["point", "--params", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("bad.toml"));
}

/// A reader that stops reading (`wheelrail … | head`) ends the program quietly, without a panic.
#[cfg(unix)]
#[test]
fn a_closed_output_pipe_ends_the_program_quietly() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    // the program reads its parameters (none: the defaults) from stdin before it writes, so the reading
    // end of its output is closed before it writes, however slow the machine
    let mut child = Command::new(env!("CARGO_BIN_EXE_wheelrail"))
        .args(["point", "--json", "--grid", "6,6", "--params", "/dev/stdin"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run wheelrail");
    drop(child.stdout.take());
    drop(child.stdin.take());
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.is_empty(), "{err}");
    assert_eq!(o.status.signal(), Some(13), "{:?}", o.status);
}

#[test]
fn committed_parameter_docs_are_current() {
    let o = wheelrail(&["parameters", "--markdown"]);
    assert!(o.status.success());
    let committed = include_str!("../../docs/parameters.md");
    assert!(
        committed == String::from_utf8(o.stdout).unwrap(),
        "docs/parameters.md differs from the parameter specification: run `make parameter-docs`"
    );
}

#[test]
fn parameters_json_lists_every_row_with_its_flag_and_fmu_variable() {
    let o = wheelrail(&["parameters", "--json"]);
    assert!(o.status.success());
    let rows: Vec<serde_json::Value> = serde_json::from_slice(&o.stdout).unwrap();
    let docs = include_str!("../../docs/parameters.md");
    for r in &rows {
        let toml = r["toml"].as_str().unwrap();
        assert!(
            docs.contains(&format!("| `{toml}` |")),
            "{toml} missing in the docs"
        );
        if let Some(flag) = r["cli"].as_str() {
            assert!(docs.contains(&format!("`{flag}`")), "{flag}");
        }
    }
    let by_toml = |k: &str| rows.iter().find(|r| r["toml"] == k).unwrap();
    let k_wet = by_toml("fluid.k_wet");
    assert_eq!(k_wet["cli"], "--k-wet");
    assert_eq!(k_wet["fmu"], "k_wet");
    assert_eq!(k_wet["value_reference"], 18);
    assert_eq!(k_wet["default"], 0.4);
    let flow = by_toml("fluid.flow_resistance");
    assert_eq!(
        (flow["min"].as_f64(), flow["min_inclusive"].as_bool()),
        (Some(0.0), Some(false))
    );
    assert!(flow["max"].is_null());
    assert_eq!(by_toml("normal_force")["name"], "normal-force");
    assert_eq!(rows.iter().filter(|r| r["kind"] == "input").count(), 6);
}

#[test]
fn params_file_is_read_and_flags_override_it() {
    let f = tmp("p.toml");
    std::fs::write(
        &f,
        "[friction]\nlaw = \"constant\"\nmu = 0.2\n[grid]\nnx = 16\nny = 16\n",
    )
    .unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec![
            "point",
            "--json",
            "--creepage-x",
            "0.3",
            "--params",
            f.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = wheelrail(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let v = run(&[]);
    assert_eq!(v["friction_law"], "constant");
    let f1 = v["traction_coefficient"].as_f64().unwrap();
    assert!((f1 - 0.2).abs() < 0.005, "{f1}");
    let v = run(&["--mu", "0.1"]);
    assert!((v["traction_coefficient"].as_f64().unwrap() - 0.1).abs() < 0.003);
}

/// The JSON objects of `--format jsonl` output, one per line.
fn jsonl(stdout: &[u8]) -> Vec<serde_json::Value> {
    String::from_utf8_lossy(stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn curve_writes_csv_jsonl_and_a_plot() {
    let png = tmp("curve.png");
    let o = wheelrail(&[
        "curve",
        "--max",
        "0.02",
        "--points",
        "5",
        "--grid",
        "12,12",
        "--plot",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 6);
    assert!(lines[0].starts_with("creepage_x,"));
    assert!(lines[0].contains("traction_coefficient"));
    let png_bytes = std::fs::read(&png).unwrap();
    assert_eq!(&png_bytes[1..4], b"PNG");
    assert!(png_bytes.len() > 5000);
    let o = wheelrail(&[
        "curve", "--over", "spin", "--max", "1", "--points", "3", "--grid", "12,12", "--format",
        "jsonl",
    ]);
    assert!(o.status.success());
    let rows = jsonl(&o.stdout);
    assert_eq!(rows.len(), 3);
    assert_eq!(rows[2]["spin"].as_f64(), Some(1.0));
    // spin alone gives a lateral force
    assert!(rows[2]["force_y"].as_f64().unwrap().abs() > 100.0);
}

/// `curve --over semi-axis-ratio` sweeps the ellipse's shape at the contact area of the given geometry: in
/// the linear range F_x/F_N follows Kalker's C11(a/b) (an independent table, docs/model.md §6).
#[test]
fn curve_over_the_semi_axis_ratio_follows_kalkers_coefficient() {
    let o = wheelrail(&[
        "curve",
        "--over",
        "semi-axis-ratio",
        "--min",
        "0.3",
        "--max",
        "3",
        "--points",
        "3",
        "--creepage-x",
        "1e-6",
        "--grid",
        "16,16",
        "--format",
        "jsonl",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = jsonl(&o.stdout);
    assert_eq!(rows.len(), 3);
    let get = |r: &serde_json::Value, k: &str| r[k].as_f64().unwrap();
    let area = get(&rows[0], "semi_axis_a") * get(&rows[0], "semi_axis_b");
    let mut slope = Vec::new();
    for (r, want) in rows.iter().zip([0.3, 1.65, 3.0]) {
        let (a, b) = (get(r, "semi_axis_a"), get(r, "semi_axis_b"));
        assert!((a / b / want - 1.0).abs() < 1e-12 && (a * b / area - 1.0).abs() < 1e-12);
        assert!((get(r, "semi_axis_ratio") - want).abs() < 1e-12);
        let c11 = wheelrail::tangential::kalker_coefficients(a, b, 0.28)
            .unwrap()
            .c11;
        slope.push(-get(r, "force_x") / c11);
    }
    // F_x = −G·a·b·C11·ξ: the same G·a·b·ξ for all three shapes
    for s in &slope[1..] {
        assert!((s / slope[0] - 1.0).abs() < 0.03, "{slope:?}");
    }
    // and a ratio needs --min > 0
    let o = wheelrail(&[
        "curve",
        "--over",
        "semi-axis-ratio",
        "--min",
        "0",
        "--max",
        "2",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("semi_axis_ratio"));
}

#[test]
fn fields_write_csv_and_heat_maps() {
    let dir = tmp("maps");
    let o = wheelrail(&[
        "fields",
        "--creepage-x",
        "0.005",
        "--grid",
        "12,12",
        "--plot",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    let header = text.lines().next().unwrap();
    for k in [
        "x",
        "y",
        "nominal_pressure",
        "area_fraction",
        "friction_coefficient",
        "adhesion_limit",
        "traction",
        "slip_velocity",
        "heat_flux",
        "temperature",
        "slipping",
    ] {
        assert!(header.split(',').any(|h| h == k), "missing column {k}");
    }
    assert!(text.lines().count() > 50);
    assert!(dir.join("temperature.png").exists());
    // columns are only ever appended: the void height is the last
    assert_eq!(header.split(',').next_back(), Some("void_height"));
}

#[test]
fn point_json_says_what_limited_an_unconverged_solve_and_null_for_what_a_law_does_not_model() {
    let json = |args: &[&str]| -> serde_json::Value {
        let o = wheelrail(&[&["point", "--json", "--grid", "12,12"], args].concat());
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let v = json(&["--creepage-x", "0.01"]);
    assert_eq!(v["termination"], "converged");
    assert!(v["limited_by"].is_null());
    let one = tmp("one-iteration.toml");
    std::fs::write(&one, "[solver]\nmax_iterations = 1\n").unwrap();
    let v = json(&["--creepage-x", "0.01", "--params", one.to_str().unwrap()]);
    assert_eq!(v["converged"], false);
    assert_eq!(v["termination"], "max_iterations_reached");
    assert_eq!(v["limited_by"], "outer");
    let absent = [
        "fluid_load_fraction",
        "mixed_lubrication_area_fraction",
        "boundary_lubrication_area_fraction",
        "fluid_mass_balance_error",
        "fluid_rejected_fraction",
        "max_dry_area_fraction",
    ];
    let v = json(&["--creepage-x", "0.01", "--friction-law", "polach"]);
    for k in absent
        .iter()
        .chain(&["spin_moment", "max_temperature", "mean_temperature"])
    {
        assert!(v[k].is_null(), "{k} = {} for polach", v[k]);
    }
    assert!(v["force_x"].as_f64().unwrap() < 0.0);
    assert_eq!(v["termination"], "closed_form");
    let v = json(&[
        "--creepage-x",
        "0.01",
        "--wetness",
        "1",
        "--friction-law",
        "constant",
    ]);
    for k in absent {
        assert!(v[k].is_null(), "{k} = {} for the constant law", v[k]);
    }
    assert!(v["max_temperature"].as_f64().unwrap() > 293.15);
    let v = json(&["--creepage-x", "0.01", "--wetness", "1"]);
    for k in absent {
        assert!(v[k].is_number(), "{k} = {} for the tomberger law", v[k]);
    }
}

/// A small table for the default parameters on a 6 × 6 grid (tests/fixtures/small-axes.toml: ξ, η ≤ 1 %,
/// |φ| ≤ 0.5 1/m, F_N 80–120 kN, V 20–40 m/s, w ≤ 0.2) and its parameter file, built once.
fn small_table() -> &'static (std::path::PathBuf, std::path::PathBuf) {
    static TABLE: std::sync::OnceLock<(std::path::PathBuf, std::path::PathBuf)> =
        std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let text = "[grid]\nnx = 6\nny = 6\n";
        let params = wheelrail::Params::from_toml_str(text).unwrap();
        let file = tmp("small-table.toml");
        std::fs::write(&file, text).unwrap();
        let dir = tmp("small-table");
        let mut files = wheelrail::table::build(
            &params,
            &wheelrail::table::Axes::from_toml_file(
                &std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("../tests/fixtures/small-axes.toml"),
            )
            .unwrap(),
            None,
            &|| (),
        )
        .unwrap();
        files.write(&dir).unwrap();
        (dir, file)
    })
}

/// `point --json` with the small table's parameters and `extra` flags, by default at ξ = 0.3 %,
/// η = 0.1 %, φ = 0.2 1/m, w = 0.1: (JSON, stderr).
fn point_with(extra: &[&str]) -> (serde_json::Value, String) {
    let (_, params) = small_table();
    let mut args = vec!["point", "--json", "--params", params.to_str().unwrap()];
    for (flag, value) in [
        ("--creepage-x", "0.003"),
        ("--creepage-y", "0.001"),
        ("--spin", "0.2"),
        ("--wetness", "0.1"),
    ] {
        if !extra.contains(&flag) {
            args.extend([flag, value]);
        }
    }
    args.extend_from_slice(extra);
    let o = wheelrail(&args);
    let err = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(o.status.success(), "{extra:?}: {err}");
    (serde_json::from_slice(&o.stdout).unwrap(), err)
}

#[test]
fn point_mode_auto_uses_the_table_where_usable_and_else_the_exact_solver() {
    let dir = small_table().0.to_str().unwrap();
    let (table, err) = point_with(&["--table", dir]);
    assert_eq!(table["evaluation"], "table");
    assert!(err.is_empty(), "{err}");
    let (auto, err) = point_with(&["--mode", "auto", "--table", dir]);
    assert_eq!(auto, table);
    assert!(err.is_empty(), "{err}");
    // outside the table's speed range: the exact solver, with a warning
    let (auto, err) = point_with(&["--mode", "auto", "--table", dir, "--speed", "60"]);
    let (exact, _) = point_with(&["--mode", "exact", "--speed", "60"]);
    assert_eq!(auto["evaluation"], "exact");
    assert_eq!(auto, exact);
    assert!(
        err.contains("outside the table's ranges") && err.contains("exact solver"),
        "{err}"
    );
    // parameters other than the table's: the exact solver, with a warning naming the reason
    let (auto, err) = point_with(&["--mode", "auto", "--table", dir, "--roughness", "0.6"]);
    assert_eq!(auto["evaluation"], "exact");
    assert!(err.contains("other parameters"), "{err}");
    assert_ne!(auto["force_x"], table["force_x"]);
}

/// `point --mode auto` with the default grid solves a contact no table serves on the grid per contact (a
/// long one: 24 × 6 dry, 24 × 12 wet); `--grid` or `--grid-accuracy` is its grid instead. `grid_cells` says
/// which.
#[test]
fn point_mode_auto_falls_back_on_the_grid_per_contact_unless_a_grid_is_given() {
    let table = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../fmu/resources/table");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "point",
            "--json",
            "--curvatures",
            "0.92,3.5",
            "--creepage-x",
            "0.004",
        ];
        args.extend_from_slice(extra);
        let o = wheelrail(&args);
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        assert!(o.status.success(), "{extra:?}: {err}");
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["evaluation"], "exact");
        (v, err)
    };
    let auto = ["--mode", "auto", "--table", table.to_str().unwrap()];
    let (dry, err) = run(&auto);
    assert_eq!(dry["grid_cells"], serde_json::json!([24, 6]));
    assert!(err.contains("another contact geometry"), "{err}");
    let (wet, _) = run(&[&auto[..], &["--wetness", "1"]].concat());
    assert_eq!(wet["grid_cells"], serde_json::json!([24, 12]));
    let (set, _) = run(&[&auto[..], &["--grid", "30,30"]].concat());
    let (exact, _) = run(&[]);
    assert_eq!(set["grid_cells"], serde_json::json!([30, 30]));
    assert_eq!(set["force_x"], exact["force_x"]);
    assert_ne!(dry["force_x"], exact["force_x"]);
    let (accuracy, _) = run(&[&auto[..], &["--grid-accuracy", "0.01"]].concat());
    assert_eq!(accuracy["grid_cells"], serde_json::json!([10, 10]));
}

#[test]
fn point_mode_exact_is_the_default_without_a_table_and_table_modes_need_one() {
    let (default, _) = point_with(&[]);
    assert_eq!(default["evaluation"], "exact");
    assert!(default.get("iterations").is_some() && default.get("in_range").is_none());
    let dir = small_table().0.to_str().unwrap();
    assert_eq!(point_with(&["--mode", "exact"]).0, default);
    assert_eq!(point_with(&["--mode", "exact", "--table", dir]).0, default);
    let (table, _) = point_with(&["--mode", "table", "--table", dir]);
    assert_eq!(table["evaluation"], "table");
    assert_eq!(table["in_range"], true);
    for mode in ["auto", "table"] {
        let o = wheelrail(&["point", "--mode", mode]);
        assert_eq!(o.status.code(), Some(2), "{mode}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains("needs a lookup table") && err.contains("--table DIR"),
            "{err}"
        );
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
}

#[test]
fn point_rolls_backwards_in_the_turned_frame_and_lifts_the_wheel() {
    let dir = small_table().0.to_str().unwrap();
    for mode in ["exact", "auto"] {
        let (back, _) = point_with(&["--mode", mode, "--table", dir, "--speed", "-30"]);
        let (turned, _) = point_with(&[
            "--mode",
            mode,
            "--table",
            dir,
            "--speed",
            "30",
            "--creepage-x",
            "-0.003",
            "--creepage-y",
            "-0.001",
        ]);
        assert_eq!(back["evaluation"], turned["evaluation"]);
        let f = |v: &serde_json::Value, k: &str| v[k].as_f64().unwrap();
        assert_eq!(f(&back, "force_x"), -f(&turned, "force_x"), "{mode}");
        assert_eq!(f(&back, "force_y"), -f(&turned, "force_y"), "{mode}");
        assert_eq!(f(&back, "spin_moment"), f(&turned, "spin_moment"), "{mode}");
    }
    let (lifted, err) = point_with(&["--normal-force", "0"]);
    assert!(err.is_empty(), "{err}");
    assert_eq!(lifted["evaluation"], "lifted");
    for k in ["force_x", "force_y", "spin_moment", "traction_coefficient"] {
        assert_eq!(lifted[k].as_f64(), Some(0.0), "{k}");
    }
    assert_eq!(lifted["max_temperature"].as_f64(), Some(293.15));
    assert_eq!(lifted["converged"], true);
}

/// `--tangential exact` selects Kalker's exact steady rolling (its sweeps reported) with Hertz's pressure
/// unless `--pressure` says otherwise; the JSON records both. The default is FASTSIM with the parabola.
#[test]
fn tangential_flag_selects_the_exact_solver_and_the_json_records_it() {
    let run = |extra: &[&str]| {
        let mut args = vec![
            "point",
            "--json",
            "--creepage-x",
            "0.002",
            "--grid",
            "12,12",
        ];
        args.extend_from_slice(extra);
        let o = wheelrail(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    let fastsim = run(&[]);
    assert_eq!(fastsim["tangential"], "fastsim");
    assert_eq!(fastsim["pressure"], "parabolic");
    assert_eq!(fastsim["tangential_sweeps"], 0);
    let exact = run(&["--tangential", "exact"]);
    assert_eq!(exact["tangential"], "exact");
    assert_eq!(exact["pressure"], "hertz");
    assert!(exact["tangential_sweeps"].as_u64().unwrap() > 0);
    assert!(exact["tangential_residual"].as_f64().unwrap() <= 1e-7);
    assert_eq!(exact["converged"], true);
    let parabolic = run(&["--tangential", "exact", "--pressure", "parabolic"]);
    assert_eq!(parabolic["pressure"], "parabolic");
    let f = |v: &serde_json::Value| v["force_x"].as_f64().unwrap();
    assert!(f(&exact) < 0.0 && f(&exact) != f(&fastsim) && f(&exact) != f(&parabolic));
    let o = wheelrail(&["point", "--tangential", "kalker"]);
    assert!(!o.status.success());
}
