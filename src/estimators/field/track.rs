//! One trajectory in the field: its unwrapped position and its cumulative Lévy area sampled on a
//! fixed time grid, and the lag sums of the diffusion tensor accumulated from every sample as a
//! time origin (`proofs-notes/magnetic-transport.md`).
//!
//! With X(t) the displacement from the start and C(t) = ∫₀ᵗ X × dX, the Lévy area of the window
//! [t₀, t₁] is A = C(t₁) − C(t₀) − X(t₀) × (X(t₁) − X(t₀)), and ⟨A⟩ grows like (D_xy − D_yx)·t:
//! twice the Hall part of the tensor, which no mean squared displacement sees.

use crate::Error;
use crate::engine::options::StopFlag;
use crate::kernel::arc::{arc_area, chord_at};
use crate::kernel::flight::EventKind;
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;
use crate::observers::excursion::Reach;
use crate::observers::lag_ring::LagRing;
use crate::scenes::Scene;
use crate::scenes::lattice::{Basis64, Lattice, LatticeState, Unwrapped};
use crate::scenes::magnetic::ArcStep;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::theory::magnetic::{FieldGeometry, Orbit};

/// The lag sums of one trajectory: for each lag, Σ Δx², Σ Δy², Σ ΔxΔy, Σ A over every time origin
/// (samples: displacement x, y and cumulative area c).
#[derive(Debug, Clone)]
pub(super) struct LagSums(LagRing<3, 4>);

impl LagSums {
    pub(super) fn new(steps: Vec<usize>) -> Self {
        LagSums(LagRing::new(steps))
    }

    /// One sample: displacement (x, y) and cumulative area c.
    pub(super) fn push(&mut self, x: f64, y: f64, c: f64) {
        self.0.push([x, y, c], |&[x0, y0, c0], &[x, y, c]| {
            let (dx, dy) = (x - x0, y - y0);
            [dx * dx, dy * dy, dx * dy, c - c0 - (x0 * dy - y0 * dx)]
        });
    }

    /// The means per lag (NaN where a lag was never reached).
    pub(super) fn means(&self) -> Vec<[f64; 4]> {
        self.0.means()
    }
}

/// What one batch measured.
#[derive(Debug, Clone)]
pub(super) struct Batch {
    /// ⟨Δx²⟩, ⟨Δy²⟩, ⟨ΔxΔy⟩, ⟨A⟩ at each lag.
    pub means: Vec<[f64; 4]>,
    /// Collisions within the batch's duration.
    pub collisions: u64,
    /// The duration (flight time).
    pub time: f64,
    /// Localized starts drawn (and set aside) before the diffusing one.
    pub rejected: u64,
    /// The largest distance from its start at the samples of the time grid.
    pub reach: Reach,
}

/// Where and how one batch runs.
pub(super) struct Setup<'a, T: Real, S: Scene> {
    pub scene: &'a S,
    pub lattice: &'a Lattice<T, S::Kernel<T>>,
    pub geometry: &'a FieldGeometry,
    /// The field at the working precision and as a double (for observables).
    pub field: (&'a T, f64),
    pub ctx: T::Ctx,
    /// Grid spacing (time units).
    pub grid: f64,
    pub steps: &'a [usize],
    pub stop: Option<&'a StopFlag>,
    pub progress: &'a (dyn Fn(u64) + Sync),
}

/// A start drawn from the invariant measure restricted to the diffusing orbits (rejection), and
/// the number of localized starts set aside ([`FieldGeometry::diffusing_start`]).
pub(super) fn start<S: Scene>(
    scene: &S,
    geometry: &FieldGeometry,
    key: StreamKey,
) -> Result<(LatticeState<f64>, u64), Error> {
    geometry.diffusing_start(scene, &mut key.rng())
}

