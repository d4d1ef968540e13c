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
//! Cost: the per-event work is one vector comparison against the time left to the next sample,
//! for all lanes at once, with that time kept in registers over the steps the engine hands over;
//! the samples those steps fall due (once per Δ, several hops) are taken afterwards, lane by lane.
//! A sample adds one squared displacement per lag:
//!
//! * **dense** (the largest lag is at most [`DENSE_STEPS`] grid steps, as for the default
//!   windows: 16 steps, 11 lags): the past samples are kept twice over in a ring per component, so
//!   that the samples 1 … R steps back are one contiguous slice, and the displacement is formed
//!   for every step back, in vector lanes, but added only at the lags accumulated;
//! * **sparse** (a longer lag: a wide window, or lags whose gcd is small): one lag at a time,
//!   from a ring of power-of-two length (an index is a mask, not a division).
//!
//! Both do per lag the same `f64` operations in the same order, so they give the same bits (a
//! test compares them), and a lane's state is kept in checkpoints in one format.

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::observe::{EventLanes, Observer, StepLanes, lanes};
use crate::numbers::lanes::Lanes;
use crate::scenes::lattice::Basis64;

/// The largest lag, in grid steps, accumulated by the dense layout (module documentation): beyond
/// it, forming the displacement at every step back would cost more than taking the lags one by
/// one.
pub const DENSE_STEPS: usize = 32;

/// Steps whose samples are found before any is taken (the engines hand over at most this many
/// at once; more are taken in groups of this size).
const GROUP: usize = 8;

/// The MSD accumulator of one trajectory: its past samples (cell i, j as exact `f64` integers
/// and the offset x, y), how many it has taken, and its sums.
///
/// Sparse layout: `ring[4·(n mod cap) + c]` holds component c of sample n, and `sums[k]` belongs
/// to lag k. Dense layout (R = the largest lag in steps): `ring[c·2R + (n mod R)]` and
/// `ring[c·2R + (n mod R) + R]` both hold it, `at` = n mod R, and `sums[R − s]` belongs to the lag
/// of s steps.
#[derive(Debug, Clone)]
struct Lane {
    ring: Vec<f64>,
    n: u64,
    at: usize,
    sums: Vec<f64>,
}

/// Accumulates the MSD of L trajectories.
#[derive(Debug, Clone)]
pub struct Msd {
    dt: f64,
    lags: Vec<usize>,
    steps: Vec<usize>,
    mask: usize,
    /// R, the largest lag in steps, if the layout is dense.
    dense: Option<usize>,
    basis: Basis64,
    until: Vec<f64>,
    lanes: Vec<Lane>,
}

impl Msd {
    /// The MSD of `lanes` trajectories at `lags` in units of `tau` (each ≥ 1), sampled every
    /// gcd(lags)·`tau`.
    pub fn new(tau: f64, lags: &[usize], basis: Basis64, lanes: usize) -> Self {
        Self::with_layout(tau, lags, basis, lanes, DENSE_STEPS)
    }

    /// [`Msd::new`] with the dense layout up to `dense_steps` (0: always sparse).
    fn with_layout(
        tau: f64,
        lags: &[usize],
        basis: Basis64,
        lanes: usize,
        dense_steps: usize,
    ) -> Self {
        let g = lags.iter().fold(0, |g, &l| gcd(g, l)).max(1);
        let steps: Vec<usize> = lags.iter().map(|&l| l / g).collect();
        let longest = steps.iter().copied().max().unwrap_or(1).max(1);
        let cap = (longest + 1).next_power_of_two();
        let dense = (longest <= dense_steps).then_some(longest);
        let lane = match dense {
            Some(r) => Lane {
                ring: vec![0.0; 8 * r],
                n: 0,
                at: 0,
                sums: vec![0.0; r],
            },
            None => Lane {
                ring: vec![0.0; 4 * cap],
                n: 0,
                at: 0,
                sums: vec![0.0; lags.len()],
            },
        };
        Msd {
            dt: g as f64 * tau,
            lags: lags.to_vec(),
            steps,
            mask: cap - 1,
            dense,
            basis,
            until: vec![0.0; lanes],
            lanes: vec![lane; lanes],
        }
    }

    /// Records every grid time from `tau` on inside lane `l`'s flight.
    #[inline(always)]
    fn sample<const L: usize>(&mut self, e: &EventLanes<L>, l: usize, mut tau: f64) {
        let t = e.time[l];
        while tau <= t {
            let u = e.unwrapped(l, tau);
            let u = [u.i as f64, u.j as f64, u.off[0], u.off[1]];
            match self.dense {
                Some(r) => self.push_dense(l, r, u),
                None => self.push_sparse(l, u),
            }
            tau += self.dt;
        }
    }

