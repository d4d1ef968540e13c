//! The MPFR kernel decides each event in `f64` balls and computes only the chosen time
//! (`kernel::certified`, `proofs-notes/certified-filter.md`). Wherever the balls decide, the
//! event and its time must be the full comparison's to the bit; wherever they cannot, the
//! kernel compares every candidate. Checked on random starts from w = 10⁻⁶ to beyond w∞ at 53,
//! 128, 256 and 1024 bits, on the starts aimed at near-ties, grazing hits and corners, and on
//! starts inside a disk and on an edge.

use super::choice::{aimed_starts, free_start};
use lorentz_gas::kernel::flight::{Event, Flight};
use lorentz_gas::kernel::trap::Trap;
use lorentz_gas::kernel::vec2::Vec2;
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus as Gen;
use rug::Float;

/// Events decided by the balls and events left to the full comparison.
#[derive(Default, Debug)]
struct Tally {
    decided: usize,
    deferred: usize,
}

/// Follows `f` for `events` events at the trap's precision. At each, the balls' event (where
/// they decide) must equal the full comparison's, kind and time bit for bit, and the kernel's
/// event must equal the generic cell kernel's.
fn follow(trap: &Trap<Float>, mut f: Flight<Float>, events: usize, what: &str, n: &mut Tally) {
    for k in 0..events {
        let want: Option<Event<Float>> = trap.next_event_compared(&f);
        match trap.next_event_decided(&f) {
            Some(ev) => {
                n.decided += 1;
                assert_eq!(Some(&ev), want.as_ref(), "{what}: event {k} from {f:?}");
            }
            None => n.deferred += 1,
        }
        assert_eq!(trap.next_event(&f), want, "{what}: event {k} (kernel)");
        assert_eq!(trap.cell().next_event(&f), want, "{what}: event {k} (cell)");
        match want {
            Some(ev) => trap.apply(&mut f, &ev),
            None => return,
        }
    }
}

#[test]
fn decided_events_are_the_full_comparisons_on_random_starts() {
    let mut rng = Gen::seed_from_u64(22);
    for w in [1e-6, 1e-3, 0.1, 0.3, 0.6, 1.9] {
        let trap = Trap::new(w).unwrap();
        for bits in [53u32, 128, 256, 1024] {
            let trap_p = Trap::new(Float::with_val(bits, w)).unwrap();
            let mut n = Tally::default();
            for s in 0..6 {
                let f = Flight::<Float>::convert_from_f64(bits, &free_start(&trap, &mut rng));
                follow(
                    &trap_p,
                    f,
                    1_000,
                    &format!("w = {w:e}, {bits} bits, start {s}"),
                    &mut n,
                );
            }
            eprintln!("w = {w:e}, {bits} bits: {n:?}");
            // The balls are 2⁻⁵⁰-wide: they leave only near-ties and grazing hits to the full
            // comparison. A filter that decides less than nine events in ten does nothing.
            assert!(n.deferred * 10 < n.decided, "w = {w:e}, {bits} bits: {n:?}");
        }
    }
}

/// Follows each of `starts` (built at `w` in `f64`) for `events` events at `bits` bits.
fn follow_starts(w: f64, bits: u32, starts: &[Flight<f64>], events: usize, what: &str) -> Tally {
    let trap = Trap::new(Float::with_val(bits, w)).unwrap();
    let mut n = Tally::default();
    for (s, f) in starts.iter().enumerate() {
        let f = Flight::<Float>::convert_from_f64(bits, f);
        let label = format!("w = {w:e}, {bits} bits, {what} {s}");
        follow(&trap, f, events, &label, &mut n);
    }
    eprintln!("w = {w:e}, {bits} bits, {what} starts: {n:?}");
    n
}

#[test]
fn aimed_starts_are_decided_exactly_or_deferred() {
    for w in [1e-6, 1e-5, 0.1, 0.3] {
        let starts = aimed_starts(&Trap::new(w).unwrap());
        for bits in [53u32, 256] {
            let n = follow_starts(w, bits, &starts, 6, "aimed");
            // Corners, grazing rims and flights along an edge are what the balls cannot decide.
            assert!(n.deferred > 0 && n.decided > 0, "w = {w:e}: {n:?}");
        }
    }
}