/// One trajectory's observer: the samples of its unwrapped position and cumulative Lévy area on
/// the time grid, fed event by event until the flight time `duration` (whichever engine finds
/// the events: the same operations on the same event give the same bits).
pub(super) struct Track {
    sums: LagSums,
    origin: Unwrapped,
    basis: Basis64,
    grid: f64,
    w: f64,
    duration: f64,
    t: f64,
    area: f64,
    next: u64,
    reach: Reach,
    /// Collisions within the duration.
    pub(super) done: u64,
}

impl Track {
    /// The observer of a trajectory that starts at `origin`.
    pub(super) fn new<T: Real, S: Scene>(
        su: &Setup<'_, T, S>,
        origin: Unwrapped,
        duration: f64,
    ) -> Self {
        let mut sums = LagSums::new(su.steps.to_vec());
        sums.push(0.0, 0.0, 0.0);
        Track {
            sums,
            origin,
            basis: su.lattice.basis_f64(),
            grid: su.grid,
            w: su.field.1,
            duration,
            t: 0.0,
            area: 0.0,
            next: 1,
            reach: Reach::new(),
            done: 0,
        }
    }

    /// `true` while the trajectory has not flown its duration.
    pub(super) fn running(&self) -> bool {
        self.t < self.duration
    }

    /// The event `step` of the flight that starts at `start` (unwrapped) with the world velocity
    /// `v`; returns `true` where it is a collision within the duration.
    pub(super) fn event(&mut self, start: &Unwrapped, v: &Vec2<f64>, step: &ArcStep) -> bool {
        let r = start.displacement_from(&self.origin, &self.basis);
        let end = self.t + step.time;
        self.sample_flight((self.t, self.area), r, v, end);
        self.area += (r[0] * step.chord[1] - r[1] * step.chord[0]) + step.area;
        self.t = end;
        let counted = matches!(step.kind, EventKind::Collision(_)) && end <= self.duration;
        self.done += u64::from(counted);
        counted
    }

    /// The samples of the time grid within the flight that starts at time `t` with the
    /// cumulative area `area`, displacement `r` and world velocity `v` and ends at `end` (none
    /// beyond the duration): the flight's part of [`Self::event`], which the SIMD driver calls
    /// only for the flights that hold a sample ([`Self::next_sample`] ≤ min(`end`, duration)).
    pub(super) fn sample_flight(
        &mut self,
        (t, area): (f64, f64),
        r: [f64; 2],
        v: &Vec2<f64>,
        end: f64,
    ) {
        let w = self.w;
        while self.next_sample() <= end.min(self.duration) {
            let tau = self.next_sample() - t;
            let x = chord_at(v, &tau, &w);
            let c = area + (r[0] * x.y - r[1] * x.x) + arc_area(tau, w);
            let (dx, dy) = (r[0] + x.x, r[1] + x.y);
            self.sums.push(dx, dy, c);
            self.reach.push(dx, dy);
            self.next += 1;
        }
    }

    /// The time of the next sample of the grid.
    pub(super) fn next_sample(&self) -> f64 {
        self.next as f64 * self.grid
    }

    /// The flight time, cumulative area and collisions so far, for the SIMD driver, which
    /// carries them in its lanes between samples.
    pub(super) fn hot(&self) -> (f64, f64, u64) {
        (self.t, self.area, self.done)
    }

    /// Takes back what [`Self::hot`] gave, carried on.
    pub(super) fn set_hot(&mut self, (t, area, done): (f64, f64, u64)) {
        (self.t, self.area, self.done) = (t, area, done);
    }

    /// The start, as the SIMD driver differences positions from it.
    pub(super) fn origin(&self) -> &Unwrapped {
        &self.origin
    }

    /// The duration.
    pub(super) fn duration(&self) -> f64 {
        self.duration
    }

    /// What the batch measured.
    pub(super) fn finish(self, rejected: u64) -> Batch {
        Batch {
            means: self.sums.means(),
            collisions: self.done,
            time: self.duration,
            rejected,
            reach: self.reach,
        }
    }
}

