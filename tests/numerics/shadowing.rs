//! True shadowing of f64 segments (`proofs-notes/shadowing.md`): Newton on the whole segment in
//! MPFR finds a true orbit with the same disk sequence near every f64 collision point.

use rug::Float;

use lorentz_gas::numbers::exact::parse_exact;
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::scenes::Scene;
use lorentz_gas::verification::shadowing::{
    self as shadowing, defects, f64_segment, shadow_pseudo_orbit, OrbitPoint, Shadow, ShadowConfig,
    Table,
};

const BITS: u32 = 128;

fn scene(w: &str) -> TriangularScene {
    TriangularScene::exact(parse_exact(w).unwrap()).unwrap()
}

fn request(collisions: usize, segments: u32) -> ShadowConfig {
    ShadowConfig {
        collisions_per_segment: collisions,
        segments,
        seed: 1,
        reference_bits: BITS,
    }
}

fn segment(sc: &TriangularScene, k: u64, n: usize) -> Vec<OrbitPoint> {
    let start = sc.sample(&mut stream(1, k));
    f64_segment(sc, &start, n, BITS).unwrap()
}

/// What a clean f64 segment's shadow must satisfy.
///
/// * δ ≤ 2K‖F(y⁰)‖₂: the Newton–Kantorovich bound (contraction ½ on the ball of radius
///   2K‖F(y⁰)‖₂), K certified at y*; not a tolerance but the theorem's conclusion.
/// * δ ≥ max_k‖F_k(y⁰)‖/(1 + max‖DT‖): F(y*) = 0, so each defect of the pseudo-orbit is at most
///   (‖DT‖ + 1)·δ to first order — δ cannot be smaller than the defects allow.
/// * δ ≤ 1e-13: the f64 one-step errors are ≲ 16u·(1 + 1/cos φ) ≈ 1e-14 at cos φ ≳ 0.03
///   (`proofs-notes/error-model.md`) and the K measured here is ≲ 50, the linear response to
///   independent errors stays at the single-step level; 1e-13 is the expectation (1e-14)
///   with a factor 10 for the worst of a few segments.
/// * residual at 2P ≤ 2^(24−P)/cos φ_min: the stopping rule (the orbit is stored at P bits).
fn assert_clean(sh: &Shadow, what: &str) {
    assert!(sh.converged, "{what}: {:?}", sh.failure);
    assert!(sh.certified, "{what}: {:?}", sh.failure);
    let delta = sh.delta.unwrap();
    let amax = sh.max_jacobian_norm.unwrap();
    assert!(
        delta <= sh.a_priori_bound.unwrap(),
        "{what}: delta {delta:e}"
    );
    assert!(
        delta >= sh.pseudo_orbit_defect.unwrap() / (1.0 + amax) * 0.99,
        "{what}: delta {delta:e} below the defects' lower bound"
    );
    assert!(delta <= 1e-13, "{what}: delta {delta:e} above 1e-13");
    let tol = (24.0 - BITS as f64).exp2() / sh.min_cos_phi.unwrap().min(1.0);
    assert!(
        sh.residual.unwrap() <= tol,
        "{what}: residual {:e}",
        sh.residual.unwrap()
    );
    assert!(sh.correction_bound.unwrap() < 1e-30, "{what}");
}

#[test]
fn f64_segments_are_shadowed_at_w_0_1_and_0_3() {
    for w in ["0.1", "0.3"] {
        let sc = scene(w);
        let r = shadowing::run(&sc, &request(300, 4), &crate::common::threads(1)).unwrap();
        assert_eq!(r.converged, 4, "w = {w}");
        for s in &r.segments {
            assert_clean(&s.shadow, &format!("w = {w}, segment {}", s.segment));
            assert!(
                s.shadow.iterations <= 4,
                "quadratic convergence from ~1e-15"
            );
        }
    }
}

#[test]
fn a_corrupted_point_is_seen_in_delta() {
    let sc = scene("0.1");
    let mut y = segment(&sc, 0, 200);
    let clean = shadow_pseudo_orbit(&sc, &y, BITS).unwrap();
    assert_clean(&clean, "clean");
    // Perturb one point by 1e-8 in p: the pseudo-orbit now has two defects ~1e-8, and the true
    // orbit nearest to it must differ from it by at least 1e-8/(1 + max‖DT‖) somewhere.
    y[100].p += 1e-8;
    let sh = shadow_pseudo_orbit(&sc, &y, BITS).unwrap();
    assert!(sh.converged, "{:?}", sh.failure);
    let delta = sh.delta.unwrap();
    let amax = sh.max_jacobian_norm.unwrap();
    assert!(delta >= 1e-8 / (1.0 + amax), "delta {delta:e}");
    assert!(delta <= sh.a_priori_bound.unwrap(), "delta {delta:e}");
    assert!(
        delta <= 1e-8,
        "the minimum-norm shadow moves at most the corruption: {delta:e}"
    );
    // …and the clean-orbit claims fail on it: the test can tell.
    assert!(
        std::panic::catch_unwind(|| assert_clean(&sh, "corrupted")).is_err(),
        "a 1e-8 corruption passed as a clean f64 segment"
    );
}

