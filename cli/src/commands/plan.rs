//! `wheelrail table plan`: the axes file of a table by similarity that covers the contacts a vehicle sees
//! (docs/tables.md, "Tables for your own profile pair"; the design: docs/model.md §9.1, §12.3).
//!
//! The contacts come as rows of semi-axes a, b at a normal force, or of gap curvatures A, B. Each gives its
//! ellipse ratio a/b and its reference pressure p_ref, the Hertz peak pressure of its shape at
//! F_ref = 100 kN (docs/model.md §2, §12.3; a contact of fixed curvatures keeps them at every load). A
//! table by similarity holds the contacts' own peak pressures p0 = p_ref·(F_N/F_ref)^(1/3) at the loads
//! they run at; a table with a normal-force axis holds p_ref. The geometry axes span them in whole cells
//! of the designs' spacing (ln-spaced: [`RATIO_CELL`], [`PRESSURE_CELL_LOW`] below [`PRESSURE_KNEE`],
//! [`PRESSURE_CELL_HIGH`] above), centred on the contacts; every other axis is the base axes file's.

use anyhow::{Context, Result, bail};
use clap::Args;
use std::fmt;
use std::path::{Path, PathBuf};
use wheelrail::table::axes::{PRESSURE, RATIO, REFERENCE_FORCE, SPEED};
use wheelrail::table::coords::{peak_pressure, reference_pressure, semi_axes};
use wheelrail::table::{Axes, AxesSpec, AxisSpec, DIMENSIONS, Interpolation, Storage};
use wheelrail::{Params, Tangential};

/// The base axes of a plan without `--base`: the running-surface design by similarity
/// (`tools/running-surface-axes.toml`). Its creepage, speed and wetness axes are the ones built and
/// verified as a whole table (docs/tables.md), and a table by similarity serves every load with about half
/// the force error of one with a normal-force axis at the same size (docs/model.md §12.3).
const DEFAULT_BASE: &str = include_str!("../../../tools/running-surface-axes.toml");

/// The name of [`DEFAULT_BASE`] in messages.
const DEFAULT_BASE_NAME: &str = "tools/running-surface-axes.toml";

/// The ellipse ratios and peak pressures the default base's creepage axes were verified on (a/b, then p0
/// [Pa]; docs/tables.md): beyond them the whole-range design's (`tools/whole-range-axes.toml`, designed
/// over a/b 0.2–5 and p0 0.15–2.5 GPa) is the better base.
const DEFAULT_BASE_GEOMETRY: [[f64; 2]; 2] = [[0.3, 1.2], [0.3e9, 1.2e9]];

/// The geometry the table designs were measured on (a/b, then p0 [Pa]; `tools/whole-range-axes.toml`,
/// docs/model.md §12.3): a plan beyond it gets a warning.
const DESIGN_GEOMETRY: [[f64; 2]; 2] = [[0.2, 5.0], [0.15e9, 2.5e9]];

/// The largest ratio of neighbouring a/b nodes: the whole-range design's (5/0.2)^(1/5) = 1.904, rounded
/// down (docs/model.md §12.3).
pub const RATIO_CELL: f64 = 1.9;

/// The largest ratio of neighbouring pressure nodes below [`PRESSURE_KNEE`] (the whole-range design's).
pub const PRESSURE_CELL_LOW: f64 = 1.5;

/// The largest ratio of neighbouring pressure nodes above [`PRESSURE_KNEE`], where wet contacts begin to
/// lose their film and the walls set in (docs/model.md §8.5, §12.3): the whole-range design's
/// (2.5 GPa/0.759 GPa)^(1/12) = 1.1045.
pub const PRESSURE_CELL_HIGH: f64 = 1.1045;

/// The pressure from which on the pressure cells are [`PRESSURE_CELL_HIGH`] [Pa]: the whole-range design's
/// node 0.15 GPa·1.5⁴.
pub const PRESSURE_KNEE: f64 = 759_375_000.0;

/// The relative margin by which the geometry axes reach beyond the outermost contacts, so that a contact
/// whose a/b or p0 an evaluation computes a rounding away from the file's stays inside [-].
const EDGE_MARGIN: f64 = 1e-3;

/// The cost of a table by similarity on the default 30 × 30 grid with FASTSIM [core-hours per million
/// points]: measured on the whole-range design (48 random creepage cubes timed: 118 core-hours for its
/// 46.1 million points, docs/tables.md "Cost") and the running-surface design (≈ 12 core-hours for
/// 4.6 million points, `tools/running-surface-axes.toml`).
pub const CORE_HOURS_PER_MILLION_POINTS: f64 = 2.6;

