//! `wheelrail fit` through the command line: known parameters recovered from synthetic measurements (the
//! model's own curves with noise) within two standard errors, a parameter the data do not determine named,
//! the fitted file reproducing the report's curve through `wheelrail point`, and bad input refused.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use wheelrail::{Model, OperatingPoint, Params};

fn wheelrail(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_wheelrail"))
        .args(args)
        .output()
        .expect("run wheelrail")
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("wheelrail-fit-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Standard normal deviates from a fixed seed (SplitMix64 and Box–Muller): reproducible noise.
fn normals(seed: u64, n: usize) -> Vec<f64> {
    let mut s = seed;
    let mut uniform = || {
        s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = s;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        (z ^ (z >> 31)) as f64 / 2f64.powi(64)
    };
    (0..n)
        .map(|_| {
            let (u1, u2) = (uniform().max(1e-300), uniform());
            (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
        })
        .collect()
}

/// Writes `start` to DIR/start.toml and measurements of the model with `truth` at the creepages `xi` of
/// each of the `curves` plus noise of standard deviation `sigma` on f (from `seed`) to DIR/data.csv.
fn synthetic(
    d: &Path,
    truth: &Params,
    start: &Params,
    curves: &[OperatingPoint],
    xi: &[f64],
    (sigma, seed): (f64, u64),
) -> (PathBuf, PathBuf) {
    let model = Model::new(truth.clone()).unwrap();
    let noise = normals(seed, curves.len() * xi.len());
    let mut csv = String::from("creepage-x,speed,wetness,f\n");
    let mut k = 0;
    for c in curves {
        for &x in xi {
            let pt = OperatingPoint {
                creepage_x: x,
                ..*c
            };
            let f = model.solve(&pt).unwrap().global.traction_coefficient;
            csv += &format!("{x},{},{},{}\n", c.speed, c.wetness, f + sigma * noise[k]);
            k += 1;
        }
    }
    let (data, params) = (d.join("data.csv"), d.join("start.toml"));
    std::fs::write(&data, csv).unwrap();
    std::fs::write(&params, start.to_toml_string()).unwrap();
    (data, params)
}

/// `wheelrail fit` of `data` from the parameter file `params` with `free` keys and `extra` arguments into
/// `out`: the report and stderr.
fn fit(
    data: &Path,
    params: &Path,
    free: &str,
    extra: &[&str],
    out: &Path,
) -> (serde_json::Value, String) {
    let (data, params, out_dir) = (
        data.to_str().unwrap(),
        params.to_str().unwrap(),
        out.to_str().unwrap(),
    );
    let args = [
        &[
            "fit", "--data", data, "--params", params, "--free", free, "--out", out_dir,
        ],
        extra,
    ]
    .concat();
    let o = wheelrail(&args);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(o.status.success(), "{args:?}: {err}");
    let report = std::fs::read_to_string(out.join("report.json")).unwrap();
    assert!(out.join("fit.png").metadata().unwrap().len() > 1000);
    (serde_json::from_str(&report).unwrap(), err)
}

/// A coarse, fast parameter set: FASTSIM on 12 × 12 cells, with heat (the falling branch).
fn coarse() -> Params {
    let mut p = Params::default();
    p.grid.nx = 12;
    p.grid.ny = 12;
    p
}

/// The true roughness and yield-stress span of [`falling_curves`].
const TRUTH: [(&str, f64); 2] = [("roughness.k_r", 0.3), ("material.yield_span", 800.0)];

/// Dry measurements at two speeds, rising to a peak near 0.3 % and falling with the heat at high creepage
/// (the yield stress falls over yield_span with the temperature), by the model with [`TRUTH`] and noise
/// of standard deviation `sigma` from `seed`, into DIR; the start parameters away from the truth.
fn falling_curves(d: &Path, sigma: f64, seed: u64) -> (PathBuf, PathBuf) {
    let mut truth = coarse();
    truth.roughness.k_r = TRUTH[0].1;
    truth.material.yield_span = TRUTH[1].1;
    let mut start = coarse();
    start.roughness.k_r = 0.6;
    start.material.yield_span = 1200.0;
    let curves = [10.0, 40.0].map(|v| OperatingPoint {
        speed: v,
        ..OperatingPoint::default()
    });
    let xi = [
        0.0005, 0.001, 0.002, 0.003, 0.005, 0.01, 0.02, 0.04, 0.07, 0.1,
    ];
    synthetic(d, &truth, &start, &curves, &xi, (sigma, seed))
}

#[test]
fn recovers_the_roughness_and_yield_span_of_curves_with_a_falling_branch() {
    let d = dir("recover");
    let sigma = 0.003;
    let (data, params) = falling_curves(&d, sigma, 7);
    let out = d.join("out");
    let (r, err) = fit(
        &data,
        &params,
        "roughness.k_r,material.yield_span",
        &[],
        &out,
    );
    assert_eq!(r["converged"], true, "{r:#}");
    assert!(!err.contains("cannot determine"), "{err}");
    for (key, value) in TRUTH {
        let p = &r["parameters"][key];
        let (fitted, se) = (
            p["value"].as_f64().unwrap(),
            p["std_error"].as_f64().unwrap(),
        );
        assert!(
            (fitted - value).abs() < 2.0 * se,
            "{key}: {fitted} ± {se}, truth {value}"
        );
        assert!(se > 0.0 && se < 0.1 * value, "{key}: {se}");
        assert_eq!(p["determined"], true);
    }
    // the residuals are the noise: rms close to sigma
    let rms = r["rms"].as_f64().unwrap();
    assert!(rms > 0.6 * sigma && rms < 1.4 * sigma, "{rms}");
    // the data have a falling branch, and the fitted curve follows it
    let points = r["points"].as_array().unwrap();
    let model = |k: usize| points[k]["traction_coefficient"]["model"].as_f64().unwrap();
    assert!(model(9) < model(4) - 0.02, "{} vs {}", model(9), model(4));

    // fitted.toml reproduces the report's curve through `point`
    let fitted = out.join("fitted.toml");
    for k in [0, 4, 19] {
        let p = &points[k];
        let o = wheelrail(&[
            "point",
            "--json",
            "--params",
            fitted.to_str().unwrap(),
            "--creepage-x",
            &p["creepage_x"].to_string(),
            "--speed",
            &p["speed"].to_string(),
        ]);
        assert!(o.status.success());
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(
            v["traction_coefficient"], p["traction_coefficient"]["model"],
            "line {}",
            p["line"]
        );
    }
}

#[test]
fn recovers_the_wet_failure_stress_factor_of_flooded_curves() {
    // flooded (w = 1) curves saturate at the boundary-lubricated traction set by k_wet (docs/model.md §8)
    let d = dir("wet");
    let mut truth = coarse();
    truth.fluid.k_wet = 0.3;
    let curves = [5.0, 30.0].map(|v| OperatingPoint {
        speed: v,
        wetness: 1.0,
        ..OperatingPoint::default()
    });
    let xi = [0.0005, 0.001, 0.002, 0.004, 0.008, 0.02, 0.05];
    let (data, params) = synthetic(&d, &truth, &coarse(), &curves, &xi, (0.002, 11));
    let (r, _) = fit(&data, &params, "fluid.k_wet", &[], &d.join("out"));
    let p = &r["parameters"]["fluid.k_wet"];
    let (fitted, se) = (
        p["value"].as_f64().unwrap(),
        p["std_error"].as_f64().unwrap(),
    );
    assert_eq!(p["initial"], 0.4);
    assert!(
        (fitted - 0.3).abs() < 2.0 * se && se < 0.01,
        "{fitted} ± {se}"
    );
}

/// A measured curve rising more slowly than Kalker's theory at small creepage: the interfacial layer's
/// thickness (docs/model.md §6.7; the layer-free model cannot follow such a slope) is recovered, the fit
/// starting without a layer (at the bound 0 of its range).
#[test]
fn recovers_the_interfacial_layer_of_a_slowly_rising_curve() {
    let d = dir("layer");
    let mut truth = coarse();
    truth.layer.thickness = 3e-4;
    let curves = [OperatingPoint {
        speed: 20.0,
        ..OperatingPoint::default()
    }];
    let xi = [0.0002, 0.0005, 0.001, 0.0015, 0.002, 0.003, 0.005, 0.01];
    let (data, params) = synthetic(&d, &truth, &coarse(), &curves, &xi, (0.002, 5));
    let (r, _) = fit(&data, &params, "layer.thickness", &[], &d.join("out"));
    assert_eq!(r["converged"], true, "{r:#}");
    let p = &r["parameters"]["layer.thickness"];
    let (fitted, se) = (
        p["value"].as_f64().unwrap(),
        p["std_error"].as_f64().unwrap(),
    );
    assert_eq!(p["initial"], 0.0);
    assert!(
        (fitted - 3e-4).abs() < 2.0 * se && se < 0.1 * 3e-4,
        "{fitted} ± {se}"
    );
}

/// The standard errors are honest: over fits to the same curves with independent noise, the fitted values
/// scatter by the standard errors the report gives, and about 95 % lie within two of them.
#[test]
fn standard_errors_match_the_scatter_over_repeated_noise() {
    const FITS: u64 = 12;
    let mut fitted: Vec<[(f64, f64); 2]> = Vec::new();
    for seed in 1..=FITS {
        let d = dir(&format!("scatter-{seed}"));
        let (data, params) = falling_curves(&d, 0.003, 100 + seed);
        let (r, _) = fit(
            &data,
            &params,
            "roughness.k_r,material.yield_span",
            &[],
            &d.join("out"),
        );
        assert_eq!(r["converged"], true);
        fitted.push(TRUTH.map(|(key, _)| {
            let p = &r["parameters"][key];
            (
                p["value"].as_f64().unwrap(),
                p["std_error"].as_f64().unwrap(),
            )
        }));
    }
    for (k, (key, truth)) in TRUTH.iter().enumerate() {
        let n = FITS as f64;
        let mean = fitted.iter().map(|f| f[k].0).sum::<f64>() / n;
        let scatter =
            (fitted.iter().map(|f| (f[k].0 - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let reported = fitted.iter().map(|f| f[k].1).sum::<f64>() / n;
        // the sample standard deviation of 12 fits is within about ±40 % of the true one (two of its
        // standard errors, 1/sqrt(2·11))
        let ratio = scatter / reported;
        assert!(
            (0.6..1.6).contains(&ratio),
            "{key}: scatter {scatter}, reported {reported}"
        );
        let within = fitted
            .iter()
            .filter(|f| (f[k].0 - truth).abs() < 2.0 * f[k].1)
            .count();
        assert!(
            within >= 10,
            "{key}: {within} of {FITS} within two standard errors"
        );
    }
}

#[test]
fn names_a_parameter_the_data_cannot_determine() {
    // dry data do not depend on the wet failure-stress factor
    let d = dir("undetermined");
    let truth = coarse();
    let curves = [OperatingPoint::default()];
    let xi = [0.001, 0.003, 0.01, 0.03];
    let (data, params) = synthetic(&d, &truth, &truth, &curves, &xi, (0.002, 7));
    let out = d.join("out");
    let (r, err) = fit(
        &data,
        &params,
        "roughness.k_r,fluid.k_wet",
        &["--bounds", "roughness.k_r=0.2:0.8"],
        &out,
    );
    assert_eq!(
        r["undetermined"],
        serde_json::json!(["fluid.k_wet"]),
        "{r:#}"
    );
    assert!(
        err.contains("warning: the data cannot determine fluid.k_wet"),
        "{err}"
    );
    assert!(r["parameters"]["fluid.k_wet"]["std_error"].is_null());
    assert_eq!(r["parameters"]["roughness.k_r"]["determined"], true);
    assert_eq!(r["parameters"]["roughness.k_r"]["lower"], 0.2);
    // the FMU takes the fitted values by variable
    assert_eq!(
        r["fmu_parameters"]["roughness"],
        r["parameters"]["roughness.k_r"]["value"]
    );

    // the roughness and the dry failure-stress factor both scale the adhesion limit (P3, P6): on these
    // curves they are not separable
    let (r, err) = fit(&data, &params, "roughness.k_r,friction.k_dry", &[], &out);
    for (key, other) in [
        ("roughness.k_r", "friction.k_dry"),
        ("friction.k_dry", "roughness.k_r"),
    ] {
        let why = r["parameters"][key]["undetermined_because"]
            .as_str()
            .unwrap();
        assert!(why.contains(&format!("correlated with {other}")), "{why}");
        assert!(
            err.contains(&format!("cannot determine {key}: correlated")),
            "{err}"
        );
    }
    let rho = r["correlation"]["matrix"][0][1].as_f64().unwrap();
    assert!(rho.abs() >= 0.99, "{rho}");
}

#[test]
fn bad_input_is_one_line_naming_the_line_or_key_exit_2() {
    let d = dir("bad");
    let write = |name: &str, text: &str| {
        let p = d.join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let good = write(
        "good.csv",
        "creepage-x,f\n0.001,0.2\n0.002,0.3\n0.003,0.33\n",
    );
    let out = d.join("out");
    let out = out.to_str().unwrap();
    for (data, free, bounds, says) in [
        (write("empty.csv", ""), "roughness.k_r", None, "empty"),
        (
            write("unknown.csv", "creepage-x,slip,f\n0.1,1,0.2\n"),
            "roughness.k_r",
            None,
            "line 1: unknown column \"slip\"",
        ),
        (
            write("missing.csv", "creepage-x,speed\n0.1,1\n"),
            "roughness.k_r",
            None,
            "line 1: no measured column",
        ),
        (
            write("nan.csv", "creepage-x,f\n0.001,0.2\n0.002,nan\n"),
            "roughness.k_r",
            None,
            "line 3: f nan is not a finite number",
        ),
        (
            good.clone(),
            "friction.law",
            None,
            "--free friction.law: not a scalar parameter key",
        ),
        (
            good.clone(),
            "grid.nx",
            None,
            "--free grid.nx: a whole number",
        ),
        (
            good.clone(),
            "roughness.k_r",
            Some("roughness.k_r=0.5:2"),
            "--bounds roughness.k_r=0.5:2: the bounds of roughness.k_r must satisfy lo < hi inside its range",
        ),
        (
            write("short.csv", "creepage-x,f\n0.001,0.2\n"),
            "roughness.k_r,friction.k_dry",
            None,
            "1 measured values for 2 free parameters",
        ),
    ] {
        let mut args = vec!["fit", "--data", &data, "--free", free, "--out", out];
        if let Some(b) = bounds {
            args.extend(["--bounds", b]);
        }
        let o = wheelrail(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
}
