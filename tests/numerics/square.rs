//! The square Lorentz gas (disks of radius 0 < r < 1/2 at unit spacing) on the generic cell
//! kernel: the checks every scene must pass.
//!
//! * Santaló's mean free path (1 − πr²)/(2r), within 4σ of batch means;
//! * no missed collision: every free flight, unwrapped into the world, misses every disk of the
//!   surrounding 5×5 block except the one it ends on (brute force at 256 bits);
//! * property tests per scalar type (f64, MPFR 128 bits), seeded and shrinking: energy
//!   ||v|² − 1| ≤ 128u·(1 + 1/(2r)) after every event, a crossing leaves v bit for bit (a translation), no
//!   post-event position inside the disk by more than 256u or outside the cell by more than
//!   256u, exclusions by identity, one-event reversal;
//! * reversibility of long orbits within the amplification bound, Liouville |det DT| = 1 of the
//!   Birkhoff map, the shadow audit with 0 events outside the error model.

use super::kernel_properties::assert_one_collision_reverses;
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::kernel::{flight::EventKind, flight::Flight};
use lorentz_gas::numbers::real::Real;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::LatticeState;
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::square::SquareScene;
use lorentz_gas::verification::error_model::{
    ENERGY_BAND_U, ONE_EVENT_U, POST_EVENT_U, UNIT_ROUNDOFF,
};
use proptest::prelude::*;
use rand::Rng;
use rug::{Float, Rational};

fn scene(r: f64) -> SquareScene {
    SquareScene::new(r).unwrap()
}

