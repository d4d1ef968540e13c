//! Long flights on the triangular lattice beyond w∞ (`scenes::long_flight::triangular`,
//! `proofs-notes/long-flights.md`, "The triangular lattice"): the audit replays every jump by
//! the MPFR trap walk and finds none outside its model, and it sees a landing off the line.

use lorentz_gas::engine::long_flight::Flights;
use lorentz_gas::kernel::flight::EventKind;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::CellIndex;
use lorentz_gas::scenes::long_flight::LongFlights;
use lorentz_gas::scenes::long_flight::triangular::{Search, trigger};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::verification::jump_audit_triangular::check_jump;
use lorentz_gas::verification::lyapunov::{self, LyapunovConfig, LyapunovReport};
use lorentz_gas::verification::shadow_audit::AuditReport;
use rug::Rational;

fn audit(w: &str, collisions: u64, flights: Flights) -> AuditReport {
    let scene = TriangularScene::exact(w.parse::<Rational>().unwrap()).unwrap();
    crate::common::full_audit(&scene, collisions, 41, None, flights)
}

/// Every jump of runs at w = 1, 10 and 1000 (just beyond w∞ the jumps are rare, at w = 1000 every
/// flight jumps) replayed by the MPFR trap walk: none outside the model, the events between them
/// inside the one-step model. Walking, nothing is jumped.
#[test]
fn audits_of_triangular_jumps_find_nothing_outside_the_model() {
    for (w, collisions, least) in [
        ("1", 20_000, 1_000),
        ("10", 20_000, 10_000),
        ("1000", 4_000, 3_900),
    ] {
        let r = audit(w, collisions, Flights::Jump);
        let j = &r.summary.triangular_jumps;
        assert_eq!(r.flights, Flights::Jump);
        assert!(j.audited >= least, "w = {w}: {} jumps", j.audited);
        assert_eq!(j.outside, 0, "w = {w}: {:?}", j.outside_jumps.first());
        assert_eq!(
            r.summary.outside,
            0,
            "w = {w}: {:?}",
            r.summary.outside_events.first()
        );
        println!(
            "w = {w}: {} jumps, {} crossings, time/bound max {:.3}, landing/bound max {:.3}",
            j.audited, j.crossings, j.time_error_over_bound.max, j.position_error_over_bound.max
        );
    }
    let r = audit("10", 2_000, Flights::Walk);
    assert_eq!(
        (r.flights, r.summary.triangular_jumps.audited),
        (Flights::Walk, 0)
    );
}

/// The audit is not blind: a landing moved along its edge by 10⁻¹⁰ of the spacing, or its time
/// by 10⁻¹⁰, is outside the model, while the landing itself is inside.
#[test]
fn a_landing_off_the_line_is_outside_the_audits_model() {
    let scene = TriangularScene::exact(Rational::from(30)).unwrap();
    let Some(LongFlights::Triangular(t)) = scene.long_flights() else {
        panic!("w = 30 has long flights");
    };
    let kref = scene.kernel::<rug::Float>(128).unwrap();
    let lat = scene.lattice::<f64>(()).unwrap();
    let mut rng = stream(5, 0);
    let (mut checked, mut s) = (0, scene.sample(&mut rng));
    while checked < 20 {
        let ev = lat.next_event(&s).unwrap();
        let about_to_jump = ev.kind == EventKind::Crossing(trigger(&s.flight.vel));
        let landing = match t.jump(CellIndex::default(), &s.flight) {
            Search::Land(l) if about_to_jump => l,
            _ => {
                lat.apply(&mut s, &ev);
                continue;
            }
        };
        let f = &s.flight;
        let c = check_jump(&kref, &t, f, &landing).unwrap();
        assert!(c.in_model, "{c:?}");
        let mut moved = landing.clone();
        let d = 1e-10 * t.a;
        moved.flight.pos.x += d * f.vel.y.signum();
        assert!(!check_jump(&kref, &t, f, &moved).unwrap().in_model);
        let mut late = landing.clone();
        late.time *= 1.0 + 1e-10;
        assert!(!check_jump(&kref, &t, f, &late).unwrap().in_model);
        checked += 1;
        lat.apply(&mut s, &ev);
    }
}

fn lyapunov_at(w: &str, flights: Flights, collisions: u64, batches: u32) -> LyapunovReport {
    let scene = TriangularScene::exact(w.parse::<Rational>().unwrap()).unwrap();
    let cfg = LyapunovConfig {
        collisions_per_batch: collisions,
        batches,
        seed: 43,
        flights,
        motion: Default::default(),
    };
    lyapunov::run(&scene, &cfg, &crate::common::threads(2)).unwrap()
}

