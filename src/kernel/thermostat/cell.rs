//! The generic cell kernel under the thermostat: the next event of a thermostatted flight among a
//! cell's disks and edges, each contact certified by [`isolate::earliest`], and its execution.
//!
//! The rules are the straight kernel's ([`crate::kernel::cell`]): ties go to the lower disk label,
//! then collisions before crossings, then the lower edge label; the disk left and the edge entered
//! by are excluded by identity, with the meaning a curved flight needs (as an arc's,
//! [`crate::kernel::field`]): the obstacle the particle is *on*, whose contact is a return. The
//! edges are searched up to a horizon by which the flight has certainly left the cell
//! ([`exit_bound`]), the disks up to the earliest crossing found.
//!
//! Executing an event moves to the flight's point at the event, then reflects specularly at a
//! disk or maps into the neighbour's frame at an edge, and ends with the Newton factor
//! (3 − |v|²)/2 (`proofs-notes/energy.md`). A point reflection turns position, velocity and field
//! by π: the thermostat is the same in every cell only if the cells are translates; a
//! point-reflected neighbour sees −E, which the caller carries ([`Flipped`]).

use super::isolate::{self, Contact, Found, Jet, Lean};
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

/// The error bounds (δX, δv) of a flight point at `t` ([`Start::error`]), δX widened by
/// 8u(`offset` + 1) for forming the offset from the obstacle.
fn flight_error<T: Real>(start: &Start<'_, T>, t: &T, offset: f64) -> (f64, f64) {
    let (dx, dv) = start.error(t);
    (dx + 8.0 * T::unit_roundoff(t.ctx()) * (offset + 1.0), dv)
}

/// |sin θ| of the flight point `at` (time `t`) against the exact flight's, rounded up by the
/// velocity's error δv and the cross product's rounding, and whether cos θ ≥ 0 beyond them.
fn lean_at<T: Real>(start: &Start<'_, T>, t: &T, at: &FlightPoint<T>) -> Lean {
    let dir = &start.thermostat().dir;
    let slack = start.error(t).1 + 4.0 * T::unit_roundoff(t.ctx());
    Lean {
        sin: dir.cross(&at.vel).to_f64().abs() + slack,
        relaxing: dir.dot(&at.vel).to_f64() > slack,
    }
}

/// |X − c|² − r² along the flight from d = p − c.
struct DiskContact<'s, 'a, T: Real> {
    start: &'s Start<'a, T>,
    d: Vec2<T>,
    r2: T,
    identity: bool,
    /// |d|, r² and ε in `f64`: the error model's inputs that do not change along the flight.
    model: [f64; 3],
}

impl<T: Real> DiskContact<'_, '_, T> {
    /// |F‴| = |2(X − c)·v̈| ≤ 2(ρ + h)ε²|sin θ| over [t, t + h].
    fn third(&self, jet: &Jet<T>, h: &T) -> T {
        let eps = &self.start.thermostat().strength;
        let lean = jet.lean.over(self.model[2], h.to_f64());
        (jet.reach.clone() + h) * &eps.square().scale((2.0 + 1.0 / 65536.0) * lean)
    }

    /// The jet at `t`, the flight being at `at` there.
    fn jet_on(&self, t: &T, at: &FlightPoint<T>) -> Jet<T> {
        let ctx = t.ctx();
        let dd = Vec2::new(self.d.x.clone() + &at.disp.x, self.d.y.clone() + &at.disp.y);
        let reach = dd.norm2().sqrt();
        let f1 = dd.dot(&at.vel).scale(2.0);
        let f2 = dd.dot(&at.acc).scale(2.0).add_f64(2.0);
        if self.identity && !t.gt0() {
            let zero = T::zero(ctx);
            let err = [zero.clone(), zero.clone(), zero.clone()];
            return Jet {
                f: zero,
                f1,
                f2,
                err,
                reach,
                lean: lean_at(self.start, t, at),
            };
        }
        let [d, r2, eps] = self.model;
        let (dx, dv) = flight_error(self.start, t, d);
        let rho = reach.to_f64();
        let u = T::unit_roundoff(ctx);
        let e = [
            2.0 * rho * dx + dx * dx + 8.0 * u * (rho * rho + r2),
            2.0 * dx + 2.0 * rho * dv + 8.0 * u * rho,
            2.0 * eps * (dx + 2.0 * rho * dv) + 8.0 * u * (1.0 + eps * rho),
        ];
        Jet {
            f: dd.norm2() - &self.r2,
            f1,
            f2,
            err: e.map(|x| T::from_f64(ctx, x)),
            reach,
            lean: lean_at(self.start, t, at),
        }
    }
}

/// σ + n·X: the signed distance to an edge along the flight.
struct EdgeContact<'s, 'a, T: Real> {
    start: &'s Start<'a, T>,
    normal: &'s Vec2<T>,
    sigma: T,
    scale: f64,
    identity: bool,
}

