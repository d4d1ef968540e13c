//! Long flights on the square lattice (`scenes::long_flight`, `proofs-notes/long-flights.md`):
//! the first disk found by lattice arithmetic against the cell walk, from invariant-measure starts
//! and from flights aimed at near misses of far disks.

use lorentz_gas::kernel::flight::{EventKind, Flight};
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::{CellIndex, LatticeState};
use lorentz_gas::scenes::long_flight::{jump, major_edge};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::square::SquareScene;

/// The first collision by the cell walk: its cell, the state on entering that cell, and the
/// crossings walked.
fn by_walk(scene: &SquareScene, start: &LatticeState<f64>) -> (CellIndex, LatticeState<f64>, u64) {
    let lat = scene.lattice::<f64>(()).unwrap();
    let mut s = start.clone();
    let mut entry = s.clone();
    let mut crossings = 0;
    loop {
        let ev = lat.step(&mut s).expect("an event");
        match ev.kind {
            EventKind::Collision(_) => return (s.cell, entry, crossings),
            EventKind::Crossing(_) => {
                crossings += 1;
                entry = s.clone();
            }
        }
    }
}

/// The first collision with jumps: the cell kernel in each cell, and a jump wherever it leaves
/// through the edge it faces along its major axis. Its cell, the state on entering that cell, the
/// jumps, and the pre-jump flight of the jump that entered the cell (if one did).
pub(crate) fn by_jumps(
    scene: &SquareScene,
    start: &LatticeState<f64>,
) -> (CellIndex, LatticeState<f64>, u64, Option<Flight<f64>>) {
    let lat = scene.lattice::<f64>(()).unwrap();
    let mut s = start.clone();
    let (mut jumps, mut last) = (0, None);
    loop {
        let ev = lat.next_event(&s).expect("an event");
        match ev.kind {
            EventKind::Collision(_) => return (s.cell, s, jumps, last),
            EventKind::Crossing(k) if k == major_edge(&s.flight.vel) => {
                let j = jump(&s.flight.pos, &s.flight.vel, scene.radius()).expect("a disk ahead");
                last = Some(s.flight.clone());
                s.cell.i += j.cells[0];
                s.cell.j += j.cells[1];
                s.flight = Flight {
                    pos: j.pos,
                    vel: s.flight.vel,
                    excluded_disk: None,
                    excluded_edge: Some(j.entered),
                };
                jumps += 1;
            }
            EventKind::Crossing(_) => {
                lat.apply(&mut s, &ev);
                last = None;
            }
        }
    }
}

/// From 2000 invariant-measure starts at each radius, the jumps meet the disk the cell walk meets,
/// and enter its cell where the walk does, to the walk's own rounding: each crossing rounds the
/// position once (p + t·v, |p| ≤ ½, |t·v| ≤ √2, t itself to a few u), so n crossings leave the walk
/// within about 4nu of the exact line, and the jump's entry is the exact line's, rounded once.
#[test]
fn jumps_meet_the_disk_the_cell_walk_meets() {
    for r in [0.25, 0.1, 1e-2, 1e-3] {
        let scene = SquareScene::new(r).unwrap();
        let (mut worst, mut walked) = (0.0f64, 0u64);
        for b in 0..2000u64 {
            let start = scene.sample(&mut stream(34, b));
            let (cw, sw, crossings) = by_walk(&scene, &start);
            let (cj, sj, _, _) = by_jumps(&scene, &start);
            assert_eq!(
                cw, cj,
                "r = {r}, start {b}: the walk's cell against the jump's"
            );
            assert_eq!(
                sw.flight.excluded_edge, sj.flight.excluded_edge,
                "r = {r}, start {b}"
            );
            let dp = (sw.flight.pos.x - sj.flight.pos.x).hypot(sw.flight.pos.y - sj.flight.pos.y);
            let u = f64::EPSILON / 2.0;
            let scale = (crossings as f64 + 1.0) * 4.0 * u;
            worst = worst.max(dp / scale);
            walked += crossings;
        }
        println!("r = {r}: worst {worst:.3} of the bound, {walked} crossings walked");
        assert!(worst <= 1.0, "r = {r}: {worst}");
    }
}