/// The world velocity of a state (its cell frame turned by the cell's orientation).
pub(super) fn world_velocity<T: Real>(s: &LatticeState<T>) -> Vec2<f64> {
    let sg = s.cell.sign();
    Vec2::new(sg * s.flight.vel.x.to_f64(), sg * s.flight.vel.y.to_f64())
}

/// Collisions between two looks at the progress and the stop flag.
pub(super) const LOOK_EVERY: u64 = 1 << 16;

/// Runs batch `index` on the scalar kernel for the flight time `duration` (the same for every
/// batch, so that the collision rate averaged over batches is Kac's even where the diffusing
/// part holds regular islands: `proofs-notes/magnetic-transport.md`).
pub(super) fn batch<T: Real, S: Scene>(
    su: &Setup<'_, T, S>,
    key: StreamKey,
    duration: f64,
) -> Result<Batch, Error> {
    let (s64, rejected) = start(su.scene, su.geometry, key)?;
    let mut s = LatticeState::<T>::convert_from_f64(su.ctx, &s64);
    s.flight.normalise_speed();
    let lat = su.lattice;
    let mut track = Track::new(su, lat.unwrapped(&s, 0.0), duration);
    while track.running() {
        let here = lat.unwrapped(&s, 0.0);
        let v = world_velocity(&s);
        let step = lat.step_in_field(&mut s, su.field.0)?;
        if track.event(&here, &v, &step) && track.done.is_multiple_of(LOOK_EVERY) {
            (su.progress)(LOOK_EVERY);
            if let Some(stop) = su.stop {
                stop.check()?;
            }
        }
    }
    (su.progress)(track.done % LOOK_EVERY);
    Ok(track.finish(rejected))
}

/// Classifies `n` phase points of stream `(seed, Classification, run, chunk)`: localized ones.
/// `stop` is looked at every [`CLASSIFY_STOP_EVERY`] points.
pub(super) fn classify_chunk<S: Scene>(
    scene: &S,
    geometry: &FieldGeometry,
    key: StreamKey,
    n: u64,
    stop: Option<&StopFlag>,
) -> Result<u64, Error> {
    let lattice = scene.lattice::<f64>(())?;
    let mut rng = key.rng();
    let mut localized = 0;
    for i in 0..n {
        if i % CLASSIFY_STOP_EVERY == 0
            && let Some(s) = stop
        {
            s.check()?;
        }
        let s = scene.sample(&mut rng);
        if geometry.classify_state(&lattice, &s) != Orbit::Diffusing {
            localized += 1;
        }
    }
    Ok(localized)
}

/// Phase points classified between two looks at the stop flag (a few milliseconds).
const CLASSIFY_STOP_EVERY: u64 = 1 << 12;

/// The key of classification chunk `chunk`.
pub(super) fn classification_key(seed: u64, run: u64, chunk: u64) -> StreamKey {
    StreamKey::new(seed, Purpose::Classification, chunk).in_run(run)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lag_sums_of_a_circle_give_its_area() {
        // A square of side √2 walked counter-clockwise, C the polygon's ∫ x × dx: over the whole
        // walk (lag 4) the displacement is 0 and the area twice the square's, 4.
        let mut s = LagSums::new(vec![1, 4]);
        let pts = [(0.0, 0.0), (1.0, 1.0), (0.0, 2.0), (-1.0, 1.0), (0.0, 0.0)];
        let mut c = 0.0;
        let mut prev: (f64, f64) = (0.0, 0.0);
        for &(x, y) in &pts {
            c += prev.0 * (y - prev.1) - prev.1 * (x - prev.0);
            s.push(x, y, c);
            prev = (x, y);
        }
        let m = s.means();
        assert_eq!(m[1], [0.0, 0.0, 0.0, 4.0]);
        // Lag 1: each side of the square, |Δ|² = 2, and no area of its own (straight sides).
        assert_eq!(m[0][0] + m[0][1], 2.0);
        assert_eq!(m[0][3], 0.0);
    }
}
