//! The drivers of kept runs: a trajectory (or a SIMD block of them) run in segments paced by
//! wall time, from its saved state if it was in flight, stopping at its marks and saving itself
//! at the keeper's interval. Where a segment ends never changes the bits.

use std::time::{Duration, Instant};

use serde::Serialize;
use serde::de::DeserializeOwned;

use super::{InFlight, Keeper, LaneCheckpoint, Quota};
use crate::Error;
use crate::engine::observe::Observer;
use crate::engine::simd::BLOCK;
use crate::engine::{SimdPath, drive, run_block};
use crate::kernel::cell::CellKernel;
use crate::numbers::real::Real;
use crate::scenes::lattice::{Lattice, LatticeState};

/// Most collisions per trajectory between two looks at the clock and the stop flag on the SIMD
/// and `f64` engines, and at MPFR precision; [`Pace`] keeps each segment near
/// [`SEGMENT_TIME`] below these.
pub(super) const SEGMENT_F64: u64 = 1 << 20;
pub(super) const SEGMENT_MPFR: u64 = 1 << 14;

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
/// engine, or the one with long flights ([`crate::engine::long_flight::drive_jumps`]). A run resumed from
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
        let q = keep.up_to_mark(job, done, (job.collisions - done).min(segment));
        keep.check_stop()?;
        let began = Instant::now();
        step(&mut s, q, obs)?;
        segment = pace.after(began.elapsed());
        done += q;
        if keep.at_mark(job, done) {
            // Kept in the journal at once: the state is saved.
            keep.mark(in_flight(job, done, &s, obs, 0))?;
            last = Instant::now();
        } else if done < job.collisions {
            keep.save_if_due(&mut last, || vec![in_flight(job, done, &s, obs, 0)])?;
        }
    }
    if keep.captures_ends() {
        keep.end(in_flight(job, done, &s, obs, 0));
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
    K: crate::engine::BlockKernel,
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
            .map(|(j, &d)| keep.up_to_mark(j, d, (j.collisions - d).min(segment)))
            .collect();
        if quotas.iter().all(|&q| q == 0) {
            if keep.captures_ends() {
                for (l, j) in jobs.iter().enumerate() {
                    keep.end(in_flight(j, done[l], &states[l], obs, l));
                }
            }
            return Ok(states);
        }
        keep.check_stop()?;
        let began = Instant::now();
        run_block(path, kernel, &mut states, &quotas, obs, progress)?;
        segment = pace.after(began.elapsed());
        done.iter_mut().zip(&quotas).for_each(|(d, q)| *d += q);
        let marked = |l: usize| quotas[l] > 0 && keep.at_mark(&jobs[l], done[l]);
        for l in (0..jobs.len()).filter(|&l| marked(l)) {
            keep.mark(in_flight(&jobs[l], done[l], &states[l], obs, l))?;
        }
        // A lane at a mark was just kept in the journal: it is not saved twice.
        keep.save_if_due(&mut last, || {
            (0..jobs.len())
                .filter(|&l| done[l] < jobs[l].collisions && !marked(l))
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
