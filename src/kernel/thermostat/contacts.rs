//! The contact functions of a thermostatted flight with a cell's disks and edges, F, F′, F″ and
//! their error bounds at a flight point ([`isolate::Jet`]), and the bound on F‴ over a step
//! (`proofs-notes/thermostat-flight.md`, "Certified events").

use super::isolate::{Contact, Jet, Lean};
use super::{FlightPoint, Start};
use crate::kernel::cell::ConvexCell;
use crate::kernel::flight::{EventKind, Flight};
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;

/// A flight point with what every contact's jet there shares: the flight's error bounds (δX, δv)
/// at its time ([`Start::error`]) and the lean of its velocity ([`Lean`]), formed once for all
/// the candidates the point serves.
pub(super) struct Here<'p, T: Real> {
    /// The flight time.
    pub t: &'p T,
    /// The flight there.
    pub at: &'p FlightPoint<T>,
    /// [`Start::error`] at `t`.
    error: (f64, f64),
    lean: Lean,
}

impl<'p, T: Real> Here<'p, T> {
    /// The point `at` of the flight `start` at the time `t`.
    pub fn new(start: &Start<'_, T>, t: &'p T, at: &'p FlightPoint<T>) -> Self {
        let error = start.error(t);
        let lean = lean_at(start, t, at, error.1);
        Here { t, at, error, lean }
    }

    /// The error bounds (δX, δv) of the point, δX widened by 8u(`offset` + 1) for forming the
    /// offset from the obstacle.
    fn flight_error(&self, offset: f64) -> (f64, f64) {
        let (dx, dv) = self.error;
        (
            dx + 8.0 * T::unit_roundoff(self.t.ctx()) * (offset + 1.0),
            dv,
        )
    }
}

/// |sin θ| of the flight point `at` (time `t`) against the exact flight's, rounded up by the
/// velocity's error δv and the cross product's rounding, and whether cos θ ≥ 0 beyond them.
fn lean_at<T: Real>(start: &Start<'_, T>, t: &T, at: &FlightPoint<T>, dv: f64) -> Lean {
    let dir = &start.thermostat().dir;
    let slack = dv + 4.0 * T::unit_roundoff(t.ctx());
    Lean {
        sin: dir.cross(&at.vel).to_f64().abs() + slack,
        relaxing: dir.dot(&at.vel).to_f64() > slack,
    }
}

/// |X − c|² − r² along the flight from d = p − c.
pub(super) struct DiskContact<'s, 'a, T: Real> {
    start: &'s Start<'a, T>,
    d: Vec2<T>,
    r2: T,
    identity: bool,
    /// |d|₁ ≥ |d|, r² and ε in `f64`: the error model's inputs that do not change along the
    /// flight.
    model: [f64; 3],
}

impl<T: Real> DiskContact<'_, '_, T> {
    /// |F‴| = |2(X − c)·v̈| ≤ 2(ρ + h)ε²|sin θ| over [t, t + h].
    fn third(&self, jet: &Jet<T>, h: &T) -> T {
        let eps = &self.start.thermostat().strength;
        let lean = jet.lean.over(self.model[2], h.to_f64());
        (jet.reach.clone() + h) * &eps.square().scale((2.0 + 1.0 / 65536.0) * lean)
    }

    /// The jet at the flight point `here`.
    fn jet_on(&self, here: &Here<'_, T>) -> Jet<T> {
        let (t, at) = (here.t, here.at);
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
                lean: here.lean,
            };
        }
        let [d, r2, eps] = self.model;
        let (dx, dv) = here.flight_error(d);
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
            lean: here.lean,
        }
    }
}

/// σ + n·X: the signed distance to an edge along the flight.
pub(super) struct EdgeContact<'s, 'a, T: Real> {
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

    /// The jet at the flight point `here`.
    fn jet_on(&self, here: &Here<'_, T>) -> Jet<T> {
        let (t, at) = (here.t, here.at);
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
                lean: here.lean,
            };
        }
        let nx = n.dot(&at.disp);
        let (dx, dv) = here.flight_error(self.scale);
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
            lean: here.lean,
        }
    }
}

/// A disk's or an edge's contact function.
pub(super) enum Candidate<'s, 'a, T: Real> {
    Disk(DiskContact<'s, 'a, T>),
    Edge(EdgeContact<'s, 'a, T>),
}

impl<'s, 'a, T: Real> Candidate<'s, 'a, T> {
    /// The contact function of the candidate `kind` along the flight from `f`.
    pub fn new(
        cell: &'s ConvexCell<T>,
        start: &'s Start<'a, T>,
        f: &Flight<T>,
        kind: EventKind,
    ) -> Self {
        match kind {
            EventKind::Collision(m) => {
                let disk = &cell.disks[m as usize];
                let (d, r2) = (f.pos.sub(&disk.centre), disk.radius2().clone());
                let eps = start.thermostat().strength.to_f64();
                // |d|₁ ≥ |d|: the offset's size in the error model, without a square root.
                let model = [d.x.to_f64().abs() + d.y.to_f64().abs(), r2.to_f64(), eps];
                Candidate::Disk(DiskContact {
                    start,
                    d,
                    r2,
                    identity: f.excluded_disk == Some(m),
                    model,
                })
            }
            EventKind::Crossing(k) => {
                let e = &cell.edges[k as usize];
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

    /// Whether the flight starts on this obstacle (the disk left, the edge entered by).
    pub fn identity(&self) -> bool {
        match self {
            Candidate::Disk(c) => c.identity,
            Candidate::Edge(c) => c.identity,
        }
    }

    /// The flight the contact is along.
    pub fn start(&self) -> &Start<'_, T> {
        match self {
            Candidate::Disk(c) => c.start,
            Candidate::Edge(c) => c.start,
        }
    }

    /// The jet at the flight point `here`.
    pub fn jet_on(&self, here: &Here<'_, T>) -> Jet<T> {
        match self {
            Candidate::Disk(c) => c.jet_on(here),
            Candidate::Edge(c) => c.jet_on(here),
        }
    }
}

impl<T: Real> Contact<T> for Candidate<'_, '_, T> {
    fn jet(&self, t: &T) -> Jet<T> {
        let at = self.start().at(t);
        self.jet_on(&Here::new(self.start(), t, &at))
    }

    fn start_jet(&self, ctx: T::Ctx) -> Jet<T> {
        let zero = T::zero(ctx);
        self.jet_on(&Here::new(self.start(), &zero, self.start().origin()))
    }

    fn third(&self, jet: &Jet<T>, h: &T) -> T {
        match self {
            Candidate::Disk(c) => c.third(jet, h),
            Candidate::Edge(c) => c.third(jet, h),
        }
    }
}
