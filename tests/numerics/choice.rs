//! Choosing before dividing (`kernel::choice`, `proofs-notes/choose-before-dividing.md`: the rule
//! of the SIMD engine, in its scalar form `Trap::next_event_chosen`) finds the event the full
//! comparison finds — every disk root and every edge quotient computed, the
//! smallest rounded time taken in the offer order — with the same bits, on random starts at gaps
//! from 2⁻²⁰ to beyond w∞, and on starts aimed at the near-ties the argument has to exclude.

use lorentz_gas::kernel::choice::{Choice, DISK_GAP_MIN};
use lorentz_gas::kernel::flight::{EventKind, Flight};
use lorentz_gas::kernel::ray_disk::ray_circle_centred;
use lorentz_gas::kernel::trap::Trap;
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::numbers::real::Real;
use lorentz_gas::scenes::lattice::{CellIndex, LatticeState};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus as Gen;
use rug::Float;

/// Compares the choice ([`Trap::next_event_chosen`]) with the full comparison (the generic
/// kernel, `ConvexCell::next_event`: every root and every quotient, offered in order) and the
/// fused trap on `f`, then follows the flight for `events` events. Returns the number of events
/// compared.
fn follow<T: Real>(trap: &Trap<T>, mut f: Flight<T>, events: usize, what: &str) -> usize {
    for k in 0..events {
        let want = trap.cell().next_event(&f);
        let chosen = trap.next_event_chosen(&f);
        assert_eq!(chosen, want, "{what}: event {k} (chosen) from {f:?}");
        assert_eq!(
            trap.next_event(&f),
            want,
            "{what}: event {k} (kernel) from {f:?}"
        );
        match want {
            Some(ev) => trap.apply(&mut f, &ev),
            None => return k,
        }
    }
    events
}

/// A uniform point of the free trap and a uniform direction.
pub(crate) fn free_start(trap: &Trap<f64>, rng: &mut Gen) -> Flight<f64> {
    loop {
        let (u, v): (f64, f64) = (rng.random(), rng.random());
        let (u, v) = if u + v > 1.0 {
            (1.0 - u, 1.0 - v)
        } else {
            (u, v)
        };
        let p = Vec2::new(trap.a() * (u + v / 2.0), trap.h() * v);
        if trap.is_free(&p) {
            let phi = rng.random::<f64>() * std::f64::consts::TAU;
            return Flight::new(p, Vec2::new(phi.cos(), phi.sin()));
        }
    }
}

const GAPS: [f64; 8] = [
    DISK_GAP_MIN * (1.0 + 1.0 / 256.0),
    1e-5,
    1e-3,
    0.02,
    0.1,
    0.3,
    0.6,
    1.9,
];

#[test]
fn choose_first_matches_every_root_on_random_starts() {
    let mut rng = Gen::seed_from_u64(21);
    let mut n = 0;
    for w in GAPS {
        let trap = Trap::new(w).unwrap();
        assert!(trap.choice().disks_by_beta, "w = {w:e}");
        let trap256 = Trap::new(Float::with_val(256, w)).unwrap();
        for s in 0..40 {
            let f = free_start(&trap, &mut rng);
            n += follow(&trap, f.clone(), 2_000, &format!("w = {w:e} start {s}"));
            if s < 2 {
                let f256 = Flight::<Float>::convert_from_f64(256, &f);
                follow(
                    &trap256,
                    f256,
                    200,
                    &format!("w = {w:e} start {s} at 256 bits"),
                );
            }
        }
    }
    assert_eq!(n, GAPS.len() * 40 * 2_000);
}

/// Unit vector at angle `phi`.
fn dir(phi: f64) -> Vec2<f64> {
    Vec2::new(phi.cos(), phi.sin())
}

/// a + k·b.
fn plus(a: &Vec2<f64>, k: f64, b: &Vec2<f64>) -> Vec2<f64> {
    Vec2::new(a.x + k * b.x, a.y + k * b.y)
}

/// Starts on lines that cut two disks about as closely after each other as lines can: through
/// the midpoint of their centres at an angle ψ to the centre line just below the inner common
/// tangent's (sin ψ = 2/|cᵢ − cⱼ|), so that both disks are barely cut and their entries are
/// √(|cᵢ − cⱼ|² − 4) ≈ 2√w apart. Both orientations, every pair, ψ short of the tangent by
/// 10⁻¹⁶ to 10⁻² (relative), from several distances before the midpoint.
fn two_disk_starts(trap: &Trap<f64>) -> Vec<Flight<f64>> {
    let mut out = Vec::new();
    for (i, j) in [(0, 1), (1, 2), (2, 0), (1, 0), (2, 1), (0, 2)] {
        let (ci, cj) = (&trap.vertices()[i], &trap.vertices()[j]);
        let d = cj.sub(ci);
        let dist = d.norm2().sqrt();
        let base = d.y.atan2(d.x);
        let mid = plus(ci, 0.5, &d);
        let tangent = (2.0 / dist).asin();
        // Half the inner tangent's length between its two contacts.
        let half = (dist * dist / 4.0 - 1.0).sqrt();
        for e in -16..=-2 {
            for side in [-1.0, 1.0] {
                let along = dir(base + side * tangent * (1.0 - 10f64.powi(e)));
                for back in [1e-2, 0.1, 0.3] {
                    let p = plus(&mid, -(half + back), &along);
                    if trap.is_free(&p) {
                        out.push(Flight::new(p, along.clone()));
                    }
                }
            }
        }
    }
    out
}

