//! What an audit replays and keeps: its configuration, each audited event with its exact
//! pre-event state, and the mergeable summary of a run's one-step errors. The straight audit
//! ([`super::shadow_audit`]) and the arc audit ([`super::arc_audit`]) both fill these.

use serde::{Deserialize, Serialize};

use super::curved::ExactMotion;
pub use super::log_histogram::LogHistogram;
use super::replay::EventCheck;
use crate::Error;
use crate::engine::long_flight::Flights;
use crate::kernel::flight::Flight;
use crate::scenes::motion::MotionInput;

/// An audited event with its exact f64 pre-event state (bit patterns, for replay).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct AuditedEvent {
    /// The scene ([`Scene::label`](crate::scenes::Scene::label)).
    pub scene: String,
    /// Position and velocity (x, y, vx, vy) as IEEE bit patterns.
    pub state_bits: [u64; 4],
    /// The same as decimals (shortest round-trip form).
    pub state: [f64; 4],
    /// Excluded disk and edge (`null` = none).
    pub excluded: [Option<u8>; 2],
    /// The state's cell is point-reflected (a down trap of the triangular lattice), where the
    /// thermostat's field is −E (absent: false; arcs and straight flights are the same in
    /// every cell).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub down: bool,
    /// The verdict.
    pub check: EventCheck,
}

impl AuditedEvent {
    /// The event of the pre-event flight `f` in scene `scene`, with its verdict.
    pub fn new(scene: &str, f: &Flight<f64>, check: &EventCheck) -> AuditedEvent {
        AuditedEvent {
            scene: scene.to_string(),
            state_bits: [
                f.pos.x.to_bits(),
                f.pos.y.to_bits(),
                f.vel.x.to_bits(),
                f.vel.y.to_bits(),
            ],
            state: [f.pos.x, f.pos.y, f.vel.x, f.vel.y],
            excluded: [f.excluded_disk, f.excluded_edge],
            down: false,
            check: check.clone(),
        }
    }
}

/// What an audit found (mergeable across batches).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct AuditSummary {
    /// Events replayed.
    pub audited: u64,
    /// Events outside the error model.
    pub outside: u64,
    /// Events whose choice was ambiguous at f64 resolution (inside the model).
    pub ambiguous: u64,
    /// Events where f64 and the reference chose different obstacles (all ambiguous if inside).
    pub different_choice: u64,
    /// One-step time errors.
    pub time_error: LogHistogram,
    /// Contact-point errors.
    pub position_error: LogHistogram,
    /// Velocity errors.
    pub velocity_error: LogHistogram,
    /// Time error as a fraction of its bound.
    pub time_error_over_bound: LogHistogram,
    /// Position error as a fraction of its bound (arcs: the running bound of each event).
    #[serde(default)]
    pub position_error_over_bound: LogHistogram,
    /// Velocity error as a fraction of its bound.
    #[serde(default)]
    pub velocity_error_over_bound: LogHistogram,
    /// The worst events by time error / bound (at most 10).
    pub worst: Vec<AuditedEvent>,
    /// Every event outside the model (at most 1000 kept).
    pub outside_events: Vec<AuditedEvent>,
    /// The long flights jumped, each replayed as a whole (`jump_audit`); empty where flights
    /// walk.
    #[serde(default)]
    pub jumps: super::jump_audit::JumpSummary,
    /// The long flights jumped on the triangular lattice, each replayed by the MPFR cell walk
    /// (`jump_audit_triangular`); empty elsewhere.
    #[serde(default)]
    pub triangular_jumps: super::jump_audit_triangular::TriangularJumpSummary,
}

impl AuditSummary {
    /// Adds another summary.
    pub fn merge(&mut self, o: &AuditSummary) {
        self.audited += o.audited;
        self.outside += o.outside;
        self.ambiguous += o.ambiguous;
        self.different_choice += o.different_choice;
        self.time_error.merge(&o.time_error);
        self.position_error.merge(&o.position_error);
        self.velocity_error.merge(&o.velocity_error);
        self.time_error_over_bound.merge(&o.time_error_over_bound);
        self.position_error_over_bound
            .merge(&o.position_error_over_bound);
        self.velocity_error_over_bound
            .merge(&o.velocity_error_over_bound);
        self.worst.extend(o.worst.iter().cloned());
        self.worst.sort_by(|a, b| ratio(b).total_cmp(&ratio(a)));
        self.worst.truncate(10);
        self.outside_events.extend(o.outside_events.iter().cloned());
        self.outside_events.truncate(1000);
        self.jumps.merge(&o.jumps);
        self.triangular_jumps.merge(&o.triangular_jumps);
    }
}

