//! The generic cell kernel under the thermostat: the next event of a thermostatted flight among a
//! cell's disks and edges, every contact certified by one march for all of them (`search`, on the
//! certificates of [`super::isolate`]), and its execution.
//!
//! The rules are the straight kernel's ([`crate::kernel::cell`]): ties go to collisions before
//! crossings, then to the lower label; the disk left and the edge entered by are excluded by
//! identity, with the meaning a curved flight needs (as an arc's, [`crate::kernel::field`]): the
//! obstacle the particle is *on*, whose contact is a return. The march goes up to a horizon by
//! which the flight has certainly left the cell ([`exit_bound`]), then up to the earliest contact
//! found.
//!
//! Executing an event moves to the flight's point at the event, then reflects specularly at a
//! disk or maps into the neighbour's frame at an edge, and ends with v ← v/|v|
//! (`proofs-notes/energy.md`). A point reflection turns position, velocity and field by π: the
//! thermostat is the same in every cell only if the cells are translates; a point-reflected
//! neighbour sees −E, which the caller carries ([`Flipped`]).

use super::contacts::Candidate;
use super::isolate::{Contact, Jet};
use super::screen::Tube;
use super::search::{self, Slot};
use super::{FlightPoint, Start, Thermostat};
use crate::kernel::cell::ConvexCell;
use crate::kernel::flight::{EventKind, Flight};
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;

/// Whether the current cell's frame is point-reflected with respect to the field's: the field
/// is −E in it (a crossing through a [`crate::kernel::cell::EdgeMap::PointReflection`] flips it).
pub type Flipped = bool;

/// The next event of a thermostatted flight.
#[derive(Debug, Clone, PartialEq)]
pub struct ThermoEvent<T> {
    /// Collision or crossing, with its label.
    pub kind: EventKind,
    /// The flight time to it.
    pub time: T,
    /// The flight there: displacement, velocity on arrival, ξ along the field.
    pub at: FlightPoint<T>,
}

/// A time by which the flight from `p` with velocity `v` has left the cell: |X(t)| ≥ ξ(t) and
/// e^{εξ} = cosh εt + c sinh εt ≥ (p/2)e^{εt} (p = 1 + c), so |X| > L, the largest distance from
/// `p` to a corner, once t > L + ln(2/p)/ε (t > L where p = 0: then ξ = −t).
pub fn exit_bound<T: Real>(cell: &ConvexCell<T>, p: &Vec2<T>, start: &Start<'_, T>) -> T {
    let ctx = p.x.ctx();
    let far = cell
        .corners
        .iter()
        .map(|c| c.sub(p).norm2())
        .fold(T::zero(ctx), |a, b| if b > a { b } else { a })
        .sqrt()
        .scale(1.0 + 1.0 / 1024.0);
    let lag = if start.p.gt0() {
        T::from_f64(ctx, ln_above(2.0 / start.p.to_f64())) / &start.thermostat().strength
    } else {
        T::zero(ctx)
    };
    (far + &lag.scale(1.0 + 1.0 / 1024.0)).add_f64(1e-9)
}

/// An upper bound on ln y for y ≥ 1 by arithmetic on its binary exponent: y = 2ᵏm with
/// m ∈ [1, 2) and ln m ≤ m − 1, so ln y ≤ k·ln 2 + m − 1 (ln 2 rounded up), within 1 − ln 2 of
/// ln y (0 below 1). No correctly rounded call for a bound the march only needs to be above the
/// exit.
pub(super) fn ln_above(y: f64) -> f64 {
    if !(y.is_finite() && y >= 1.0) {
        return if y < 1.0 { 0.0 } else { f64::INFINITY };
    }
    let bits = y.to_bits();
    let k = ((bits >> 52) & 0x7ff) as f64 - 1023.0;
    let m = f64::from_bits((bits & ((1u64 << 52) - 1)) | (1023u64 << 52));
    k * 0.693_147_180_559_945_4 + (m - 1.0)
}

