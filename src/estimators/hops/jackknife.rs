//! Errors of the numbers derived from measured hop tables (the hierarchy's D_k, the exact D of a
//! correlated walk, their differences from D_GK): the jackknife over the independent batches.
//! Each quantity is a smooth function of batch means (sequence frequencies, p_cf, D_GK), so
//! evaluating it on the n leave-one-out pools gives its standard error with n − 1 dof
//! ([`crate::statistics::comparison::jackknife_se`]) — the delta method without derivatives of
//! a resolvent. Differences such as D_k − D_GK are jackknifed as one function, so the
//! correlation of the two (the same trajectories) is kept.

use crate::Error;
use crate::observers::hops::Hops;
use crate::scenes::symbols::sequence_name;
use crate::statistics::comparison::jackknife_se;
use crate::theory::green_kubo;
use crate::theory::sequences::SequenceProbabilities;

/// The statistics of a pool of batches that the theory is evaluated on.
pub(super) struct Pool {
    /// Sequence tables of length 1 … order (index k − 1): the mean over the pool's batches of
    /// each batch's frequencies, as [`super::run`] computes them.
    pub tables: Vec<SequenceProbabilities>,
    /// Mean collisionless fraction.
    pub p_cf: f64,
    /// Mean backscattering frequency (the sequence "z").
    pub p_bs: f64,
    /// Hop-level D_GK/D_MZ: the mean of the pool's per-batch estimates (fixed truncation).
    pub d_gk_over_d_mz: f64,
}

/// The n pools that leave out one batch each, in batch order.
pub(super) fn leave_one_out(res: &[Hops], order: usize) -> Result<Vec<Pool>, Error> {
    let dirs: Vec<_> = res.iter().map(|h| h.directions.clone()).collect();
    let gk = green_kubo::estimate(&dirs, green_kubo::HOP_TRUNCATION)?;
    (0..res.len())
        .map(|skip| {
            let keep: Vec<usize> = (0..res.len()).filter(|&i| i != skip).collect();
            pool(res, &keep, &gk.batch_values, order)
        })
        .collect()
}

/// The pool of batches `keep`.
fn pool(res: &[Hops], keep: &[usize], gk: &[f64], order: usize) -> Result<Pool, Error> {
    let n = keep.len() as f64;
    let mean = |f: &dyn Fn(usize) -> f64| keep.iter().map(|&i| f(i)).sum::<f64>() / n;
    let mut tables = Vec::with_capacity(order);
    for k in 1..=order {
        let len = 3usize.pow(k as u32);
        let freq = |i: usize, code: usize| {
            let tot: u64 = res[i].counts[k - 1].iter().sum();
            res[i].counts[k - 1][code] as f64 / tot.max(1) as f64
        };
        let p: Vec<f64> = (0..len).map(|code| mean(&|i| freq(i, code))).collect();
        tables.push(SequenceProbabilities::from_weights(k, p)?);
    }
    let z = (0..3)
        .find(|&c| sequence_name(1, c) == "z")
        .ok_or_else(|| Error::Failed("no symbol z among the length-1 sequences".into()))?;
    let p_bs = mean(&|i| {
        let tot: u64 = res[i].counts[0].iter().sum();
        res[i].counts[0][z] as f64 / tot.max(1) as f64
    });
    Ok(Pool {
        tables,
        p_cf: mean(&|i| res[i].collisionless as f64 / res[i].visits.max(1) as f64),
        p_bs,
        d_gk_over_d_mz: mean(&|i| gk[i]),
    })
}

/// The jackknife standard error of `f` over the leave-one-out pools.
pub(super) fn se(pools: &[Pool], f: impl Fn(&Pool) -> Result<f64, Error>) -> Result<f64, Error> {
    let values = pools.iter().map(f).collect::<Result<Vec<f64>, Error>>()?;
    Ok(jackknife_se(&values))
}
