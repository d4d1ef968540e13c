//! Monte Carlo of the order-k correlated walk on the honeycomb (the lattice gas of the paper's
//! Fig. 6b): hops at the exact mean time τ each, D from the Einstein formula.
//!
//! Each walker starts at a trap with a history drawn from the stationary distribution π of
//! [`CorrelatedWalk::stationary`] and a uniformly random arrival direction (one of six), so its
//! increments are stationary from the first hop. Positions are exact integer lattice
//! coordinates ([`LatticePoint`]) and squared displacements exact integers, summed exactly in
//! `u128`. The mean squared displacement (units l²) of batch b is
//! MSD_b(n) = Σ_walkers |Δr(n)|²/l² / walkers after n hops, and since D_MZ = l²/(4τ),
//!
//! D/D_MZ = slope of MSD(n) against n (time nτ) = lim MSD(n)/n,
//!
//! fitted by least squares over n ∈ [`LatticeWalkConfig::fit_from`], `hops`]. Batch b uses
//! [`crate::scenes::sampling::stream`]`(seed, b)` only, so batches are independent and the result does
//! not depend on the number of threads (rayon over batches, results collected in order).
//! D/D_MZ and its standard error are the mean and standard error of the batch slopes.
//!
//! The fit's deterministic bias is exactly computable from the chain
//! ([`fit_bias`]): MSD(n) = n + 2Σ_{j<n}(n − j)C_j, so the slope over [n₀, n] differs from
//! 1 + 2ΣC_j only by terms of order Σ_{j≥n₀} j|C_j|.

use rand::Rng;
use rayon::prelude::*;

use crate::Error;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::statistics::{linear_fit, mean_se};

use super::honeycomb::{LatticePoint, next_direction};
use super::markov::CorrelatedWalk;
use crate::scenes::symbols::Symbol;

/// The random stream of walker batch `index` (never a trajectory's stream of the same seed).
fn walk_stream(seed: u64, index: u64) -> rand_xoshiro::Xoshiro256PlusPlus {
    StreamKey::new(seed, Purpose::LatticeWalk, index).rng()
}

/// Run parameters of [`simulate`].
#[derive(Debug, Clone, PartialEq)]
pub struct LatticeWalkConfig {
    /// Number of independent batches (≥ 2, for the standard error).
    pub batches: usize,
    /// Independent walkers per batch.
    pub walkers: usize,
    /// Hops per walker (the longest time, in units of τ).
    pub hops: usize,
    /// First time (in hops) of the linear fit; the fit runs over `fit_from..=hops`.
    pub fit_from: usize,
    /// Seed of the run ([`crate::scenes::sampling::stream`]).
    pub seed: u64,
}

impl LatticeWalkConfig {
    /// `batches` × `walkers` walkers of `hops` hops, fit over the second half.
    pub fn new(batches: usize, walkers: usize, hops: usize, seed: u64) -> Self {
        LatticeWalkConfig {
            batches,
            walkers,
            hops,
            fit_from: hops / 2,
            seed,
        }
    }

    fn check(&self) -> Result<(), Error> {
        if self.batches < 2 {
            return Err(Error::TooFew {
                what: "batches",
                min: 2,
                got: self.batches as u64,
            });
        }
        if self.walkers == 0 {
            return Err(Error::Zero { what: "walkers" });
        }
        if self.fit_from == 0 || self.fit_from + 2 > self.hops {
            return Err(Error::out_of_range(
                "fit_from",
                self.fit_from,
                format!(
                    "the fit window fit_from..={} must start at >= 1 hop and contain at least 3 \
                     times",
                    self.hops
                ),
            ));
        }
        Ok(())
    }
}

/// Result of [`simulate`].
#[derive(Debug, Clone, PartialEq)]
pub struct LatticeWalkResult {
    /// D/D_MZ (mean of the batch slopes).
    pub d_over_d_mz: f64,
    /// Its standard error (batch means).
    pub se: f64,
    /// The slope of each batch.
    pub batch_values: Vec<f64>,
    /// Total number of hops simulated.
    pub hops_total: u64,
}

impl LatticeWalkResult {
    /// D and its standard error in absolute units, D = D_MZ(w)·D/D_MZ.
    pub fn d(&self, g: &crate::scenes::triangular::geometry::Geometry<f64>) -> (f64, f64) {
        let m = g.d_mz();
        (self.d_over_d_mz * m, self.se * m)
    }
}

