//! Per-event audit of long flights on the triangular lattice beyond w∞: each sampled jump
//! ([`crate::scenes::long_flight::triangular`]) is replayed from its exact `f64` pre-jump state
//! by the cell walk in MPFR, on the traps of the exact gap, and judged against the jump's error
//! model (`proofs-notes/long-flights.md`, "The triangular lattice").
//!
//! The walk must cross into the landing's trap before any collision (a collision first is a disk
//! the jump skipped), through the landing's edge, at the landing's point and time within the
//! bounds: the landing's own roundings and the distance between the `f64` lattice the search
//! uses (a, h rounded) and the exact one the reference walks.

use rug::Float;
use serde::{Deserialize, Serialize};

use super::error_model::UNIT_ROUNDOFF as U;
use super::log_histogram::LogHistogram;
use crate::Error;
use crate::kernel::cell::CellKernel;
use crate::kernel::flight::{EventKind, Flight};
use crate::scenes::lattice::{CellIndex, Lattice, LatticeState};
use crate::scenes::long_flight::Landing;
use crate::scenes::long_flight::triangular::TriangularFlights;

/// The verdict on one replayed jump.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TriangularJumpCheck {
    /// Trap crossings the reference walked to the landing.
    pub crossings: u64,
    /// The reference met a disk before the landing's trap (a skipped disk: outside the model).
    pub collided: bool,
    /// The reference crossed into the landing's trap through the landing's edge.
    pub reached: bool,
    /// |t_jump − t_ref| of the flight time to the landing, and its bound.
    pub time_error: f64,
    /// Error-model bound on the time error.
    pub time_bound: f64,
    /// |x_jump − x_ref| of the landing point in the landing trap's frame.
    pub position_error: f64,
    /// Error-model bound on the position error.
    pub position_bound: f64,
    /// Everything within the model.
    pub in_model: bool,
}

/// Replays the jump `landing` of the `f64` flight `f` (in the trap (0, 0), up) by the cell walk
/// of the reference kernel `kref` (the same scene's traps in MPFR), and judges it.
///
/// # Errors
/// A reference state without a next event.
pub fn check_jump<K: CellKernel<Float>>(
    kref: &K,
    t: &TriangularFlights,
    f: &Flight<f64>,
    landing: &Landing,
) -> Result<TriangularJumpCheck, Error> {
    let bits = kref.cell().lattice.a.prec();
    let lat = Lattice::from_kernel(kref.clone());
    let mut s = LatticeState {
        cell: CellIndex::default(),
        flight: Flight::convert_from_f64(bits, f),
    };
    let target = landing.cell;
    let span = (target.i.unsigned_abs() + target.j.unsigned_abs()) as f64;
    // A straight line crosses at most three trap edges per column it passes, and a column is h
    // wide: far more than enough, yet finite for a reference gone astray.
    let most = 8 * (target.i.unsigned_abs() + target.j.unsigned_abs()) + 64;
    let mut c = TriangularJumpCheck::default();
    let mut time = Float::with_val(bits, 0);
    while c.crossings < most {
        let ev = lat
            .next_event(&s)
            .ok_or_else(|| Error::Failed("the reference walk lost its next event".into()))?;
        if let EventKind::Collision(_) = ev.kind {
            c.collided = true;
            break;
        }
        time += &ev.time;
        lat.apply(&mut s, &ev);
        c.crossings += 1;
        if s.cell == target {
            c.reached = s.flight.excluded_edge == landing.flight.excluded_edge;
            break;
        }
    }
    let (pos, tref) = (s.flight.pos.to_f64(), time.to_f64());
    c.position_error = (pos[0] - landing.flight.pos.x).hypot(pos[1] - landing.flight.pos.y);
    c.time_error = (tref - landing.time).abs();
    let (bp, bt) = bounds(t, span, landing.time);
    c.position_bound = bp;
    c.time_bound = bt;
    c.in_model = !c.collided
        && c.reached
        && c.position_error <= c.position_bound
        && c.time_error <= c.time_bound;
    Ok(c)
}

/// The bounds on the landing point's and the flight time's errors for a landing `span` = |i| + |j|
/// lattice steps away at flight time `t` (`proofs-notes/long-flights.md`, "The triangular
/// lattice"): the lattice point there moves by at most E_Q = u·a·(5·span + 8) between the `f64`
/// lattice and the exact one, the crossing along the edge by E_Q/sin 60° and its frame's origin by
/// E_Q; the landing's arithmetic adds 14u·a, the time's three roundings and its integers' 4u·t.
fn bounds(t: &TriangularFlights, span: f64, time: f64) -> (f64, f64) {
    let sin60 = 3f64.sqrt() / 2.0;
    let eq = U * t.a * (5.0 * span + 8.0);
    let position = eq * (1.0 + 1.0 / sin60) + 14.0 * U * t.a;
    let timing = (eq + 14.0 * U * t.a) / sin60 + 4.0 * U * time.abs();
    (position, timing)
}

/// The triangular jumps of an audit.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TriangularJumpSummary {
    /// Jumps replayed.
    pub audited: u64,
    /// Jumps outside the model.
    pub outside: u64,
    /// Trap crossings the reference walked, in all.
    pub crossings: u64,
    /// The longest jump, in crossings.
    pub longest: u64,
    /// Time error over its bound.
    pub time_error_over_bound: LogHistogram,
    /// Landing-point error over its bound.
    pub position_error_over_bound: LogHistogram,
    /// Every jump outside the model (at most 1000 kept): the pre-jump state (x, y, vx, vy) as
    /// IEEE bit patterns, and the verdict.
    pub outside_jumps: Vec<([u64; 4], TriangularJumpCheck)>,
}

impl TriangularJumpSummary {
    /// Counts one replayed jump of the pre-jump flight `f`.
    pub fn add(&mut self, f: &Flight<f64>, c: &TriangularJumpCheck) {
        self.audited += 1;
        self.crossings += c.crossings;
        self.longest = self.longest.max(c.crossings);
        self.time_error_over_bound.add(c.time_error / c.time_bound);
        self.position_error_over_bound
            .add(c.position_error / c.position_bound);
        if !c.in_model {
            self.outside += 1;
            if self.outside_jumps.len() < 1000 {
                let bits = [f.pos.x, f.pos.y, f.vel.x, f.vel.y].map(f64::to_bits);
                self.outside_jumps.push((bits, c.clone()));
            }
        }
    }

    /// Adds another summary.
    pub fn merge(&mut self, o: &TriangularJumpSummary) {
        self.audited += o.audited;
        self.outside += o.outside;
        self.crossings += o.crossings;
        self.longest = self.longest.max(o.longest);
        self.time_error_over_bound.merge(&o.time_error_over_bound);
        self.position_error_over_bound
            .merge(&o.position_error_over_bound);
        self.outside_jumps.extend(o.outside_jumps.iter().cloned());
        self.outside_jumps.truncate(1000);
    }
}