#[test]
fn the_shadow_is_a_true_orbit_at_256_bits() {
    let sc = scene("0.3");
    let y = segment(&sc, 2, 200);
    let sh = shadow_pseudo_orbit(&sc, &y, BITS).unwrap();
    assert_clean(&sh, "w = 0.3");
    let d_true = defects(&sc, &sh.orbit, 256).unwrap();
    let d_f64 = defects(&sc, &y, 256).unwrap();
    let max = |d: &[f64]| d.iter().cloned().fold(0.0, f64::max);
    // The shadow is stored at 128 bits: its defects at 256 bits are the 128-bit rounding level
    // (2^(24−128)/cos φ_min), 20 orders below the f64 pseudo-orbit's (≥ u = 1.1e-16).
    let tol = (24.0 - BITS as f64).exp2() / sh.min_cos_phi.unwrap().min(1.0);
    assert!(max(&d_true) <= tol, "{:e}", max(&d_true));
    assert!(max(&d_f64) > 1e-17, "{:e}", max(&d_f64));
}

#[test]
fn the_analytic_jacobian_matches_central_differences() {
    let sc = scene("0.1");
    let y = segment(&sc, 3, 20);
    let bits = 256;
    let table = Table::new(&sc, bits).unwrap();
    let h = Float::with_val(bits, 1e-35);
    for k in 0..19 {
        let x = OrbitPoint {
            disk: y[k].disk,
            s: Float::with_val(bits, &y[k].s),
            p: Float::with_val(bits, &y[k].p),
        };
        let (_, jac) = table.map(&x, y[k + 1].disk).unwrap();
        let det = jac[0].clone() * &jac[3] - &(jac[1].clone() * &jac[2]);
        assert!((det.to_f64() - 1.0).abs() < 1e-30, "det DT = {det}");
        for dir in 0..2 {
            let shifted = |sign: f64| {
                let mut z = x.clone();
                if dir == 0 {
                    z.s += h.clone() * sign;
                } else {
                    z.p += h.clone() * sign;
                }
                table.map(&z, y[k + 1].disk).unwrap().0
            };
            let (fp, fm) = (shifted(1.0), shifted(-1.0));
            let two_h = h.clone() * 2u32;
            let ds = ((fp.s - &fm.s) / &two_h).to_f64();
            let dp = ((fp.p - &fm.p) / &two_h).to_f64();
            // Central differences: error ~h²·|D³T| ≈ 1e-70·… plus 2^-256/h ≈ 1e-42.
            let scale = 1.0 + jac.iter().map(|v| v.to_f64().abs()).fold(0.0, f64::max);
            assert!((ds - jac[dir].to_f64()).abs() < 1e-25 * scale, "k {k}");
            assert!((dp - jac[2 + dir].to_f64()).abs() < 1e-25 * scale, "k {k}");
        }
    }
}

#[test]
fn grazing_segments_are_reported_not_panicked() {
    let sc = scene("0.1");
    let y = segment(&sc, 4, 100);
    // Exactly tangent outgoing velocity at event 50: cos φ = 0, DT is singular there.
    let mut g = y.clone();
    g[50].p = Float::with_val(BITS, 1);
    let sh = shadow_pseudo_orbit(&sc, &g, BITS).unwrap();
    assert!(!sh.converged);
    let why = sh.failure.unwrap();
    assert!(why.contains("grazing collision at event 50"), "{why}");
    // Nearly tangent (cos φ ≈ 1e-15): the flight no longer reaches the recorded disk, or Newton
    // cannot repair it; either way a reason, never a panic.
    let mut g = y.clone();
    g[50].p = Float::with_val(BITS, 1) - Float::with_val(BITS, 1e-30);
    let sh = shadow_pseudo_orbit(&sc, &g, BITS).unwrap();
    assert!(!sh.converged);
    let why = sh.failure.unwrap();
    assert!(
        why.contains("misses") || why.contains("passes through") || why.contains("grazing"),
        "{why}"
    );
}

#[test]
fn bad_requests_name_the_valid_range() {
    let sc = scene("0.1");
    let y = segment(&sc, 0, 3);
    let e = shadow_pseudo_orbit(&sc, &y[..1], BITS)
        .unwrap_err()
        .to_string();
    assert!(e.contains("use 2 to 10000"), "{e}");
    let e = shadow_pseudo_orbit(&sc, &y, 64).unwrap_err().to_string();
    assert!(e.contains("use 128 to"), "{e}");
    let e = shadowing::run(&sc, &request(10, 0), &crate::common::threads(1))
        .unwrap_err()
        .to_string();
    assert!(e.contains("use 1 to"), "{e}");
}
