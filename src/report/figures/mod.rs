//! Figures with plotters: PNG and SVG, text rendered from an embedded DejaVu Sans (no system font
//! libraries; the font's licence is in `src/report/figures/DejaVuSans-LICENSE.txt`).

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;

pub mod driven_sweep;
pub mod field_sweep;
mod glyphs;
mod legend;
pub mod paper;
pub mod section;
pub mod sweep;

use crate::Error;

static FONT: Once = Once::new();

/// The embedded DejaVu Sans.
const FONT_BYTES: &[u8] = include_bytes!("DejaVuSans.ttf");

/// Registers the embedded font as "sans-serif" (idempotent).
pub fn register_font() {
    FONT.call_once(|| {
        // The font is valid; registration only fails for malformed data.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT_BYTES);
    });
}

pub use glyphs::Glyphs;

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

/// A shaded region under the series: an estimate's error band (`y` = value ± error over `x`)
/// or a window of x over the whole height (`y` = `None`), with its legend label.
pub struct Band {
    /// Legend label.
    pub label: String,
    /// The x extent.
    pub x: (f64, f64),
    /// The y extent, or the whole axis.
    pub y: Option<(f64, f64)>,
}

/// Axes of a simple scientific plot.
#[derive(Default)]
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
    /// Shaded regions drawn under the series.
    pub bands: &'a [Band],
    /// The y axis counts things: integer tick labels only.
    pub count_y: bool,
    /// Bars of this width (x units) for every series not joined by a line: one bar from 0 to
    /// each point's y, centred on its x (a histogram); `None`: markers.
    pub bar_width: Option<f64>,
}

impl<'a> PlotSpec<'a> {
    /// Linear axes with this title and these labels, no bands, real-valued y (set the other
    /// fields with `PlotSpec { log_y: true, ..PlotSpec::new(..) }`).
    pub fn new(title: &'a str, x_label: &'a str, y_label: &'a str) -> Self {
        PlotSpec {
            title,
            x_label,
            y_label,
            ..Default::default()
        }
    }
}

/// A tick label as people write it: integers without ".0", other values to six significant
/// digits without trailing zeros, very large or small ones in scientific notation.
fn tick(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if v.fract() == 0.0 && a < 1e7 {
        format!("{v:.0}")
    } else if (1e-4..1e7).contains(&a) {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.1e}")
    }
}

/// The decimals that write every one of the tick values `keys` exactly (to 10⁻⁹ of their step),
/// so a linear axis labels its ticks alike (0.166, 0.168, 0.170 — not 0.17); `None` where
/// [`tick`]'s own form is better (no ticks, or values beyond 10⁻⁴ … 10⁷).
fn axis_decimals(keys: &[f64]) -> Option<usize> {
    let top = keys.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let step = keys
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min);
    if keys.is_empty() || top >= 1e7 || (step.is_finite() && step < 1e-4) {
        return None;
    }
    let tolerance = if step.is_finite() { step * 1e-9 } else { 1e-12 };
    (0..=6).find(|&d| {
        let scale = 10f64.powi(d as i32);
        keys.iter()
            .all(|v| ((v * scale).round() / scale - v).abs() <= tolerance)
    })
}

/// The tick labels of an axis whose labelled ticks are `keys`: on a linear axis all with the
/// same decimals ([`axis_decimals`]), else each as [`tick`] writes it.
fn tick_labels(keys: &[f64], log: bool) -> impl Fn(&f64) -> String {
    let decimals = if log { None } else { axis_decimals(keys) };
    move |v: &f64| match decimals {
        Some(d) => {
            let s = format!("{v:.d$}");
            // "-0.000" is 0.
            if s.trim_start_matches('-')
                .chars()
                .all(|c| c == '0' || c == '.')
            {
                s.trim_start_matches('-').to_string()
            } else {
                s
            }
        }
        None => tick(*v),
    }
}

