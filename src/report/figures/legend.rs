//! The colours of a figure's series and its legend, drawn below the axes (never over the data):
//! one entry per shaded band and per series, in two columns where the labels fit.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{PlotSpec, Series};

/// Colours a reader tells apart, also in print and with the common colour-vision deficiencies
/// (Okabe & Ito's palette, without its yellow, which white paper hides).
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

/// The colour of the `i`-th series (bands follow the series).
pub fn colour(i: usize) -> RGBAColor {
    PALETTE[i % PALETTE.len()].to_rgba()
}

/// How an entry's sample is drawn: a line (a series) or a filled box (a band, bars).
#[derive(Clone, Copy)]
pub enum Swatch {
    /// A line in this colour.
    Line(RGBAColor),
    /// A box filled with this colour.
    Box(RGBAColor),
}

/// One entry: its sample and its label.
pub type Entry = (Swatch, String);

/// The font of the legend's labels.
fn font() -> TextStyle<'static> {
    ("sans-serif", 14).into_font().color(&BLACK)
}

/// Height of one entry's row, in pixels.
const ROW: u32 = 22;
/// Left edge of the legend (the axes' left edge: margin and y-label area).
const LEFT: i32 = 92;
/// Width of a sample, and its gap to the label.
const SAMPLE: i32 = 26;

/// The entries of a plot: its bands, then its series, each labelled.
pub fn entries(spec: &PlotSpec, series: &[Series]) -> Vec<Entry> {
    let bands = spec.bands.iter().enumerate().map(|(k, b)| {
        (
            Swatch::Box(colour(series.len() + k).mix(0.35)),
            b.label.clone(),
        )
    });
    let lines = series.iter().enumerate().map(|(i, s)| {
        let c = colour(i);
        let bars = spec.bar_width.is_some() && !s.line;
        let swatch = if bars {
            Swatch::Box(c.mix(0.6))
        } else {
            Swatch::Line(c)
        };
        (swatch, s.label.clone())
    });
    bands.chain(lines).filter(|e| !e.1.is_empty()).collect()
}

/// Columns that fit `entries` across `width` pixels: 2 if every label fits half of it, else 1.
fn columns<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
    width: u32,
) -> usize {
    let half = (width as i32 - LEFT) / 2 - SAMPLE - 16;
    let fits = entries.iter().all(|(_, label)| {
        area.estimate_text_size(label, &font())
            .is_ok_and(|(w, _)| (w as i32) < half)
    });
    if fits && entries.len() > 1 { 2 } else { 1 }
}

/// The height the legend of `entries` takes below the axes (0 without entries).
pub fn height<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
    width: u32,
) -> u32 {
    if entries.is_empty() {
        return 0;
    }
    let rows = entries.len().div_ceil(columns(area, entries, width));
    8 + ROW * rows as u32
}

/// Draws `entries` on `area` (the strip below the axes), row by row, left to right.
pub fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
    width: u32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    if entries.is_empty() {
        return Ok(());
    }
    let cols = columns(area, entries, width);
    let step = (width as i32 - LEFT) / cols as i32;
    for (n, (swatch, label)) in entries.iter().enumerate() {
        let x = LEFT + step * (n % cols) as i32;
        let y = 4 + (ROW * (n / cols) as u32) as i32 + ROW as i32 / 2;
        match *swatch {
            Swatch::Line(c) => area.draw(&PathElement::new(
                vec![(x, y), (x + SAMPLE - 6, y)],
                c.stroke_width(3),
            ))?,
            Swatch::Box(c) => area.draw(&Rectangle::new(
                [(x, y - 6), (x + SAMPLE - 6, y + 6)],
                c.filled(),
            ))?,
        }
        let text = font().pos(plotters::style::text_anchor::Pos::new(
            plotters::style::text_anchor::HPos::Left,
            plotters::style::text_anchor::VPos::Center,
        ));
        area.draw(&Text::new(label.clone(), (x + SAMPLE, y), text))?;
    }
    Ok(())
}
