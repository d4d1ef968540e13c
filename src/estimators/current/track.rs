//! One trajectory under the thermostat: a warm-up towards the steady state, then its unwrapped
//! position and velocity angle sampled on a fixed time grid, every sample a time origin of the
//! lag moments ⟨Δx²⟩, ⟨Δy²⟩, ⟨ΔxΔy⟩, ⟨Δx⟩, ⟨Δy⟩ (the spread about the drift is their
//! difference), and the current X(T)/T of the observed stretch.

use crate::Error;
use crate::engine::options::StopFlag;
use crate::kernel::flight::EventKind;
use crate::kernel::thermostat::{Start, Thermostat};
use crate::kernel::vec2::Vec2;
use crate::numbers::atan::atan2;
use crate::numbers::real::Real;
use crate::observers::lag_ring::LagRing;
use crate::scenes::Scene;
use crate::scenes::lattice::{Basis64, Lattice, LatticeState, Unwrapped};
use crate::scenes::sampling::StreamKey;
use crate::scenes::thermostat::{CellFields, ThermoStep};

use super::tangent::{Pair, PairBatch};

/// Bins of the velocity angle's histogram over (−π, π], the angle from E.
pub const ANGLE_BINS: usize = 72;

/// Collisions between two looks at the progress and the stop flag.
pub(super) const LOOK_EVERY: u64 = 1 << 14;

/// The lag moments of one trajectory's displacement (x, y): per lag Σ Δx², Σ Δy², Σ ΔxΔy, Σ Δx,
/// Σ Δy over every time origin.
type DriftSums = LagRing<2, 5>;

/// A pair's contribution to [`DriftSums`].
fn drift_moments(&[x0, y0]: &[f64; 2], &[x, y]: &[f64; 2]) -> [f64; 5] {
    let (dx, dy) = (x - x0, y - y0);
    [dx * dx, dy * dy, dx * dy, dx, dy]
}

/// What one batch measured over its observed stretch.
#[derive(Debug, Clone)]
pub(super) struct Batch {
    /// The current X(T)/T.
    pub current: [f64; 2],
    /// ⟨Δx²⟩, ⟨Δy²⟩, ⟨ΔxΔy⟩, ⟨Δx⟩, ⟨Δy⟩ at each lag.
    pub means: Vec<[f64; 5]>,
    /// Grid samples of the velocity angle from E, by bin of (−π, π].
    pub angles: Vec<u64>,
    /// Collisions within the observed stretch.
    pub collisions: u64,
    /// Its duration T.
    pub time: f64,
    /// The Lyapunov pair.
    pub pair: PairBatch,
}

/// Where and how one batch runs.
pub(super) struct Setup<'a, T: Real, S: Scene> {
    pub scene: &'a S,
    pub lattice: &'a Lattice<T, S::Kernel<T>>,
    /// The field in every cell's frame, at the working precision.
    pub fields: &'a CellFields<T>,
    /// The field in the world's frame as doubles (for the samples between events).
    pub world: &'a Thermostat<f64>,
    pub ctx: T::Ctx,
    /// Grid spacing (time).
    pub grid: f64,
    /// The lags in grid steps.
    pub steps: &'a [usize],
    /// Flight time before the observed stretch starts (at the first event after it).
    pub warm_up: f64,
    /// Grid steps observed.
    pub samples: u64,
    pub stop: Option<&'a StopFlag>,
    pub progress: &'a (dyn Fn(u64) + Sync),
}

/// One trajectory's observer, fed flight by flight.
struct Drift<'a> {
    sums: DriftSums,
    angles: Vec<u64>,
    world: &'a Thermostat<f64>,
    grid: f64,
    last: u64,
    next: u64,
    t: f64,
    end: [f64; 2],
    done: u64,
}

impl Drift<'_> {
    fn running(&self) -> bool {
        self.next <= self.last
    }

    /// The flight `start` from the displacement `r`, `step` to its event: its grid samples, and
    /// the collision at its end if it is within the observed stretch.
    fn flight(&mut self, r: [f64; 2], start: &Start<'_, f64>, step: &ThermoStep) {
        let end = self.t + step.time;
        while self.next <= self.last && self.next as f64 * self.grid <= end {
            let at = start.at(&(self.next as f64 * self.grid - self.t));
            let (x, y) = (r[0] + at.disp.x, r[1] + at.disp.y);
            self.sums.push([x, y], drift_moments);
            let e = &self.world.dir;
            let theta = atan2(e.cross(&at.vel), e.dot(&at.vel));
            let bin = ((theta + std::f64::consts::PI) / std::f64::consts::TAU * ANGLE_BINS as f64)
                .floor() as usize;
            self.angles[bin.min(ANGLE_BINS - 1)] += 1;
            if self.next == self.last {
                self.end = [x, y];
            }
            self.next += 1;
        }
        self.t = end;
        let observed = end <= self.last as f64 * self.grid;
        self.done += u64::from(matches!(step.kind, EventKind::Collision(_)) && observed);
    }
}