/// Labelled ticks per axis (plotters' count of bold mesh lines, each with its label).
const TICKS: usize = 10;

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
    // Bars reach half their width either side of their centre.
    let half = spec.bar_width.unwrap_or(0.0) / 2.0;
    let xs = series
        .iter()
        .flat_map(|s| s.points.iter().flat_map(move |p| [p.0 - half, p.0 + half]));
    let xs = xs.chain(spec.bands.iter().flat_map(|b| [b.x.0, b.x.1]));
    let ys = series
        .iter()
        .flat_map(|s| s.points.iter().flat_map(|p| [p.1 - p.2, p.1 + p.2]));
    let ys = ys.chain(
        spec.bands
            .iter()
            .filter_map(|b| b.y)
            .flat_map(|y| [y.0, y.1]),
    );
    let (x0, x1) = range(xs, spec.log_x);
    let (y0, y1) = range(ys.filter(|y| !spec.log_y || *y > 0.0), spec.log_y);
    // The legend below the axes, off the data.
    let entries = legend::entries(spec, series);
    let (w, h) = root.dim_in_pixel();
    let below = legend::height(&root, &entries, w);
    let (upper, lower) = root.split_vertically(h.saturating_sub(below));
    legend::draw(&lower, &entries, w).map_err(io)?;
    let mut b = ChartBuilder::on(&upper);
    b.caption(spec.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(80);
    // One chart body per pair of scales (each pair is its own coordinate type).
    macro_rules! body_on {
        ($x:expr, $y:expr) => {
            chart_body(
                &mut b.build_cartesian_2d($x, $y).map_err(io)?,
                spec,
                series,
                (y0, y1),
                &io,
            )?
        };
    }
    match (spec.log_x, spec.log_y) {
        (true, true) => body_on!((x0..x1).log_scale(), (y0..y1).log_scale()),
        (true, false) => body_on!((x0..x1).log_scale(), y0..y1),
        (false, true) => body_on!(x0..x1, (y0..y1).log_scale()),
        (false, false) => body_on!(x0..x1, y0..y1),
    }
    root.present().map_err(io)?;
    Ok(())
}

/// An axis of `f64` values with tick labels, on any scale.
trait Axis: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64> {}

impl<T: Ranged<ValueType = f64> + plotters::coord::ranged1d::ValueFormatter<f64>> Axis for T {}

/// What turns a drawing error of the backend `DB` into the crate's error.
type DrawError<'e, DB> = dyn Fn(plotters::drawing::DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>) -> Error
    + 'e;

/// The mesh, every series (line, points or pixels, notes, error bars) and the legend, on a chart
/// of any axis scales.
fn chart_body<'a, DB, X: Axis, Y: Axis>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    spec: &PlotSpec,
    series: &[Series],
    (y0, y1): (f64, f64),
    io: &DrawError<'_, DB>,
) -> Result<(), Error>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
{
    let keys = |log: bool, k: Vec<f64>| if log { Vec::new() } else { k };
    // A count axis ticks at whole numbers only: no more ticks than counts in its range.
    let y_ticks = if spec.count_y {
        ((y1 - y0).floor().max(1.0) as usize + 1).min(TICKS)
    } else {
        TICKS
    };
    let x_keys = keys(spec.log_x, chart.as_coord_spec().x_spec().key_points(TICKS));
    let y_keys = keys(
        spec.log_y,
        chart.as_coord_spec().y_spec().key_points(y_ticks),
    );
    let x_tick = tick_labels(&x_keys, spec.log_x);
    let y_real = tick_labels(&y_keys, spec.log_y);
    let y_tick = |v: &f64| {
        if !spec.count_y {
            y_real(v)
        } else if v.fract() == 0.0 {
            tick(*v)
        } else {
            String::new()
        }
    };
    // A light major grid (no minor lines), axes in black, labels in the embedded font.
    chart
        .configure_mesh()
        .x_labels(TICKS)
        .y_labels(y_ticks)
        .bold_line_style(RGBColor(225, 225, 225).stroke_width(1))
        .light_line_style(TRANSPARENT)
        .axis_style(BLACK.stroke_width(1))
        .x_desc(spec.x_label)
        .y_desc(spec.y_label)
        .x_label_formatter(&x_tick)
        .y_label_formatter(&y_tick)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .draw()
        .map_err(io)?;
    for (k, b) in spec.bands.iter().enumerate() {
        let c = legend::colour(series.len() + k);
        let (lo, hi) = b.y.unwrap_or((y0, y1));
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(b.x.0, lo), (b.x.1, hi)],
                c.mix(0.18).filled(),
            )))
            .map_err(io)?;
    }
    for (i, s) in series.iter().enumerate() {
        match spec.bar_width {
            Some(width) if !s.line => draw_bars(chart, legend::colour(i), s, width, io)?,
            _ => draw_one(chart, legend::colour(i), s, io)?,
        }
    }
    Ok(())
}

/// Draws the legend of `chart` at `position`: a black frame over white of opacity `opacity`,
/// labels in the embedded sans-serif at `size` pixels.
fn draw_legend<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
    opacity: f64,
    size: u32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>>
