//! Independent batches on a fixed number of threads, combined in batch order (so results do not
//! depend on the thread count).

use rayon::prelude::*;

use crate::error::Error;

/// Runs `f(b)` for batches b = 0 … n−1 on `threads` threads; results in batch order.
pub fn par_batches<R: Send, F: Fn(u32) -> Result<R, Error> + Sync + Send>(
    threads: usize,
    n: u32,
    f: F,
) -> Result<Vec<R>, Error> {
    if threads == 0 {
        return Err(Error::Zero { what: "threads" });
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Invalid(e.to_string()))?;
    pool.install(|| (0..n).into_par_iter().map(&f).collect())
}
