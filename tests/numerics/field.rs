//! The kernel in a uniform magnetic field (arcs), and the exact geometry of its localized orbits.
//!
//! * MPFR at 53 bits follows the `f64` arc kernel bit for bit, event for event (both scenes, fields
//!   of either sign from 10⁻² to 10²): only correctly rounded operations decide and carry out an
//!   arc event;
//! * every `f64` event against the same event computed at 256 bits from the same state: the same
//!   obstacle, and the `f64` state after it on its disk and in its cell within the straight
//!   kernel's post-event bound, with the speed inside the energy band (`proofs-notes/magnetic-arcs.md`);
//! * a weak field bends each flight by its sagitta |ω|t²/2 and no more; cyclotron radii from 10⁻⁶
//!   to 10⁶ keep every contact on its obstacle;
//! * reversal (x, v, B) → (x, −v, −B) retraces an orbit (256 bits, within the amplified roundoff);
//! * a pinned circle has no event, a skipping orbit stays in its annulus for ever;
//! * the sampled shares of pinned and skipping phase points agree with the exact shares within the
//!   binomial 4σ bound.

use lorentz_gas::kernel::flight::{EventKind, Flight};
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::{CellIndex, LatticeState};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::square::SquareScene;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::theory::magnetic::{FieldGeometry, Orbit};
use lorentz_gas::verification::error_model::{ENERGY_BAND_U, POST_EVENT_U, UNIT_ROUNDOFF};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus as Gen;
use rug::Float;

const FIELDS: [f64; 6] = [0.01, -0.3, 1.0, -2.5, 10.0, 100.0];

/// The events `check(scene, seed, B, n)` counts over every B of [`FIELDS`] (its index `i`) on the
/// triangular lattice at w = 0.1 (seed `first + i`), at w = 0.3 (`first + 10 + i`) and the
/// square one at r = 1/4 (`first + 20 + i`). A macro: `check` is generic over the scene.
macro_rules! over_fields {
    ($check:ident, $first:expr, $n:expr) => {{
        let mut events = 0;
        for (i, &w) in FIELDS.iter().enumerate() {
            let i = i as u64;
            events += $check(&triangular(0.1), $first + i, w, $n);
            events += $check(&triangular(0.3), $first + 10 + i, w, $n);
            events += $check(&SquareScene::new(0.25).unwrap(), $first + 20 + i, w, $n);
        }
        events
    }};
}

fn triangular(w: f64) -> TriangularScene {
    TriangularScene::new(w).unwrap()
}

/// Runs `n` events of the orbit from `s` at both types and asserts the same events and bits.
fn same_bits<S: Scene>(scene: &S, seed: u64, w: f64, n: usize) -> usize {
    let l64 = scene.lattice::<f64>(()).unwrap();
    let l53 = scene.lattice::<Float>(53).unwrap();
    let mut a = scene.sample(&mut stream(seed, 0));
    let mut b = LatticeState::<Float>::convert_from_f64(53, &a);
    let w53 = Float::with_val(53, w);
    for k in 0..n {
        let (ea, eb) = (
            l64.next_event_in_field(&a, &w),
            l53.next_event_in_field(&b, &w53),
        );
        assert_eq!(ea.is_none(), eb.is_none(), "event {k} at B = {w}");
        let (Some(ea), Some(eb)) = (ea, eb) else {
            // A pinned orbit (the sampled start's circle meets no disk).
            return k;
        };
        assert_eq!(ea.kind, eb.kind, "event {k} at B = {w}");
        l64.apply_in_field(&mut a, &ea);
        l53.apply_in_field(&mut b, &eb);
        assert_eq!(b.to_f64(), a, "state after event {k} at B = {w}");
    }
    n
}

#[test]
fn mpfr53_follows_the_f64_arc_kernel_bit_for_bit() {
    let events = over_fields!(same_bits, 10, 3000);
    assert!(
        events > 35_000,
        "most orbits should collide: {events} events"
    );
}

