//! The audit's list of checks and the helpers every kind's checks share: the record against the
//! configuration, and indices drawn at random.

use super::{Check, Verdict};
use crate::engine::metadata::RunMeta;
use crate::statistics::comparison::{MIN_VERDICT_DOF, no_verdict};
use crate::statistics::normal_sigma_equivalent_t;

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

    /// The PASS or FAIL `ok` of a statistical check whose bound has `dof` degrees of freedom —
    /// or, below [`MIN_VERDICT_DOF`], a SKIP saying why: a bound from too few batches means
    /// nothing, so the check is not a PASS and the audit is INCOMPLETE.
    pub(super) fn judge(
        &mut self,
        dof: f64,
        ok: bool,
        (group, name): (&str, &str),
        detail: String,
        numbers: &[(&str, f64)],
    ) {
        if dof >= MIN_VERDICT_DOF {
            return self.pass_if(ok, group, name, detail, numbers);
        }
        self.skip(group, name, format!("{detail}: {}", no_verdict(dof)));
    }

    /// The check that `v ± e` agrees with `x` within the Student-t bound of `dof` degrees of
    /// freedom (the crate's 4σ-equivalent, [`super::SIGMAS`]; judged as [`Checks::judge`]), its
    /// detail `what` followed by the numbers.
    pub(super) fn within_t(
        &mut self,
        dof: f64,
        (group, name): (&str, &str),
        ((v, e), x): ((f64, f64), f64),
        what: String,
    ) {
        let bound = normal_sigma_equivalent_t(dof, super::SIGMAS);
        let z = (v - x) / e;
        self.judge(
            dof,
            z.abs() <= bound,
            (group, name),
            format!("{what}{v} ± {e:.1e} against {x} ({z:+.2}σ; bound {bound:.2}σ)"),
            &[("value", v), ("err", e), ("exact", x)],
        );
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

/// A number drawn from the operating system's entropy (the thread's generator, seeded from it),
/// once per audit: whoever edits a result file can neither know nor choose which batch or run the audit
/// re-runs — padding the file or editing it again changes nothing (`proofs-notes/audit-draw.md`).
pub(super) fn entropy_draw() -> u64 {
    rand::random()
}

/// The index below `n` that the audit's `draw` ([`entropy_draw`]) picks: uniform to within
/// n/2⁶⁴.
pub(super) fn pick(draw: u64, n: u64) -> u64 {
    draw % n.max(1)
}
