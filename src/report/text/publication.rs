//! The text `lorentz report` prints (the publication audit of a result file): the command line
//! writes it to stdout, and Python's `str()` of the result is the same text.

use std::path::Path;

use super::line;
use crate::report::publication::{PublicationReport, Verdict};

/// The text of a `report` result written into `out`, line by line as the command line prints
/// it: the verdict first (with the file, the checks and the work), the headline, one line per
/// check, and where the documents were written.
pub fn publication(r: &PublicationReport, out: &Path) -> String {
    let mut text = String::new();
    let skipped = r
        .checks
        .iter()
        .filter(|c| c.verdict == Verdict::Skip)
        .count();
    line!(
        text,
        "{}: {} ({} checks, {skipped} skipped; {:.3e} collisions re-run, {:.1} s)",
        r.provenance.result_file,
        r.verdict_stated(),
        r.checks.len(),
        r.rerun_collisions as f64,
        r.seconds,
    );
    let head: Vec<String> = r
        .headline
        .iter()
        .map(|h| format!("{} = {}", h.name, h.value))
        .collect();
    line!(text, "{}", head.join(", "));
    for c in &r.checks {
        line!(
            text,
            "{}  {:<16} {}: {}",
            c.verdict,
            c.group,
            c.name,
            c.detail
        );
    }
    line!(text, "written: {}/report.{{md,html,json}}", out.display());
    text
}
