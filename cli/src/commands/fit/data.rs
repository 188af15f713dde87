//! The measurements of `wheelrail fit`: a CSV file whose header names the operating-point inputs as
//! `point`'s flags, the contact geometry, the measured columns and an optional weight.

use super::super::plan::{cells, csv_lines};
use std::fmt;
use std::path::Path;
use wheelrail::params::{Geometry, Input, spec::SEMI_AXIS_RANGE};
use wheelrail::solver::GlobalResults;
use wheelrail::{OperatingPoint, Params};

/// Bad input of `wheelrail fit` (the data file, `--free`, `--bounds`): exit code 2. It names the file
/// and line, or the key.
#[derive(Debug)]
pub struct FitInputError(pub String);

impl fmt::Display for FitInputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for FitInputError {}

/// A measured quantity, the column that holds it and the model's value it is compared with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measured {
    /// `f`: the traction coefficient |F_T|/F_N [-] (`point`'s `traction_coefficient`).
    TractionCoefficient,
    /// `force-x`: the longitudinal force F_x [N] (`point`'s `force_x`, same sign convention).
    ForceX,
    /// `force-y`: the lateral force F_y [N] (`point`'s `force_y`).
    ForceY,
}

impl Measured {
    /// Every measured quantity, in the order the report lists them.
    pub const ALL: [Measured; 3] = [
        Measured::TractionCoefficient,
        Measured::ForceX,
        Measured::ForceY,
    ];

    /// The column name in the data file.
    pub const fn column(self) -> &'static str {
        match self {
            Measured::TractionCoefficient => "f",
            Measured::ForceX => "force-x",
            Measured::ForceY => "force-y",
        }
    }

    /// The model's value of the quantity.
    pub fn of(self, g: &GlobalResults) -> f64 {
        match self {
            Measured::TractionCoefficient => g.traction_coefficient,
            Measured::ForceX => g.force_x,
            Measured::ForceY => g.force_y,
        }
    }

    /// The scale that makes a difference of this quantity a traction coefficient: 1 for f, the point's
    /// normal force [N] for the forces. The fit's residuals are all dimensionless this way, so that f
    /// and force columns can be fitted together.
    pub fn scale(self, point: &OperatingPoint) -> f64 {
        match self {
            Measured::TractionCoefficient => 1.0,
            Measured::ForceX | Measured::ForceY => point.normal_force,
        }
    }
}

/// The weight column's name: a relative weight (> 0) of the row's squared residuals.
pub const WEIGHT: &str = "weight";

/// The geometry columns: prescribed semi-axes a, b [m] or gap curvatures A, B [1/m], each as a pair.
const SEMI_AXES: [&str; 2] = ["semi-axis-a", "semi-axis-b"];
const CURVATURES: [&str; 2] = ["curvature-x", "curvature-y"];

/// One row of measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Its line in the file (1-based).
    pub line: usize,
    /// The operating point: the row's inputs, the others at `point`'s defaults or flags.
    pub point: OperatingPoint,
    /// The contact geometry the row gives.
    pub geometry: RowGeometry,
    /// The measured values, one per measured column of the file ([`Data::measured`], same order).
    pub values: Vec<f64>,
    /// The relative weight of its squared residuals.
    pub weight: f64,
}

/// The contact geometry of a row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RowGeometry {
    /// None: the parameter set's (which a fit of `geometry.curvature_x` or `curvature_y` changes).
    Parameters,
    /// Prescribed semi-axes [a, b] [m].
    SemiAxes([f64; 2]),
    /// Gap curvatures [A, B] [1/m].
    Curvatures([f64; 2]),
}

impl RowGeometry {
    /// The contact geometry of the row with the parameter set `params`.
    pub fn of(&self, params: &Params) -> Geometry {
        let mut g = params.geometry.clone();
        match *self {
            RowGeometry::Parameters => {}
            RowGeometry::SemiAxes(axes) => g.semi_axes = Some(axes),
            RowGeometry::Curvatures([a, b]) => {
                g.curvature_x = a;
                g.curvature_y = b;
                g.semi_axes = None;
            }
        }
        g
    }
}

/// The measurements of a data file.
#[derive(Debug, Clone, PartialEq)]
pub struct Data {
    /// The measured columns of the file, in the order of [`Measured::ALL`].
    pub measured: Vec<Measured>,
    /// The rows, in file order.
    pub rows: Vec<Row>,
}

