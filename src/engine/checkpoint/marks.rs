//! Marks: the states every trajectory of a kept run leaves at two fixed points — [`MARK`]
//! collisions after its start and [`MARK`] before its end — with which a resumed run checks one
//! finished batch in bounded time instead of computing it again whole
//! (`proofs-notes/checkpoints.md`, claim 3).
//!
//! The check draws a finished batch at random and runs two short pieces of its trajectory: from
//! its seed to the first mark, which must give the recorded state and accumulators there to the
//! bit, and from the recorded second mark to the end, which must give the recorded result to the
//! bit. Together at most 2·[`MARK`] collisions, whatever the batch's length; a trajectory too
//! short to have two marks is computed again whole (at most that much too).

use std::path::Path;
use std::sync::{MutexGuard, PoisonError};

use serde::Serialize;
use serde::de::DeserializeOwned;

use super::{InFlight, Keeper, Marks, Quota, recomputed_differs};

/// A finished batch drawn for the check: its (run, batch), result and marks.
type Drawn<F, S> = ((u64, u32), F, Vec<InFlight<S>>);
use crate::Error;
use crate::engine::options::StopFlag;

/// Collisions from either end of a trajectory to its marks: 2¹⁶, about 3 ms of the `f64` engine
/// and well under a second at any MPFR precision the crate runs.
pub const MARK: u64 = 1 << 16;

/// The marks of a trajectory of `n` collisions: [`MARK`] and `n − MARK`, if it is longer than
/// twice [`MARK`] (a shorter one is checked whole).
pub(super) fn points(n: u64) -> Option<(u64, u64)> {
    (n > 2 * MARK).then(|| (MARK, n - MARK))
}

impl<F, S> Keeper<F, S>
where
    F: Serialize + DeserializeOwned + Clone,
    S: Serialize + DeserializeOwned + Clone,
{
    /// A keeper for a probe of `job`'s trajectory, whose full length is `collisions`: nothing is
    /// written, the states at the marks are kept in memory ([`Keeper::probed`]), and the
    /// trajectory starts from `from` if given.
    pub fn probe(job: &Quota, collisions: u64, from: Option<InFlight<S>>) -> Self {
        let key = (job.run, job.index);
        let mut k = Keeper::none();
        k.marking = true;
        k.quotas.insert(key, collisions);
        k.in_flight.extend(from.map(|f| (key, f)));
        k
    }

    /// The states a probe kept at `job`'s marks.
    pub fn probed(&self, job: &Quota) -> Vec<InFlight<S>> {
        (self.lock_marks().get(&(job.run, job.index)).cloned()).unwrap_or_default()
    }

    /// The marks of `job`'s trajectory if this keeper keeps them.
    fn marks_of(&self, job: &Quota) -> Option<(u64, u64)> {
        if !self.marking {
            return None;
        }
        let n = self.quotas.get(&(job.run, job.index));
        points(n.copied().unwrap_or(job.collisions))
    }

    /// At most `q` collisions from `done`: fewer if a mark of `job` comes first.
    pub(super) fn up_to_mark(&self, job: &Quota, done: u64, q: u64) -> u64 {
        match self.marks_of(job) {
            Some((a, b)) => [a, b]
                .into_iter()
                .filter(|&m| m > done)
                .fold(q, |q, m| q.min(m - done)),
            None => q,
        }
    }

    /// Whether `done` collisions of `job` is one of its marks.
    pub(super) fn at_mark(&self, job: &Quota, done: u64) -> bool {
        self.marks_of(job)
            .is_some_and(|(a, b)| done == a || done == b)
    }

    /// Keeps `state`, `job`'s trajectory at a mark: in memory for its finished record, and in
    /// the journal at once (a run cut before the batch ends still has it).
    pub(super) fn mark(&self, state: InFlight<S>) -> Result<(), Error> {
        if let Some(j) = &self.journal {
            j.append(&super::Record::InFlight(state.clone()))?;
        }
        let key = (state.run, state.index);
        let _ = self.take_marks(key, vec![state]);
        Ok(())
    }

    /// Adds the states among `found` that lie at marks of trajectory `key` (others are
    /// ignored); refuses more than one state at the same mark that differ, or a mark of a
    /// trajectory this run does not have.
    pub(super) fn take_marks(
        &self,
        key: (u64, u32),
        found: Vec<InFlight<S>>,
    ) -> Result<(), &'static str> {
        let n = self.quotas.get(&key).copied();
        let Some((a, b)) = n.and_then(points) else {
            return match found.is_empty() || n.is_some() {
                true => Ok(()),
                false => Err("has marks of no trajectory of this run"),
            };
        };
        if found.iter().any(|f| (f.run, f.index) != key) {
            return Err("has marks of another trajectory");
        }
        let mut all = self.lock_marks();
        let kept = all.entry(key).or_default();
        for f in found
            .into_iter()
            .filter(|f| f.collisions == a || f.collisions == b)
        {
            if !kept.iter().any(|m| m.collisions == f.collisions) {
                kept.push(f);
            }
        }
        kept.sort_by_key(|m| m.collisions);
        Ok(())
    }

    /// The marks, by trajectory (a poisoned lock still holds whole states: each is inserted
    /// whole).
    pub(super) fn lock_marks(&self) -> MutexGuard<'_, Marks<S>> {
        self.marks.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// One finished batch found at the start, drawn uniformly with operating-system entropy so
    /// that no one editing the checkpoint can know which: its key, result and marks.
    fn draw(&self) -> Option<Drawn<F, S>> {
        let n = self.finished.len();
        if n == 0 {
            return None;
        }
        let (&key, f) = self.finished.iter().nth(rand::random_range(0..n))?;
        let marks = self.lock_marks().get(&key).cloned().unwrap_or_default();
        Some((key, f.clone(), marks))
    }
}

