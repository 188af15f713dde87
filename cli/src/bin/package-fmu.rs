//! Packs `WheelRailFriction.fmu`, or writes only `modelDescription.xml`.
//!
//! ```text
//! package-fmu --model-description PATH
//! package-fmu --library target/release/libWheelRailFriction.so --out target/fmu/WheelRailFriction.fmu
//! package-fmu --library linux64=libWheelRailFriction.so --library win64=WheelRailFriction.dll \
//!             --library darwin64=libWheelRailFriction.dylib --out WheelRailFriction.fmu
//! package-fmu --binaries DIR --out WheelRailFriction.fmu
//! package-fmu --fmi3 --library linux64=libWheelRailFriction.so --out WheelRailFriction-fmi3.fmu
//! ```
//!
//! `--fmi3` packs the FMI 3.0 FMU from the same library: its `modelDescription.xml` (contacts as arrays)
//! and the FMI 3.0 platform directories (`x86_64-linux`, `x86_64-windows`, … for `linux64`, `win64`, …).
//!
//! The archive holds `modelDescription.xml`, the shared library of every platform as
//! `binaries/<platform>/WheelRailFriction.<so|dll|dylib>` (renamed to the modelIdentifier), `resources/`
//! (the lookup table directory `fmu/resources/table` when it exists), and `documentation/` (`index.html`
//! with variables, conventions and a traction–creepage plot from real solves; `_main.html`, the FMI 2.0
//! entry point, links to it).
//!
//! Binaries: `--library PATH` is the library of the platform the packager runs on (default:
//! `target/release/` and the platform's library name, e.g. `libWheelRailFriction.so` on linux64);
//! `--library PLATFORM=PATH` (repeatable) a library built elsewhere; `--binaries DIR` takes one library
//! from each `DIR/<platform>/` (or `DIR/binaries/<platform>/`, e.g. an unpacked FMU). Platforms are those
//! of FMI 2.0 (`win32`, `win64`, `linux32`, `linux64`, `darwin32`, `darwin64`); each library must have the
//! platform's file extension and be a shared library of the platform's format (PE, ELF, Mach-O: the
//! first bytes are checked), and no platform may be given twice.

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

/// An FMI 2.0 platform (standard §2.3: the `binaries/` subdirectories) and its shared-library format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Platform {
    /// The directory name under `binaries/`.
    name: &'static str,
    /// The directory name under `binaries/` in an FMI 3.0 FMU (its platform tuple, standard §2.5.1.4).
    tuple: &'static str,
    /// The shared library's file extension.
    extension: &'static str,
    /// The format's name, for messages.
    format: &'static str,
    /// Possible first bytes of a library of this format.
    magic: &'static [&'static [u8]],
}

const PE: &[&[u8]] = &[b"MZ"];
const ELF: &[&[u8]] = &[b"\x7fELF"];
/// Mach-O 32 and 64 bit in both byte orders, and universal (fat) binaries.
const MACH_O: &[&[u8]] = &[
    b"\xfe\xed\xfa\xce",
    b"\xce\xfa\xed\xfe",
    b"\xfe\xed\xfa\xcf",
    b"\xcf\xfa\xed\xfe",
    b"\xca\xfe\xba\xbe",
];

const fn platform(
    name: &'static str,
    tuple: &'static str,
    extension: &'static str,
    format: &'static str,
    magic: &'static [&'static [u8]],
) -> Platform {
    Platform {
        name,
        tuple,
        extension,
        format,
        magic,
    }
}

/// The platforms of FMI 2.0.
const PLATFORMS: [Platform; 6] = [
    platform("win32", "x86-windows", "dll", "PE", PE),
    platform("win64", "x86_64-windows", "dll", "PE", PE),
    platform("linux32", "x86-linux", "so", "ELF", ELF),
    platform("linux64", "x86_64-linux", "so", "ELF", ELF),
    platform("darwin32", "x86-darwin", "dylib", "Mach-O", MACH_O),
    platform("darwin64", "x86_64-darwin", "dylib", "Mach-O", MACH_O),
];