/// Where each known column of the header is.
struct Columns {
    inputs: Vec<(Input, usize)>,
    semi_axes: Option<[usize; 2]>,
    curvatures: Option<[usize; 2]>,
    measured: Vec<(Measured, usize)>,
    weight: Option<usize>,
}

/// The column names an input has in the data file: its `point` flag.
fn input_column(i: Input) -> &'static str {
    i.spec().cli.expect("every input has a flag")
}

/// The known columns, for messages.
fn known_columns() -> String {
    let names: Vec<&str> = Input::ALL
        .into_iter()
        .map(input_column)
        .chain(SEMI_AXES)
        .chain(CURVATURES)
        .chain(Measured::ALL.map(Measured::column))
        .chain([WEIGHT])
        .collect();
    names.join(", ")
}

/// A pair of geometry columns: both or neither.
fn pair(header: &[&str], names: [&str; 2]) -> Result<Option<[usize; 2]>, String> {
    let at = names.map(|n| header.iter().position(|h| *h == n));
    match at {
        [Some(a), Some(b)] => Ok(Some([a, b])),
        [None, None] => Ok(None),
        [Some(_), None] => Err(format!("column {} needs column {}", names[0], names[1])),
        [None, Some(_)] => Err(format!("column {} needs column {}", names[1], names[0])),
    }
}

/// The columns of a header line; an unknown or repeated name, half a geometry pair, both geometry pairs
/// or no measured column is an error.
fn columns(header: &[&str]) -> Result<Columns, String> {
    for (k, name) in header.iter().enumerate() {
        let known = Input::ALL.into_iter().any(|i| input_column(i) == *name)
            || SEMI_AXES.contains(name)
            || CURVATURES.contains(name)
            || Measured::ALL.iter().any(|m| m.column() == *name)
            || *name == WEIGHT;
        if !known {
            return Err(format!(
                "unknown column {name:?} (known: {})",
                known_columns()
            ));
        }
        if header[..k].contains(name) {
            return Err(format!("column {name:?} appears twice"));
        }
    }
    let find = |name: &str| header.iter().position(|h| *h == name);
    let semi_axes = pair(header, SEMI_AXES)?;
    let curvatures = pair(header, CURVATURES)?;
    if semi_axes.is_some() && curvatures.is_some() {
        return Err("give the semi-axes or the curvatures of a contact, not both".into());
    }
    let measured: Vec<(Measured, usize)> = Measured::ALL
        .into_iter()
        .filter_map(|m| find(m.column()).map(|k| (m, k)))
        .collect();
    if measured.is_empty() {
        return Err(format!(
            "no measured column: give one or more of {}",
            Measured::ALL.map(Measured::column).join(", ")
        ));
    }
    Ok(Columns {
        inputs: Input::ALL
            .into_iter()
            .filter_map(|i| find(input_column(i)).map(|k| (i, k)))
            .collect(),
        semi_axes,
        curvatures,
        measured,
        weight: find(WEIGHT),
    })
}

/// The number in column `k` of a row (finite).
fn number(cells: &[&str], k: usize, name: &str) -> Result<f64, String> {
    let text = cells
        .get(k)
        .copied()
        .filter(|t| !t.is_empty())
        .ok_or_else(|| format!("no value in column {name}"))?;
    let x: f64 = text
        .parse()
        .map_err(|_| format!("{name} {text:?} is not a number"))?;
    if !x.is_finite() {
        return Err(format!("{name} {text} is not a finite number"));
    }
    Ok(x)
}