/// How a resumed run computes a piece of one of its trajectories: `run(job, keep)` runs `job`
/// (whose collisions may be fewer than the batch's) with `keep`, and returns its result.
pub type Rerun<'a, F, S> = &'a dyn Fn(&Quota, &Keeper<F, S>) -> Result<F, Error>;

/// Checks one finished batch of `keep`, drawn at random, against its trajectory (module
/// documentation): from its seed to its first mark, and from its second mark to the end, with
/// `run`; `same(fresh, recorded)` compares results to the bit. A batch without both marks (too
/// short, or kept by an older version) is computed again whole. `stop` is honoured throughout.
///
/// # Errors
/// [`recomputed_differs`] (the checkpoint at `path` moved aside) naming the batch and `what`
/// differs; an error of `run`.
pub fn recheck_one_batch<F, S>(
    keep: &Keeper<F, S>,
    jobs: &[Quota],
    stop: Option<&StopFlag>,
    run: Rerun<'_, F, S>,
    same: &dyn Fn(&F, &F) -> bool,
    (path, what): (Option<&Path>, &str),
) -> Result<(), Error>
where
    F: Serialize + DeserializeOwned + Clone,
    S: Serialize + DeserializeOwned + Clone,
{
    let Some((key, recorded, marks)) = keep.draw() else {
        return Ok(());
    };
    let batch = format!("batch {} of run {}", key.1, key.0);
    let Some(job) = jobs.iter().find(|j| (j.run, j.index) == key) else {
        return Err(Error::Failed(format!(
            "{}: a finished {batch} that this configuration does not have",
            path.map_or_else(|| "the checkpoint".into(), |p| p.display().to_string())
        )));
    };
    let differs = |part: String| Err(recomputed_differs(path, &part, what));
    let (head, tail) = match (points(job.collisions), marks.as_slice()) {
        (Some((a, b)), [h, t]) if h.collisions == a && t.collisions == b => (h, t),
        _ => {
            let fresh = run(job, &Keeper::none().watching(stop))?;
            return if same(&fresh, &recorded) {
                Ok(())
            } else {
                differs(batch)
            };
        }
    };
    let probe = Keeper::probe(job, job.collisions, None).watching(stop);
    let to_head = Quota {
        collisions: head.collisions,
        ..*job
    };
    run(&to_head, &probe)?;
    let json = |m: &InFlight<S>| serde_json::to_value(m).ok();
    let fresh_head = probe
        .probed(job)
        .into_iter()
        .find(|m| m.collisions == head.collisions);
    if fresh_head
        .as_ref()
        .and_then(json)
        .is_none_or(|f| Some(f) != json(head))
    {
        return differs(format!(
            "{batch} (its first {} collisions)",
            head.collisions
        ));
    }
    let probe = Keeper::probe(job, job.collisions, Some(tail.clone())).watching(stop);
    let fresh = run(job, &probe)?;
    if !same(&fresh, &recorded) {
        return differs(format!(
            "{batch} (its last {} collisions)",
            job.collisions - tail.collisions
        ));
    }
    Ok(())
}
