//! Independent batches on a fixed number of threads, combined in batch order (so results do not
//! depend on the thread count).

use rayon::prelude::*;

use super::options::StopFlag;
use crate::Error;

/// Most batches (trajectories, orbits, runs) accepted: every batch keeps its result in memory until
/// the end, and error bars need dozens, not millions; 2²⁰ keeps the results well below a GiB.
pub const MAX_BATCHES: u32 = 1 << 20;

/// Refuses more than [`MAX_BATCHES`] batches, naming `what` and the valid range.
pub fn check_batches(what: &'static str, n: u32) -> Result<(), Error> {
    if n > MAX_BATCHES {
        return Err(Error::out_of_range(
            what,
            n,
            format!(
                "use at most {MAX_BATCHES} (each keeps its result in memory until the end; \
                 error bars need dozens)"
            ),
        ));
    }
    Ok(())
}

/// A pool of `threads` workers (a pool the system cannot start is a failure of the run).
pub fn thread_pool(threads: usize) -> Result<rayon::ThreadPool, Error> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Failed(format!("thread pool: {e}")))
}

/// The share of batch `b` when `total` units (collisions, visits) are split over `batches`:
/// ⌊total/batches⌋, plus one for the first `total mod batches` batches — `total` in all, exactly.
///
/// # Examples
///
/// ```
/// use lorentz_gas::engine::parallel::share;
/// let parts: Vec<u64> = (0..3).map(|b| share(10, 3, b)).collect();
/// assert_eq!(parts, vec![4, 3, 3]);
/// ```
pub fn share(total: u64, batches: u32, b: u32) -> u64 {
    let n = batches as u64;
    total / n + u64::from((b as u64) < total % n)
}

/// Runs `f(range)` for consecutive ranges of `chunk` items out of 0 … n−1 (the last may be
/// shorter) on `threads` threads; the results, each a vector of one value per item, are
/// concatenated in item order. For the SIMD engine, whose unit of work is a block of
/// trajectories.
pub fn par_chunks<R: Send, F: Fn(std::ops::Range<usize>) -> Result<Vec<R>, Error> + Sync + Send>(
    threads: usize,
    n: usize,
    chunk: usize,
    f: F,
) -> Result<Vec<R>, Error> {
    if threads == 0 {
        return Err(Error::Zero { what: "threads" });
    }
    let pool = thread_pool(threads)?;
    let ranges: Vec<std::ops::Range<usize>> = (0..n)
        .step_by(chunk.max(1))
        .map(|a| a..(a + chunk.max(1)).min(n))
        .collect();
    let parts: Vec<Vec<R>> = pool.install(|| {
        ranges
            .into_par_iter()
            .map(&f)
            .collect::<Result<Vec<_>, Error>>()
    })?;
    Ok(parts.into_iter().flatten().collect())
}

/// Runs `f(b)` for batches b = 0 … n−1 on `threads` threads; results in batch order.
pub fn par_batches<R: Send, F: Fn(u32) -> Result<R, Error> + Sync + Send>(
    threads: usize,
    n: u32,
    f: F,
) -> Result<Vec<R>, Error> {
    par_batches_watched(threads, n, None, f)
}

/// [`par_batches`], looking at `stop` before each batch: once it is requested, the batches not
/// yet started end at once and the run returns [`Error::Interrupted`].
pub fn par_batches_watched<R: Send, F: Fn(u32) -> Result<R, Error> + Sync + Send>(
    threads: usize,
    n: u32,
    stop: Option<&StopFlag>,
    f: F,
) -> Result<Vec<R>, Error> {
    if threads == 0 {
        return Err(Error::Zero { what: "threads" });
    }
    check_batches("batches", n)?;
    let pool = thread_pool(threads)?;
    let watched = |b: u32| {
        if let Some(s) = stop {
            s.check()?;
        }
        f(b)
    };
    pool.install(|| (0..n).into_par_iter().map(watched).collect())
}

/// The `items` in blocks of at most [`super::simd::BLOCK`] (one SIMD engine block each), as few
/// per block as spreads them over `threads` threads, each block run by `f` with `stop` looked at
/// before it ([`par_batches_watched`]); the results of all blocks in the items' order.
///
/// # Errors
/// Whatever `f` returns, no threads, or an interruption.
pub fn par_lane_blocks<T: Sync, R: Send>(
    threads: usize,
    items: &[T],
    stop: Option<&StopFlag>,
    f: impl Fn(&[T]) -> Result<Vec<R>, Error> + Sync + Send,
) -> Result<Vec<R>, Error> {
    let per = items
        .len()
        .div_ceil(threads.max(1))
        .clamp(1, super::simd::BLOCK);
    let blocks = items.len().div_ceil(per) as u32;
    let done = par_batches_watched(threads, blocks, stop, |b| {
        let from = b as usize * per;
        f(&items[from..(from + per).min(items.len())])
    })?;
    Ok(done.into_iter().flatten().collect())
}

/// Collisions of a scalar trajectory between two looks at the stop flag ([`in_legs`]): about a
/// second of walking at w = 0.1, less with jumps.
pub const STOP_EVERY: u64 = 1 << 20;

/// Drives one trajectory of `collisions` collisions as legs of at most `every` collisions,
/// `leg(k)` each, looking at `stop` before each leg, so that a stop requested mid-batch ends it
/// within a leg. The scalar drives keep nothing between calls but the state and the observer, so
/// the legs have the bits of one drive (`tests/numerics`' `a_trajectory_in_legs_has_the_bits_of_one_drive`).
///
/// # Errors
/// [`Error::Interrupted`] once a stop is requested, or `leg`'s error.
pub fn in_legs(
    stop: Option<&StopFlag>,
    collisions: u64,
    every: u64,
    mut leg: impl FnMut(u64) -> Result<(), Error>,
) -> Result<(), Error> {
    let every = every.max(1);
    let mut done = 0u64;
    while done < collisions {
        if let Some(s) = stop {
            s.check()?;
        }
        let k = every.min(collisions - done);
        leg(k)?;
        done += k;
    }
    Ok(())
}
