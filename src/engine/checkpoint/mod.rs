//! Trajectories that survive a kill: what a resumable run keeps so that an interruption loses at
//! most one checkpoint interval — the finished batches, and at the interval the whole state of
//! every trajectory in flight (its exact position, velocity, cell and exclusions, its collision
//! count, and its observers' accumulators) — as records of the run's [`Journal`] (digested line
//! by line), and the engines' drivers that run a trajectory in segments, restore it and save it.
//!
//! A resumed trajectory continues from its saved state with the same operations, so the result
//! has the uninterrupted bits on any engine and thread count (`proofs-notes/checkpoints.md`).

use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::metadata::RunMeta;
use super::options::StopFlag;
use super::resume::Journal;
use crate::Error;
use crate::numbers::real::Real;
use crate::scenes::lattice::{ExactState, LatticeState};

mod carry;
mod drive;
mod marks;
mod quarantine;

pub use carry::Carry;
use drive::{SEGMENT_F64, SEGMENT_MPFR};
pub use drive::{drive_kept, drive_kept_with, run_block_kept};
pub use marks::{MARK, recheck_one_batch};
pub(crate) use quarantine::quarantined;
pub use quarantine::{quarantine, recomputed_differs};

/// An observer whose accumulators, lane by lane, can be saved and put back exactly.
pub trait LaneCheckpoint {
    /// Everything one lane has accumulated.
    type Lane: Serialize + DeserializeOwned + Clone + Send + Sync;
    /// Lane `l`'s accumulators.
    fn save_lane(&self, l: usize) -> Self::Lane;
    /// Puts `saved` back into lane `l`.
    ///
    /// # Errors
    /// A state this observer could not have saved (other sizes, impossible values).
    fn restore_lane(&mut self, l: usize, saved: &Self::Lane) -> Result<(), Error>;
}

/// One trajectory of a run: its run and batch (stream) index, and its collisions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Quota {
    /// The run it belongs to (several runs share a journal when packed together).
    pub run: u64,
    /// Its batch index.
    pub index: u32,
    /// Collisions it makes.
    pub collisions: u64,
}

/// One line of a checkpoint: a finished batch's result `F`, or a trajectory in flight whose
/// observers saved `S`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Record<F, S> {
    /// A finished batch.
    Finished {
        /// Its run.
        run: u64,
        /// Its batch index.
        index: u32,
        /// Its result.
        result: F,
        /// The trajectory's states at its marks ([`MARK`] collisions from either end), with which
        /// a resumed run checks this batch in bounded time ([`recheck_one_batch`]); none for a
        /// batch too short to have marks, or kept by an older version.
        #[serde(default = "Vec::new", skip_serializing_if = "Vec::is_empty")]
        marks: Vec<InFlight<S>>,
    },
    /// A trajectory in flight.
    InFlight(InFlight<S>),
}

/// A trajectory in flight, whole: enough to continue it as if it had never stopped.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InFlight<S> {
    /// Its run.
    pub run: u64,
    /// Its batch index.
    pub index: u32,
    /// Collisions done.
    pub collisions: u64,
    /// Its state after the last of them.
    pub state: ExactState,
    /// Its observers' accumulators.
    pub observers: S,
}

/// The states kept at the marks of each trajectory ([`MARK`]), by (run, batch).
type Marks<S> = HashMap<(u64, u32), Vec<InFlight<S>>>;

/// The work of a run kept on disk (or nowhere): what was found when it started, and where new
/// work goes.
pub struct Keeper<F, S> {
    journal: Option<Journal<Record<F, S>>>,
    /// Save the trajectories in flight this often (`None`: finished batches only).
    every: Option<Duration>,
    finished: BTreeMap<(u64, u32), F>,
    in_flight: HashMap<(u64, u32), InFlight<S>>,
    /// A request to stop, looked at between segments (`None`: the run is not watched).
    stop: Option<StopFlag>,
    /// Whether trajectories stop at their marks ([`MARK`]) to keep their states there.
    marking: bool,
    /// The collisions of each trajectory of the run, for its marks (a probe runs part of one).
    quotas: HashMap<(u64, u32), u64>,
    /// The states kept at the marks, by trajectory.
    marks: Mutex<Marks<S>>,
    /// The trajectories' final states, where they are captured ([`Keeper::capturing`]).
    ends: Option<Mutex<Vec<InFlight<S>>>>,
}

