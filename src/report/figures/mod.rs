//! Figures with plotters: PNG and SVG, text rendered from an embedded DejaVu Sans (no system font
//! libraries; the font's licence is in `src/report/figures/DejaVuSans-LICENSE.txt`).

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;

pub mod field_sweep;
pub mod paper;
pub mod section;
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

/// Room at the top of the y range for `entries` legend lines, so the legend (upper right) never
/// covers data: the data keep the lower part of a plot area about 470 px high.
fn headroom((y0, y1): (f64, f64), entries: usize, log: bool) -> (f64, f64) {
    let f = ((22 * entries + 24) as f64 / 470.0).min(0.45);
    if log {
        (y0, y0 * (y1 / y0).powf(1.0 / (1.0 - f)))
    } else {
        (y0, y0 + (y1 - y0) / (1.0 - f))
    }
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
    let (y0, y1) = headroom((y0, y1), series.len() + spec.bands.len(), spec.log_y);
    let mut b = ChartBuilder::on(&root);
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
    let count_tick = |v: &f64| {
        if v.fract() == 0.0 {
            tick(*v)
        } else {
            String::new()
        }
    };
    let y_tick: &dyn Fn(&f64) -> String = if spec.count_y {
        &count_tick
    } else {
        &|v: &f64| tick(*v)
    };
    chart
        .configure_mesh()
        .x_desc(spec.x_label)
        .y_desc(spec.y_label)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(y_tick)
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(io)?;
    for (k, b) in spec.bands.iter().enumerate() {
        let c = Palette99::pick(series.len() + k).to_rgba();
        let (lo, hi) = b.y.unwrap_or((y0, y1));
        let fill = c.mix(0.18).filled();
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(b.x.0, lo), (b.x.1, hi)],
                fill,
            )))
            .map_err(io)?
            .label(b.label.clone())
            .legend(move |(x, y)| {
                Rectangle::new([(x, y - 6), (x + 18, y + 6)], c.mix(0.35).filled())
            });
    }
    for (i, s) in series.iter().enumerate() {
        draw_one(chart, Palette99::pick(i).to_rgba(), s, io)?;
    }
    draw_legend(chart, SeriesLabelPosition::UpperRight, 0.8, 14).map_err(io)?;
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
    let bars = s
        .points
        .iter()
        .filter(|p| p.2 > 0.0)
        .map(|p| ErrorBar::new_vertical(p.0, p.1 - p.2, p.1, p.1 + p.2, c.stroke_width(1), 6));
    chart.draw_series(bars).map_err(io)?;
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
        BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area(),
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

    /// Renders series whose points crowd the upper right corner (where the legend goes) and
    /// asserts on the SVG itself: the legend box covers no data point and no end of an error
    /// bar; the band is drawn; count ticks are integers. (Broken on purpose — the headroom taken
    /// out — the legend box sits on the top points and the test fails.)
    #[test]
    fn the_legend_covers_no_data_and_counts_tick_as_integers() {
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
        let legend = svg
            .split('<')
            .find(|e| e.starts_with("rect") && e.contains("opacity=\"0.8\""))
            .expect("a legend box");
        let (x, y) = (attr(legend, "x").unwrap(), attr(legend, "y").unwrap());
        let (w, h) = (
            attr(legend, "width").unwrap(),
            attr(legend, "height").unwrap(),
        );
        let inside = |px: f64, py: f64| px >= x && px <= x + w && py >= y && py <= y + h;
        let circles: Vec<(f64, f64)> = svg
            .split('<')
            .filter(|e| e.starts_with("circle"))
            .map(|e| (attr(e, "cx").unwrap(), attr(e, "cy").unwrap()))
            .collect();
        assert!(circles.len() >= 160, "every point drawn: {}", circles.len());
        assert!(
            circles.iter().all(|&(cx, cy)| !inside(cx, cy)),
            "a data point under the legend box {legend}"
        );
        let ends = svg
            .split('<')
            .filter(|e| e.starts_with("line"))
            .filter_map(|e| Some((attr(e, "x1")?, attr(e, "y1")?)));
        assert!(ends.into_iter().all(|(bx, by)| !inside(bx, by)));
        assert!(svg.contains("opacity=\"0.18\""), "the band is drawn");
        // Count ticks: "0", "1", … and never a fraction.
        let texts: Vec<&str> = svg
            .split("<text")
            .skip(1)
            .filter_map(|t| Some(t.split_once('>')?.1.split('<').next()?.trim()))
            .collect();
        assert!(texts.contains(&"3"), "{texts:?}");
        assert!(!texts.iter().any(|t| t.contains('.')), "{texts:?}");
    }

    #[test]
    fn ticks_read_as_people_write_them() {
        assert_eq!(tick(20.0), "20");
        assert_eq!(tick(0.1695), "0.1695");
        assert_eq!(tick(2.5e-9), "2.5e-9");
        assert_eq!(tick(0.0), "0");
    }
}
