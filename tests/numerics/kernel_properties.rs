//! Property tests of the kernel, one suite instantiated per scalar type (f64, MPFR 128 and
//! 256 bits), with tolerances scaled by each type's unit roundoff u. Seeded (proptest's
//! ChaCha runner with a fixed seed) and shrinking.
//!
//! Bounds (proofs-notes/error-model.md):
//! * energy: after every event ||v|² − 1| ≤ 128u (one reflection's rounding; the Newton factor
//!   removes the incoming deviation); a crossing negates v exactly, so |v|² is unchanged bit for
//!   bit;
//! * a post-event position is never inside a disk by more than 256u (|x − c|² ≥ 1 − 256u);
//! * a post-event position is within 256u·a of the closed triangle.

use lorentz_gas::kernel::cell::CellKernel;
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::kernel::{flight::Event, flight::EventKind, flight::Flight, trap::Trap};
use lorentz_gas::numbers::real::Real;
use lorentz_gas::verification::error_model::{ENERGY_BAND_U, ONE_EVENT_U, POST_EVENT_U};
use proptest::prelude::*;
use proptest::test_runner::{TestCaseError, TestRunner};
use rug::Float;

/// A free start in the canonical trap from three numbers in [0, 1): position by reflection of
/// the unit square onto the triangle, direction angle 2π·u₃ (in f64: inputs, not kernel code).
fn start(w: f64, u1: f64, u2: f64, u3: f64) -> Option<Flight<f64>> {
    let t = Trap::new(w).ok()?;
    // A deterministic additive-recurrence walk from (u1, u2) until the point is free, so that
    // shrinking still acts on the inputs and every case is used.
    let p = (0..256).find_map(|i| {
        let (mut a, mut b) = (
            (u1 + i as f64 * 0.618_033_988_749_895).fract(),
            (u2 + i as f64 * 0.414_213_562_373_095).fract(),
        );
        if a + b > 1.0 {
            a = 1.0 - a;
            b = 1.0 - b;
        }
        let p = Vec2::new(a * t.a() + b * t.a() * 0.5, b * t.h());
        t.is_free(&p).then_some(p)
    })?;
    let ang = 2.0 * std::f64::consts::PI * u3;
    Some(Flight::new(p, Vec2::new(ang.cos(), ang.sin())))
}

fn runner(cases: u32) -> TestRunner {
    crate::common::runner(cases, 7)
}

/// Carries out the collision `ev` of `f` on `kernel`, reverses and takes the next event: the same
/// collision at zero time (within ONE_EVENT_U·u), after which the velocity is −v₀ within `dv_max`
/// and the position has moved by at most ONE_EVENT_U·u.
pub(crate) fn assert_one_collision_reverses<T: Real, K: CellKernel<T>>(
    kernel: &K,
    mut f: Flight<T>,
    ev: &Event<T>,
    u: f64,
    dv_max: f64,
) -> Result<(), TestCaseError> {
    let v0 = f.vel.clone();
    kernel.apply(&mut f, ev);
    let x1 = f.pos.clone();
    f.reverse();
    let back = kernel.next_event(&f).unwrap();
    prop_assert_eq!(back.kind, ev.kind);
    prop_assert!(
        back.time.to_f64() <= ONE_EVENT_U * u,
        "re-collision at t = {:e}",
        back.time.to_f64()
    );
    kernel.apply(&mut f, &back);
    let dv = Vec2::new(f.vel.x.clone() + &v0.x, f.vel.y.clone() + &v0.y)
        .norm2()
        .sqrt()
        .to_f64();
    prop_assert!(dv <= dv_max, "velocity error {dv:e}");
    let dx = f.pos.sub(&x1).norm2().sqrt().to_f64();
    prop_assert!(dx <= ONE_EVENT_U * u, "position moved by {dx:e}");
    Ok(())
}

