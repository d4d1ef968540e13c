//! The shadow audit of arcs (`verification::arc_audit`, `proofs-notes/magnetic-audit.md`): every
//! sampled `f64` arc event replayed on tracked numbers, judged against the running error bound of
//! its own computation.
//!
//! * production trajectories at w = 0.1 and 0.3 (and the square scene) in fields 1/10, 1, 10 and
//!   −3: nothing outside the bound, and the bound is not vacuous (its median is a few u);
//! * the audit catches a kernel that is off: an `f64` lattice at a gap 10⁻¹² from the exact one
//!   puts most events outside;
//! * the recorded worst events replay to their verdict.

use lorentz_gas::numbers::real::Real;
use lorentz_gas::numbers::tracked::Tracked;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::square::SquareScene;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::verification::arc_audit::{check_arc_event, recorded_state};
use lorentz_gas::verification::shadow_audit::AuditReport;
use rug::Rational;

fn audit<S: Scene>(scene: &S, field: &str, collisions: u64, seed: u64) -> AuditReport {
    crate::common::full_audit(scene, collisions, seed, Some(field), Default::default())
}

/// Every replayed arc event inside its running bound, with the bound a few u at the median
/// (a bound of ∞ would pass anything) and the events the run flew all audited.
#[test]
fn audit_of_arc_trajectories_finds_nothing_outside_the_running_bound() {
    let square = SquareScene::exact(Rational::from((1, 3))).unwrap();
    let mut runs = Vec::new();
    for (i, field) in ["1/10", "1", "10", "-3"].iter().enumerate() {
        for w in [0.1, 0.3] {
            let scene = TriangularScene::new(w).unwrap();
            runs.push((
                scene.label(),
                *field,
                audit(&scene, field, 10_000, 40 + i as u64),
            ));
        }
        runs.push((
            square.label(),
            *field,
            audit(&square, field, 10_000, 50 + i as u64),
        ));
    }
    for (label, field, r) in &runs {
        let s = &r.summary;
        assert_eq!(s.audited, r.events, "{label} B={field}");
        assert!(s.audited >= 10_000, "{label} B={field}: {}", s.audited);
        assert_eq!(
            s.outside,
            0,
            "{label} B={field}: {:?}",
            s.outside_events.first()
        );
        let pos = r.quantiles.position_error_over_bound.unwrap();
        assert!(pos.max <= 1.0, "{label} B={field}: {pos:?}");
        assert!(
            s.ambiguous * 100 < s.audited,
            "{label} B={field}: {}",
            s.ambiguous
        );
        let bound = s
            .worst
            .iter()
            .map(|e| e.check.position_bound)
            .fold(0.0, f64::max);
        assert!(
            bound < 1e-12,
            "{label} B={field}: worst events' bound {bound}"
        );
    }
}

/// A kernel off by 10⁻¹² in the gap is caught: its events leave the bound of the exact one.
#[test]
fn audit_catches_an_f64_kernel_off_by_a_picometre() {
    let exact = TriangularScene::new(0.1).unwrap();
    let off = TriangularScene::new(0.1 + 1e-12).unwrap();
    let lat64 = off.lattice::<f64>(()).unwrap();
    let lat_t = exact.lattice::<Tracked>(128).unwrap();
    let b = Tracked::from_rational(128, &Rational::from(1));
    let mut rng = lorentz_gas::scenes::sampling::stream(3, 0);
    let (mut outside, mut n) = (0, 0);
    while n < 200 {
        let mut s = off.sample(&mut rng);
        for _ in 0..10 {
            let Some(ev) = lat64.next_event_in_field(&s, &1.0) else {
                break;
            };
            let c = check_arc_event(&lat64, &lat_t, &s, 1.0, &b).unwrap();
            outside += usize::from(!c.in_model);
            n += 1;
            lat64.apply_in_field(&mut s, &ev);
        }
    }
    assert!(outside * 2 > n, "{outside} of {n} outside");
}

/// The worst events of a run, replayed from their bit patterns, give the same verdict.
#[test]
fn worst_arc_events_replay_to_their_verdict() {
    let scene = TriangularScene::new(0.2).unwrap();
    let r = audit(&scene, "1", 5_000, 61);
    let lat64 = scene.lattice::<f64>(()).unwrap();
    let lat_t = scene.lattice::<Tracked>(128).unwrap();
    let b = Tracked::from_rational(128, &Rational::from(1));
    assert!(!r.summary.worst.is_empty());
    for e in &r.summary.worst {
        let s = recorded_state(e);
        let c = check_arc_event(&lat64, &lat_t, &s, 1.0, &b).unwrap();
        assert_eq!(c.position_error, e.check.position_error);
        assert_eq!(c.in_model, e.check.in_model);
    }
}
