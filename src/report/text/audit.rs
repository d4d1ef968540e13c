//! The text `lorentz audit` prints (a shadow audit): the command line writes it to stdout, and Python's
//! `str()` of the result is the same text.

use super::line;
use crate::verification::shadow_audit::AuditReport;

/// The text of an `audit` result, line by line as the command line prints it.
pub fn audit(r: &AuditReport) -> String {
    let mut out = String::new();
    let s = &r.summary;
    let c = &r.config;
    let field = match (&c.motion.field, c.field_exact()) {
        (Some(b), Ok(Some(_))) => {
            format!(" in the field B = {b} (arcs, against their running error bound)")
        }
        _ => match &c.motion.electric {
            Some(e) if matches!(c.exact_motion(), Ok(Some(_))) => format!(
                " under the thermostatted field E = {e} at {} degrees (against the running \
                 error bound and the closed forms)",
                c.motion.electric_angle.as_deref().unwrap_or("0")
            ),
            _ => String::new(),
        },
    };
    line!(
        out,
        "shadow audit, {}{field}: {} events of {} ({} collisions, {} batches, seed {}) replayed at {} bits in {:.1} s",
        c.scene,
        s.audited,
        r.events,
        c.collisions,
        c.batches,
        c.seed,
        c.reference_bits,
        r.seconds
    );
    line!(
        out,
        "outside the error model: {}   ambiguous at f64 resolution: {}   f64 chose another obstacle: {}",
        s.outside,
        s.ambiguous,
        s.different_choice
    );
    let q = &r.quantiles;
    line!(out, "one-step error            median      99%         max");
    for (name, v) in [
        ("flight time", q.time_error),
        ("contact point", q.position_error),
        ("velocity", q.velocity_error),
        ("time error / bound", q.time_error_over_bound),
    ]
    .into_iter()
    .chain(
        [
            ("position error / bound", q.position_error_over_bound),
            ("velocity error / bound", q.velocity_error_over_bound),
        ]
        .into_iter()
        .filter_map(|(n, v)| v.map(|v| (n, v))),
    ) {
        line!(
            out,
            "{name:<22} {:>10.2e} {:>10.2e} {:>10.2e}",
            v.median,
            v.p99,
            v.max
        );
    }
    jumps(&mut out, r);
    for e in s.outside_events.iter().take(5) {
        line!(
            out,
            "outside: state bits {:x?} excluded {:?}: {:?}",
            e.state_bits,
            e.excluded,
            e.check
        );
    }
    out
}

/// One line per histogram: median, 99 % and maximum.
fn quantile_lines(
    out: &mut String,
    rows: &[(&str, &crate::verification::log_histogram::LogHistogram)],
) {
    for (name, h) in rows {
        line!(
            out,
            "{name:<22} {:>10.2e} {:>10.2e} {:>10.2e}",
            h.quantile(0.5),
            h.quantile(0.99),
            h.max
        );
    }
}

/// The lines on the long flights jumped on the triangular lattice, where the run jumped them.
fn triangular_jumps(out: &mut String, r: &AuditReport) {
    let j = &r.summary.triangular_jumps;
    if j.audited == 0 {
        return;
    }
    line!(
        out,
        "long flights jumped: {} replayed by the MPFR trap walk ({} crossings, longest {}); \
         outside the model: {}",
        j.audited,
        j.crossings,
        j.longest,
        j.outside
    );
    quantile_lines(
        out,
        &[
            ("jump time error / bound", &j.time_error_over_bound),
            ("landing error / bound", &j.position_error_over_bound),
        ],
    );
    for (bits, c) in j.outside_jumps.iter().take(5) {
        line!(out, "outside: jump from state bits {bits:x?}: {c:?}");
    }
}

/// The lines on the long flights jumped, where the run jumped them.
fn jumps(out: &mut String, r: &AuditReport) {
    triangular_jumps(out, r);
    let j = &r.summary.jumps;
    if j.audited == 0 {
        return;
    }
    line!(
        out,
        "long flights jumped: {} replayed against the exact column walk ({} columns, longest {}); \
         outside the model: {}   corner ties: {}",
        j.audited,
        j.columns,
        j.longest,
        j.outside,
        j.ambiguous
    );
    quantile_lines(
        out,
        &[
            ("jump time error / bound", &j.time_error_over_bound),
            ("entry error / bound", &j.position_error_over_bound),
            ("candidate |D| / window", &j.candidate_over_window),
        ],
    );
    for e in j.outside_jumps.iter().take(5) {
        line!(
            out,
            "outside: jump from state bits {:x?}: {:?}",
            e.state_bits,
            e.check
        );
    }
}