/// Cumulative sampling tables of a walk.
#[derive(Debug, Clone)]
pub struct Sampler<'a> {
    walk: &'a CorrelatedWalk,
    cum: Vec<[f64; 2]>,
    pi_cum: Vec<f64>,
}

impl<'a> Sampler<'a> {
    /// Precomputes the cumulative conditional and stationary distributions.
    pub fn new(walk: &'a CorrelatedWalk) -> Self {
        let cum = (0..walk.histories())
            .map(|h| {
                let c = walk.conditional(h);
                [c[0], c[0] + c[1]]
            })
            .collect();
        let mut acc = 0.0;
        let pi_cum = walk
            .stationary()
            .iter()
            .map(|p| {
                acc += p;
                acc
            })
            .collect();
        Sampler { walk, cum, pi_cum }
    }

    /// A walker in stationarity: history from π, arrival direction uniform in 0..6, at the
    /// origin.
    pub fn start<R: Rng + ?Sized>(&self, rng: &mut R) -> Walker {
        let u = rng.random::<f64>() * self.pi_cum[self.pi_cum.len() - 1];
        let h = self
            .pi_cum
            .iter()
            .position(|&c| u < c)
            .unwrap_or(self.pi_cum.len() - 1);
        let dir = rng.random_range(0..6u8);
        Walker {
            history: h,
            dir,
            pos: LatticePoint::default(),
        }
    }

    /// One hop: draws the exit symbol from p(· | history), moves, returns the symbol.
    #[inline]
    pub fn step<R: Rng + ?Sized>(&self, w: &mut Walker, rng: &mut R) -> Symbol {
        let u = rng.random::<f64>();
        let c = self.cum[w.history];
        let s = if u < c[0] {
            Symbol::Z
        } else if u < c[1] {
            Symbol::L
        } else {
            Symbol::R
        };
        w.dir = next_direction(w.dir, s);
        w.pos.hop(w.dir);
        w.history = self.walk.next_history(w.history, s);
        s
    }
}

/// One walker: history index, direction of the last hop, position (units of l, exact).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Walker {
    /// Index of the last k − 1 symbols.
    pub history: usize,
    /// Direction index (0..6) of the last hop.
    pub dir: u8,
    /// Position relative to the start.
    pub pos: LatticePoint,
}

/// The hop directions (indices 0..6) of one stationary walker of `n` hops, from
/// the lattice-walk stream `(seed, LatticeWalk, index)`: the input of [`super::green_kubo`].
pub fn direction_sequence(walk: &CorrelatedWalk, seed: u64, index: u64, n: usize) -> Vec<u8> {
    let s = Sampler::new(walk);
    let mut rng = walk_stream(seed, index);
    let mut w = s.start(&mut rng);
    (0..n)
        .map(|_| {
            s.step(&mut w, &mut rng);
            w.dir
        })
        .collect()
}

/// The exit symbols of one stationary walker of `n` hops, from the lattice-walk stream `(seed, LatticeWalk, index)`.
pub fn symbol_sequence(walk: &CorrelatedWalk, seed: u64, index: u64, n: usize) -> Vec<Symbol> {
    let s = Sampler::new(walk);
    let mut rng = walk_stream(seed, index);
    let mut w = s.start(&mut rng);
    (0..n).map(|_| s.step(&mut w, &mut rng)).collect()
}

