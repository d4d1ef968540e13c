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

use crate::Error;
use crate::kernel::flight::EventKind;
use crate::kernel::thermostat::cell::ThermoEvent;
use crate::numbers::real::Real;
use crate::scenes::lattice::{LatticeState, TriangularLattice};
use crate::scenes::thermostat::CellFields;

use super::super::{FloorTimes, median};

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
    /// The full search's time on the tape (each event found and carried out) and the winner
    /// alone's.
    #[serde(flatten)]
    pub times: FloorTimes,
    /// The winner-only search's nanoseconds per collision, one a repetition.
    pub samples: Vec<f64>,
    /// The full search's on the tape, one a repetition.
    pub full_samples: Vec<f64>,
    /// The median over repetitions of the floor's rate over the straight flights' per thread,
    /// timed in the same repetition: the best thermostat over straight ratio this kernel's
    /// certificates allow.
    pub floor_over_straight: f64,
}

/// The tape of the floor and its timings, one pair a repetition of the run.
pub(super) struct Tape<T: Real> {
    entries: Vec<Entry<T>>,
    collisions: u64,
    identical: u64,
    /// Seconds of each full pass over the tape, and of each winner-only pass.
    full: Vec<f64>,
    floor: Vec<f64>,
}

/// An event of the tape: the state before it and the candidate the full search found.
type Entry<T> = (LatticeState<T>, EventKind);

impl<T: Real> Tape<T> {
    /// The thermostatted walk from `start` up to `collisions` collisions (at most
    /// [`MAX_TAPE_COLLISIONS`]), each event's state before it and its candidate, and how many of
    /// its events the winner alone finds as the full search does.
    pub fn record(
        lat: &TriangularLattice<T>,
        fields: &CellFields<T>,
        start: LatticeState<T>,
        collisions: u64,
    ) -> Result<Self, Error> {
        let collisions = collisions.clamp(1, MAX_TAPE_COLLISIONS);
        let (mut s, mut entries, mut made, mut identical) = (start, Vec::new(), 0, 0);
        while made < collisions {
            // The walk's own event (as `step_thermostat` finds and carries it out), then the
            // winner alone from the same state.
            let ev = search(lat, fields, &s, None).ok_or_else(no_event)?;
            identical += (search(lat, fields, &s, Some(ev.kind)).as_ref() == Some(&ev)) as u64;
            made += matches!(ev.kind, EventKind::Collision(_)) as u64;
            entries.push((s.clone(), ev.kind));
            lat.apply_thermostat(&mut s, &ev);
        }
        Ok(Tape {
            entries,
            collisions,
            identical,
            full: Vec::new(),
            floor: Vec::new(),
        })
    }

    /// One repetition: the full search over the tape, then the winner alone.
    pub fn time(
        &mut self,
        lat: &TriangularLattice<T>,
        fields: &CellFields<T>,
    ) -> Result<(), Error> {
        self.full.push(pass(lat, fields, &self.entries, false)?);
        self.floor.push(pass(lat, fields, &self.entries, true)?);
        Ok(())
    }

    /// The floor, beside the straight flights' rate per thread of each repetition, `straight`
    /// (timed in the same repetitions).
    pub fn result(&self, straight: &[f64]) -> ThermostatFloor {
        let per = |secs: &[f64]| -> Vec<f64> {
            secs.iter()
                .map(|t| 1e9 * t / self.collisions as f64)
                .collect()
        };
        let (full, floor) = (per(&self.full), per(&self.floor));
        let over: Vec<f64> = floor
            .iter()
            .zip(straight)
            .map(|(f, s)| 1e9 / f / s)
            .collect();
        ThermostatFloor {
            events: self.entries.len() as u64,
            collisions: self.collisions,
            identical: self.identical,
            times: FloorTimes::of(&full, &floor),
            floor_over_straight: median(&over),
            samples: floor,
            full_samples: full,
        }
    }
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
        let ev = search(lat, fields, s, winner.then_some(*kind)).ok_or_else(no_event)?;
        let mut after = s.clone();
        lat.apply_thermostat(&mut after, &ev);
        std::hint::black_box(&after);
    }
    Ok(t0.elapsed().as_secs_f64())
}

/// A flight of the tape without a next event (a creeping slide along a disk, of measure zero).
fn no_event() -> Error {
    Error::Failed("a thermostatted flight of the tape has no next event".into())
}