impl Platform {
    fn named(name: &str) -> Result<Platform> {
        PLATFORMS
            .iter()
            .find(|p| p.name == name)
            .copied()
            .with_context(|| {
                let names: Vec<_> = PLATFORMS.iter().map(|p| p.name).collect();
                format!(
                    "unknown platform \"{name}\" (FMI 2.0 platforms: {})",
                    names.join(", ")
                )
            })
    }

    /// The platform the packager runs on.
    fn host() -> Platform {
        let name = match (std::env::consts::OS, cfg!(target_pointer_width = "64")) {
            ("windows", true) => "win64",
            ("windows", false) => "win32",
            ("macos", true) => "darwin64",
            ("macos", false) => "darwin32",
            (_, true) => "linux64",
            (_, false) => "linux32",
        };
        Platform::named(name).expect("the host platform is in the table")
    }

    /// The library's path inside the FMU (`fmi3`: an FMI 3.0 FMU).
    fn archive_path(self, fmi3: bool) -> String {
        format!(
            "binaries/{}/{}.{}",
            if fmi3 { self.tuple } else { self.name },
            INFO.model_identifier,
            self.extension
        )
    }

    /// Reads the library at `path`, checking its extension and format.
    fn read_library(self, path: &Path) -> Result<Vec<u8>> {
        let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !extension.eq_ignore_ascii_case(self.extension) {
            bail!(
                "{}: a {} library must be a .{} file",
                path.display(),
                self.name,
                self.extension
            );
        }
        let bytes = std::fs::read(path)
            .with_context(|| format!("reading the shared library {}", path.display()))?;
        if !self.magic.iter().any(|m| bytes.starts_with(m)) {
            bail!(
                "{} is not a {} shared library (a {} library is in {} format)",
                path.display(),
                self.format,
                self.name,
                self.format
            );
        }
        Ok(bytes)
    }
}

#[derive(Debug)]
struct Args {
    model_description: Option<PathBuf>,
    /// The libraries by platform, in the order given.
    libraries: Vec<(Platform, PathBuf)>,
    out: PathBuf,
    /// `--fmi3`: the FMI 3.0 FMU (its model description and platform directories).
    fmi3: bool,
}

/// One `--library` value: `PLATFORM=PATH`, or a path of the host platform's library.
fn library_arg(value: &str) -> Result<(Platform, PathBuf)> {
    match value.split_once('=') {
        Some((name, path))
            if !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric()) =>
        {
            Ok((Platform::named(name)?, path.into()))
        }
        _ => Ok((Platform::host(), value.into())),
    }
}

/// The libraries of `--binaries DIR`: one per `<platform>/` subdirectory of DIR (or of `DIR/binaries`).
fn binaries_dir(dir: &Path) -> Result<Vec<(Platform, PathBuf)>> {
    let dir = match dir.join("binaries") {
        nested if nested.is_dir() => nested,
        _ => dir.to_path_buf(),
    };
    let mut found = Vec::new();
    let mut entries = std::fs::read_dir(&dir)
        .with_context(|| format!("reading the binaries directory {}", dir.display()))?
        .map(|e| Ok(e?.path()))
        .collect::<Result<Vec<_>>>()?;
    entries.sort();
    for sub in entries.into_iter().filter(|p| p.is_dir()) {
        let name = sub.file_name().and_then(|n| n.to_str()).unwrap_or("");
        let platform =
            Platform::named(name).with_context(|| format!("directory {}", sub.display()))?;
        let libraries: Vec<PathBuf> = std::fs::read_dir(&sub)?
            .map(|e| Ok(e?.path()))
            .collect::<Result<Vec<_>>>()?
            .into_iter()
            .filter(|p| {
                p.is_file()
                    && p.extension()
                        .and_then(|e| e.to_str())
                        .is_some_and(|e| e.eq_ignore_ascii_case(platform.extension))
            })
            .collect();
        match libraries.as_slice() {
            [one] => found.push((platform, one.clone())),
            [] => bail!("{} holds no .{} library", sub.display(), platform.extension),
            _ => bail!(
                "{} holds {} .{} libraries; which one is the FMU's is ambiguous",
                sub.display(),
                libraries.len(),
                platform.extension
            ),
        }
    }
    if found.is_empty() {
        bail!(
            "{} has no platform directories (e.g. win64/)",
            dir.display()
        );
    }
    Ok(found)
}