impl<T: Real> ConvexCell<T> {
    /// The next event of the flight `f` under the thermostat `th` (expressed in this cell's
    /// frame), or `None`: a particle sliding along the disk it is on (the creeping limit,
    /// [`super::isolate::Found::Creeps`]), or a flight with no contact before its exit bound (a
    /// zero or non-finite velocity).
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::kernel::{flight::{EventKind, Flight}, thermostat::Thermostat, trap::Trap, vec2::Vec2};
    /// let cell = Trap::new(0.1f64).unwrap().cell().clone();
    /// // From the middle of the base gap straight up, the field along +y: the apex disk P₂.
    /// let th = Thermostat { strength: 0.3, dir: Vec2::new(0.0, 1.0) };
    /// let f = Flight::new(Vec2::new(1.05, 0.0), Vec2::new(0.0, 1.0));
    /// assert_eq!(cell.next_event_thermostat(&f, &th).unwrap().kind, EventKind::Collision(2));
    /// ```
    pub fn next_event_thermostat(
        &self,
        f: &Flight<T>,
        th: &Thermostat<T>,
    ) -> Option<ThermoEvent<T>> {
        let kinds = (0..self.edges.len() as u8)
            .map(EventKind::Crossing)
            .chain((0..self.disks.len() as u8).map(EventKind::Collision));
        self.next_event_thermostat_among(f, th, kinds)
    }

    /// [`ConvexCell::next_event_thermostat`] among the candidates `kinds` only (in the order
    /// given; the full search offers the edges, then the disks). Given the one candidate the full
    /// search found, it is the winner-only floor of an event: the certificates of that contact
    /// alone, which no way of ruling out the others in advance can save
    /// (`benches/thermostat.rs`).
    pub fn next_event_thermostat_among(
        &self,
        f: &Flight<T>,
        th: &Thermostat<T>,
        kinds: impl Iterator<Item = EventKind>,
    ) -> Option<ThermoEvent<T>> {
        let start = th.start(&f.vel);
        let exit = exit_bound(self, &f.pos, &start);
        let tube = Tube::new(f, &th.strength, &exit);
        let mut slots: Vec<Slot<'_, '_, T>> = kinds
            .map(|k| {
                Slot::new(
                    k,
                    Candidate::new(self, &start, f, k),
                    tube.free_time(self, f, k),
                )
            })
            .collect();
        let found = search::earliest_event(&start, &mut slots, &exit)?;
        // The Taylor step from the march's last point where its remainder is below the
        // precision, else the closed form at the event's time.
        let at = found
            .from
            .and_then(|(p, s)| start.step_from(&p, &s))
            .unwrap_or_else(|| start.at(&found.time));
        Some(ThermoEvent {
            kind: found.kind,
            time: found.time,
            at,
        })
    }

    /// The contact function of the candidate `kind` along the flight `f` at the time `t`: its
    /// value, slope and curvature with their error bounds (a transversal contact's time is
    /// accurate to about e₀/|F′|, `proofs-notes/thermostat-flight.md`).
    pub fn thermostat_jet(
        &self,
        f: &Flight<T>,
        th: &Thermostat<T>,
        kind: EventKind,
        t: &T,
    ) -> Jet<T> {
        let start = th.start(&f.vel);
        Candidate::new(self, &start, f, kind).jet(t)
    }

    /// Moves along the flight to the event and carries it out, then brings the velocity to unit
    /// speed, v/|v|; returns whether the frame was point-reflected (the field is then −E in the
    /// new cell's frame). The flight's forms take |v| = 1 (`Thermostat::start`), and a reflection
    /// at a point a residual δF off the circle changes the speed² by up to 4δF/r² — 10⁻⁹ at a disk
    /// of radius 10⁻¹⁰, which the Newton factor (3 − |v|²)/2 of the arrival velocity, taken
    /// before the reflection, left in place (`proofs-notes/thermostat-flight.md`).
    pub fn apply_thermostat(&self, f: &mut Flight<T>, ev: &ThermoEvent<T>) -> Flipped {
        let x = Vec2::new(
            f.pos.x.clone() + &ev.at.disp.x,
            f.pos.y.clone() + &ev.at.disp.y,
        );
        let flipped = self.land(f, ev.kind, x, ev.at.vel.clone(), ev.time.gt0(), None);
        let norm = f.vel.norm2().sqrt();
        if norm.gt0() {
            f.vel = Vec2::new(f.vel.x.clone() / &norm, f.vel.y.clone() / &norm);
        }
        flipped
    }
}