impl<T: Real> EdgeContact<'_, '_, T> {
    /// |F‴| = |n·v̈| ≤ ε²|sin θ| over [t, t + h].
    fn third(&self, jet: &Jet<T>, h: &T) -> T {
        let eps = &self.start.thermostat().strength;
        let lean = jet.lean.over(eps.to_f64(), h.to_f64());
        eps.square().scale((1.0 + 1.0 / 65536.0) * lean)
    }

    /// The jet at `t`, the flight being at `at` there.
    fn jet_on(&self, t: &T, at: &FlightPoint<T>) -> Jet<T> {
        let ctx = t.ctx();
        let n = self.normal;
        let f1 = n.dot(&at.vel);
        let f2 = n.dot(&at.acc);
        let zero = T::zero(ctx);
        if self.identity && !t.gt0() {
            let err = [zero.clone(), zero.clone(), zero.clone()];
            return Jet {
                f: zero.clone(),
                f1,
                f2,
                err,
                reach: zero,
                lean: lean_at(self.start, t, at),
            };
        }
        let nx = n.dot(&at.disp);
        let (dx, dv) = flight_error(self.start, t, self.scale);
        let eps = self.start.thermostat().strength.to_f64();
        let u = T::unit_roundoff(ctx);
        let e = [
            dx + 4.0 * u * (self.scale + nx.to_f64().abs()),
            dv + 4.0 * u,
            2.0 * eps * dv + 4.0 * u * eps,
        ];
        Jet {
            f: self.sigma.clone() + &nx,
            f1,
            f2,
            err: e.map(|x| T::from_f64(ctx, x)),
            reach: zero,
            lean: lean_at(self.start, t, at),
        }
    }
}

/// A disk's or an edge's contact function.
enum Candidate<'s, 'a, T: Real> {
    Disk(DiskContact<'s, 'a, T>),
    Edge(EdgeContact<'s, 'a, T>),
}

impl<T: Real> Candidate<'_, '_, T> {
    fn identity(&self) -> bool {
        match self {
            Candidate::Disk(c) => c.identity,
            Candidate::Edge(c) => c.identity,
        }
    }

    fn start(&self) -> &Start<'_, T> {
        match self {
            Candidate::Disk(c) => c.start,
            Candidate::Edge(c) => c.start,
        }
    }

    /// The jet at `t`, the flight being at `at` there.
    fn jet_on(&self, t: &T, at: &FlightPoint<T>) -> Jet<T> {
        match self {
            Candidate::Disk(c) => c.jet_on(t, at),
            Candidate::Edge(c) => c.jet_on(t, at),
        }
    }
}

impl<T: Real> Contact<T> for Candidate<'_, '_, T> {
    fn jet(&self, t: &T) -> Jet<T> {
        self.jet_on(t, &self.start().at(t))
    }

    fn start_jet(&self, ctx: T::Ctx) -> Jet<T> {
        self.jet_on(&T::zero(ctx), self.start().origin())
    }

    fn third(&self, jet: &Jet<T>, h: &T) -> T {
        match self {
            Candidate::Disk(c) => c.third(jet, h),
            Candidate::Edge(c) => c.third(jet, h),
        }
    }
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
        (T::from_f64(ctx, 2.0) / &start.p).ln() / &start.thermostat().strength
    } else {
        T::zero(ctx)
    };
    (far + &lag.scale(1.0 + 1.0 / 1024.0)).add_f64(1e-9)
}

/// Edges a cell's order holds on the stack (a cell with more keeps the rest in a `Vec`).
const STACK_EDGES: usize = 8;

/// The edges of a cell sorted by (straight crossing time, label): on the stack, one insertion
/// per edge, for a cell of at most [`STACK_EDGES`] edges (no allocation per event), else sorted in
/// `more`. Labels are distinct, so both give the one order of that total order.
#[derive(Default)]
struct EdgeOrder {
    stack: [(f64, u8); STACK_EDGES],
    len: usize,
    more: Vec<(f64, u8)>,
}

impl EdgeOrder {
    /// Inserts an edge in order (at most [`STACK_EDGES`] of them).
    fn insert(&mut self, time: f64, k: u8) {
        let before = |a: &&(f64, u8)| a.0.total_cmp(&time).then(a.1.cmp(&k)).is_lt();
        let at = self.stack[..self.len].iter().take_while(before).count();
        self.stack.copy_within(at..self.len, at + 1);
        self.stack[at] = (time, k);
        self.len += 1;
    }

    fn labels(&self) -> impl Iterator<Item = u8> + '_ {
        self.stack[..self.len].iter().chain(&self.more).map(|a| a.1)
    }
}

