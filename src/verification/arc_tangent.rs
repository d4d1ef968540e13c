//! The tangent map of an arc event (`proofs-notes/tangent-map.md`, "In a magnetic field"): the
//! linearised flow of a particle turning at the angular velocity ω between collisions, carried
//! through crossings and specular collisions with the field's acceleration ωJv on both sides.

use nalgebra::{Vector2, Vector4};

use crate::engine::observe::CROSSING_CODE;
use crate::engine::simd::BLOCK;
use crate::kernel::cell::ConvexCell;
use crate::kernel::field::ArcEvent;
use crate::kernel::flight::{EventKind, Flight};
use crate::numbers::lanes::Lanes;

/// J(x, y) = (−y, x): the quarter turn in the sense of a positive field.
fn quarter(v: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-v[1], v[0])
}

/// The free flight of the tangent vector (δq, δv) for the time `t` in the field `w`:
/// δv ← R(ωt)δv, δq ← δq + (sin ωt/ω)δv + ((1 − cos ωt)/ω)Jδv, with 1 − cos φ = 2 sin²(φ/2)
/// (no cancellation for small φ).
pub fn arc_flight(t: &mut Vector4<f64>, time: f64, w: f64) {
    let phi = w * time;
    let (s, c) = phi.sin_cos();
    let half = (0.5 * phi).sin();
    let dv = Vector2::new(t[2], t[3]);
    let jdv = quarter(&dv);
    // sin(φ)/ω and (1 − cos φ)/ω, both → t as ω → 0 (their ratios are taken in the limit).
    let (a, b) = if phi == 0.0 {
        (time, 0.0)
    } else {
        (s / w, 2.0 * half * half / w)
    };
    let dq = Vector2::new(t[0], t[1]) + dv * a + jdv * b;
    let dv = dv * c + jdv * s;
    *t = Vector4::new(dq[0], dq[1], dv[0], dv[1]);
}

/// Applies the linearisation of the arc event `ev` of the flight `f` (flight time `time`, field
/// `w`) in `cell` to the tangent vector (δq, δv): the free flight ([`arc_flight`]), then a
/// crossing (a point reflection negates the vector, a translation leaves it) or a collision
/// ([`collision_map`]). The reference, event by event: the runs carry the vector from collision
/// to collision ([`TangentLane`]), and `tests/numerics/arc_tangent.rs` holds the two together.
pub fn arc_tangent_step(
    t: &mut Vector4<f64>,
    f: &Flight<f64>,
    ev: &ArcEvent<f64>,
    time: f64,
    cell: &ConvexCell<f64>,
    w: f64,
) {
    arc_flight(t, time, w);
    match ev.kind {
        EventKind::Crossing(k) => {
            if cell.edges[k as usize].flips() {
                *t = -*t;
            }
        }
        EventKind::Collision(m) => collision_map(t, f, ev, m, cell, w),
    }
}

/// The linearisation of the collision `ev` of the flight `f` with disk `m` of `cell` (field `w`),
/// applied to the tangent vector (δq, δv) at the contact: with n the outward normal at the
/// contact, r the disk's radius, v⁻ the arrival velocity and v⁺ = Rv⁻ its reflection,
/// δt = −(n·δq)/(n·v⁻), δn = (δq + v⁻δt)/r, and δq ← δq − 2(n·δq)n,
/// δv ← Rδv − 2ωδt·Jv⁺ − 2(v⁻·δn)n − 2(v⁻·n)δn (the field's acceleration before and after the
/// bounce, RJv⁻ − Jv⁺ = −2Jv⁺).
pub fn collision_map(
    t: &mut Vector4<f64>,
    f: &Flight<f64>,
    ev: &ArcEvent<f64>,
    m: u8,
    cell: &ConvexCell<f64>,
    w: f64,
) {
    let disk = &cell.disks[m as usize];
    let x = Vector2::new(f.pos.x + ev.chord.x, f.pos.y + ev.chord.y);
    let c = Vector2::new(disk.centre.x, disk.centre.y);
    let n = (x - c).normalize();
    let v = Vector2::new(ev.velocity.x, ev.velocity.y);
    let (dq, dv) = (Vector2::new(t[0], t[1]), Vector2::new(t[2], t[3]));
    let vn = v.dot(&n);
    let dt = -n.dot(&dq) / vn;
    let dn = (dq + v * dt) / *disk.radius();
    let vplus = v - n * (2.0 * vn);
    let dq2 = dq - n * (2.0 * n.dot(&dq));
    let dv2 = dv
        - n * (2.0 * dv.dot(&n))
        - quarter(&vplus) * (2.0 * w * dt)
        - n * (2.0 * v.dot(&dn))
        - dn * (2.0 * vn);
    *t = Vector4::new(dq2[0], dq2[1], dv2[0], dv2[1]);
}

