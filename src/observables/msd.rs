//! Mean squared displacement ⟨|r(t + τ) − r(t)|²⟩ at a set of lags, with every sample a time
//! origin (overlapping windows). Positions are sampled on the fixed grid t = k·Δ, interpolated
//! inside the free flight that contains the sample time; displacements are differenced as exact
//! lattice integers plus bounded offsets ([`Unwrapped`]).

use crate::kernel::{CellKernel, Event};
use crate::real::Real;
use crate::scenes::lattice::{Basis64, Lattice, LatticeState, Unwrapped};

/// Accumulates the MSD of one trajectory.
#[derive(Debug, Clone)]
pub struct Msd {
    dt: f64,
    lags: Vec<usize>,
    ring: Vec<Unwrapped>,
    n: u64,
    until: f64,
    sums: Vec<f64>,
    counts: Vec<u64>,
    basis: Basis64,
}

impl Msd {
    /// Samples every `dt` (time units); lags in units of `dt`.
    pub fn new(dt: f64, lags: &[usize], basis: Basis64) -> Self {
        let cap = lags.iter().copied().max().unwrap_or(1) + 1;
        Msd {
            dt,
            lags: lags.to_vec(),
            ring: vec![Unwrapped::default(); cap],
            n: 0,
            until: 0.0,
            sums: vec![0.0; lags.len()],
            counts: vec![0; lags.len()],
            basis,
        }
    }

    /// Called with the state *before* `ev` is applied: records every grid time inside the
    /// flight of duration `ev.time`.
    #[inline(always)]
    pub fn observe<T: Real, K: CellKernel<T>>(
        &mut self,
        lat: &Lattice<T, K>,
        s: &LatticeState<T>,
        ev: &Event<T>,
    ) {
        let t = ev.time.to_f64();
        if self.until > t {
            self.until -= t;
            return;
        }
        let mut tau = self.until;
        while tau <= t {
            self.push(lat.unwrapped(s, tau));
            tau += self.dt;
        }
        self.until = tau - t;
    }

    #[inline(always)]
    fn push(&mut self, u: Unwrapped) {
        let cap = self.ring.len();
        let idx = (self.n % cap as u64) as usize;
        self.ring[idx] = u;
        for (k, &lag) in self.lags.iter().enumerate() {
            if (lag as u64) <= self.n {
                let old = &self.ring[(idx + cap - lag) % cap];
                let d = u.displacement_from(old, &self.basis);
                self.sums[k] += d[0] * d[0] + d[1] * d[1];
                self.counts[k] += 1;
            }
        }
        self.n += 1;
    }

    /// The lags (in units of the sampling interval).
    pub fn lags(&self) -> &[usize] {
        &self.lags
    }
    /// The sampling interval.
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// MSD at each lag.
    pub fn values(&self) -> Vec<f64> {
        self.sums
            .iter()
            .zip(&self.counts)
            .map(|(s, &c)| if c > 0 { s / c as f64 } else { f64::NAN })
            .collect()
    }
    /// Number of samples taken.
    pub fn samples(&self) -> u64 {
        self.n
    }
}
