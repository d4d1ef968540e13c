//! The figure of a driven sweep: the mobility J/E against |E|, one curve per gap, with the
//! standard errors as bars — the figure Bonetto, Daems & Lebowitz drew to ask whether it is smooth.

use std::path::Path;

use super::{PlotSpec, Series, plot};
use crate::Error;
use crate::estimators::sweep::driven::DrivenSweepReport;

/// The files [`write_driven_sweep_figures`] writes.
pub const FILES: [&str; 2] = ["driven-mobility.png", "driven-mobility.svg"];

/// Writes `driven-mobility` (`.png`, `.svg`) into `dir`: J/E against |E| per gap (points at −E
/// are drawn at |E|, beside those at E).
///
/// # Errors
/// If a file cannot be written.
pub fn write_driven_sweep_figures(r: &DrivenSweepReport, dir: &Path) -> Result<(), Error> {
    let series: Vec<Series> = (r.mobility.iter())
        .map(|m| {
            let mut points: Vec<(f64, f64, f64)> = (r.rows.iter())
                .filter(|row| row.w == m.w)
                .map(|row| {
                    let s = &row.steady;
                    (row.electric.abs(), s.mobility, s.mobility_err)
                })
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            Series {
                label: format!("w = {}", m.w),
                points,
                notes: Vec::new(),
                line: true,
            }
        })
        .collect();
    let xs = r.rows.iter().map(|row| row.electric.abs());
    let (lo, hi) = xs.fold((f64::INFINITY, 0.0f64), |(l, h), x| (l.min(x), h.max(x)));
    let spec = PlotSpec {
        log_x: lo > 0.0 && hi >= 20.0 * lo,
        ..PlotSpec::new(
            "mobility of the thermostatted driven gas (→ D as E → 0)",
            "field |E|",
            "J/E",
        )
    };
    plot(&dir.join("driven-mobility"), &spec, &series)
}