/// The tangent vectors of `V::WIDTH` orbits carried from collision to collision, written once
/// over the lane width ([`Lanes`]): `f64` for one orbit ([`CollisionTangent`]), vector lanes for
/// a block of the SIMD arc engine, the same operations in the same order, so the same bits.
///
/// A crossing negates the vector (a point reflection) or leaves it (a translation), and either
/// commutes with the linear free flight, so the flight is applied once per collision, for the
/// whole arc since the last one (`proofs-notes/tangent-map.md`, "From collision to collision"):
/// its rotation R(φ) from the arc's velocities at its start v₀ and on arrival u = R(φ)v₀ at unit
/// speed, cos φ = v₀·u and sin φ = v₀×u, with 1 − cos φ = sin²φ/(1 + cos φ) where cos φ > 0 (no
/// cancellation); its time φ/ω from the arc's chord X (the events' chords summed in the current
/// cell's frame), [`arc_time`](crate::kernel::arc::arc_time)'s half angle atan2(ω|X|²/2, v₀·X), taken by the caller.
#[derive(Debug, Clone, Copy)]
pub struct TangentLane<V: Lanes> {
    /// The tangent vector (δq, δv) in the current cell's frame, the free flight since the last
    /// collision not yet applied.
    pub vector: [V; 4],
    /// The velocity at the start of the current arc, in the current cell's frame.
    start: [V; 2],
    /// The arc's chord so far, in the current cell's frame.
    chord: [V; 2],
    /// All bits set where no arc has begun (the next event's velocity starts it).
    fresh: V,
}

/// One event of `V::WIDTH` orbits, as the arc kernel gives it: the code (disk m, or
/// [`CROSSING_CODE`] + edge k), the position and velocity before it, the chord to it and the
/// velocity on arrival, all in the cell's frame.
#[derive(Debug, Clone, Copy)]
pub struct LaneEvent<V: Lanes> {
    /// Disk m, or [`CROSSING_CODE`] + edge k.
    pub code: V,
    /// Position before the event.
    pub pos: [V; 2],
    /// Velocity before the event.
    pub vel: [V; 2],
    /// The chord to the event.
    pub chord: [V; 2],
    /// The velocity on arrival.
    pub arrival: [V; 2],
}

/// What a collision gives back: the growth of the vector (renormalised to 1) and the arguments
/// (y, x) of its arc's half angle, the flight time being 2·atan2(y, x)/ω ([`arc_time`](crate::kernel::arc::arc_time)).
#[derive(Debug, Clone, Copy)]
pub struct Collided<V: Lanes> {
    /// The lanes that collided.
    pub lanes: V::Mask,
    /// The vector's growth over the arc and the collision.
    pub growth: V,
    /// ω|X|²/2.
    pub y: V,
    /// v₀·X.
    pub x: V,
}

/// The cell's disks and its point-reflecting edges, splatted, for [`TangentLane::event`].
pub struct TangentCell<V: Lanes> {
    /// Centre x, centre y and radius of each disk.
    disks: Vec<[V; 3]>,
    /// The codes of the crossings that point-reflect.
    flips: Vec<V>,
    w: V,
}

impl<V: Lanes> TangentCell<V> {
    /// `cell` in the field `w`.
    #[inline(always)]
    pub fn new(cell: &ConvexCell<f64>, w: f64) -> Self {
        let disks = cell
            .disks
            .iter()
            .map(|d| [d.centre.x, d.centre.y, *d.radius()].map(V::splat))
            .collect();
        let flips = (cell.edges.iter().enumerate())
            .filter(|(_, e)| e.flips())
            .map(|(k, _)| V::splat(CROSSING_CODE + k as f64))
            .collect();
        TangentCell {
            disks,
            flips,
            w: V::splat(w),
        }
    }

    /// Disk `code`'s centre and radius in each lane (disk 0's where it names none).
    #[inline(always)]
    fn disk(&self, code: V) -> [V; 3] {
        let mut d = self.disks[0];
        for (m, dm) in self.disks.iter().enumerate().skip(1) {
            let here = code.eq(V::splat(m as f64));
            d = [0, 1, 2].map(|i| V::select(here, dm[i], d[i]));
        }
        d
    }

    /// Where `code` is a point-reflecting crossing.
    #[inline(always)]
    fn flips(&self, code: V) -> V::Mask {
        let none = V::from_bits(0);
        self.flips.iter().fold(none, |m, f| V::or(m, code.eq(*f)))
    }
}

