//! The computation of each figure: which operating points, which outputs, which axes.
//!
//! Conditions are the paper's Table 1 (UIC60/S1002 running surface, Hertz mapped to a parabola, F_N = 100 kN,
//! V = 30 m/s, k_r = 0.5, water ξ_f = 0.012 Pa·s, k_wet = 0.4, ψ_b = 0.9995) unless a figure varies them.
//! "Water" is a flooded inlet (wetness 1, docs/model.md §8). The boundary-lubricated ("BL") curves of Figs. 17
//! and 21 use a film just thick enough to apply k_wet fully (h_f0 = 1.2·h_bl, docs/model.md §5): it fits into
//! the asperity voids, so no fluid pressure builds and the contact stays boundary lubricated (the CSV
//! reports the mixed-lubrication share to show where it does).

use super::fmax::{solve_converged, traction_maximum};
use super::{Figure, FigureId, Plot, Progress, Settings, Table};
use crate::plot::Series;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use wheelrail::contact::ContactGrid;
use wheelrail::error::{Error, Result, Stage};
use wheelrail::fluid::{Regime, base_height};
use wheelrail::microcontact::{Microcontact, contact_probability};
use wheelrail::params::{OperatingPoint, Params};
use wheelrail::solver::{Fields, Solution, normal_contact};

/// Inlet film of the boundary-lubricated curves in units of h_bl (see [`boundary_lubrication_wetness`]).
const BL_FILM: f64 = 1.2;
/// Speed of the "V → 0" curve of Fig. 14 [m/s].
const CREEP_SPEED: f64 = 0.01;
/// Rolling speeds of Figs. 16 and 17 [m/s].
const SPEEDS: [f64; 8] = [0.1, 1.0, 5.0, 10.0, 20.0, 30.0, 45.0, 60.0];
/// Roughness parameters of Figs. 18 and 19 and of Fig. 5's sweep step.
const ROUGHNESSES: [f64; 6] = [0.0, 0.2, 0.4, 0.6, 0.8, 1.0];
/// Speeds of the curves of Figs. 18 and 19 [m/s].
const CURVE_SPEEDS: [f64; 4] = [1.0, 10.0, 30.0, 60.0];
/// Roughness parameters of the curves of Figs. 16, 17, 20 and 21.
const CURVE_ROUGHNESSES: [f64; 3] = [0.0, 0.5, 1.0];
/// Normal loads of Figs. 20 and 21 [N].
const LOADS: [f64; 6] = [25e3, 50e3, 75e3, 100e3, 150e3, 200e3];
/// Speeds of the traction–creepage curves of Fig. 15 [m/s].
const FIG15_SPEEDS: [f64; 2] = [3.0, 30.0];
/// Creepages of Fig. 15 [-].
const FIG15_CREEPAGES: [f64; 22] = [
    0.0005, 0.001, 0.002, 0.003, 0.005, 0.0075, 0.01, 0.015, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07,
    0.08, 0.09, 0.10, 0.12, 0.14, 0.16, 0.18, 0.20,
];

const MM: f64 = 1e3;
const UM: f64 = 1e6;
const MPA: f64 = 1e-6;

/// Formats a number for the CSV (shortest representation that round-trips).
fn num(v: f64) -> String {
    format!("{v}")
}

/// Formats a quantity the law may not model: empty when absent.
fn known(v: Option<f64>) -> String {
    v.map_or_else(String::new, num)
}

/// A creepage in per cent for the CSV, rounded to 1e-9 % (no binary noise like 7.000000000000001).
fn percent(xi: f64) -> String {
    num((xi * 100.0 * 1e9).round() / 1e9)
}

pub(super) fn compute(id: FigureId, s: &Settings, progress: Progress) -> Result<Figure> {
    use FigureId::*;
    let mut fig = match id {
        Fig5 => fig5(s),
        Fig7 => fig7(s),
        Fig10 => fig10(s),
        Fig11 => fig11(s),
        Fig12 => fig12(s),
        Fig13 => fig13(s),
        Fig14 => fig14(s),
        Fig15 => fig15(s, progress),
        Fig16 | Fig17 | Fig18 | Fig19 | Fig20 | Fig21 => match study(id) {
            Some(st) => fmax_study(&st, s, progress),
            None => Err(Error::OutOfRange {
                name: "figure".into(),
                value: id.to_string(),
                allowed: "an f_max figure (16 ..= 21)".into(),
            }),
        },
    }?;
    fig.title = match id {
        // microcontact only: no contact grid involved
        Fig5 | Fig7 => format!("{id}: {}", fig.title),
        _ => format!(
            "{id}: {} (grid {}×{})",
            fig.title, s.params.grid.nx, s.params.grid.ny
        ),
    };
    Ok(fig)
}

