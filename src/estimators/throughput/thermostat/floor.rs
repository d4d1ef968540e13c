//! The thermostat's winner-only floor (`lorentz bench --electric E --oracle-floor`): the events
//! of a tape of the thermostatted walk found again, once by the full search over every candidate
//! and once given the candidate it found ([`ConvexCell::next_event_thermostat_among`] of that one
//! alone), each carried out, in turns on one thread. The winner-only search still certifies that
//! contact — its march from t = 0, its closed-form point, its Taylor steps, its jets and the
//! event's point — so its time is what no way of ruling out the other candidates in advance can
//! beat with this kernel's certificates, on this CPU (`proofs-notes/thermostat-flight.md`,
//! "Cost").
//!
//! [`ConvexCell::next_event_thermostat_among`]: crate::kernel::cell::ConvexCell::next_event_thermostat_among

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::{ElectricBenchConfig, scene};
use crate::Error;
use crate::kernel::flight::EventKind;
use crate::kernel::thermostat::cell::ThermoEvent;
use crate::numbers::precision::AtPrecision;
use crate::numbers::real::Real;
use crate::scenes::lattice::{LatticeState, TriangularLattice};
use crate::scenes::thermostat::CellFields;

use super::super::{median, starts};

/// The longest tape, in collisions (its states are kept in memory).
pub const MAX_TAPE_COLLISIONS: u64 = 200_000;

/// The thermostat's winner-only floor beside its full search, on one tape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ThermostatFloor {
    /// Events on the tape: the thermostatted walk from the first thread's start, recorded.
    pub events: u64,
    /// Collisions among them (the run's collisions per thread, at most [`MAX_TAPE_COLLISIONS`]).
    pub collisions: u64,
    /// Events the winner-only search finds as the full one does: the same candidate, time and
    /// flight point (the march's points can differ where the others' certificates placed them).
    pub identical: u64,
    /// The full search's median nanoseconds per collision on the tape (found and carried out).
    pub full_ns_per_collision: f64,
    /// The winner-only search's.
    pub floor_ns_per_collision: f64,
    /// Its collisions per second, 10⁹ over the line above.
    pub floor_collisions_per_second: f64,
    /// The median over repetitions of the winner-only time over the full one.
    pub paired_ratio: f64,
    /// The floor's rate over the straight flights': the run's paired ratio (thermostat over
    /// straight) over this one (floor over full time), each a median of ratios of runs made in
    /// turns — the best thermostat over straight ratio this kernel's certificates allow.
    pub floor_over_straight: f64,
}

impl ThermostatFloor {
    /// With the run's median paired ratio of the thermostat's rate over the straight flights'.
    pub(super) fn beside(mut self, thermostat_over_straight: f64) -> Self {
        self.floor_over_straight = thermostat_over_straight / self.paired_ratio;
        self
    }
}

/// The floor's tape and timings at one precision.
pub(super) struct Floor<'a> {
    pub cfg: &'a ElectricBenchConfig,
    pub w: f64,
}

/// An event of the tape: the state before it and the candidate the full search found.
type Entry<T> = (LatticeState<T>, EventKind);

impl AtPrecision for Floor<'_> {
    type Output = Result<ThermostatFloor, Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Self::Output {
        let s = &self.cfg.straight;
        let (trap64, lat, fields) = scene::<T>(self.cfg, self.w, ctx)?;
        let start = starts::<T>(ctx, &trap64, s.seed, 1, 1).remove(0).remove(0);
        let collisions = s.collisions_per_thread.clamp(1, MAX_TAPE_COLLISIONS);
        let tape = record(&lat, &fields, start, collisions)?;
        let identical = tape
            .iter()
            .filter(|(st, kind)| {
                search(&lat, &fields, st, None) == search(&lat, &fields, st, Some(*kind))
            })
            .count() as u64;
        let (mut full, mut floor, mut ratio) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..s.repetitions {
            let all = pass(&lat, &fields, &tape, false)?;
            let only = pass(&lat, &fields, &tape, true)?;
            full.push(1e9 * all / collisions as f64);
            floor.push(1e9 * only / collisions as f64);
            ratio.push(only / all);
        }
        let floor_ns = median(&floor);
        Ok(ThermostatFloor {
            events: tape.len() as u64,
            collisions,
            identical,
            full_ns_per_collision: median(&full),
            floor_ns_per_collision: floor_ns,
            floor_collisions_per_second: 1e9 / floor_ns,
            paired_ratio: median(&ratio),
            floor_over_straight: f64::NAN,
        })
    }
}

/// The thermostatted walk from `start` up to `collisions` collisions, each event's state before
/// it and its candidate.
fn record<T: Real>(
    lat: &TriangularLattice<T>,
    fields: &CellFields<T>,
    start: LatticeState<T>,
    collisions: u64,
) -> Result<Vec<Entry<T>>, Error> {
    let (mut s, mut tape, mut made) = (start, Vec::new(), 0);
    while made < collisions {
        let before = s.clone();
        let kind = lat.step_thermostat(&mut s, fields)?.kind;
        made += matches!(kind, EventKind::Collision(_)) as u64;
        tape.push((before, kind));
    }
    Ok(tape)
}

/// The next event from the state `s`: the full search, or among `only` alone.
fn search<T: Real>(
    lat: &TriangularLattice<T>,
    fields: &CellFields<T>,
    s: &LatticeState<T>,
    only: Option<EventKind>,
) -> Option<ThermoEvent<T>> {
    let th = fields.in_cell(&s.cell);
    match only {
        None => lat.cell().next_event_thermostat(&s.flight, th),
        Some(kind) => lat
            .cell()
            .next_event_thermostat_among(&s.flight, th, std::iter::once(kind)),
    }
}

/// Seconds to find and carry out every event of the tape, by the full search or (`winner`)
/// given each event's candidate.
fn pass<T: Real>(
    lat: &TriangularLattice<T>,
    fields: &CellFields<T>,
    tape: &[Entry<T>],
    winner: bool,
) -> Result<f64, Error> {
    let t0 = Instant::now();
    for (s, kind) in tape {
        let ev = search(lat, fields, s, winner.then_some(*kind)).ok_or_else(|| {
            Error::Failed("a thermostatted flight of the tape has no next event".into())
        })?;
        let mut after = s.clone();
        lat.apply_thermostat(&mut after, &ev);
        std::hint::black_box(&after);
    }
    Ok(t0.elapsed().as_secs_f64())
}