/// |x − c|² − r² for the world-free check at 256 bits: how far inside disk `m` the state is.
fn depth(cell: &lorentz_gas::kernel::cell::ConvexCell<f64>, m: usize, p: &Vec2<f64>) -> f64 {
    let d = &cell.disks[m];
    let q =
        Vec2::<Float>::from_f64(256, p.x, p.y).sub(&Vec2::from_f64(256, d.centre.x, d.centre.y));
    (q.norm2() - Float::with_val(256, d.radius2())).to_f64()
}

/// Runs an orbit and checks every event against its 256-bit recomputation from the same state.
fn against_256<S: Scene>(scene: &S, seed: u64, w: f64, n: usize) -> usize {
    let l64 = scene.lattice::<f64>(()).unwrap();
    let l256 = scene.lattice::<Float>(256).unwrap();
    let cell = l64.cell().clone();
    let extent = 1.0 + cell.extent() / cell.smallest_radius();
    let u = UNIT_ROUNDOFF;
    let w256 = Float::with_val(256, w);
    let mut s = scene.sample(&mut stream(seed, 1));
    for k in 0..n {
        let Some(ev) = l64.next_event_in_field(&s, &w) else {
            return k;
        };
        let hi = LatticeState::<Float>::convert_from_f64(256, &s);
        let ev_hi = l256
            .next_event_in_field(&hi, &w256)
            .expect("the same orbit collides");
        assert_eq!(ev.kind, ev_hi.kind, "event {k} at B = {w}: {s:?}");
        l64.apply_in_field(&mut s, &ev);
        let f = &s.flight;
        let speed = (f.vel.x * f.vel.x + f.vel.y * f.vel.y - 1.0).abs();
        assert!(
            speed <= ENERGY_BAND_U * u * extent,
            "speed {speed:e} at event {k}"
        );
        for m in 0..cell.disks.len() {
            let inside = depth(&cell, m, &f.pos);
            assert!(inside >= -POST_EVENT_U * u, "inside disk {m} by {inside:e}");
        }
        for e in 0..cell.edges.len() {
            let sigma = cell.edge_distance(e, &f.pos);
            assert!(
                sigma >= -POST_EVENT_U * u * extent,
                "beyond edge {e} by {sigma:e}"
            );
        }
    }
    n
}

#[test]
fn every_arc_event_is_the_256_bit_event_and_stays_on_its_obstacle() {
    let events = over_fields!(against_256, 40, 1500);
    assert!(events > 20_000, "{events}");
}

#[test]
fn cyclotron_radii_from_a_millionth_to_a_million_keep_contacts_on_their_obstacles() {
    for (i, w) in [1e6, 1e4, 1e2, 1e-2, 1e-4, 1e-6].into_iter().enumerate() {
        for sign in [1.0, -1.0] {
            against_256(&triangular(0.2), 70 + i as u64, sign * w, 300);
            against_256(
                &SquareScene::new(0.1).unwrap(),
                80 + i as u64,
                sign * w,
                300,
            );
        }
    }
}

/// From the same state, the arc event of a weak field is the straight event, and its chord the
/// straight displacement bent linearly in ω: the bend at 2ω is twice the bend at ω, to the
/// relative O(ω) of the next order (2·10⁻⁵ at ω = 10⁻⁶ on the worst event of this orbit, so
/// 2·10⁻⁸ at ω = 10⁻⁹) plus the rounding of the two chords (4·10⁻¹⁵ absolute).
#[test]
fn a_weak_field_bends_each_flight_linearly_in_the_field() {
    let scene = triangular(0.15);
    let lat = scene.lattice::<f64>(()).unwrap();
    for w in [1e-9, -1e-9] {
        let mut s = scene.sample(&mut stream(90, 0));
        let mut ties = 0;
        for k in 0..2000 {
            let straight = lat.next_event(&s).unwrap();
            let t = straight.time;
            let bend = |w: f64| {
                let arc = lat.next_event_in_field(&s, &w).unwrap();
                let (dx, dy) = (
                    arc.chord.x - t * s.flight.vel.x,
                    arc.chord.y - t * s.flight.vel.y,
                );
                (arc.kind, dx.hypot(dy))
            };
            let ((k1, b1), (k2, b2)) = (bend(w), bend(2.0 * w));
            if k1 != straight.kind || k2 != straight.kind {
                // A corner passed within the bend: the obstacles swap, a near-tie.
                ties += 1;
            } else if b1 > 1e-14 {
                assert!(
                    (b2 / b1 - 2.0).abs() < 1e-6 + 4e-15 / b1,
                    "event {k}: {b1:e} {b2:e}"
                );
            }
            lat.apply(&mut s, &straight);
        }
        assert!(ties <= 2, "{ties} near-ties in 2000 events");
    }
}

