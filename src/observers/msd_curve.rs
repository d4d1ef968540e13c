//! The mean squared displacement, the velocity autocorrelation and its running Green–Kubo
//! integral on a logarithmic time grid that starts inside the first free flight: the curve from
//! the ballistic regime (MSD = t² while no collision has happened) to the diffusive one
//! (MSD ≈ 4Dt), at about four times per octave.
//!
//! The grid is a multiple-τ scheme (Frenkel & Smit, *Understanding Molecular Simulation*, §4.4.2;
//! Ramírez et al., J. Chem. Phys. 133, 154103 (2010)) applied to *positions*, so it needs no
//! averaging and loses nothing: level 0 samples the position and velocity every Δ (a fraction of
//! the mean free time) and keeps the lags 1Δ … 7Δ; level k ≥ 1 keeps every 2ᵏ-th of those
//! samples and the lags 4·2ᵏΔ … 7·2ᵏΔ. The pairs are summed at the level-0 samples n ≡ 0
//! (mod 8), once per mean free time (every sample of the levels k ≥ 3): origins closer than one
//! flight see the same flight and add almost nothing. Per lag the sums are
//!
//! * |Δr|², Δr = r(t₀ + t) − r(t₀) differenced as exact lattice integers plus bounded offsets
//!   (as [`super::msd`] does), for the MSD;
//! * v(t₀)·Δr, whose mean is ∫₀ᵗ ⟨v(0)·v(s)⟩ ds by stationarity, so that half of it is the running
//!   Green–Kubo integral D(t) = ½∫₀ᵗ ⟨v(0)·v(s)⟩ ds with no quadrature at all
//!   (`proofs-notes/msd-curve.md`);
//! * v(t₀)·v(t₀ + t), the velocity autocorrelation (1 at t = 0: the speed is 1).
//!
//! Work: about 16 samples stored and 5 eight-wide pair sums per collision (about 30 times the
//! engine's own cost per collision; it is an opt-in diagnostic). Nothing here touches [`super::msd`], which D is fitted from: a run
//! with this curve has the bits of a run without it.

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::observe::{EventLanes, Observer};
use crate::numbers::lanes::Lanes;
use crate::scenes::lattice::Basis64;

/// The lag multiples of level 0 (in steps Δ).
const FIRST: std::ops::RangeInclusive<usize> = 1..=7;
/// The lag multiples of level k ≥ 1 (in steps 2ᵏΔ).
const LATER: std::ops::RangeInclusive<usize> = 4..=7;
/// Samples kept per level: the longest lag, 7 steps, needs the last 8.
const RING: usize = 8;
/// The most levels a grid may have (2²⁴Δ: far beyond any run's longest usable lag).
pub const MAX_LEVELS: usize = 24;

/// One sample: cell i, j (exact integers in `f64`), the offset x, y, and the velocity vx, vy in
/// the world frame.
type Sample = [f64; 6];

/// The grid: the first step Δ and the number of levels.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CurveGrid {
    /// The level-0 sampling interval Δ (a time).
    pub step: f64,
    /// Levels 0 … levels − 1 (1 to [`MAX_LEVELS`]).
    pub levels: usize,
}

impl CurveGrid {
    /// The grid of step `step` that reaches as far as `longest` (a time) allows: the levels
    /// whose longest lag 7·2ᵏΔ is at most `longest`, at least one and at most [`MAX_LEVELS`].
    pub fn reaching(step: f64, longest: f64) -> Self {
        let mut levels = 1;
        while levels < MAX_LEVELS && 7.0 * step * (1u64 << levels) as f64 <= longest {
            levels += 1;
        }
        CurveGrid { step, levels }
    }

    /// The (level, multiple) of every lag, in increasing time.
    fn lags(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (0..self.levels).flat_map(|k| multiples(k).map(move |m| (k, m)))
    }