/// The grid the cost per point was measured on (cells; the cost is about proportional to the cell count,
/// docs/tables.md "Cost").
const COST_GRID_CELLS: f64 = 900.0;

/// The cost of a table of the exact tangential solver per FASTSIM's: 22 against 5 ms per point and thread
/// on 30 × 30 (docs/tables.md "Cost").
const EXACT_TANGENTIAL_COST: f64 = 22.0 / 5.0;

/// The bytes of u16z per u16 storage: the running-surface table's 17.8 MB against 59.8 MB (docs/model.md
/// §12.3, finest codes).
const U16Z_PER_U16: f64 = 17.8 / 59.8;

/// The bytes of u16x per u16 storage: the running-surface table's 10.6 MB against 59.8 MB.
const U16X_PER_U16: f64 = 10.6 / 59.8;

/// The most shards the suggested job uses: below Slurm's default `MaxArraySize` (1001).
const MAX_SHARDS: usize = 1000;

/// The loads a table by similarity serves by default [N]: those its base's equivalent speeds were laid out
/// for (0.32–158 m/s serve V 1–100 m/s at 10–250 kN, docs/model.md §12.3).
const DEFAULT_LOADS: [f64; 2] = [10e3, 250e3];

/// Arguments of `wheelrail table plan`.
#[derive(Debug, Args)]
pub struct PlanArgs {
    /// The contacts (CSV): a header line naming the columns `a,b` (semi-axes [m]) with `normal_force`
    /// [N] (or --normal-force), or `A,B` (gap curvatures [1/m]); other columns are ignored, `#` starts a
    /// comment.
    #[arg(long, value_name = "FILE.csv")]
    contacts: PathBuf,
    /// The axes file to write.
    #[arg(long, value_name = "AXES.toml", default_value = "plan-axes.toml")]
    out: PathBuf,
    /// The axes of every other axis (creepages, normal force, speed, wetness) [default: those of
    /// tools/running-surface-axes.toml, a table by similarity].
    #[arg(long, value_name = "AXES.toml")]
    base: Option<PathBuf>,
    /// The normal force [N] of rows of semi-axes without a normal_force value.
    #[arg(long, value_name = "N")]
    normal_force: Option<f64>,
    /// The loads MIN,MAX [N] the contacts run at: a table by similarity holds their peak pressures at all
    /// of them [default: 10e3,250e3].
    #[arg(long, value_name = "MIN,MAX")]
    loads: Option<String>,
    /// Parameter file (TOML) of the table: its material gives the Hertz contacts of curvatures, its grid
    /// and tangential solver the cost [default: the default parameter set].
    #[arg(long, value_name = "FILE.toml")]
    params: Option<PathBuf>,
    /// The job directory of the printed `table slurm` command.
    #[arg(long, value_name = "DIR", default_value = "table-job")]
    job: PathBuf,
}

/// A contacts file that cannot be used: the file, the line (1-based) and why. Invalid input (exit code 2).
#[derive(Debug)]
pub struct ContactsError {
    path: String,
    line: Option<usize>,
    reason: String,
}

impl fmt::Display for ContactsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(n) => write!(f, "contacts file {}, line {n}: {}", self.path, self.reason),
            None => write!(f, "contacts file {}: {}", self.path, self.reason),
        }
    }
}

impl std::error::Error for ContactsError {}

/// What the rows of a contacts file give.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Columns {
    /// Semi-axes a, b [m] (column indices), with the normal force's column if there is one.
    SemiAxes {
        a: usize,
        b: usize,
        force: Option<usize>,
    },
    /// Gap curvatures A, B [1/m] (column indices).
    Curvatures { a: usize, b: usize },
}

/// One contact of the file: its ellipse ratio a/b and reference pressure p_ref [Pa].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// a/b [-].
    pub ratio: f64,
    /// p_ref [Pa]: the Hertz peak pressure of the contact's shape at F_ref.
    pub reference_pressure: f64,
}

/// The text of a line without its comment, trimmed.
fn content(line: &str) -> &str {
    line.split('#').next().unwrap_or("").trim()
}

/// The lines of a CSV text that hold something, with their 1-based numbers, without comments: the first
/// is the header.
pub(super) fn csv_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| (i + 1, content(l)))
        .filter(|(_, l)| !l.is_empty())
}