fn lines(x_label: &str, y_label: &str, series: Vec<Series>) -> Plot {
    Plot::Lines {
        x_label: x_label.into(),
        y_label: y_label.into(),
        series,
    }
}

/// Fig. 5: the metallic area ratio A_m/A_n and the separation d/z_s against k_r at the bulk temperature,
/// for a constant nominal pressure: the centre pressure of the Table-1 contact, 2F_N/(π·a·b).
fn fig5(s: &Settings) -> Result<Figure> {
    let p = &s.params;
    let p_n = normal_contact(p, OperatingPoint::default().normal_force)?.parabolic_peak();
    let mat = p.material.at(p.material.bulk_temperature);
    let mut rows = Vec::new();
    let (mut area, mut sep) = (Vec::new(), Vec::new());
    for k in 0..=20 {
        let mut r = p.roughness.clone();
        r.k_r = k as f64 / 20.0;
        let sol = Microcontact::new(&r)?.separation_for_load(p_n, &mat)?;
        if !sol.converged {
            return Err(Error::Numerical {
                stage: Stage::Reproduction,
                reason: format!("separation at k_r = {} did not converge", r.k_r),
            });
        }
        let d_over = sol.state.separation / r.z_s();
        area.push((r.k_r, sol.state.area_fraction));
        sep.push((r.k_r, d_over));
        rows.push(vec![
            num(r.k_r),
            num(r.z_s() * UM),
            num(r.r_a() * UM),
            num(p_n * MPA),
            num(sol.state.area_fraction),
            num(d_over),
        ]);
    }
    Ok(Figure {
        id: FigureId::Fig5,
        title: format!(
            "A_m/A_n and d/z_s against k_r, p_n = {:.0} MPa, {:.0} °C",
            p_n * MPA,
            p.material.bulk_temperature - wheelrail::params::CELSIUS_ZERO
        ),
        table: Table {
            columns: [
                "k_r",
                "z_s_um",
                "R_a_um",
                "nominal_pressure_MPa",
                "area_fraction",
                "separation_over_z_s",
            ]
            .map(String::from)
            .to_vec(),
            rows,
        },
        plot: lines(
            "roughness parameter k_r [-]",
            "A_m/A_n [-],  d/z_s [-]",
            vec![
                Series {
                    label: "A_m/A_n".into(),
                    points: area,
                },
                Series {
                    label: "d/z_s".into(),
                    points: sep,
                },
            ],
        ),
    })
}

/// Fig. 7: surface-fraction curves A_m,z/A_n = ψ(z) = ½·erfc(z/(√2·z_s)) (P5, P9) of a smooth (k_r = 0), a
/// medium (0.5) and a rough (1) surface against the height z above the mean plane of the asperity summits.
fn fig7(s: &Settings) -> Result<Figure> {
    let kr = [0.0, 0.5, 1.0];
    let surfaces: Vec<(f64, f64)> = kr
        .iter()
        .map(|&k| {
            let mut r = s.params.roughness.clone();
            r.k_r = k;
            (k, r.z_s())
        })
        .collect();
    let z_max = 4.0 * surfaces.iter().map(|x| x.1).fold(0.0, f64::max);
    let n = 120;
    let zs: Vec<f64> = (0..=n)
        .map(|i| -z_max + 2.0 * z_max * i as f64 / n as f64)
        .collect();
    let psi = contact_probability;
    let mut columns = vec!["z_um".to_string()];
    columns.extend(kr.iter().map(|k| format!("surface_fraction_k_r_{k}")));
    let rows = zs
        .iter()
        .map(|&z| {
            std::iter::once(num(z * UM))
                .chain(surfaces.iter().map(|(_, z_s)| num(psi(z, *z_s))))
                .collect()
        })
        .collect();
    let series = surfaces
        .iter()
        .map(|&(k, z_s)| Series {
            label: format!(
                "{} k_r = {k} (z_s = {:.1} µm, d_b = {:.1} µm)",
                match k {
                    0.0 => "smooth,",
                    1.0 => "rough,",
                    _ => "",
                },
                z_s * UM,
                base_height(z_s, s.params.fluid.psi_b) * UM
            )
            .trim()
            .to_string(),
            points: zs.iter().map(|&z| (z * UM, psi(z, z_s))).collect(),
        })
        .collect();
    Ok(Figure {
        id: FigureId::Fig7,
        title: "surface fraction A_m,z/A_n of smooth and rough surfaces".into(),
        table: Table { columns, rows },
        plot: lines(
            "height z above the mean summit plane [µm]",
            "A_m,z/A_n [-]",
            series,
        ),
    })
}

