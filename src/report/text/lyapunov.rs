//! The text `lorentz lyapunov` prints without a field (the tangent-space exponent and the
//! divergence of finite-precision orbits): the command line writes it to stdout, and Python's
//! `str()` of the result is the same text.

use serde::{Deserialize, Serialize};

use super::line;
use crate::statistics::{comparison, welch_dof};
use crate::verification::divergence::{DIVERGENCE_REFERENCE_BITS, Divergence};
use crate::verification::lyapunov::LyapunovReport;

/// The result of `lorentz lyapunov` without a field: the exponent and the divergence rows (none
/// where they were not measured).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LyapunovResult {
    /// The tangent-space exponent.
    pub tangent: LyapunovReport,
    /// One row per precision against the reference.
    pub divergence: Vec<Divergence>,
}

/// The text of a `lyapunov` result, line by line as the command line prints it.
pub fn lyapunov(r: &LyapunovResult) -> String {
    let mut out = String::new();
    let l = &r.tangent;
    line!(
        out,
        "{}: largest Lyapunov exponent (tangent space, {} batches x {} collisions{})\n  {:.5} ± {:.5} per collision, {:.5} ± {:.5} per unit time{}",
        l.scene,
        l.batches,
        l.collisions_per_batch,
        super::jumped(l.flights),
        l.per_collision,
        l.per_collision_err,
        l.per_time,
        l.per_time_err,
        comparison::few_samples_note(l.batches as usize, "batches")
    );
    let Some(first) = r.divergence.first() else {
        return out;
    };
    let starts = first.starts;
    line!(
        out,
        "divergence from a {DIVERGENCE_REFERENCE_BITS}-bit reference ({starts} initial conditions){}:",
        comparison::few_samples_note(starts as usize, "starts")
    );
    line!(
        out,
        "precision  horizon (collisions to 1e-3)   growth per collision   growth per unit time   growth per collision against λ (independent runs, Welch dof)"
    );
    for x in &r.divergence {
        let dof = welch_dof(
            x.rate_per_collision_err,
            starts as f64,
            l.per_collision_err,
            l.batches as f64,
        );
        let e = x.rate_per_collision_err.hypot(l.per_collision_err);
        let against = comparison::of(x.rate_per_collision - l.per_collision, e, dof);
        line!(
            out,
            "{:>9}  {:>12.1} ± {:<8.1}       {:.4} ± {:.4}        {:.4} ± {:.4}        {}",
            x.precision,
            x.horizon,
            x.horizon_err,
            x.rate_per_collision,
            x.rate_per_collision_err,
            x.rate_per_time,
            x.rate_per_time_err,
            against.describe("Welch")
        );
    }
    out
}
