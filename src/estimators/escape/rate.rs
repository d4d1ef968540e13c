//! The escape rate from lifetimes: a constant hazard on a time window, pooled over batches
//! (the censored exponential's estimate, with the batch and Fisher errors), and where the tail
//! starts.

use serde::{Deserialize, Serialize};

use crate::Error;

/// The life of one particle: its time in the strip (capped at t_max) and whether it was absorbed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Lifetime {
    /// Absorption time, or t_max if censored.
    pub time: f64,
    /// `false` if the particle was still inside at t_max.
    pub absorbed: bool,
}

/// Absorptions and exposure of a set of lifetimes inside the time window (from, to]: the
/// sufficient statistics of a constant hazard rate on that window (every particle alive at
/// `from` contributes min(t, to) − from of exposure; an absorption counts if from < t ≤ to).
pub fn window_counts(lifetimes: &[Lifetime], from: f64, to: f64) -> (u64, f64) {
    let mut n = 0u64;
    let mut exposure = 0.0;
    for l in lifetimes.iter().filter(|l| l.time > from) {
        exposure += l.time.min(to) - from;
        if l.absorbed && l.time <= to {
            n += 1;
        }
    }
    (n, exposure)
}

/// A rate on a time window, pooled over batches, with both of its error bars.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RateEstimate {
    /// γ̂ = Σn_b / ΣE_b.
    pub gamma: f64,
    /// Batch (ratio-estimator) standard error.
    pub err: f64,
    /// Fisher standard error of the censored exponential, γ̂/√n.
    pub err_mle: f64,
    /// Absorptions in the window.
    pub absorbed: u64,
    /// Particles alive at the window's start.
    pub alive: u64,
}

/// The censored-exponential MLE on (from, to] pooled over `batches`, with the ratio-estimator
/// batch error.
///
/// # Errors
/// If fewer than two batches, or no absorption in the window.
pub fn window_rate(batches: &[Vec<Lifetime>], from: f64, to: f64) -> Result<RateEstimate, Error> {
    if batches.len() < 2 {
        return Err(Error::TooFew {
            what: "batches",
            min: 2,
            got: batches.len() as u64,
        });
    }
    let counts: Vec<(u64, f64)> = batches.iter().map(|b| window_counts(b, from, to)).collect();
    let n: u64 = counts.iter().map(|c| c.0).sum();
    let e: f64 = counts.iter().map(|c| c.1).sum();
    if n == 0 || e <= 0.0 {
        return Err(Error::Failed(format!(
            "no absorption in the time window ({from}, {to}]: use more particles"
        )));
    }
    let gamma = n as f64 / e;
    let b = batches.len() as f64;
    let ss: f64 = counts
        .iter()
        .map(|&(nb, eb)| (nb as f64 - gamma * eb).powi(2))
        .sum();
    let alive = batches.iter().flatten().filter(|l| l.time > from).count() as u64;
    Ok(RateEstimate {
        gamma,
        err: (b / (b - 1.0) * ss).sqrt() / e,
        err_mle: gamma / (n as f64).sqrt(),
        absorbed: n,
        alive,
    })
}

/// The tail start: the time at which the empirical survival of `lifetimes` has fallen to
/// `survival` (the order statistic with that fraction of the particles above it).
pub fn tail_start(lifetimes: &[Lifetime], survival: f64) -> f64 {
    let mut t: Vec<f64> = lifetimes.iter().map(|l| l.time).collect();
    t.sort_by(f64::total_cmp);
    let k = ((1.0 - survival) * t.len() as f64).floor() as usize;
    t[k.min(t.len().saturating_sub(1))]
}