impl<T: Real> ConvexCell<T> {
    /// The next event of the flight `f` under the thermostat `th` (expressed in this cell's
    /// frame), or `None`: a particle sliding along the disk it is on (the creeping limit,
    /// [`Found::Creeps`]), or a flight no edge of which is found before its exit bound (a zero or
    /// non-finite velocity).
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
        let start = th.start(&f.vel);
        let mut horizon = exit_bound(self, &f.pos, &start);
        let mut best: Option<EventKind> = None;
        for k in self.edge_order(f).labels() {
            let contact = self.candidate(&start, f, EventKind::Crossing(k));
            let t = match isolate::earliest(&contact, contact.identity(), &horizon) {
                Found::Root(t) => t,
                Found::Creeps => T::zero(horizon.ctx()),
                Found::Clear => continue,
            };
            let first = match best {
                Some(EventKind::Crossing(b)) => t < horizon || (t == horizon && k < b),
                _ => true,
            };
            if first {
                best = Some(EventKind::Crossing(k));
                horizon = t;
            }
        }
        best?;
        for m in 0..self.disks.len() as u8 {
            let contact = self.candidate(&start, f, EventKind::Collision(m));
            match isolate::earliest(&contact, contact.identity(), &horizon) {
                Found::Root(t) => {
                    let over_edge = matches!(best, Some(EventKind::Crossing(_)));
                    if t < horizon || (over_edge && t <= horizon) {
                        best = Some(EventKind::Collision(m));
                        horizon = t;
                    }
                }
                Found::Creeps => return None,
                Found::Clear => {}
            }
        }
        let at = start.at(&horizon);
        best.map(|kind| ThermoEvent {
            kind,
            time: horizon,
            at,
        })
    }

    /// The edges in the order the straight flight from `f` crosses their lines (edges it moves
    /// away from last, then by label): the search of the earliest crossing then meets the exit
    /// first, and the other edges are searched only up to it. The order changes no certificate
    /// (ties still go to the lower label); it is read from the `f64` values, so it is the same
    /// order in `f64` and MPFR-53.
    fn edge_order(&self, f: &Flight<T>) -> EdgeOrder {
        let time = |k: u8| {
            let e = &self.edges[k as usize];
            let (nv, sigma) = (
                e.normal.dot(&f.vel).to_f64(),
                e.normal.dot(&f.pos) - &e.offset,
            );
            if nv < 0.0 {
                sigma.to_f64() / -nv
            } else {
                f64::INFINITY
            }
        };
        let mut order = EdgeOrder::default();
        let n = self.edges.len() as u8;
        if n as usize <= STACK_EDGES {
            (0..n).for_each(|k| order.insert(time(k), k));
        } else {
            order.more = (0..n).map(|k| (time(k), k)).collect();
            order
                .more
                .sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        }
        order
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
        self.candidate(&start, f, kind).jet(t)
    }

    /// The contact function of the candidate `kind` along the flight from `f`.
    fn candidate<'s, 'a>(
        &'s self,
        start: &'s Start<'a, T>,
        f: &Flight<T>,
        kind: EventKind,
    ) -> Candidate<'s, 'a, T> {
        match kind {
            EventKind::Collision(m) => {
                let disk = &self.disks[m as usize];
                let (d, r2) = (f.pos.sub(&disk.centre), disk.radius2().clone());
                let eps = start.thermostat().strength.to_f64();
                let model = [d.norm2().sqrt().to_f64(), r2.to_f64(), eps];
                Candidate::Disk(DiskContact {
                    start,
                    d,
                    r2,
                    identity: f.excluded_disk == Some(m),
                    model,
                })
            }
            EventKind::Crossing(k) => {
                let e = &self.edges[k as usize];
                let (p, o) = (&f.pos, e.offset.to_f64().abs());
                Candidate::Edge(EdgeContact {
                    start,
                    normal: &e.normal,
                    sigma: e.normal.dot(p) - &e.offset,
                    scale: p.x.to_f64().abs() + p.y.to_f64().abs() + o,
                    identity: f.excluded_edge == Some(k),
                })
            }
        }
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

#[cfg(test)]
mod order_tests {
    use super::{EdgeOrder, STACK_EDGES};

    /// The order on the stack is the sort by (time, label) of the `Vec` it replaced, ties,
    /// infinities and signed zeros included (labels are distinct, so the order is unique).
    #[test]
    fn the_stack_order_is_the_sort_by_time_then_label() {
        let times = [0.5, f64::INFINITY, -0.0, 0.0, 0.5, 1e-300, 2.0, 0.5];
        let mut seed = 60u64;
        for round in 0..2000 {
            let n = 1 + round % STACK_EDGES;
            let mut edges = Vec::new();
            let mut order = EdgeOrder::default();
            for k in 0..n as u8 {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let t = times[(seed >> 33) as usize % times.len()];
                edges.push((t, k));
                order.insert(t, k);
            }
            edges.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let sorted: Vec<u8> = edges.iter().map(|e| e.1).collect();
            assert_eq!(order.labels().collect::<Vec<_>>(), sorted, "{edges:?}");
        }
    }
}