/// Starts that aim at the places where the choice could differ from the full comparison:
/// lines that barely cut two disks, corners (both edge lines crossed at once), flights along an
/// edge through its gap, and rim starts leaving a disk at grazing angles.
pub(crate) fn aimed_starts(trap: &Trap<f64>) -> Vec<Flight<f64>> {
    let mut out = two_disk_starts(trap);
    let centroid = Vec2::new(trap.a() / 2.0, trap.h() / 3.0);
    for c in trap.vertices() {
        for k in -8..=8 {
            let v = c.sub(&centroid);
            let phi = v.y.atan2(v.x) + k as f64 * 1e-9;
            out.push(Flight::new(centroid.clone(), dir(phi)));
        }
    }
    for m in 0..3 {
        // Along edge m's gap, leaving through the corner disks at tiny angles.
        let (i, j) = ((m + 1) % 3, (m + 2) % 3);
        let (ci, cj) = (&trap.vertices()[i], &trap.vertices()[j]);
        let mid = plus(ci, 0.5, &cj.sub(ci));
        let d = cj.sub(ci);
        let base = d.y.atan2(d.x);
        for k in -6..=6 {
            let tilt = k as f64 * 1e-12;
            for phi in [base + tilt, base + std::f64::consts::PI + tilt] {
                let mut f = Flight::new(mid.clone(), dir(phi));
                f.excluded_edge = Some(m as u8);
                out.push(f);
            }
        }
    }
    for m in 0..3u8 {
        let c = &trap.vertices()[m as usize];
        for k in 0..64 {
            let theta = k as f64 * std::f64::consts::TAU / 64.0;
            let rim = plus(c, 1.0, &dir(theta));
            if !trap.is_free(&rim) {
                continue;
            }
            for eps in [1e-15, 1e-9, 1e-4] {
                for side in [-1.0, 1.0] {
                    let phi = theta + side * (std::f64::consts::FRAC_PI_2 - eps);
                    let mut f = Flight::new(rim.clone(), dir(phi));
                    f.excluded_disk = Some(m);
                    out.push(f);
                }
            }
        }
    }
    out
}

/// The smallest difference between the two earliest disk entry times over the starts' first
/// events (∞ if no start has two disks ahead).
fn closest_disk_pair(trap: &Trap<f64>, starts: &[Flight<f64>]) -> f64 {
    let mut closest = f64::INFINITY;
    for f in starts {
        let mut t: Vec<f64> = (0..3u8)
            .filter(|&m| f.excluded_disk != Some(m))
            .filter_map(|m| {
                let c = &trap.vertices()[m as usize];
                ray_circle_centred(f.pos.x - c.x, f.pos.y - c.y, &f.vel, &f.vel.norm2(), &1.0)
            })
            .collect();
        t.sort_by(f64::total_cmp);
        if t.len() >= 2 {
            closest = closest.min(t[1] - t[0]);
        }
    }
    closest
}

#[test]
fn near_ties_aimed_at_the_argument() {
    let (mut n, mut total) = (0, 0);
    for w in [DISK_GAP_MIN * (1.0 + 1.0 / 256.0), 1e-5, 0.1, 0.3] {
        let trap = Trap::new(w).unwrap();
        let trap53 = Trap::new(Float::with_val(53, w)).unwrap();
        let pairs = two_disk_starts(&trap);
        let starts = aimed_starts(&trap);
        eprintln!(
            "w = {w:e}: {} two-disk starts, {} in all",
            pairs.len(),
            starts.len()
        );
        assert!(
            pairs.len() >= 100,
            "{} two-disk starts at w = {w:e}",
            pairs.len()
        );
        // They bring two disks' entries within about 2√w of each other, the closest two valid
        // disks can come (proofs-notes/choose-before-dividing.md).
        let closest = closest_disk_pair(&trap, &pairs);
        eprintln!(
            "  closest two disk entries: {closest:e} (2√w = {:e})",
            2.0 * w.sqrt()
        );
        assert!(closest < 3.0 * w.sqrt(), "w = {w:e}: closest {closest:e}");
        total += starts.len();
        for (s, f) in starts.iter().enumerate() {
            n += follow(&trap, f.clone(), 6, &format!("w = {w:e} aimed start {s}"));
            let f53 = Flight::<Float>::convert_from_f64(53, f);
            follow(
                &trap53,
                f53,
                6,
                &format!("w = {w:e} aimed start {s} at 53 bits"),
            );
        }
    }
    assert_eq!(n, 6 * total, "every aimed start ran its six events");
}