/// The pure-rolling solution at speed V [m/s] and wetness w of Table 1 (Figs. 10–14).
fn rolling(s: &Settings, speed: f64, wetness: f64) -> Result<Solution> {
    solve_converged(
        &s.params,
        &OperatingPoint {
            speed,
            wetness,
            ..Default::default()
        },
    )
}

fn fields(sol: &Solution) -> &Fields {
    // the Tomberger law always returns local fields
    sol.fields
        .as_ref()
        .expect("local fields of the exact model")
}

/// The strip nearest y = 0, leading cell first: its y [m] and cell indices.
pub(super) fn centre_strip(grid: &ContactGrid) -> (f64, Vec<usize>) {
    let strip = grid
        .strips
        .iter()
        .min_by(|a, b| a.y.abs().total_cmp(&b.y.abs()))
        .expect("a contact grid has strips");
    (strip.y, strip.cells.clone().collect())
}

/// The x [mm] of the cells of the centre strip and its y [mm].
fn centre_x(f: &Fields) -> (f64, Vec<usize>, Vec<f64>) {
    let (y, cells) = centre_strip(&f.grid);
    let xs = cells.iter().map(|&k| f.grid.cells[k].x * MM).collect();
    (y * MM, cells, xs)
}

fn curve(label: &str, xs: &[f64], cells: &[usize], values: &[f64], scale: f64) -> Series {
    Series {
        label: label.into(),
        points: xs
            .iter()
            .zip(cells)
            .map(|(x, &k)| (*x, values[k] * scale))
            .collect(),
    }
}

/// Fig. 10: available cell height l_c − l_m and fluid height l_f along the centre line, pure rolling, water,
/// 30 m/s; a vertical line marks where the boundary-lubricated (BL) outlet region begins.
fn fig10(s: &Settings) -> Result<Figure> {
    let sol = rolling(s, 30.0, 1.0)?;
    let f = fields(&sol);
    let (y, cells, xs) = centre_x(f);
    let void: Vec<f64> = f
        .cell_height
        .iter()
        .zip(&f.metal_height)
        .map(|(c, m)| c - m)
        .collect();
    let rows = cells
        .iter()
        .zip(&xs)
        .map(|(&k, x)| {
            vec![
                num(*x),
                num(void[k] * UM),
                num(f.fluid_height[k] * UM),
                num(f.cell_height[k] * UM),
                num(f.metal_height[k] * UM),
                num(f.fluid_pressure[k] * MPA),
                format!("{:?}", f.regime[k]).to_lowercase(),
            ]
        })
        .collect();
    let mut series = vec![
        curve("l_c − l_m (available cell height)", &xs, &cells, &void, UM),
        curve("l_f (fluid height)", &xs, &cells, &f.fluid_height, UM),
    ];
    // BL region: downstream of the last mixed-lubricated cell of the strip
    if let Some(last_mixed) = cells.iter().rposition(|&k| f.regime[k] == Regime::Mixed)
        && last_mixed + 1 < cells.len()
    {
        let x_bl = xs[last_mixed] - 0.5 * f.grid.hx * MM;
        let top = void.iter().cloned().fold(0.0, f64::max) * UM;
        series.push(Series {
            label: format!("start of BL (x < {x_bl:.2} mm)"),
            points: vec![(x_bl, 0.0), (x_bl, top)],
        });
    }
    Ok(Figure {
        id: FigureId::Fig10,
        title: format!("l_c − l_m and l_f at y = {y:.2} mm, pure rolling, water, 30 m/s"),
        table: Table {
            columns: [
                "x_mm",
                "void_height_um",
                "fluid_height_um",
                "cell_height_um",
                "metal_height_um",
                "fluid_pressure_MPa",
                "regime",
            ]
            .map(String::from)
            .to_vec(),
            rows,
        },
        plot: lines("x [mm] (inlet at +a, outlet at −a)", "height [µm]", series),
    })
}

