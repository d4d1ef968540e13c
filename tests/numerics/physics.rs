//! Physics checks: exact identities within 4σ, the horizon threshold w∞, the collisionless
//! flight onset w₀, the maximal free path, and energy without drift.

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::diffusion::{DiffusionConfig, run};
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::kernel::{flight::EventKind, flight::Flight};
use lorentz_gas::scenes::lattice::{CellIndex, LatticeState, TriangularLattice};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::triangular::equilibrium_state;
use lorentz_gas::scenes::triangular::geometry::Geometry;
use lorentz_gas::verification::error_model::{ENERGY_BAND_U, UNIT_ROUNDOFF, UNWRAP_EPS};

/// Asserts that `x` ± `err` (a finite positive error) is within `k` errors of `exact`; `what`
/// names it.
pub(crate) fn within(x: f64, err: f64, exact: f64, k: f64, what: &str) {
    assert!(err > 0.0 && err.is_finite(), "{what}: bad error {err}");
    assert!(
        (x - exact).abs() <= k * err,
        "{what}: {x} ± {err} vs exact {exact} (t = {:.1}, bound {k:.2})",
        (x - exact) / err
    );
}

/// Santaló ⟨ℓ⟩ = π|Q|/|∂Q|, τ = πA/(3w) and collisions/hop = π/(3w), each within 4σ
/// (σ the standard error over 16 independent batches). The z-score of a mean whose SE comes from
/// the spread of n batch means is Student-t with n − 1 dof: "4σ" is its quantile at the normal's
/// two-sided 4σ tail probability 6.3·10⁻⁵ (t₁₅: 5.48).
#[test]
fn exact_identities_within_four_sigma() {
    use lorentz_gas::statistics::normal_sigma_equivalent_t;
    for &w in &[0.05, 0.25] {
        let cfg = crate::common::diffusion_config(w, 40_000_000, 16, 2024);
        let r = run(&cfg, &crate::common::threads(2)).unwrap();
        let k = normal_sigma_equivalent_t(r.meta.batches.unwrap() as f64 - 1.0, 4.0);
        within(
            r.mean_free_path,
            r.mean_free_path_err,
            r.mean_free_path_exact,
            k,
            "mean free path",
        );
        within(r.tau_hop, r.tau_hop_err, r.tau_hop_exact, k, "tau");
        within(
            r.collisions_per_hop,
            r.collisions_per_hop_err,
            r.collisions_per_hop_exact,
            k,
            "collisions/hop",
        );
        // D is finite, positive and its two windows agree within 4 combined σ. Both come from
        // the same batches (positively correlated: √(σ₁² + σ₂²) overstates the σ of the
        // difference), so the conservative dof is n − 1.
        let comb = (r.D_err.powi(2) + r.D_check_err.powi(2)).sqrt();
        assert!(
            r.D > 0.0 && (r.D - r.D_check).abs() <= k * comb,
            "windows disagree: {} vs {}",
            r.D,
            r.D_check
        );
    }
}

/// Same seed ⇒ same bits, whatever the number of threads.
#[test]
fn same_seed_same_bits_any_thread_count() {
    let mut cfg = crate::common::diffusion_config(0.15, 4_000_000, 4, 99);
    cfg.window = "2:8".parse().unwrap();
    cfg.check_window = "4:16".parse().unwrap();
    let a = run(&cfg, &crate::common::threads(1)).unwrap();
    let b = run(&cfg, &crate::common::threads(2)).unwrap();
    assert_eq!(a.D.to_bits(), b.D.to_bits());
    assert_eq!(a.mean_free_path.to_bits(), b.mean_free_path.to_bits());
    cfg.seed = 100;
    let c = run(&cfg, &crate::common::threads(2)).unwrap();
    assert_ne!(a.D.to_bits(), c.D.to_bits());
}