/// The cells of a line: split at commas, trimmed, and without the double quotes a spreadsheet may put
/// around them.
pub(super) fn cells(line: &str) -> Vec<&str> {
    line.split(',')
        .map(|c| c.trim().trim_matches('"').trim())
        .collect()
}

/// The column of a header naming one of `names`.
fn column(header: &[&str], names: &[&str]) -> Option<usize> {
    header.iter().position(|h| names.contains(h))
}

/// The columns a header names: `a,b` (or `semi_axis_a,semi_axis_b`) with an optional `normal_force`, or
/// `A,B` (or `curvature_x,curvature_y`), not both.
fn columns(header: &[&str]) -> std::result::Result<Columns, String> {
    let semi = (
        column(header, &["a", "semi_axis_a"]),
        column(header, &["b", "semi_axis_b"]),
    );
    let curv = (
        column(header, &["A", "curvature_x"]),
        column(header, &["B", "curvature_y"]),
    );
    match (semi, curv) {
        ((Some(a), Some(b)), (None, None)) => Ok(Columns::SemiAxes {
            a,
            b,
            force: column(header, &["normal_force", "F_N"]),
        }),
        ((None, None), (Some(a), Some(b))) => Ok(Columns::Curvatures { a, b }),
        ((Some(_), Some(_)), (Some(_), Some(_))) => {
            Err("the header names both semi-axes (a,b) and curvatures (A,B): give one pair".into())
        }
        _ => Err(format!(
            "the header {:?} must name the columns a,b (semi-axes [m], with normal_force [N] or \
             --normal-force) or A,B (gap curvatures [1/m])",
            header.join(",")
        )),
    }
}

/// The value of column `i` of a row: a finite number > 0.
fn positive(cells: &[&str], i: usize, name: &str, unit: &str) -> std::result::Result<f64, String> {
    let text = cells
        .get(i)
        .copied()
        .filter(|t| !t.is_empty())
        .ok_or_else(|| format!("no value of {name}"))?;
    let x: f64 = text
        .parse()
        .map_err(|_| format!("{name} {text:?} is not a number"))?;
    if !(x.is_finite() && x > 0.0) {
        return Err(format!("{name} {text} must be finite and > 0 {unit}"));
    }
    Ok(x)
}

/// Reads the contacts of `path` (see [`PlanArgs::contacts`]): per row a/b and p_ref, the Hertz contacts of
/// curvatures with the material of `params` (E* at the bulk temperature, as the solver takes it).
pub fn read_contacts(
    path: &Path,
    normal_force: Option<f64>,
    params: &Params,
) -> Result<Vec<Contact>> {
    let err = |line: Option<usize>, reason: String| ContactsError {
        path: path.display().to_string(),
        line,
        reason,
    };
    let text = std::fs::read_to_string(path).map_err(|e| err(None, e.to_string()))?;
    let mut lines = csv_lines(&text);
    let (header_line, header) = lines
        .next()
        .ok_or_else(|| err(None, "no header line and no contacts".into()))?;
    let header = cells(header);
    let cols = columns(&header).map_err(|r| err(Some(header_line), r))?;
    let mut contacts = Vec::new();
    for (n, line) in lines {
        let cells = cells(line);
        let contact = |reason| err(Some(n), reason);
        let (ratio, p_ref) = match cols {
            Columns::SemiAxes { a, b, force } => {
                let (a, b) = (
                    positive(&cells, a, "a", "m").map_err(contact)?,
                    positive(&cells, b, "b", "m").map_err(contact)?,
                );
                let f = match force.filter(|i| cells.get(*i).is_some_and(|t| !t.is_empty())) {
                    Some(i) => positive(&cells, i, "normal_force", "N").map_err(contact)?,
                    None => normal_force.ok_or_else(|| {
                        contact(
                            "semi-axes need the normal force they were computed at: a column \
                             normal_force or --normal-force"
                                .into(),
                        )
                    })?,
                };
                (a / b, reference_pressure(a, b, f))
            }
            Columns::Curvatures { a, b } => {
                let (ca, cb) = (
                    positive(&cells, a, "A", "1/m").map_err(contact)?,
                    positive(&cells, b, "B", "1/m").map_err(contact)?,
                );
                let mut p = params.clone();
                p.geometry.curvature_x = ca;
                p.geometry.curvature_y = cb;
                p.geometry.semi_axes = None;
                let h = wheelrail::solver::normal_contact(&p, REFERENCE_FORCE)
                    .map_err(|e| contact(e.to_string()))?;
                (h.a / h.b, h.p0)
            }
        };
        contacts.push(Contact {
            ratio,
            reference_pressure: p_ref,
        });
    }
    if contacts.is_empty() {
        return Err(err(Some(header_line), "no contacts below the header".into()).into());
    }
    Ok(contacts)
}

