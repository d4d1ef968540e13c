//! Chaos, measured two ways.
//!
//! * [`run`]: the largest Lyapunov exponent from the tangent dynamics
//!   (`proofs-notes/tangent-map.md`) along long f64 orbits — a tangent vector is propagated
//!   event by event and renormalised; λ = Σ ln(growth)/N per collision and Σ ln(growth)/T per
//!   unit time, with the standard error over independent orbits.
//! * [`super::divergence`]: the same initial condition run at f64 and at 64 … 1024 bits against
//!   a 4096-bit reference; the fitted growth rate is the Lyapunov exponent again.

use nalgebra::Vector4;

use super::birkhoff::tangent_step;
use rug::Float;
use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::drive;
use crate::engine::long_flight::{Flights, drive_jumps};
use crate::engine::metadata::RunMeta;
use crate::engine::observe::{EventLanes, Observer};
use crate::engine::options::RunOptions;
use crate::engine::parallel::{STOP_EVERY, in_legs, par_batches_watched};
use crate::engine::work::{Work, crossings_per_collision};
use crate::kernel::cell::ConvexCell;
use crate::kernel::{cell::CellKernel, flight::EventKind};
use crate::numbers::lanes::Lanes;
use crate::numbers::real::Real;
use crate::scenes::Scene;
use crate::scenes::lattice::{Lattice, LatticeState};
use crate::scenes::motion::MotionInput;
use crate::scenes::sampling::stream;
use crate::scenes::spec::Motion;
use crate::statistics::mean_se;

/// Collisions discarded at the start of each tangent orbit, so the tangent vector has turned into
/// the unstable direction (it does so within a few collisions at λ ≈ 1 per collision; 1000 is
/// ample and costs 0.05 % of a default orbit).
pub const TANGENT_TRANSIENT: u64 = 1000;

/// Largest Lyapunov exponent with its standard error.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LyapunovReport {
    /// The scene ([`Scene::label`]).
    pub scene: String,
    /// λ per collision.
    pub per_collision: f64,
    /// Its standard error over orbits.
    pub per_collision_err: f64,
    /// λ per unit time.
    pub per_time: f64,
    /// Its standard error.
    pub per_time_err: f64,
    /// Collisions of each batch (one orbit each), after a transient of 1000.
    pub collisions_per_batch: u64,
    /// How the flights crossed the lattice: `walk` or `jump`.
    pub flights: Flights,
    /// Independent batches (tangent-space orbits).
    pub batches: u32,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// What a tangent-space Lyapunov measurement runs: straight flights ([`run`]) or, with `field`,
/// the arcs of a magnetic field ([`crate::estimators::field::lyapunov::run`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LyapunovConfig {
    /// Collisions of each batch (one orbit), after a transient of [`TANGENT_TRANSIENT`].
    pub collisions_per_batch: u64,
    /// Independent batches (tangent-space orbits), at least 2; the error is over them.
    pub batches: u32,
    /// Seed: orbit b starts from stream (seed, b).
    pub seed: u64,
    /// How flights cross the lattice ([`Flights`]): `auto` (jumps where the scene supplies them and they are faster, [`crate::engine::long_flight::AUTO_MAX_RADIUS`]).
    #[serde(default)]
    pub flights: Flights,
    /// The motion, each parameter exactly as typed (flattened: the keys `field`, `electric` and
    /// `electric_angle`): a uniform magnetic field B with 10⁻³ ≤ |B| ≤ 10³ — the exponent of the
    /// arcs — or a thermostatted electric field with 0 < |E| ≤ 10 — the Lyapunov pair of the
    /// driven gas ([`crate::estimators::current::lyapunov::run`]); none: straight flights.
    #[serde(flatten)]
    pub motion: MotionInput,
}

impl LyapunovConfig {
    /// The same measurement in the field B (as typed): the exponent of the arcs, or of straight
    /// flights where B is exactly zero ([`MotionInput::with_field`]).
    pub fn in_field(self, b: &str) -> Self {
        LyapunovConfig {
            motion: self.motion.with_field(b),
            ..self
        }
    }

    /// The same measurement under the thermostatted field of strength `e` along `angle` degrees
    /// (each as typed): the driven gas's Lyapunov pair, or straight flights where E is exactly
    /// zero ([`MotionInput::with_electric`]).
    pub fn under_electric(self, e: &str, angle: &str) -> Self {
        LyapunovConfig {
            motion: self.motion.with_electric(e, angle),
            ..self
        }
    }

    /// Refuses a field, for the measurement of straight flights.
    fn refuse_field(&self) -> Result<(), Error> {
        match self.motion.resolve()? {
            Motion::Field(b) => Err(Error::parameter(
                "field",
                b,
                "this measurement flies straight lines: the exponent in a field is the arcs' \
                 (estimators::field::lyapunov::run)",
            )),
            Motion::Thermostat { field, .. } => Err(Error::parameter(
                "electric",
                field,
                "this measurement flies straight lines: the driven gas's pair is \
                 estimators::current::lyapunov::run's",
            )),
            _ => Ok(()),
        }
    }

    /// The command line's defaults: 2·10⁶ collisions in each of 16 batches, seed 1.
    pub fn new() -> Self {
        LyapunovConfig {
            collisions_per_batch: 2_000_000,
            batches: 16,
            seed: 1,
            flights: Flights::Auto,
            motion: MotionInput::default(),
        }
    }
}

impl Default for LyapunovConfig {
    fn default() -> Self {
        Self::new()
    }
}