/// A map figure (Figs. 11, 12): the plotted field in `unit` and extra CSV columns, per cell.
fn map_figure(
    id: FigureId,
    title: &str,
    f: &Fields,
    plotted: (&str, Vec<f64>),
    extra: Vec<(&str, Vec<f64>)>,
) -> Figure {
    let (unit, values) = plotted;
    let mut columns = vec!["x_mm".to_string(), "y_mm".to_string()];
    columns.extend(extra.iter().map(|c| c.0.to_string()));
    columns.push("regime".into());
    let rows = f
        .grid
        .cells
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let mut r = vec![num(c.x * MM), num(c.y * MM)];
            r.extend(extra.iter().map(|col| num(col.1[k])));
            r.push(format!("{:?}", f.regime[k]).to_lowercase());
            r
        })
        .collect();
    Figure {
        id,
        title: title.into(),
        table: Table { columns, rows },
        plot: Plot::Map {
            unit: unit.into(),
            grid: f.grid.clone(),
            values,
        },
    }
}

fn scaled(v: &[f64], s: f64) -> Vec<f64> {
    v.iter().map(|x| x * s).collect()
}

/// Fig. 11: fluid pressure p_f over the contact, pure rolling, water, 30 m/s.
fn fig11(s: &Settings) -> Result<Figure> {
    let sol = rolling(s, 30.0, 1.0)?;
    let f = fields(&sol);
    let pf = scaled(&f.fluid_pressure, MPA);
    Ok(map_figure(
        FigureId::Fig11,
        "fluid pressure p_f, pure rolling, water, 30 m/s",
        f,
        ("p_f [MPa]", pf.clone()),
        vec![
            ("fluid_pressure_MPa", pf),
            ("nominal_pressure_MPa", scaled(&f.nominal_pressure, MPA)),
        ],
    ))
}

/// Fig. 12: metallic pressure over the contact, pure rolling, water, 30 m/s. Plotted is the nominal metallic
/// pressure p_m·A_m/A_n (the share of p_n the asperities carry, P17); the CSV also has p_m on the real area.
fn fig12(s: &Settings) -> Result<Figure> {
    let sol = rolling(s, 30.0, 1.0)?;
    let f = fields(&sol);
    let pm = scaled(&f.nominal_metal_pressure, MPA);
    Ok(map_figure(
        FigureId::Fig12,
        "nominal metallic pressure, pure rolling, water, 30 m/s",
        f,
        ("p_m·A_m/A_n [MPa]", pm.clone()),
        vec![
            ("nominal_metal_pressure_MPa", pm),
            ("metal_pressure_MPa", scaled(&f.metal_pressure, MPA)),
            ("nominal_pressure_MPa", scaled(&f.nominal_pressure, MPA)),
            ("area_fraction", f.area_fraction.clone()),
        ],
    ))
}

/// Fig. 13: A_m/A_n and the local friction coefficient μ (P1) along the centre line, pure rolling, water,
/// 30 m/s.
fn fig13(s: &Settings) -> Result<Figure> {
    let sol = rolling(s, 30.0, 1.0)?;
    let f = fields(&sol);
    let (y, cells, xs) = centre_x(f);
    let rows = cells
        .iter()
        .zip(&xs)
        .map(|(&k, x)| {
            vec![
                num(*x),
                num(f.area_fraction[k]),
                num(f.friction_coefficient[k]),
                num(f.nominal_metal_pressure[k] * MPA),
                num(f.nominal_pressure[k] * MPA),
                format!("{:?}", f.regime[k]).to_lowercase(),
            ]
        })
        .collect();
    Ok(Figure {
        id: FigureId::Fig13,
        title: format!("A_m/A_n and μ at y = {y:.2} mm, pure rolling, water, 30 m/s"),
        table: Table {
            columns: [
                "x_mm",
                "area_fraction",
                "friction_coefficient",
                "nominal_metal_pressure_MPa",
                "nominal_pressure_MPa",
                "regime",
            ]
            .map(String::from)
            .to_vec(),
            rows,
        },
        plot: lines(
            "x [mm] (inlet at +a, outlet at −a)",
            "A_m/A_n [-],  μ [-]",
            vec![
                curve("A_m/A_n", &xs, &cells, &f.area_fraction, 1.0),
                curve("μ", &xs, &cells, &f.friction_coefficient, 1.0),
            ],
        ),
    })
}

