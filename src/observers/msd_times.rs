//! The mean squared displacement, the velocity autocorrelation (whole and per component) and its
//! running Green–Kubo integral at times the user chooses, from t = 0 on.
//!
//! Time origins are taken every `spacing` (the mean free time ⟨ℓ⟩, or longer when the longest
//! time asks for more than [`MAX_ORIGINS`] of them in memory), and each origin is paired with the
//! position and velocity at every grid time after it. A grid time t is written t = q·spacing + ρ
//! with an integer q and 0 ≤ ρ < spacing: the end of origin m − q at lag t comes ρ after origin
//! m, so the ends due after an origin all come before the next one, in the order of their ρ. Only
//! one countdown is kept (the time to the next origin, as [`super::msd_curve`] keeps it) and a
//! ring of the last q_max + 1 origins; no absolute time is ever formed, so a lag is t to the
//! rounding of the flights it spans, at any length of run. Per grid time the sums are
//!
//! * |Δr|², Δr differenced as exact lattice integers plus bounded offsets (as [`super::msd`]);
//! * v(t₀)·Δr, half of whose mean is the running Green–Kubo integral ½∫₀ᵗ⟨v(0)·v(s)⟩ds
//!   (`proofs-notes/msd-curve.md`);
//! * v_x(t₀)v_x(t₀ + t) and v_y(t₀)v_y(t₀ + t), the velocity autocorrelation per component
//!   (½ each at t = 0 for an isotropic start at speed 1: `proofs-notes/msd-times.md`).
//!
//! At t = 0 the end is the origin itself: Δr = 0 exactly. Work: one pair per grid time per
//! origin, so about as many pair sums per collision as grid times (an opt-in diagnostic). Nothing
//! here touches [`super::msd`], which D is fitted from.

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::observe::{EventLanes, Observer};
use crate::numbers::lanes::Lanes;
use crate::scenes::lattice::Basis64;

/// The most grid times.
pub const MAX_TIMES: usize = 1000;
/// The most time origins one lane keeps in memory (the ring): the spacing of the origins grows
/// beyond ⟨ℓ⟩ when the longest time would need more.
pub const MAX_ORIGINS: usize = 1 << 14;

/// One sample: cell i, j (exact integers in `f64`), the offset x, y, and the velocity vx, vy in
/// the world frame.
type Sample = [f64; 6];

/// The grid: the times (from 0, increasing) and the spacing of the time origins.
#[derive(Debug, Clone, PartialEq)]
pub struct TimesGrid {
    times: Vec<f64>,
    spacing: f64,
    /// Per time: q (whole spacings) and ρ (the rest).
    split: Vec<(usize, f64)>,
    /// The times' indices in increasing ρ.
    order: Vec<usize>,
}

impl TimesGrid {
    /// The grid of `times` (finite, ≥ 0, increasing; validated by the caller) with origins every
    /// ⟨ℓ⟩ = `mean_free_path`, or every longest/[`MAX_ORIGINS`] if that is longer.
    pub fn new(times: Vec<f64>, mean_free_path: f64) -> Self {
        let longest = times.last().copied().unwrap_or(0.0);
        let spacing = mean_free_path.max(longest / MAX_ORIGINS as f64);
        let split: Vec<(usize, f64)> = times
            .iter()
            .map(|&t| {
                let q = (t / spacing).floor();
                let rest = (t - q * spacing).clamp(0.0, spacing);
                // A rest that rounds to the spacing is the next whole spacing.
                if rest >= spacing {
                    (q as usize + 1, 0.0)
                } else {
                    (q as usize, rest)
                }
            })
            .collect();
        let mut order: Vec<usize> = (0..times.len()).collect();
        order.sort_by(|&a, &b| split[a].1.total_cmp(&split[b].1).then(a.cmp(&b)));
        TimesGrid {
            times,
            spacing,
            split,
            order,
        }
    }

    /// The times.
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The time between two origins.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// Origins the ring keeps: q_max + 1.
    fn ring(&self) -> usize {
        self.split.iter().map(|s| s.0).max().unwrap_or(0) + 1
    }
}

/// Everything one lane has accumulated, exactly (what a checkpoint keeps).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimesLaneState {
    /// Time from the current point to the next origin.
    pub until: f64,
    /// Time from the current point back to the latest origin (≤ 0).
    pub last: f64,
    /// The next end of the latest origin still due (an index into the times in increasing ρ).
    pub next: usize,
    /// Origins taken.
    pub origins: u64,
    /// The ring of the last origins, origin n at slot n mod its length.
    pub ring: Vec<Sample>,
    /// Per time: [Σ|Δr|², Σ v(t₀)·Δr, Σ v_x v_x, Σ v_y v_y].
    pub sums: Vec<[f64; 4]>,
    /// Per time: the pairs summed.
    pub pairs: Vec<u64>,
}

/// The values of one trajectory at the grid times (NaN where no pair was summed).
#[derive(Debug, Clone, PartialEq)]
pub struct TimesValues {
    /// ⟨|Δr|²⟩.
    pub msd: Vec<f64>,
    /// ⟨v(0)·v(t)⟩.
    pub vacf: Vec<f64>,
    /// ⟨v_x(0)v_x(t)⟩.
    pub vacf_x: Vec<f64>,
    /// ⟨v_y(0)v_y(t)⟩.
    pub vacf_y: Vec<f64>,
    /// ½⟨v(0)·Δr(t)⟩.
    pub green_kubo: Vec<f64>,
}

