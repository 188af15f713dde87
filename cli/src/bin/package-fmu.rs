//! Packs `WheelRailFriction.fmu`, or writes only `modelDescription.xml`.
//!
//! ```text
//! package-fmu --model-description PATH
//! package-fmu --library target/release/libWheelRailFriction.so --out target/fmu/WheelRailFriction.fmu
//! ```
//!
//! The archive holds `modelDescription.xml`, `binaries/linux64/WheelRailFriction.so` (the cdylib, renamed
//! to the modelIdentifier), `resources/` (the lookup table directory `fmu/resources/table` when it exists),
//! and `documentation/` (`index.html` with variables, conventions and a traction–creepage plot from real
//! solves; `_main.html`, the FMI 2.0 entry point, links to it).

use WheelRailFriction::contact::WheelRailModel;
use WheelRailFriction::contact::variables::*;
use WheelRailFriction::fmi2::logging::Logger;
use WheelRailFriction::fmi2::model::Model;
use WheelRailFriction::fmi2::variables::{Causality, Kind, Value, Values, Variable};
use anyhow::{Context, Result, bail};
use std::io::Write;
use std::path::{Path, PathBuf};
use wheelrail_cli::plot::{Chart, Series, line_chart};
use zip::write::SimpleFileOptions;

struct Args {
    model_description: Option<PathBuf>,
    library: PathBuf,
    out: PathBuf,
}

fn parse_args() -> Result<Args> {
    let mut a = Args {
        model_description: None,
        library: PathBuf::from("target/release/libWheelRailFriction.so"),
        out: PathBuf::from("target/fmu/WheelRailFriction.fmu"),
    };
    let mut it = std::env::args().skip(1);
    while let Some(flag) = it.next() {
        let mut value = || it.next().with_context(|| format!("{flag} needs a value"));
        match flag.as_str() {
            "--model-description" => a.model_description = Some(value()?.into()),
            "--library" => a.library = value()?.into(),
            "--out" => a.out = value()?.into(),
            _ => bail!("unknown argument {flag} (see the source's header for usage)"),
        }
    }
    Ok(a)
}