/// Fig. 14: tangential adhesion limit τ_l (P6) along the centre line in pure rolling with water at 30 m/s and
/// at V → 0 (0.01 m/s), and dry at 30 m/s for reference.
fn fig14(s: &Settings) -> Result<Figure> {
    let cases = [
        ("water, V = 30 m/s", 30.0, 1.0),
        ("water, V → 0 (0.01 m/s)", CREEP_SPEED, 1.0),
        ("dry, V = 30 m/s (reference)", 30.0, 0.0),
    ];
    let sols = cases
        .par_iter()
        .map(|(_, v, w)| rolling(s, *v, *w))
        .collect::<Result<Vec<_>>>()?;
    let f0 = fields(&sols[0]);
    let (y, cells, xs) = centre_x(f0);
    let mut columns = vec!["x_mm".to_string()];
    columns.extend(
        [
            "adhesion_limit_water_30_MPa",
            "adhesion_limit_water_0_01_MPa",
            "adhesion_limit_dry_30_MPa",
            "regime_water_30",
            "regime_water_0_01",
        ]
        .map(String::from),
    );
    let rows = cells
        .iter()
        .zip(&xs)
        .map(|(&k, x)| {
            let mut r = vec![num(*x)];
            r.extend(
                sols.iter()
                    .map(|sol| num(fields(sol).adhesion_limit[k] * MPA)),
            );
            r.extend(
                sols[..2]
                    .iter()
                    .map(|sol| format!("{:?}", fields(sol).regime[k]).to_lowercase()),
            );
            r
        })
        .collect();
    let series = cases
        .iter()
        .zip(&sols)
        .map(|((label, _, _), sol)| curve(label, &xs, &cells, &fields(sol).adhesion_limit, MPA))
        .collect();
    Ok(Figure {
        id: FigureId::Fig14,
        title: format!("adhesion limit τ_l at y = {y:.2} mm, pure rolling"),
        table: Table { columns, rows },
        plot: lines("x [mm] (inlet at +a, outlet at −a)", "τ_l [MPa]", series),
    })
}

/// Wetness of the boundary-lubricated ("BL") curves of Figs. 17 and 21: inlet film h_f0 = 1.2·h_bl. The film
/// is carried through the contact at the mean speed, so a cell holds l_f = h_f0·v_r/v_m = h_f0·(1 − ξ/2)
/// (docs/model.md §8): with 1.2·h_bl every cell keeps l_f ≥ h_bl, hence the full k_wet (docs/model.md §5), up to
/// ξ = 1/3, while the film is thin enough to fit into the asperity voids of the Table-1 contact, so that no
/// fluid pressure builds (above about 120 kN some centre cells fill and carry a little pressure).
pub fn boundary_lubrication_wetness(p: &Params) -> f64 {
    (BL_FILM * p.fluid.h_bl / p.fluid.h_f_max).min(1.0)
}

/// Dry contact, flooded inlet (water), or a film that only boundary-lubricates.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Film {
    Dry,
    Water,
    Boundary,
}

impl Film {
    fn wetness(self, p: &Params) -> f64 {
        match self {
            Film::Dry => 0.0,
            Film::Water => 1.0,
            Film::Boundary => boundary_lubrication_wetness(p),
        }
    }

    fn name(self) -> &'static str {
        match self {
            Film::Dry => "dry",
            Film::Water => "water",
            Film::Boundary => "water BL",
        }
    }
}

