//! The trap's next event decided in `f64` balls and computed at the working precision.
//!
//! At MPFR precision most of an event's cost is the arithmetic of candidates that lose: the
//! roots of disks that are not hit first and the quotients of edges that are not crossed first.
//! Here every candidate of the full comparison ([`super::trap::Trap::next_event_compared`]) is first evaluated
//! with [`Ball`]s — `f64` midpoint–radius enclosures of the values the working precision
//! computes, by the same sequence of operations — and when the balls decide every sign the full
//! comparison tests and put one candidate's time strictly before all the others, only that
//! candidate is computed at the working precision, by exactly the full comparison's operations.
//! Its event and time are then the full comparison's, bit for bit. Where the balls decide
//! nothing (a grazing disk, a start on an edge, a near-tie at a corner, two times of 0), the
//! function says so and the caller compares every candidate as before: the filter never
//! decides by a tolerance, it only skips work whose outcome it has proved
//! (`proofs-notes/certified-filter.md`).

use super::flight::Flight;
use super::vec2::Vec2;
use crate::numbers::ball::Ball;
use crate::numbers::real::Real;

/// The trap's constants as balls around their working-precision values.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrapBalls {
    /// √3/2, the slanted normals' x component.
    k: Ball,
    /// The height h.
    h: Ball,
    /// The disk centres P₁ = (a, 0) and P₂ = (a/2, h).
    centres: [[Ball; 2]; 2],
}

impl TrapBalls {
    /// Balls around a trap's working-precision constants: the slanted normals' x component
    /// `k` = √3/2, the height `h` and the disk centres P₁, P₂.
    pub fn new<T: Real>(k: &T, h: &T, p1: &Vec2<T>, p2: &Vec2<T>) -> Self {
        let b = |x: &T| Ball::around(x.to_f64());
        TrapBalls {
            k: b(k),
            h: b(h),
            centres: [[b(&p1.x), b(&p1.y)], [b(&p2.x), b(&p2.y)]],
        }
    }
}

/// A candidate as the balls see it.
enum Seen {
    /// Certainly not a candidate (moving away, missing, or excluded).
    Absent,
    /// Certainly a candidate, its rounded time in this ball.
    At(Ball),
    /// The balls cannot tell.
    Unknown,
}

/// The disk with offset `d` from its centre, by the operations of
/// [`super::ray_disk::approach`] and [`super::ray_disk::Approach::entry`].
#[inline(always)]
fn disk(d: [Ball; 2], v: [Ball; 2], vv: Ball) -> Seen {
    let beta = d[0] * v[0] + d[1] * v[1];
    if beta.non_negative() {
        return Seen::Absent;
    }
    if !beta.negative() {
        return Seen::Unknown;
    }
    let q = d[0] * v[1] - d[1] * v[0];
    let disc = vv - q.sqr();
    if disc.non_positive() {
        return Seen::Absent;
    }
    if !disc.positive() {
        return Seen::Unknown;
    }
    let gamma = d[0].sqr() + d[1].sqr() + Ball::exact(-1.0);
    if gamma.non_positive() {
        return Seen::At(Ball::exact(0.0));
    }
    if !gamma.positive() {
        return Seen::Unknown;
    }
    Seen::At(gamma / (disc.sqrt() - beta))
}

/// The edge with n·v = `nv` and σ = `sigma`, as the full comparison times it.
#[inline(always)]
fn edge(nv: Ball, sigma: Ball) -> Seen {
    if nv.non_negative() {
        return Seen::Absent;
    }
    if !nv.negative() {
        return Seen::Unknown;
    }
    if sigma.non_positive() {
        return Seen::At(Ball::exact(0.0));
    }
    if !sigma.positive() {
        return Seen::Unknown;
    }
    Seen::At(sigma / -nv)
}

/// The six candidates (disks 0–2, edges 0–2) as the balls see them, in the full comparison's
/// offer order.
#[inline(always)]
fn candidates<T: Real>(c: &TrapBalls, f: &Flight<T>) -> [Seen; 6] {
    let b = |x: &T| Ball::around(x.to_f64());
    let p = [b(&f.pos.x), b(&f.pos.y)];
    let v = [b(&f.vel.x), b(&f.vel.y)];
    let vv = v[0].sqr() + v[1].sqr();
    let half = Ball::exact(0.5);
    let disk_at = |m: u8| {
        if f.excluded_disk == Some(m) {
            return Seen::Absent;
        }
        let d = match m {
            0 => p,
            _ => {
                let o = c.centres[m as usize - 1];
                [p[0] - o[0], p[1] - o[1]]
            }
        };
        disk(d, v, vv)
    };
    // Trap::slanted_edges: −(kvₓ + v_y/2), −(kpₓ + p_y/2) + h, kvₓ − v_y/2, kpₓ − p_y/2.
    let (kvx, hvy) = (c.k * v[0], v[1] * half);
    let (kpx, hpy) = (c.k * p[0], p[1] * half);
    let edge_at = |e: u8, nv: Ball, sigma: Ball| {
        if f.excluded_edge == Some(e) {
            Seen::Absent
        } else {
            edge(nv, sigma)
        }
    };
    [
        disk_at(0),
        disk_at(1),
        disk_at(2),
        edge_at(0, -(kvx + hvy), -(kpx + hpy) + c.h),
        edge_at(1, kvx - hvy, kpx - hpy),
        edge_at(2, v[1], p[1]),
    ]
}

/// The index (0–2 disks, 3–5 edges) of the candidate whose time is certainly before every
/// other's, or `None` if the balls cannot tell.
#[inline(always)]
fn certain_first(seen: &[Seen; 6]) -> Option<usize> {
    let mut first: Option<(usize, Ball)> = None;
    for (i, s) in seen.iter().enumerate() {
        match s {
            Seen::Unknown => return None,
            Seen::At(t) if first.is_none_or(|(_, b)| t.m < b.m) => first = Some((i, *t)),
            _ => {}
        }
    }
    let (i, t) = first?;
    let alone = seen.iter().enumerate().all(|(j, s)| match s {
        Seen::At(u) => j == i || t.before(*u),
        _ => true,
    });
    alone.then_some(i)
}

/// The candidate of `f`'s next event (0–2 the disks, 3–5 the edges) when the balls `balls` of
/// its trap decide it: the one [`super::trap::Trap::next_event_compared`] finds, whose time the
/// trap then computes alone ([`super::trap::Trap::next_event_decided`]); `None` when they
/// cannot decide (the caller then compares every candidate).
#[inline(always)]
pub fn decide<T: Real>(balls: &TrapBalls, f: &Flight<T>) -> Option<usize> {
    certain_first(&candidates(balls, f))
}
