//! The figures of a diffusion audit: the local slope D(t) with its error band and the recorded D, and the histogram of the batch values.

use super::*;

/// The figures of a diffusion audit: the local slope D(t) with the recorded D, and the histogram
/// of the batch values.
pub(super) fn diffusion_figures(
    r: &DiffusionReport,
    out: &Path,
    figures: &mut Vec<String>,
) -> Result<(), Error> {
    let slope_series = local_slopes(r);
    let t_first = r.msd_times.first().copied().unwrap_or(0.0);
    let t_last = r.msd_times.last().copied().unwrap_or(t_first);
    let tau = r.tau_hop_exact;
    let (lo, hi) = (r.window.lo as f64 * tau, r.window.hi as f64 * tau);
    let shown = crate::report::publication::headline::with_error(r.D, r.D_err);
    let bands = [
        Band {
            label: format!("D ± D_err = {shown}"),
            x: (t_first, t_last),
            y: Some((r.D - r.D_err, r.D + r.D_err)),
        },
        Band {
            label: format!(
                "fit window [{}τ, {}τ] (τ = {tau:.4})",
                r.window.lo, r.window.hi
            ),
            x: (lo, hi),
            y: None,
        },
    ];
    let stem = out.join("local-slope");
    plot(
        &stem,
        &PlotSpec {
            bands: &bands,
            ..PlotSpec::new(
                "Local slope D(t) = d MSD / (4 dt), with the recorded D",
                "t (time; speed 1, lengths in disk radii)",
                "D(t)",
            )
        },
        &[
            Series {
                label: "local slope between lags (error: over batches)".into(),
                points: slope_series,
                notes: Vec::new(),
                line: true,
            },
            Series {
                label: "MSD/(4t)".into(),
                points: r
                    .msd_times
                    .iter()
                    .zip(r.msd_over_4t.iter().zip(&r.msd_over_4t_err))
                    .map(|(t, (v, e))| (*t, *v, *e))
                    .collect(),
                notes: Vec::new(),
                line: true,
            },
            Series {
                label: format!("D = {shown}"),
                points: vec![(t_first, r.D, 0.0), (t_last, r.D, 0.0)],
                notes: Vec::new(),
                line: true,
            },
        ],
    )?;
    figures.push("local-slope".into());
    let groups = [(format!("{} batches", r.batch_D.len()), &r.batch_D[..])];
    super::super::histogram::histogram(
        &groups,
        r.D,
        ("D of each batch", "D"),
        &out.join("batch-histogram"),
    )?;
    figures.push("batch-histogram".into());
    Ok(())
}

/// The local slope (MSD(t_{k+1}) − MSD(t_k)) / (4 (t_{k+1} − t_k)) per batch, mean ± error, at the
/// interval midpoints.
pub(super) fn local_slopes(r: &DiffusionReport) -> Vec<(f64, f64, f64)> {
    let t = &r.msd_times;
    (0..t.len().saturating_sub(1))
        .map(|k| {
            let v: Vec<f64> = r
                .batch_msd
                .iter()
                .map(|m| (m[k + 1] - m[k]) / (4.0 * (t[k + 1] - t[k])))
                .collect();
            let (m, e) = mean_se(&v);
            (0.5 * (t[k] + t[k + 1]), m, e)
        })
        .collect()
}