    /// The lag times, increasing: Δ … 7Δ, then 4·2ᵏΔ … 7·2ᵏΔ for each later level k.
    pub fn times(&self) -> Vec<f64> {
        self.lags()
            .map(|(k, m)| (m as u64 * (1u64 << k)) as f64 * self.step)
            .collect()
    }
}

/// Level-0 samples per pair sum: the sums are taken at the level-0 samples n ≡ 0 (mod 8), once
/// per mean free time ⟨ℓ⟩ = 8Δ (at level k ≥ 3 that is every sample). A flight of ⟨ℓ⟩ holds about
/// eight samples that all see the same flight, so ends (and so origins) closer than that add
/// almost nothing (`proofs-notes/msd-curve.md`), while they would cost most of the work.
const ENDS: u64 = 8;

/// The pair sums at lag `m` (in steps of level `k`) after `samples` samples of level k: the
/// ends j ≥ m among the level's samples 0 … samples − 1 that are sums (j ≡ 0 mod 8/2ᵏ).
fn pairs(k: usize, m: u64, samples: u64) -> u64 {
    let every = (ENDS >> k.min(3)).max(1);
    if samples <= m {
        0
    } else {
        (samples - 1) / every - (m - 1) / every
    }
}

fn multiples(level: usize) -> std::ops::RangeInclusive<usize> {
    if level == 0 { FIRST } else { LATER }
}

/// The sums of one level of one lane, in lag order (Δ … 7Δ at level 0, 4·2ᵏΔ … 7·2ᵏΔ at level k): Σ|Δr|², Σ v(t₀)·Δr and
/// Σ v(t₀)·v(t₀ + t).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LevelState {
    /// The last 8 samples, sample n at slot n mod 8 (older slots: 0).
    pub ring: Vec<Sample>,
    /// Samples taken at this level.
    pub samples: u64,
    /// Per lag: [Σ |Δr|², Σ v(t₀)·Δr, Σ v(t₀)·v(t₀ + t)].
    pub sums: Vec<[f64; 3]>,
}

/// One level of one lane as it is worked on: its ring of the last 8 samples kept twice over per
/// component (`ring[c][p + i]`, p = n mod 8, holds component c of sample n − 8 + i for
/// i = 0 … 7, so that the samples 8 … 1 steps back are one contiguous slice), and its sums per
/// step back i (lag 8 − i; only the lags of the level are read).
#[derive(Debug, Clone)]
struct Level {
    ring: [[f64; 2 * RING]; 6],
    samples: u64,
    /// The lags (8 − i) this level keeps: 1 where kept, 0 elsewhere.
    keep: [f64; RING],
    sums: [[f64; RING]; 3],
}

impl Level {
    fn new(level: usize) -> Self {
        let mut keep = [0.0; RING];
        for m in multiples(level) {
            keep[RING - m] = 1.0;
        }
        Level {
            ring: [[0.0; 2 * RING]; 6],
            samples: 0,
            keep,
            sums: [[0.0; RING]; 3],
        }
    }

    /// Adds sample `u`, and with `sum` the three products for every step back at once (one
    /// vector loop), added where the lag is kept and its origin has been sampled (+0 elsewhere,
    /// which leaves a sum bit for bit: no sum is ever −0).
    #[inline(always)]
    fn push(&mut self, b: &Basis64, u: &Sample, sum: bool) {
        let n = self.samples;
        let p = (n % RING as u64) as usize;
        if sum {
            let [ri, rj, rx, ry, rvx, rvy] = &self.ring;
            let (wi, wj) = (&ri[p..p + RING], &rj[p..p + RING]);
            let (wx, wy) = (&rx[p..p + RING], &ry[p..p + RING]);
            let (wvx, wvy) = (&rvx[p..p + RING], &rvy[p..p + RING]);
            let [s0, s1, s2] = &mut self.sums;
            for i in 0..RING {
                let on = if ((RING - i) as u64) <= n {
                    self.keep[i]
                } else {
                    0.0
                };
                let (di, dj) = (u[0] - wi[i], u[1] - wj[i]);
                let dx = b.a * (di + b.beta * dj) + (u[2] - wx[i]);
                let dy = b.h * dj + (u[3] - wy[i]);
                s0[i] += on * (dx * dx + dy * dy);
                s1[i] += on * (wvx[i] * dx + wvy[i] * dy);
                s2[i] += on * (wvx[i] * u[4] + wvy[i] * u[5]);
            }
        }
        for (ring, x) in self.ring.iter_mut().zip(u) {
            ring[p] = *x;
            ring[p + RING] = *x;
        }
        self.samples = n + 1;
    }

