//! The audit of long flights (`verification::jump_audit`, `proofs-notes/long-flights.md`, "The
//! audit"): the exact column walk it judges jumps by is the MPFR cell walk, and a run's jumps are
//! all inside the model.

use lorentz_gas::engine::long_flight::Flights;
use lorentz_gas::kernel::flight::EventKind;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::{CellIndex, LatticeState};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::square::SquareScene;
use lorentz_gas::verification::jump_audit::check_jump;
use rug::{Float, Rational};

/// The MPFR cell walk at `bits` from an `f64` state lifted exactly: the cell of its first
/// collision and the state on entering that cell, rounded to doubles.
fn mpfr_walk(scene: &SquareScene, start: &LatticeState<f64>, bits: u32) -> (CellIndex, [f64; 2]) {
    let lat = scene.lattice::<Float>(bits).unwrap();
    let mut s = LatticeState::<Float>::convert_from_f64(bits, start);
    let mut entry = [start.flight.pos.x, start.flight.pos.y];
    loop {
        let ev = lat.next_event(&s).expect("an event");
        if let EventKind::Collision(_) = ev.kind {
            return (s.cell, entry);
        }
        lat.apply(&mut s, &ev);
        entry = [s.flight.pos.x.to_f64(), s.flight.pos.y.to_f64()];
    }
}

/// From 400 invariant-measure starts at r = 1/30, 1/100 and 1/1000 (the exact radii), the MPFR
/// cell walk at 128 bits meets its first disk in the cell the jumps reach, and enters that cell
/// where the jump does within the jump's own position bound (the walk's rounding, about
/// n·2⁻¹²⁸, is far below it); every jump on the way is inside the audit's model. Where the walk
/// and the jumps part is only a tangency within the kernel's rounding: none occurs here.
#[test]
fn the_mpfr_cell_walk_meets_the_disk_the_jumps_meet() {
    for (p, q) in [(1u32, 30u32), (1, 100), (1, 1000)] {
        let scene = SquareScene::exact(Rational::from((p, q))).unwrap();
        let r = scene.radius();
        let (mut worst, mut crossings) = (0.0f64, 0u64);
        for b in 0..400u64 {
            let start = scene.sample(&mut stream(36, b));
            let (cw, ew) = mpfr_walk(&scene, &start, 128);
            let (cj, sj, _, last) = super::long_flight::by_jumps(&scene, &start);
            let ej = [sj.flight.pos.x, sj.flight.pos.y];
            assert_eq!(cw, cj, "r = {p}/{q}, start {b}");
            let Some(f) = last else { continue };
            let c = check_jump(&f, r, 128).expect("a disk ahead");
            assert!(c.in_model, "r = {p}/{q}, start {b}: {c:?}");
            let err = (ew[0] - ej[0]).abs().max((ew[1] - ej[1]).abs());
            worst = worst.max(err / c.position_bound);
            crossings += c.columns;
        }
        println!("r = {p}/{q}: entry error up to {worst:.3} of the bound, {crossings} columns");
        assert!(worst <= 1.0, "r = {p}/{q}: {worst}");
    }
}

/// The audit of a run whose flights jump (square lattice, r = 1/100 and 1/1000, 10⁵ collisions
/// each, every event replayed): every jump replayed, none outside the model, the collisions
/// after them inside the one-step model, the engine recorded. Walking, nothing is jumped.
#[test]
fn audits_with_jumps_find_nothing_outside_the_model() {
    use lorentz_gas::verification::shadow_audit::AuditReport;
    let run = |q: u32, collisions: u64, flights: Flights| -> AuditReport {
        let scene = SquareScene::exact(Rational::from((1, q))).unwrap();
        crate::common::full_audit(&scene, collisions, 37, None, flights)
    };
    for q in [100u32, 1000] {
        let r = run(q, 100_000, Flights::Auto);
        let j = &r.summary.jumps;
        assert_eq!(r.flights, Flights::Jump);
        assert!(j.audited >= 99_000, "1/{q}: {} jumps", j.audited);
        assert_eq!(j.outside, 0, "1/{q}: {:?}", j.outside_jumps.first());
        assert_eq!(
            r.summary.outside,
            0,
            "1/{q}: {:?}",
            r.summary.outside_events.first()
        );
        assert!(j.time_error_over_bound.max <= 1.0 && j.position_error_over_bound.max <= 1.0);
        println!(
            "1/{q}: {} jumps, {} columns, time/bound max {:.3}, entry/bound max {:.3}",
            j.audited, j.columns, j.time_error_over_bound.max, j.position_error_over_bound.max
        );
    }
    let r = run(100, 2_000, Flights::Walk);
    assert_eq!((r.flights, r.summary.jumps.audited), (Flights::Walk, 0));
}

/// `count` random 24-byte inputs of a fuzz oracle, the same on every run (seed `seed`).
pub(crate) fn random_inputs(seed: u64, count: usize) -> impl Iterator<Item = [u8; 24]> {
    use rand::{RngCore, SeedableRng};
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    (0..count).map(move |_| {
        let mut data = [0u8; 24];
        rng.fill_bytes(&mut data);
        data
    })
}

/// The long-flight fuzz oracle (`verification::oracle::long_flight`, the `long_flight` fuzz
/// target) on 100 000 random inputs: near misses of far disks (r(1 ± 2^−e) from a disk up to
/// 65 536 columns away), lines along and near small rational directions, and any direction, at
/// radii 2⁻³² to 1/4. Every jump walked is inside its model; the families reach the window's edge
/// (candidates at |D|/W > 0.999) and long corridors. (Breaking it on purpose: the search's window
/// at 0.9r made the oracle fail on skipped disks.)
#[test]
fn the_long_flight_oracle_finds_every_jump_inside_its_model() {
    use lorentz_gas::verification::oracle::long_flight;
    let (mut checked, mut skipped, mut edge, mut columns) = (0u64, 0u64, 0u64, 0u64);
    for data in random_inputs(38, 100_000) {
        let r = long_flight(&data).unwrap_or_else(|e| panic!("{data:?}: {e}"));
        checked += u64::from(r.checked);
        skipped += u64::from(r.skipped);
        if let Some(c) = r.check {
            edge += u64::from(c.candidate_over_window > 0.999);
            columns = columns.max(c.columns);
        }
    }
    println!(
        "{checked} jumps checked, {skipped} skipped, {edge} at the window's edge, longest {columns}"
    );
    // About a sixth meet no disk within the walked length (corridors) or are too long to walk.
    assert!(
        checked > 75_000 && edge > 1_000 && columns > 1 << 16,
        "{checked} {edge} {columns}"
    );
}