fn ratio(e: &AuditedEvent) -> f64 {
    if e.check.time_bound > 0.0 {
        e.check.time_error / e.check.time_bound
    } else {
        0.0
    }
}

impl AuditSummary {
    /// Counts one replayed event; `record` describes it if it is kept (outside the model, or
    /// among the worst by time error over bound).
    pub fn add(&mut self, c: &EventCheck, record: impl Fn() -> AuditedEvent) {
        let s = self;
        s.audited += 1;
        s.time_error.add(c.time_error);
        s.position_error.add(c.position_error);
        s.velocity_error.add(c.velocity_error);
        let r = if c.time_bound > 0.0 {
            c.time_error / c.time_bound
        } else {
            0.0
        };
        s.time_error_over_bound.add(r);
        let over = |e: f64, b: f64| if b > 0.0 { e / b } else { 0.0 };
        s.position_error_over_bound
            .add(over(c.position_error, c.position_bound));
        s.velocity_error_over_bound
            .add(over(c.velocity_error, c.velocity_bound));
        if c.ambiguous {
            s.ambiguous += 1;
        }
        if c.kind_f64 != c.kind_ref {
            s.different_choice += 1;
        }
        if !c.in_model {
            s.outside += 1;
            if s.outside_events.len() < 1000 {
                s.outside_events.push(record());
            }
        }
        if s.worst.len() < 10 || r > ratio(s.worst.last().expect("non-empty")) {
            s.worst.push(record());
            s.worst.sort_by(|a, b| ratio(b).total_cmp(&ratio(a)));
            s.worst.truncate(10);
        }
    }
}

/// What an audit run does: `collisions` collisions in all, over `batches` independent f64
/// trajectories from the invariant measure (seed `seed`), replaying a fraction `sample` of their
/// events at `reference_bits`. The thread count is not part of it: it never changes the result.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AuditConfig {
    /// The scene ([`Scene::label`](crate::scenes::Scene::label)).
    pub scene: String,
    /// Collisions in all (trajectory i gets ⌊N/T⌋, plus one for the first N mod T).
    pub collisions: u64,
    /// Independent batches (one trajectory each).
    pub batches: u32,
    /// Fraction of events replayed, in (0, 1].
    pub sample: f64,
    /// MPFR precision of the replay, in bits.
    pub reference_bits: u32,
    /// Seed.
    pub seed: u64,
    /// The motion, each parameter exactly as given (flattened: the keys `field`, `electric` and
    /// `electric_angle`): arcs of a magnetic field B with 10⁻⁶ ≤ |B| ≤ 10⁶, judged by the arc
    /// kernel's running error bound ([`super::arc_audit`]), or the flights of a thermostatted
    /// electric field with 0 < |E| ≤ 10, judged by their kernel's running error bound and checked
    /// against independent closed forms ([`super::thermo_audit`]); none: straight flights.
    #[serde(flatten)]
    pub motion: MotionInput,
    /// How straight flights cross the lattice ([`Flights`]): `auto` jumps where the scene
    /// supplies long flights and they are faster ([`Flights::resolve`]), and there is no field.
    #[serde(default)]
    pub flights: Flights,
}

/// The fields an audit takes: 10⁻⁶ ≤ |B| ≤ 10⁶ (cyclotron radii from 10⁻⁶ to 10⁶ at speed 1).
pub const AUDIT_FIELD_RANGE: (f64, f64) = (1e-6, 1e6);

impl AuditConfig {
    /// The field, exact, if there is one (`None` for an absent or zero field).
    ///
    /// # Errors
    /// A field that is not an exact decimal or fraction, or outside [`AUDIT_FIELD_RANGE`].
    pub fn field_exact(&self) -> Result<Option<rug::Rational>, Error> {
        super::exact_field(self.motion.field.as_deref(), AUDIT_FIELD_RANGE)
    }

    /// The curved motion, exact, if there is one: the magnetic field, or the thermostatted
    /// electric one (`None`: straight flights, a zero or absent field).
    ///
    /// # Errors
    /// Both fields given, an angle without a strength, or a field that is not exact or out of
    /// its range ([`AuditConfig::field_exact`],
    /// [`check_electric`](crate::estimators::diffusion::check_electric)).
    pub fn exact_motion(&self) -> Result<Option<ExactMotion>, Error> {
        ExactMotion::of(&self.motion, AUDIT_FIELD_RANGE)
    }
}