/// The Lyapunov exponent with jumps against the cell walk at r = 1/100 (independent orbits: the
/// two engines' roundings differ, so the orbits part after some collisions): consistent within the
/// Welch–Student-t equivalent of 4σ, the engine recorded, and `jump` refused where it does not
/// apply. Broken on purpose (the jump's flight time halved): 294σ apart per collision.
#[test]
fn lyapunov_with_jumps_agrees_with_the_cell_walk() {
    use lorentz_gas::engine::long_flight::Flights;
    use lorentz_gas::scenes::triangular::TriangularScene;
    use lorentz_gas::statistics::{normal_sigma_equivalent_t, welch_dof};
    use lorentz_gas::verification::lyapunov::{self, LyapunovConfig};
    let scene = SquareScene::new(0.01).unwrap();
    let run = |flights| {
        let cfg = LyapunovConfig {
            collisions_per_batch: 50_000,
            batches: 8,
            seed: 5,
            flights,
            motion: Default::default(),
        };
        lyapunov::run(&scene, &cfg, &crate::common::threads(2)).unwrap()
    };
    let (walk, jumps) = (run(Flights::Walk), run(Flights::Jump));
    assert_eq!(
        (walk.flights, jumps.flights),
        (Flights::Walk, Flights::Jump)
    );
    let auto = |r: f64| {
        Flights::Auto
            .resolve(&SquareScene::new(r).unwrap())
            .unwrap()
    };
    // `auto` jumps where jumps apply and are faster (2^-32 <= r <= 1/8).
    assert_eq!(
        (auto(0.125), auto(0.25), auto(0.3)),
        (Flights::Jump, Flights::Walk, Flights::Walk)
    );
    for (a, ea, b, eb) in [
        (
            walk.per_collision,
            walk.per_collision_err,
            jumps.per_collision,
            jumps.per_collision_err,
        ),
        (
            walk.per_time,
            walk.per_time_err,
            jumps.per_time,
            jumps.per_time_err,
        ),
    ] {
        let t4 = normal_sigma_equivalent_t(welch_dof(ea, 8.0, eb, 8.0), 4.0);
        let z = (a - b).abs() / ea.hypot(eb);
        assert!(
            z < t4,
            "walk {a} ± {ea}, jumps {b} ± {eb}: {z:.2}σ (bound {t4:.2})"
        );
    }
    let tri = TriangularScene::new(0.1).unwrap();
    let cfg = LyapunovConfig {
        flights: Flights::Jump,
        ..LyapunovConfig::new()
    };
    let e = lyapunov::run(&tri, &cfg, &crate::common::threads(1)).unwrap_err();
    assert!(e.to_string().contains("flights = jump"), "{e}");
}

/// Dahlqvist's small-disk limit (arXiv chao-dyn/9601007) for the disk-to-disk map of the unit
/// square: λ = −2 ln R + C + O(R ln² R), C = 1 − 4 ln 2 + 27ζ(3)/(2π²) = −0.128 34. At R = 10⁻⁴
/// with jumps (4 × 2·10⁵ collisions, well under a second) λ + 2 ln R must be C within the
/// Student-t 4σ-equivalent of its error plus |R ln² R| (8.5·10⁻³, the size of the neglected term).
/// Broken on purpose (ln R for 2 ln R): off by 9.2.
#[test]
fn the_lyapunov_exponent_at_small_radius_is_dahlqvists() {
    use lorentz_gas::engine::long_flight::Flights;
    use lorentz_gas::verification::lyapunov::{self, LyapunovConfig};
    let r: f64 = 1e-4;
    let cfg = LyapunovConfig {
        collisions_per_batch: 200_000,
        batches: 4,
        seed: 7,
        flights: Flights::Auto,
        motion: Default::default(),
    };
    let l = lyapunov::run(
        &SquareScene::new(r).unwrap(),
        &cfg,
        &crate::common::threads(2),
    )
    .unwrap();
    assert_eq!(l.flights, Flights::Jump);
    let measured = l.per_collision + 2.0 * r.ln();
    assert_dahlqvist("lambda + 2 ln R", measured, l.per_collision_err, r);
}

/// Asserts that `measured` (the exponent less its leading logarithm, ± `err` over 4 batches) is
/// Dahlqvist's C = 1 − 4 ln 2 + 27ζ(3)/(2π²) = −0.128 34 within the Student-t 4σ-equivalent of
/// its error plus |R ln² R|, the size of the neglected term at the (effective) radius `r`; `what`
/// names the measured quantity.
pub(crate) fn assert_dahlqvist(what: &str, measured: f64, err: f64, r: f64) {
    use lorentz_gas::statistics::normal_sigma_equivalent_t;
    let zeta3 = 1.202_056_903_159_594_3;
    let c = 1.0 - 4.0 * 2f64.ln() + 27.0 * zeta3 / (2.0 * std::f64::consts::PI.powi(2));
    let slack = normal_sigma_equivalent_t(3.0, 4.0) * err + r * r.ln().powi(2);
    println!("{what} = {measured:.5} ± {err:.5}, C = {c:.5}");
    assert!(
        (measured - c).abs() < slack,
        "{measured} ± {err} against C = {c}"
    );
}
