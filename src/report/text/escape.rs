//! The text `lorentz escape` prints (D(w) from the escape rate): the command line writes it to stdout, and Python's
//! `str()` of the result is the same text.

use super::line;
use crate::estimators::escape::EscapeReport;

/// The text of an `escape` result, line by line as the command line prints it.
pub fn escape(r: &EscapeReport) -> String {
    let mut out = String::new();
    let m = &r.meta;
    line!(
        out,
        "escape rate from open strips, w = {}  (seed {}, {} batches per width, {}, {:.3e} events, {:.1} s)",
        r.w,
        m.seed.unwrap_or_default(),
        r.batches_per_width,
        crate::report::counted(m.threads.unwrap_or_default() as u64, "thread"),
        r.events as f64,
        r.seconds
    );
    line!(
        out,
        "{:>9} {:>6} {:>10} {:>10} {:>24} {:>22} {:>10}",
        "L",
        "L/a",
        "particles",
        "tail t0",
        "gamma",
        "D_eff",
        "tail chk"
    );
    for w in &r.widths {
        line!(
            out,
            "{:>9.4} {:>6.1} {:>10} {:>10.1} {:>13.6e} ± {:>8.2e} {:>11.6} ± {:>8.6} {:>+8.1} σ",
            w.L,
            w.L_over_a,
            w.particles,
            w.tail_start,
            w.gamma,
            w.gamma_err,
            w.D_eff,
            w.D_eff_err,
            w.tail_check_sigma
        );
    }
    line!(out, "fit: {}", r.finite_size_form);
    line!(
        out,
        "D_escape       = {}   (chi2/dof = {:.2} with {} dof{})",
        super::estimate(r.D_escape, r.D_escape_err),
        r.chi2_per_dof,
        r.dof,
        if r.errors_scaled {
            "; errors scaled by sqrt(chi2/dof)"
        } else {
            ""
        }
    );
    line!(
        out,
        "slope c        = {:.5} ± {:.5}   boundary shift b = {:.4} ± {:.4}",
        r.slope,
        r.slope_err,
        r.boundary_shift,
        r.boundary_shift_err
    );
    line!(out, "D_MZ           = {:.6}", r.D_MZ);
    out
}
