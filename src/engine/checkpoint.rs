//! Trajectories that survive a kill: what a resumable run keeps so that an interruption loses at
//! most one checkpoint interval — the finished batches, and at the interval the whole state of
//! every trajectory in flight (its exact position, velocity, cell and exclusions, its collision
//! count, and its observers' accumulators) — as records of the run's [`Journal`] (digested line
//! by line), and the engines' drivers that run a trajectory in segments, restore it and save it.
//!
//! A resumed trajectory continues from its saved state with the same operations, so the result
//! has the uninterrupted bits on any engine and thread count (`proofs-notes/checkpoints.md`).

use std::collections::{BTreeMap, HashMap};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::metadata::RunMeta;
use super::observe::Observer;
use super::options::StopFlag;
use super::resume::Journal;
use super::simd::BLOCK;
use super::{SimdPath, drive, run_block};
use crate::Error;
use crate::kernel::cell::CellKernel;
use crate::numbers::real::Real;
use crate::scenes::lattice::{ExactState, Lattice, LatticeState};

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

/// Most collisions per trajectory between two looks at the clock and the stop flag on the SIMD
/// and `f64` engines, and at MPFR precision; [`Pace`] keeps each segment near
/// [`SEGMENT_TIME`] below these.
const SEGMENT_F64: u64 = 1 << 20;
const SEGMENT_MPFR: u64 = 1 << 14;

/// The wall time a segment aims at: a stop requested mid-segment is honoured within about this
/// much (a few times it on a loaded machine).
const SEGMENT_TIME: Duration = Duration::from_millis(100);

/// Segment lengths that follow the wall time of the segments done: the first is short
/// ([`FIRST_SEGMENT`] collisions), and each next one is twice or half the last while the last
/// took under half or over twice [`SEGMENT_TIME`], within `max`. Where the segments end never
/// changes the bits (the drives continue a state exactly).
struct Pace {
    len: u64,
    max: u64,
}

/// Collisions per trajectory of the first segment of a watched run.
const FIRST_SEGMENT: u64 = 1 << 10;

impl Pace {
    /// Segments of at most `max` collisions (`u64::MAX`: one segment, nobody watches).
    fn new(max: u64) -> Self {
        let len = if max == u64::MAX {
            max
        } else {
            FIRST_SEGMENT.min(max)
        };
        Pace { len, max }
    }

