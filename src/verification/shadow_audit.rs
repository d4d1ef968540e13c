//! Per-event shadow audit of f64 production runs.
//!
//! An [`Auditor`] watches an f64 trajectory and, for a random sample of its events (rate r),
//! replays the event at P ≥ 128 bits from the *exact* f64 pre-event state
//! ([`super::replay::check_event`]) and judges it against the one-step error model. It keeps
//! log-histograms of the one-step errors (time, contact point, velocity, and each as a fraction of
//! its bound), the worst events, and every event outside the model with its exact state, so it can
//! be replayed with [`replay`]. A run whose audited events are all inside the model is an
//! ε-pseudo-orbit with the measured ε (`proofs-notes/error-model.md`).

use rand::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;
use rug::Float;
use serde::{Deserialize, Serialize};

pub use super::audited::{
    AUDIT_FIELD_RANGE, AuditConfig, AuditSummary, AuditedEvent, LogHistogram,
};
use super::replay::{EventCheck, check_event};
use crate::Error;
use crate::engine::long_flight::{Flights, drive_jumps};
use crate::engine::metadata::RunMeta;
use crate::engine::observe::{EventLanes, Observer};
use crate::engine::options::{AuditSpec, RunOptions};
use crate::engine::work::{Work, crossings_per_collision};
use crate::kernel::flight::{EventKind, Flight};
use crate::kernel::vec2::Vec2;
use crate::scenes::Scene;
use crate::scenes::lattice::CellIndex;
use crate::scenes::long_flight::triangular::{Search, TriangularFlights, trigger};
use crate::scenes::long_flight::{Landing, LongFlights, major_edge};

/// The auditors of L trajectories as an [`Observer`]: lane `l`'s events go to auditor `l` (a
/// lane without one is not audited). The first replay error is kept and the rest skipped.
pub struct AuditLanes<S: Scene> {
    /// One auditor per lane.
    pub lanes: Vec<Option<Auditor<S>>>,
    /// The first error met while replaying.
    pub error: Option<Error>,
}

impl<const L: usize, S: Scene> Observer<L> for AuditLanes<S> {
    fn observe<V: crate::numbers::lanes::Lanes>(&mut self, steps: &[EventLanes<L>]) {
        for e in steps {
            if self.error.is_some() {
                return;
            }
            for (l, a) in self.lanes.iter_mut().enumerate() {
                if let (true, Some(a)) = (e.is_live(l), a.as_mut())
                    && let Err(err) = a.observe_event(&e.state(l).flight, e.event(l).kind)
                {
                    self.error = Some(err);
                    return;
                }
            }
        }
    }
}

/// Audits a sample of the events of one f64 trajectory of scene `S`.
pub struct Auditor<S: Scene> {
    label: String,
    t64: S::Kernel<f64>,
    tref: S::Kernel<Float>,
    rate: f64,
    bits: u32,
    rng: Xoshiro256PlusPlus,
    /// The long flights where the run jumps them ([`Auditor::with_jumps`]).
    jumps: Option<LongFlights>,
    /// What was found so far.
    pub summary: AuditSummary,
}

impl<S: Scene> Auditor<S> {
    /// An auditor of `scene`, sampling rate `rate ∈ (0, 1]`, reference precision `bits ≥ 128`,
    /// with its own random stream (it never touches the trajectory's stream). The f64 replay
    /// runs the scene's production kernel; the reference is the same kernel at `bits`, whose
    /// constants come from the same exact scene parameters.
    pub fn new(scene: &S, rate: f64, bits: u32, rng: Xoshiro256PlusPlus) -> Result<Self, Error> {
        AuditSpec::new(rate, bits)?;
        Ok(Auditor {
            label: scene.label(),
            t64: scene.kernel::<f64>(())?,
            tref: scene.kernel::<Float>(bits)?,
            rate,
            bits,
            rng,
            jumps: None,
            summary: AuditSummary::default(),
        })
    }

