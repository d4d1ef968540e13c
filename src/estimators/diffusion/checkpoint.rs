//! What a diffusion run keeps so that a kill loses at most one checkpoint interval: the finished
//! batches, and at the interval the whole state of every trajectory in flight (its exact
//! position, velocity, cell and exclusions, its collision count and its observers'
//! accumulators), as records of the run's [`Journal`] (digested line by line).
//!
//! A resumed trajectory continues from its saved state with the same operations, so the result
//! has the uninterrupted bits, on any engine and thread count (`proofs-notes/checkpoints.md`).

use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use super::execution::Job;
use super::BatchResult;
use crate::engine::metadata::RunMeta;
use crate::engine::resume::Journal;
use crate::numbers::real::Real;
use crate::observers::counters::CounterLaneState;
use crate::observers::msd::MsdLaneState;
use crate::scenes::lattice::{ExactState, LatticeState};
use crate::Error;

/// One line of a diffusion checkpoint or of a sweep point's journal.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub(super) enum Record {
    /// A finished batch of run `run`.
    Finished { run: u64, batch: BatchResult },
    /// A trajectory in flight.
    InFlight(InFlight),
}

/// A trajectory in flight, whole: enough to continue it as if it had never stopped.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct InFlight {
    /// Its run.
    pub(super) run: u64,
    /// Its batch (stream) index.
    pub(super) index: u32,
    /// Collisions done.
    pub(super) collisions: u64,
    /// Its state after the last of them.
    pub(super) state: ExactState,
    /// Its counters.
    pub(super) counters: CounterLaneState,
    /// Its MSD accumulator.
    pub(super) msd: MsdLaneState,
}

impl InFlight {
    /// The saved state at number type `T`.
    pub(super) fn state<T: Real>(&self, ctx: T::Ctx) -> Result<LatticeState<T>, Error> {
        LatticeState::from_exact(ctx, &self.state)
    }
}

/// Kind of the records of a diffusion checkpoint.
pub(super) const CHECKPOINT_KIND: &str = "diffusion trajectories";

/// Kind of the records of a [`super::run_many`] journal.
pub(super) const PACKED_KIND: &str = "packed diffusion trajectories";

/// Collisions per trajectory between two looks at the clock on the SIMD and `f64` engines
/// (2²⁰: about 0.1 s for a block of 16), and at MPFR precision (2¹⁴: about as long).
const SEGMENT_F64: u64 = 1 << 20;
const SEGMENT_MPFR: u64 = 1 << 14;

/// The work of a run kept on disk (or nowhere): what was found when it started, and where new
/// work goes.
pub(super) struct Keeper {
    journal: Option<Journal<Record>>,
    /// Save the trajectories in flight this often (`None`: finished batches only).
    every: Option<Duration>,
    finished: BTreeMap<(u64, u32), BatchResult>,
    in_flight: HashMap<(u64, u32), InFlight>,
}

impl Keeper {
    /// Nothing kept.
    pub(super) fn none() -> Self {
        Keeper {
            journal: None,
            every: None,
            finished: BTreeMap::new(),
            in_flight: HashMap::new(),
        }
    }

    /// The journal at `path` (if any) of work `kind` at `config`, whose trajectories are `jobs`:
    /// its records checked against the jobs (each finished batch once, with its job's
    /// collisions; each trajectory in flight short of them), the newest state of each
    /// trajectory kept and the journal compacted to them. `every`: the save interval of
    /// trajectories in flight (`None`: finished batches only, as with a per-event audit, whose
    /// replay state is not saved).
    pub(super) fn open<C: Serialize>(
        path: Option<&Path>,
        kind: &str,
        config: &C,
        meta: Option<RunMeta>,
        jobs: &[Job],
        every: Option<Duration>,
    ) -> Result<Self, Error> {
        let Some(p) = path else {
            return Ok(Keeper::none());
        };
        let (journal, records) = Journal::<Record>::open(p, kind, config, meta)?;
        let quota: HashMap<(u64, u32), u64> = jobs
            .iter()
            .map(|j| ((j.run, j.index), j.collisions))
            .collect();
        let mut k = Keeper {
            journal: None,
            every,
            finished: BTreeMap::new(),
            in_flight: HashMap::new(),
        };
        for r in records {
            k.take(p, r, &quota)?;
        }
        k.in_flight.retain(|key, _| !k.finished.contains_key(key));
        let mut kept: Vec<Record> = k
            .finished
            .iter()
            .map(|(&(run, _), b)| Record::Finished {
                run,
                batch: b.clone(),
            })
            .collect();
        let mut flying: Vec<&InFlight> = k.in_flight.values().collect();
        flying.sort_by_key(|f| (f.run, f.index));
        kept.extend(flying.into_iter().cloned().map(Record::InFlight));
        journal.rewrite(&kept)?;
        k.journal = Some(journal);
        Ok(k)
    }