/// Tangent-space largest Lyapunov exponent of `scene` from `cfg.batches` independent f64 orbits
/// of `cfg.collisions_per_batch` collisions each. `options.progress` receives collision counts;
/// only `threads` and `progress` of the options apply.
///
/// # Errors
/// No collisions, fewer than 2 batches, or invalid options.
pub fn run<S: Scene>(
    scene: &S,
    cfg: &LyapunovConfig,
    options: &RunOptions,
) -> Result<LyapunovReport, Error> {
    options.accept("lyapunov", &[])?;
    cfg.refuse_field()?;
    let LyapunovConfig {
        collisions_per_batch,
        batches,
        seed,
        flights,
        ..
    } = *cfg;
    let flights = flights.resolve(scene)?;
    let radius = scene.long_flights().filter(|_| flights == Flights::Jump);
    let (threads, progress) = (options.threads, options.progress);
    if collisions_per_batch == 0 || batches < 2 || threads == 0 {
        return Err(Error::TooFew {
            what: "collisions_per_batch, batches (>= 2) or threads",
            min: 2,
            got: batches as u64,
        });
    }
    // With its transient, a batch is one trajectory: a count near 2^64 would wrap around.
    crate::engine::check_trajectory_length(
        collisions_per_batch,
        "collisions_per_batch",
        collisions_per_batch,
    )?;
    let collisions = batches as f64 * (collisions_per_batch + TANGENT_TRANSIENT) as f64;
    let crossings = if radius.is_some() {
        0.0
    } else {
        crossings_per_collision(scene)
    };
    Work::new("lyapunov", &["collisions_per_batch", "batches"], collisions)
        .walking(scene)
        .crossing(crossings)
        .check(threads)?;
    let lat = scene.lattice::<f64>(())?;
    let cell = lat.cell().clone();
    let per: Vec<(f64, f64)> = par_batches_watched(threads, batches, options.stop.as_ref(), |b| {
        let mut rng = stream(seed, b as u64);
        let mut s = scene.sample(&mut rng);
        let d = crate::scenes::sampling::direction(&mut rng);
        let mut tangent = Tangent {
            t: Vector4::new(d.x, d.y, 0.3 * d.y, -0.3 * d.x),
            cell: &cell,
            collisions: 0,
            transient: TANGENT_TRANSIENT,
            logsum: 0.0,
            time: 0.0,
        };
        let n = collisions_per_batch + TANGENT_TRANSIENT;
        in_legs(options.stop.as_ref(), n, STOP_EVERY, |k| match radius {
            Some(r) => drive_jumps(&lat, &r, &mut s, k, &mut tangent, progress),
            None => drive(&lat, &mut s, k, &mut tangent, progress),
        })?;
        let (logsum, time) = (tangent.logsum, tangent.time);
        Ok((logsum / collisions_per_batch as f64, logsum / time))
    })?;
    let (pc, pce) = mean_se(&per.iter().map(|p| p.0).collect::<Vec<_>>());
    let (pt, pte) = mean_se(&per.iter().map(|p| p.1).collect::<Vec<_>>());
    Ok(LyapunovReport {
        scene: scene.label(),
        per_collision: pc,
        per_collision_err: pce,
        per_time: pt,
        per_time_err: pte,
        collisions_per_batch,
        flights,
        batches,
        meta: RunMeta::new(Some(seed), Some(batches as u64), "f64", Some(threads)),
    })
}

/// The tangent dynamics along one orbit (an observer of the scalar engine): the tangent vector
/// is carried through every event by the linearised map and renormalised at every collision;
/// after `transient` collisions, the logarithms of the growth factors and the flight times are
/// summed.
struct Tangent<'a> {
    t: Vector4<f64>,
    cell: &'a ConvexCell<f64>,
    collisions: u64,
    transient: u64,
    logsum: f64,
    time: f64,
}

impl Observer<1> for Tangent<'_> {
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<1>]) {
        for e in steps {
            let (s, ev) = (e.state(0), e.event(0));
            tangent_step(&mut self.t, &s.flight, &ev, self.cell);
            if self.collisions >= self.transient {
                self.time += ev.time;
            }
            if let EventKind::Collision(_) = ev.kind {
                self.collisions += 1;
                let n = self.t.norm();
                self.t /= n;
                if self.collisions > self.transient {
                    self.logsum += n.ln();
                }
            }
        }
    }
}

/// World contact points and velocities at the first `n` collisions of an orbit, as 4096-bit
/// (or lower) numbers converted to `Float` at `out_bits`.
pub(crate) fn collision_track<T: Real, K: CellKernel<T>>(
    lat: &Lattice<T, K>,
    start: &LatticeState<T>,
    n: usize,
    out_bits: u32,
) -> Result<Vec<([Float; 4], f64)>, Error> {
    let mut s = start.clone();
    let mut out = Vec::with_capacity(n);
    let mut time = 0.0;
    while out.len() < n {
        let ev = lat.step(&mut s)?;
        time += ev.time.to_f64();
        if let EventKind::Collision(_) = ev.kind {
            let x = lat.world(&s);
            let (vx, vy) = if s.cell.down {
                (-s.flight.vel.x.clone(), -s.flight.vel.y.clone())
            } else {
                (s.flight.vel.x.clone(), s.flight.vel.y.clone())
            };
            // Exact: every T value is a binary float of ≤ out_bits bits.
            let conv = |v: &T| -> Float { v.to_mpfr(out_bits) };
            out.push(([conv(&x.x), conv(&x.y), conv(&vx), conv(&vy)], time));
        }
    }
    Ok(out)
}