/// Nodes in whole cells of length 1 in the coordinate `u`, centred on [lo, hi] widened by
/// [`EDGE_MARGIN`]: at least one cell, `to`/`from` mapping u to the axis' values and back.
fn centred_cells(lo: f64, hi: f64, to: impl Fn(f64) -> f64, from: impl Fn(f64) -> f64) -> Vec<f64> {
    let (u0, u1) = (to(lo / (1.0 + EDGE_MARGIN)), to(hi * (1.0 + EDGE_MARGIN)));
    let cells = (u1 - u0).ceil().max(1.0);
    let start = 0.5 * (u0 + u1) - 0.5 * cells;
    (0..=cells as usize)
        .map(|k| from(start + k as f64))
        .collect()
}

/// The a/b nodes over ratios lo..hi: ln-spaced, [`RATIO_CELL`] per cell.
pub fn ratio_points(lo: f64, hi: f64) -> Vec<f64> {
    let step = RATIO_CELL.ln();
    centred_cells(lo, hi, |r| r.ln() / step, |u| (u * step).exp())
}

/// The pressure nodes over lo..hi [Pa]: ln-spaced, [`PRESSURE_CELL_LOW`] per cell below
/// [`PRESSURE_KNEE`] and [`PRESSURE_CELL_HIGH`] above (a cell across the knee: each part within its
/// ratio).
pub fn pressure_points(lo: f64, hi: f64) -> Vec<f64> {
    let (low, high) = (PRESSURE_CELL_LOW.ln(), PRESSURE_CELL_HIGH.ln());
    let knee = PRESSURE_KNEE.ln();
    let to = |p: f64| {
        let l = p.ln() - knee;
        if l < 0.0 { l / low } else { l / high }
    };
    let from = |u: f64| (knee + if u < 0.0 { u * low } else { u * high }).exp();
    centred_cells(lo, hi, to, from)
}

/// The geometry a plan covers: the a/b range and the pressure range of its axis (p0 over the loads by
/// similarity, else p_ref).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    /// a/b [min, max].
    pub ratio: [f64; 2],
    /// p0 or p_ref [min, max] [Pa].
    pub pressure: [f64; 2],
}

/// The span of `contacts` in a table by similarity at `loads` [N] (p0 of each contact at the lightest and
/// the heaviest load: p0 = p_ref·(F_N/F_ref)^(1/3)), or in one with a normal-force axis (`loads` None:
/// p_ref).
pub fn span(contacts: &[Contact], loads: Option<[f64; 2]>) -> Span {
    let fold = |f: &dyn Fn(&Contact) -> [f64; 2]| {
        contacts.iter().fold([f64::MAX, 0.0f64], |[lo, hi], c| {
            let [l, h] = f(c);
            [lo.min(l), hi.max(h)]
        })
    };
    let p0 = |c: &Contact, force: f64| {
        let [a, b] = semi_axes(c.ratio, c.reference_pressure, force);
        peak_pressure(a, b, force)
    };
    Span {
        ratio: fold(&|c| [c.ratio, c.ratio]),
        pressure: fold(&|c| match loads {
            Some([lo, hi]) => [p0(c, lo), p0(c, hi)],
            None => [c.reference_pressure; 2],
        }),
    }
}

/// An ln-interpolated axis of `points`.
fn log_axis(points: Vec<f64>) -> AxisSpec {
    AxisSpec {
        points: Some(points),
        interpolation: Some(Interpolation::Log),
        ..Default::default()
    }
}

/// The loads of `--loads MIN,MAX`.
fn parse_loads(text: &str) -> Result<[f64; 2]> {
    let bad = || wheelrail::Error::OutOfRange {
        name: "loads".into(),
        value: text.into(),
        allowed: "MIN,MAX [N], finite, 0 < MIN <= MAX".into(),
    };
    let [lo, hi] = super::pair("loads", text).map_err(|_| bad())?;
    if !(lo > 0.0 && lo <= hi && hi.is_finite()) {
        bail!(bad());
    }
    Ok([lo, hi])
}

/// A number of bytes in MB (kB below 1 MB).
fn megabytes(bytes: f64) -> String {
    if bytes < 1e6 {
        format!("{:.1} kB", bytes / 1e3)
    } else {
        format!("{:.1} MB", bytes / 1e6)
    }
}