/// Starts whose first two candidates come within rounding of each other: lines through the
/// points where an edge line meets a rim (the crossing and the disk's entry nearly coincide),
/// shifted along the edge by 0 to 10⁻¹³, from inside the trap at angles across the edge. At
/// more than 53 bits the `f64` midpoints alone would order some of them wrongly.
fn rim_crossing_starts(trap: &Trap<f64>) -> Vec<Flight<f64>> {
    let mut out = Vec::new();
    let centroid = Vec2::new(trap.a() / 2.0, trap.h() / 3.0);
    for e in 0..3usize {
        let (i, j) = ((e + 1) % 3, (e + 2) % 3);
        for (from, to) in [(i, j), (j, i)] {
            let (c, d) = (
                &trap.vertices()[from],
                trap.vertices()[to].sub(&trap.vertices()[from]),
            );
            let along = Vec2::new(d.x / trap.a(), d.y / trap.a());
            for k in -12..=12 {
                let shift = k as f64 * 1e-14 * if k % 2 == 0 { 0.01 } else { 1.0 };
                let r = 1.0 + shift;
                let target = Vec2::new(c.x + r * along.x, c.y + r * along.y);
                for n in 0..24 {
                    // From points on a circle of radius 0.2 about the centroid, through the target.
                    let phi = n as f64 * std::f64::consts::TAU / 24.0;
                    let p = Vec2::new(centroid.x + 0.2 * phi.cos(), centroid.y + 0.2 * phi.sin());
                    let d = target.sub(&p);
                    let len = d.norm2().sqrt();
                    out.push(Flight::new(p, Vec2::new(d.x / len, d.y / len)));
                }
            }
        }
    }
    out
}

#[test]
fn rim_crossings_are_decided_exactly_or_deferred() {
    for w in [1e-3, 0.1, 0.3] {
        let starts = rim_crossing_starts(&Trap::new(w).unwrap());
        for bits in [53u32, 256] {
            let n = follow_starts(w, bits, &starts, 3, "rim");
            assert!(n.deferred > 0, "w = {w:e}: {n:?}");
        }
    }
}

/// Starts the balls must leave alone: inside a disk moving in (time 0 there, and 0 ties), on
/// an edge line (σ = 0), at every corner, and exactly tangent to a disk (Δ = 0).
#[test]
fn zero_times_and_tangents_are_deferred_or_exact() {
    let bits = 256;
    let trap = Trap::new(Float::with_val(bits, 0.1)).unwrap();
    let t64 = Trap::new(0.1).unwrap();
    let f = |x: f64, y: f64, vx: f64, vy: f64| {
        Flight::<Float>::convert_from_f64(bits, &Flight::new(Vec2::new(x, y), Vec2::new(vx, vy)))
    };
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let mut starts = vec![
        f(0.5, 0.5, -s, -s),              // inside disk 0, moving in
        f(t64.a() / 2.0, 0.0, 0.0, -1.0), // on edge 2, leaving
        f(t64.a() / 2.0, 0.0, 0.6, -0.8), // on edge 2, leaving at a slant
        f(t64.a() / 2.0, 2.0, -1.0, 0.0), // y = 2 … a horizontal flight
        f(-1.0, 1.0 / 3.0, 1.0, 0.0),     // outside, aimed by the cell's tangent y = 1
        f(t64.a() / 2.0, 1.0, -1.0, 0.0), // tangent to disk 0 (|d × v| = 1 exactly)
    ];
    for c in t64.vertices() {
        for (vx, vy) in [(1.0, 0.0), (-s, s), (0.0, -1.0), (s, s)] {
            starts.push(f(c.x, c.y, vx, vy));
        }
    }
    let mut n = Tally::default();
    for (k, f0) in starts.into_iter().enumerate() {
        follow(&trap, f0, 4, &format!("special start {k}"), &mut n);
    }
    eprintln!("special starts: {n:?}");
    assert!(n.deferred >= 6, "{n:?}");
}
