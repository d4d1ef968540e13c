//! Mean squared displacement ⟨|r(t + τ) − r(t)|²⟩ at a set of lags, with every sample a time
//! origin (overlapping windows). Positions are sampled on the fixed grid t = k·Δ, interpolated
//! inside the free flight that contains the sample time; displacements are differenced as exact
//! lattice integers plus bounded offsets ([`crate::scenes::lattice::Unwrapped`]).
//!
//! The grid is as coarse as the lags allow: lags L₁ … Lₖ in units of τ are sampled every Δ = gτ
//! with g = gcd(L₁, …, Lₖ) (5 for the default fit windows [10τ, 40τ] and [20τ, 80τ]), so every
//! lag is a whole number of grid steps and every grid point is a time origin. Origins every 5τ
//! instead of every τ cost almost nothing in statistical power at lags ≥ 10τ — the windows
//! overlap by half or more and are nearly redundant (`proofs-notes/msd-grid.md`) — and the
//! displacements to accumulate drop fivefold.
//!
//! Cost: only the lags the fit windows use are accumulated (a dozen), the ring of past samples
//! has a power-of-two length (an index is a mask, not a division), and the per-event work is one
//! vector comparison against the time left to the next sample for all lanes at once; a sample
//! (once per Δ, several hops) is handled lane by lane.

use serde::{Deserialize, Serialize};

use crate::engine::observe::{lanes, EventLanes, Observer};
use crate::numbers::lanes::Lanes;
use crate::scenes::lattice::Basis64;
use crate::Error;

/// The MSD accumulator of one trajectory: a ring of past samples (cell i, j as exact `f64`
/// integers and the offset x, y) and one sum per lag.
#[derive(Debug, Clone)]
struct Lane {
    ring: Vec<[f64; 4]>,
    n: u64,
    sums: Vec<f64>,
}

/// Accumulates the MSD of L trajectories.
#[derive(Debug, Clone)]
pub struct Msd {
    dt: f64,
    lags: Vec<usize>,
    steps: Vec<usize>,
    mask: usize,
    basis: Basis64,
    until: Vec<f64>,
    lanes: Vec<Lane>,
}

impl Msd {
    /// The MSD of `lanes` trajectories at `lags` in units of `tau` (each ≥ 1), sampled every
    /// gcd(lags)·`tau`.
    pub fn new(tau: f64, lags: &[usize], basis: Basis64, lanes: usize) -> Self {
        let g = lags.iter().fold(0, |g, &l| gcd(g, l)).max(1);
        let steps: Vec<usize> = lags.iter().map(|&l| l / g).collect();
        let cap = (steps.iter().copied().max().unwrap_or(1) + 1).next_power_of_two();
        Msd {
            dt: g as f64 * tau,
            lags: lags.to_vec(),
            steps,
            mask: cap - 1,
            basis,
            until: vec![0.0; lanes],
            lanes: vec![
                Lane {
                    ring: vec![[0.0; 4]; cap],
                    n: 0,
                    sums: vec![0.0; lags.len()],
                };
                lanes
            ],
        }
    }

    /// Records every grid time inside lane `l`'s flight (the rare path).
    #[inline(always)]
    fn sample<const L: usize>(&mut self, e: &EventLanes<L>, l: usize) {
        let t = e.time[l];
        let mut tau = self.until[l];
        while tau <= t {
            let u = e.unwrapped(l, tau);
            self.push(l, [u.i as f64, u.j as f64, u.off[0], u.off[1]]);
            tau += self.dt;
        }
        self.until[l] = tau - t;
    }