    /// The auditor of a run whose long flights jump ([`crate::engine::long_flight::drive_jumps`]):
    /// every crossing of the edge that hands a flight to the search and lands it is a jump,
    /// replayed by [`super::jump_audit::check_jump`] (square) or
    /// [`super::jump_audit_triangular::check_jump`] (triangular).
    pub fn with_jumps(mut self, flights: LongFlights) -> Self {
        self.jumps = Some(flights);
        self
    }

    /// Called with the pre-event state and the kind of every event: a jump where the run jumps,
    /// else one event ([`Auditor::observe`]).
    #[inline]
    pub fn observe_event(&mut self, f: &Flight<f64>, kind: EventKind) -> Result<(), Error> {
        match self.jumps {
            Some(LongFlights::Square { radius })
                if kind == EventKind::Crossing(major_edge(&f.vel)) =>
            {
                self.observe_jump(f, radius)
            }
            Some(LongFlights::Triangular(t)) if kind == EventKind::Crossing(trigger(&f.vel)) => {
                match t.jump(CellIndex::default(), f) {
                    Search::Land(l) => self.observe_triangular_jump(f, &t, &l),
                    _ => self.observe(f),
                }
            }
            _ => self.observe(f),
        }
    }

    fn observe_triangular_jump(
        &mut self,
        f: &Flight<f64>,
        t: &TriangularFlights,
        landing: &Landing,
    ) -> Result<(), Error> {
        if self.rate < 1.0 && self.rng.random::<f64>() >= self.rate {
            return Ok(());
        }
        let c = super::jump_audit_triangular::check_jump(&self.tref, t, f, landing)?;
        self.summary.triangular_jumps.add(f, &c);
        Ok(())
    }

    fn observe_jump(&mut self, f: &Flight<f64>, r: f64) -> Result<(), Error> {
        if self.rate < 1.0 && self.rng.random::<f64>() >= self.rate {
            return Ok(());
        }
        let c = super::jump_audit::check_jump(f, r, self.bits)
            .ok_or_else(|| Error::Failed("a free flight along a corridor meets no disk".into()))?;
        self.summary.jumps.add(f, &c);
        Ok(())
    }

    /// Called with the pre-event state of every event; replays a random sample of them.
    #[inline]
    pub fn observe(&mut self, f: &Flight<f64>) -> Result<(), Error> {
        if self.rate < 1.0 && self.rng.random::<f64>() >= self.rate {
            return Ok(());
        }
        let c = check_event(&self.t64, &self.tref, f)?;
        let label = &self.label;
        self.summary.add(&c, || AuditedEvent::new(label, f, &c));
        Ok(())
    }
}

/// Replays a recorded event of `scene` at `bits` of precision.
///
/// # Errors
/// If the event was recorded in another scene, or the precision is out of range.
pub fn replay<S: Scene>(scene: &S, e: &AuditedEvent, bits: u32) -> Result<EventCheck, Error> {
    if e.scene != scene.label() {
        return Err(Error::Invalid(format!(
            "the event was recorded in scene `{}`, not `{}`",
            e.scene,
            scene.label()
        )));
    }
    let [x, y, vx, vy] = e.state_bits.map(f64::from_bits);
    let mut f = Flight::new(Vec2::new(x, y), Vec2::new(vx, vy));
    f.excluded_disk = e.excluded[0];
    f.excluded_edge = e.excluded[1];
    check_event(&scene.kernel::<f64>(())?, &scene.kernel::<Float>(bits)?, &f)
}

/// The result of [`run`] (the CLI's `audit --json`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct AuditReport {
    /// What was run.
    pub config: AuditConfig,
    /// Events simulated.
    pub events: u64,
    /// Quantiles (median, 0.99, max) of the time error, contact-point error, velocity error and
    /// time error / bound.
    pub quantiles: AuditQuantiles,
    /// Everything found.
    pub summary: AuditSummary,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// How the flights crossed the lattice: `walk` or `jump` (files written before jumps
    /// existed: `walk`).
    #[serde(default = "walked")]
    pub flights: Flights,
    /// Version, seed, batches, reference precision, engine, threads, command line.
    pub meta: RunMeta,
}