/// A checkpointed run that is interrupted resumes without redoing finished batches and gives
/// the same bits as an uninterrupted run.
#[test]
fn checkpoint_resumes_finished_batches() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.jsonl");
    let _ = std::fs::remove_file(&path);
    let mut cfg = DiffusionConfig::new(0.2);
    cfg.collisions = 2_000_000;
    cfg.batches = 4;
    cfg.window = "2:8".parse().unwrap();
    cfg.check_window = "4:16".parse().unwrap();
    let resumable = RunOptions {
        threads: 2,
        resume: Some(path.clone()),
        ..RunOptions::default()
    };
    let full = run(&cfg, &resumable).unwrap();
    // Simulate an interruption: keep the header and two finished batches, plus a torn line.
    let text = std::fs::read_to_string(&path).unwrap();
    let header = text.lines().next().unwrap();
    let finished: Vec<&str> = text
        .lines()
        .filter(|l| l.contains("\"finished\""))
        .collect();
    std::fs::write(
        &path,
        format!(
            "{header}\n{}\n{}\n{{\"index\":3,\"coun",
            finished[0], finished[1]
        ),
    )
    .unwrap();
    let resumed = run(&cfg, &resumable).unwrap();
    assert_eq!(resumed.resumed_batches, 2);
    assert_eq!(resumed.D.to_bits(), full.D.to_bits());
    // A different configuration refuses the file.
    cfg.seed += 1;
    assert!(run(&cfg, &resumable).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Above w∞ the horizontal ray midway between two rows of disks never collides: it is at
/// distance h/2 > 1 from both rows. Below w∞ the same ray collides within ℓ_max.
#[test]
fn horizon_threshold_w_inf() {
    let w_inf = Geometry::<f64>::w_inf(());
    for &w in &[w_inf + 1e-9, w_inf + 1e-3, 0.35, 0.5] {
        let lat = TriangularLattice::new(w).unwrap();
        let (a, h) = (lat.trap().a(), lat.trap().h());
        assert!(
            h / 2.0 - 1.0 > 1e6 * f64::EPSILON,
            "the corridor is resolvable at w = {w}"
        );
        let mut s = LatticeState {
            cell: CellIndex::default(),
            flight: Flight::new(Vec2::new(a / 2.0, h / 2.0), Vec2::new(1.0, 0.0)),
        };
        const EVENTS: u32 = 100_000;
        let mut travelled = lorentz_gas::statistics::CompensatedSum::default();
        for _ in 0..EVENTS {
            let ev = lat.step(&mut s).unwrap();
            assert!(
                matches!(ev.kind, EventKind::Crossing(_)),
                "collision in the open corridor at w = {w}"
            );
            travelled.add(ev.time);
        }
        let travelled = travelled.value();
        let x = lat.world(&s);
        // Each crossing moves the unwrapped position by t·v within UNWRAP_EPS·ε·(diameter + t)
        // (the trap's diameter is a); summed over the crossings, plus 2u·t for the compensated
        // sum and 2u·|x| (|x| ≈ t) for the world map's a·i and its addition.
        let bound = UNWRAP_EPS * f64::EPSILON * (EVENTS as f64 * a + travelled)
            + 4.0 * UNIT_ROUNDOFF * travelled;
        let (dx, dy) = ((x.x - a / 2.0 - travelled).abs(), (x.y - h / 2.0).abs());
        assert!(
            dx <= bound && dy <= bound,
            "straight line at w = {w}: off by ({dx:e}, {dy:e}), bound {bound:e}"
        );
    }
    for &w in &[0.01, 0.1, 0.2, 0.3, w_inf - 1e-6] {
        let lat = TriangularLattice::new(w).unwrap();
        let g = Geometry::new(w).unwrap();
        let (a, h) = (lat.trap().a(), lat.trap().h());
        let mut s = LatticeState {
            cell: CellIndex::default(),
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
        let lat = TriangularLattice::new(w).unwrap();
        let bound = Geometry::new(w).unwrap().max_free_path_bound().unwrap();
        let mut s = equilibrium_state(lat.trap(), &mut stream(5, k as u64));
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

/// The collisionless crossings of a trap (entered by one gap and left by another without a
/// collision) in 4·10⁶ events of the equilibrium trajectory of stream `seed` at the gap `w`.
pub(crate) fn collisionless_crossings(w: f64, seed: u64) -> u64 {
    let lat = TriangularLattice::new(w).unwrap();
    let mut s = equilibrium_state(lat.trap(), &mut stream(seed, 0));
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
}

/// Collisionless crossings of a trap (enter by one gap, leave by another, no collision) are
/// impossible below w₀ = 2/√3 − 1 and exist above it.
#[test]
fn collisionless_flights_onset_w0() {
    let w0 = Geometry::<f64>::w_0(());
    let count = |w: f64| collisionless_crossings(w, 8);
    assert_eq!(count(w0 * 0.999), 0);
    assert_eq!(count(0.1), 0);
    assert!(count(0.17) > 0);
    assert!(count(0.25) > 1000);
    // The explicit chord of proofs-notes/w0.md: from (r, 0) on E₂ towards r(1/2, √3/2) on E₁,
    // r = (a − 1 + 2/√3)/2, passes P₀ at distance r√3/2 > 1 for w > w₀.
    for &w in &[w0 + 1e-6, 0.2, 0.3] {
        let lat = TriangularLattice::new(w).unwrap();
        let a = lat.trap().a();
        let r = 0.5 * (a - 1.0 + 2.0 / 3f64.sqrt());
        let mut f = Flight::new(Vec2::new(r, 0.0), Vec2::new(-0.5, 3f64.sqrt() / 2.0));
        f.excluded_edge = Some(2);
        assert_eq!(f.excluded_disk, None);
        let ev = lat.trap().next_event(&f).unwrap();
        assert_eq!(ev.kind, EventKind::Crossing(1), "w = {w}");
    }
}

/// Energy (proofs-notes/energy.md), three claims of which none implies another.
///
/// 1. **Bound.** After every collision η = |v|² − 1 satisfies |η| ≤ 128u (one reflection's
///    rounding 4|ε| + 12u, |ε| ≤ 28u the contact point's offset from the circle), over all 10⁷
///    collisions. A reflection that passes deviations on (η_out = η_in + δ) is a random walk
///    whose spread after N collisions is √N·rms(δ) ≈ 1.5·10⁴u (rms δ ≈ 5u, N = 10⁷), plus the
///    measured bias N·b ≈ 2.6·10⁵u: it leaves the band within about 10³ collisions.
/// 2. **Contraction** (the mechanism). A speed off by η = ±2⁻³⁰ (≈ 8·10⁶u, far outside the band)
///    returns after one collision to |η_out| ≤ 128u + η²: the Newton factor k = 1 − η/2 gives
///    (1 + η)(1 − η/2)² = 1 − 3η²/4 + η³/4, plus the reflection's own δ. Claim 1 on an
///    equilibrium orbit never probes this, since there η_in is already in the band.
/// 3. **No drift.** The band of claim 1 only sees a drift b per collision once N·b > 128u, i.e.
///    b > 1.3·10⁻⁵u over 10⁷ collisions. Stronger: the law of η_n is the same at the end of the
///    run as at the start. η_n = δ_n + O(η²) depends on the n-th collision only, so the means m_j
///    of B = 20 consecutive blocks of L = 5·10⁵ collisions are independent and identically
///    distributed (correlations of a few collisions at the seams are negligible against L).
///    Least squares m_j = c + s·j: ŝ/SE(ŝ), SE(ŝ)² = Σr²/((B − 2)Σ(j − j̄)²), is Student-t
///    with B − 2 dof, and a drift b adds s = b·L. |ŝ| ≤ t₁₈(4σ-equivalent)·SE(ŝ) = 5.18·SE(ŝ);
///    SE(ŝ) ≈ σ_η/√(L·Σ(j − j̄)²) (measured 1.5·10⁻⁴u for σ_η ≈ 2.8u) detects
///    b ≳ 1.6·10⁻⁹u per collision, ~10⁴ times below what claim 1 can see.
#[test]
fn energy_has_no_drift_over_ten_million_collisions() {
    use lorentz_gas::statistics::{linear_fit, normal_sigma_equivalent_t};
    let u = UNIT_ROUNDOFF;
    let lat = TriangularLattice::new(0.1).unwrap();

    // 2. Contraction from ±2⁻³⁰ off the unit speed, 1000 equilibrium starts.
    for k in 0..1000u64 {
        let mut s = equilibrium_state(lat.trap(), &mut stream(9, 1 + k));
        let f = if k % 2 == 0 {
            1.0 + 2f64.powi(-31)
        } else {
            1.0 - 2f64.powi(-31)
        };
        s.flight.vel = Vec2::new(s.flight.vel.x * f, s.flight.vel.y * f);
        let eta_in = s.flight.vel.norm2() - 1.0;
        assert!(eta_in.abs() > 1e6 * u);
        while !matches!(lat.step(&mut s).unwrap().kind, EventKind::Collision(_)) {}
        let eta = s.flight.vel.norm2() - 1.0;
        assert!(
            eta.abs() <= ENERGY_BAND_U * u + eta_in * eta_in,
            "start {k}: |v|^2 - 1 = {eta_in:e} before the collision, {eta:e} = {:.1}u after \
             (no contraction)",
            eta / u
        );
    }

    // 1. and 3. along one equilibrium orbit of 10⁷ collisions.
    const B: usize = 20;
    const L: u64 = 500_000;
    let mut s = equilibrium_state(lat.trap(), &mut stream(9, 0));
    let (mut c, mut worst_eta, mut worst_step) = (0u64, 0.0f64, 0.0f64);
    let mut prev = s.flight.vel.norm2();
    let mut block_sum = 0.0; // Σ η/u over the current block
    let mut means = Vec::with_capacity(B);
    while c < B as u64 * L {
        if let EventKind::Collision(_) = lat.step(&mut s).unwrap().kind {
            c += 1;
            let e = s.flight.vel.norm2();
            let eta = e - 1.0;
            assert!(
                eta.abs() <= ENERGY_BAND_U * u,
                "|v|^2 - 1 = {eta:e} = {:.1}u after collision {c}",
                eta / u
            );
            worst_eta = worst_eta.max(eta.abs());
            worst_step = worst_step.max((e - prev).abs());
            prev = e;
            block_sum += eta / u;
            if c % L == 0 {
                means.push(block_sum / L as f64);
                block_sum = 0.0;
            }
        }
    }
    let j: Vec<f64> = (0..B).map(|j| j as f64).collect();
    let (c0, slope) = linear_fit(&j, &means);
    let jbar = (B as f64 - 1.0) / 2.0;
    let sxx: f64 = j.iter().map(|x| (x - jbar).powi(2)).sum();
    let ss: f64 = j
        .iter()
        .zip(&means)
        .map(|(x, m)| (m - c0 - slope * x).powi(2))
        .sum();
    let se = (ss / (B as f64 - 2.0) / sxx).sqrt();
    let t_max = normal_sigma_equivalent_t(B as f64 - 2.0, 4.0);
    assert!(
        slope.abs() <= t_max * se,
        "|v|^2 drifts: block means of (|v|^2 - 1)/u {means:?} have slope {slope:e} ± {se:e} \
         per block of {L} collisions (t = {:.1}, 4σ-equivalent {t_max:.2})",
        slope / se
    );
    eprintln!(
        "worst ||v|^2 - 1| {:.1}u, worst step {:.1}u; |v|^2 - 1 after 1e7 collisions: {:e}",
        worst_eta / u,
        worst_step / u,
        prev - 1.0
    );
    eprintln!(
        "block means of (|v|^2 - 1)/u: first {:.4}, last {:.4}; slope {slope:.2e} ± {se:.2e} per \
         block (t = {:.2}, bound {t_max:.2}): drift below {:.1e}u per collision excluded",
        means[0],
        means[B - 1],
        slope / se,
        t_max * se / L as f64
    );
}

/// The unwrapped world position is continuous: over every event the world displacement (exact
/// lattice integers plus offsets) equals flight time × world velocity, for every kind of
/// crossing of both trap orientations. This is what the MSD, hence D, is built from.
#[test]
fn unwrapped_position_is_continuous_across_every_crossing() {
    for (k, &w) in [0.02, 0.2, 0.3].iter().enumerate() {
        let lat = TriangularLattice::new(w).unwrap();
        let basis = lat.basis_f64();
        let a = basis.a;
        let mut s = equilibrium_state(lat.trap(), &mut stream(12, k as u64));
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
            let d = lat.unwrapped(&s, 0.0).displacement_from(&before, &basis);
            let err = ((d[0] - ev.time * vx).powi(2) + (d[1] - ev.time * vy).powi(2)).sqrt();
            assert!(
                err <= UNWRAP_EPS * f64::EPSILON * (a + ev.time),
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