/// `x` > 0 to three significant digits.
fn significant(x: f64) -> String {
    let decimals = (2 - x.log10().floor() as i32).max(0) as usize;
    format!("{x:.decimals$}")
}

/// Runs `wheelrail table plan`.
pub fn run(a: &PlanArgs) -> Result<()> {
    let params = match &a.params {
        Some(p) => Params::from_toml_file(p)?,
        None => Params::default(),
    };
    if let Some(f) = a.normal_force
        && !(f.is_finite() && f > 0.0)
    {
        bail!(wheelrail::Error::out_of_range(
            "normal-force",
            f,
            "finite > 0 N"
        ));
    }
    let (base_name, base_text) = match &a.base {
        Some(p) => (
            p.display().to_string(),
            std::fs::read_to_string(p).map_err(|e| wheelrail::Error::ParameterFile {
                path: p.display().to_string(),
                reason: e.to_string(),
            })?,
        ),
        None => (DEFAULT_BASE_NAME.to_string(), DEFAULT_BASE.to_string()),
    };
    let bad_base = |reason: String| wheelrail::Error::ParameterFile {
        path: base_name.clone(),
        reason,
    };
    let mut spec: AxesSpec = toml::from_str(&base_text).map_err(|e| bad_base(e.to_string()))?;
    let base = Axes::from_spec(&spec).map_err(|e| bad_base(e.to_string()))?;
    let contacts = read_contacts(&a.contacts, a.normal_force, &params)?;
    let loads = match (&a.loads, base.similarity()) {
        (Some(text), true) => Some(parse_loads(text)?),
        (None, true) => Some(DEFAULT_LOADS),
        (Some(_), false) => bail!(wheelrail::Error::OutOfRange {
            name: "loads".into(),
            value: a.loads.clone().unwrap_or_default(),
            allowed: format!(
                "only with a base by similarity: {base_name} has a normal-force axis, whose points \
                 set the loads"
            ),
        }),
        (None, false) => None,
    };
    let span = span(&contacts, loads);
    spec.semi_axis_ratio = Some(log_axis(ratio_points(span.ratio[0], span.ratio[1])));
    spec.reference_pressure = Some(log_axis(pressure_points(
        span.pressure[0],
        span.pressure[1],
    )));
    let axes = Axes::from_spec(&spec).context("the planned axes")?;
    let text = plan_text(
        a, &base_name, &contacts, &span, loads, &axes, &params, &spec,
    )?;
    std::fs::write(&a.out, text).with_context(|| format!("writing {}", a.out.display()))?;
    Ok(())
}