fn walked() -> Flights {
    Flights::Walk
}

/// Median, 99th percentile and maximum of each one-step error.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct AuditQuantiles {
    /// Time error.
    pub time_error: Quantiles,
    /// Contact-point error.
    pub position_error: Quantiles,
    /// Velocity error.
    pub velocity_error: Quantiles,
    /// Time error / bound.
    pub time_error_over_bound: Quantiles,
    /// Position error / bound (absent in files written before it was recorded).
    #[serde(default)]
    pub position_error_over_bound: Option<Quantiles>,
    /// Velocity error / bound (likewise).
    #[serde(default)]
    pub velocity_error_over_bound: Option<Quantiles>,
}

/// Median, 99th percentile and maximum of one error.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct Quantiles {
    /// Median.
    pub median: f64,
    /// 99th percentile.
    pub p99: f64,
    /// Maximum.
    pub max: f64,
}

impl AuditQuantiles {
    /// The quantiles of every histogram of `summary`.
    fn of(summary: &AuditSummary) -> Self {
        AuditQuantiles {
            time_error: q3(&summary.time_error),
            position_error: q3(&summary.position_error),
            velocity_error: q3(&summary.velocity_error),
            time_error_over_bound: q3(&summary.time_error_over_bound),
            position_error_over_bound: Some(q3(&summary.position_error_over_bound)),
            velocity_error_over_bound: Some(q3(&summary.velocity_error_over_bound)),
        }
    }
}

fn q3(h: &LogHistogram) -> Quantiles {
    Quantiles {
        median: h.quantile(0.5),
        p99: h.quantile(0.99),
        max: h.max,
    }
}

/// Refuses the audit `cfg` of `scene` when even the floor costs make it longer than a week of
/// its `threads` ([`Work`]): its collisions, the cells they walk, and the sampled replays in MPFR
/// (a jump is replayed by walking its column exactly, so sampled jumps walk their cells).
fn price<S: Scene>(
    scene: &S,
    cfg: &AuditConfig,
    flights: Flights,
    threads: usize,
) -> Result<(), Error> {
    let walked = crossings_per_collision(scene);
    let (crossings, replayed) = match flights {
        Flights::Jump => (
            0.0,
            walked * crate::engine::work::seconds_per_crossing(scene),
        ),
        _ => (walked, 0.0),
    };
    Work::new(
        "audit",
        &["collisions", "sample", "reference_bits"],
        cfg.collisions as f64,
    )
    .walking(scene)
    .crossing(crossings)
    .replaying(cfg.sample, cfg.reference_bits)
    .costing_more(cfg.sample * replayed)
    .check(threads)
}

/// Runs the audit `cfg` on `threads` threads (the result does not depend on them). `progress`
/// receives collision counts.
///
/// Only `threads` and `progress` of the options apply (the audit's own sample rate and bits
/// are in `cfg`).
pub fn run<S: Scene>(
    scene: &S,
    cfg: &AuditConfig,
    options: &RunOptions,
) -> Result<AuditReport, Error> {
    options.accept("audit", &[])?;
    let (threads, progress) = (options.threads, options.progress);
    if cfg.scene != scene.label() {
        return Err(Error::Failed(format!(
            "audit configuration for scene `{}` run on `{}`",
            cfg.scene,
            scene.label()
        )));
    }
    if cfg.collisions == 0 {
        return Err(Error::Zero { what: "collisions" });
    }
    if cfg.batches == 0 {
        return Err(Error::Zero { what: "batches" });
    }
    crate::engine::parallel::check_batches("batches", cfg.batches)?;
    let motion = cfg.exact_motion()?;
    let flights = audit_flights(scene, cfg.flights, motion.is_some())?;
    // The ranges first: the work is priced from values known to be in range.
    AuditSpec::new(cfg.sample, cfg.reference_bits)?;
    price(scene, cfg, flights, threads)?;
    if threads == 0 {
        return Err(Error::Zero { what: "threads" });
    }
    let start = std::time::Instant::now();
    let lat = scene.lattice::<f64>(())?;
    let parts: Vec<(AuditSummary, u64)> = crate::engine::parallel::par_batches_watched(
        threads,
        cfg.batches,
        options.stop.as_ref(),
        |b| {
            if let Some(m) = &motion {
                return super::arc_audit::batch(scene, cfg, m, b, options);
            }
            straight_batch(
                scene,
                &lat,
                cfg,
                flights,
                b,
                (progress, options.stop.as_ref()),
            )
        },
    )?;
    let mut summary = AuditSummary::default();
    let mut events = 0;
    for (p, e) in &parts {
        summary.merge(p);
        events += e;
    }
    Ok(AuditReport {
        config: cfg.clone(),
        events,
        quantiles: AuditQuantiles::of(&summary),
        summary,
        seconds: start.elapsed().as_secs_f64(),
        flights,
        meta: RunMeta::new(
            Some(cfg.seed),
            Some(cfg.batches as u64),
            cfg.reference_bits,
            Some(threads),
        ),
    })
}

