//! Kernel throughput (the CLI's `bench`): events only, no observables; one trajectory per thread.

use std::time::Instant;

use rayon::prelude::*;
use serde::Serialize;

use crate::error::Error;
use crate::geometry::Geometry;
use crate::kernel::trap::Trap;
use crate::metadata::RunMeta;
use crate::precision::{AtPrecision, Precision};
use crate::real::Real;
use crate::sampling::stream;
use crate::scenes::lattice::{LatticeState, TriangularLattice};
use crate::scenes::triangular::equilibrium_state;

/// Throughput measurement: the median of several timed repetitions.
#[derive(Debug, Clone, Serialize)]
pub struct Throughput {
    /// Gap w.
    pub w: f64,
    /// Collisions per trajectory per repetition.
    pub collisions: u64,
    /// Number of repetitions.
    pub repetitions: usize,
    /// Trajectories run at once, one per thread.
    pub threads: usize,
    /// Median collisions per wall-clock second over the repetitions (all threads together).
    pub collisions_per_second: f64,
    /// Median collisions per second per thread.
    pub collisions_per_second_per_thread: f64,
    /// Median nanoseconds per collision on one thread.
    pub ns_per_collision: f64,
    /// Every repetition's collisions per second (all threads), in order.
    pub samples: Vec<f64>,
    /// Crossings per collision seen (to compare event counts across implementations).
    pub crossings_per_collision: f64,
    /// Version, seed, precision, engine, threads, command line.
    pub meta: RunMeta,
}

fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(|a, b| a.total_cmp(b));
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

/// Most repetitions: the median is settled long before.
pub const MAX_REPETITIONS: usize = 1000;

/// Timed repetitions of `threads` trajectories on number type `T`.
struct TimeRuns<'a> {
    w: f64,
    seed: u64,
    collisions: u64,
    reps: usize,
    threads: usize,
    progress: &'a (dyn Fn(u64) + Sync),
}

impl AtPrecision for TimeRuns<'_> {
    type Output = Result<(Vec<f64>, f64), Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Self::Output {
        let trap64 = Trap::new(self.w)?;
        let lat = TriangularLattice::new(T::from_f64(ctx, self.w))?;
        let mut states: Vec<LatticeState<T>> = (0..self.threads)
            .map(|k| {
                let s64 = equilibrium_state(&trap64, &mut stream(self.seed, k as u64));
                let mut s = LatticeState::convert_from_f64(ctx, &s64);
                s.flight.normalise_speed();
                s
            })
            .collect();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads)
            .build()
            .map_err(|e| Error::Invalid(format!("thread pool: {e}")))?;
        let n = self.collisions;
        let go = |states: &mut Vec<LatticeState<T>>, n: u64| -> Result<u64, Error> {
            pool.install(|| {
                states
                    .par_iter_mut()
                    .map(|s| lat.run_collisions(s, n))
                    .collect::<Result<Vec<u64>, Error>>()
                    .map(|v| v.iter().sum())
            })
        };
        // One untimed warm-up of a tenth of the length.
        go(&mut states, (n / 10).max(1))?;
        let mut out = Vec::with_capacity(self.reps);
        let mut hops = 0;
        for _ in 0..self.reps {
            let t0 = Instant::now();
            hops = go(&mut states, n)?;
            out.push((n * self.threads as u64) as f64 / t0.elapsed().as_secs_f64());
            (self.progress)(1);
        }
        Ok((out, hops as f64 / (n * self.threads as u64) as f64))
    }
}

/// Times `reps` repetitions of `collisions` collisions on each of `threads` trajectories run at
/// once (one per thread), continuing equilibrium starts (seed `seed`). `progress` receives
/// finished repetitions.
pub fn throughput(
    w: f64,
    precision: Precision,
    collisions: u64,
    reps: usize,
    seed: u64,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Throughput, Error> {
    Geometry::new(w)?;
    if collisions == 0 {
        return Err(Error::Zero { what: "collisions" });
    }
    if reps == 0 || reps > MAX_REPETITIONS {
        return Err(Error::Invalid(format!(
            "repetitions = {reps}: use 1 to {MAX_REPETITIONS}"
        )));
    }
    if threads == 0 {
        return Err(Error::Zero { what: "threads" });
    }
    let (samples, cpc) = precision.dispatch(TimeRuns {
        w,
        seed,
        collisions,
        reps,
        threads,
        progress,
    })?;
    let m = median(&samples);
    Ok(Throughput {
        w,
        collisions,
        repetitions: reps,
        threads,
        collisions_per_second: m,
        collisions_per_second_per_thread: m / threads as f64,
        ns_per_collision: 1e9 * threads as f64 / m,
        samples,
        crossings_per_collision: cpc,
        meta: RunMeta::new(Some(seed), None, precision, Some(threads)),
    })
}