/// Prints the plan and returns the axes file's text.
#[allow(clippy::too_many_arguments)]
fn plan_text(
    a: &PlanArgs,
    base_name: &str,
    contacts: &[Contact],
    span: &Span,
    loads: Option<[f64; 2]>,
    axes: &Axes,
    params: &Params,
    spec: &AxesSpec,
) -> Result<String> {
    let gpa = |p: f64| p / 1e9;
    let (ratio, pressure) = (&axes.0[RATIO], &axes.0[PRESSURE]);
    let pressure_name = match loads {
        Some([lo, hi]) => format!(
            "p0 (by similarity: the contacts' peak pressures at F_N {:.0}–{:.0} kN)",
            lo / 1e3,
            hi / 1e3
        ),
        None => "p_ref (at 100 kN; the base's normal-force axis sets the loads)".into(),
    };
    let mut out = Vec::new();
    out.push(format!(
        "{} contacts of {}: a/b {:.4}–{:.4}, p_ref {:.4}–{:.4} GPa",
        contacts.len(),
        a.contacts.display(),
        span.ratio[0],
        span.ratio[1],
        gpa(contacts
            .iter()
            .map(|c| c.reference_pressure)
            .fold(f64::MAX, f64::min)),
        gpa(contacts
            .iter()
            .map(|c| c.reference_pressure)
            .fold(0.0, f64::max)),
    ));
    out.push(format!(
        "a/b    {:>2} points {:.4}–{:.4} (ln-spaced, {RATIO_CELL}× per cell)",
        ratio.points.len(),
        ratio.min(),
        ratio.max()
    ));
    out.push(format!(
        "{pressure_name}\n       {:>2} points {:.4}–{:.4} GPa over {:.4}–{:.4} GPa (ln-spaced, \
         {PRESSURE_CELL_LOW}× per cell below {} GPa, {PRESSURE_CELL_HIGH}× above)",
        pressure.points.len(),
        gpa(pressure.min()),
        gpa(pressure.max()),
        gpa(span.pressure[0]),
        gpa(span.pressure[1]),
        gpa(PRESSURE_KNEE),
    ));
    let others: Vec<String> = (0..RATIO)
        .map(|d| format!("{} {}", DIMENSIONS[d].symbol, axes.0[d].points.len()))
        .collect();
    out.push(format!("other axes of {base_name}: {}", others.join(", ")));
    if let Some([lo, hi]) = loads {
        let v = &axes.0[SPEED];
        let served = |f: f64| {
            let scale = (f / REFERENCE_FORCE).sqrt();
            format!(
                "V {:.3}–{:.3} m/s at {:.0} kN",
                v.min() / scale,
                v.max() / scale,
                f / 1e3
            )
        };
        out.push(format!(
            "       equivalent speeds {}–{} m/s: {}, {}",
            v.min(),
            v.max(),
            served(lo),
            served(hi)
        ));
    }
    let [[r0, r1], [p0, p1]] = DEFAULT_BASE_GEOMETRY;
    let beyond_base =
        span.ratio[0] < r0 || span.ratio[1] > r1 || span.pressure[0] < p0 || span.pressure[1] > p1;
    if a.base.is_none() && beyond_base {
        out.push(format!(
            "note: the contacts reach beyond a/b {r0}–{r1}, p0 {}–{} GPa, where the base's creepage axes \
             were verified; --base tools/whole-range-axes.toml takes the creepage axes designed for the \
             whole range (31 ξ̂ nodes, the spin scaled with the contact's size)",
            gpa(p0),
            gpa(p1)
        ));
    }
    let [[r0, r1], [p0, p1]] = DESIGN_GEOMETRY;
    if ratio.min() < r0 || ratio.max() > r1 || pressure.min() < p0 || pressure.max() > p1 {
        eprintln!(
            "warning: the plan reaches beyond a/b {r0}–{r1}, p {}–{} GPa, the geometry the table designs \
             were measured on: check it with `table verify`",
            gpa(p0),
            gpa(p1)
        );
    }
    let points = axes.len();
    let [nx, ny] = params.grid.cells();
    let solver = match params.tangential {
        Tangential::Exact => EXACT_TANGENTIAL_COST,
        _ => 1.0,
    };
    let core_hours = CORE_HOURS_PER_MILLION_POINTS * points as f64 / 1e6 * (nx * ny) as f64
        / COST_GRID_CELLS
        * solver;
    out.push(format!("points {points}"));
    out.push(format!(
        "cost   ≈ {} core-hours ({CORE_HOURS_PER_MILLION_POINTS} per million points on \
         30 × 30 cells, measured on the bundled designs, docs/tables.md; scaled to {nx} × {ny} cells{})",
        significant(core_hours),
        if solver > 1.0 {
            ", × 4.4 for the exact tangential solver"
        } else {
            ""
        }
    ));
    let f32_bytes = wheelrail::table::file::array_bytes(axes, Storage::F32).expect("uncompressed");
    let u16_bytes = wheelrail::table::file::array_bytes(axes, Storage::U16).expect("uncompressed");
    out.push(format!(
        "bytes  f32 {f32_bytes} ({}), u16 {u16_bytes} ({}) of arrays; estimated u16z ≈ {}, u16x ≈ {} \
         (the running-surface table's ratios)",
        megabytes(f32_bytes as f64),
        megabytes(u16_bytes as f64),
        megabytes(u16_bytes as f64 * U16Z_PER_U16),
        megabytes(u16_bytes as f64 * U16X_PER_U16),
    ));
    let shards = wheelrail::table::file::cube_count(axes).min(MAX_SHARDS);
    let params_flag = a
        .params
        .as_ref()
        .map_or(String::new(), |p| format!(" --params {}", p.display()));
    out.push(format!("wrote {}; build it with", a.out.display()));
    out.push(format!(
        "  wheelrail table slurm --axes {} --out {} --shards {shards}{params_flag} --storage u16x",
        a.out.display(),
        a.job.display(),
    ));
    for line in &out {
        println!("{line}");
    }
    let mut text = format!(
        "# Planned by `wheelrail table plan` for the contacts of {} (docs/tables.md):\n",
        a.contacts.display()
    );
    for line in out.iter().take(out.len() - 2) {
        for l in line.lines() {
            text.push_str(&format!("# {}\n", l.trim_start()));
        }
    }
    text.push_str(&toml::to_string(spec).context("writing the axes")?);
    Ok(text)
}
