//! Moments at lags t on a logarithmic grid, with every grid time a time origin (overlapping
//! windows): the mean squared displacement ⟨|Δr(t)|²⟩, the velocity autocorrelation
//! ⟨v(0)·v(t)⟩, and at chosen lags the histogram of the scaled displacement
//! Δx/√(scale·t ln t) and Δy/√(scale·t ln t) (both components, as two samples).
//!
//! Positions and velocities are sampled on the fixed grid t = k·Δ, inside the free flight that
//! holds the grid time; displacements are differenced as exact lattice integers plus bounded
//! offsets ([`crate::scenes::lattice::Unwrapped`]), and the world velocity is the frame velocity
//! times the cell's orientation. Each sample costs one pass over the lags; at Δ equal to the mean
//! free time that is about one pass per collision.

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::checkpoint::LaneCheckpoint;
use crate::engine::observe::{EventLanes, Observer};
use crate::numbers::lanes::Lanes;
use crate::scenes::lattice::{Basis64, Unwrapped};

/// Bins of a histogram of the scaled displacement.
pub const HISTOGRAM_BINS: usize = 800;
/// The histograms cover [−`HISTOGRAM_RANGE`, `HISTOGRAM_RANGE`); values beyond fall in the end
/// bins.
pub const HISTOGRAM_RANGE: f64 = 8.0;

/// One trajectory's sums.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LagSums {
    /// Grid samples taken.
    pub samples: u64,
    /// Per lag: Σ |Δr|².
    pub squared: Vec<f64>,
    /// Per lag: Σ v(0)·v(t).
    pub velocity: Vec<f64>,
    /// Per histogram lag: [`HISTOGRAM_BINS`] counts of Δx/√(scale·t ln t) and Δy/√(…).
    pub histograms: Vec<Vec<u64>>,
}

impl LagSums {
    /// Windows (pairs of samples) at a lag of `steps` grid steps.
    pub fn windows(&self, steps: usize) -> u64 {
        self.samples.saturating_sub(steps as u64)
    }
}

/// One lane exactly (what a checkpoint keeps): the time left to the next grid time, the ring
/// of past samples (cell i, j, offset x, y, velocity x, y) and the sums.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MomentLane {
    until: f64,
    ring: Vec<[f64; 6]>,
    sums: LagSums,
}

/// The lag moments of L trajectories.
#[derive(Debug, Clone)]
pub struct LagMoments {
    dt: f64,
    steps: Vec<usize>,
    /// For each histogram: (index of its lag, 1/√(scale·t ln t) in bins per unit length).
    histogrammed: Vec<(usize, f64)>,
    mask: usize,
    basis: Basis64,
    lanes: Vec<MomentLane>,
}

impl LagMoments {
    /// Moments of `lanes` trajectories sampled every `dt`, at lags of `steps` grid steps
    /// (ascending, each ≥ 1), with a histogram at the lags `histogram_at` (indices into `steps`,
    /// each lag t = steps·dt > 1) of Δx/√(`scale`·t ln t).
    pub fn new(
        dt: f64,
        steps: &[usize],
        histogram_at: &[usize],
        scale: f64,
        basis: Basis64,
        lanes: usize,
    ) -> Self {
        let cap = (steps.iter().copied().max().unwrap_or(1) + 1).next_power_of_two();
        let bins_per_unit = HISTOGRAM_BINS as f64 / (2.0 * HISTOGRAM_RANGE);
        let histogrammed = histogram_at
            .iter()
            .map(|&k| {
                let t = steps[k] as f64 * dt;
                (k, bins_per_unit / (scale * t * t.ln()).sqrt())
            })
            .collect();
        let sums = LagSums {
            samples: 0,
            squared: vec![0.0; steps.len()],
            velocity: vec![0.0; steps.len()],
            histograms: vec![vec![0; HISTOGRAM_BINS]; histogram_at.len()],
        };
        LagMoments {
            dt,
            steps: steps.to_vec(),
            histogrammed,
            mask: cap - 1,
            basis,
            lanes: vec![
                MomentLane {
                    until: 0.0,
                    ring: vec![[0.0; 6]; cap],
                    sums,
                };
                lanes
            ],
        }
    }

