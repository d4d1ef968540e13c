//! The next event of a thermostatted flight in a cell: one march for all its candidates.
//!
//! Every disk and edge is certified at the same flight points ([`isolate::verdict`]), so that one
//! closed-form point — three correctly rounded calls — serves the jets of all of them, where a
//! march per candidate formed points of its own (`proofs-notes/thermostat-flight.md`, "One march
//! for all candidates"). The march goes to the earliest time up to which some candidate is not yet
//! certified free; a candidate leaves it when it is certified free up to the earliest contact found
//! so far (the horizon), or when its contact is found. Ties go to collisions before crossings, then
//! to the lower label (the straight kernel's rule). A candidate starts certified free up to its
//! screen's time ([`super::screen`]), so one no contact reaches before the event needs no jet; a
//! point within a Taylor step's reach of the last closed-form point is that step
//! ([`super::Start::step_from`], "Taylor steps" in the note).

use super::contacts::{Candidate, Here};
use super::isolate::{self, MAX_STEPS, Verdict};
use super::{FlightPoint, Start};
use crate::kernel::flight::EventKind;
use crate::numbers::real::Real;

/// One candidate of the search: its contact function, its march's step hint, and the time up
/// to which it is certified free.
pub(super) struct Slot<'s, 'a, T: Real> {
    kind: EventKind,
    contact: Candidate<'s, 'a, T>,
    hint: T,
    free: T,
    live: bool,
    /// The march point whose jet it has seen last.
    seen: Option<usize>,
}

/// A contact found: its time, its candidate, and where its Taylor step left from — the flight
/// point of the march at a and the step s, the contact being at a + s (none where it is the
/// march's own point).
pub(super) struct Found<T> {
    /// The contact's time.
    pub time: T,
    /// Its candidate.
    pub kind: EventKind,
    /// The march point a and the step s to the contact.
    pub from: Option<(FlightPoint<T>, T)>,
}

/// The earliest contact found so far.
type Best<T> = Option<Found<T>>;

/// The order of simultaneous events: collisions before crossings, then the lower label.
fn rank(kind: EventKind) -> (bool, u8) {
    match kind {
        EventKind::Collision(m) => (false, m),
        EventKind::Crossing(k) => (true, k),
    }
}

/// Keeps the contact of `kind` at `t`, reached from `from`, if it comes before the best so far.
fn offer<T: Real>(
    best: &mut Best<T>,
    time: T,
    kind: EventKind,
    from: impl FnOnce() -> Option<(FlightPoint<T>, T)>,
) {
    let first = match best {
        None => true,
        Some(b) => time < b.time || (time == b.time && rank(kind) < rank(b.kind)),
    };
    if first {
        let from = from();
        *best = Some(Found { time, kind, from });
    }
}

/// The time no march needs to pass: the earliest contact so far, else the exit bound.
fn horizon<T: Real>(best: &Best<T>, exit: &T) -> T {
    best.as_ref().map_or(exit, |b| &b.time).clone()
}

impl<'s, 'a, T: Real> Slot<'s, 'a, T> {
    /// The candidate `kind` with its contact function, certified free up to `free` ≥ 0 (the
    /// screen's time, [`super::screen`]; 0 where the march certifies it from its start).
    pub fn new(kind: EventKind, contact: Candidate<'s, 'a, T>, free: f64) -> Self {
        let ctx = contact.start().thermostat().strength.ctx();
        Slot {
            kind,
            contact,
            hint: T::one(ctx),
            free: T::from_f64(ctx, free).anchored(),
            live: true,
            seen: None,
        }
    }

    /// The candidate's verdict at the flight point `here` (the start if `first`) with the
    /// horizon `horizon`: its contact offered to `best`, or its certificate extended. `false`
    /// for the creeping limit on a disk (no next event).
    fn visit(&mut self, here: &Here<'_, T>, first: bool, horizon: &T, best: &mut Best<T>) -> bool {
        let a = here.t;
        let identity = first && self.contact.identity();
        let j = self.contact.jet_on(here);
        let remaining = horizon.clone() - a;
        match isolate::verdict(&self.contact, &j, identity, &remaining, &mut self.hint) {
            Verdict::Root(s) => {
                self.live = false;
                let t = a.clone() + &s;
                offer(best, t, self.kind, || Some((here.at.clone(), s)));
            }
            Verdict::Creeps => {
                self.live = false;
                if matches!(self.kind, EventKind::Collision(_)) {
                    return false;
                }
                // Entered by this edge and turning back out of the cell: an exit now.
                offer(best, a.clone(), self.kind, || None);
            }
            Verdict::Clear => self.live = false,
            Verdict::Free(s) => {
                let until = a.clone() + &s;
                // A step below the point's resolution: the march stands at the root.
                if T::freely(|| until <= *a) {
                    self.live = false;
                    offer(best, a.clone(), self.kind, || None);
                } else if T::freely(|| until > self.free) {
                    // Any certified point serves: [0, free] and [a, a + s] are both free and
                    // a ≤ free.
                    self.free = until.anchored();
                }
            }
        }
        true
    }
}