/// Below 2⁻²⁰ the kernel computes every root: it agrees with the full comparison there too, on
/// the same aimed starts, and the choice says so.
#[test]
fn below_the_gap_every_root_is_computed() {
    for w in [1e-9, DISK_GAP_MIN * (1.0 - 1.0 / 256.0)] {
        let trap = Trap::new(w).unwrap();
        assert!(!trap.choice().disks_by_beta, "w = {w:e}");
        for (s, f) in aimed_starts(&trap).into_iter().enumerate() {
            follow(&trap, f, 6, &format!("w = {w:e} aimed start {s}"));
        }
    }
    assert!(
        Choice::<f64>::new((), None, &0.25).disks_by_beta,
        "one disk"
    );
}

/// Edge near-ties the certificate cannot decide: a start at a corner (σ = 0 on both edges it
/// leaves by, products 0 = 0) takes the lower edge, as the full comparison does — on the scalar
/// kernel and on every SIMD path (where the fallback is a branch).
#[test]
fn undecided_edges_fall_back_to_the_quotients() {
    let trap = Trap::new(0.1).unwrap();
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let mut starts = Vec::new();
    for (m, v) in [
        (0u8, Vec2::new(-s, -s)),
        (1, Vec2::new(s, -s)),
        (2, Vec2::new(0.0, 1.0)),
    ] {
        let mut f = Flight::new(trap.vertices()[m as usize].clone(), v);
        f.excluded_disk = Some(m);
        let ev = trap.cell().next_event(&f).unwrap();
        assert_eq!(ev.time, 0.0, "corner {m}");
        assert_eq!(trap.next_event_chosen(&f), Some(ev.clone()), "corner {m}");
        starts.push(f);
    }
    // Corner 0, leaving through edges 1 and 2 at t = 0: the lower label, edge 1.
    assert_eq!(
        trap.next_event_chosen(&starts[0]).unwrap().kind,
        EventKind::Crossing(1)
    );
    let states: Vec<LatticeState<f64>> = starts
        .into_iter()
        .map(|flight| LatticeState {
            cell: CellIndex {
                i: 0,
                j: 0,
                down: false,
            },
            flight,
        })
        .collect();
    let quotas = vec![3; states.len()];
    for path in super::engine::available_paths("undecided_edges_fall_back_to_the_quotients") {
        super::engine::compare(path, 0.1, &states, &quotas);
    }
}

/// The note's error model of a grazing entry (`proofs-notes/choose-before-dividing.md`): rays
/// that pass disk P₁ at impact parameters 1 ± 10⁻ᵏ (k = 3..=18), in 256 directions, from 0.01
/// to 2 before the closest approach. Each f64 entry time must be within E_t = 2.2·10⁻⁷ of the
/// exact entry time of the disk enlarged by ε = 28u, the bound on Δ's rounding. The reference is
/// computed at 256 bits from the same f64 inputs. Where the f64 root reports a hit of a line
/// that truly misses, it is compared with the enlarged disk's entry, which that line does cut.
#[test]
fn grazing_entry_times_are_within_the_notes_bound() {
    let trap = Trap::new(0.1).unwrap();
    let c = trap.vertices()[1].clone();
    let eps = 28.0 * f64::EPSILON / 2.0;
    let rho2 = Float::with_val(256, 1.0 + eps).square();
    let (mut worst, mut n, mut misses) = (0.0f64, 0, 0);
    for i in 0..256 {
        let phi = i as f64 * std::f64::consts::TAU / 256.0;
        let (along, across) = (dir(phi), dir(phi + std::f64::consts::FRAC_PI_2));
        for k in 3..=18 {
            for b in [1.0 - 10f64.powi(-k), 1.0 + 10f64.powi(-k)] {
                for back in [0.01, 0.3, 1.0, 2.0] {
                    let p = plus(&plus(&c, b, &across), -back, &along);
                    let (dx, dy) = (p.x - c.x, p.y - c.y);
                    let Some(t) = ray_circle_centred(dx, dy, &along, &along.norm2(), &1.0)
                        .filter(|&t| t > 0.0)
                    else {
                        continue;
                    };
                    // Exact offset and velocity at 256 bits; the enlarged disk's entry.
                    let f = |x: f64| Float::with_val(256, x);
                    let (ex, ey) = (f(p.x) - f(c.x), f(p.y) - f(c.y));
                    let (vx, vy) = (f(along.x), f(along.y));
                    let vv = vx.clone().square() + vy.clone().square();
                    let beta = ex.clone() * &vx + ey.clone() * &vy;
                    let q2 = (ex * &vy - ey * &vx).square();
                    if q2 >= vv {
                        misses += 1;
                    }
                    let disc = vv.clone() * &rho2 - q2;
                    assert!(
                        disc > 0,
                        "a reported hit misses the enlarged disk: p = {p:?}"
                    );
                    let exact = (-beta - disc.sqrt()) / vv;
                    worst = worst.max((t - exact.to_f64()).abs());
                    n += 1;
                }
            }
        }
    }
    eprintln!("{n} grazing entries ({misses} of lines outside the disk), worst error {worst:e}");
    assert!(n > 10_000 && misses >= 50, "{n} entries, {misses} misses");
    assert!(
        worst <= 2.2e-7,
        "worst grazing entry error {worst:e} above the note's E_t"
    );
}