/// Mean free path: total flight time over collisions, 16 independent equilibrium batches of
/// 2·10⁵ collisions each at three radii; the batch means' standard error is the σ. (The infinite
/// horizon gives the free-path density an ℓ⁻³ tail, so ⟨ℓ²⟩ diverges logarithmically; at these
/// radii the corridors are narrow and the batch spread still measures the error — a "4σ" bound:
/// the Student-t quantile with 15 dof at the normal's 4σ tail probability, 5.48.)
#[test]
fn mean_free_path_is_santalos() {
    for (k, &r) in [0.1, 1.0 / 3.0, 0.45].iter().enumerate() {
        let s = scene(r);
        let lat = s.lattice::<f64>(()).unwrap();
        let means: Vec<f64> = (0..16u64)
            .map(|b| {
                let mut st = s.sample(&mut stream(71 + k as u64, b));
                let (mut t, mut c) = (0.0, 0u64);
                // Start the clock at the first collision (the first flight is not a free path).
                while !matches!(lat.step(&mut st).unwrap().kind, EventKind::Collision(_)) {}
                while c < 200_000 {
                    let ev = lat.step(&mut st).unwrap();
                    t += ev.time;
                    if let EventKind::Collision(_) = ev.kind {
                        c += 1;
                    }
                }
                t / c as f64
            })
            .collect();
        let n = means.len() as f64;
        let m = means.iter().sum::<f64>() / n;
        let se = (means.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
        let exact = s.mean_free_path();
        // The t-ratio of a mean over 16 batches has 15 dof: the crate's "4σ" rule.
        let bound = lorentz_gas::statistics::normal_sigma_equivalent_t(n - 1.0, 4.0);
        assert!(
            (m - exact).abs() < bound * se,
            "r = {r}: <l> = {m} ± {se}, Santalo {exact}"
        );
    }
}

/// Brute force at 256 bits: the world segment of every flight meets no disk of the 5×5 block of
/// integer points around its start, except at its end when the event is a collision.
#[test]
fn no_collision_is_missed() {
    let bits = 256;
    for (k, &r) in [0.05, 0.25, 0.49].iter().enumerate() {
        let s = scene(r);
        let lat = s.lattice::<Float>(bits).unwrap();
        let r2 = Float::with_val(bits, lat.cell().disks[0].radius2());
        let s64 = s.sample(&mut stream(81, k as u64));
        let mut st = LatticeState::<Float>::convert_from_f64(bits, &s64);
        for i in 0..20_000 {
            let a = lat.world(&st);
            let ev = lat.step(&mut st).unwrap();
            let b = lat.world(&st);
            let (ci, cj) = (st.cell.i, st.cell.j);
            for di in -2..=2i64 {
                for dj in -2..=2i64 {
                    let c = Vec2::new(
                        Float::with_val(bits, ci + di),
                        Float::with_val(bits, cj + dj),
                    );
                    // Distance² from c to the segment [a, b], minus r².
                    let ab = b.sub(&a);
                    let ac = c.sub(&a);
                    let l2 = ab.norm2();
                    let mut t = if l2.is_zero() {
                        Float::with_val(bits, 0)
                    } else {
                        ac.dot(&ab) / &l2
                    };
                    t = t.clamp(&0, &1);
                    let p = a.along(&t, &ab);
                    let gap = (p.sub(&c).norm2() - &r2).to_f64();
                    let ends_here =
                        matches!(ev.kind, EventKind::Collision(_)) && di == 0 && dj == 0;
                    if !ends_here {
                        assert!(
                            gap > -1e-60,
                            "r = {r} event {i}: flight crosses disk ({}, {}): {gap:e}",
                            ci + di,
                            cj + dj
                        );
                    }
                }
            }
        }
    }
}

/// A free start in the cell from three numbers in [0, 1) (a walk until outside the disk, so that
/// shrinking still acts on the inputs).
fn start(r: f64, u1: f64, u2: f64, u3: f64) -> Flight<f64> {
    let p = (0..256)
        .find_map(|i| {
            let x = (u1 + i as f64 * 0.618_033_988_749_895).fract() - 0.5;
            let y = (u2 + i as f64 * 0.414_213_562_373_095).fract() - 0.5;
            (x * x + y * y >= r * r).then(|| Vec2::new(x, y))
        })
        .unwrap_or(Vec2::new(0.5, 0.5));
    let ang = 2.0 * std::f64::consts::PI * u3;
    Flight::new(p, Vec2::new(ang.cos(), ang.sin()))
}

macro_rules! square_properties {
    ($name:ident, $t:ty, $ctx:expr, $cases:expr) => {
        mod $name {
            use super::*;
            at_precision!($t, $ctx);

            #[test]
            fn energy_cell_and_exclusions_hold_after_every_event() {
                crate::common::check_starts($cases, 9, 0.01f64..0.4999, |(r, u1, u2, u3)| {
                    let cell = scene(r).kernel::<T>(ctx()).unwrap();
                    let mut f = lift(&start(r, u1, u2, u3));
                    let tol = POST_EVENT_U * u();
                    for _ in 0..200 {
                        let v_in = f.vel.clone();
                        let ev = cell.next_event(&f).unwrap();
                        prop_assert!(ev.time.to_f64() >= 0.0);
                        cell.apply(&mut f, &ev);
                        // One reflection's rounding: 128u for the unit disks of the
                        // triangular trap; with |n| = r the contact point's absolute
                        // error u·(½ + t) is relative u(½ + t)/r, so the band widens by
                        // the factor 1 + 1/(2r) (proofs-notes/energy.md).
                        let e2 = f.vel.norm2().add_f64(-1.0).to_f64();
                        let band = ENERGY_BAND_U * u() * (1.0 + 0.5 / r);
                        prop_assert!(e2.abs() <= band, "|v|^2 - 1 = {e2:e}");
                        match ev.kind {
                            EventKind::Crossing(k) => {
                                // A translation: the velocity is untouched, bit for bit.
                                prop_assert!(f.vel == v_in, "crossing {k} changed v");
                                prop_assert_eq!(
                                    f.excluded_edge,
                                    Some(cell.edges[k as usize].entered)
                                );
                                prop_assert_eq!(f.excluded_disk, None);
                            }
                            EventKind::Collision(m) => {
                                prop_assert_eq!(f.excluded_disk, Some(m));
                                prop_assert_eq!(f.excluded_edge, None);
                            }
                        }
                        let d = (f.pos.sub(&cell.disks[0].centre).norm2()
                            - cell.disks[0].radius2())
                        .to_f64();
                        prop_assert!(d >= -tol, "inside the disk: {d:e}");
                        for k in 0..4 {
                            let s = cell.edge_distance(k, &f.pos).to_f64();
                            prop_assert!(s >= -tol, "outside edge {k}: {s:e}");
                        }
                    }
                    Ok(())
                });
            }

            #[test]
            fn single_event_reversal_returns_within_the_one_step_bound() {
                crate::common::check_starts($cases, 9, 0.01f64..0.4999, |(r, u1, u2, u3)| {
                    let cell = scene(r).kernel::<T>(ctx()).unwrap();
                    let mut f = lift(&start(r, u1, u2, u3));
                    // Fly to the first collision (crossings on the way are translations).
                    let ev = loop {
                        let ev = cell.next_event(&f).unwrap();
                        if matches!(ev.kind, EventKind::Collision(_)) {
                            break ev;
                        }
                        cell.apply(&mut f, &ev);
                    };
                    // Two reflections with |n| = r: the error scales like u/r.
                    let dv_max = 4.0 * ONE_EVENT_U * u() / r;
                    assert_one_collision_reverses(&cell, f, &ev, u(), dv_max)
                });
            }
        }
    };
}

square_properties!(f64_square, f64, (), 1000);
square_properties!(mpfr128_square, Float, 128, 150);

/// N collisions forward, reverse, N back: the error stays within the bound 2E·256u·max‖J‖ of
/// `proofs-notes/reversibility.md`, at f64 and at 256 bits.
#[test]
fn long_orbits_reverse_within_the_amplification_bound() {
    use super::verification::{Reversed, reversal_with_bound};
    use lorentz_gas::verification::reversibility::{reversal_bound, reverse_and_return};
    let s = scene(1.0 / 3.0);
    for k in 0..4u64 {
        let s64 = s.sample(&mut stream(91, k));
        for n in [5u64, 15] {
            let lat = s.lattice::<f64>(()).unwrap();
            let Reversed {
                r: rev,
                amp,
                events,
                bound,
            } = reversal_with_bound(&lat, &s64, n, UNIT_ROUNDOFF);
            assert!(
                rev.position_error <= bound,
                "f64 n={n}: {} > {bound:e}",
                rev.position_error
            );
            let lat = s.lattice::<Float>(256).unwrap();
            let st = LatticeState::<Float>::convert_from_f64(256, &s64);
            let rev = reverse_and_return(&lat, &st, n).unwrap();
            let bound = reversal_bound((-256f64).exp2(), events, amp);
            assert!(rev.position_error.to_f64() <= bound, "256 bits n={n}");
        }
    }
}

/// Liouville: |det DT| = 1 for the Birkhoff map, by central differences at 256 bits
/// (h = 2⁻⁹⁰; the error budget of `proofs-notes/liouville.md` with curvature 1/r ≤ 20).
#[test]
fn birkhoff_map_preserves_phase_space_volume() {
    let dets = super::verification::birkhoff_determinants(16, 92, |rng| {
        let r = 0.05 + 0.44 * rng.random::<f64>();
        let s = 2.0 * std::f64::consts::PI * rng.random::<f64>();
        (scene(r), format!("r = {r}"), s)
    });
    for (what, det) in dets {
        let dev = (det.abs() - 1u32).abs().to_f64();
        assert!(dev < 1e-30, "{what}: |det| - 1 = {dev:e}");
    }
}

/// The shadow audit on the square scene: 2·10⁵ collisions (about 6·10⁵ events) replayed at
/// 128 bits, none outside the one-step error model; the radius 1/3 is taken exactly, so the
/// reference runs at the exact radius while the f64 run uses its nearest double.
#[test]
fn shadow_audit_finds_nothing_outside_the_model() {
    let s = SquareScene::exact(Rational::from((1, 3))).unwrap();
    let r = crate::common::full_audit(&s, 200_000, 93, None, Default::default());
    crate::common::assert_audit_clean(&r, 200_000, "square r = 1/3");
}

/// The horizon is infinite for every radius, and the Einstein D is refused.
#[test]
fn diffusion_is_refused_in_the_square_scene() {
    let s = scene(0.45);
    assert!(!s.finite_horizon());
    let e = lorentz_gas::estimators::diffusion::require_finite_horizon(&s).unwrap_err();
    assert!(e.to_string().contains("lacks a finite horizon"), "{e}");
}

/// The event counters see every event of the square cell, whose four edges carry the event
/// codes CROSSING_CODE + 0 … 3: counted along a trajectory they equal the events stepped one by
/// one (with CROSSING_CODE = 3 and NO_EVENT = 6, edge 3's crossings had the code of "no event"
/// and a quarter of the crossings went uncounted — the audit's "12858197 events of 9688777").
#[test]
fn counters_see_every_crossing_of_the_four_edges() {
    use lorentz_gas::engine::drive;
    use lorentz_gas::observers::counters::CounterLanes;
    let sc = scene(0.01);
    let lat = sc.lattice::<f64>(()).unwrap();
    let start = sc.sample(&mut stream(4, 0));
    let (mut collisions, mut crossings, mut edges) = (0u64, 0u64, [0u64; 4]);
    let mut s = start.clone();
    while collisions < 2000 {
        match lat.step(&mut s).unwrap().kind {
            EventKind::Collision(_) => collisions += 1,
            EventKind::Crossing(k) => {
                crossings += 1;
                edges[k as usize] += 1;
            }
        }
    }
    assert!(edges.iter().all(|&n| n > 0), "{edges:?}");
    let mut counters = CounterLanes::new(1);
    let mut s = start;
    drive(&lat, &mut s, 2000, &mut counters, &|_| {}).unwrap();
    let c = counters.lane(0);
    assert_eq!((c.collisions, c.crossings), (collisions, crossings));
}
