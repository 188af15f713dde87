//! Tables and axes for the library's tests.

use super::Table;
use super::axes::{Axes, AxesSpec, AxisSpec, DIMS, XI};
use super::build::tabulate;
use super::file::OUTPUTS;
use crate::params::Params;

/// A table in memory from node values `f(coordinates) -> outputs` (for tests).
pub(crate) fn synthetic(
    axes: &Axes,
    params: &Params,
    f: &dyn Fn(&[f64; DIMS]) -> [f64; OUTPUTS],
) -> Table {
    Table::from_files(tabulate(params, axes, f), None).unwrap()
}

/// Axes with explicit points per dimension (ξ̂, η̂, φ̂, F_N, V, w, a/b, p_ref), ξ̂ mirrored (stored ξ̂ ≥ 0),
/// raw limits of the creepages `raw`.
pub(super) fn explicit_axes(points: [&[f64]; DIMS], raw: [f64; 3]) -> Axes {
    let spec = |d: usize| {
        Some(AxisSpec {
            points: Some(points[d].to_vec()),
            mirrored: (d == XI).then_some(true),
            raw_limit: raw.get(d).copied(),
            ..Default::default()
        })
    };
    Axes::from_spec(&AxesSpec {
        creepage_x: spec(0),
        creepage_y: spec(1),
        spin: spec(2),
        normal_force: spec(3),
        speed: spec(4),
        wetness: spec(5),
        semi_axis_ratio: spec(6),
        reference_pressure: spec(7),
    })
    .expect("valid axes")
}

/// The axes of the small test table `tests/fixtures/small-axes.toml` (1152 points around the default
/// operating point and contact), which the FMU's and the command line's tests and benchmarks read from the
/// file.
pub(crate) fn small_axes() -> Axes {
    let spec: AxesSpec = toml::from_str(include_str!("../../tests/fixtures/small-axes.toml"))
        .expect("the fixture is an axes file");
    Axes::from_spec(&spec).expect("valid axes")
}

/// The default parameters on a coarse 6 × 6 grid: a table over [`tiny_axes`] builds in a fraction of a
/// second.
pub(crate) fn coarse_params() -> Params {
    let mut p = Params::default();
    p.grid.nx = 6;
    p.grid.ny = 6;
    p
}

/// Small valid axes (3·3·4·2·2·2·2·2 = 1152 points) around the default contact (a/b ≈ 0.56, p_ref ≈
/// 0.77 GPa), wider than [`small_axes`]: ξ̂ ≤ 10 (|ξ| up to about 5 %), η̂ ≤ 4 (|η| ≤ 2 %), |φ̂| ≤ 0.5
/// (|φ| up to about 1.4 /m).
pub(crate) fn tiny_axes() -> Axes {
    explicit_axes(
        [
            &[0.0, 1.0, 10.0],
            &[0.0, 0.6, 4.0],
            &[-0.5, -0.1, 0.1, 0.5],
            &[50e3, 100e3],
            &[10.0, 30.0],
            &[0.0, 1.0],
            &[0.5, 0.6],
            &[0.7e9, 0.85e9],
        ],
        [0.1, 0.03, 2.0],
    )
}