    /// The next segment's length, the last having taken `took`.
    fn after(&mut self, took: Duration) -> u64 {
        if took < SEGMENT_TIME / 2 {
            self.len = self.len.saturating_mul(2).min(self.max);
        } else if took > SEGMENT_TIME * 2 {
            self.len = (self.len / 2).max(1);
        }
        self.len
    }
}

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
        };
        for r in records {
            k.take(p, r, &quota, fits)?;
        }
        k.in_flight.retain(|key, _| !k.finished.contains_key(key));
        let mut kept: Vec<Record<F, S>> = k
            .finished
            .iter()
            .map(|(&(run, index), b)| Record::Finished {
                run,
                index,
                result: b.clone(),
            })
            .collect();
        let mut flying: Vec<&InFlight<S>> = k.in_flight.values().collect();
        flying.sort_by_key(|f| (f.run, f.index));
        kept.extend(flying.into_iter().cloned().map(Record::InFlight));
        journal.rewrite(&kept)?;
        k.journal = Some(journal);
        Ok(k)
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
            Record::Finished { run, index, result } => {
                let key = (run, index);
                if !quota.get(&key).is_some_and(|q| fits(q, &result)) {
                    return Err(foreign(run, index, "is not a batch of this run"));
                }
                if self.finished.insert(key, result).is_some() {
                    return Err(foreign(key.0, key.1, "appears twice"));
                }
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

    /// One finished batch found at the start, `((run, index), result)`, drawn uniformly with
    /// operating-system entropy, so that no one editing the checkpoint can know which: the batch
    /// a resumed run computes again to check the checkpoint (`None` if none is finished).
    pub fn random_finished(&self) -> Option<((u64, u32), &F)> {
        let n = self.finished.len();
        if n == 0 {
            return None;
        }
        self.finished
            .iter()
            .nth(rand::random_range(0..n))
            .map(|(k, f)| (*k, f))
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

    /// Keeps the finished batch `result` of `job`.
    pub fn finish(&self, job: &Quota, result: &F) -> Result<(), Error> {
        match &self.journal {
            Some(j) => j.append(&Record::Finished {
                run: job.run,
                index: job.index,
                result: result.clone(),
            }),
            None => Ok(()),
        }
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

/// The refusal of the checkpoint at `path` whose finished `batch`, computed again from its seed,
/// did not give the recorded `values` ([`Keeper::random_finished`]). The file is moved aside
/// first ([`quarantine`]): a refused checkpoint cannot be resumed again as it is, so retrying does
/// not draw again until an honest batch comes up — the next run starts afresh.
pub fn recomputed_differs(path: Option<&Path>, batch: &str, values: &str) -> Error {
    let shown = path.map_or_else(|| "the checkpoint".into(), |p| p.display().to_string());
    let moved = path.map(quarantine);
    Error::Failed(format!(
        "{shown}: {batch}, computed again from its seed to check the checkpoint, does not give the \
         recorded {values}: the checkpoint was edited (its digests recomputed) or belongs to \
         another configuration; {}",
        quarantined(moved)
    ))
}

/// What became of a refused file, for the refusal: moved aside, or why not.
pub(crate) fn quarantined(moved: Option<Result<PathBuf, Error>>) -> String {
    match moved {
        Some(Ok(to)) => format!(
            "it is moved to {} and cannot be resumed; the same command starts afresh",
            to.display()
        ),
        Some(Err(e)) => format!("it could not be moved aside ({e}): do not resume it"),
        None => "use another file".into(),
    }
}

/// Moves the file at `path` aside to `PATH.refused` (or `PATH.refused.N`), never over an
/// existing file: what a re-check refused cannot be resumed again as it is. The name is linked
/// first and the old one removed, so the file is never lost and nothing is replaced; where hard
/// links are not supported it is renamed to a name that does not exist.
///
/// # Errors
/// An I/O error naming the path, or 1000 names taken.
pub fn quarantine(path: &Path) -> Result<PathBuf, Error> {
    use std::io::ErrorKind;
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    for n in 0..1000 {
        let to = path.with_file_name(match n {
            0 => format!("{name}.refused"),
            _ => format!("{name}.refused.{n}"),
        });
        match std::fs::hard_link(path, &to) {
            Ok(()) => {
                std::fs::remove_file(path).map_err(Error::io("remove", path))?;
                return Ok(to);
            }
            Err(e) if e.kind() == ErrorKind::AlreadyExists => continue,
            Err(_) if std::fs::symlink_metadata(&to).is_err() => {
                std::fs::rename(path, &to).map_err(Error::io("rename", path))?;
                return Ok(to);
            }
            Err(e) => return Err(Error::io("link", path)(e)),
        }
    }
    Err(Error::Failed(format!(
        "{}: 1000 refused copies of it are already beside it",
        path.display()
    )))
}

/// Runs `job`'s trajectory on the scalar engine at precision `ctx` until it has made its
/// collisions — from `start()`, or from its saved state if it was in flight (with `obs`'s lane
/// put back) — in segments, saving it at `keep`'s interval. Returns the final state. The same
/// bits as [`drive`] in one piece.
///
/// # Errors
/// A saved state that does not fit, a lost next event, or an I/O error of the journal.
pub fn drive_kept<T, K, O, F>(
    lat: &Lattice<T, K>,
    ctx: T::Ctx,
    job: &Quota,
    start: impl FnOnce() -> LatticeState<T>,
    obs: &mut O,
    keep: &Keeper<F, O::Lane>,
    progress: &dyn Fn(u64),
) -> Result<LatticeState<T>, Error>
where
    T: Real,
    K: CellKernel<T>,
    O: Observer<1> + LaneCheckpoint,
    F: Serialize + DeserializeOwned + Clone,
{
    let step = |s: &mut LatticeState<T>, q: u64, obs: &mut O| drive(lat, s, q, obs, progress);
    drive_kept_with(ctx, job, start, obs, keep, step)
}

/// [`drive_kept`] with the engine given as `step(state, collisions, observer)`: the scalar
/// engine, or the one with long flights ([`super::long_flight::drive_jumps`]). A run resumed from
/// a checkpoint continues with the same engine, so the same bits as `step` in one piece.
///
/// # Errors
/// As [`drive_kept`].
pub fn drive_kept_with<T, O, F>(
    ctx: T::Ctx,
    job: &Quota,
    start: impl FnOnce() -> LatticeState<T>,
    obs: &mut O,
    keep: &Keeper<F, O::Lane>,
    mut step: impl FnMut(&mut LatticeState<T>, u64, &mut O) -> Result<(), Error>,
) -> Result<LatticeState<T>, Error>
where
    T: Real,
    O: Observer<1> + LaneCheckpoint,
    F: Serialize + DeserializeOwned + Clone,
{
    let (mut s, mut done) = match keep.resumed(job) {
        Some(f) => {
            obs.restore_lane(0, &f.observers)?;
            (f.state::<T>(ctx)?, f.collisions)
        }
        None => (start(), 0),
    };
    let mut pace = Pace::new(keep.segment(T::bits(ctx) > 53));
    let mut segment = pace.len;
    let mut last = Instant::now();
    while done < job.collisions {
        let q = (job.collisions - done).min(segment);
        keep.check_stop()?;
        let began = Instant::now();
        step(&mut s, q, obs)?;
        segment = pace.after(began.elapsed());
        done += q;
        if done < job.collisions {
            keep.save_if_due(&mut last, || vec![in_flight(job, done, &s, obs, 0)])?;
        }
    }
    Ok(s)
}

/// Runs up to [`BLOCK`] trajectories `jobs` together on the SIMD engine's `path` (the lanes of
/// `kernel`: the triangular trap or a convex cell) until each has
/// made its collisions — lane l from `start(l)`, or from its saved state if it was in flight
/// (with `obs`'s lane put back) — in segments, saving them at `keep`'s interval. Returns the
/// final states. The same bits as [`run_block`] in one piece.
///
/// # Errors
/// As [`run_block`], a saved state that does not fit, or an I/O error of the journal.
pub fn run_block_kept<O, F, K>(
    path: SimdPath,
    kernel: &K,
    jobs: &[Quota],
    start: impl Fn(usize) -> LatticeState<f64>,
    obs: &mut O,
    keep: &Keeper<F, O::Lane>,
    progress: &dyn Fn(u64),
) -> Result<Vec<LatticeState<f64>>, Error>
where
    O: Observer<BLOCK> + LaneCheckpoint,
    F: Serialize + DeserializeOwned + Clone,
    K: super::BlockKernel,
{
    let mut states = Vec::with_capacity(jobs.len());
    let mut done = vec![0u64; jobs.len()];
    for (l, j) in jobs.iter().enumerate() {
        match keep.resumed(j) {
            Some(f) => {
                obs.restore_lane(l, &f.observers)?;
                states.push(f.state::<f64>(())?);
                done[l] = f.collisions;
            }
            None => states.push(start(l)),
        }
    }
    let mut pace = Pace::new(keep.segment(false));
    let mut segment = pace.len;
    let mut last = Instant::now();
    loop {
        let quotas: Vec<u64> = jobs
            .iter()
            .zip(&done)
            .map(|(j, d)| (j.collisions - d).min(segment))
            .collect();
        if quotas.iter().all(|&q| q == 0) {
            return Ok(states);
        }
        keep.check_stop()?;
        let began = Instant::now();
        run_block(path, kernel, &mut states, &quotas, obs, progress)?;
        segment = pace.after(began.elapsed());
        done.iter_mut().zip(&quotas).for_each(|(d, q)| *d += q);
        keep.save_if_due(&mut last, || {
            (0..jobs.len())
                .filter(|&l| done[l] < jobs[l].collisions)
                .map(|l| in_flight(&jobs[l], done[l], &states[l], obs, l))
                .collect()
        })?;
    }
}

/// Lane `l`'s trajectory in flight: `job` after `collisions` collisions in `state`.
fn in_flight<T: Real, O: LaneCheckpoint>(
    job: &Quota,
    collisions: u64,
    state: &LatticeState<T>,
    obs: &O,
    l: usize,
) -> InFlight<O::Lane> {
    InFlight {
        run: job.run,
        index: job.index,
        collisions,
        state: state.to_exact(),
        observers: obs.save_lane(l),
    }
}