fn main() -> Result<()> {
    let a = parse_args()?;
    let xml = WheelRailFriction::model_description();
    if let Some(path) = a.model_description {
        std::fs::write(&path, xml).with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
        return Ok(());
    }
    let library = std::fs::read(&a.library).with_context(|| {
        format!(
            "reading the shared library {} (build it with `make fmu`)",
            a.library.display()
        )
    })?;
    let doc_dir = a.out.with_extension("doc");
    std::fs::create_dir_all(&doc_dir)?;
    let plot = doc_dir.join("traction_creepage.png");
    draw_traction_curves(&plot)?;
    if let Some(dir) = a.out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let file =
        std::fs::File::create(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let deflated =
        SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let mut add = |name: &str, bytes: &[u8], mode: u32| -> Result<()> {
        zip.start_file(name, deflated.unix_permissions(mode))?;
        zip.write_all(bytes)?;
        Ok(())
    };
    add("modelDescription.xml", xml.as_bytes(), 0o644)?;
    add("binaries/linux64/WheelRailFriction.so", &library, 0o755)?;
    add(
        "documentation/index.html",
        documentation().as_bytes(),
        0o644,
    )?;
    add("documentation/_main.html", MAIN_HTML.as_bytes(), 0o644)?;
    add(
        "documentation/traction_creepage.png",
        &std::fs::read(&plot)?,
        0o644,
    )?;
    let table = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fmu/resources/table");
    if table.is_dir() {
        for entry in std::fs::read_dir(&table)? {
            let path = entry?.path();
            if path.is_file() {
                let name = path
                    .file_name()
                    .and_then(|n| n.to_str())
                    .context("table file name is not UTF-8")?;
                add(
                    &format!("resources/table/{name}"),
                    &std::fs::read(&path)?,
                    0o644,
                )?;
            }
        }
    } else {
        // an empty resources/ directory, so that importers always pass a resource location
        zip.add_directory("resources/", SimpleFileOptions::default())?;
    }
    zip.finish()?;
    println!("wrote {}", a.out.display());
    Ok(())
}

const MAIN_HTML: &str = "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><meta http-equiv=\"refresh\" \
                         content=\"0; url=index.html\"><title>WheelRailFriction</title></head>\n<body><a \
                         href=\"index.html\">WheelRailFriction documentation</a></body></html>\n";

/// Traction coefficient over longitudinal creepage, dry and wet, at the default parameters, computed by the
/// FMU's own model (the same code path as `fmi2DoStep`).
fn draw_traction_curves(path: &Path) -> Result<()> {
    let mut model = WheelRailModel::new(None);
    let log = Logger::new(None, false);
    let mut series = Vec::new();
    for (label, wetness) in [("dry (w = 0)", 0.0), ("wet (w = 1)", 1.0)] {
        let mut values = Values::start(&VARIABLES);
        values.set(MODE, Value::Integer(2));
        values.set(WETNESS, Value::Real(wetness));
        let mut points = Vec::new();
        for xi in [
            0.0, 5e-4, 1e-3, 1.5e-3, 2e-3, 3e-3, 5e-3, 7.5e-3, 0.01, 0.015, 0.02, 0.03,
        ] {
            values.set(CREEPAGE_LONGITUDINAL, Value::Real(xi));
            model
                .calculate(&mut values, &log)
                .map_err(|e| anyhow::anyhow!("solving creepage {xi}: {e}"))?;
            points.push((100.0 * xi, values.real(TRACTION_COEFFICIENT)));
        }
        series.push(Series {
            label: label.into(),
            points,
        });
    }
    let chart = Chart {
        title: "Traction-creepage curve (F_N = 100 kN, V = 30 m/s, default parameters)",
        x_label: "longitudinal creepage xi [%]",
        y_label: "traction coefficient f = |F_T|/F_N [-]",
    };
    line_chart(path, &chart, &series)
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

fn row(v: &Variable) -> String {
    let opt = |x: Option<String>| x.unwrap_or_default();
    let (ty, unit, start, min, max) = match v.kind {
        Kind::Real {
            unit,
            start,
            min,
            max,
            ..
        } => (
            "Real",
            unit,
            opt(start.map(|x| format!("{x}"))),
            opt(min.map(|x| format!("{x}"))),
            opt(max.map(|x| format!("{x}"))),
        ),
        Kind::Integer { start, min, max } => (
            "Integer",
            "",
            opt(start.map(|x| x.to_string())),
            opt(min.map(|x| x.to_string())),
            opt(max.map(|x| x.to_string())),
        ),
        Kind::Boolean { start } => (
            "Boolean",
            "",
            opt(start.map(|x| x.to_string())),
            String::new(),
            String::new(),
        ),
        Kind::String { start } => (
            "String",
            "",
            opt(start.map(|s| format!("\"{s}\""))),
            String::new(),
            String::new(),
        ),
    };
    let causality = match v.causality {
        Causality::Parameter => "parameter",
        Causality::Input => "input",
        Causality::Output => "output",
    };
    format!(
        "<tr><td><code>{}</code></td><td>{}</td><td>{causality}</td><td>{ty}</td><td>{}</td><td>{start}</td><td>{min}</td><td>{max}</td><td>{}</td></tr>\n",
        v.name,
        v.vr,
        esc(unit),
        esc(v.description)
    )
}

fn documentation() -> String {
    let rows: String = VARIABLES.iter().map(row).collect();
    format!(
        r#"<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>WheelRailFriction FMU</title>
<style>body{{font-family:sans-serif;max-width:70em;margin:2em auto;line-height:1.45}}
table{{border-collapse:collapse}}td,th{{border:1px solid #bbb;padding:.2em .5em;vertical-align:top}}
code{{background:#f3f3f3}}</style></head><body>
<h1>WheelRailFriction {version}</h1>
<p>Friction in one wheel&ndash;rail contact after Tomberger, Dietmaier, Sextro and Six, <i>Friction in
wheel&ndash;rail contact: a model comprising interfacial fluids, surface roughness and temperature</i>, Wear 271
(2011) 2&ndash;12: Hertz contact, Greenwood&ndash;Williamson microcontact, temperature-dependent failure stress,
FASTSIM with a locally varying adhesion limit, flash temperature and an interfacial fluid, solved as one coupled
fixed point. FMI 2.0 Co-Simulation, one instance per contact; any number of instances per process, on any
threads.</p>

<h2>Conventions</h2>
<ul>
<li><b>Frame:</b> x along the track in the direction of travel for positive <code>rolling_speed</code>, y lateral,
z normal. SI units; temperatures in kelvin.</li>
<li><b>Creepages</b> are the rigid slip velocity of the wheel relative to the rail divided by |V|:
w = |V|&middot;(&xi; &minus; &phi;&middot;y, &eta; + &phi;&middot;x) (Kalker).</li>
<li><b>Forces</b> act on the wheel, Kalker's sign convention: they oppose the slip, F<sub>x</sub> =
&minus;G&middot;c&sup2;&middot;C<sub>11</sub>&middot;&xi; in the linear range. The traction coefficient
f = |F<sub>T</sub>|/F<sub>N</sub> is non-negative.</li>
<li><b>Quasi-static:</b> the outputs are a function of the current inputs and parameters. After
<code>fmi2ExitInitializationMode</code> and after every <code>fmi2DoStep</code> they belong to the inputs set
before the call; <code>fmi2GetReal</code> after changing inputs also returns the outputs of the new inputs.</li>
<li><b>Rolling backwards</b> (<code>rolling_speed</code> &lt; 0): solved in the frame turned by 180&deg; about z
(&xi;' = &minus;&xi;, &eta;' = &minus;&eta;, &phi;' = &phi;, V' = |V|), results turned back
(F<sub>x</sub> = &minus;F'<sub>x</sub>, F<sub>y</sub> = &minus;F'<sub>y</sub>, M<sub>z</sub> = M'<sub>z</sub>).
Without spin the forces are the same for &plusmn;V; the lateral force due to spin and the spin moment due to
creepage (slip zone at the trailing edge) change sign with the rolling direction.</li>
<li><b>Standstill:</b> |V| below <code>minimum_speed</code> (default {vmin} m/s) is raised to it; never NaN.</li>
<li><b>Wheel lifted:</b> <code>normal_force</code> &le; 1 mN gives zero forces and moment, f = 0,
<code>max_temperature</code> = <code>bulk_temperature</code>, no error.</li>
<li><b>Invalid inputs:</b> NaN or infinite values are rejected by <code>fmi2SetReal</code> with
<code>fmi2Error</code> and a message naming the variable; <code>wetness</code> outside [0, 1] is clamped with
one warning; values outside the model's range (e.g. |&xi;| &gt; 1.9) make <code>fmi2DoStep</code> fail with a
message naming the variable.</li>
<li><b>Evaluation mode:</b> <code>mode</code> 0 (auto) uses the lookup table where usable and otherwise the
exact solver, logging one warning; 1 (table only) fails at initialization without a usable table; 2 uses the
exact solver. This build has no lookup table yet, so <code>evaluation_mode</code> is 2. The exact solver's
grid is <code>grid_size</code>&sup2; cells; <code>converged</code> = false (with a warning and
<code>fmi2Warning</code>) flags a coupled iteration that missed its tolerance.</li>
<li><b>Directional derivatives</b> (<code>fmi2GetDirectionalDerivative</code>, Real outputs with respect to Real
inputs): one forward difference along the seed, step 10<sup>&minus;4</sup>&middot;max(|u|, nominal) per input,
solver tolerance 10<sup>&minus;8</sup>. At the stick/slip switching points of the discretised contact (kinks of
F(&xi;)) this is the one-sided slope in the seed direction.</li>
<li><b>FMU states</b> hold parameters, inputs, the last outputs, time and state; the serialized form is
versioned and checksummed, and corrupt bytes are rejected.</li>
</ul>

<h2>Capabilities</h2>
<p>All FMI 2.0 common and co-simulation functions are exported. <code>canHandleVariableCommunicationStepSize</code>,
<code>canGetAndSetFMUstate</code>, <code>canSerializeFMUstate</code>, <code>providesDirectionalDerivative</code>,
<code>canNotUseMemoryManagementFunctions</code>: true. <code>canInterpolateInputs</code>,
<code>canRunAsynchronuously</code>, <code>canBeInstantiatedOnlyOncePerProcess</code>: false;
<code>maxOutputDerivativeOrder</code> = 0. Log categories: logEvents, logStatusWarning, logStatusError, logAll.</p>

<h2>Traction&ndash;creepage curve</h2>
<p><img src="traction_creepage.png" alt="traction coefficient over longitudinal creepage, dry and wet"
width="900"></p>

<h2>Variables</h2>
<table><tr><th>name</th><th>value reference</th><th>causality</th><th>type</th><th>unit</th><th>start</th>
<th>min</th><th>max</th><th>description</th></tr>
{rows}</table>
</body></html>
"#,
        version = env!("CARGO_PKG_VERSION"),
        vmin = DEFAULT_MINIMUM_SPEED,
    )
}
