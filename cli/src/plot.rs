//! Plots for the CLI and the reports: line charts (traction–creepage curves) and heat maps of contact fields,
//! as PNG or SVG by file extension. The font is compiled in (DejaVu Sans), so nothing depends on fontconfig.

use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use std::path::Path;
use std::sync::Once;
use wheelrail::contact::ContactGrid;

static FONT: Once = Once::new();

fn ensure_font() {
    FONT.call_once(|| {
        // the bundled font is a valid TrueType file; failure would only mean missing labels
        let _ = register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../../assets/DejaVuSans.ttf"),
        );
    });
}

/// One named curve of a line chart.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points (x, y).
    pub points: Vec<(f64, f64)>,
}

/// Axis and title texts of a chart.
#[derive(Debug, Clone)]
pub struct Chart<'a> {
    /// Title above the plot.
    pub title: &'a str,
    /// x-axis label with unit.
    pub x_label: &'a str,
    /// y-axis label with unit.
    pub y_label: &'a str,
}

fn plot_err<E: std::fmt::Display>(e: E) -> anyhow::Error {
    anyhow::anyhow!("plot: {e}")
}

fn finite_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-12 * hi.abs().max(1.0));
    (lo - pad, hi + pad)
}

/// Draws the series as a line chart into `path` (.png or .svg).
pub fn line_chart(path: &Path, chart: &Chart, series: &[Series]) -> anyhow::Result<()> {
    data_and_lines_chart(path, chart, &[], series)
}

/// Draws `points` as markers and `lines` as lines into `path` (.png or .svg): the k-th series of each
/// in the same colour (measurements and the model fitted to them), labelled once.
pub fn data_and_lines_chart(
    path: &Path,
    chart: &Chart,
    points: &[Series],
    lines: &[Series],
) -> anyhow::Result<()> {
    ensure_font();
    let svg = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    if svg {
        let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
        draw(root, chart, points, lines)
    } else {
        let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
        draw(root, chart, points, lines)
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    chart: &Chart,
    points: &[Series],
    lines: &[Series],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(plot_err)?;
    let all = || points.iter().chain(lines).flat_map(|s| s.points.iter());
    let (x0, x1) = finite_range(all().map(|p| p.0));
    let (y0, y1) = finite_range(all().map(|p| p.1));
    let mut ctx = ChartBuilder::on(&root)
        .caption(chart.title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(plot_err)?;
    ctx.configure_mesh()
        .x_desc(chart.x_label)
        .y_desc(chart.y_label)
        .label_style(("sans-serif", 15))
        .draw()
        .map_err(plot_err)?;
    for (k, s) in points.iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        ctx.draw_series(
            s.points
                .iter()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .map(|&p| Circle::new(p, 4, color.filled())),
        )
        .map_err(plot_err)?;
    }
    for (k, s) in lines.iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        ctx.draw_series(LineSeries::new(
            s.points.iter().cloned().filter(|p| p.1.is_finite()),
            color.stroke_width(2),
        ))
        .map_err(plot_err)?
        .label(s.label.clone())
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
    }
    if lines.len() > 1 || lines.iter().any(|s| !s.label.is_empty()) {
        ctx.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 15))
            .draw()
            .map_err(plot_err)?;
    }
    root.present().map_err(plot_err)?;
    Ok(())
}

/// Draws a heat map of one value per active cell of `grid` into `path` (.png or .svg), x along the
/// rolling direction (leading edge right), with a colour bar from the minimum to the maximum.
pub fn heat_map(
    path: &Path,
    title: &str,
    unit: &str,
    grid: &ContactGrid,
    values: &[f64],
) -> anyhow::Result<()> {
    ensure_font();
    let svg = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    if svg {
        let root = SVGBackend::new(path, (800, 700)).into_drawing_area();
        draw_map(root, title, unit, grid, values)
    } else {
        let root = BitMapBackend::new(path, (800, 700)).into_drawing_area();
        draw_map(root, title, unit, grid, values)
    }
}

fn colour(t: f64) -> RGBColor {
    // a perceptually ordered blue → yellow → red ramp
    let t = t.clamp(0.0, 1.0);
    let (r, g, b) = if t < 0.5 {
        let s = t / 0.5;
        (40.0 + 215.0 * s, 60.0 + 170.0 * s, 200.0 - 150.0 * s)
    } else {
        let s = (t - 0.5) / 0.5;
        (255.0, 230.0 - 200.0 * s, 50.0 - 30.0 * s)
    };
    RGBColor(r as u8, g as u8, b as u8)
}

fn draw_map<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    unit: &str,
    grid: &ContactGrid,
    values: &[f64],
) -> anyhow::Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(plot_err)?;
    let (main, bar) = root.split_horizontally(680);
    let (lo, hi) = finite_range(values.iter().cloned());
    let span = (hi - lo).max(f64::MIN_POSITIVE);
    let mm = 1e3;
    let mut ctx = ChartBuilder::on(&main)
        .caption(title, ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(-grid.a * mm..grid.a * mm, -grid.b * mm..grid.b * mm)
        .map_err(plot_err)?;
    ctx.configure_mesh()
        .x_desc("x [mm] (rolling direction, inlet at right)")
        .y_desc("y [mm]")
        .label_style(("sans-serif", 14))
        .disable_mesh()
        .draw()
        .map_err(plot_err)?;
    let (hx, hy) = (grid.hx * mm / 2.0, grid.hy * mm / 2.0);
    ctx.draw_series(grid.cells.iter().zip(values).map(|(c, v)| {
        let (x, y) = (c.x * mm, c.y * mm);
        let col = if v.is_finite() {
            colour((v - lo) / span)
        } else {
            RGBColor(200, 200, 200)
        };
        Rectangle::new([(x - hx, y - hy), (x + hx, y + hy)], col.filled())
    }))
    .map_err(plot_err)?;
    let mut cb = ChartBuilder::on(&bar)
        .margin_top(50)
        .margin_bottom(60)
        .margin_right(60)
        .y_label_area_size(0)
        .right_y_label_area_size(55)
        .caption(unit, ("sans-serif", 14))
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(plot_err)?;
    cb.configure_mesh()
        .disable_x_axis()
        .disable_mesh()
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(plot_err)?;
    let steps = 100;
    cb.draw_series((0..steps).map(|k| {
        let v0 = lo + span * k as f64 / steps as f64;
        let v1 = lo + span * (k + 1) as f64 / steps as f64;
        Rectangle::new(
            [(0.0, v0), (1.0, v1)],
            colour((k as f64 + 0.5) / steps as f64).filled(),
        )
    }))
    .map_err(plot_err)?;
    root.present().map_err(plot_err)?;
    Ok(())
}