    /// This level exactly, in the checkpoint's form (slot n mod 8 of sample n).
    fn state(&self, level: usize) -> LevelState {
        let n = self.samples;
        let mut ring = vec![[0.0; 6]; RING];
        for m in n.saturating_sub(RING as u64)..n {
            let slot = (m % RING as u64) as usize;
            ring[slot] = [0, 1, 2, 3, 4, 5].map(|c| self.ring[c][slot]);
        }
        let sums = multiples(level)
            .map(|m| [0, 1, 2].map(|c| self.sums[c][RING - m]))
            .collect();
        LevelState {
            ring,
            samples: n,
            sums,
        }
    }

    /// The level `level` that [`Level::state`] gave `s`.
    fn from_state(level: usize, s: &LevelState) -> Self {
        let mut out = Level::new(level);
        out.samples = s.samples;
        for (slot, x) in s.ring.iter().enumerate() {
            for (ring, &v) in out.ring.iter_mut().zip(x) {
                ring[slot] = v;
                ring[slot + RING] = v;
            }
        }
        for (m, x) in multiples(level).zip(&s.sums) {
            for (sums, &v) in out.sums.iter_mut().zip(x) {
                sums[RING - m] = v;
            }
        }
        out
    }

    /// Whether `s` could be a state of level `level`: its sizes, and finite values.
    fn fits(level: usize, s: &LevelState) -> bool {
        s.ring.len() == RING
            && s.ring.iter().flatten().all(|v| v.is_finite())
            && s.sums.len() == multiples(level).count()
            && s.sums
                .iter()
                .all(|x| x.iter().all(|v| v.is_finite()) && x[0] >= 0.0)
    }
}

/// Everything one lane has accumulated, exactly (what a checkpoint keeps).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CurveLaneState {
    /// Time left to the next level-0 sample.
    pub until: f64,
    /// The levels, 0 first.
    pub levels: Vec<LevelState>,
}

/// One lane as it is worked on.
#[derive(Debug, Clone)]
struct Lane {
    until: f64,
    levels: Vec<Level>,
}

/// The curve's values of one trajectory at [`CurveGrid::times`] (NaN where no origin was
/// summed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CurveValues {
    /// ⟨|Δr|²⟩.
    pub msd: Vec<f64>,
    /// ⟨v(0)·v(t)⟩.
    pub vacf: Vec<f64>,
    /// ½⟨v(0)·Δr(t)⟩ = ½∫₀ᵗ ⟨v(0)·v(s)⟩ ds.
    pub green_kubo: Vec<f64>,
    /// ⟨v_x(0)v_x(t)⟩ (at the user's times, [`super::msd_times`]; empty on this grid).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vacf_x: Vec<f64>,
    /// ⟨v_y(0)v_y(t)⟩ (likewise).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub vacf_y: Vec<f64>,
}

/// Accumulates the curve of L trajectories.
#[derive(Debug, Clone)]
pub struct MsdCurve {
    grid: CurveGrid,
    basis: Basis64,
    lanes: Vec<Lane>,
}

impl MsdCurve {
    /// The curve of `lanes` trajectories on `grid`, displacements in `basis`.
    pub fn new(grid: CurveGrid, basis: Basis64, lanes: usize) -> Self {
        let lane = Lane {
            until: 0.0,
            levels: (0..grid.levels).map(Level::new).collect(),
        };
        MsdCurve {
            grid,
            basis,
            lanes: vec![lane; lanes],
        }
    }

