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

/// The exponent per unit time to 5 decimals, or to 5 significant digits below 10⁻³ (small disks:
/// free flights of thousands of time units).
fn per_time(x: f64, err: f64) -> String {
    if x.abs() >= 1e-3 || x == 0.0 {
        format!("{x:.5} ± {err:.5}")
    } else {
        format!("{x:.4e} ± {err:.1e}")
    }
}

/// The text of a `lyapunov` result, line by line as the command line prints it.
pub fn lyapunov(r: &LyapunovResult) -> String {
    let mut out = String::new();
    let l = &r.tangent;
    line!(
        out,
        "{}: largest Lyapunov exponent (tangent space, {} batches x {} collisions{})\n  {:.5} ± {:.5} per collision, {} per unit time{}",
        l.scene,
        l.batches,
        l.collisions_per_batch,
        super::jumped(l.flights),
        l.per_collision,
        l.per_collision_err,
        per_time(l.per_time, l.per_time_err),
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
        // Where λ is large the growth from 10⁴u to 10⁻³ takes fewer than the 5 collisions a
        // start's fit needs, and fewer than 2 starts give a rate: no error, no comparison.
        let against = if x.rate_per_collision_err.is_finite() && x.rate_per_collision_err > 0.0 {
            let dof = welch_dof(
                x.rate_per_collision_err,
                starts as f64,
                l.per_collision_err,
                l.batches as f64,
            );
            let e = x.rate_per_collision_err.hypot(l.per_collision_err);
            comparison::of(x.rate_per_collision - l.per_collision, e, dof).describe("Welch")
        } else {
            "no comparison: fewer than 2 starts grew through 5 collisions between 1e4 u and 1e-3"
                .to_string()
        };
        // A rate of no start, or the error of fewer than 2, is "-", not NaN.
        let num = |e: f64| {
            if e.is_finite() {
                format!("{e:.4}")
            } else {
                "-".into()
            }
        };
        line!(
            out,
            "{:>9}  {:>12.1} ± {:<8.1}       {:>6} ± {:<6}        {:>6} ± {:<6}        {}",
            x.precision,
            x.horizon,
            x.horizon_err,
            num(x.rate_per_collision),
            num(x.rate_per_collision_err),
            num(x.rate_per_time),
            num(x.rate_per_time_err),
            against
        );
    }
    out
}

/// The text of `lyapunov --electric E`: the pair, the sum rule on average and per trajectory,
/// and the Kaplan–Yorke dimension.
pub fn driven(r: &crate::estimators::current::lyapunov::DrivenLyapunovReport) -> String {
    let mut out = String::new();
    let l = &r.tangent;
    let angle = r.config.motion.electric_angle.as_deref().unwrap_or("0");
    let e = r.config.motion.electric.as_deref().unwrap_or("0");
    let est = |v: f64, err: f64| super::estimate(v, err);
    line!(
        out,
        "{} at {angle}° (typed E = {e}): the Lyapunov pair of the thermostatted flow ({} trajectories x {} collisions after a warm-up of {}){}",
        l.scene,
        l.batches,
        l.collisions_per_batch,
        r.warm_up_collisions,
        comparison::few_samples_note(l.batches as usize, "batches")
    );
    line!(
        out,
        "  λ₊ {} per unit time ({:.5} ± {:.5} per collision); λ₋ {} per unit time ({:.5} ± {:.5} per collision)",
        est(r.lambda_plus, r.lambda_plus_err),
        l.per_collision,
        l.per_collision_err,
        est(r.lambda_minus, r.lambda_minus_err),
        r.lambda_minus_per_collision,
        r.lambda_minus_per_collision_err
    );
    line!(
        out,
        "  sum rule: λ₊ + λ₋ + ⟨α⟩ = {} with ⟨α⟩ = E·J = {}: {}; per trajectory within {:.1e} of exact (rounding bound {:.1e})",
        est(r.sum_rule.difference, r.sum_rule.err),
        est(r.contraction, r.contraction_err),
        r.sum_rule.describe("paired over the trajectories"),
        r.sum_rule_residual,
        r.sum_rule_residual_bound
    );
    line!(
        out,
        "  Kaplan–Yorke dimension 2 + λ₊/|λ₋| = {}; mean free time {:.6}",
        est(r.kaplan_yorke, r.kaplan_yorke_err),
        r.mean_free_time
    );
    out
}