impl<V: Lanes> TangentLane<V> {
    /// The vectors `vector` at the start of an arc.
    #[inline(always)]
    pub fn new(vector: [V; 4]) -> Self {
        let z = V::splat(0.0);
        TangentLane {
            vector,
            start: [z; 2],
            chord: [z; 2],
            fresh: V::select(z.eq(z), V::splat(1.0), z),
        }
    }

    /// The event `e` in the lanes `live` of `cell`: at a collision the vector is carried along
    /// the whole arc and through the collision and renormalised; at a point-reflecting crossing
    /// it is negated. Lanes outside `live` are left as they are.
    #[inline(always)]
    pub fn event(&mut self, cell: &TangentCell<V>, live: V::Mask, e: &LaneEvent<V>) -> Collided<V> {
        let (z, one) = (V::splat(0.0), V::splat(1.0));
        let begins = V::and(live, self.fresh.eq(one));
        let v0 = [0, 1].map(|i| V::select(begins, e.vel[i], self.start[i]));
        let x = [0, 1].map(|i| self.chord[i].add(e.chord[i]));
        let hit = V::and(live, e.code.lt(V::splat(CROSSING_CODE)));
        let flip = V::and(V::and_not(live, hit), cell.flips(e.code));
        let sign = V::select(flip, V::splat(-1.0), one);
        let carried = self.carry(cell, e, v0);
        for i in 0..4 {
            let crossed = self.vector[i].mul(sign);
            self.vector[i] = V::select(hit, carried.vector[i], crossed);
        }
        for i in 0..2 {
            self.start[i] = V::select(hit, z, v0[i].mul(sign));
            self.chord[i] = V::select(hit, z, V::select(live, x[i].mul(sign), self.chord[i]));
        }
        self.fresh = V::select(hit, one, V::select(live, z, self.fresh));
        Collided {
            lanes: hit,
            growth: carried.growth,
            y: cell
                .w
                .mul(x[0].mul(x[0]).add(x[1].mul(x[1])))
                .mul(V::splat(0.5)),
            x: v0[0].mul(x[0]).add(v0[1].mul(x[1])),
        }
    }

    /// The vector carried along the arc from v₀ and through the collision `e`,
    /// renormalised (every lane computes it; only a collision's lanes keep it).
    #[inline(always)]
    fn carry(&self, cell: &TangentCell<V>, e: &LaneEvent<V>, v0: [V; 2]) -> Carried<V> {
        let (one, two) = (V::splat(1.0), V::splat(2.0));
        let [ux, uy] = e.arrival;
        let c = v0[0].mul(ux).add(v0[1].mul(uy));
        let s = v0[0].mul(uy).sub(v0[1].mul(ux));
        let versine = V::select(c.gt(V::splat(0.0)), s.mul(s).div(one.add(c)), one.sub(c));
        let (a, b) = (s.div(cell.w), versine.div(cell.w));
        let [q0, q1, d0, d1] = self.vector;
        // δq + a·δv + b·Jδv, R(φ)δv = c·δv + s·Jδv, with Jδv = (−δv_y, δv_x).
        let q = [
            q0.add(d0.mul(a)).sub(d1.mul(b)),
            q1.add(d1.mul(a)).add(d0.mul(b)),
        ];
        let d = [d0.mul(c).sub(d1.mul(s)), d1.mul(c).add(d0.mul(s))];
        // The collision: n the outward normal at the contact, v = u the arrival velocity.
        let [cx, cy, r] = cell.disk(e.code);
        let (nx, ny) = (
            e.pos[0].add(e.chord[0]).sub(cx),
            e.pos[1].add(e.chord[1]).sub(cy),
        );
        let len = nx.mul(nx).add(ny.mul(ny)).sqrt();
        let (nx, ny) = (nx.div(len), ny.div(len));
        let vn = ux.mul(nx).add(uy.mul(ny));
        let dt = nx.mul(q[0]).add(ny.mul(q[1])).neg().div(vn);
        let dn = [q[0].add(ux.mul(dt)).div(r), q[1].add(uy.mul(dt)).div(r)];
        let (px, py) = (ux.sub(nx.mul(two.mul(vn))), uy.sub(ny.mul(two.mul(vn))));
        let nq = two.mul(nx.mul(q[0]).add(ny.mul(q[1])));
        let nd = two.mul(d[0].mul(nx).add(d[1].mul(ny)));
        let wdt = two.mul(cell.w).mul(dt);
        let vdn = two.mul(ux.mul(dn[0]).add(uy.mul(dn[1])));
        let twovn = two.mul(vn);
        let out = [
            q[0].sub(nx.mul(nq)),
            q[1].sub(ny.mul(nq)),
            d[0].sub(nx.mul(nd))
                .add(py.mul(wdt))
                .sub(nx.mul(vdn))
                .sub(dn[0].mul(twovn)),
            d[1].sub(ny.mul(nd))
                .sub(px.mul(wdt))
                .sub(ny.mul(vdn))
                .sub(dn[1].mul(twovn)),
        ];
        let growth = out
            .iter()
            .fold(V::splat(0.0), |g, o| g.add(o.mul(*o)))
            .sqrt();
        Carried {
            vector: out.map(|o| o.div(growth)),
            growth,
        }
    }
}