macro_rules! kernel_properties {
    ($name:ident, $t:ty, $ctx:expr, $cases:expr) => {
        mod $name {
            use super::*;
            at_precision!($t, $ctx);

            /// The trap at gap `w` and the start `start(w, u1, u2, u3)` lifted to it, if any.
            fn trap_and_start(w: f64, u1: f64, u2: f64, u3: f64) -> Option<(Trap<T>, Flight<T>)> {
                let f64s = start(w, u1, u2, u3)?;
                Some((Trap::new(T::from_f64(ctx(), w)).unwrap(), lift(&f64s)))
            }

            #[test]
            fn energy_positions_and_exclusions_over_twenty_events() {
                crate::common::check_starts($cases, 7, 0.001f64..0.309, |(w, u1, u2, u3)| {
                    let Some((trap, mut f)) = trap_and_start(w, u1, u2, u3) else {
                        return Ok(());
                    };
                    let tol = POST_EVENT_U * u();
                    for _ in 0..20 {
                        let v_in = f.vel.clone();
                        let e2 = v_in.norm2();
                        let ev = trap
                            .next_event(&f)
                            .expect("a unit velocity always has an event");
                        prop_assert!(!ev.time.lt0(), "negative flight time");
                        trap.apply(&mut f, &ev);
                        let e2b = f.vel.norm2();
                        // |v|² − 1 is formed in T before rounding to f64: rounding |v|²
                        // itself to f64 would read every MPFR deviation below 2⁻⁵³ as 0.
                        let eta = e2b.clone().add_f64(-1.0).to_f64();
                        prop_assert!(
                            eta.abs() <= ENERGY_BAND_U * u(),
                            "|v|^2 - 1 = {:e} = {:.1}u after {:?} (before: {:e})",
                            eta,
                            eta / u(),
                            ev.kind,
                            e2.clone().add_f64(-1.0).to_f64()
                        );
                        // A crossing is a point reflection: v ↦ −v exactly, so |v|² is
                        // unchanged bit for bit (no rounding may enter; the 128u band
                        // would hide one).
                        if let EventKind::Crossing(k) = ev.kind {
                            prop_assert!(
                                f.vel.x == -v_in.x.clone() && f.vel.y == -v_in.y.clone(),
                                "crossing {k} changed v beyond a sign: {:?} -> {:?}",
                                v_in,
                                f.vel
                            );
                            prop_assert!(
                                e2b == e2,
                                "crossing {k} changed |v|^2 by {:e}u",
                                (e2b.clone() - e2.clone()).to_f64() / u()
                            );
                        }
                        for c in trap.vertices() {
                            // |x − c|² − 1 in T (as for the energy: 1 − 256u is 1 in f64).
                            let d = f.pos.sub(c).norm2().add_f64(-1.0).to_f64();
                            prop_assert!(d >= -tol, "inside a disk: |x-c|^2 - 1 = {d:e}");
                        }
                        for k in 0..3 {
                            let s = trap.edge_distance(k, &f.pos).to_f64();
                            prop_assert!(s >= -tol * trap.a().to_f64(), "outside edge {k}: {s:e}");
                        }
                        match ev.kind {
                            EventKind::Collision(m) => {
                                prop_assert_eq!(f.excluded_disk, Some(m))
                            }
                            EventKind::Crossing(k) => {
                                prop_assert_eq!(f.excluded_edge, Some(k))
                            }
                        }
                    }
                    Ok(())
                });
            }

            #[test]
            fn single_event_reversal_returns_within_the_one_step_bound() {
                // Forward one collision, reverse, one collision back (at zero time): the velocity
                // returns to −v₀ within 4·256u (two reflections), the position stays put.
                crate::common::check_starts($cases, 7, 0.01f64..0.3, |(w, u1, u2, u3)| {
                    let Some((trap, f)) = trap_and_start(w, u1, u2, u3) else {
                        return Ok(());
                    };
                    let ev = trap.next_event(&f).unwrap();
                    if !matches!(ev.kind, EventKind::Collision(_)) {
                        return Ok(());
                    }
                    assert_one_collision_reverses(&trap, f, &ev, u(), 4.0 * ONE_EVENT_U * u())
                });
            }
        }
    };
}

kernel_properties!(f64_kernel, f64, (), 2000);
kernel_properties!(mpfr128_kernel, Float, 128, 300);
kernel_properties!(mpfr256_kernel, Float, 256, 200);

/// The property runner shrinks: a deliberately false property is reduced to a minimal case.
#[test]
fn the_runner_shrinks_failures() {
    let r = runner(256).run(&(0u64..1_000_000), |n| {
        prop_assert!(n < 1000);
        Ok(())
    });
    match r {
        Err(proptest::test_runner::TestError::Fail(_, n)) => assert_eq!(n, 1000, "shrunk to {n}"),
        other => panic!("expected a shrunk failure, got {other:?}"),
    }
}
