//! The text `lorentz diffusion` prints: the command line writes it to stdout, and Python's
//! `str()` of a result is the same text.

use super::{line, sigmas};
use crate::estimators::diffusion::DiffusionReport;
use crate::statistics::comparison;

/// The text of a diffusion result, line by line as the command line prints it.
pub fn diffusion(r: &DiffusionReport) -> String {
    let mut out = super::first_line(
        format_args!("periodic Lorentz gas, w = {}", r.w),
        &r.meta,
        (r.collisions, r.seconds, Some(r.collisions_per_second)),
        true,
    );
    d_lines(&mut out, r);
    identity_lines(&mut out, r);
    curve_lines(&mut out, r);
    plan_lines(&mut out, r);
    if let Some(a) = &r.audit {
        line!(
            out,
            "self-audit     : {} events replayed in MPFR, {} outside the error model, worst time error / bound {:.2e}",
            a.audited,
            a.outside,
            a.time_error_over_bound.max
        );
    }
    if r.resumed_collisions > 0 {
        line!(
            out,
            "({} finished batches and {:.3e} collisions in all resumed from the checkpoint; the \
             speed counts this run's collisions only)",
            r.resumed_batches,
            r.resumed_collisions as f64
        );
    }
    out
}

/// The MSD curve's extent and D by Green–Kubo against the Einstein D (runs on the log grid).
fn curve_lines(out: &mut String, r: &DiffusionReport) {
    let Some(c) = &r.msd_curve else {
        return;
    };
    let (first, last) = (c.times.first().copied(), c.times.last().copied());
    line!(
        out,
        "MSD curve      : {} times from {:.4} to {:.4e} (MSD, velocity autocorrelation and \
         Green-Kubo integral, in the JSON result's msd_curve)",
        c.times.len(),
        first.unwrap_or(f64::NAN),
        last.unwrap_or(f64::NAN)
    );
    let g = &r.green_kubo;
    match (g.D_green_kubo, g.D_green_kubo_err) {
        (Some(d), Some(e)) => {
            let n = r.batch_D.len();
            let diff = comparison::of(
                g.D_minus_D_green_kubo.unwrap_or(f64::NAN),
                g.D_minus_D_green_kubo_err.unwrap_or(f64::NAN),
                comparison::batch_dof(n),
            );
            line!(
                out,
                "D (Green-Kubo) = {d:.6} ± {e:.6}   (running integral over [{}τ, {}τ]; D − D_green_kubo = \
                 {:+.6} ± {:.6}, {})",
                r.window.lo,
                r.window.hi,
                diff.difference,
                diff.err,
                diff.describe(&format!("paired over {n} batches"))
            );
        }
        _ => line!(
            out,
            "D (Green-Kubo) : no grid time inside [{}τ, {}τ] (more collisions per batch reach it)",
            r.window.lo,
            r.window.hi
        ),
    }
}

/// The relative error this run reached against a planned one, and what the next decade needs.
fn plan_lines(out: &mut String, r: &DiffusionReport) {
    match &r.pilot {
        Some(p) if r.collisions < p.planned_collisions => line!(
            out,
            "plan only      : a pilot of {:.3e} collisions for {} %; the planned run was not run",
            p.collisions as f64,
            100.0 * p.rel_err_target
        ),
        Some(p) => line!(
            out,
            "planned run    : for {} % from a pilot of {:.3e} collisions ({:.3} %){}; reached {:.3} %",
            100.0 * p.rel_err_target,
            p.collisions as f64,
            100.0 * p.rel_err,
            if p.continued { ", continued" } else { "" },
            100.0 * r.D_err / r.D.abs()
        ),
        None => {}
    }
    if let Some(p) = &r.plan {
        line!(
            out,
            "precision plan : {} % needs {:.2e} collisions, about {} here (the error falls as \
             1/sqrt(collisions); a run planned for a relative error stops there)",
            100.0 * p.rel_err,
            p.collisions as f64,
            crate::engine::progress_lines::clock(p.seconds)
        );
    }
}

/// D over both windows, their paired difference (the command line adds a warning on stderr when
/// they disagree), and
/// the closed forms D_MZ and D_Bo.
fn d_lines(out: &mut String, r: &DiffusionReport) {
    line!(
        out,
        "D              = {}   ({:.3} %, MSD slope over [{}τ, {}τ]){}{}",
        super::estimate(r.D, r.D_err),
        100.0 * r.D_err / r.D,
        r.window.lo,
        r.window.hi,
        comparison::few_samples_note(r.batch_D.len(), "batches"),
        super::negative_note(r.D, r.D_err, bound_of(r.batch_D.len()))
    );
    let n = r.batch_D.len();
    let window_check = comparison::of(
        r.D_minus_D_check,
        r.D_minus_D_check_err,
        comparison::batch_dof(n),
    );
    line!(
        out,
        "D (check)      = {}   (MSD slope over [{}τ, {}τ]; D − D_check = {:+.6} ± {:.6}, {})",
        super::estimate(r.D_check, r.D_check_err),
        r.check_window.lo,
        r.check_window.hi,
        r.D_minus_D_check,
        r.D_minus_D_check_err,
        window_check.describe(&format!("paired over {n} batches"))
    );
    line!(
        out,
        "D_MZ           = {:.6}           D/D_MZ = {:.4}",
        r.D_MZ,
        r.D / r.D_MZ
    );
    line!(out, "D_Bo           = {:.6}", r.D_Bo);
}

/// The measured exact identities against their closed forms, each with its bound and verdict.
fn identity_lines(out: &mut String, r: &DiffusionReport) {
    let n = r.batch_D.len();
    line!(
        out,
        "mean free path = {:.7} ± {:.7}   exact {:.7}  ({})",
        r.mean_free_path,
        r.mean_free_path_err,
        r.mean_free_path_exact,
        sigmas(
            r.mean_free_path,
            r.mean_free_path_err,
            r.mean_free_path_exact,
            n
        )
    );
    line!(
        out,
        "mean hop time  = {:.6} ± {:.6}   exact {:.6}  ({})",
        r.tau_hop,
        r.tau_hop_err,
        r.tau_hop_exact,
        sigmas(r.tau_hop, r.tau_hop_err, r.tau_hop_exact, n)
    );
    line!(
        out,
        "collisions/hop = {:.5} ± {:.5}   exact {:.5}  ({})",
        r.collisions_per_hop,
        r.collisions_per_hop_err,
        r.collisions_per_hop_exact,
        sigmas(
            r.collisions_per_hop,
            r.collisions_per_hop_err,
            r.collisions_per_hop_exact,
            n
        )
    );
}

/// The 4σ-equivalent bound of an error from `n` batches.
fn bound_of(n: usize) -> f64 {
    comparison::agreement_bound(comparison::batch_dof(n))
}