/// (x, v, B) → (x, −v, −B) retraces the orbit: 12 events forward and back return to the
/// start, within an error that is rounding and nothing else — it shrinks with the precision by
/// the ratio of the unit roundoffs (2⁻²⁵⁶ from 256 to 512 bits; asserted 2⁻²⁰⁰, the amplification
/// of a grazing event being the same at both precisions).
#[test]
fn reversing_velocity_and_field_retraces_the_orbit() {
    for (i, w) in [0.4, -1.0, 3.0].into_iter().enumerate() {
        let gap = |bits: u32| {
            let scene = triangular(0.2);
            let lat = scene.lattice::<Float>(bits).unwrap();
            let sample = scene.sample(&mut stream(100 + i as u64, 0));
            let mut start = LatticeState::<Float>::convert_from_f64(bits, &sample);
            // |v| = 1 at this precision: the Newton factor would otherwise change the speed
            // (and the cyclotron radius) by the f64 start's 10⁻¹⁶ squared, forward and back alike.
            start.flight.normalise_speed();
            let fw = Float::with_val(bits, w);
            // Start at an event, where the reversed orbit stops again.
            let first = lat.next_event_in_field(&start, &fw).unwrap();
            lat.apply_in_field(&mut start, &first);
            let mut s = start.clone();
            for _ in 0..12 {
                let ev = lat.next_event_in_field(&s, &fw).unwrap();
                lat.apply_in_field(&mut s, &ev);
            }
            s.flight.reverse();
            let back = Float::with_val(bits, -w);
            let distance = |s: &LatticeState<Float>| {
                lat.world(s).sub(&lat.world(&start)).norm2().to_f64().sqrt()
            };
            // The world point decides (a crossing point is the same point in either cell).
            let mut events = 0;
            while events < 40 && distance(&s) > 1e-20 {
                let ev = lat.next_event_in_field(&s, &back).unwrap();
                lat.apply_in_field(&mut s, &ev);
                events += 1;
            }
            (distance(&s), events)
        };
        let ((g256, e256), (g512, e512)) = (gap(256), gap(512));
        assert!(
            e256 >= 12 && e256 == e512,
            "B = {w}: {e256} and {e512} events back"
        );
        assert!(g256 <= 1e-20, "B = {w}: back within {g256:e}");
        assert!(
            g512 <= g256 * 2f64.powi(-200),
            "B = {w}: {g256:e} at 256 bits, {g512:e} at 512"
        );
    }
}

