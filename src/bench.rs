//! Single-trajectory kernel throughput (the CLI's `bench`): events only, no observables.

use std::time::Instant;

use rug::Float;
use serde::Serialize;

use crate::diffusion::Precision;
use crate::error::Error;
use crate::geometry::Geometry;
use crate::kernel::trap::Trap;
use crate::real::Real;
use crate::sampling::{equilibrium_state, stream};
use crate::scenes::lattice::{LatticeState, PeriodicLattice};

/// Throughput measurement: the median of several timed repetitions.
#[derive(Debug, Clone, Serialize)]
pub struct Throughput {
    /// Gap w.
    pub w: f64,
    /// "f64" or bits.
    pub precision: String,
    /// Collisions per repetition.
    pub collisions: u64,
    /// Number of repetitions.
    pub repetitions: usize,
    /// Median collisions per second over the repetitions.
    pub collisions_per_second: f64,
    /// Median nanoseconds per collision.
    pub ns_per_collision: f64,
    /// Every repetition's collisions per second, in order.
    pub samples: Vec<f64>,
    /// Crossings per collision seen (to compare event counts across implementations).
    pub crossings_per_collision: f64,
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

fn time_runs<T: Real>(
    lat: &PeriodicLattice<T>,
    start: &LatticeState<T>,
    n: u64,
    reps: usize,
) -> Result<(Vec<f64>, f64), Error> {
    // One untimed warm-up of a tenth of the length.
    let mut s = start.clone();
    lat.run_collisions(&mut s, (n / 10).max(1))?;
    let mut out = Vec::with_capacity(reps);
    let mut hops = 0;
    for _ in 0..reps {
        let t0 = Instant::now();
        hops = lat.run_collisions(&mut s, n)?;
        out.push(n as f64 / t0.elapsed().as_secs_f64());
    }
    Ok((out, hops as f64 / n as f64))
}

/// Times `reps` repetitions of `collisions` collisions on one thread, continuing one trajectory
/// from an equilibrium start (seed `seed`).
pub fn throughput(
    w: f64,
    precision: Precision,
    collisions: u64,
    reps: usize,
    seed: u64,
) -> Result<Throughput, Error> {
    Geometry::new(w)?;
    if collisions == 0 {
        return Err(Error::Zero { what: "collisions" });
    }
    if reps == 0 {
        return Err(Error::Zero {
            what: "repetitions",
        });
    }
    let trap64 = Trap::new(w)?;
    let s64 = equilibrium_state(&trap64, &mut stream(seed, 0));
    let (samples, cpc) = match precision {
        Precision::F64 => time_runs(&PeriodicLattice::new(w)?, &s64, collisions, reps)?,
        Precision::Bits(b) => {
            <Float as Real>::check_ctx(b)?;
            let lat = PeriodicLattice::new(Float::with_val(b, w))?;
            time_runs(
                &lat,
                &LatticeState::convert_from_f64(b, &s64),
                collisions,
                reps,
            )?
        }
    };
    let m = median(&samples);
    Ok(Throughput {
        w,
        precision: precision.to_string(),
        collisions,
        repetitions: reps,
        collisions_per_second: m,
        ns_per_collision: 1e9 / m,
        samples,
        crossings_per_collision: cpc,
    })
}
