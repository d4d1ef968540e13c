//! How strong a quick audit is: which of a result's batches (or runs) it re-ran, drawn at random.

use serde::Serialize;

use super::{PublicationReport, Verdict};

/// What a quick audit re-ran from their seeds: `rerun` of a result's `count` batches (or of a
/// sweep's runs), drawn from operating-system entropy as the audit ran, so that no edit of the
/// file can choose them. A forged unit passes only if the draw misses it: the PASS of a quick
/// audit is only as strong as [`Sampled::p_forged_pass`], and a result is published with
/// the full audit, which re-runs every one (`proofs-notes/audit-draw.md`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Sampled {
    /// What was sampled: `batches` or `runs`.
    pub units: &'static str,
    /// How many were re-run.
    pub rerun: u64,
    /// Of how many.
    pub count: u64,
    /// The chance that a result with one forged unit passes the re-run check: that the draw
    /// misses it, (count − rerun)/count. A result with k forged units passes with
    /// chance C(count − k, rerun)/C(count, rerun), no more.
    pub p_forged_pass: f64,
}

impl Sampled {
    /// `rerun` of `count` units re-run (`None` if that is all of them).
    pub fn new(units: &'static str, rerun: u64, count: u64) -> Option<Self> {
        (rerun < count).then(|| Sampled {
            units,
            rerun,
            count,
            p_forged_pass: (count - rerun) as f64 / count as f64,
        })
    }

    /// The strength of the quick audit in words, for its verdict.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::report::publication::Sampled;
    /// let s = Sampled::new("batches", 1, 32).unwrap();
    /// assert_eq!(s.p_forged_pass, 31.0 / 32.0);
    /// assert!(s.strength().starts_with("quick audit: 1 of 32 batches re-run"), "{}", s.strength());
    /// assert!(Sampled::new("runs", 4, 4).is_none());
    /// ```
    pub fn strength(&self) -> String {
        format!(
            "quick audit: {} of {} {} re-run, drawn at random as the audit ran; a result with one \
             of the others forged passes it with chance {}/{} ({:.0} %): publish with the full audit",
            self.rerun,
            self.count,
            self.units,
            self.count - self.rerun,
            self.count,
            100.0 * self.p_forged_pass
        )
    }
}

impl PublicationReport {
    /// The verdict as the report states it: a quick audit's PASS with its strength
    /// ([`Sampled::strength`]).
    pub fn verdict_stated(&self) -> String {
        match (&self.sampled, self.verdict) {
            (Some(s), Verdict::Pass) => format!("{} ({})", self.verdict, s.strength()),
            _ => self.verdict.to_string(),
        }
    }
}