#[test]
fn a_pinned_circle_has_no_event_and_a_skipping_orbit_circles_its_disk() {
    let scene = triangular(0.3);
    let lat = scene.lattice::<f64>(()).unwrap();
    let geo = FieldGeometry::new(scene.disk_lattice().unwrap(), 10.0).unwrap();
    // The trap's centroid, radius 0.1: inside the free triangle, touching nothing.
    let (a, h) = (2.3, 2.3 * 3f64.sqrt() / 2.0);
    let pinned = LatticeState {
        cell: CellIndex::default(),
        flight: Flight::new(Vec2::new(a / 2.0, h / 3.0), Vec2::new(1.0, 0.0)),
    };
    assert!(lat.next_event_in_field(&pinned, &10.0).is_none());
    assert_eq!(geo.classify(a / 2.0, h / 3.0, 1.0, 0.0), Orbit::Pinned);
    // Leaving disk P₀ radially along (cos 30°, sin 30°) — into the trap — on a radius of 0.1:
    // the orbit bounces round P₀ for ever, within 1 + 2ρ of its centre.
    let v = Vec2::new(3f64.sqrt() / 2.0, 0.5);
    let mut s = LatticeState {
        cell: CellIndex::default(),
        flight: Flight {
            pos: v.clone(),
            vel: v.clone(),
            excluded_disk: Some(0),
            excluded_edge: None,
        },
    };
    assert_eq!(geo.classify(v.x, v.y, v.x, v.y), Orbit::Skipping);
    let (mut collisions, mut crossings) = (0, 0);
    for _ in 0..20_000 {
        match lat.step_in_field(&mut s, &10.0).unwrap().kind {
            EventKind::Collision(_) => collisions += 1,
            EventKind::Crossing(_) => crossings += 1,
        }
        let r = lat.world(&s).norm2().sqrt();
        assert!(r <= 1.2 + 1e-12, "left the annulus: {r}");
    }
    assert!(
        collisions > 5000 && crossings > 100,
        "{collisions} {crossings}"
    );
}

/// Pinned and skipping shares of phase points drawn from the invariant measure against the exact
/// shares: |f̂ − f| ≤ 4·√(f(1 − f)/n) + 1/n (the binomial 4σ bound; n = 2·10⁵ per case).
#[test]
fn sampled_localized_shares_agree_with_the_exact_ones() {
    let cases = [
        (0.1, 5.0),
        (0.1, 1.2),
        (0.3, 20.0),
        (0.3, 2.0),
        (0.3, 0.9),
        (0.5, 1.5),
    ];
    for (k, &(w, b)) in cases.iter().enumerate() {
        shares_agree(&triangular(w), b, 200 + k as u64);
    }
    for (k, &(r, b)) in [(0.25, 4.0), (0.1, 8.0)].iter().enumerate() {
        shares_agree(&SquareScene::new(r).unwrap(), b, 210 + k as u64);
    }
}

pub(super) fn shares_agree<S: Scene>(scene: &S, b: f64, seed: u64) {
    let lat = scene.lattice::<f64>(()).unwrap();
    let geo = FieldGeometry::new(scene.disk_lattice().unwrap(), b).unwrap();
    let n = 200_000u64;
    let (mut pinned, mut skipping) = (0.0, 0.0);
    for i in 0..n {
        let s = scene.sample(&mut stream(seed, i));
        let p = lat.world(&s);
        let sg = s.cell.sign();
        match geo.classify(p.x, p.y, sg * s.flight.vel.x, sg * s.flight.vel.y) {
            Orbit::Pinned => pinned += 1.0,
            Orbit::Skipping => skipping += 1.0,
            Orbit::Diffusing => {}
        }
    }
    let n = n as f64;
    for (what, count, exact) in [
        ("pinned", pinned, geo.pinned_fraction()),
        ("skipping", skipping, geo.skipping_fraction()),
    ] {
        let f = count / n;
        let bound = 4.0 * (exact * (1.0 - exact) / n).sqrt() + 1.0 / n;
        assert!(
            (f - exact).abs() <= bound,
            "{} B={b}: {what} {f} vs exact {exact} (bound {bound:e})",
            scene.label()
        );
    }
}

