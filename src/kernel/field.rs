//! The generic cell kernel in a uniform magnetic field: the next event of an arc among a cell's
//! disks and edges, and its execution ([`super::arc`] for the contacts).
//!
//! The rules are the straight kernel's ([`super::cell`]) with the chord in place of the time:
//! candidates are offered disks first (by label), then edges (by label), and a later offer wins
//! only when strictly [`earlier`](super::arc::earlier). Exclusion is still by identity, with the meaning an arc needs:
//! the disk left (`excluded_disk`) is the circle the particle is *on*, so its contact is the
//! return along the arc, and likewise the edge entered by. After a crossing the particle is on
//! the disk it left only if it has not moved (a zero chord), so only then does that exclusion
//! carry over.
//!
//! Executing an event: the particle moves by the chord, its velocity becomes the reflection of v
//! in the chord ([`velocity_after`]), or v + ωJx ([`velocity_along`]) at a contact found in the
//! disk's frame (near-concentric circles, [`Arc::contact`]); a collision then reflects it specularly, a crossing maps
//! it into the neighbour's frame (a point reflection turns position and velocity by π and keeps
//! the sense of rotation, so ω is the same in every cell). Every event ends with the Newton factor
//! (3 − |v_in|²)/2 of the incoming speed, as the straight kernel's collisions
//! (`proofs-notes/energy.md`): rounding cannot make the speed drift.
//!
//! The field ω = 0 is not an arc: callers run the straight kernel there, with its own bits.

use super::arc::{Arc, is_zero, velocity_after, velocity_along};
use super::cell::ConvexCell;
use super::flight::{EventKind, Flight};
use super::vec2::Vec2;
use crate::numbers::real::Real;

/// The next event of an arc: what ends it and the chord from the current position to it.
#[derive(Debug, Clone, PartialEq)]
pub struct ArcEvent<T> {
    /// Collision or crossing, with the disk/edge label.
    pub kind: EventKind,
    /// The displacement to the event, in the cell's frame.
    pub chord: Vec2<T>,
    /// The velocity on arrival, before the event acts: the reflection of v in the chord, or
    /// v + ωJx at a contact found in the disk's frame ([`Arc::contact`]).
    pub velocity: Vec2<T>,
}

impl<T: Real> ConvexCell<T> {
    /// The next event of the flight `f` on its arc in the field `w` (≠ 0), or `None` if there is
    /// none: a cyclotron circle inside the cell that meets no disk (a pinned orbit), a particle
    /// sliding along the disk it is on (the measure-zero creeping limit, [`Arc::creeps`]), or a
    /// zero or non-finite velocity.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::kernel::{trap::Trap, flight::EventKind, flight::Flight, vec2::Vec2};
    /// let cell = Trap::new(0.1f64).unwrap().cell().clone();
    /// // From the middle of the base gap straight up, turning left on a radius of 10: the apex
    /// // disk P₂ is still met.
    /// let f = Flight::new(Vec2::new(1.05, 0.0), Vec2::new(0.0, 1.0));
    /// let ev = cell.next_event_in_field(&f, &0.1).unwrap();
    /// assert_eq!(ev.kind, EventKind::Collision(2));
    /// ```
    pub fn next_event_in_field(&self, f: &Flight<T>, w: &T) -> Option<ArcEvent<T>> {
        let (p, v) = (&f.pos, &f.vel);
        let arc = Arc::new(v, w);
        let mut best: Option<(EventKind, Vec2<T>, bool)> = None;
        let mut offer = |chord: Vec2<T>, kind: EventKind, disk_frame: bool| {
            if best.as_ref().is_none_or(|b| arc.earlier(&chord, &b.1)) {
                best = Some((kind, chord, disk_frame));
            }
        };
        for (m, d) in self.disks.iter().enumerate() {
            let m = m as u8;
            let c = &d.centre;
            let (dx, dy) = (p.x.clone() - &c.x, p.y.clone() - &c.y);
            let on = f.excluded_disk == Some(m);
            if on && arc.creeps(&dx, &dy) {
                return None;
            }
            if let Some(c) = arc.contact(dx, dy, d.radius(), d.radius2(), on) {
                offer(c.chord, EventKind::Collision(m), c.disk_frame);
            }
        }
        for (k, e) in self.edges.iter().enumerate() {
            let k = k as u8;
            let sigma = e.normal.dot(p) - &e.offset;
            let entered = f.excluded_edge == Some(k);
            if let Some(x) = arc.line(&e.normal, sigma, entered) {
                offer(x, EventKind::Crossing(k), false);
            }
        }
        best.map(|(kind, chord, disk_frame)| {
            let velocity = if disk_frame {
                velocity_along(v, &chord, w)
            } else {
                velocity_after(v, &chord)
            };
            ArcEvent {
                kind,
                chord,
                velocity,
            }
        })
    }

    /// Moves along the arc to the event and carries it out (see the module documentation).
    pub fn apply_in_field(&self, f: &mut Flight<T>, ev: &ArcEvent<T>) {
        let newton = (-f.vel.norm2()).add_f64(3.0).scale(0.5);
        let x = Vec2::new(f.pos.x.clone() + &ev.chord.x, f.pos.y.clone() + &ev.chord.y);
        let moved = !is_zero(&ev.chord);
        self.land(f, ev.kind, x, ev.velocity.clone(), moved, Some(&newton));
    }

    /// Carries out the event `kind` of a curved flight that reached `x` with the velocity `v`: a
    /// collision reflects specularly, a crossing maps into the neighbour's frame (the disk left
    /// carried over only if the particle has not `moved`); then the speed is multiplied by
    /// `newton` if given. Returns whether the frame was point-reflected. Shared by arcs and
    /// thermostatted flights.
    pub fn land(
        &self,
        f: &mut Flight<T>,
        kind: EventKind,
        x: Vec2<T>,
        mut v: Vec2<T>,
        moved: bool,
        newton: Option<&T>,
    ) -> bool {
        let flipped = match kind {
            EventKind::Collision(m) => {
                self.disks[m as usize].reflect(&mut v, &x);
                f.pos = x;
                f.excluded_disk = Some(m);
                f.excluded_edge = None;
                false
            }
            EventKind::Crossing(k) => {
                let e = &self.edges[k as usize];
                f.pos = e.map.carry(&x, &mut v);
                f.excluded_disk = if moved {
                    None
                } else {
                    f.excluded_disk.and_then(|m| e.disks_after[m as usize])
                };
                f.excluded_edge = Some(e.entered);
                e.flips()
            }
        };
        if let Some(k) = newton {
            v.x *= k;
            v.y *= k;
        }
        f.vel = v;
        flipped
    }
}