    /// Adds sample `u` of lane `l`: for every lag, |u − (the sample that many steps back)|²
    /// ([`squared_displacement`]), one lag at a time.
    #[inline(always)]
    fn push_sparse(&mut self, l: usize, u: [f64; 4]) {
        let lane = &mut self.lanes[l];
        let ring = &mut lane.ring[..4 * (self.mask + 1)];
        let idx = (lane.n as usize) & self.mask;
        ring[4 * idx..4 * idx + 4].copy_from_slice(&u);
        let b = &self.basis;
        for (&step, sum) in self.steps.iter().zip(lane.sums.iter_mut()) {
            if step as u64 <= lane.n {
                let o = 4 * (idx.wrapping_sub(step) & self.mask);
                let old = &ring[o..o + 4];
                *sum += squared_displacement(b, &u, [old[0], old[1], old[2], old[3]]);
            }
        }
        lane.n += 1;
    }

    /// [`Msd::push_sparse`]'s sums, formed for every step back 1 … `r` at once from contiguous
    /// slices (the same operations per lag), and added where that many samples exist; the sums of
    /// steps that are not lags are never read. Adding +0 instead leaves a sum bit for bit (it is
    /// +0 or positive).
    #[inline(always)]
    fn push_dense(&mut self, l: usize, r: usize, u: [f64; 4]) {
        let lane = &mut self.lanes[l];
        let (n, p) = (lane.n, lane.at);
        let (ri, rest) = lane.ring.split_at_mut(2 * r);
        let (rj, rest) = rest.split_at_mut(2 * r);
        let (rx, ry) = rest.split_at_mut(2 * r);
        // Slot p + j holds the sample r − j steps back, j = 0 … r − 1.
        let (wi, wj, wx, wy) = (&ri[p..p + r], &rj[p..p + r], &rx[p..p + r], &ry[p..p + r]);
        let sums = &mut lane.sums[..r];
        let b = &self.basis;
        for j in 0..r {
            let v = squared_displacement(b, &u, [wi[j], wj[j], wx[j], wy[j]]);
            sums[j] += if ((r - j) as u64) <= n { v } else { 0.0 };
        }
        for (ring, x) in [ri, rj, rx, ry].into_iter().zip(u) {
            ring[p] = x;
            ring[p + r] = x;
        }
        lane.n = n + 1;
        lane.at = if p + 1 == r { 0 } else { p + 1 };
    }

    /// The lags (in units of τ, as given).
    pub fn lags(&self) -> &[usize] {
        &self.lags
    }
    /// The sampling interval gcd(lags)·τ.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Lane `l`'s sum at lag k (the k-th of [`Msd::lags`]).
    fn sum(&self, l: usize, k: usize) -> f64 {
        let lane = &self.lanes[l];
        match self.dense {
            Some(r) => lane.sums[r - self.steps[k]],
            None => lane.sums[k],
        }
    }

