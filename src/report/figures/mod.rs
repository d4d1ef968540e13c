//! Figures with plotters: PNG and SVG, text rendered from an embedded DejaVu Sans (no system font
//! libraries; the font's licence is in `src/report/figures/DejaVuSans-LICENSE.txt`).

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;

pub mod field_sweep;
pub mod paper;
pub mod sweep;

use crate::Error;

static FONT: Once = Once::new();

/// Registers the embedded font as "sans-serif" (idempotent).
pub fn register_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("DejaVuSans.ttf");
        // The font is valid; registration only fails for malformed data.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

/// One series of a log-log or lin-log plot: label, points (x, y, optional y error).
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Points (x, y, y-error or 0).
    pub points: Vec<(f64, f64, f64)>,
    /// Optional text next to each point (empty: none).
    pub notes: Vec<String>,
    /// Join the points with a line (otherwise markers only).
    pub line: bool,
}

/// Axes of a simple scientific plot.
pub struct PlotSpec<'a> {
    /// Title.
    pub title: &'a str,
    /// x label.
    pub x_label: &'a str,
    /// y label.
    pub y_label: &'a str,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
}

/// A plotting error while drawing `path` (the backends write the file when the figure is
/// presented, so their errors are I/O errors on that file).
fn io(path: &Path) -> impl Fn(&dyn std::fmt::Display) -> Error + '_ {
    move |e| Error::io("write", path)(std::io::Error::other(e.to_string()))
}

fn range(v: impl Iterator<Item = f64> + Clone, log: bool) -> (f64, f64) {
    let lo = v.clone().fold(f64::INFINITY, f64::min);
    let hi = v.fold(f64::NEG_INFINITY, f64::max);
    if log {
        (lo / 2.0, hi * 2.0)
    } else {
        let pad = 0.08 * (hi - lo).max(1e-12);
        (lo - pad, hi + pad)
    }
}

fn draw<DB: DrawingBackend>(
    path: &Path,
    root: DrawingArea<DB, plotters::coord::Shift>,
    spec: &PlotSpec,
    series: &[Series],
) -> Result<(), Error>
where
    DB::ErrorType: 'static,
{
    let fail = io(path);
    let io = |e: plotters::drawing::DrawingAreaErrorKind<DB::ErrorType>| fail(&e);
    root.fill(&WHITE).map_err(io)?;
    let xs = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
    let ys = series
        .iter()
        .flat_map(|s| s.points.iter().flat_map(|p| [p.1 - p.2, p.1 + p.2]));
    let (x0, x1) = range(xs, spec.log_x);
    let (y0, y1) = range(ys.filter(|y| !spec.log_y || *y > 0.0), spec.log_y);
    let mut b = ChartBuilder::on(&root);
    b.caption(spec.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(80);
    match (spec.log_x, spec.log_y) {
        (true, true) => chart_body(
            &mut b
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(io)?,
            spec,
            series,
            &io,
        )?,
        (true, false) => chart_body(
            &mut b
                .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
                .map_err(io)?,
            spec,
            series,
            &io,
        )?,
        (false, true) => chart_body(
            &mut b
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(io)?,
            spec,
            series,
            &io,
        )?,
        (false, false) => chart_body(
            &mut b.build_cartesian_2d(x0..x1, y0..y1).map_err(io)?,
            spec,
            series,
            &io,
        )?,
    }
    root.present().map_err(io)?;
    Ok(())
}

/// The mesh, every series (line, points or pixels, notes, error bars) and the legend, on a chart
/// of any axis scales.
fn chart_body<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    spec: &PlotSpec,
    series: &[Series],
    io: &dyn Fn(plotters::drawing::DrawingAreaErrorKind<DB::ErrorType>) -> Error,
) -> Result<(), Error>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    X: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc(spec.x_label)
        .y_desc(spec.y_label)
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(io)?;
    for (i, s) in series.iter().enumerate() {
        let c = Palette99::pick(i).to_rgba();
        let joined: Vec<(f64, f64)> = if s.line {
            s.points.iter().map(|p| (p.0, p.1)).collect()
        } else {
            Vec::new()
        };
        chart
            .draw_series(LineSeries::new(joined, c.stroke_width(2)))
            .map_err(io)?
            .label(s.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)));
        if s.line || s.points.len() < 1000 {
            let dots = s
                .points
                .iter()
                .map(|p| Circle::new((p.0, p.1), 3, c.filled()));
            chart.draw_series(dots).map_err(io)?;
        } else {
            // Dense scatter (e.g. Fig. 5): single pixels.
            let pixels = s.points.iter().map(|p| Pixel::new((p.0, p.1), c));
            chart.draw_series(pixels).map_err(io)?;
        }
        let notes = s.points.iter().zip(&s.notes);
        chart
            .draw_series(notes.map(|(p, t)| Text::new(t.clone(), (p.0, p.1), ("sans-serif", 13))))
            .map_err(io)?;
        let bars =
            s.points.iter().filter(|p| p.2 > 0.0).map(|p| {
                ErrorBar::new_vertical(p.0, p.1 - p.2, p.1, p.1 + p.2, c.stroke_width(1), 6)
            });
        chart.draw_series(bars).map_err(io)?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(io)?;
    Ok(())
}

/// Figure size in pixels.
const SIZE: (u32, u32) = (800, 600);

/// Writes `stem.png` and `stem.svg` (800×600). Both are drawn in memory and written by
/// [`crate::files::write`], so a link found where a figure goes is refused, not followed.
pub fn plot(stem: &Path, spec: &PlotSpec, series: &[Series]) -> Result<(), Error> {
    register_font();
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    draw(
        &png,
        BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area(),
        spec,
        series,
    )?;
    let mut encoded = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut encoded),
        &rgb,
        SIZE.0,
        SIZE.1,
        image::ColorType::Rgb8,
    )
    .map_err(|e| Error::io("encode", &png)(std::io::Error::other(e.to_string())))?;
    crate::files::write(&png, encoded)?;
    let mut text = String::new();
    draw(
        &svg,
        SVGBackend::with_string(&mut text, SIZE).into_drawing_area(),
        spec,
        series,
    )?;
    crate::files::write(&svg, text)
}

/// Text for HTML pages (reports, indexes): `&`, `<` and `>` escaped.
///
/// # Examples
///
/// ```
/// assert_eq!(lorentz_gas::report::figures::html_escape("a<b & c"), "a&lt;b &amp; c");
/// ```
pub fn html_escape(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
