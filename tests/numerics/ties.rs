//! The tie rule: a collision and a cell-edge crossing at the same time go to the collision
//! (`kernel::cell`: "collisions before crossings, then the lower edge label"), in every straight
//! kernel, at every precision.
//!
//! The tie is exact: from (9/8, 1/2) with the velocity (−1, −4), the flight hits the disk of
//! P₀ = (0, 0) (radius 1) at (1, 0) at t = 1/8 — transversally, the line cutting the circle — the
//! moment it reaches the base edge y = 0 (label 2). Every operation of both times is exact there:
//! d = p, β = d·v = −25/8, |v|² = 17, d × v = −4, Δ = |v|² − (d × v)² = 1, |d|² − 1 = 33/64, the
//! entry (33/64)/(25/8 + √1) = 1/8, and the crossing's σ/(−n·v) = (1/2)/4. So the two times are
//! equal at every precision and only the rule decides. (A grazing contact would not do: the
//! straight kernels take Δ = 0 as a miss.) Inverting the rule (the edge where it is not later)
//! makes these tests fail.

use lorentz_gas::kernel::flight::{Event, EventKind, Flight};
use lorentz_gas::kernel::trap::Trap;
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::numbers::real::Real;
use rug::Float;

/// The flight from (9/8, 1/2) with the velocity (−1, −4), at the precision `ctx`.
fn at_the_corner<T: Real>(ctx: T::Ctx) -> Flight<T> {
    let k = |x: f64| T::from_f64(ctx, x);
    Flight::new(Vec2::new(k(1.125), k(0.5)), Vec2::new(k(-1.0), k(-4.0)))
}

/// Every straight kernel of the trap at `w` finds the collision with P₀ at t = 1/8, not the
/// crossing of the base edge (label 2) at the same time.
fn tie_goes_to_the_collision<T: Real>(w: T) {
    let ctx = w.ctx();
    let trap = Trap::new(w).unwrap();
    let f = at_the_corner::<T>(ctx);
    let want = Some(Event {
        kind: EventKind::Collision(0),
        time: T::from_f64(ctx, 0.125),
    });
    // The crossing is there too, at the same time, when the disk is not a candidate.
    let mut off = f.clone();
    off.excluded_disk = Some(0);
    let edge = trap.cell().next_event(&off).unwrap();
    assert_eq!(edge.kind, EventKind::Crossing(2));
    assert_eq!(edge.time, T::from_f64(ctx, 0.125), "the crossing's time");
    assert_eq!(trap.cell().next_event(&f), want, "generic cell kernel");
    assert_eq!(trap.next_event_compared(&f), want, "full comparison");
    assert_eq!(trap.next_event_chosen(&f), want, "choice (the SIMD rule)");
    assert_eq!(trap.next_event(&f), want, "trap kernel");
    if let Some(ev) = trap.next_event_decided(&f) {
        assert_eq!(Some(ev), want, "decided in balls");
    }
}

#[test]
fn a_collision_and_a_crossing_at_the_same_time_go_to_the_collision_in_f64() {
    for w in [0.1, 0.2, 0.3] {
        tie_goes_to_the_collision::<f64>(w);
    }
}

#[test]
fn a_collision_and_a_crossing_at_the_same_time_go_to_the_collision_in_mpfr() {
    for bits in [53, 200] {
        for w in ["0.1", "0.2", "0.3"] {
            let w = Float::with_val(bits, Float::parse(w).unwrap());
            tie_goes_to_the_collision::<Float>(w);
        }
    }
}