fn parse_args(args: impl IntoIterator<Item = String>) -> Result<Args> {
    let mut a = Args {
        model_description: None,
        libraries: Vec::new(),
        out: PathBuf::from("target/fmu/WheelRailFriction.fmu"),
        fmi3: false,
    };
    let mut it = args.into_iter();
    while let Some(flag) = it.next() {
        let mut value = || it.next().with_context(|| format!("{flag} needs a value"));
        match flag.as_str() {
            "--model-description" => a.model_description = Some(value()?.into()),
            "--library" => a.libraries.push(library_arg(&value()?)?),
            "--binaries" => a.libraries.extend(binaries_dir(Path::new(&value()?))?),
            "--out" => a.out = value()?.into(),
            "--fmi3" => a.fmi3 = true,
            _ => bail!("unknown argument {flag} (see the source's header for usage)"),
        }
    }
    if a.libraries.is_empty() {
        let library = format!(
            "target/release/{}WheelRailFriction{}",
            std::env::consts::DLL_PREFIX,
            std::env::consts::DLL_SUFFIX
        );
        a.libraries.push((Platform::host(), library.into()));
    }
    for (k, (p, _)) in a.libraries.iter().enumerate() {
        if a.libraries[..k].iter().any(|(q, _)| q == p) {
            bail!("platform {} is given more than once", p.name);
        }
    }
    Ok(a)
}