/// Fig. 15: traction–creepage curves, dry and water, at a low and a high speed.
fn fig15(s: &Settings, progress: Progress) -> Result<Figure> {
    let cases: Vec<(Film, f64)> = [Film::Dry, Film::Water]
        .into_iter()
        .flat_map(|f| FIG15_SPEEDS.map(|v| (f, v)))
        .collect();
    let jobs: Vec<(usize, f64)> = (0..cases.len())
        .flat_map(|c| FIG15_CREEPAGES.map(|x| (c, x)))
        .collect();
    let done = AtomicUsize::new(0);
    let sols = jobs
        .par_iter()
        .map(|&(c, xi)| {
            let (film, speed) = cases[c];
            let sol = solve_converged(
                &s.params,
                &OperatingPoint {
                    creepage_x: xi,
                    speed,
                    wetness: film.wetness(&s.params),
                    ..Default::default()
                },
            )?;
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            progress(&format!(
                "Fig. 15: {n}/{} points ({}, V = {speed} m/s, ξ = {xi}: f = {:.4})",
                jobs.len(),
                film.name(),
                sol.global.traction_coefficient
            ));
            Ok(sol)
        })
        .collect::<Result<Vec<_>>>()?;
    let label = |(film, v): (Film, f64)| format!("{}, V = {v} m/s", film.name());
    let mut series: Vec<Series> = cases
        .iter()
        .map(|c| Series {
            label: label(*c),
            points: vec![],
        })
        .collect();
    let mut rows = Vec::new();
    for (&(c, xi), sol) in jobs.iter().zip(&sols) {
        let g = &sol.global;
        series[c].points.push((xi * 100.0, g.traction_coefficient));
        rows.push(vec![
            label(cases[c]),
            num(cases[c].1),
            num(cases[c].0.wetness(&s.params)),
            percent(xi),
            num(g.traction_coefficient),
            known(g.max_temperature),
            known(g.fluid_load_fraction),
            known(g.mixed_lubrication_area_fraction),
        ]);
    }
    Ok(Figure {
        id: FigureId::Fig15,
        title: "traction–creepage curves, dry and water".into(),
        table: Table {
            columns: [
                "curve",
                "speed_m_s",
                "wetness",
                "creepage_percent",
                "traction_coefficient",
                "max_temperature_K",
                "fluid_load_fraction",
                "mixed_lubrication_area_fraction",
            ]
            .map(String::from)
            .to_vec(),
            rows,
        },
        plot: lines(
            "longitudinal creepage ξ [%]",
            "traction coefficient f [-]",
            series,
        ),
    })
}

/// A quantity varied along an f_max figure's axis or between its curves.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Var {
    /// Rolling speed V [m/s].
    Speed,
    /// Roughness parameter k_r [-].
    Roughness,
    /// Normal force F_N [N] (shown in kN).
    Load,
}

impl Var {
    fn apply(self, p: &mut Params, pt: &mut OperatingPoint, v: f64) {
        match self {
            Var::Speed => pt.speed = v,
            Var::Roughness => p.roughness.k_r = v,
            Var::Load => pt.normal_force = v,
        }
    }
    /// The value in display units (kN for the load).
    fn shown(self, v: f64) -> f64 {
        match self {
            Var::Load => v * 1e-3,
            _ => v,
        }
    }
    fn column(self) -> &'static str {
        match self {
            Var::Speed => "speed_m_s",
            Var::Roughness => "k_r",
            Var::Load => "normal_force_kN",
        }
    }
    fn axis(self) -> &'static str {
        match self {
            Var::Speed => "rolling velocity v_rx [m/s]",
            Var::Roughness => "roughness parameter k_r [-]",
            Var::Load => "normal load F_N [kN]",
        }
    }
    fn label(self, v: f64) -> String {
        match self {
            Var::Speed => format!("V = {v} m/s"),
            Var::Roughness => format!("k_r = {v}"),
            Var::Load => format!("F_N = {} kN", v * 1e-3),
        }
    }
}

/// One curve of an f_max figure: the value of the curve variable and the film.
struct Curve {
    value: f64,
    film: Film,
}

/// An f_max figure: f_max against `x` for each curve.
struct Study {
    id: FigureId,
    title: &'static str,
    x: Var,
    xs: Vec<f64>,
    by: Var,
    curves: Vec<Curve>,
}

fn curves(values: &[f64], film: Film) -> Vec<Curve> {
    values.iter().map(|&value| Curve { value, film }).collect()
}