    /// MSD at each lag of lane `l` (NaN at a lag longer than the samples taken).
    pub fn values(&self, l: usize) -> Vec<f64> {
        let n = self.lanes[l].n;
        (0..self.steps.len())
            .map(|k| {
                let c = n.saturating_sub(self.steps[k] as u64);
                if c > 0 {
                    self.sum(l, k) / c as f64
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

    /// Everything lane `l` has accumulated, exactly (what a checkpoint keeps), in the sparse
    /// layout whatever the lane's own (the dense one keeps only the last R samples, all a lag
    /// reads; the ring's older slots are 0).
    pub fn lane_state(&self, l: usize) -> MsdLaneState {
        let lane = &self.lanes[l];
        let cap = self.mask + 1;
        let ring = match self.dense {
            None => lane
                .ring
                .chunks(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect(),
            Some(r) => {
                let mut ring = vec![[0.0; 4]; cap];
                for m in lane.n.saturating_sub(r as u64)..lane.n {
                    let at = (m % r as u64) as usize;
                    ring[m as usize & self.mask] = [0, 1, 2, 3].map(|c| lane.ring[c * 2 * r + at]);
                }
                ring
            }
        };
        MsdLaneState {
            until: self.until[l],
            ring,
            samples: lane.n,
            sums: (0..self.steps.len()).map(|k| self.sum(l, k)).collect(),
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
        let n = s.samples;
        self.lanes[l] = match self.dense {
            None => Lane {
                ring: s.ring.iter().flatten().copied().collect(),
                n,
                at: 0,
                sums: s.sums.clone(),
            },
            Some(r) => {
                let mut ring = vec![0.0; 8 * r];
                for m in n.saturating_sub(r as u64)..n {
                    let at = (m % r as u64) as usize;
                    for (c, &x) in s.ring[m as usize & self.mask].iter().enumerate() {
                        ring[c * 2 * r + at] = x;
                        ring[c * 2 * r + at + r] = x;
                    }
                }
                let mut sums = vec![0.0; r];
                for (&step, &x) in self.steps.iter().zip(&s.sums) {
                    sums[r - step] = x;
                }
                Lane {
                    ring,
                    n,
                    at: (n % r as u64) as usize,
                    sums,
                }
            }
        };
        Ok(())
    }
}

/// |u − old|² for samples (cell i, j as exact `f64` integers, offset x, y), differenced as in
/// [`crate::scenes::lattice::Unwrapped::displacement_from`]: exact integer differences, then the
/// basis. Both layouts use it, so their sums are the same operations.
#[inline(always)]
fn squared_displacement(b: &Basis64, u: &[f64; 4], old: [f64; 4]) -> f64 {
    let (di, dj) = (u[0] - old[0], u[1] - old[1]);
    let dx = b.a * (di + b.beta * dj) + (u[2] - old[2]);
    let dy = b.h * dj + (u[3] - old[3]);
    dx * dx + dy * dy
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
    if b == 0 { a } else { gcd(b, a % b) }
}

impl<const L: usize> Observer<L> for Msd {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        for group in steps.chunks(GROUP.min(StepLanes::<L>::STEPS)) {
            self.group::<V, L>(group);
        }
    }
}

impl Msd {
    /// Finds which lanes fall due in `steps` (at most [`GROUP`]), then takes their samples.
    #[inline(always)]
    fn group<V: Lanes, const L: usize>(&mut self, steps: &[EventLanes<L>]) {
        let mut first = [[0.0; L]; GROUP];
        let mut due = StepLanes::<L>::default();
        let until = lanes::<f64, L>(&mut self.until);
        let dt = V::splat(self.dt);
        let mut o = 0;
        while o < L {
            let mut u = V::load(&until[o..]);
            for (k, e) in steps.iter().enumerate() {
                // A flight that ends before the next grid time only shortens the wait; one
                // that reaches it is sampled from there (u), and waits for the grid time after
                // its last sample: tau += dt while tau ≤ t, then tau − t, as one step would do.
                let live = V::from_bits(e.live_bits >> o);
                let t = V::load(&e.time[o..]);
                let reach = V::and_not(live, u.gt(t));
                u.store(&mut first[k][o..]);
                let next = u.add(dt);
                // A lane that is not live has t = +0 (`EventLanes`), and u − (+0) = u.
                let left = V::select(reach, next, u).sub(t);
                let again = V::bits(V::and(reach, t.ge(next)));
                u = left;
                if again != 0 {
                    // Rare: a flight longer than dt. Scalar, on copies (no vector crosses a call).
                    let (mut w, mut nx, mut tt) = ([0.0; 64], [0.0; 64], [0.0; 64]);
                    let n = V::WIDTH;
                    left.store(&mut w[..n]);
                    next.store(&mut nx[..n]);
                    t.store(&mut tt[..n]);
                    later_grid_times(&mut w[..n], &nx[..n], &tt[..n], self.dt, again);
                    u = V::load(&w[..n]);
                }
                due.set(k, V::bits(reach) << o);
            }
            u.store(&mut until[o..]);
            o += V::WIDTH;
        }
        for (k, l) in due {
            self.sample::<L>(&steps[k], l, first[k][l]);
        }
    }
}

/// The rare lanes (bits `again`) whose flight `t` holds more than one grid time: tau = `next`
/// continues by `dt` while tau ≤ t, and their wait becomes tau − t (the other lanes keep `wait`).
#[cold]
#[inline(never)]
fn later_grid_times(wait: &mut [f64], next: &[f64], t: &[f64], dt: f64, again: u64) {
    for l in (0..wait.len()).filter(|&l| (again >> l) & 1 == 1) {
        let mut tau = next[l];
        while tau <= t[l] {
            tau += dt;
        }
        wait[l] = tau - t[l];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::drive;
    use crate::scenes::lattice::TriangularLattice;
    use crate::scenes::sampling::stream;
    use crate::scenes::triangular::equilibrium_state;

    /// The MSD as first written, one sample and one lag at a time, with every sample kept: the
    /// reference both layouts must equal bit for bit.
    struct Reference {
        dt: f64,
        steps: Vec<usize>,
        basis: Basis64,
        until: f64,
        samples: Vec<[f64; 4]>,
        sums: Vec<f64>,
    }

    impl Observer<1> for Reference {
        fn observe<V: Lanes>(&mut self, steps: &[EventLanes<1>]) {
            for e in steps {
                let t = e.time[0];
                if self.until > t {
                    self.until -= t;
                    continue;
                }
                let mut tau = self.until;
                while tau <= t {
                    let u = e.unwrapped(0, tau);
                    let u = [u.i as f64, u.j as f64, u.off[0], u.off[1]];
                    let n = self.samples.len();
                    let b = &self.basis;
                    for (&step, sum) in self.steps.iter().zip(self.sums.iter_mut()) {
                        if step <= n {
                            let old = self.samples[n - step];
                            let (di, dj) = (u[0] - old[0], u[1] - old[1]);
                            let dx = b.a * (di + b.beta * dj) + (u[2] - old[2]);
                            let dy = b.h * dj + (u[3] - old[3]);
                            *sum += dx * dx + dy * dy;
                        }
                    }
                    self.samples.push(u);
                    tau += self.dt;
                }
                self.until = tau - t;
            }
        }
    }

    /// One trajectory at w watched by the dense and the sparse layout and by the reference;
    /// returns (dense, sparse, reference) values and the number of samples.
    fn watch(w: f64, tau: f64, lags: &[usize], collisions: u64) -> [Vec<f64>; 3] {
        let lat = TriangularLattice::new(w).unwrap();
        let basis = lat.basis_f64();
        let mut s = equilibrium_state(lat.trap(), &mut stream(41, 3));
        let g = lags.iter().fold(0, |g, &l| gcd(g, l));
        let mut obs = (
            Msd::with_layout(tau, lags, basis, 1, usize::MAX),
            Msd::with_layout(tau, lags, basis, 1, 0),
            Reference {
                dt: g as f64 * tau,
                steps: lags.iter().map(|&l| l / g).collect(),
                basis,
                until: 0.0,
                samples: Vec::new(),
                sums: vec![0.0; lags.len()],
            },
        );
        assert!(obs.0.dense.is_some() && obs.1.dense.is_none());
        drive(&lat, &mut s, collisions, &mut obs, &|_| {}).unwrap();
        let n = obs.2.samples.len() as u64;
        assert_eq!((obs.0.samples(0), obs.1.samples(0)), (n, n));
        let want = obs
            .2
            .steps
            .iter()
            .zip(&obs.2.sums)
            .map(|(&st, s)| match n.saturating_sub(st as u64) {
                0 => f64::NAN,
                c => s / c as f64,
            })
            .collect();
        [obs.0.values(0), obs.1.values(0), want]
    }

    fn same_bits(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
    }

    /// Both layouts equal the reference bit for bit: at the default grid, and at a grid much
    /// finer than a flight (several samples per flight: the rare path of `later_grid_times`),
    /// with lags that leave steps out and a lag longer than the run.
    #[test]
    fn both_layouts_equal_the_one_lag_at_a_time_reference() {
        for (w, tau, lags, n) in [
            (
                0.1,
                3.55,
                vec![10, 15, 20, 25, 30, 35, 40, 50, 60, 70, 80],
                200_000,
            ),
            (0.2, 0.013, vec![1, 2, 5, 7, 16], 3_000),
            (0.05, 0.3, vec![3, 9, 12, 30, 3_000_000], 20_000),
        ] {
            let [dense, sparse, want] = watch(w, tau, &lags, n);
            assert!(same_bits(&dense, &want), "dense {dense:?} vs {want:?}");
            assert!(same_bits(&sparse, &want), "sparse {sparse:?} vs {want:?}");
            assert!(want[0].is_finite() && want[0] > 0.0);
        }
    }

    /// A lane saved in the middle of a run and put back, into either layout, goes on to the
    /// bits of the run that was never stopped.
    #[test]
    fn a_saved_lane_resumes_in_either_layout() {
        let lat = TriangularLattice::new(0.15).unwrap();
        let basis = lat.basis_f64();
        let lags = [2, 4, 6, 10, 14];
        let make = |dense| Msd::with_layout(0.4, &lags, basis, 1, dense);
        let start = equilibrium_state(lat.trap(), &mut stream(9, 1));
        let mut whole = make(usize::MAX);
        drive(&lat, &mut start.clone(), 60_000, &mut whole, &|_| {}).unwrap();
        for (first, second) in [(usize::MAX, usize::MAX), (0, usize::MAX), (usize::MAX, 0)] {
            let mut s = start.clone();
            let mut a = make(first);
            drive(&lat, &mut s, 25_000, &mut a, &|_| {}).unwrap();
            let state = a.lane_state(0);
            assert_eq!(state.ring.len(), 8);
            let mut b = make(second);
            b.set_lane_state(0, &state).unwrap();
            if first == second {
                // (Across layouts, the dense one keeps only the slots a lag reads.)
                assert_eq!(b.lane_state(0), state);
            }
            drive(&lat, &mut s, 35_000, &mut b, &|_| {}).unwrap();
            assert!(
                same_bits(&b.values(0), &whole.values(0)),
                "{first} → {second}"
            );
            assert_eq!(b.samples(0), whole.samples(0));
        }
    }
}