/// The engine an audit runs: `walk` in a field (arcs and thermostatted flights cross cell by
/// cell), else `flights` resolved for the scene.
///
/// # Errors
/// `jump` in a field or in a scene without long flights.
fn audit_flights<S: Scene>(scene: &S, flights: Flights, field: bool) -> Result<Flights, Error> {
    if field {
        flights.in_field()
    } else {
        flights.resolve(scene)
    }
}

/// Collisions of an audited trajectory between two looks at the stop flag: each event may be
/// replayed in MPFR, so a leg takes about as long as the scalar engine's [`STOP_EVERY`] legs.
///
/// [`STOP_EVERY`]: crate::engine::parallel::STOP_EVERY
const AUDIT_STOP_EVERY: u64 = 1 << 14;

/// Batch `b` of an audit without a field: its share of the collisions, every event offered to
/// an [`Auditor`] watching the engine's trajectory (long flights jumped where `flights` says
/// so, each jump replayed as a whole), looking at `stop` every [`AUDIT_STOP_EVERY`] collisions.
/// Returns the summary and the events.
fn straight_batch<S: Scene>(
    scene: &S,
    lat: &crate::scenes::lattice::Lattice<f64, S::Kernel<f64>>,
    cfg: &AuditConfig,
    flights: Flights,
    b: u32,
    (progress, stop): (
        &(dyn Fn(u64) + Sync),
        Option<&crate::engine::options::StopFlag>,
    ),
) -> Result<(AuditSummary, u64), Error> {
    use crate::engine::drive;
    use crate::observers::counters::CounterLanes;
    use crate::scenes::sampling::{Purpose, StreamKey, stream};
    let n = crate::engine::parallel::share(cfg.collisions, cfg.batches, b);
    let mut s = scene.sample(&mut stream(cfg.seed, b as u64));
    let mut a = Auditor::new(
        scene,
        cfg.sample,
        cfg.reference_bits,
        StreamKey::new(cfg.seed, Purpose::Audit, b as u64).rng(),
    )?;
    let radius = scene.long_flights().filter(|_| flights == Flights::Jump);
    if let Some(r) = radius {
        a = a.with_jumps(r);
    }
    let mut obs = (
        AuditLanes {
            lanes: vec![Some(a)],
            error: None,
        },
        CounterLanes::new(1),
    );
    crate::engine::parallel::in_legs(stop, n, AUDIT_STOP_EVERY, |k| match radius {
        Some(r) => drive_jumps(lat, &r, &mut s, k, &mut obs, progress),
        None => drive(lat, &mut s, k, &mut obs, progress),
    })?;
    let (audit, counters) = obs;
    if let Some(e) = audit.error {
        return Err(e);
    }
    let a = audit
        .lanes
        .into_iter()
        .next()
        .flatten()
        .expect("one auditor");
    let c = counters.lane(0);
    let events = c.collisions + c.crossings;
    Ok((a.summary, events))
}