/// The f_max figure `id` (16–21) and its sweeps; None for the other figures.
fn study(id: FigureId) -> Option<Study> {
    let water_and_bl = |values: &[f64]| {
        // the boundary-lubricated curve at Table 1's roughness
        let mut c = vec![Curve {
            value: wheelrail::params::Roughness::default().k_r,
            film: Film::Boundary,
        }];
        c.extend(curves(values, Film::Water));
        c
    };
    let (title, x, xs, by, curves) = match id {
        FigureId::Fig16 => (
            "f_max against rolling velocity, dry",
            Var::Speed,
            SPEEDS.to_vec(),
            Var::Roughness,
            curves(&CURVE_ROUGHNESSES, Film::Dry),
        ),
        FigureId::Fig17 => (
            "f_max against rolling velocity, water (BL: boundary lubricated)",
            Var::Speed,
            SPEEDS.to_vec(),
            Var::Roughness,
            water_and_bl(&CURVE_ROUGHNESSES),
        ),
        FigureId::Fig18 => (
            "f_max against roughness parameter, dry",
            Var::Roughness,
            ROUGHNESSES.to_vec(),
            Var::Speed,
            curves(&CURVE_SPEEDS, Film::Dry),
        ),
        FigureId::Fig19 => (
            "f_max against roughness parameter, water",
            Var::Roughness,
            ROUGHNESSES.to_vec(),
            Var::Speed,
            curves(&CURVE_SPEEDS, Film::Water),
        ),
        FigureId::Fig20 => (
            "f_max against normal load, dry",
            Var::Load,
            LOADS.to_vec(),
            Var::Roughness,
            curves(&CURVE_ROUGHNESSES, Film::Dry),
        ),
        FigureId::Fig21 => (
            "f_max against normal load, water (BL: boundary lubricated)",
            Var::Load,
            LOADS.to_vec(),
            Var::Roughness,
            water_and_bl(&CURVE_ROUGHNESSES),
        ),
        _ => return None,
    };
    Some(Study {
        id,
        title,
        x,
        xs,
        by,
        curves,
    })
}

/// Computes an f_max figure: one f_max search per (curve, x), all in parallel.
fn fmax_study(st: &Study, s: &Settings, progress: Progress) -> Result<Figure> {
    let jobs: Vec<(usize, f64)> = (0..st.curves.len())
        .flat_map(|c| st.xs.iter().map(move |&x| (c, x)))
        .collect();
    let label = |c: &Curve| match c.film {
        Film::Boundary => format!("{} (BL)", st.by.label(c.value)),
        _ => st.by.label(c.value),
    };
    let done = AtomicUsize::new(0);
    let maxima = jobs
        .par_iter()
        .map(|&(c, x)| {
            let curve = &st.curves[c];
            let mut p = s.params.clone();
            let mut pt = OperatingPoint::default();
            st.by.apply(&mut p, &mut pt, curve.value);
            st.x.apply(&mut p, &mut pt, x);
            pt.wetness = curve.film.wetness(&p);
            let m = traction_maximum(&p, &pt, &s.search)?;
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            progress(&format!(
                "{}: {n}/{} f_max ({}, {}, {}): {:.4} at ξ = {:.2} %",
                st.id,
                jobs.len(),
                curve.film.name(),
                st.by.label(curve.value),
                st.x.label(x),
                m.traction,
                m.creepage * 100.0
            ));
            Ok(m)
        })
        .collect::<Result<Vec<_>>>()?;
    let mut series: Vec<Series> = st
        .curves
        .iter()
        .map(|c| Series {
            label: label(c),
            points: vec![],
        })
        .collect();
    let mut rows = Vec::new();
    for (&(c, x), m) in jobs.iter().zip(&maxima) {
        let curve = &st.curves[c];
        let g = &m.solution.global;
        series[c].points.push((st.x.shown(x), m.traction));
        rows.push(vec![
            label(curve),
            curve.film.name().to_string(),
            num(st.by.shown(curve.value)),
            num(st.x.shown(x)),
            num(m.traction),
            percent(m.creepage),
            m.at_range_end.to_string(),
            known(g.max_temperature),
            known(g.fluid_load_fraction),
            known(g.mixed_lubrication_area_fraction),
            known(g.boundary_lubrication_area_fraction),
            m.evaluations.len().to_string(),
        ]);
    }
    let columns = [
        "curve",
        "film",
        st.by.column(),
        st.x.column(),
        "f_max",
        "creepage_at_max_percent",
        "at_range_end",
        "max_temperature_K",
        "fluid_load_fraction",
        "mixed_lubrication_area_fraction",
        "boundary_lubrication_area_fraction",
        "solves",
    ]
    .map(String::from)
    .to_vec();
    Ok(Figure {
        id: st.id,
        title: st.title.into(),
        table: Table { columns, rows },
        plot: lines(
            st.x.axis(),
            "maximum traction coefficient f_max [-]",
            series,
        ),
    })
}
