//! The text `lorentz diffusion --electric E` prints (the steady state under the thermostatted
//! field): the command line writes it to stdout, and Python's `str()` of the result is the same
//! text.

use super::{estimate, line};
use crate::estimators::current::{CurrentReport, DriftTensor};

/// The text of a run under the thermostat, line by line as the command line prints it.
pub fn current(r: &CurrentReport) -> String {
    let (e, angle) = match &r.config.table.motion {
        crate::scenes::spec::Motion::Thermostat { field, angle } => {
            (field.as_str(), angle.as_str())
        }
        _ => ("0", "0"),
    };
    let title = format_args!(
        "periodic Lorentz gas under a thermostatted electric field, {}, E = {e} at {angle}°",
        r.scene
    );
    let counts = (r.collisions, r.seconds, Some(r.collisions_per_second));
    let mut out = super::first_line(title, &r.meta, counts, false);
    let s = &r.steady;
    let est = |(v, e): (f64, f64)| estimate(v, e);
    let (jx, jy) = (est((s.J_x, s.J_x_err)), est((s.J_y, s.J_y_err)));
    let (along, across) = (
        est((s.J_parallel, s.J_parallel_err)),
        est((s.J_perp, s.J_perp_err)),
    );
    line!(
        out,
        "current       : J_x {jx}, J_y {jy}   (along E {along}, across {across})"
    );
    let mobility = est((s.mobility, s.mobility_err));
    let production = est((s.entropy_production, s.entropy_production_err));
    line!(
        out,
        "mobility J/E  = {mobility}   (→ D as E → 0: the Einstein relation); entropy production E·J = ⟨α⟩ = {production}"
    );
    let (plus, minus) = (
        est((s.lambda_plus, s.lambda_plus_err)),
        est((s.lambda_minus, s.lambda_minus_err)),
    );
    let (rule, ky) = (
        est((s.sum_rule, s.sum_rule_err)),
        est((s.kaplan_yorke, s.kaplan_yorke_err)),
    );
    line!(
        out,
        "Lyapunov      : λ₊ {plus}, λ₋ {minus} per unit time; λ₊ + λ₋ + ⟨α⟩ = {rule}   (sum rule; per trajectory within {:.1e} of exact, rounding bound {:.1e}); Kaplan–Yorke dimension {ky}",
        s.sum_rule_residual,
        s.sum_rule_residual_bound
    );
    tensor(&mut out, "about the drift", &s.diffusion, r);
    tensor(&mut out, "check window", &r.diffusion_check, r);
    line!(
        out,
        "mean free time = {}   (without the field {:.6}); each batch {:.4e} in flight after a warm-up of {:.4e}",
        estimate(s.mean_free_time, s.mean_free_time_err),
        r.mean_free_time_no_field,
        r.measured_time,
        r.warm_up
    );
    out
}

/// One window's tensor line.
fn tensor(out: &mut String, what: &str, t: &DriftTensor, r: &CurrentReport) {
    let w = if what == "check window" {
        r.check_window
    } else {
        r.window
    };
    line!(
        out,
        "D {what:<15}: along E {}, across {}; D_xx {}, D_yy {}, D_xy {}   (over [{}τ, {}τ], τ = {:.4})",
        estimate(t.D_parallel, t.D_parallel_err),
        estimate(t.D_perp, t.D_perp_err),
        estimate(t.D_xx, t.D_xx_err),
        estimate(t.D_yy, t.D_yy_err),
        estimate(t.D_xy, t.D_xy_err),
        w.lo,
        w.hi,
        r.tau
    );
}
