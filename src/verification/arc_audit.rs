//! Per-event shadow audit of arcs: each sampled `f64` event of a run in a magnetic field is
//! replayed from its exact pre-event state by the same generic kernel on [`Tracked`] numbers,
//! which gives the event at 128 bits or more *and*, operation by operation, a bound on how far
//! the `f64` computation can be from it (the running error analysis of `numbers::tracked`).
//!
//! The verdict (`proofs-notes/magnetic-audit.md`): the `f64` event must be the reference's
//! (same obstacle, same cell) with every coordinate of the post-event position and velocity
//! within its bound, unless a decision on the way — a sign, a comparison of chords, the choice
//! between the radical-line and the disk-frame contact — was within its bounds of the other
//! outcome: such an event is *ambiguous* at `f64` resolution and inside the model whatever it
//! chose. The bound is the `f64` computation's own, so unlike the straight audit's closed-form
//! model it follows every formula of the arc kernel, near-concentric and grazing ones included,
//! with no constant fitted to data. The flight time (an observable, computed with `atan2`) is
//! judged the same way.
//!
//! Thermostatted flights ([`Curved::Thermostat`]) are replayed the same way, by their own kernel
//! on the same tracked numbers, with what a certified march adds (`proofs-notes/thermostat-audit.md`):
//! the march's free choices anchored, the band in which either run may stop
//! ([`super::thermo_audit::stopping_band`]) added to the time's and the state's bounds, and the
//! reference flight checked against closed forms the kernel does not use.

use rand::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;

use super::audited::{AuditConfig, AuditSummary, AuditedEvent};
use super::curved::{Curved, CurvedEvent, ExactMotion};
use super::replay::EventCheck;
use super::thermo_audit::StoppingBand;
use crate::Error;
use crate::kernel::cell::CellKernel;
use crate::kernel::flight::EventKind;
use crate::numbers::tracked::{Tracked, take_ambiguous, take_free_ambiguous};
use crate::scenes::Scene;
use crate::scenes::lattice::{Lattice, LatticeState};

fn label(k: EventKind) -> String {
    match k {
        EventKind::Collision(m) => format!("collision {m}"),
        EventKind::Crossing(e) => format!("crossing {e}"),
    }
}

/// |x₆₄ − x| and the bound of each coordinate pair (its running bound widened by `widen`), as
/// Euclidean norms; `within` if every coordinate is inside its bound.
fn compare(x64: [f64; 2], x: [&Tracked; 2], widen: [f64; 2]) -> (f64, f64, bool) {
    let mut err2 = 0.0;
    let mut bound2 = 0.0;
    let mut within = true;
    for ((a, t), w) in x64.iter().zip(x).zip(widen) {
        let d = (rug::Float::with_val(t.v.prec(), *a) - &t.v).to_f64().abs();
        let bound = t.e + w;
        within &= d <= bound;
        err2 += d * d;
        bound2 += bound * bound;
    }
    (err2.sqrt(), bound2.sqrt(), within)
}

/// Replays the next arc event of the `f64` state `s` in the field `b64` on tracked numbers
/// (`lat_t`, field `b`: the exact field at the reference precision) and judges it
/// ([`check_curved_event`] for arcs).
///
/// # Errors
/// If the `f64` state has no next event (a pinned orbit: the caller starts only colliding
/// ones).
pub fn check_arc_event<K64: CellKernel<f64>, KT: CellKernel<Tracked>>(
    lat64: &Lattice<f64, K64>,
    lat_t: &Lattice<Tracked, KT>,
    s: &LatticeState<f64>,
    b64: f64,
    b: &Tracked,
) -> Result<EventCheck, Error> {
    check_curved_event(lat64, lat_t, s, &Curved::Arc(b64), &Curved::Arc(b.clone()))
}