where
    DB: DrawingBackend + 'a,
    CT: plotters::coord::CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(opacity))
        .border_style(BLACK)
        .label_font(("sans-serif", size))
        .draw()
}

/// One series of a chart in the colour `c`: its line (if joined), dots or single pixels, notes
/// and error bars, in that order.
fn draw_one<'a, DB, X: Axis, Y: Axis>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    c: RGBAColor,
    s: &Series,
    io: &DrawError<'_, DB>,
) -> Result<(), Error>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
{
    let joined: Vec<(f64, f64)> = if s.line {
        s.points.iter().map(|p| (p.0, p.1)).collect()
    } else {
        Vec::new()
    };
    chart
        .draw_series(LineSeries::new(joined, c.stroke_width(2)))
        .map_err(io)?;
    // Markers on the measured points (a series with error bars, or without a line); a
    // reference line (a mean, a closed form) is a plain line.
    let measured = !s.line || s.points.iter().any(|p| p.2 > 0.0);
    if measured && s.points.len() < 1000 {
        let dots = s
            .points
            .iter()
            .map(|p| Circle::new((p.0, p.1), 3, c.filled()));
        chart.draw_series(dots).map_err(io)?;
    } else if !s.line {
        // Dense scatter (e.g. Fig. 5): single pixels.
        let pixels = s.points.iter().map(|p| Pixel::new((p.0, p.1), c));
        chart.draw_series(pixels).map_err(io)?;
    }
    let notes = s.points.iter().zip(&s.notes);
    chart
        .draw_series(notes.map(|(p, t)| Text::new(t.clone(), (p.0, p.1), ("sans-serif", 13))))
        .map_err(io)?;
    let bars = s
        .points
        .iter()
        .filter(|p| p.2 > 0.0)
        .map(|p| ErrorBar::new_vertical(p.0, p.1 - p.2, p.1, p.1 + p.2, c.stroke_width(1), 6));
    chart.draw_series(bars).map_err(io)?;
    Ok(())
}

/// The series `s` as bars of `width` from 0 to each point's y, filled in `c` (translucent, so
/// a second histogram shows through) with a solid outline.
fn draw_bars<'a, DB, X: Axis, Y: Axis>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    c: RGBAColor,
    s: &Series,
    width: f64,
    io: &DrawError<'_, DB>,
) -> Result<(), Error>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
{
    let corners = |p: &(f64, f64, f64)| [(p.0 - width / 2.0, 0.0), (p.0 + width / 2.0, p.1)];
    let bars = s.points.iter().filter(|p| p.1 > 0.0);
    chart
        .draw_series(
            bars.clone()
                .map(|p| Rectangle::new(corners(p), c.mix(0.6).filled())),
        )
        .map_err(io)?;
    chart
        .draw_series(bars.map(|p| Rectangle::new(corners(p), c.stroke_width(1))))
        .map_err(io)?;
    Ok(())
}

/// Figure size in pixels.
const SIZE: (u32, u32) = (800, 600);

/// The PNG encoding of `rgb`, an RGB bitmap of `size` pixels drawn for `path` (which an error
/// names).
fn png_bytes(rgb: &[u8], size: (u32, u32), path: &Path) -> Result<Vec<u8>, Error> {
    let mut encoded = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut encoded),
        rgb,
        size.0,
        size.1,
        image::ColorType::Rgb8,
    )
    .map_err(|e| Error::io("encode", path)(std::io::Error::other(e.to_string())))?;
    Ok(encoded)
}

