//! The figure of a Poincaré section: θ ∈ [−π, π) across, p ∈ [−1, 1] up, one dot per recorded
//! collision, coloured by its orbit's component (the chaotic sea light grey under the regular
//! islands), a legend with the number of orbits of each.

use std::path::Path;

use plotters::prelude::*;

use super::{draw_legend, png_bytes, register_font};
use crate::Error;
use crate::estimators::section::{Component, SectionResult};

/// The figure's size in pixels.
const SIZE: (u32, u32) = (1200, 900);

/// The components in drawing order (the sea first, under the rest), each with its colour and
/// its legend's name.
const LAYERS: [(Component, RGBColor, &str); 3] = [
    (
        Component::Diffusing,
        RGBColor(185, 185, 185),
        "diffusing (chaotic sea)",
    ),
    (
        Component::Skipping,
        RGBColor(31, 119, 180),
        "skipping (round one disk)",
    ),
    (
        Component::Bounded,
        RGBColor(214, 39, 40),
        "bounded (regular islands)",
    ),
];

/// The title: the scene and the field.
fn title(r: &SectionResult) -> String {
    match r.config.table.field() {
        Some(b) => format!("Poincaré section, {}, B = {b}", r.scene),
        None => format!("Poincaré section, {}, no field", r.scene),
    }
}

/// Draws the section on `area`.
fn draw<DB: DrawingBackend>(
    r: &SectionResult,
    area: DrawingArea<DB, plotters::coord::Shift>,
) -> Result<(), String> {
    let e = |x: &dyn std::fmt::Display| x.to_string();
    area.fill(&WHITE).map_err(|x| e(&x))?;
    let pi = std::f64::consts::PI;
    let mut chart = ChartBuilder::on(&area)
        .caption(title(r), ("sans-serif", 26))
        .margin(14)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(-pi..pi, -1.0..1.0)
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("θ: polar angle of the contact point on its disk (radians; arc length s = rθ)")
        .y_desc("p = sin α (outgoing velocity along the counter-clockwise tangent)")
        .x_labels(9)
        .y_labels(11)
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 17))
        .draw()
        .map_err(|x| e(&x))?;
    let per_orbit = &r.component;
    for (c, colour, name) in LAYERS {
        let n = r.count(c);
        let dots = (r.theta.iter().zip(&r.p).zip(&r.trajectory))
            .filter(|(_, o)| per_orbit[**o as usize] == c)
            .map(|((t, p), _)| Pixel::new((*t, *p), colour));
        chart
            .draw_series(dots)
            .map_err(|x| e(&x))?
            .label(format!(
                "{name}: {n} trajector{}",
                if n == 1 { "y" } else { "ies" }
            ))
            .legend(move |(x, y)| Circle::new((x + 8, y), 5, colour.filled()));
    }
    let localized = format!("pinned (no collision): {} trajectories", r.pinned);
    chart
        .draw_series(std::iter::empty::<Pixel<(f64, f64)>>())
        .map_err(|x| e(&x))?
        .label(localized)
        .legend(|(x, y)| Circle::new((x + 8, y), 5, BLACK));
    draw_legend(&mut chart, SeriesLabelPosition::LowerRight, 0.85, 16).map_err(|x| e(&x))?;
    area.present().map_err(|x| e(&x))
}

/// The section's figure as PNG bytes.
///
/// # Errors
/// If the figure cannot be drawn or encoded.
pub fn section_png(r: &SectionResult, path: &Path) -> Result<Vec<u8>, Error> {
    register_font();
    let failed = |what: String| Error::io("draw", path)(std::io::Error::other(what));
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    draw(
        r,
        super::Glyphs(BitMapBackend::with_buffer(&mut rgb, SIZE)).into_drawing_area(),
    )
    .map_err(failed)?;
    png_bytes(&rgb, SIZE, path)
}

/// Writes the section's figure to `path` (PNG, [`crate::files::write`]: a link there is refused,
/// not followed).
///
/// # Errors
/// If the figure cannot be drawn or written.
pub fn write_section_figure(r: &SectionResult, path: &Path) -> Result<(), Error> {
    crate::files::write(path, section_png(r, path)?)
}

/// Writes the points of the section to `path` as CSV: `orbit,component,disk,theta,p`, one line
/// per recorded collision (θ and p with the digits that read back to their bits).
///
/// # Errors
/// If the file cannot be written.
pub fn write_section_csv(r: &SectionResult, path: &Path) -> Result<(), Error> {
    use std::fmt::Write as _;
    let mut text = String::from("trajectory,component,disk,theta,p\n");
    for i in 0..r.theta.len() {
        let o = r.trajectory[i] as usize;
        let c = match r.component[o] {
            Component::Pinned => "pinned",
            Component::Skipping => "skipping",
            Component::Bounded => "bounded",
            Component::Diffusing => "diffusing",
        };
        let _ = writeln!(text, "{o},{c},{},{:?},{:?}", r.disk[i], r.theta[i], r.p[i]);
    }
    crate::files::write(path, text)
}
