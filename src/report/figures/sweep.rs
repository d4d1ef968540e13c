//! The sweep's figures: D(w) against Machta–Zwanzig (paper Fig. 2), D against 1/n with
//! Boltzmann (Fig. 7), and the residuals from a linear fit (Fig. 8).

use std::path::Path;

use super::{PlotSpec, Series, plot};
use crate::Error;
use crate::estimators::sweep::{SweepReport, SweepRow};

/// The files [`write_sweep_figures`] writes.
pub const FILES: [&str; 6] = [
    "fig2-D-vs-w.png",
    "fig2-D-vs-w.svg",
    "fig7-boltzmann.png",
    "fig7-boltzmann.svg",
    "fig8-residuals.png",
    "fig8-residuals.svg",
];

/// Writes `fig2-D-vs-w`, `fig7-boltzmann` and `fig8-residuals` (`.png`, `.svg`) into `dir`.
///
/// # Errors
/// If a file cannot be written.
pub fn write_sweep_figures(r: &SweepReport, dir: &Path) -> Result<(), Error> {
    let pts = |f: &dyn Fn(&SweepRow) -> (f64, f64, f64)| r.rows.iter().map(f).collect::<Vec<_>>();
    let s = |label: &str, points| Series {
        label: label.into(),
        points,
        notes: Vec::new(),
        line: true,
    };
    plot(
        &dir.join("fig2-D-vs-w"),
        &PlotSpec::new("Diffusion coefficient D(w) (paper Fig. 2)", "gap w", "D"),
        &[
            s("D (Einstein, this crate)", pts(&|x| (x.w, x.D, x.D_err))),
            s("Machta-Zwanzig D_MZ", pts(&|x| (x.w, x.D_MZ, 0.0))),
        ],
    )?;
    let off = r.boltzmann_offset.mean;
    plot(
        &dir.join("fig7-boltzmann"),
        &PlotSpec::new(
            &format!("D against 1/n (paper Fig. 7); D_Bo - {off:.4}"),
            "1/n",
            "D",
        ),
        &[
            s("D", pts(&|x| (x.inv_n, x.D, x.D_err))),
            s(
                &format!("Boltzmann (3/16)(1/n - pi) - {off:.4}"),
                pts(&|x| (x.inv_n, x.D_Bo - off, 0.0)),
            ),
            s("Machta-Zwanzig", pts(&|x| (x.inv_n, x.D_MZ, 0.0))),
        ],
    )?;
    let mut runs = Vec::new();
    for row in &r.rows {
        for d in &row.run_D {
            runs.push((row.w, d - r.linear_fit.at(row.w), 0.0));
        }
    }
    plot(
        &dir.join("fig8-residuals"),
        &PlotSpec::new(
            "Residuals of D from a linear fit in w (paper Fig. 8)",
            "gap w",
            "D - linear fit",
        ),
        &[
            s(
                "mean over runs (error bar: from the batches)",
                pts(&|x| (x.w, x.residual, x.D_err)),
            ),
            Series {
                label: "single runs".into(),
                points: runs,
                notes: Vec::new(),
                line: false,
            },
        ],
    )?;
    Ok(())
}
