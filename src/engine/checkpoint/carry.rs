//! A run continued from another: a planned diffusion run (`rel_err`) continues the trajectories
//! of its pilot, whose seeds and observers are its own, instead of computing them again. The
//! pilot's keeper captures each trajectory's final state and its first mark ([`Carry`]); the
//! planned run's keeper takes them as trajectories in flight. A trajectory continued from a state
//! has the bits of the uninterrupted one (`proofs-notes/checkpoints.md`, claim 1), so the planned
//! run's result is bit for bit the plain run of its size.

use std::collections::HashMap;
use std::sync::{Mutex, PoisonError};

use serde::Serialize;
use serde::de::DeserializeOwned;

use super::{InFlight, Keeper, Quota, Record};
use crate::Error;

/// The trajectories of a finished run, whole, for a longer run of the same seeds to continue.
#[derive(Debug, Clone)]
pub struct Carry<S> {
    /// Each trajectory's final state and accumulators.
    ends: Vec<InFlight<S>>,
    /// Each trajectory's state at its first mark, if it reached it.
    marks: Vec<InFlight<S>>,
}

impl<F, S> Keeper<F, S>
where
    F: Serialize + DeserializeOwned + Clone,
    S: Serialize + DeserializeOwned + Clone,
{
    /// A keeper that writes nothing and captures, for [`Keeper::carry`], the final state of each
    /// of `jobs`' trajectories and its first mark (the second lies beyond any length).
    pub fn capturing(jobs: &[Quota]) -> Self {
        let mut k = Keeper::none();
        k.marking = true;
        k.quotas = jobs.iter().map(|j| ((j.run, j.index), u64::MAX)).collect();
        k.ends = Some(Mutex::new(Vec::new()));
        k
    }

    /// Whether the drivers hand this keeper their trajectories' final states.
    pub(super) fn captures_ends(&self) -> bool {
        self.ends.is_some()
    }

    /// Keeps `state`, a trajectory's final state, if this keeper captures them.
    pub(super) fn end(&self, state: InFlight<S>) {
        if let Some(e) = &self.ends {
            e.lock().unwrap_or_else(PoisonError::into_inner).push(state);
        }
    }

    /// What a capturing keeper kept ([`Keeper::capturing`]).
    pub fn carry(&self) -> Carry<S> {
        let ends = self.ends.as_ref().map(|e| {
            let mut v = e.lock().unwrap_or_else(PoisonError::into_inner).clone();
            v.sort_by_key(|s| (s.run, s.index));
            v
        });
        let mut marks: Vec<InFlight<S>> = self.lock_marks().values().flatten().cloned().collect();
        marks.sort_by_key(|s| (s.run, s.index, s.collisions));
        Carry {
            ends: ends.unwrap_or_default(),
            marks,
        }
    }

    /// Continues `carry`'s trajectories: each becomes a trajectory in flight of this run (and a
    /// record of its journal, so that a kill keeps it) unless this run finished it or holds a
    /// later state of it, or it is not shorter than its batch here; its first mark is kept with
    /// it. Returns how many trajectories and collisions were taken.
    ///
    /// # Errors
    /// An I/O error of the journal.
    pub fn continue_from(&mut self, carry: Carry<S>) -> Result<(usize, u64), Error> {
        let mut taken = (0, 0);
        let mut by_key: HashMap<(u64, u32), Vec<InFlight<S>>> = HashMap::new();
        for m in carry.marks {
            by_key.entry((m.run, m.index)).or_default().push(m);
        }
        for e in carry.ends {
            let key = (e.run, e.index);
            let later = self
                .in_flight
                .get(&key)
                .is_some_and(|f| f.collisions >= e.collisions);
            let fits = self.quotas.get(&key).is_some_and(|&n| e.collisions < n);
            if later || !fits || self.finished.contains_key(&key) {
                continue;
            }
            let marks = by_key.remove(&key).unwrap_or_default();
            let job = Quota {
                run: e.run,
                index: e.index,
                collisions: e.collisions,
            };
            for m in marks.iter().filter(|m| m.collisions < e.collisions) {
                if self.at_mark(&job, m.collisions) {
                    self.mark(m.clone())?;
                }
            }
            if let Some(j) = &self.journal {
                j.append(&Record::InFlight(e.clone()))?;
            }
            taken = (taken.0 + 1, taken.1 + e.collisions);
            self.in_flight.insert(key, e);
        }
        Ok(taken)
    }
}