/// Replays the next event of the `f64` state `s` under the motion `m64` on tracked numbers
/// (`lat_t`, motion `m_t`: its exact parameters at the reference precision) and judges it: the
/// same obstacle and cell, every post-event coordinate and the flight time within its running
/// bound, or an ambiguous decision on the way. A thermostatted flight's reference must also be
/// the thermostatted flight, checked against closed forms the kernel does not use
/// ([`super::thermo_audit`]).
///
/// # Errors
/// If the `f64` state has no next event (a pinned orbit, a creeping slide).
pub fn check_curved_event<K64: CellKernel<f64>, KT: CellKernel<Tracked>>(
    lat64: &Lattice<f64, K64>,
    lat_t: &Lattice<Tracked, KT>,
    s: &LatticeState<f64>,
    m64: &Curved<f64>,
    m_t: &Curved<Tracked>,
) -> Result<EventCheck, Error> {
    let ev64 = m64
        .next(lat64, s)
        .ok_or_else(|| Error::Failed("the f64 flight has no next event".into()))?;
    let bits = m_t.bits();
    take_ambiguous();
    take_free_ambiguous();
    let mut st = LatticeState::<Tracked>::convert_from_f64(bits, s);
    let evt = m_t.next(lat_t, &st);
    let t64 = m64.time(s, &ev64);
    let mut a64 = s.clone();
    m64.apply(lat64, &mut a64, &ev64);
    let mut flight_identity = None;
    let mut band = Some(StoppingBand {
        time: 0.0,
        state: [0.0; 4],
    });
    let (kind_ref, time_t) = match &evt {
        Some(e) => {
            if let (Curved::Thermostat(fields), CurvedEvent::Thermostat(te)) = (m_t, e) {
                let v0 = [&st.flight.vel.x, &st.flight.vel.y];
                let th = fields.in_cell(&st.cell);
                flight_identity = Some(super::thermo_audit::flight_residual(th, v0, te));
                band = super::thermo_audit::stopping_band(lat_t.cell(), &st.flight, th, te);
            }
            let t = m_t.time(&st, e);
            m_t.apply(lat_t, &mut st, e);
            (label(e.kind()), Some(t))
        }
        None => ("none".to_string(), None),
    };
    // A contact grazing at f64 resolution has no stopping band: its time is ambiguous.
    let ambiguous = take_ambiguous() > 0 || band.is_none();
    let band = band.unwrap_or(StoppingBand {
        time: 0.0,
        state: [0.0; 4],
    });
    let [wx, wy, wvx, wvy] = band.state;
    // A free choice within its bounds (a march's step) changes the path, not the event: it
    // excuses a different event only (a graze the other path would have missed).
    let free = take_free_ambiguous() > 0;
    let same = evt.as_ref().is_some_and(|e| e.kind() == ev64.kind()) && st.cell == a64.cell;
    let f = (&a64.flight, &st.flight);
    let (position_error, position_bound, pos_ok) =
        compare([f.0.pos.x, f.0.pos.y], [&f.1.pos.x, &f.1.pos.y], [wx, wy]);
    let (velocity_error, velocity_bound, vel_ok) =
        compare([f.0.vel.x, f.0.vel.y], [&f.1.vel.x, &f.1.vel.y], [wvx, wvy]);
    let (time_error, time_bound, time_ok) = match &time_t {
        Some(t) => {
            let e = (rug::Float::with_val(bits, t64) - &t.v).to_f64().abs();
            let bound = t.e + band.time;
            (e, bound, e <= bound)
        }
        None => (f64::INFINITY, 0.0, false),
    };
    // The reference is the exact flight whatever the f64 run decided.
    let exact_flight = flight_identity.is_none_or(|r| r <= 1.0);
    let in_model =
        exact_flight && (ambiguous || (!same && free) || (same && pos_ok && vel_ok && time_ok));
    Ok(EventCheck {
        kind_f64: label(ev64.kind()),
        kind_ref,
        time_error,
        time_bound,
        position_error,
        velocity_error,
        position_bound,
        velocity_bound,
        ambiguous,
        in_model,
        flight_identity,
    })
}

