//! The figures of a field sweep: D_xx and the Hall D_xy against B, one curve per gap or radius (or against w,
//! one curve per field, for a sweep over w at a fixed field), with the standard errors as bars.

use std::path::Path;

use super::{PlotSpec, Series, plot};
use crate::Error;
use crate::estimators::sweep::field::{FieldSweepReport, FieldSweepRow};

/// The files [`write_field_sweep_figures`] writes.
pub const FILES: [&str; 4] = [
    "field-D_xx.png",
    "field-D_xx.svg",
    "field-D_xy.png",
    "field-D_xy.svg",
];

/// Writes `field-D_xx` and `field-D_xy` (`.png`, `.svg`) into `dir`.
///
/// # Errors
/// If a file cannot be written.
pub fn write_field_sweep_figures(r: &FieldSweepReport, dir: &Path) -> Result<(), Error> {
    let grid = r.config.field_grid()?;
    let over_fields = grid.fields.len() > 1;
    let x_of = |row: &FieldSweepRow| if over_fields { row.field } else { row.place() };
    let xs: Vec<f64> = r.rows.iter().map(x_of).collect();
    let lo = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let log_x = lo > 0.0 && hi >= 20.0 * lo;
    let x_label = if over_fields { "field B" } else { "gap w" };
    let place = if grid.radius.is_some() { "r" } else { "w" };
    let table = grid.table.as_ref().map(|t| t.title().to_string());
    let curves = |y: &dyn Fn(&FieldSweepRow) -> (f64, f64)| -> Vec<Series> {
        let mut keys: Vec<f64> = Vec::new();
        for row in &r.rows {
            let k = if over_fields { row.place() } else { row.field };
            if !keys.contains(&k) {
                keys.push(k);
            }
        }
        keys.into_iter()
            .map(|k| {
                let mut points: Vec<(f64, f64, f64)> = r
                    .rows
                    .iter()
                    .filter(|row| (if over_fields { row.place() } else { row.field }) == k)
                    .map(|row| {
                        let (v, e) = y(row);
                        (x_of(row), v, e)
                    })
                    .collect();
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                Series {
                    label: if let Some(t) = &table {
                        t.clone()
                    } else if over_fields {
                        format!("{place} = {k}")
                    } else {
                        format!("B = {k}")
                    },
                    points,
                    notes: Vec::new(),
                    line: true,
                }
            })
            .collect()
    };
    for (stem, title, y_label, y) in [
        (
            "field-D_xx",
            "D_xx in a magnetic field (whole phase space)",
            "D_xx",
            &(|row: &FieldSweepRow| (row.D_xx, row.D_xx_err))
                as &dyn Fn(&FieldSweepRow) -> (f64, f64),
        ),
        (
            "field-D_xy",
            "Hall part D_xy in a magnetic field (whole phase space)",
            "D_xy",
            &|row: &FieldSweepRow| (row.D_xy, row.D_xy_err),
        ),
    ] {
        plot(
            &dir.join(stem),
            &PlotSpec {
                log_x,
                ..PlotSpec::new(title, x_label, y_label)
            },
            &curves(y),
        )?;
    }
    Ok(())
}
