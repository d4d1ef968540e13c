//! What every check of one audit shares ([`Ctx`]): the audit's draw, the settings, the re-runs
//! and the budget's admission of each.

use std::cell::Cell;
use std::path::Path;

use super::Sampled;
use super::checks::{Checks, pick};
use crate::Error;
use crate::engine::options::RunOptions;

/// What every check of one audit shares: its random draw, where figures go, the settings, the
/// re-runs with the budget's admission of each, and where re-runs report their collisions.
pub(super) struct Ctx<'a> {
    /// The audit's one draw of operating-system entropy: which batch or run a quick audit
    /// re-runs ([`pick`]).
    pub(super) draw: u64,
    /// What a quick audit re-ran of the units it could have ([`Sampled`]), set by the check
    /// that re-runs them.
    pub(super) sampled: Cell<Option<Sampled>>,
    pub(super) out: &'a Path,
    pub(super) quick: bool,
    pub(super) bits: u32,
    pub(super) threads: usize,
    pub(super) progress: &'a (dyn Fn(u64) + Sync),
    /// The re-runs' collisions, in the order the checks take them.
    pub(super) reruns: Vec<u64>,
    /// Whether each fits in the budget.
    pub(super) admitted: Vec<bool>,
    /// The next re-run to be taken.
    pub(super) next: Cell<usize>,
    /// Collisions of the re-runs taken so far.
    pub(super) done: Cell<u64>,
    pub(super) budget: Option<u64>,
}

impl Ctx<'_> {
    /// Takes the next re-run: `Ok(collisions)` if the budget admits it, else `Err(reason)` for the
    /// SKIP of its check.
    pub(super) fn take(&self) -> Result<u64, String> {
        let i = self.next.get();
        self.next.set(i + 1);
        let n = self.reruns.get(i).copied().unwrap_or(u64::MAX);
        if self.admitted.get(i).copied().unwrap_or(false) {
            self.done.set(self.done.get() + n);
            return Ok(n);
        }
        let budget = self.budget.unwrap_or(u64::MAX);
        Err(format!(
            "the re-run needs {:.3e} collisions (computed from the recorded configuration); the audit re-runs at most {:.3e} in all ({}), {:.3e} of them left: not re-run",
            n as f64,
            budget as f64,
            if self.quick {
                "quick report"
            } else {
                "its bound"
            },
            budget.saturating_sub(self.done.get()) as f64,
        ))
    }

    /// [`Ctx::take`], or the SKIP of the check (`group`, `name`) when the budget does not admit
    /// the re-run.
    pub(super) fn take_or_skip(
        &self,
        checks: &mut Checks,
        (group, name): (&str, &str),
    ) -> Option<u64> {
        self.take()
            .map_err(|why| checks.skip(group, name, why))
            .ok()
    }

    /// The quick re-run of one of `count` batches, drawn from the audit's entropy: `rerun` gives
    /// the batch's values (its progress in `units` units over the batch, `None`: collisions),
    /// which must be `recorded[i][batch]` to the bit for every named series i.
    pub(super) fn one_batch_rerun(
        &self,
        checks: &mut Checks,
        (count, units): (u32, Option<u64>),
        recorded: &[(&str, &[f64])],
        rerun: impl FnOnce(u32, &RunOptions) -> Result<Vec<f64>, Error>,
    ) -> Result<(), Error> {
        let name = "the recorded configuration re-run gives the same bits";
        let Some(n) = self.take_or_skip(checks, ("reproducibility", name)) else {
            return Ok(());
        };
        let b = pick(self.draw, u64::from(count)) as u32;
        self.sampled
            .set(Sampled::new("batches", 1, u64::from(count)));
        let again = self.rerun_in_units(n, units.unwrap_or(n), |o| rerun(b, o))?;
        let i = b as usize;
        let pairs: Vec<String> = (recorded.iter().zip(&again))
            .map(|((what, r), a)| format!("{what} {a} (recorded {})", r[i]))
            .collect();
        let same = recorded.len() == again.len()
            && (recorded.iter().zip(&again)).all(|((_, r), a)| r[i].to_bits() == a.to_bits());
        checks.pass_if(
            same,
            "reproducibility",
            name,
            format!(
                "batch {b} of {count} re-run from its seed: {}",
                pairs.join(", ")
            ),
            &[("batch", f64::from(b))],
        );
        Ok(())
    }

    /// Runs `f` with the options of a re-run of `n` collisions whose progress comes in `units`
    /// units (particles, visits) of about n/units collisions each.
    pub(super) fn rerun_in_units<T>(
        &self,
        n: u64,
        units: u64,
        f: impl FnOnce(&RunOptions) -> Result<T, Error>,
    ) -> Result<T, Error> {
        let per = n / units.max(1);
        let progress = |v: u64| (self.progress)(v.saturating_mul(per));
        f(&RunOptions {
            progress: &progress,
            ..self.options()
        })
    }

    /// Run options for a re-run: the default engine on the audit's threads, its progress.
    pub(super) fn options(&self) -> RunOptions<'_> {
        RunOptions {
            threads: self.threads,
            progress: self.progress,
            ..RunOptions::default()
        }
    }
}
