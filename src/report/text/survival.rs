//! The text `lorentz escape --repeller` (or `--open FILE`) prints (an open table's escape rate,
//! Lyapunov exponent and KS entropy by survival): the command line writes it to stdout, and
//! Python's `str()` of the result is the same text.

use super::line;
use crate::estimators::escape::survival::SurvivalReport;

/// The text of a survival result, line by line as the command line prints it.
pub fn survival(r: &SurvivalReport) -> String {
    let mut out = String::new();
    let m = &r.meta;
    let n0 = r.config.window;
    line!(
        out,
        "escape from the {} by survival  (seed {}, {} particles in {} batches, {}, {:.3e} collisions, {:.1} s)",
        r.table,
        m.seed.unwrap_or_default(),
        r.config.particles,
        r.batches,
        crate::report::counted(m.threads.unwrap_or_default() as u64, "thread"),
        r.collisions as f64,
        r.seconds
    );
    line!(out, "start: {}", r.start_density);
    line!(
        out,
        "window from collision {n0}: gamma = Z_(n+1) = Z_n root of the time-weighted survival"
    );
    let pm = |x: f64, e: f64| format!("{x:.9} ± {e:.1e}");
    line!(
        out,
        "  escape rate      gamma  = {}",
        pm(r.gamma, r.gamma_err)
    );
    line!(
        out,
        "  window from {}:   gamma  = {}   ({:+.2} σ from the window at {n0})",
        n0 + 1,
        pm(r.gamma_late, r.gamma_late_err),
        r.window_check_sigma
    );
    line!(
        out,
        "  Lyapunov         lambda = {}",
        pm(r.lyapunov, r.lyapunov_err)
    );
    line!(
        out,
        "  KS entropy       h_KS   = {}",
        pm(r.entropy, r.entropy_err)
    );
    line!(
        out,
        "  mean flight time <T>   = {}",
        pm(r.mean_flight_time, r.mean_flight_time_err)
    );
    line!(
        out,
        "errors: standard errors over the {} batches (95 %: × {:.3}, Student-t with {} dof)",
        r.batches,
        crate::statistics::student_t_quantile(f64::from(r.batches - 1), 0.025),
        r.batches - 1
    );
    line!(out, "window start   gamma                    lambda");
    for w in &r.windows {
        line!(
            out,
            "{:>12}   {:<22} {}",
            w.start,
            pm(w.gamma, w.gamma_err),
            pm(w.lyapunov, w.lyapunov_err)
        );
    }
    if let (Some(ratio), Some(bias)) = (r.transient_ratio, r.transient_bias) {
        line!(
            out,
            "transient: ratio {ratio:.3} per collision, so gamma at window {n0} is biased by about \
             {bias:+.1e} (gamma - bias = {:.9})",
            r.gamma - bias
        );
    }
    let fractions: Vec<String> = r.survival.iter().map(|s| format!("{s:.4e}")).collect();
    line!(
        out,
        "surviving fraction at collision 0..{}: {}",
        r.survival.len() - 1,
        fractions.join(" ")
    );
    out
}