/// Audits a sample of the events of `f64` trajectories of scene `S` under one curved motion:
/// arcs in a magnetic field or thermostatted flights.
pub struct CurvedAuditor<S: Scene> {
    label: String,
    lat64: Lattice<f64, S::Kernel<f64>>,
    lat_t: Lattice<Tracked, S::Kernel<Tracked>>,
    m64: Curved<f64>,
    m_t: Curved<Tracked>,
    rate: f64,
    rng: Xoshiro256PlusPlus,
    /// What was found so far.
    pub summary: AuditSummary,
}

impl<S: Scene> CurvedAuditor<S> {
    /// An auditor of `scene` under `motion` (exact), replaying a fraction `rate` of the events
    /// at `bits` (≥ 128) with its own random stream.
    pub fn new(
        scene: &S,
        motion: &ExactMotion,
        rate: f64,
        bits: u32,
        rng: Xoshiro256PlusPlus,
    ) -> Result<Self, Error> {
        Ok(CurvedAuditor {
            label: scene.label(),
            lat64: scene.lattice::<f64>(())?,
            lat_t: scene.lattice::<Tracked>(bits)?,
            m64: motion.in_f64(bits),
            m_t: motion.tracked(bits),
            rate,
            rng,
            summary: AuditSummary::default(),
        })
    }

    /// The motion as the `f64` run flies it.
    pub fn motion(&self) -> &Curved<f64> {
        &self.m64
    }

    /// The `f64` lattice the audited run flies on.
    pub fn lattice(&self) -> &Lattice<f64, S::Kernel<f64>> {
        &self.lat64
    }

    /// Called with the pre-event state of every event; replays a random sample of them.
    pub fn observe(&mut self, s: &LatticeState<f64>) -> Result<(), Error> {
        if self.rate < 1.0 && self.rng.random::<f64>() >= self.rate {
            return Ok(());
        }
        let c = check_curved_event(&self.lat64, &self.lat_t, s, &self.m64, &self.m_t)?;
        let label = &self.label;
        self.summary.add(&c, || AuditedEvent {
            down: s.cell.down,
            ..AuditedEvent::new(label, &s.flight, &c)
        });
        Ok(())
    }
}

/// Batch `b` of an audit under the curved `motion`: its share of `cfg.collisions` from a start
/// drawn from the invariant measure (stream (seed, b), as the straight audit's; pinned starts,
/// which never collide, are drawn again), with every event offered to a [`CurvedAuditor`] of
/// stream (seed, Audit, b). Returns the summary and the number of events.
pub(super) fn batch<S: Scene>(
    scene: &S,
    cfg: &AuditConfig,
    motion: &ExactMotion,
    b: u32,
    options: &crate::engine::options::RunOptions,
) -> Result<(AuditSummary, u64), Error> {
    use crate::scenes::sampling::{Purpose, StreamKey, stream};
    let n = crate::engine::parallel::share(cfg.collisions, cfg.batches, b);
    let key = StreamKey::new(cfg.seed, Purpose::Audit, b as u64);
    let mut a = CurvedAuditor::new(scene, motion, cfg.sample, cfg.reference_bits, key.rng())?;
    let m = a.motion().clone();
    let mut s = colliding_start(scene, a.lattice(), &m, &mut stream(cfg.seed, b as u64))?;
    let (mut collisions, mut events, mut since) = (0u64, 0u64, 0u64);
    while collisions < n {
        a.observe(&s)?;
        let ev = m.next(a.lattice(), &s);
        let ev = ev.filter(|_| since < MAX_CROSSINGS).ok_or_else(|| {
            Error::Failed(format!(
                "an orbit under the motion {motion:?} stopped colliding ({since} crossings since \
                 the last collision)"
            ))
        })?;
        m.apply(a.lattice(), &mut s, &ev);
        events += 1;
        since += 1;
        if let EventKind::Collision(_) = ev.kind() {
            (collisions, since) = (collisions + 1, 0);
            if collisions % 4096 == 0 {
                (options.progress)(4096);
                if let Some(stop) = &options.stop {
                    stop.check()?;
                }
            }
        }
    }
    (options.progress)(collisions % 4096);
    Ok((a.summary, events))
}

