//! Mean squared displacement ⟨|r(t + τ) − r(t)|²⟩ at a set of lags, with every sample a time
//! origin (overlapping windows). Positions are sampled on the fixed grid t = k·Δ, interpolated
//! inside the free flight that contains the sample time; displacements are differenced as exact
//! lattice integers plus bounded offsets ([`Unwrapped`]).
//!
//! Cost: only the lags the fit windows use are accumulated (a dozen, not every multiple of Δ), the
//! ring of past samples has a power-of-two length (an index is a mask, not a division), and the
//! per-event work is one comparison per lane against the time left to the next sample — done for
//! all lanes at once; a sample (once per Δ ≈ one hop) is handled lane by lane.

use super::{lanes, EventLanes, Observer};
use crate::scenes::lattice::{Basis64, Unwrapped};

/// The MSD accumulator of one trajectory.
#[derive(Debug, Clone)]
struct Lane {
    ring: Vec<Unwrapped>,
    n: u64,
    sums: Vec<f64>,
}

/// Accumulates the MSD of L trajectories.
#[derive(Debug, Clone)]
pub struct Msd {
    dt: f64,
    lags: Vec<usize>,
    mask: usize,
    basis: Basis64,
    until: Vec<f64>,
    lanes: Vec<Lane>,
}

impl Msd {
    /// Samples every `dt` (time units); lags in units of `dt`; `lanes` trajectories.
    pub fn new(dt: f64, lags: &[usize], basis: Basis64, lanes: usize) -> Self {
        let cap = (lags.iter().copied().max().unwrap_or(1) + 1).next_power_of_two();
        Msd {
            dt,
            lags: lags.to_vec(),
            mask: cap - 1,
            basis,
            until: vec![0.0; lanes],
            lanes: vec![
                Lane {
                    ring: vec![Unwrapped::default(); cap],
                    n: 0,
                    sums: vec![0.0; lags.len()],
                };
                lanes
            ],
        }
    }

    /// Records every grid time inside lane `l`'s flight (the rare path).
    #[cold]
    #[inline(never)]
    fn sample<const L: usize>(&mut self, e: &EventLanes<L>, l: usize) {
        let t = e.time[l];
        let mut tau = self.until[l];
        while tau <= t {
            let u = e.unwrapped(l, tau);
            self.push(l, u);
            tau += self.dt;
        }
        self.until[l] = tau - t;
    }

    #[inline(always)]
    fn push(&mut self, l: usize, u: Unwrapped) {
        let lane = &mut self.lanes[l];
        let idx = (lane.n as usize) & self.mask;
        lane.ring[idx] = u;
        for (k, &lag) in self.lags.iter().enumerate() {
            if (lag as u64) <= lane.n {
                let old = &lane.ring[idx.wrapping_sub(lag) & self.mask];
                let d = u.displacement_from(old, &self.basis);
                lane.sums[k] += d[0] * d[0] + d[1] * d[1];
            }
        }
        lane.n += 1;
    }

    /// The lags (in units of the sampling interval).
    pub fn lags(&self) -> &[usize] {
        &self.lags
    }
    /// The sampling interval.
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// MSD at each lag of lane `l` (NaN at a lag longer than the samples taken).
    pub fn values(&self, l: usize) -> Vec<f64> {
        let lane = &self.lanes[l];
        self.lags
            .iter()
            .zip(&lane.sums)
            .map(|(&lag, s)| {
                let c = lane.n.saturating_sub(lag as u64);
                if c > 0 {
                    s / c as f64
                } else {
                    f64::NAN
                }
            })
            .collect()
    }
    /// Number of samples taken in lane `l`.
    pub fn samples(&self, l: usize) -> u64 {
        self.lanes[l].n
    }
}

impl<const L: usize> Observer<L> for Msd {
    #[inline(always)]
    fn observe(&mut self, e: &EventLanes<L>) {
        let until = lanes::<f64, L>(&mut self.until);
        let mut due = 0u64;
        for l in 0..L {
            // A flight that ends before the next grid time only shortens the wait.
            let wait = e.live[l] && until[l] > e.time[l];
            until[l] = if wait { until[l] - e.time[l] } else { until[l] };
            due |= ((e.live[l] && !wait) as u64) << l;
        }
        while due != 0 {
            let l = due.trailing_zeros() as usize;
            due &= due - 1;
            self.sample(e, l);
        }
    }
}
