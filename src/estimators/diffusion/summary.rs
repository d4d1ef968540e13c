//! From finished batches to a report: D and its check from each batch's MSD slope, the exact
//! identities, and the metadata.

use super::{BatchResult, DiffusionConfig, DiffusionReport, Estimate, Window};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::observers::counters::Counters;
use crate::scenes::triangular::geometry::Geometry;
use crate::statistics::{linear_fit, mean_se};
use crate::verification::shadow_audit::AuditSummary;

/// The lag times (lags in units of `tau`) and MSD/(4t) at each, mean and standard error over
/// the batches.
pub(super) fn msd_over_4t(done: &[BatchResult], tau: f64) -> (Vec<f64>, Vec<Estimate>) {
    let lags = done.first().map(|b| b.lags.clone()).unwrap_or_default();
    let msd_times: Vec<f64> = lags.iter().map(|&l| l as f64 * tau).collect();
    let over = (0..lags.len())
        .map(|k| {
            let v: Vec<f64> = done
                .iter()
                .map(|b| b.msd[k] / (4.0 * msd_times[k]))
                .collect();
            let (value, err) = mean_se(&v);
            Estimate { value, err }
        })
        .collect();
    (msd_times, over)
}

/// The batches' per-event audits merged (`None` without an audit).
pub(super) fn merged_audit(done: &[BatchResult]) -> Option<AuditSummary> {
    done.iter()
        .filter_map(|b| b.audit.as_ref())
        .fold(None, |acc: Option<AuditSummary>, a| {
            let mut m = acc.unwrap_or_default();
            m.merge(a);
            Some(m)
        })
}

pub(super) fn d_of_batch(b: &BatchResult, tau: f64, win: &Window) -> f64 {
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for (lag, m) in b.lags.iter().zip(&b.msd) {
        if *lag >= win.lo && *lag <= win.hi {
            x.push(*lag as f64 * tau);
            y.push(*m);
        }
    }
    linear_fit(&x, &y).1 / 4.0
}

#[allow(clippy::too_many_arguments)]
pub(super) fn summarise(
    cfg: &DiffusionConfig,
    g: &Geometry<f64>,
    tau: f64,
    done: &[BatchResult],
    threads: usize,
    seconds: f64,
    resumed: u32,
    run_now: u64,
) -> Result<DiffusionReport, Error> {
    let super::WindowDs {
        ds,
        dc,
        d: (d, d_err),
        check: (dcv, dce),
        diff: window_diff,
    } = super::window_ds(done, tau, &cfg.window, &cfg.check_window)?;
    let [(mfp, mfp_e), (th, th_e), (cph, cph_e)] = counter_means(done);
    let (msd_times, msd_over_4t) = msd_over_4t(done, tau);
    let grid = super::execution::curve_grid(
        &cfg.msd_grid,
        g.mean_free_path(),
        cfg.collisions,
        cfg.batches,
    );
    let times = grid.map(|g| g.times());
    let (msd_curve, green_kubo) = super::curve::summarise(times, done, tau, &cfg.window, &ds)?;
    let total: u64 = done.iter().map(|b| b.counters.collisions).sum();
    let audit = merged_audit(done);
    Ok(DiffusionReport {
        w: cfg.gap()?,
        D: d,
        D_err: d_err,
        window: cfg.window,
        D_check: dcv,
        D_check_err: dce,
        check_window: cfg.check_window,
        D_minus_D_check: window_diff.difference,
        D_minus_D_check_err: window_diff.err,
        D_MZ: g.d_mz(),
        D_Bo: g.d_bo(),
        mean_free_path: mfp,
        mean_free_path_err: mfp_e,
        mean_free_path_exact: g.mean_free_path(),
        tau_hop: th,
        tau_hop_err: th_e,
        tau_hop_exact: tau,
        collisions_per_hop: cph,
        collisions_per_hop_err: cph_e,
        collisions_per_hop_exact: g.collisions_per_hop(),
        msd_times,
        msd_over_4t: msd_over_4t.iter().map(|e| e.value).collect(),
        msd_over_4t_err: msd_over_4t.iter().map(|e| e.err).collect(),
        msd_curve,
        green_kubo,
        longest_free_path: longest_free_path(done),
        collisions: total,
        seconds,
        collisions_per_second: run_now as f64 / seconds,
        resumed_batches: resumed,
        resumed_collisions: 0,
        audit,
        config: Some(cfg.clone()),
        batch_D: ds,
        batch_D_check: dc,
        batch_msd: done.iter().map(|b| b.msd.clone()).collect(),
        plan: None,
        pilot: None,
        meta: RunMeta::new(
            Some(cfg.seed),
            Some(cfg.batches as u64),
            cfg.precision,
            Some(threads),
        ),
    })
}

/// The mean free time, the mean time per hop and the collisions per hop, each as the mean over
/// the batches with its standard error.
fn counter_means(done: &[BatchResult]) -> [(f64, f64); 3] {
    let ratio = |f: &dyn Fn(&Counters) -> f64| {
        mean_se(&done.iter().map(|b| f(&b.counters)).collect::<Vec<_>>())
    };
    [
        ratio(&|c| c.time / c.collisions as f64),
        ratio(&|c| c.time / c.crossings as f64),
        ratio(&|c| c.collisions as f64 / c.crossings as f64),
    ]
}

/// The longest free path of any batch.
pub(super) fn longest_free_path(done: &[BatchResult]) -> f64 {
    done.iter()
        .map(|b| b.counters.longest_free_path)
        .fold(0.0, f64::max)
}
