//! The text `lorentz shadow` prints (true orbits near f64 segments): the command line writes it
//! to stdout, and Python's `str()` of the result is the same text.

use super::line;
use crate::verification::curved::ExactMotion;
use crate::verification::shadowing::ShadowReport;

/// The text of a `shadow` result, line by line as the command line prints it.
pub fn shadow(r: &ShadowReport) -> String {
    let mut out = String::new();
    let opt = |x: Option<f64>| x.map_or_else(|| "-".to_string(), |v| format!("{v:.2e}"));
    line!(
        out,
        "{}{}: {} segments of {} collisions at {} bits: {} converged, {} certified; median delta {}, max {}",
        r.scene,
        match (
            r.config.exact_motion(),
            &r.config.motion.field,
            &r.config.motion.electric
        ) {
            (Ok(Some(ExactMotion::Field(_))), Some(b), _) =>
                format!(" in the field B = {b} (arcs)"),
            (Ok(Some(ExactMotion::Thermostat { .. })), _, Some(e)) => format!(
                " under the thermostatted field E = {e} at {} deg",
                r.config.motion.electric_angle.as_deref().unwrap_or("0")
            ),
            _ => String::new(),
        },
        r.segments.len(),
        r.config.collisions_per_segment,
        r.config.reference_bits,
        r.converged,
        r.certified,
        opt(r.median_delta),
        opt(r.max_delta)
    );
    line!(
        out,
        "segment  conv  iter     delta  residual  2K|F(y0)|         K  2K*eps  min cos phi  failure"
    );
    for s in &r.segments {
        let sh = &s.shadow;
        line!(
            out,
            "{:>7}  {:>4}  {:>4}  {:>8}  {:>8}  {:>9}  {:>8}  {:>6}  {:>11}  {}",
            s.segment,
            if sh.converged { "yes" } else { "no" },
            sh.iterations,
            opt(sh.delta),
            opt(sh.residual),
            opt(sh.a_priori_bound),
            opt(sh.inverse_bound),
            opt(sh.correction_bound),
            opt(sh.min_cos_phi),
            sh.failure.as_deref().unwrap_or("")
        );
    }
    out
}