/// One data row: the base point and parameters supply what the columns do not give.
fn row(
    cells: &[&str],
    width: usize,
    cols: &Columns,
    base: &OperatingPoint,
    params: &Params,
) -> Result<(OperatingPoint, RowGeometry, Vec<f64>, f64), String> {
    if cells.len() != width {
        return Err(format!("{} values for {width} columns", cells.len()));
    }
    let mut point = *base;
    for &(i, k) in &cols.inputs {
        point.set(i, number(cells, k, input_column(i))?);
    }
    point.validate().map_err(|e| e.to_string())?;
    let geometry = match (cols.semi_axes, cols.curvatures) {
        (Some([a, b]), _) => RowGeometry::SemiAxes([
            number(cells, a, SEMI_AXES[0])?,
            number(cells, b, SEMI_AXES[1])?,
        ]),
        (None, Some([a, b])) => RowGeometry::Curvatures([
            number(cells, a, CURVATURES[0])?,
            number(cells, b, CURVATURES[1])?,
        ]),
        (None, None) => RowGeometry::Parameters,
    };
    geometry.of(params).validate().map_err(|e| {
        format!(
            "{e} (semi-axes in {}; the columns are {})",
            SEMI_AXIS_RANGE.bounds(),
            [SEMI_AXES, CURVATURES].concat().join(", ")
        )
    })?;
    let values = cols
        .measured
        .iter()
        .map(|&(m, k)| number(cells, k, m.column()))
        .collect::<Result<Vec<_>, _>>()?;
    let weight = match cols.weight {
        Some(k) => number(cells, k, WEIGHT)?,
        None => 1.0,
    };
    if weight <= 0.0 {
        return Err(format!("weight {weight} must be > 0"));
    }
    Ok((point, geometry, values, weight))
}

/// Reads the measurements of `path`. Columns the file does not give take `base` (the flags' or the
/// default operating point) and the geometry of `params`. Lines may carry `#` comments; blank lines are
/// skipped. Every error names the file and its line.
pub fn read(path: &Path, base: &OperatingPoint, params: &Params) -> Result<Data, FitInputError> {
    let err = |line: Option<usize>, reason: String| {
        FitInputError(match line {
            Some(n) => format!("data file {}, line {n}: {reason}", path.display()),
            None => format!("data file {}: {reason}", path.display()),
        })
    };
    let text = std::fs::read_to_string(path).map_err(|e| err(None, e.to_string()))?;
    // a spreadsheet may begin the file with a byte-order mark
    let mut lines = csv_lines(text.trim_start_matches('\u{feff}'));
    let (header_line, header) = lines
        .next()
        .ok_or_else(|| err(None, "empty: no header line and no measurements".into()))?;
    let header = cells(header);
    let cols = columns(&header).map_err(|r| err(Some(header_line), r))?;
    let mut rows = Vec::new();
    for (n, line) in lines {
        let (point, geometry, values, weight) =
            row(&cells(line), header.len(), &cols, base, params).map_err(|r| err(Some(n), r))?;
        rows.push(Row {
            line: n,
            point,
            geometry,
            values,
            weight,
        });
    }
    if rows.is_empty() {
        return Err(err(
            Some(header_line),
            "no measurements below the header".into(),
        ));
    }
    Ok(Data {
        measured: cols.measured.iter().map(|&(m, _)| m).collect(),
        rows,
    })
}

