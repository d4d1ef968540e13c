//! Physics checks: exact identities within 4σ, the horizon threshold w∞, the collisionless
//! flight onset w₀, the maximal free path, and energy without drift.

use lorentz_gas::diffusion::{run, DiffusionConfig};
use lorentz_gas::geometry::Geometry;
use lorentz_gas::kernel::trap::{EventKind, Flight, NONE};
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::sampling::{equilibrium_state, stream};
use lorentz_gas::scenes::lattice::{Cell, LatticeState, PeriodicLattice};

fn within(x: f64, err: f64, exact: f64, k: f64, what: &str) {
    assert!(err > 0.0 && err.is_finite(), "{what}: bad error {err}");
    assert!(
        (x - exact).abs() <= k * err,
        "{what}: {x} ± {err} vs exact {exact} ({:.1}σ)",
        (x - exact) / err
    );
}

/// Santaló ⟨ℓ⟩ = π|Q|/|∂Q|, τ = πA/(3w) and collisions/hop = π/(3w), each within 4σ
/// (σ the standard error over 16 independent batches).
#[test]
fn exact_identities_within_four_sigma() {
    for &w in &[0.05, 0.25] {
        let mut cfg = DiffusionConfig::new(w);
        cfg.collisions = 40_000_000;
        cfg.batches = 16;
        cfg.seed = 2024;
        let r = run(&cfg, 2, None, &|_| {}).unwrap();
        within(
            r.mean_free_path,
            r.mean_free_path_err,
            r.mean_free_path_exact,
            4.0,
            "mean free path",
        );
        within(r.tau_hop, r.tau_hop_err, r.tau_hop_exact, 4.0, "tau");
        within(
            r.collisions_per_hop,
            r.collisions_per_hop_err,
            r.collisions_per_hop_exact,
            4.0,
            "collisions/hop",
        );
        // D is finite, positive and its two windows agree within 4 combined σ.
        let comb = (r.D_err.powi(2) + r.D_check_err.powi(2)).sqrt();
        assert!(
            r.D > 0.0 && (r.D - r.D_check).abs() <= 4.0 * comb,
            "windows disagree: {} vs {}",
            r.D,
            r.D_check
        );
    }
}

/// Same seed ⇒ same bits, whatever the number of threads.
#[test]
fn same_seed_same_bits_any_thread_count() {
    let mut cfg = DiffusionConfig::new(0.15);
    cfg.collisions = 4_000_000;
    cfg.batches = 4;
    cfg.seed = 99;
    cfg.window = "2:8".parse().unwrap();
    cfg.check_window = "4:16".parse().unwrap();
    let a = run(&cfg, 1, None, &|_| {}).unwrap();
    let b = run(&cfg, 2, None, &|_| {}).unwrap();
    assert_eq!(a.D.to_bits(), b.D.to_bits());
    assert_eq!(a.mean_free_path.to_bits(), b.mean_free_path.to_bits());
    cfg.seed = 100;
    let c = run(&cfg, 2, None, &|_| {}).unwrap();
    assert_ne!(a.D.to_bits(), c.D.to_bits());
}

