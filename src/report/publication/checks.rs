//! The audit's list of checks and the helpers every kind's checks share: the record against the
//! configuration, and indices chosen by the file's digest.

use super::{Check, Verdict};
use crate::engine::metadata::RunMeta;

/// The checks of one audit, in order.
pub(super) struct Checks(pub(super) Vec<Check>);

impl Checks {
    pub(super) fn add(
        &mut self,
        group: &str,
        name: &str,
        verdict: Verdict,
        detail: String,
        numbers: &[(&str, f64)],
    ) {
        self.0.push(Check {
            group: group.into(),
            name: name.into(),
            verdict,
            detail,
            numbers: numbers.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
        });
    }

    pub(super) fn pass_if(
        &mut self,
        ok: bool,
        group: &str,
        name: &str,
        detail: String,
        numbers: &[(&str, f64)],
    ) {
        let v = if ok { Verdict::Pass } else { Verdict::Fail };
        self.add(group, name, v, detail, numbers);
    }

    /// A SKIP of `name` for `reason`.
    pub(super) fn skip(&mut self, group: &str, name: &str, reason: String) {
        self.add(group, name, Verdict::Skip, reason, &[]);
    }
}

/// What in a recorded `meta` block disagrees with the configuration: its seed, its number of
/// batches, its precision.
pub(super) fn meta_problems(
    meta: &RunMeta,
    seed: Option<u64>,
    batches: Option<u64>,
    precision: &str,
) -> Vec<String> {
    let mut bad = Vec::new();
    if meta.seed != seed {
        bad.push(format!("meta.seed {:?}, configured {seed:?}", meta.seed));
    }
    if meta.batches != batches {
        bad.push(format!(
            "meta.batches {:?}, configured {batches:?}",
            meta.batches
        ));
    }
    if meta.precision != precision {
        bad.push(format!(
            "meta.precision {:?}, configured {precision:?}",
            meta.precision
        ));
    }
    bad
}

/// The check that the record agrees with its configuration (`bad` lists what does not).
pub(super) fn record_check(bad: Vec<String>, checks: &mut Checks) {
    checks.pass_if(
        bad.is_empty(),
        "reproducibility",
        "the record agrees with its configuration",
        if bad.is_empty() {
            "gap, work, seed, batches, precision and closed forms as configured".into()
        } else {
            bad.join("; ")
        },
        &[],
    );
}

/// An index below `n` chosen by the file's digest: not known in advance to whoever edits the
/// file.
pub(super) fn pick_from_digest(sha: &str, n: u64) -> u64 {
    let head = sha
        .get(..16)
        .and_then(|h| u64::from_str_radix(h, 16).ok())
        .unwrap_or(0);
    head % n.max(1)
}

/// A batch index below `batches` chosen by the file's digest.
pub(super) fn batch_from_digest(sha: &str, batches: u32) -> u32 {
    // Below `batches`, so it fits.
    pick_from_digest(sha, u64::from(batches)) as u32
}