/// Draws before a batch gives up finding a start that collides (every orbit pinned).
const MAX_DRAWS: u32 = 100_000;
/// Crossings without a collision after which an orbit is taken to be pinned (a measure-zero
/// start the exact classification did not see, e.g. on a scene without a disk lattice).
const MAX_CROSSINGS: u64 = 1 << 20;

/// A start from the invariant measure whose cyclotron circle meets a disk: a pinned circle
/// (exact geometry, `theory::magnetic`, where the scene has a disk lattice) may cross cell
/// edges for ever without a collision, and is drawn again.
fn colliding_start<S: Scene>(
    scene: &S,
    lat: &Lattice<f64, S::Kernel<f64>>,
    m: &Curved<f64>,
    rng: &mut Xoshiro256PlusPlus,
) -> Result<LatticeState<f64>, Error> {
    use crate::theory::magnetic::{FieldGeometry, Orbit};
    let w = match m {
        Curved::Arc(w) => *w,
        Curved::Thermostat(_) => return flying_start(scene, lat, m, rng),
    };
    let geometry = match scene.disk_lattice() {
        Some(d) => Some(FieldGeometry::new(d, w)?),
        None => None,
    };
    // Starts are drawn until one meets a disk: where that share is too small for the draws to
    // find one (a strong field, circles far smaller than the gaps), refuse at once with it.
    let meets = geometry.as_ref().map_or(1.0, |g| 1.0 - g.pinned_fraction());
    if meets * f64::from(MAX_DRAWS) < 20.0 {
        return Err(Error::out_of_range(
            "field",
            format!("{w:e}"),
            format!(
                "in this field only {meets:.1e} of the starts have a cyclotron circle that meets \
                 a disk (the rest are pinned): the audit draws its starts among those, so use a \
                 weaker field"
            ),
        ));
    }
    for _ in 0..MAX_DRAWS {
        let s = scene.sample(rng);
        let pinned = match &geometry {
            Some(g) => {
                let (p, sg) = (lat.world(&s), s.cell.sign());
                g.classify(p.x, p.y, sg * s.flight.vel.x, sg * s.flight.vel.y) == Orbit::Pinned
            }
            None => lat.next_event_in_field(&s, &w).is_none(),
        };
        if !pinned {
            return Ok(s);
        }
    }
    Err(Error::Failed(format!(
        "no start in {MAX_DRAWS} draws meets a disk: every orbit is pinned in the field {w:e}"
    )))
}

/// A start from the invariant measure that has a next event under the thermostat (a start of
/// measure zero creeping along a disk has none, and is drawn again).
fn flying_start<S: Scene>(
    scene: &S,
    lat: &Lattice<f64, S::Kernel<f64>>,
    m: &Curved<f64>,
    rng: &mut Xoshiro256PlusPlus,
) -> Result<LatticeState<f64>, Error> {
    for _ in 0..MAX_DRAWS {
        let s = scene.sample(rng);
        if m.next(lat, &s).is_some() {
            return Ok(s);
        }
    }
    Err(Error::Failed(format!(
        "no start in {MAX_DRAWS} draws has a next event under the thermostat"
    )))
}

/// The pre-event state of a recorded event, from its exact bit patterns, in the cell (0, 0) of
/// its orientation (the kernel works in the cell's own frame: the cell index moves with the state
/// and does not enter the event; the orientation does under the thermostat, whose field is −E in
/// a point-reflected cell).
pub fn recorded_state(e: &AuditedEvent) -> LatticeState<f64> {
    let [x, y, vx, vy] = e.state_bits.map(f64::from_bits);
    let mut flight = crate::kernel::flight::Flight::new(
        crate::kernel::vec2::Vec2::new(x, y),
        crate::kernel::vec2::Vec2::new(vx, vy),
    );
    flight.excluded_disk = e.excluded[0];
    flight.excluded_edge = e.excluded[1];
    LatticeState {
        cell: crate::scenes::lattice::CellIndex {
            i: 0,
            j: 0,
            down: e.down,
        },
        flight,
    }
}