    /// Adds sample `u` of lane `l`: for every lag, |u − (the sample that many steps back)|²,
    /// differenced as in [`crate::scenes::lattice::Unwrapped::displacement_from`] (exact integer
    /// differences, then the basis). Plain scalar code: it runs once per grid step, so a dozen
    /// lags cost little, and it is the same code on every engine.
    #[inline(always)]
    fn push(&mut self, l: usize, u: [f64; 4]) {
        let lane = &mut self.lanes[l];
        let ring = &mut lane.ring[..=self.mask];
        let idx = (lane.n as usize) & self.mask;
        ring[idx] = u;
        let b = &self.basis;
        for (&step, sum) in self.steps.iter().zip(lane.sums.iter_mut()) {
            if step as u64 <= lane.n {
                let old = &ring[idx.wrapping_sub(step) & self.mask];
                let (di, dj) = (u[0] - old[0], u[1] - old[1]);
                let dx = b.a * (di + b.beta * dj) + (u[2] - old[2]);
                let dy = b.h * dj + (u[3] - old[3]);
                *sum += dx * dx + dy * dy;
            }
        }
        lane.n += 1;
    }

    /// The lags (in units of τ, as given).
    pub fn lags(&self) -> &[usize] {
        &self.lags
    }
    /// The sampling interval gcd(lags)·τ.
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// MSD at each lag of lane `l` (NaN at a lag longer than the samples taken).
    pub fn values(&self, l: usize) -> Vec<f64> {
        let lane = &self.lanes[l];
        self.steps
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

    /// Everything lane `l` has accumulated, exactly (what a checkpoint keeps).
    pub fn lane_state(&self, l: usize) -> MsdLaneState {
        let lane = &self.lanes[l];
        MsdLaneState {
            until: self.until[l],
            ring: lane.ring.clone(),
            samples: lane.n,
            sums: lane.sums.clone(),
        }
    }

    /// Puts back into lane `l` what [`Msd::lane_state`] took from an MSD of the same lags and
    /// sampling interval.
    ///
    /// # Errors
    /// If the state has another ring or number of lags, or non-finite values.
    pub fn set_lane_state(&mut self, l: usize, s: &MsdLaneState) -> Result<(), Error> {
        let finite = s.until.is_finite()
            && s.ring.iter().flatten().all(|x| x.is_finite())
            && s.sums.iter().all(|x| x.is_finite() && *x >= 0.0);
        if s.ring.len() != self.mask + 1 || s.sums.len() != self.lags.len() || !finite {
            return Err(Error::Invalid(format!(
                "an MSD lane state with {} samples in its ring and {} sums does not fit this run \
                 ({} and {}, all finite)",
                s.ring.len(),
                s.sums.len(),
                self.mask + 1,
                self.lags.len()
            )));
        }
        self.until[l] = s.until;
        self.lanes[l] = Lane {
            ring: s.ring.clone(),
            n: s.samples,
            sums: s.sums.clone(),
        };
        Ok(())
    }
}

/// One lane of an [`Msd`], exactly: the time left to its next sample, its ring of past samples,
/// how many it has taken, and its sums per lag.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MsdLaneState {
    /// Time left to the next grid time.
    pub until: f64,
    /// Past samples (cell i, j, offset x, y), indexed by sample number modulo the ring length.
    pub ring: Vec<[f64; 4]>,
    /// Samples taken.
    pub samples: u64,
    /// Sum of squared displacements per lag.
    pub sums: Vec<f64>,
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

impl<const L: usize> Observer<L> for Msd {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        for e in steps {
            self.step::<V, L>(e);
        }
    }
}

impl Msd {
    #[inline(always)]
    fn step<V: Lanes, const L: usize>(&mut self, e: &EventLanes<L>) {
        let until = lanes::<f64, L>(&mut self.until);
        let mut due = 0u64;
        let mut o = 0;
        while o < L {
            // A flight that ends before the next grid time only shortens the wait.
            let live = V::from_bits(e.live_bits >> o);
            let u = V::load(&until[o..]);
            let t = V::load(&e.time[o..]);
            let wait = V::and(live, u.gt(t));
            V::select(wait, u.sub(t), u).store(&mut until[o..]);
            due |= V::bits(V::and_not(live, wait)) << o;
            o += V::WIDTH;
        }
        while due != 0 {
            let l = due.trailing_zeros() as usize;
            due &= due - 1;
            self.sample::<L>(e, l);
        }
    }
}