impl<V: Lanes> TangentLane<V> {
    /// Lanes `o..o + V::WIDTH` of `b`.
    #[inline(always)]
    pub fn load(b: &TangentBlock, o: usize) -> Self {
        TangentLane {
            vector: b.vector.map(|a| V::load(&a[o..])),
            start: b.start.map(|a| V::load(&a[o..])),
            chord: b.chord.map(|a| V::load(&a[o..])),
            fresh: V::load(&b.fresh[o..]),
        }
    }

    /// Into lanes `o..o + V::WIDTH` of `b`.
    #[inline(always)]
    pub fn store(&self, b: &mut TangentBlock, o: usize) {
        for (a, v) in b.vector.iter_mut().zip(self.vector) {
            v.store(&mut a[o..]);
        }
        for (a, v) in b.start.iter_mut().zip(self.start) {
            v.store(&mut a[o..]);
        }
        for (a, v) in b.chord.iter_mut().zip(self.chord) {
            v.store(&mut a[o..]);
        }
        self.fresh.store(&mut b.fresh[o..]);
    }
}

/// The tangent vectors of a block of [`BLOCK`] orbits ([`TangentLane`], lane by lane).
#[derive(Debug, Clone)]
pub struct TangentBlock {
    vector: [[f64; BLOCK]; 4],
    start: [[f64; BLOCK]; 2],
    chord: [[f64; BLOCK]; 2],
    fresh: [f64; BLOCK],
}

impl TangentBlock {
    /// The vectors `vectors` (at most [`BLOCK`]; lanes beyond them hold 0) at the start of an
    /// arc.
    pub fn new(vectors: &[Vector4<f64>]) -> Self {
        let mut b = TangentBlock {
            vector: [[0.0; BLOCK]; 4],
            start: [[0.0; BLOCK]; 2],
            chord: [[0.0; BLOCK]; 2],
            fresh: [0.0; BLOCK],
        };
        for (l, v) in vectors.iter().enumerate().take(BLOCK) {
            TangentLane::<f64>::new([v[0], v[1], v[2], v[3]]).store(&mut b, l);
        }
        b
    }
}

/// A vector carried through an arc and a collision, renormalised, and its growth.
struct Carried<V: Lanes> {
    vector: [V; 4],
    growth: V,
}

/// One orbit's tangent vector carried from collision to collision ([`TangentLane`] at width 1).
#[derive(Debug, Clone)]
pub struct CollisionTangent {
    lane: TangentLane<f64>,
}

impl CollisionTangent {
    /// The vector `vector` at the start of an arc.
    pub fn new(vector: Vector4<f64>) -> Self {
        CollisionTangent {
            lane: TangentLane::new([vector[0], vector[1], vector[2], vector[3]]),
        }
    }

    /// The tangent vector, renormalised at the last collision.
    pub fn vector(&self) -> Vector4<f64> {
        Vector4::from(self.lane.vector)
    }

    /// The event `ev` of the flight `f` in `cell` (field `w`): at a collision, the vector's
    /// growth (it is renormalised) and the arc's flight time; at a crossing, `None`.
    pub fn event(
        &mut self,
        f: &Flight<f64>,
        ev: &ArcEvent<f64>,
        cell: &TangentCell<f64>,
        w: f64,
    ) -> Option<(f64, f64)> {
        let code = match ev.kind {
            EventKind::Collision(m) => f64::from(m),
            EventKind::Crossing(k) => CROSSING_CODE + f64::from(k),
        };
        let e = LaneEvent {
            code,
            pos: [f.pos.x, f.pos.y],
            vel: [f.vel.x, f.vel.y],
            chord: [ev.chord.x, ev.chord.y],
            arrival: [ev.velocity.x, ev.velocity.y],
        };
        let c = self.lane.event(cell, true, &e);
        c.lanes.then(|| (c.growth, half_angle_time(c.y, c.x, w)))
    }
}

/// The flight time 2·atan2(y, x)/ω of a [`Collided`] lane ([`arc_time`](crate::kernel::arc::arc_time)'s operations).
#[inline]
pub fn half_angle_time(y: f64, x: f64, w: f64) -> f64 {
    y.atan2(x) * 2.0 / w
}
