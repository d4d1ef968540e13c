//! The text `lorentz audit` prints (a shadow audit): the command line writes it to stdout, and Python's
//! `str()` of the result is the same text.

use super::line;
use crate::verification::shadow_audit::AuditReport;

/// The text of an `audit` result, line by line as the command line prints it.
pub fn audit(r: &AuditReport) -> String {
    let mut out = String::new();
    let s = &r.summary;
    let c = &r.config;
    let field = match (&c.field, c.field_exact()) {
        (Some(b), Ok(Some(_))) => {
            format!(" in the field B = {b} (arcs, against their running error bound)")
        }
        _ => String::new(),
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

/// The lines on the long flights jumped, where the run jumped them.
fn jumps(out: &mut String, r: &AuditReport) {
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
    for (name, h) in [
        ("jump time error / bound", &j.time_error_over_bound),
        ("entry error / bound", &j.position_error_over_bound),
        ("candidate |D| / window", &j.candidate_over_window),
    ] {
        line!(
            out,
            "{name:<22} {:>10.2e} {:>10.2e} {:>10.2e}",
            h.quantile(0.5),
            h.quantile(0.99),
            h.max
        );
    }
    for e in j.outside_jumps.iter().take(5) {
        line!(
            out,
            "outside: jump from state bits {:x?}: {:?}",
            e.state_bits,
            e.check
        );
    }
}
