//! The text `lorentz superdiffusion` prints (an infinite horizon against the exact corridor
//! constants): the command line writes it to stdout, and Python's `str()` of the result is the
//! same text.

use super::{line, sigmas, sigmas_unconverged};
use crate::estimators::superdiffusion::SuperdiffusionReport;

/// Corridor widths the text lists (the result file has them all).
const WIDTHS_SHOWN: usize = 8;

/// The text of a `superdiffusion` result, line by line as the command line prints it.
pub fn superdiffusion(r: &SuperdiffusionReport) -> String {
    let mut out = String::new();
    let n = r.meta.batches.unwrap_or(2) as usize;
    line!(
        out,
        "{}: superdiffusion ({} batches x {} collisions, mean free path l = {:.6}{})",
        r.scene,
        n,
        r.collisions_per_batch,
        r.mean_free_path,
        super::jumped(r.flights)
    );
    // The widest few: at small radii there are thousands (2388 at r = 1/100).
    let mut widths: Vec<String> = r
        .corridors
        .iter()
        .take(WIDTHS_SHOWN)
        .map(|c| format!("{:.6}", c.width))
        .collect();
    if r.corridors.len() > WIDTHS_SHOWN {
        widths.push("...".into());
    }
    line!(
        out,
        "exact ({} corridors, widths {}): D_sup = {:.6e}  C_flow = {:.6e}  C_map = {:.6e}  <dx^2> ~ {:.6e} t ln t",
        r.corridors.len(),
        widths.join(", "),
        r.d_sup_exact,
        r.c_flow_exact,
        r.c_map_exact,
        r.msd_log_slope_exact
    );
    estimates(&mut out, r, n);
    lags(&mut out, r);
    law(&mut out, r);
    out
}

/// The fitted constants, each against its exact value.
fn estimates(out: &mut String, r: &SuperdiffusionReport, n: usize) {
    line!(out, "measured, each against its exact value:");
    let l = r.mean_free_path;
    let row = |out: &mut String, what: &str, x: f64, e: f64, exact: f64, range, from| {
        out.push_str(&estimate(what, [x, e, exact], range, from, l, n));
    };
    let from = crate::estimators::superdiffusion::CONVERGED_FROM;
    match (
        r.c_flow_tail,
        r.c_flow_tail_err,
        r.c_map_tail,
        r.c_map_tail_err,
        r.tail_fit,
    ) {
        (Some(f), Some(fe), Some(m), Some(me), Some(range)) => {
            row(
                out,
                "C_flow  (s P(tau > s) = C + B/s)",
                f,
                fe,
                r.c_flow_exact,
                range,
                from.tails,
            );
            row(
                out,
                "C_map   (s^2 mu(tau > s) = C + B/s)",
                m,
                me,
                r.c_map_exact,
                range,
                from.tails,
            );
        }
        _ => line!(
            out,
            "  C_flow, C_map: not fitted (every batch needs 100 flights longer than the tail fit's start, in mean free paths, at two lags; use more collisions)"
        ),
    }
    row(
        out,
        "D_sup   (t C_xx(t), weighted mean)",
        r.d_sup_vacf,
        r.d_sup_vacf_err,
        r.d_sup_exact,
        r.vacf_fit,
        from.vacf,
    );
    row(
        out,
        "2D_sup  (slope of <dx^2>/t in ln t)",
        r.msd_log_slope,
        r.msd_log_slope_err,
        r.msd_log_slope_exact,
        r.msd_fit,
        from.msd,
    );
    line!(
        out,
        "  intercept of <dx^2>/t in ln t      {:.6e} ± {:.1e}",
        r.msd_log_intercept,
        r.msd_log_intercept_err
    );
    line!(
        out,
        "  (the last two errors: batch {:.1e} and {:.1e}, with the bound on flights longer than the longest seen, L = {:.1}: {:.1e} and {:.1e})",
        r.d_sup_vacf_err_batch,
        r.msd_log_slope_err_batch,
        r.longest_flight,
        r.d_sup_vacf_err_unsampled,
        r.msd_log_slope_err_unsampled
    );
}

/// One line per lag, each quantity over its exact value.
fn lags(out: &mut String, r: &SuperdiffusionReport) {
    line!(
        out,
        "per lag (relative to the exact value; batch errors, and in [ ] the bound on unsampled flights):"
    );
    line!(
        out,
        "      t/l            t   s P(tau>s)/C_flow  s^2 mu(tau>s)/C_map   t C(t)/D_sup   local slope/2D_sup"
    );
    let rel = |x: f64, e: f64, exact: f64| format!("{:>7.4} ± {:<7.4}", x / exact, e / exact);
    for l in &r.lags {
        let slope = match (l.msd_local_slope, l.msd_local_slope_err) {
            (Some(s), Some(e)) => format!(
                "{} [{:.4}]",
                rel(s, e, r.msd_log_slope_exact),
                l.msd_local_slope_unsampled.unwrap_or(0.0) / r.msd_log_slope_exact
            ),
            _ => String::new(),
        };
        line!(
            out,
            "  {:>7} {:>12.4}   {}  {}  {}  {}",
            l.t_over_ell,
            l.t,
            rel(l.s_p_flow, l.s_p_flow_err, r.c_flow_exact),
            rel(l.s2_p_map, l.s2_p_map_err, r.c_map_exact),
            format!(
                "{} [{:.4}]",
                rel(l.t_c, l.t_c_err, r.d_sup_exact),
                l.t_c_unsampled / r.d_sup_exact
            ),
            slope
        );
    }
}

/// One line per octave of the limit law.
fn law(out: &mut String, r: &SuperdiffusionReport) {
    line!(
        out,
        "limit law of u = dx / sqrt(D_sup t ln t) (-> N(0, 1)):"
    );
    line!(
        out,
        "             t   (IQR/1.349)^2 (-> 1)   <u^2> (-> 2)       Kolmogorov distance   samples"
    );
    for l in &r.limit_law {
        line!(
            out,
            "  {:>12.4}   {:>7.4} ± {:<7.4}      {:>7.4} ± {:<7.4}   {:.4}                {}",
            l.t,
            l.variance_ratio,
            l.variance_ratio_err,
            l.second_moment_ratio,
            l.second_moment_ratio_err,
            l.ks_distance,
            l.samples
        );
    }
}

/// One fitted constant against its exact value: `[x, err, exact]` over the lag window `range`,
/// with a verdict only where the window starts at or after `from` mean free paths `l`.
fn estimate(
    what: &str,
    [x, e, exact]: [f64; 3],
    range: [f64; 2],
    from: f64,
    l: f64,
    n: usize,
) -> String {
    let start = range[0] / l;
    // The window's first lag is a grid time, rounded from the mean free times asked for.
    let verdict = if start < from * (1.0 - 1e-9) {
        let why = format!(
            "the window starts at {}l, below the {from}l from which this estimator has converged",
            if (start - start.round()).abs() < 1e-9 {
                format!("{start:.0}")
            } else {
                format!("{start:.3}")
            }
        );
        sigmas_unconverged(x, e, exact, n, &why)
    } else {
        sigmas(x, e, exact, n)
    };
    let mut out = String::new();
    line!(
        out,
        "  {what:<36} {x:.6e} ± {e:.1e}  over t in [{:.4}, {:.4}]  ({verdict})",
        range[0],
        range[1],
    );
    out
}
