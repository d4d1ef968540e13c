//! True shadowing of f64 segments (`proofs-notes/shadowing.md`): Newton on the whole segment in
//! MPFR finds a true orbit with the same disk sequence near every f64 collision point.

use rug::Float;

use lorentz_gas::numbers::exact::parse_exact;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::verification::error_model::UNIT_ROUNDOFF;
use lorentz_gas::verification::shadowing::{
    self as shadowing, CONVERGENCE_SLACK_BITS, OrbitPoint, Shadow, ShadowConfig, Table, defects,
    f64_segment, shadow_pseudo_orbit,
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
        motion: Default::default(),
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
/// * δ cannot be smaller than the pseudo-orbit's defects allow: F_k(y⁰) is the sum of
///   T(x⁰_k) − T(x*_k), F_k(y*) and x*_{k+1} − x⁰_{k+1}, and by the mean value theorem
///   ‖T(x⁰_k) − T(x*_k)‖ ≤ (‖DT(x*_k)‖ + Mδ)·δ, so
///   max_k‖F_k(y⁰)‖ ≤ (1 + max‖DT‖ + Mδ)·δ + max‖F_k(y*)‖ — exactly, not to first order.
///   Checked on the reported numbers with: M = 100·M_est (the margin the certificate puts on
///   the secant estimate; 100·M_est·δ ≲ 3e-9 ≪ 1 here); ‖F_k(y*)‖ ≤ the 2P-bit residual plus
///   one evaluation allowance e_T = 2^(24−P)/cos φ_min, and the P-bit evaluation of F(y⁰) off
///   by another e_T (2e_T ≈ 3e-30, vs δ ≈ 5e-16); and the roundings to `f64` — δ and
///   max‖F_k(y⁰)‖ by u each, the Frobenius max‖DT‖ (≥ the spectral norm) from rounded entries
///   by ≤ 4u, the test's own products and sums by 4u — within 16u relative.
///   The measured margin is a factor ≥ 6 (the defects are not worst-case aligned), so this
///   is a consistency check of δ, not a tight one.
/// * δ ≤ 1e-13: the f64 one-step errors are ≲ 16u·(1 + 1/cos φ) ≈ 1e-14 at cos φ ≳ 0.03
///   (`proofs-notes/error-model.md`) and the K measured here is ≲ 50, the linear response to
///   independent errors stays at the single-step level; 1e-13 is the expectation (1e-14)
///   with a factor 10 for the worst of a few segments.
/// * residual at 2P ≤ 2^(24−P)/cos φ_min: the stopping rule (the orbit is stored at P bits).
fn assert_clean(sh: &Shadow, what: &str) {
    assert_certified(sh, what);
    let delta = sh.delta.unwrap();
    assert!(delta <= 1e-13, "{what}: delta {delta:e} above 1e-13");
}

/// Every claim of [`assert_clean`] but the empirical δ ≤ 1e-13: what the theorem and the stopping
/// rule give (shared with the shadows of arcs, `arc_shadowing.rs`).
pub(crate) fn assert_certified(sh: &Shadow, what: &str) {
    assert!(sh.converged, "{what}: {:?}", sh.failure);
    assert!(sh.certified, "{what}: {:?}", sh.failure);
    let delta = sh.delta.unwrap();
    let amax = sh.max_jacobian_norm.unwrap();
    assert!(
        delta <= sh.a_priori_bound.unwrap(),
        "{what}: delta {delta:e}"
    );
    let tol =
        (CONVERGENCE_SLACK_BITS as f64 - BITS as f64).exp2() / sh.min_cos_phi.unwrap().min(1.0);
    let m = 100.0 * sh.second_derivative_estimate.unwrap();
    let defect = sh.pseudo_orbit_defect.unwrap();
    let reach = (1.0 + 16.0 * UNIT_ROUNDOFF) * delta * (1.0 + amax + m * delta)
        + sh.residual.unwrap()
        + 2.0 * tol;
    assert!(
        defect <= reach,
        "{what}: delta {delta:e} below the defects' lower bound: defect {defect:e} > {reach:e}"
    );
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

/// The analytic DT_k against central differences, compared in MPFR at P = 256 bits (not in
/// `f64`: converting both sides with `to_f64` would round them to the same double whenever they
/// agree to ~1e-17 relative, so a tolerance below u = 1.1e-16 would test nothing).
///
/// Error model of (T(x + h·e) − T(x − h·e))/(2h) − DT·e, with c = min(1, cos φ, cos φ′) at the
/// event and J = max |DT entry|:
/// * the steps are exact: x has 128 significant bits and 2⁻¹¹⁶ ≤ |x| < 4 (s ∈ (−π, π],
///   p ∈ (−1, 1)), h = 2⁻¹¹⁶ is a power of two, so x ± h and the division by 2h are exact at
///   256 bits (the subtraction of the two images rounds relatively by 2⁻²⁵⁶, negligible);
/// * rounding: each evaluation of T is within e_T = 2^(S−P)/c of the exact map (the library's
///   allowance, S = `CONVERGENCE_SLACK_BITS` = 24: ~20 roundings amplified by 1/cos φ′), so the
///   quotient is off by ≤ 2e_T/(2h) = 2^(S−P)/(h·c) = 2⁻¹¹⁶/c ≈ 1.2e-35/c;
/// * the analytic entries round by the same allowance times 1 + J: 2^(S−P)·(1 + J)/c ≲ 4e-69;
/// * truncation: h²/6·|D³T| with |D³T| ≲ J³/c⁴ (the powers of 1/cos φ of D²T ≲ J²/(cos φ cos φ′)
///   once more; a heuristic, not derived): ≲ 1.5e-70·J³/c⁴ ≲ 1e-65 here, 30 orders below.
///
/// So tol = 2^(S−P)·(1/h + 1 + J)/c + h²·J³/c⁴ ≈ 1.2e-35/c (c ≥ 0.27 on this segment). The
/// measured differences are ≤ 3e-42, i.e. the real e_T is a few units of 2⁻²⁵⁶ and the allowance
/// has its 2²⁴ slack to spare; a relative 1e-20 error in the analytic DT fails by 15 orders.
/// det DT = 1 (Liouville): the entries' errors 2^(S−P)·(1 + J)/c enter twice in each of the two
/// products, |det − 1| ≤ 4J·2^(S−P)·(1 + J)/c (≈ 1e-67; measured ≤ 1e-76).
#[test]
fn the_analytic_jacobian_matches_central_differences() {
    let sc = scene("0.1");
    let y = segment(&sc, 3, 20);
    let bits = 256;
    let table = Table::new(&sc, bits).unwrap();
    let h = Float::with_val(bits, -116f64).exp2();
    for k in 0..19 {
        assert_eq!(
            (y[k].s.prec(), y[k].p.prec()),
            (BITS, BITS),
            "the steps x ± h are exact for 128-bit points"
        );
        assert_step_jacobian(&table, bits, &y[k], y[k + 1].disk, &h, &format!("k {k}"));
    }
}

/// Asserts that the analytic DT of the step from `from` (taken at the table's precision `bits`)
/// to the disk `next` on `table` matches central differences of step `h` within
/// tol = 2^(S−P)·(1/h + 1 + J)/c + h²·J³/c⁴, and that det DT = 1 within 4J times the entries'
/// error 2^(S−P)·(1 + J)/c (c the smaller cos φ of the step's ends); `what` names the step.
pub(crate) fn assert_step_jacobian(
    table: &Table,
    bits: u32,
    from: &OrbitPoint,
    next: [i64; 2],
    h: &Float,
    what: &str,
) {
    let rounding = (CONVERGENCE_SLACK_BITS as f64 - bits as f64).exp2();
    let cos = |p: &Float| {
        (Float::with_val(bits, 1) - p.clone().square())
            .sqrt()
            .to_f64()
    };
    let x = OrbitPoint {
        disk: from.disk,
        s: Float::with_val(bits, &from.s),
        p: Float::with_val(bits, &from.p),
    };
    let (image, jac) = table.map(&x, next).unwrap();
    let c = cos(&x.p).min(cos(&image.p)).min(1.0);
    let big_j = jac.iter().map(|v| v.to_f64().abs()).fold(0.0, f64::max);
    let entry_err = rounding * (1.0 + big_j) / c;
    let tol = rounding * (1.0 / h.to_f64() + 1.0 + big_j) / c
        + h.to_f64().powi(2) * big_j.powi(3) / c.powi(4);
    let det = jac[0].clone() * &jac[3] - &(jac[1].clone() * &jac[2]);
    let det_err = (det - 1u32).abs().to_f64();
    assert!(
        det_err <= 4.0 * big_j * entry_err,
        "{what}: det DT − 1 = {det_err:e}"
    );
    assert_central_differences(table, &x, next, &jac, h, tol, what);
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

/// Asserts that each entry of `jac`, the analytic DT at `x` towards the disk `next` on `table`,
/// is within `tol` of the central difference (T(x + h·e) − T(x − h·e))/(2h), compared in MPFR at
/// the table's precision.
pub(crate) fn assert_central_differences(
    table: &Table,
    x: &OrbitPoint,
    next: [i64; 2],
    jac: &[Float; 4],
    h: &Float,
    tol: f64,
    what: &str,
) {
    let two_h = h.clone() * 2u32;
    for dir in 0..2 {
        let shifted = |sign: i32| {
            let mut z = x.clone();
            if dir == 0 {
                z.s += h.clone() * sign;
            } else {
                z.p += h.clone() * sign;
            }
            table.map(&z, next).unwrap().0
        };
        let (fp, fm) = (shifted(1), shifted(-1));
        let es = ((fp.s - &fm.s) / &two_h - &jac[dir]).abs().to_f64();
        let ep = ((fp.p - &fm.p) / &two_h - &jac[2 + dir]).abs().to_f64();
        assert!(
            es <= tol,
            "{what}, dir {dir}: |ds/dx − DT| = {es:e} > {tol:e}"
        );
        assert!(
            ep <= tol,
            "{what}, dir {dir}: |dp/dx − DT| = {ep:e} > {tol:e}"
        );
    }
}
