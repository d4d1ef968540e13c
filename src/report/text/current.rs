//! The text `lorentz diffusion --electric E` prints (the steady state under the thermostatted
//! field): the command line writes it to stdout, and Python's `str()` of the result is the same
//! text.

use super::{estimate, line};
use crate::estimators::current::{CurrentReport, DriftTensor};

/// The text of a run under the thermostat, line by line as the command line prints it.
pub fn current(r: &CurrentReport) -> String {
    let mut out = String::new();
    let m = &r.meta;
    let table = &r.config.table;
    let (e, angle) = match &table.motion {
        crate::scenes::spec::Motion::Thermostat { field, angle } => {
            (field.as_str(), angle.as_str())
        }
        _ => ("0", "0"),
    };
    line!(
        out,
        "periodic Lorentz gas under a thermostatted electric field, {}, E = {} at {}° ({} precision, {} engine, seed {}, {} batches, {:.3e} collisions, {}, {:.1} s, {:.3e} collisions/s)",
        r.scene,
        e,
        angle,
        m.precision,
        m.engine,
        m.seed.unwrap_or_default(),
        m.batches.unwrap_or_default(),
        r.collisions as f64,
        crate::report::counted(m.threads.unwrap_or_default() as u64, "thread"),
        r.seconds,
        r.collisions_per_second
    );
    line!(
        out,
        "current       : J_x {}, J_y {}   (along E {}, across {})",
        estimate(r.J_x, r.J_x_err),
        estimate(r.J_y, r.J_y_err),
        estimate(r.J_parallel, r.J_parallel_err),
        estimate(r.J_perp, r.J_perp_err)
    );
    line!(
        out,
        "mobility J/E  = {}   (→ D as E → 0: the Einstein relation)",
        estimate(r.mobility, r.mobility_err)
    );
    line!(
        out,
        "entropy production E·J = ⟨α⟩ = {}",
        estimate(r.entropy_production, r.entropy_production_err)
    );
    line!(
        out,
        "Lyapunov      : λ₊ {}, λ₋ {} per unit time; λ₊ + λ₋ + ⟨α⟩ = {}   (sum rule; per trajectory within {:.1e} of exact, rounding bound {:.1e}); Kaplan–Yorke dimension {}",
        estimate(r.lambda_plus, r.lambda_plus_err),
        estimate(r.lambda_minus, r.lambda_minus_err),
        estimate(r.sum_rule, r.sum_rule_err),
        r.sum_rule_residual,
        r.sum_rule_residual_bound,
        estimate(r.kaplan_yorke, r.kaplan_yorke_err)
    );
    tensor(&mut out, "about the drift", &r.diffusion, r);
    tensor(&mut out, "check window", &r.diffusion_check, r);
    line!(
        out,
        "mean free time = {}   (without the field {:.6}); each batch {:.4e} in flight after a warm-up of {:.4e}",
        estimate(r.mean_free_time, r.mean_free_time_err),
        r.mean_free_time_no_field,
        r.duration,
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