/// At w = 30 the exponent per collision and per unit time of runs that jump and runs that walk
/// (independent streams of flights: the jumps' landings are not the walk's bits) agree within the
/// Student-t 4σ-equivalent of their Welch difference; `auto` walks below a = 8 and jumps from it.
#[test]
fn walking_and_jumping_give_one_exponent_beyond_w_inf() {
    let walk = lyapunov_at("30", Flights::Walk, 100_000, 8);
    let jump = lyapunov_at("30", Flights::Jump, 100_000, 8);
    assert_eq!((walk.flights, jump.flights), (Flights::Walk, Flights::Jump));
    let per_collision = (walk.per_collision, walk.per_collision_err);
    let per_time = (walk.per_time, walk.per_time_err);
    for ((a, ea), (b, eb)) in [
        (per_collision, (jump.per_collision, jump.per_collision_err)),
        (per_time, (jump.per_time, jump.per_time_err)),
    ] {
        let (z, t4) = (
            (a - b).abs() / ea.hypot(eb),
            crate::common::t4_welch(ea, 8, eb, 8),
        );
        assert!(
            z < t4,
            "walk {a} ± {ea}, jumps {b} ± {eb}: {z:.2}σ (bound {t4:.2})"
        );
    }
    let auto = |w: &str| {
        let scene = TriangularScene::exact(w.parse::<Rational>().unwrap()).unwrap();
        Flights::Auto.resolve(&scene).unwrap()
    };
    assert_eq!(
        (auto("1/2"), auto("5"), auto("6"), auto("1000")),
        (Flights::Walk, Flights::Walk, Flights::Jump, Flights::Jump)
    );
    // Beyond a = 2^20 the trap kernel cannot resolve a disk: no long flights.
    let huge = TriangularScene::exact(Rational::from(1u64 << 21)).unwrap();
    assert!(huge.long_flights().is_none());
}

/// The small-disk limit is the lattice's free-path law (`proofs-notes/free-path-law.md`): the
/// exponent of the disk-to-disk map is λ = ln(2⟨ℓ⟩/R) + C + O(r ln² r), C = 1 − 4 ln 2 +
/// 27ζ(3)/(2π²) the constant Dahlqvist found on the square lattice, for any lattice. On the
/// triangular one at w = 10⁴ (R = 1, ⟨ℓ⟩ = √3a²/4 − π/2, r = R/√(cell area) = 1.07·10⁻⁴) λ −
/// ln 2⟨ℓ⟩ must be C within the Student-t 4σ-equivalent of its error plus r ln² r (9·10⁻³, the
/// size of the neglected term). Broken on purpose (ln⟨ℓ⟩ for ln 2⟨ℓ⟩): off by ln 2.
#[test]
fn at_small_disks_the_triangular_exponent_has_the_square_lattices_constant() {
    let w = 10_000.0f64;
    let l = lyapunov_at("10000", Flights::Auto, 200_000, 4);
    assert_eq!(l.flights, Flights::Jump);
    let a = 2.0 + w;
    let ell = 3f64.sqrt() * a * a / 4.0 - std::f64::consts::FRAC_PI_2;
    let r = 1.0 / (3f64.sqrt() * a * a / 2.0).sqrt();
    let measured = l.per_collision - (2.0 * ell).ln();
    super::long_flight::assert_dahlqvist("lambda - ln 2<l>", measured, l.per_collision_err, r);
}

/// The triangular long-flight fuzz oracle (`verification::oracle::long_flight_triangular`, the
/// `long_flight_triangular` fuzz target) on 3 000 random inputs: near misses of far disks (1 ± 2^−e
/// from a disk up to 1 024 lattice steps away), lattice directions turned by 2^−e, any direction,
/// from just beyond w∞ to a = 2²⁰. Every jump replayed is inside its model, and most inputs jump.
/// (Breaking it on purpose: the search's window at 0.99|v| made it fail on skipped disks.)
#[test]
fn the_triangular_long_flight_oracle_finds_every_jump_inside_its_model() {
    use lorentz_gas::verification::oracle::long_flight_triangular;
    let (mut checked, mut skipped, mut longest) = (0u64, 0u64, 0u64);
    for data in super::long_flight_audit::random_inputs(44, 3_000) {
        let r = long_flight_triangular(&data).unwrap_or_else(|e| panic!("{data:?}: {e}"));
        checked += u64::from(r.checked);
        skipped += u64::from(r.skipped);
        longest = longest.max(r.check.map_or(0, |c| c.crossings));
    }
    println!("{checked} jumps checked, {skipped} skipped, longest {longest} crossings");
    assert!(
        checked > 1_500 && longest > 1_000,
        "{checked} {skipped} {longest}"
    );
}