    /// The grid.
    pub fn grid(&self) -> CurveGrid {
        self.grid
    }

    /// Records every level-0 grid time inside lane `l`'s flight of `e`; level k takes every
    /// 2ᵏ-th of them.
    #[inline(always)]
    fn flight<const L: usize>(&mut self, e: &EventLanes<L>, l: usize) {
        let t = e.time[l];
        let lane = &mut self.lanes[l];
        if lane.until > t {
            lane.until -= t;
            return;
        }
        let sg = e.cell[2][l];
        let mut tau = lane.until;
        while tau <= t {
            let p = e.unwrapped(l, tau);
            let u = [
                p.i as f64,
                p.j as f64,
                p.off[0],
                p.off[1],
                sg * e.vel[0][l],
                sg * e.vel[1][l],
            ];
            let n = lane.levels[0].samples;
            // Time origins at most once per ⟨ℓ⟩ = 8Δ: see `ENDS`.
            let sum = n.is_multiple_of(ENDS);
            for (k, level) in lane.levels.iter_mut().enumerate() {
                if k > 0 && !n.is_multiple_of(1u64 << k) {
                    break;
                }
                level.push(&self.basis, &u, sum);
            }
            tau += self.grid.step;
        }
        lane.until = tau - t;
    }

    /// Lane `l`'s values at [`CurveGrid::times`].
    pub fn values(&self, l: usize) -> CurveValues {
        let mut v = CurveValues {
            msd: Vec::new(),
            vacf: Vec::new(),
            green_kubo: Vec::new(),
            vacf_x: Vec::new(),
            vacf_y: Vec::new(),
        };
        for (k, level) in self.lanes[l].levels.iter().enumerate() {
            for m in multiples(k) {
                let c = match pairs(k, m as u64, level.samples) {
                    0 => f64::NAN,
                    c => c as f64,
                };
                let i = RING - m;
                v.msd.push(level.sums[0][i] / c);
                v.green_kubo.push(0.5 * level.sums[1][i] / c);
                v.vacf.push(level.sums[2][i] / c);
            }
        }
        v
    }

    /// Everything lane `l` has accumulated, exactly.
    pub fn lane_state(&self, l: usize) -> CurveLaneState {
        let lane = &self.lanes[l];
        CurveLaneState {
            until: lane.until,
            levels: lane
                .levels
                .iter()
                .enumerate()
                .map(|(k, x)| x.state(k))
                .collect(),
        }
    }

    /// Puts back into lane `l` what [`MsdCurve::lane_state`] took from a curve on the same grid.
    ///
    /// # Errors
    /// If the state has another number of levels or lags, or values that no run produces.
    pub fn set_lane_state(&mut self, l: usize, s: &CurveLaneState) -> Result<(), Error> {
        let fits = s.until.is_finite()
            && s.until >= 0.0
            && s.levels.len() == self.grid.levels
            && s.levels.iter().enumerate().all(|(k, x)| Level::fits(k, x));
        if !fits {
            return Err(Error::Invalid(format!(
                "a saved MSD-curve lane does not fit this run ({} levels of finite sums expected)",
                self.grid.levels
            )));
        }
        self.lanes[l] = Lane {
            until: s.until,
            levels: s
                .levels
                .iter()
                .enumerate()
                .map(|(k, x)| Level::from_state(k, x))
                .collect(),
        };
        Ok(())
    }
}

impl<const L: usize> Observer<L> for MsdCurve {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        for e in steps {
            e.each_live(self.lanes.len(), |l| self.flight(e, l));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::drive;
    use crate::scenes::lattice::TriangularLattice;
    use crate::scenes::sampling::stream;
    use crate::scenes::triangular::equilibrium_state;