/// Writes `stem.png` and `stem.svg` (800×600). Both are drawn in memory and written by
/// [`crate::files::write`], so a link found where a figure goes is refused, not followed.
pub fn plot(stem: &Path, spec: &PlotSpec, series: &[Series]) -> Result<(), Error> {
    register_font();
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    draw(
        &png,
        Glyphs(BitMapBackend::with_buffer(&mut rgb, SIZE)).into_drawing_area(),
        spec,
        series,
    )?;
    crate::files::write(&png, png_bytes(&rgb, SIZE, &png)?)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The number of attribute `name` in an SVG element's text.
    fn attr(el: &str, name: &str) -> Option<f64> {
        let key = format!(" {name}=\"");
        let start = el.find(&key)? + key.len();
        el[start..].split('"').next()?.parse().ok()
    }

    /// Renders series whose points crowd the upper right corner and asserts on the SVG itself:
    /// every legend label sits below every data point, every end of an error bar and the x
    /// axis's labels (the legend is off the data); the band is drawn; count ticks are integers;
    /// the grid has no minor lines (one line per labelled tick). (Broken on purpose — the legend
    /// drawn on the upper part of the figure instead of the strip below — the labels sit among
    /// the points and the test fails.)
    #[test]
    fn the_legend_is_below_the_data_and_counts_tick_as_integers() {
        register_font();
        let points: Vec<(f64, f64, f64)> = (0..40)
            .map(|k| (k as f64, (k as f64).sqrt(), 0.2))
            .collect();
        let bands = [Band {
            label: "band".into(),
            x: (0.0, 39.0),
            y: Some((2.0, 3.0)),
        }];
        let spec = PlotSpec {
            bands: &bands,
            count_y: true,
            ..PlotSpec::new("t", "x", "count")
        };
        let series: Vec<Series> = (0..4)
            .map(|i| Series {
                label: format!("a series with a long label {i}"),
                points: points
                    .iter()
                    .map(|p| (p.0, p.1 + i as f64 * 0.01, p.2))
                    .collect(),
                notes: Vec::new(),
                line: true,
            })
            .collect();
        let mut svg = String::new();
        draw(
            Path::new("t.svg"),
            SVGBackend::with_string(&mut svg, SIZE).into_drawing_area(),
            &spec,
            &series,
        )
        .unwrap();
        let texts: Vec<(f64, &str)> = svg
            .split("<text")
            .skip(1)
            .filter_map(|t| {
                let (head, rest) = t.split_once('>')?;
                Some((attr(head, "y")?, rest.split('<').next()?.trim()))
            })
            .collect();
        let labels: Vec<f64> = texts
            .iter()
            .filter(|t| t.1.starts_with("a series with a long label") || t.1 == "band")
            .map(|t| t.0)
            .collect();
        assert_eq!(labels.len(), 5, "every entry labelled: {texts:?}");
        let top_of_legend = labels.iter().copied().fold(f64::INFINITY, f64::min);
        let circles: Vec<f64> = svg
            .split('<')
            .filter(|e| e.starts_with("circle"))
            .map(|e| attr(e, "cy").unwrap())
            .collect();
        assert!(circles.len() >= 160, "every point drawn: {}", circles.len());
        assert!(
            circles.iter().all(|&cy| cy < top_of_legend),
            "a data point at or below the legend (top {top_of_legend})"
        );
        let bar_ends = svg
            .split('<')
            .filter(|e| e.starts_with("line"))
            .filter_map(|e| attr(e, "y1"));
        assert!(bar_ends.into_iter().all(|y| y < top_of_legend));
        let x_desc = texts.iter().find(|t| t.1 == "x").expect("the x label").0;
        assert!(x_desc < top_of_legend, "the legend above the x label");
        assert!(svg.contains("opacity=\"0.18\""), "the band is drawn");
        // The grid: one light line per labelled tick, no minor lines between them.
        let grid = svg.matches("stroke=\"#E1E1E1\"").count();
        assert!((4..=2 * (TICKS + 1)).contains(&grid), "{grid} grid lines");
        // Count ticks: "0", "1", … and never a fraction.
        let ticks: Vec<&str> = texts.iter().map(|t| t.1).collect();
        assert!(ticks.contains(&"3"), "{ticks:?}");
        assert!(!ticks.iter().any(|t| t.contains('.')), "{ticks:?}");
    }

    #[test]
    fn an_axis_labels_its_ticks_with_the_same_decimals() {
        let keys = [0.164, 0.166, 0.168, 0.17, 0.172];
        let label = tick_labels(&keys, false);
        let shown: Vec<String> = keys.iter().map(&label).collect();
        assert_eq!(shown, ["0.164", "0.166", "0.168", "0.170", "0.172"]);
        let label = tick_labels(&[0.0, 0.25, 0.5, 0.75, 1.0], false);
        assert_eq!(label(&1.0), "1.00");
        assert_eq!(label(&-0.0), "0.00");
        let label = tick_labels(&[20.0, 40.0, 60.0], false);
        assert_eq!(label(&40.0), "40");
        // A logarithmic axis labels each tick as written.
        let label = tick_labels(&[0.01, 0.1, 1.0], true);
        assert_eq!((label(&0.01), label(&1.0)), ("0.01".into(), "1".into()));
    }

    #[test]
    fn ticks_read_as_people_write_them() {
        assert_eq!(tick(20.0), "20");
        assert_eq!(tick(0.1695), "0.1695");
        assert_eq!(tick(2.5e-9), "2.5e-9");
        assert_eq!(tick(0.0), "0");
    }
}