/// The world velocity of a state (its cell frame turned by the cell's orientation).
pub(super) fn world_velocity<T: Real>(s: &LatticeState<T>) -> Vec2<f64> {
    let sg = s.cell.sign();
    Vec2::new(sg * s.flight.vel.x.to_f64(), sg * s.flight.vel.y.to_f64())
}

/// Counts the collisions of `step` and, every [`LOOK_EVERY`], reports them and looks at the stop
/// flag.
pub(super) fn look(
    (progress, stop): (&(dyn Fn(u64) + Sync), Option<&StopFlag>),
    count: &mut u64,
    step: &ThermoStep,
) -> Result<(), Error> {
    if matches!(step.kind, EventKind::Collision(_)) {
        *count += 1;
        if count.is_multiple_of(LOOK_EVERY) {
            progress(LOOK_EVERY);
            if let Some(stop) = stop {
                stop.check()?;
            }
        }
    }
    Ok(())
}

/// The start of the trajectory of stream `key`: a point of the field-free invariant measure at
/// the working precision `ctx`, its speed made 1 there.
pub(super) fn start<T: Real, S: Scene>(scene: &S, ctx: T::Ctx, key: StreamKey) -> LatticeState<T> {
    let s64 = scene.sample(&mut key.rng());
    let mut s = LatticeState::<T>::convert_from_f64(ctx, &s64);
    s.flight.normalise_speed();
    s
}

/// Runs the batch of stream `key` on the scalar kernel: a start from the field-free invariant
/// measure, the warm-up, then the observed stretch of [`Setup::samples`] grid steps.
pub(super) fn batch<T: Real, S: Scene>(
    su: &Setup<'_, T, S>,
    key: StreamKey,
) -> Result<Batch, Error> {
    let mut s = start::<T, S>(su.scene, su.ctx, key);
    let lat = su.lattice;
    let mut pair = Pair::new(su.world, &world_velocity(&s));
    let mut count = 0;
    let mut t = 0.0;
    while t < su.warm_up {
        let start = su.world.start(&world_velocity(&s));
        let step = lat.step_thermostat(&mut s, su.fields)?;
        tangent(lat, &s, &mut pair, (&start, &step));
        t += step.time;
        look((su.progress, su.stop), &mut count, &step)?;
    }
    pair.restart_at(&world_velocity(&s));
    let basis: Basis64 = lat.basis_f64();
    let origin: Unwrapped = lat.unwrapped(&s, 0.0);
    let mut sums = DriftSums::new(su.steps.to_vec());
    sums.push([0.0, 0.0], drift_moments);
    let mut drift = Drift {
        sums,
        angles: vec![0; ANGLE_BINS],
        world: su.world,
        grid: su.grid,
        last: su.samples,
        next: 1,
        t: 0.0,
        end: [0.0; 2],
        done: 0,
    };
    while drift.running() {
        let r = lat.unwrapped(&s, 0.0).displacement_from(&origin, &basis);
        let start = su.world.start(&world_velocity(&s));
        let step = lat.step_thermostat(&mut s, su.fields)?;
        drift.flight(r, &start, &step);
        tangent(lat, &s, &mut pair, (&start, &step));
        look((su.progress, su.stop), &mut count, &step)?;
    }
    (su.progress)(count % LOOK_EVERY);
    let time = su.samples as f64 * su.grid;
    Ok(Batch {
        current: [drift.end[0] / time, drift.end[1] / time],
        means: drift.sums.means(),
        angles: drift.angles,
        collisions: drift.done,
        time,
        pair: pair.finish(),
    })
}

/// The pair through the event `step` of the flight `start` (world frame), the state `s` being the
/// one after it (at a collision: on the disk, leaving).
pub(super) fn tangent<T: Real, K: crate::kernel::cell::CellKernel<T>>(
    lat: &Lattice<T, K>,
    s: &LatticeState<T>,
    pair: &mut Pair<'_>,
    (start, step): (&Start<'_, f64>, &ThermoStep),
) {
    pair.flight(start, step.time, step.along);
    if let EventKind::Collision(m) = step.kind {
        let (n, r) = contact_normal(lat, s, m);
        pair.collision(&n, r, &world_velocity(s));
    }
}

/// The outward unit normal (world) at the contact of the state `s` on disk `m` of its cell, and
/// the disk's radius.
pub(super) fn contact_normal<T: Real, K: crate::kernel::cell::CellKernel<T>>(
    lat: &Lattice<T, K>,
    s: &LatticeState<T>,
    m: u8,
) -> (Vec2<f64>, f64) {
    let disk = &lat.cell().disks[m as usize];
    let r = disk.radius().to_f64();
    let sg = s.cell.sign() / r;
    let n = Vec2::new(
        sg * (s.flight.pos.x.to_f64() - disk.centre.x.to_f64()),
        sg * (s.flight.pos.y.to_f64() - disk.centre.y.to_f64()),
    );
    (n, r)
}