/// The live candidate certified free for the shortest time, if that is before `horizon`
/// (those certified free up to it leave the march).
fn least_free<T: Real>(slots: &mut [Slot<'_, '_, T>], horizon: &T) -> Option<usize> {
    let mut least: Option<usize> = None;
    for k in 0..slots.len() {
        if !slots[k].live {
            continue;
        }
        if T::freely(|| slots[k].free >= *horizon) {
            slots[k].live = false;
        } else if least.is_none_or(|l| T::freely(|| slots[k].free < slots[l].free)) {
            least = Some(k);
        }
    }
    least
}

/// The earliest contact of the flight `start` among `slots` before the exit bound `exit`, and its
/// time: one march from t = 0 whose next point is where the least certified candidate's
/// certificate ends. At each point a candidate's jet is formed only if its certificate ends
/// first (all of them at the start), so that a point is formed only where a certificate from
/// the point before cannot reach further. `None` for the creeping limit on a disk, or where no
/// candidate has a contact before `exit`.
pub(super) fn earliest_event<T: Real>(
    start: &Start<'_, T>,
    slots: &mut [Slot<'_, '_, T>],
    exit: &T,
) -> Option<Found<T>> {
    let mut best: Best<T> = None;
    let mut a = T::zero(exit.ctx());
    // The last point formed in closed form and its time (none: the origin): a later point within
    // a Taylor step's reach of it is that step, never a step from a step (`Start::step_from`).
    let mut base: Option<(T, FlightPoint<T>)> = None;
    for n in 0..MAX_STEPS {
        let owned;
        let at = if n == 0 {
            start.origin()
        } else {
            let stepped = match &base {
                Some((t0, p0)) => start.step_from(p0, &(a.clone() - t0)),
                None => start.step_from(start.origin(), &a),
            };
            owned = stepped.unwrap_or_else(|| {
                let p = start.at(&a);
                base = Some((a.clone(), p.clone()));
                p
            });
            &owned
        };
        let here = Here::new(start, &a, at);
        loop {
            let h = horizon(&best, exit);
            let Some(k) = least_free(slots, &h) else {
                return best;
            };
            let slot = &mut slots[k];
            if slot.seen == Some(n) {
                a = slot.free.clone();
                break;
            }
            slot.seen = Some(n);
            if !slot.visit(&here, n == 0, &h, &mut best) {
                return None;
            }
        }
    }
    // A march that has not ended stands at a grazing approach it can neither certify nor
    // refuse: the candidates held at `a` take their contact there (as `isolate::earliest`).
    for slot in slots.iter().filter(|s| s.live && s.free == a) {
        offer(&mut best, a.clone(), slot.kind, || None);
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Offers every candidate at one time in `order` and returns the one kept.
    fn kept(order: &[EventKind]) -> EventKind {
        let mut best: Best<f64> = None;
        for &kind in order {
            offer(&mut best, 0.5, kind, || None);
        }
        best.unwrap().kind
    }

    /// Simultaneous contacts go to collisions before crossings, then to the lower label, in
    /// whatever order the march finds them (an earlier time always wins).
    #[test]
    fn simultaneous_contacts_go_to_the_collision_then_the_lower_label() {
        use EventKind::{Collision, Crossing};
        let all = [
            Crossing(0),
            Crossing(2),
            Collision(1),
            Collision(0),
            Crossing(1),
        ];
        let mut order = all;
        for turn in 0..all.len() {
            order.rotate_left(1);
            assert_eq!(kept(&order), Collision(0), "turn {turn}: {order:?}");
            let mut back = order;
            back.reverse();
            assert_eq!(kept(&back), Collision(0), "turn {turn}, reversed: {back:?}");
        }
        assert_eq!(kept(&[Crossing(2), Crossing(1)]), Crossing(1));
        let mut best: Best<f64> = None;
        offer(&mut best, 0.5, Collision(0), || None);
        offer(&mut best, 0.25, Crossing(2), || None);
        assert_eq!(best.unwrap().kind, Crossing(2), "an earlier crossing wins");
    }
}