fn main() -> Result<()> {
    let a = parse_args(std::env::args().skip(1))?;
    let xml = match a.fmi3 {
        true => WheelRailFriction::model_description_fmi3(),
        false => WheelRailFriction::model_description(),
    };
    if let Some(path) = a.model_description {
        std::fs::write(&path, xml).with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
        return Ok(());
    }
    let libraries = a
        .libraries
        .iter()
        .map(|(platform, path)| {
            let bytes = platform.read_library(path).with_context(|| {
                format!(
                    "the {} library (build it with `make fmu` on that platform)",
                    platform.name
                )
            })?;
            Ok((platform.archive_path(a.fmi3), bytes))
        })
        .collect::<Result<Vec<_>>>()?;
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
    for (name, bytes) in &libraries {
        add(name, bytes, 0o755)?;
    }
    add(
        "documentation/index.html",
        documentation(a.fmi3).as_bytes(),
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
    let platforms: Vec<_> = a.libraries.iter().map(|(p, _)| p.name).collect();
    println!(
        "wrote {} (binaries: {})",
        a.out.display(),
        platforms.join(", ")
    );
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
    let shown = (INFO.display_unit)(v).unwrap_or_default();
    format!(
        "<tr><td><code>{}</code></td><td>{}</td><td>{ty}</td><td>{}</td><td>{}</td><td>{start}</td><td>{min}</td><td>{max}</td><td>{}</td></tr>\n",
        v.name,
        v.vr,
        esc(unit),
        esc(shown),
        esc(v.description)
    )
}

/// The variables of one causality as an HTML table (the header names the columns of [`row`]).
fn variable_table(causality: Causality) -> String {
    let rows: String = VARIABLES
        .iter()
        .filter(|v| v.causality == causality)
        .map(row)
        .collect();
    format!(
        "<table><tr><th>name</th><th>value reference</th><th>type</th><th>unit</th><th>display unit</th>\
         <th>start</th><th>min</th><th>max</th><th>description</th></tr>\n{rows}</table>"
    )
}

/// The FMI 3.0 FMU's section of the documentation: contacts as arrays, threads.
const FMI3_HTML: &str = "<h2>FMI 3.0: contacts as arrays</h2>\n<p>This FMI 3.0 FMU holds any number of contacts \
in one instance: set the structural parameter <code>contacts</code> (UInt64, default 1) in configuration mode \
(<code>fmi3EnterConfigurationMode</code> after instantiation), and every input and output below, and \
<code>roughness</code>, is an array of that many values, one per contact; the other parameters are shared. \
<code>threads</code> (UInt64, default 0: the cores the process may use) is how many threads evaluate the \
contacts of a step; the results are bit for bit those of one evaluation after another, and of one FMI 2.0 \
instance per contact with the same values. Log messages of a contact start with <code>contact k:</code>.</p>\n";

fn documentation(fmi3: bool) -> String {
    let inputs = variable_table(Causality::Input);
    let outputs = variable_table(Causality::Output);
    let parameters = variable_table(Causality::Parameter);
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
fixed point. FMI 2.0 Co-Simulation and Model Exchange (one binary), one instance per contact; any number of
instances per process, on any threads.</p>
{fmi3_section}
<h2>Conventions</h2>
<ul>
<li><b>Frame:</b> x along the track in the direction of travel for positive <code>rolling_speed</code>, y lateral,
z normal into the rail; the contact ellipse has the semi-axis a along x and b along y. SI units; temperatures in
kelvin. One instance per contact.</li>
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
exact solver (<code>evaluation_mode</code> reports which: 1 table, 2 exact). The FMU bundles the default table
(default parameters, the default running-surface contact; axes and ranges in
<code>resources/table/table.json</code>); <code>table_file</code> selects another. The exact solver's grid is
<code>grid_size</code>&sup2; cells, or, with <code>grid_accuracy</code> &gt; 0, the cells whose measured force
error |&Delta;F|/F<sub>N</sub> is within it (0.01: 10 &times; 10); with <code>grid_size</code> 0 (the default)
30 &times; 30, and mode 0 solves the points the table does not serve on a grid per contact (16 to 24 cells
along x, 6 to 12 across: forces within 1 % of F<sub>N</sub> and T<sub>max</sub> within 10 K of 30 &times; 30);
<code>converged</code> = false (with a warning and
<code>fmi2Warning</code>) flags a coupled iteration that missed its tolerance.</li>
<li><b>Directional derivatives</b> (<code>fmi2GetDirectionalDerivative</code>, Real outputs with respect to Real
inputs): one forward difference along the seed, step 10<sup>&minus;4</sup>&middot;max(|u|, nominal) per input,
solver tolerance 10<sup>&minus;8</sup>. At the stick/slip switching points of the discretised contact (kinks of
F(&xi;)) this is the one-sided slope in the seed direction.</li>
<li><b>FMU states</b> hold parameters, inputs, the last outputs, time and state; the serialized form is
versioned and checksummed, and corrupt bytes are rejected.</li>
</ul>

<h2>Capabilities</h2>
<p>All FMI 2.0 common, co-simulation and model-exchange functions are exported. Model Exchange: no continuous
states and no event indicators; the outputs are algebraic functions of the inputs (direct feedthrough), computed
when read after an input changed, with directional derivatives for the integrator's Jacobian; the exact solver's
warm start advances only at accepted points (<code>fmi2ExitInitializationMode</code>,
<code>fmi2EnterContinuousTimeMode</code>, <code>fmi2CompletedIntegratorStep</code>), so that repeated evaluations
within an integrator step give the same outputs for the same inputs. <code>canHandleVariableCommunicationStepSize</code>,
<code>canGetAndSetFMUstate</code>, <code>canSerializeFMUstate</code>, <code>providesDirectionalDerivative</code>,
<code>canNotUseMemoryManagementFunctions</code>: true. <code>canInterpolateInputs</code>,
<code>canRunAsynchronuously</code>, <code>canBeInstantiatedOnlyOncePerProcess</code>: false;
<code>maxOutputDerivativeOrder</code> = 0. Log categories: logEvents, logStatusWarning, logStatusError, logAll.</p>

<h2>Traction&ndash;creepage curve</h2>
<p><img src="traction_creepage.png" alt="traction coefficient over longitudinal creepage, dry and wet"
width="900"></p>

<h2>Inputs</h2>
<p>Continuous, set before every step (Co-Simulation) or evaluation (Model Exchange). Values in SI units; the
display unit is the one an importer shows by default (<code>displayUnit</code> in modelDescription.xml).</p>
{inputs}

<h2>Outputs</h2>
<p>Every output depends on every input (direct feedthrough, no states).</p>
{outputs}

<h2>Parameters</h2>
<p>Fixed: set between instantiation and <code>fmi2ExitInitializationMode</code>.</p>
{parameters}
</body></html>
"#,
        version = env!("CARGO_PKG_VERSION"),
        vmin = DEFAULT_MINIMUM_SPEED,
        fmi3_section = if fmi3 { FMI3_HTML } else { "" },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(list: &[&str]) -> Result<Args> {
        parse_args(list.iter().map(|s| s.to_string()))
    }

    #[test]
    fn libraries_are_named_per_platform_and_validated() {
        let a = args(&["--library", "x/libWheelRailFriction.so"]).unwrap();
        assert_eq!(
            a.libraries,
            [(Platform::host(), "x/libWheelRailFriction.so".into())]
        );
        let a = args(&[
            "--library",
            "win64=C:/b=1/WheelRailFriction.dll",
            "--library",
            "darwin64=m.dylib",
        ])
        .unwrap();
        let paths: Vec<_> = a
            .libraries
            .iter()
            .map(|(p, _)| p.archive_path(false))
            .collect();
        assert_eq!(
            paths,
            [
                "binaries/win64/WheelRailFriction.dll",
                "binaries/darwin64/WheelRailFriction.dylib"
            ]
        );
        assert_eq!(
            a.libraries[0].1,
            PathBuf::from("C:/b=1/WheelRailFriction.dll")
        );
        // a path with '=' that names no platform stays a path of the host's library
        let a = args(&["--library", "out/a-b=c.so"]).unwrap();
        assert_eq!(a.libraries[0].0, Platform::host());
        let e = args(&["--library", "win65=x.dll"]).unwrap_err().to_string();
        assert!(
            e.contains("unknown platform \"win65\"") && e.contains("darwin64"),
            "{e}"
        );
        let e = args(&["--library", "win64=a.dll", "--library", "win64=b.dll"]).unwrap_err();
        assert!(
            e.to_string()
                .contains("platform win64 is given more than once")
        );
        let default = args(&[]).unwrap();
        assert_eq!(default.libraries.len(), 1);
        assert!(default.libraries[0].1.starts_with("target/release"));
    }

    #[test]
    fn the_documentation_lists_each_variable_once_in_the_table_of_its_causality() {
        let html = documentation(false);
        let section = |title: &str| {
            let start = html.find(&format!("<h2>{title}</h2>")).unwrap();
            let end = html[start..].find("</table>").unwrap() + start;
            html[start..end].to_string()
        };
        let sections = [
            (Causality::Input, section("Inputs")),
            (Causality::Output, section("Outputs")),
            (Causality::Parameter, section("Parameters")),
        ];
        for v in &VARIABLES {
            let cell = format!("<td><code>{}</code></td>", v.name);
            for (causality, text) in &sections {
                let want = usize::from(*causality == v.causality);
                assert_eq!(text.matches(&cell).count(), want, "{}", v.name);
            }
        }
        // the display units of modelDescription.xml, e.g. the temperature in degrees Celsius
        assert!(html.contains(
            "<td><code>max_temperature</code></td><td>10</td><td>Real</td><td>K</td><td>degC</td>"
        ));
    }

    #[test]
    fn a_library_must_have_its_platforms_extension_and_format() {
        let dir = std::env::temp_dir().join(format!("package-fmu-unit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let write = |name: &str, bytes: &[u8]| {
            let p = dir.join(name);
            std::fs::write(&p, bytes).unwrap();
            p
        };
        let dll = write("WheelRailFriction.dll", b"MZ\x90\x00fake");
        let so = write("libWheelRailFriction.so", b"\x7fELF\x02fake");
        let dylib = write("libWheelRailFriction.dylib", b"\xcf\xfa\xed\xfefake");
        let win64 = Platform::named("win64").unwrap();
        let linux64 = Platform::named("linux64").unwrap();
        let darwin64 = Platform::named("darwin64").unwrap();
        assert!(win64.read_library(&dll).is_ok());
        assert!(linux64.read_library(&so).is_ok());
        assert!(darwin64.read_library(&dylib).is_ok());
        let e = win64.read_library(&so).unwrap_err().to_string();
        assert!(e.contains("a win64 library must be a .dll file"), "{e}");
        // the right name but the wrong format: a Linux library renamed
        let renamed = write("renamed.dll", b"\x7fELF\x02fake");
        let e = win64.read_library(&renamed).unwrap_err().to_string();
        assert!(e.contains("is not a PE shared library"), "{e}");
        let e = darwin64
            .read_library(&dll.with_extension("dylib"))
            .unwrap_err();
        assert!(
            format!("{e:#}").contains("reading the shared library"),
            "{e:#}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