    fn same_bits(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
    }

    /// A lane saved in the middle of a run and put back goes on to the bits of the run that was
    /// never stopped; a state of another grid is refused.
    #[test]
    fn a_saved_lane_resumes_to_the_bits_of_the_run_never_stopped() {
        let lat = TriangularLattice::new(0.15).unwrap();
        let basis = lat.basis_f64();
        let grid = CurveGrid::reaching(0.05, 400.0);
        let start = equilibrium_state(lat.trap(), &mut stream(9, 1));
        let mut whole = MsdCurve::new(grid, basis, 1);
        drive(&lat, &mut start.clone(), 60_000, &mut whole, &|_| {}).unwrap();
        let mut s = start.clone();
        let mut a = MsdCurve::new(grid, basis, 1);
        drive(&lat, &mut s, 25_000, &mut a, &|_| {}).unwrap();
        let state = a.lane_state(0);
        let mut b = MsdCurve::new(grid, basis, 1);
        b.set_lane_state(0, &state).unwrap();
        drive(&lat, &mut s, 35_000, &mut b, &|_| {}).unwrap();
        let (x, y) = (b.values(0), whole.values(0));
        assert!(same_bits(&x.msd, &y.msd) && same_bits(&x.vacf, &y.vacf));
        assert!(same_bits(&x.green_kubo, &y.green_kubo));
        assert!(x.msd.iter().all(|m| m.is_finite()), "{:?}", x.msd);
        let other = CurveGrid::reaching(0.05, 100.0);
        assert!(
            MsdCurve::new(other, basis, 1)
                .set_lane_state(0, &state)
                .is_err()
        );
    }

    /// Every displacement is at most the path length t (speed 1), so the MSD is at most t², and
    /// the velocities are unit vectors, so |⟨v(0)·v(t)⟩| ≤ 1 and |½⟨v(0)·Δr⟩| ≤ t/2 — up to
    /// the rounding of the positions (a few ulps of the cell size).
    #[test]
    fn displacements_never_outrun_the_path_length() {
        let lat = TriangularLattice::new(0.2).unwrap();
        let grid = CurveGrid::reaching(0.02, 200.0);
        let mut c = MsdCurve::new(grid, lat.basis_f64(), 1);
        let mut s = equilibrium_state(lat.trap(), &mut stream(3, 2));
        drive(&lat, &mut s, 40_000, &mut c, &|_| {}).unwrap();
        let v = c.values(0);
        for (k, t) in grid.times().into_iter().enumerate() {
            let slack = 1e-13 * (1.0 + t);
            assert!(
                v.msd[k] <= t * t * (1.0 + 1e-14) + slack,
                "t = {t}: {}",
                v.msd[k]
            );
            assert!(v.vacf[k].abs() <= 1.0 + 1e-14, "t = {t}: {}", v.vacf[k]);
            assert!(
                v.green_kubo[k].abs() <= 0.5 * t + slack,
                "t = {t}: {}",
                v.green_kubo[k]
            );
        }
        // The first lag lies inside most flights: nearly ballistic.
        assert!(v.msd[0] > 0.9 * 0.02 * 0.02 && v.vacf[0] > 0.9, "{v:?}");
    }

    #[test]
    fn the_grid_is_increasing_and_about_four_times_per_octave() {
        let g = CurveGrid::reaching(0.25, 1000.0);
        let t = g.times();
        assert!(t.windows(2).all(|p| p[0] < p[1]), "{t:?}");
        assert_eq!(t[0], 0.25);
        assert_eq!(t.len(), 7 + 4 * (g.levels - 1));
        assert!(*t.last().unwrap() <= 1000.0 && 2.0 * t.last().unwrap() > 1000.0);
        assert_eq!(CurveGrid::reaching(1.0, 0.5).levels, 1);
        assert_eq!(CurveGrid::reaching(1e-9, 1e30).levels, MAX_LEVELS);
    }
}