impl<F, S> Keeper<F, S>
where
    F: Serialize + DeserializeOwned + Clone,
    S: Serialize + DeserializeOwned + Clone,
{
    /// Nothing kept.
    pub fn none() -> Self {
        Keeper {
            journal: None,
            every: None,
            finished: BTreeMap::new(),
            in_flight: HashMap::new(),
            stop: None,
            marking: false,
            quotas: HashMap::new(),
            marks: Mutex::new(HashMap::new()),
            ends: None,
        }
    }

    /// The same keeper, looking at `stop` between segments (a run whose stop is requested saves
    /// its trajectories in flight at the end of the current segment and ends with
    /// [`Error::Interrupted`]).
    pub fn watching(mut self, stop: Option<&StopFlag>) -> Self {
        self.stop = stop.cloned();
        self
    }

    /// [`Error::Interrupted`] if a stop was requested.
    pub fn check_stop(&self) -> Result<(), Error> {
        match &self.stop {
            Some(s) => s.check(),
            None => Ok(()),
        }
    }

    /// The journal at `path` (if any) of work `kind` at `config`, whose trajectories are `jobs`:
    /// its records checked against the jobs (each finished batch once, with its job's
    /// collisions; each trajectory in flight short of them), the newest state of each
    /// trajectory kept and the journal compacted to them. `every`: the save interval of
    /// trajectories in flight (`None`: finished batches only, as with a per-event audit, whose
    /// replay state is not saved). `fits`: whether a finished result can be the one of its job
    /// (its index, its collisions).
    pub fn open<C: Serialize>(
        path: Option<&Path>,
        kind: &str,
        config: &C,
        meta: Option<RunMeta>,
        jobs: &[Quota],
        every: Option<Duration>,
        fits: &dyn Fn(&Quota, &F) -> bool,
    ) -> Result<Self, Error> {
        let Some(p) = path else {
            return Ok(Keeper::none());
        };
        let (journal, records) = Journal::<Record<F, S>>::open(p, kind, config, meta)?;
        let quota: HashMap<(u64, u32), Quota> =
            jobs.iter().map(|j| ((j.run, j.index), *j)).collect();
        let mut k = Keeper {
            journal: None,
            every,
            finished: BTreeMap::new(),
            in_flight: HashMap::new(),
            stop: None,
            // Marks are states in flight: kept only where those are saved.
            marking: every.is_some(),
            quotas: quota.iter().map(|(&k, q)| (k, q.collisions)).collect(),
            marks: Mutex::new(HashMap::new()),
            ends: None,
        };
        for r in records {
            k.take(p, r, &quota, fits)?;
        }
        k.in_flight.retain(|key, _| !k.finished.contains_key(key));
        journal.rewrite(&k.compacted())?;
        k.journal = Some(journal);
        Ok(k)
    }

    /// The records a journal is rewritten to when it is opened: the finished batches (with their
    /// marks), then the newest state of each trajectory in flight and its marks before it.
    fn compacted(&self) -> Vec<Record<F, S>> {
        let marks = self.lock_marks();
        let mut kept: Vec<Record<F, S>> = (self.finished.iter())
            .map(|(&(run, index), b)| Record::Finished {
                run,
                index,
                result: b.clone(),
                marks: marks.get(&(run, index)).cloned().unwrap_or_default(),
            })
            .collect();
        let mut flying: Vec<&InFlight<S>> = self.in_flight.values().collect();
        flying.sort_by_key(|f| (f.run, f.index));
        for f in flying {
            let earlier = marks.get(&(f.run, f.index)).into_iter().flatten();
            kept.extend(
                earlier
                    .filter(|m| m.collisions < f.collisions)
                    .cloned()
                    .map(Record::InFlight),
            );
            kept.push(Record::InFlight(f.clone()));
        }
        kept
    }

    /// Adds record `r` of the journal at `p`, checked against the jobs' quotas.
    fn take(
        &mut self,
        p: &Path,
        r: Record<F, S>,
        quota: &HashMap<(u64, u32), Quota>,
        fits: &dyn Fn(&Quota, &F) -> bool,
    ) -> Result<(), Error> {
        let foreign = |run: u64, index: u32, why: &str| {
            Error::malformed(
                p,
                format!(
                    "the record of run {run}, batch {index} {why}: an edited or foreign \
                     checkpoint (use another file)"
                ),
            )
        };
        match r {
            Record::Finished {
                run,
                index,
                result,
                marks,
            } => {
                let key = (run, index);
                if !quota.get(&key).is_some_and(|q| fits(q, &result)) {
                    return Err(foreign(run, index, "is not a batch of this run"));
                }
                if self.finished.insert(key, result).is_some() {
                    return Err(foreign(key.0, key.1, "appears twice"));
                }
                self.take_marks(key, marks)
                    .map_err(|why| foreign(run, index, why))?;
            }
            Record::InFlight(f) => {
                let key = (f.run, f.index);
                if quota.get(&key).is_none_or(|q| f.collisions >= q.collisions) {
                    return Err(foreign(
                        f.run,
                        f.index,
                        "is not a trajectory in flight of this run",
                    ));
                }
                self.take_marks(key, vec![f.clone()])
                    .map_err(|why| foreign(f.run, f.index, why))?;
                let newer = self
                    .in_flight
                    .get(&key)
                    .is_none_or(|old| old.collisions < f.collisions);
                if newer {
                    self.in_flight.insert(key, f);
                }
            }
        }
        Ok(())
    }

    /// Finished batches found at the start, with their runs, in (run, batch) order.
    pub fn finished(&self) -> impl Iterator<Item = (u64, &F)> {
        self.finished.iter().map(|(&(run, _), b)| (run, b))
    }

    /// Finished batches found at the start, with their indices, in (run, batch) order.
    pub fn finished_by_index(&self) -> impl Iterator<Item = (u32, F)> + '_ {
        self.finished.iter().map(|(&(_, i), b)| (i, b.clone()))
    }

    /// Whether the batch of `job` was finished before this start.
    pub fn is_finished(&self, job: &Quota) -> bool {
        self.finished.contains_key(&(job.run, job.index))
    }

    /// How many trajectories continue from a saved state.
    pub fn in_flight_count(&self) -> usize {
        self.in_flight.len()
    }

    /// Collisions already done (finished batches of `jobs` and trajectories in flight).
    pub fn collisions_done(&self, jobs: &[Quota]) -> u64 {
        let f: u64 = jobs
            .iter()
            .filter(|j| self.is_finished(j))
            .map(|j| j.collisions)
            .sum();
        f + self.in_flight.values().map(|s| s.collisions).sum::<u64>()
    }

    /// Collisions of the trajectories in flight that this run resumed (of run `run` only, if
    /// given): work an earlier invocation did.
    pub fn in_flight_collisions(&self, run: Option<u64>) -> u64 {
        self.in_flight
            .iter()
            .filter(|((r, _), _)| run.is_none_or(|x| x == *r))
            .map(|(_, s)| s.collisions)
            .sum()
    }

    /// The saved state of `job`'s trajectory, if it was in flight.
    pub fn resumed(&self, job: &Quota) -> Option<&InFlight<S>> {
        self.in_flight.get(&(job.run, job.index))
    }

    /// Most collisions per trajectory between looks at the clock and at the stop request (the
    /// segments are paced below it, by wall time): all of them when nothing in flight is saved and
    /// nobody can ask the run to stop.
    pub fn segment(&self, mpfr: bool) -> u64 {
        match (self.every, &self.stop) {
            (None, None) => u64::MAX,
            _ if mpfr => SEGMENT_MPFR,
            _ => SEGMENT_F64,
        }
    }

    /// Keeps the finished batch `result` of `job`, with its marks.
    pub fn finish(&self, job: &Quota, result: &F) -> Result<(), Error> {
        let Some(j) = &self.journal else {
            return Ok(());
        };
        let marks = self.lock_marks().remove(&(job.run, job.index));
        j.append(&Record::Finished {
            run: job.run,
            index: job.index,
            result: result.clone(),
            marks: marks.unwrap_or_default(),
        })
    }

    /// Saves the trajectories in flight that `states` yields if an interval has passed since
    /// `last` (then resets it), or at once if a stop was requested.
    pub fn save_if_due(
        &self,
        last: &mut Instant,
        states: impl FnOnce() -> Vec<InFlight<S>>,
    ) -> Result<(), Error> {
        let (Some(j), Some(every)) = (&self.journal, self.every) else {
            return Ok(());
        };
        // A requested stop saves at once: the run ends at the next look at the flag with
        // nothing in flight lost.
        let stopping = self.stop.as_ref().is_some_and(StopFlag::requested);
        if last.elapsed() < every && !stopping {
            return Ok(());
        }
        for s in states() {
            j.append(&Record::InFlight(s))?;
        }
        *last = Instant::now();
        Ok(())
    }
}

impl<S> InFlight<S> {
    /// The saved state at number type `T`.
    pub fn state<T: Real>(&self, ctx: T::Ctx) -> Result<LatticeState<T>, Error> {
        LatticeState::from_exact(ctx, &self.state)
    }
}