    /// Adds record `r` of the journal at `p`, checked against the jobs' quotas.
    fn take(&mut self, p: &Path, r: Record, quota: &HashMap<(u64, u32), u64>) -> Result<(), Error> {
        let foreign = |run: u64, index: u32, why: &str| {
            Error::Invalid(format!(
                "{}: the record of run {run}, batch {index} {why}: an edited or foreign checkpoint (use another file)",
                p.display()
            ))
        };
        match r {
            Record::Finished { run, batch } => {
                let key = (run, batch.index);
                if quota.get(&key) != Some(&batch.counters.collisions) {
                    return Err(foreign(run, batch.index, "is not a batch of this run"));
                }
                if self.finished.insert(key, batch).is_some() {
                    return Err(foreign(key.0, key.1, "appears twice"));
                }
            }
            Record::InFlight(f) => {
                let key = (f.run, f.index);
                if quota.get(&key).is_none_or(|&q| f.collisions >= q) {
                    return Err(foreign(
                        f.run,
                        f.index,
                        "is not a trajectory in flight of this run",
                    ));
                }
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
    pub(super) fn finished(&self) -> impl Iterator<Item = (u64, &BatchResult)> {
        self.finished.iter().map(|(&(run, _), b)| (run, b))
    }

    /// Whether the batch of `job` was finished before this start.
    pub(super) fn is_finished(&self, job: &Job) -> bool {
        self.finished.contains_key(&(job.run, job.index))
    }

    /// How many trajectories continue from a saved state.
    pub(super) fn in_flight_count(&self) -> usize {
        self.in_flight.len()
    }

    /// Collisions already done (finished batches and trajectories in flight).
    pub(super) fn collisions_done(&self) -> u64 {
        let f: u64 = self.finished.values().map(|b| b.counters.collisions).sum();
        f + self.in_flight.values().map(|s| s.collisions).sum::<u64>()
    }

    /// The saved state of `job`'s trajectory, if it was in flight.
    pub(super) fn resumed(&self, job: &Job) -> Option<&InFlight> {
        self.in_flight.get(&(job.run, job.index))
    }

    /// Collisions per trajectory between looks at the clock: all of them when nothing in
    /// flight is saved.
    pub(super) fn segment(&self, mpfr: bool) -> u64 {
        match self.every {
            None => u64::MAX,
            Some(_) if mpfr => SEGMENT_MPFR,
            Some(_) => SEGMENT_F64,
        }
    }

    /// Keeps finished batch `batch` of `job`.
    pub(super) fn finish(&self, job: &Job, batch: &BatchResult) -> Result<(), Error> {
        match &self.journal {
            Some(j) => j.append(&Record::Finished {
                run: job.run,
                batch: batch.clone(),
            }),
            None => Ok(()),
        }
    }

    /// Saves the trajectories in flight that `states` yields if an interval has passed since
    /// `last` (then resets it).
    pub(super) fn save_if_due(
        &self,
        last: &mut Instant,
        states: impl FnOnce() -> Vec<InFlight>,
    ) -> Result<(), Error> {
        let (Some(j), Some(every)) = (&self.journal, self.every) else {
            return Ok(());
        };
        if last.elapsed() < every {
            return Ok(());
        }
        for s in states() {
            j.append(&Record::InFlight(s))?;
        }
        *last = Instant::now();
        Ok(())
    }
}