/// The rows of `data` as curves for warm starts: rows with the same load, speed, wetness and geometry
/// (columns) form a curve, ordered by (ξ, η, φ) so that each solve starts from its neighbour along the swept
/// creepage. Each curve is the list of its rows' indices; the curves are in the order of their first row.
pub fn curves(data: &Data) -> Vec<Vec<usize>> {
    let key = |r: &Row| {
        let p = &r.point;
        let (kind, [a, b]) = match r.geometry {
            RowGeometry::Parameters => (0.0, [0.0; 2]),
            RowGeometry::SemiAxes(axes) => (1.0, axes),
            RowGeometry::Curvatures(c) => (2.0, c),
        };
        [p.normal_force, p.speed, p.wetness, kind, a, b].map(f64::to_bits)
    };
    let mut groups: Vec<([u64; 6], Vec<usize>)> = Vec::new();
    for (k, r) in data.rows.iter().enumerate() {
        let id = key(r);
        match groups.iter_mut().find(|(g, _)| *g == id) {
            Some((_, members)) => members.push(k),
            None => groups.push((id, vec![k])),
        }
    }
    groups
        .into_iter()
        .map(|(_, mut members)| {
            members.sort_by(|&i, &j| {
                let c = |k: usize| {
                    let p = &data.rows[k].point;
                    [p.creepage_x, p.creepage_y, p.spin]
                };
                c(i).partial_cmp(&c(j))
                    .expect("validated inputs are finite")
            });
            members
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read_text(text: &str) -> Result<Data, FitInputError> {
        static FILES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let n = FILES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let path =
            std::env::temp_dir().join(format!("wheelrail-fit-data-{}-{n}.csv", std::process::id()));
        std::fs::write(&path, text).unwrap();
        let d = read(&path, &OperatingPoint::default(), &Params::default());
        let _ = std::fs::remove_file(path);
        d
    }

    #[test]
    fn rows_take_their_columns_and_the_defaults_for_the_rest() {
        let d = read_text(
            "\u{feff}# a roller rig\ncreepage-x,speed,f,force-y,weight\n0.002,10,0.3,-50,2\n\n0.001,10,0.2,-40,1 # low\n",
        )
        .unwrap();
        assert_eq!(
            d.measured,
            [Measured::TractionCoefficient, Measured::ForceY]
        );
        assert_eq!(d.rows.len(), 2);
        let r = &d.rows[0];
        assert_eq!(
            (r.line, r.point.creepage_x, r.point.speed),
            (3, 0.002, 10.0)
        );
        assert_eq!(r.point.normal_force, OperatingPoint::default().normal_force);
        assert_eq!((r.values.clone(), r.weight), (vec![0.3, -50.0], 2.0));
        assert_eq!(r.geometry, RowGeometry::Parameters);
        // without geometry columns the row's contact follows the parameters (a fitted curvature)
        let mut p = Params::default();
        p.geometry.curvature_y = 0.3;
        assert_eq!(r.geometry.of(&p), p.geometry);
        assert_eq!(d.rows[1].line, 5);
        // one curve, ordered by creepage
        assert_eq!(curves(&d), vec![vec![1, 0]]);
    }

    #[test]
    fn geometry_columns_set_the_contact_and_split_the_curves() {
        let d = read_text("creepage-x,semi-axis-a,semi-axis-b,f\n0.001,0.006,0.01,0.2\n0.002,0.006,0.01,0.3\n0.001,0.005,0.01,0.2\n").unwrap();
        assert_eq!(
            d.rows[0].geometry.of(&Params::default()).semi_axes,
            Some([0.006, 0.01])
        );
        assert_eq!(curves(&d), vec![vec![0, 1], vec![2]]);
        let d = read_text("curvature-x,curvature-y,f\n2,3,0.2\n").unwrap();
        let g = d.rows[0].geometry.of(&Params::default());
        assert_eq!(
            (g.curvature_x, g.curvature_y, g.semi_axes),
            (2.0, 3.0, None)
        );
    }

    #[test]
    fn bad_files_name_the_line_or_column() {
        for (text, says) in [
            ("", "empty"),
            ("# only a comment\n", "empty"),
            ("creepage-x,f\n", "line 1: no measurements"),
            ("creepage-x,speed\n0.1,3\n", "line 1: no measured column"),
            (
                "creepage-x,slip,f\n0.1,3,0.2\n",
                "line 1: unknown column \"slip\"",
            ),
            ("f,f\n0.1,0.2\n", "appears twice"),
            (
                "semi-axis-a,f\n0.01,0.2\n",
                "column semi-axis-a needs column semi-axis-b",
            ),
            (
                "semi-axis-a,semi-axis-b,curvature-x,curvature-y,f\n1,1,1,1,1\n",
                "not both",
            ),
            (
                "creepage-x,f\n0.001,0.2\n0.002,NaN\n",
                "line 3: f NaN is not a finite number",
            ),
            (
                "creepage-x,f\n0.001,0.2\n0.002,0.2x\n",
                "line 3: f \"0.2x\" is not a number",
            ),
            (
                "creepage-x,f\n0.001,inf\n",
                "line 2: f inf is not a finite number",
            ),
            ("creepage-x,f\n0.001\n", "line 2: 1 values for 2 columns"),
            (
                "creepage-x,f\n,0.2\n",
                "line 2: no value in column creepage-x",
            ),
            (
                "creepage-x,f\n2.5,0.2\n",
                "line 2: invalid value for creepage-x: 2.5",
            ),
            (
                "creepage-x,f,weight\n0.001,0.2,0\n",
                "line 2: weight 0 must be > 0",
            ),
            (
                "semi-axis-a,semi-axis-b,f\n2,0.01,0.2\n",
                "line 2: invalid value for geometry.semi_axes[0]",
            ),
        ] {
            let e = read_text(text).unwrap_err().to_string();
            assert!(e.contains(says), "{text:?}: {e}");
            assert!(e.starts_with("data file "), "{e}");
        }
    }
}