    /// Lane `l`'s sums so far.
    pub fn sums(&self, l: usize) -> &LagSums {
        &self.lanes[l].sums
    }

    /// Records every grid time inside lane `l`'s flight.
    #[inline(always)]
    fn sample<const L: usize>(&mut self, e: &EventLanes<L>, l: usize) {
        let t = e.time[l];
        let mut tau = self.lanes[l].until;
        let sg = e.cell[2][l];
        let v = [sg * e.vel[0][l], sg * e.vel[1][l]];
        while tau <= t {
            let u = e.unwrapped(l, tau);
            self.push(l, [u.i as f64, u.j as f64, u.off[0], u.off[1], v[0], v[1]]);
            tau += self.dt;
        }
        self.lanes[l].until = tau - t;
    }

    /// Adds sample `u` (cell i, j, offset x, y, velocity x, y) to lane `l`.
    #[inline(always)]
    fn push(&mut self, l: usize, u: [f64; 6]) {
        let lane = &mut self.lanes[l];
        let ring = &mut lane.ring[..=self.mask];
        let idx = (lane.sums.samples as usize) & self.mask;
        ring[idx] = u;
        let here = Unwrapped {
            i: u[0] as i64,
            j: u[1] as i64,
            off: [u[2], u[3]],
        };
        let s = &mut lane.sums;
        let mut next_histogram = 0;
        for (k, &step) in self.steps.iter().enumerate() {
            if step as u64 > s.samples {
                break;
            }
            let old = &ring[idx.wrapping_sub(step) & self.mask];
            let from = Unwrapped {
                i: old[0] as i64,
                j: old[1] as i64,
                off: [old[2], old[3]],
            };
            let d = here.displacement_from(&from, &self.basis);
            s.squared[k] += d[0] * d[0] + d[1] * d[1];
            s.velocity[k] += u[4] * old[4] + u[5] * old[5];
            if let Some(&(hk, per)) = self.histogrammed.get(next_histogram)
                && hk == k
            {
                let h = &mut s.histograms[next_histogram];
                h[bin(d[0] * per)] += 1;
                h[bin(d[1] * per)] += 1;
                next_histogram += 1;
            }
        }
        s.samples += 1;
    }
}

/// The bin of a value already in bins from the histogram's centre.
#[inline(always)]
fn bin(x: f64) -> usize {
    let b = (x + HISTOGRAM_BINS as f64 / 2.0).floor();
    b.clamp(0.0, (HISTOGRAM_BINS - 1) as f64) as usize
}

impl LaneCheckpoint for LagMoments {
    type Lane = MomentLane;
    fn save_lane(&self, l: usize) -> MomentLane {
        self.lanes[l].clone()
    }
    fn restore_lane(&mut self, l: usize, saved: &MomentLane) -> Result<(), Error> {
        let s = &saved.sums;
        let finite = saved.until.is_finite()
            && saved.until >= 0.0
            && saved.ring.iter().flatten().all(|x| x.is_finite())
            && s.squared.iter().chain(&s.velocity).all(|x| x.is_finite());
        let fits = saved.ring.len() == self.mask + 1
            && s.squared.len() == self.steps.len()
            && s.velocity.len() == self.steps.len()
            && s.histograms.len() == self.histogrammed.len()
            && s.histograms.iter().all(|h| h.len() == HISTOGRAM_BINS);
        if !(finite && fits) {
            return Err(Error::Invalid(format!(
                "a lag-moment lane with a ring of {} and {} lags does not fit this run ({} and {}, all finite)",
                saved.ring.len(),
                s.squared.len(),
                self.mask + 1,
                self.steps.len()
            )));
        }
        self.lanes[l] = saved.clone();
        Ok(())
    }
}

impl<const L: usize> Observer<L> for LagMoments {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        for e in steps {
            for l in 0..L {
                if !e.is_live(l) {
                    continue;
                }
                if self.lanes[l].until > e.time[l] {
                    self.lanes[l].until -= e.time[l];
                } else {
                    self.sample::<L>(e, l);
                }
            }
        }
    }
}