/// Accumulates the values at the grid times of L trajectories.
#[derive(Debug, Clone)]
pub struct MsdAtTimes {
    grid: TimesGrid,
    basis: Basis64,
    lanes: Vec<TimesLaneState>,
}

impl MsdAtTimes {
    /// The values of `lanes` trajectories at the times of `grid`, displacements in `basis`.
    pub fn new(grid: TimesGrid, basis: Basis64, lanes: usize) -> Self {
        let n = grid.times.len();
        let lane = TimesLaneState {
            until: 0.0,
            last: 0.0,
            next: n,
            origins: 0,
            ring: vec![[0.0; 6]; grid.ring()],
            sums: vec![[0.0; 4]; n],
            pairs: vec![0; n],
        };
        MsdAtTimes {
            grid,
            basis,
            lanes: vec![lane; lanes],
        }
    }

    /// The grid.
    pub fn grid(&self) -> &TimesGrid {
        &self.grid
    }

    /// Lane `l`'s flight of `e`: the ends due in it and the origins in it, in time order.
    #[inline(always)]
    fn flight<const L: usize>(&mut self, e: &EventLanes<L>, l: usize) {
        let t = e.time[l];
        let (grid, basis) = (&self.grid, &self.basis);
        let lane = &mut self.lanes[l];
        let sg = e.cell[2][l];
        let sample = |dt: f64| -> Sample {
            let p = e.unwrapped(l, dt);
            let v = [sg * e.vel[0][l], sg * e.vel[1][l]];
            [p.i as f64, p.j as f64, p.off[0], p.off[1], v[0], v[1]]
        };
        loop {
            // Every end still due of the latest origin comes before the next origin.
            let due = if lane.until <= t { f64::INFINITY } else { t };
            while lane.next < grid.order.len() {
                let k = grid.order[lane.next];
                let (q, rho) = grid.split[k];
                let te = lane.last + rho;
                if te > due {
                    break;
                }
                lane.next += 1;
                let m = lane.origins - 1;
                if (q as u64) <= m {
                    let slot = ((m - q as u64) % lane.ring.len() as u64) as usize;
                    let u = sample(te.clamp(0.0, t));
                    add_pair(basis, &lane.ring[slot], &u, &mut lane.sums[k]);
                    lane.pairs[k] += 1;
                }
            }
            if lane.until > t {
                break;
            }
            let slot = (lane.origins % lane.ring.len() as u64) as usize;
            lane.ring[slot] = sample(lane.until);
            lane.origins += 1;
            lane.last = lane.until;
            lane.until += grid.spacing;
            lane.next = 0;
        }
        lane.until -= t;
        lane.last -= t;
    }

    /// Lane `l`'s values at the grid times.
    pub fn values(&self, l: usize) -> TimesValues {
        let lane = &self.lanes[l];
        let mut v = TimesValues {
            msd: Vec::new(),
            vacf: Vec::new(),
            vacf_x: Vec::new(),
            vacf_y: Vec::new(),
            green_kubo: Vec::new(),
        };
        for (s, &n) in lane.sums.iter().zip(&lane.pairs) {
            let c = if n == 0 { f64::NAN } else { n as f64 };
            v.msd.push(s[0] / c);
            v.green_kubo.push(0.5 * s[1] / c);
            v.vacf.push((s[2] + s[3]) / c);
            v.vacf_x.push(s[2] / c);
            v.vacf_y.push(s[3] / c);
        }
        v
    }

    /// Everything lane `l` has accumulated, exactly.
    pub fn lane_state(&self, l: usize) -> TimesLaneState {
        self.lanes[l].clone()
    }

    /// Puts back into lane `l` what [`MsdAtTimes::lane_state`] took from a run on the same grid.
    ///
    /// # Errors
    /// If the state has another number of times or origins kept, or values no run produces.
    pub fn set_lane_state(&mut self, l: usize, s: &TimesLaneState) -> Result<(), Error> {
        let n = self.grid.times.len();
        let fits = s.until.is_finite()
            && s.until >= 0.0
            && s.last.is_finite()
            && s.last <= 0.0
            && s.next <= n
            && (s.origins > 0 || s.next == n)
            && s.ring.len() == self.grid.ring()
            && s.ring.iter().flatten().all(|v| v.is_finite())
            && s.sums.len() == n
            && s.pairs.len() == n
            && s.sums
                .iter()
                .all(|x| x.iter().all(|v| v.is_finite()) && x[0] >= 0.0);
        if !fits {
            return Err(Error::Invalid(format!(
                "a saved MSD lane does not fit this run's grid ({n} times, {} origins kept)",
                self.grid.ring()
            )));
        }
        self.lanes[l] = s.clone();
        Ok(())
    }
}

/// Adds the pair (origin `o`, end `u`) to the sums of one time.
#[inline(always)]
fn add_pair(b: &Basis64, o: &Sample, u: &Sample, sums: &mut [f64; 4]) {
    let (di, dj) = (u[0] - o[0], u[1] - o[1]);
    let dx = b.a * (di + b.beta * dj) + (u[2] - o[2]);
    let dy = b.h * dj + (u[3] - o[3]);
    sums[0] += dx * dx + dy * dy;
    sums[1] += o[4] * dx + o[5] * dy;
    sums[2] += o[4] * u[4];
    sums[3] += o[5] * u[5];
}

impl<const L: usize> Observer<L> for MsdAtTimes {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        for e in steps {
            e.each_live(self.lanes.len(), |l| self.flight(e, l));
        }
    }
}

#[cfg(test)]
mod tests;