/// The Einstein-formula D/D_MZ of the walk by Monte Carlo (see the module documentation).
///
/// # Examples
///
/// ```
/// use lorentz_gas::theory::{lattice_walk::{simulate, LatticeWalkConfig}, markov::CorrelatedWalk};
/// let w = CorrelatedWalk::memoryless(1.0 / 3.0).unwrap();
/// let r = simulate(&w, &LatticeWalkConfig::new(16, 128, 32, 1)).unwrap();
/// // The error is over 16 batches: a Student-t z-score with 15 dof, "4σ" = 5.48.
/// let k = lorentz_gas::statistics::normal_sigma_equivalent_t(15.0, 4.0);
/// assert!((r.d_over_d_mz - 1.0).abs() < k * r.se);
/// ```
pub fn simulate(
    walk: &CorrelatedWalk,
    cfg: &LatticeWalkConfig,
) -> Result<LatticeWalkResult, Error> {
    cfg.check()?;
    let sampler = Sampler::new(walk);
    let times: Vec<f64> = (cfg.fit_from..=cfg.hops).map(|n| n as f64).collect();
    let batch_values: Vec<f64> = (0..cfg.batches as u64)
        .into_par_iter()
        .map(|b| {
            let mut rng = walk_stream(cfg.seed, b);
            let mut sums = vec![0u128; cfg.hops + 1];
            for _ in 0..cfg.walkers {
                let mut w = sampler.start(&mut rng);
                for slot in sums.iter_mut().skip(1) {
                    sampler.step(&mut w, &mut rng);
                    *slot += w.pos.norm2() as u128;
                }
            }
            let msd: Vec<f64> = sums[cfg.fit_from..=cfg.hops]
                .iter()
                .map(|&s| s as f64 / cfg.walkers as f64)
                .collect();
            linear_fit(&times, &msd).1
        })
        .collect();
    let (m, se) = mean_se(&batch_values);
    Ok(LatticeWalkResult {
        d_over_d_mz: m,
        se,
        batch_values,
        hops_total: (cfg.batches * cfg.walkers * cfg.hops) as u64,
    })
}

/// The exact expected slope of the fit of [`simulate`] minus the exact D/D_MZ: the fit of the
/// exact MSD(n) = n + 2Σ_{j=1}^{n−1}(n − j)C_j over `fit_from..=hops`, minus
/// [`CorrelatedWalk::d_over_d_mz`]. Shows that the window is long enough.
pub fn fit_bias(walk: &CorrelatedWalk, cfg: &LatticeWalkConfig) -> Result<f64, Error> {
    let c = walk.correlations(cfg.hops);
    let times: Vec<f64> = (cfg.fit_from..=cfg.hops).map(|n| n as f64).collect();
    let msd: Vec<f64> = (cfg.fit_from..=cfg.hops)
        .map(|n| {
            let s: f64 = (1..n).map(|j| (n - j) as f64 * c[j - 1]).sum();
            n as f64 + 2.0 * s
        })
        .collect();
    Ok(linear_fit(&times, &msd).1 - walk.d_over_d_mz()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walkers_stay_on_the_honeycomb() {
        // After each hop the walker is on the sublattice fixed by the parity of the hop count:
        // the direction parity alternates.
        let w = CorrelatedWalk::memoryless(0.3).unwrap();
        let d = direction_sequence(&w, 5, 0, 1000);
        for p in d.windows(2) {
            assert_ne!(p[0] % 2, p[1] % 2);
        }
    }

    #[test]
    fn same_bits_for_any_thread_count() {
        let w = CorrelatedWalk::memoryless(0.38).unwrap();
        let cfg = LatticeWalkConfig::new(6, 200, 16, 9);
        let a = simulate(&w, &cfg).unwrap();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let b = pool.install(|| simulate(&w, &cfg).unwrap());
        assert_eq!(a, b);
    }

    #[test]
    fn bad_configurations_are_rejected() {
        let w = CorrelatedWalk::memoryless(0.38).unwrap();
        assert!(simulate(&w, &LatticeWalkConfig::new(1, 10, 16, 0)).is_err());
        assert!(simulate(&w, &LatticeWalkConfig::new(2, 0, 16, 0)).is_err());
        assert!(simulate(&w, &LatticeWalkConfig::new(2, 10, 2, 0)).is_err());
    }

    #[test]
    fn fit_bias_of_the_memoryless_walk_vanishes() {
        // C_j = 0 for p_bs = 1/3: MSD(n) = n exactly.
        let w = CorrelatedWalk::memoryless(1.0 / 3.0).unwrap();
        // Least squares on exact data: relative error ≤ m·κ·u with m = 33 points and
        // κ([1, n]) ≤ 2·64 for n ∈ [32, 64]: ≤ 33·128·u ≈ 4.7e-13.
        let b = fit_bias(&w, &LatticeWalkConfig::new(2, 1, 64, 0)).unwrap();
        assert!(b.abs() <= 33.0 * 128.0 * f64::EPSILON / 2.0, "{b}");
    }
}