/// A checkpointed run that is interrupted resumes without redoing finished batches and gives
/// the same bits as an uninterrupted run.
#[test]
fn checkpoint_resumes_finished_batches() {
    let dir = std::env::temp_dir().join(format!("lorentz-ckpt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.jsonl");
    let _ = std::fs::remove_file(&path);
    let mut cfg = DiffusionConfig::new(0.2);
    cfg.collisions = 2_000_000;
    cfg.batches = 4;
    cfg.window = "2:8".parse().unwrap();
    cfg.check_window = "4:16".parse().unwrap();
    let full = run(&cfg, 2, Some(&path), &|_| {}).unwrap();
    // Simulate an interruption: keep the header and two finished batches, plus a torn line.
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().filter(|l| !l.is_empty()).collect();
    std::fs::write(
        &path,
        format!(
            "{}\n{}\n{}\n{{\"index\":3,\"coun",
            lines[0], lines[1], lines[2]
        ),
    )
    .unwrap();
    let resumed = run(&cfg, 2, Some(&path), &|_| {}).unwrap();
    assert_eq!(resumed.resumed_batches, 2);
    assert_eq!(resumed.D.to_bits(), full.D.to_bits());
    // A different configuration refuses the file.
    cfg.seed += 1;
    assert!(run(&cfg, 2, Some(&path), &|_| {}).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Above w∞ the horizontal ray midway between two rows of disks never collides: it is at
/// distance h/2 > 1 from both rows. Below w∞ the same ray collides within ℓ_max.
#[test]
fn horizon_threshold_w_inf() {
    let w_inf = Geometry::<f64>::w_inf(());
    for &w in &[w_inf + 1e-9, w_inf + 1e-3, 0.35, 0.5] {
        let lat = PeriodicLattice::new(w).unwrap();
        let (a, h) = (lat.trap.a, lat.trap.h);
        assert!(
            h / 2.0 - 1.0 > 1e6 * f64::EPSILON,
            "the corridor is resolvable at w = {w}"
        );
        let mut s = LatticeState {
            cell: Cell::default(),
            flight: Flight::new(Vec2::new(a / 2.0, h / 2.0), Vec2::new(1.0, 0.0)),
        };
        let mut travelled = 0.0;
        for _ in 0..100_000 {
            let ev = lat.step(&mut s).unwrap();
            assert!(
                matches!(ev.kind, EventKind::Crossing(_)),
                "collision in the open corridor at w = {w}"
            );
            travelled += ev.time;
        }
        let x = lat.world(&s);
        assert!(
            (x.x - a / 2.0 - travelled).abs() < 1e-9 * travelled && (x.y - h / 2.0).abs() < 1e-9,
            "straight line"
        );
    }
    for &w in &[0.01, 0.1, 0.2, 0.3, w_inf - 1e-6] {
        let lat = PeriodicLattice::new(w).unwrap();
        let g = Geometry::new(w).unwrap();
        let (a, h) = (lat.trap.a, lat.trap.h);
        let mut s = LatticeState {
            cell: Cell::default(),
            flight: Flight::new(Vec2::new(a / 2.0, h / 2.0), Vec2::new(1.0, 0.0)),
        };
        let mut t = 0.0;
        loop {
            let ev = lat.step(&mut s).unwrap();
            t += ev.time;
            if let EventKind::Collision(_) = ev.kind {
                break;
            }
            assert!(
                t <= g.max_free_path_bound().unwrap(),
                "flight beyond the bound at w = {w}"
            );
        }
    }
}

/// Every free path of long equilibrium runs is within the proven bound ℓ_max(w).
#[test]
fn free_paths_are_bounded_below_w_inf() {
    let w_inf = Geometry::<f64>::w_inf(());
    for (k, &w) in [0.05, 0.15, 0.2, 0.3, w_inf - 1e-4].iter().enumerate() {
        let lat = PeriodicLattice::new(w).unwrap();
        let bound = Geometry::new(w).unwrap().max_free_path_bound().unwrap();
        let mut s = equilibrium_state(&lat.trap, &mut stream(5, k as u64));
        let (mut run, mut longest) = (0.0, 0.0f64);
        let mut c = 0;
        while c < 2_000_000 {
            let ev = lat.step(&mut s).unwrap();
            run += ev.time;
            if let EventKind::Collision(_) = ev.kind {
                c += 1;
                if c > 1 {
                    longest = longest.max(run);
                }
                run = 0.0;
            }
        }
        assert!(
            longest <= bound,
            "w = {w}: free path {longest} > bound {bound}"
        );
        eprintln!("w = {w}: longest free path {longest:.4}, bound {bound:.4}");
    }
}

/// Collisionless crossings of a trap (enter by one gap, leave by another, no collision) are
/// impossible below w₀ = 2/√3 − 1 and exist above it.
#[test]
fn collisionless_flights_onset_w0() {
    let w0 = Geometry::<f64>::w_0(());
    let count = |w: f64| -> u64 {
        let lat = PeriodicLattice::new(w).unwrap();
        let mut s = equilibrium_state(&lat.trap, &mut stream(8, 0));
        let (mut since_crossing, mut collided, mut n) = (false, true, 0);
        for _ in 0..4_000_000 {
            match lat.step(&mut s).unwrap().kind {
                EventKind::Collision(_) => collided = true,
                EventKind::Crossing(_) => {
                    if since_crossing && !collided {
                        n += 1;
                    }
                    since_crossing = true;
                    collided = false;
                }
            }
        }
        n
    };
    assert_eq!(count(w0 * 0.999), 0);
    assert_eq!(count(0.1), 0);
    assert!(count(0.17) > 0);
    assert!(count(0.25) > 1000);
    // The explicit chord of proofs-notes/w0.md: from (r, 0) on E₂ towards r(1/2, √3/2) on E₁,
    // r = (a − 1 + 2/√3)/2, passes P₀ at distance r√3/2 > 1 for w > w₀.
    for &w in &[w0 + 1e-6, 0.2, 0.3] {
        let lat = PeriodicLattice::new(w).unwrap();
        let a = lat.trap.a;
        let r = 0.5 * (a - 1.0 + 2.0 / 3f64.sqrt());
        let mut f = Flight::new(Vec2::new(r, 0.0), Vec2::new(-0.5, 3f64.sqrt() / 2.0));
        f.excluded_edge = 2;
        assert_eq!(f.excluded_disk, NONE);
        let ev = lat.trap.next_event(&f).unwrap();
        assert_eq!(ev.kind, EventKind::Crossing(1), "w = {w}");
    }
}

/// Energy: after every collision ||v|² − 1| ≤ 128u (one reflection's rounding, 4|ε| + 12u with
/// |ε| ≤ 28u the contact point's offset from the circle; the Newton factor removes the incoming
/// deviation to O(η²): proofs-notes/energy.md), and over 10⁷ f64 collisions |v|² does not drift: the total change is within 6 random-walk standard deviations √(Σ δ²) of the
/// per-collision changes δ (a systematic bias b would give N·b ≫ √N·rms).
#[test]
fn energy_has_no_drift_over_ten_million_collisions() {
    let u = f64::EPSILON / 2.0;
    let lat = PeriodicLattice::new(0.1).unwrap();
    let mut s = equilibrium_state(&lat.trap, &mut stream(9, 0));
    let e0 = s.flight.vel.norm2();
    let mut e = e0;
    let (mut sum_sq, mut c, mut worst, mut worst_eta) = (0.0, 0u64, 0.0f64, 0.0f64);
    while c < 10_000_000 {
        if let EventKind::Collision(_) = lat.step(&mut s).unwrap().kind {
            c += 1;
            let e1 = s.flight.vel.norm2();
            assert!(
                (e1 - 1.0).abs() <= 128.0 * u,
                "|v|^2 - 1 = {:e} after collision {c}",
                e1 - 1.0
            );
            worst_eta = worst_eta.max((e1 - 1.0).abs());
            let d = e1 - e;
            worst = worst.max(d.abs());
            sum_sq += d * d;
            e = e1;
        }
    }
    assert!(
        worst <= 256.0 * u,
        "one collision changed |v|^2 by {worst:e}"
    );
    let drift = e - e0;
    assert!(
        drift.abs() <= 6.0 * sum_sq.sqrt() + 4.0 * u,
        "drift {drift:e} vs random walk {:e}",
        sum_sq.sqrt()
    );
    eprintln!("worst ||v|^2 - 1| {:.2}u", worst_eta / u);
    eprintln!(
        "|v|^2 - 1 after 1e7 collisions: {:e}; worst step {:.2}u; random-walk scale {:e}",
        e - 1.0,
        worst / u,
        sum_sq.sqrt()
    );
}

/// The unwrapped world position is continuous: over every event the world displacement (exact
/// lattice integers plus offsets) equals flight time × world velocity, for every kind of
/// crossing of both trap orientations. This is what the MSD, hence D, is built from.
#[test]
fn unwrapped_position_is_continuous_across_every_crossing() {
    for (k, &w) in [0.02, 0.2, 0.3].iter().enumerate() {
        let lat = PeriodicLattice::new(w).unwrap();
        let (a, h) = lat.a_h_f64();
        let mut s = equilibrium_state(&lat.trap, &mut stream(12, k as u64));
        let mut seen = std::collections::HashSet::new();
        for _ in 0..200_000 {
            let before = lat.unwrapped(&s, 0.0);
            let sg = s.cell.sign();
            let (vx, vy) = (sg * s.flight.vel.x, sg * s.flight.vel.y);
            let down = s.cell.down;
            let ev = lat.step(&mut s).unwrap();
            if let EventKind::Crossing(e) = ev.kind {
                seen.insert((down, e));
            }
            let d = lat.unwrapped(&s, 0.0).displacement_from(&before, a, h);
            let err = ((d[0] - ev.time * vx).powi(2) + (d[1] - ev.time * vy).powi(2)).sqrt();
            assert!(
                err <= 64.0 * f64::EPSILON * (a + ev.time),
                "w={w}: jump {err:e} over {:?}",
                ev.kind
            );
        }
        assert_eq!(
            seen.len(),
            6,
            "all three edges of both orientations crossed"
        );
    }
}