/// Nearly concentric circles (the cyclotron centre 10⁻¹² to 0.4ρ from the disk's centre, radii
/// within half that distance of each other, so they cut at an angle ~D/r): the contact is found
/// in the disk's frame, and the point reached, d + x evaluated exactly from the `f64` chord, is
/// on the disk to 16u(r + |d|) — |y| = r to about 6u, and the chord y − d and its sum with d
/// add 2u(r + |d|) — and on the cyclotron circle to 16u(r + |d| + ρ): the disk frame's
/// rounding along the circles, u(|ω||d| + V)/√M, times the angle √M/V at which they cut. The
/// radical-line form missed the disk by u/M (10⁸u at M = 2·10⁻⁹, the fourth libFuzzer
/// campaign). The velocity v + ωJx has |v|² = 1 to the same order.
#[test]
fn nearly_concentric_circles_meet_on_the_disk_to_a_few_u() {
    use lorentz_gas::kernel::arc::{Arc, velocity_along};
    let u = UNIT_ROUNDOFF;
    let mut rng = Gen::seed_from_u64(33);
    let (mut worst_disk, mut worst_cyc, mut tried) = (0.0f64, 0.0f64, 0);
    for n in 0..20_000 {
        let r: f64 = [1.0, 0.3, 2.5][n % 3];
        let rho = r * (1.0 + rng.random_range(-0.3..0.3f64) * 10f64.powi(-(n as i32 % 7)));
        let dist = (rho - r).abs() * 2.0 + r * 10f64.powf(rng.random_range(-12.0..-0.4f64));
        let dist = dist.min(0.4 * rho);
        if dist <= (rho - r).abs() * 1.5 {
            continue;
        }
        let (a, b) = (rng.random_range(0.0..6.3f64), rng.random_range(0.0..6.3f64));
        let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
        let w = sign / rho;
        // Cyclotron centre o (disk at the origin), particle at o + ρ(cos b, sin b); v = ωJ(p − o).
        let o = (dist * a.cos(), dist * a.sin());
        let d = Vec2::new(o.0 + rho * b.cos(), o.1 + rho * b.sin());
        let v = Vec2::new(-w * (d.y - o.1), w * (d.x - o.0));
        if d.norm2() <= r * r {
            continue;
        }
        let arc = Arc::new(&v, &w);
        let Some(c) = arc.contact(d.x, d.y, &r, &(r * r), false) else {
            panic!("no contact: r {r} rho {rho} dist {dist}");
        };
        assert!(c.disk_frame, "{dist} {rho}");
        let hi = |x: f64| Float::with_val(256, x);
        let (yx, yy) = (hi(d.x) + hi(c.chord.x), hi(d.y) + hi(c.chord.y));
        let on_disk = (Float::with_val(256, &yx * &yx + &yy * &yy).sqrt() - r)
            .to_f64()
            .abs();
        // The cyclotron centre from the f64 state: p + Jv/ω.
        let (ox, oy) = (hi(d.x) - hi(v.y) / hi(w), hi(d.y) + hi(v.x) / hi(w));
        let (ex, ey) = (yx - ox, yy - oy);
        let vv = hi(v.x) * hi(v.x) + hi(v.y) * hi(v.y);
        let rho_exact = Float::with_val(256, vv.sqrt() / hi(w).abs());
        let on_cyc = (Float::with_val(256, &ex * &ex + &ey * &ey).sqrt() - rho_exact)
            .to_f64()
            .abs();
        let scale = r + d.norm2().sqrt();
        tried += 1;
        worst_disk = worst_disk.max(on_disk / (u * scale));
        worst_cyc = worst_cyc.max(on_cyc / (u * (scale + rho)));
        let vel = velocity_along(&v, &c.chord, &w);
        assert!((vel.norm2() - v.norm2()).abs() < 16.0 * u * (1.0 + w.abs() * scale));
    }
    assert!(tried > 10_000, "{tried}");
    assert!(worst_disk < 16.0, "on the disk to {worst_disk} u(r + |d|)");
    assert!(
        worst_cyc < 16.0,
        "on the cyclotron circle to {worst_cyc} u(r + |d| + rho)"
    );
    println!("worst: disk {worst_disk:.2}, cyclotron circle {worst_cyc:.2}");
}
