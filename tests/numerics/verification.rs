//! Verification: reversibility with a chaos-aware bound, Liouville invariance of the Birkhoff
//! map, uniform sin φ at collisions, and f64 events replayed in MPFR within the error model.

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::kernel::cell::CellKernel;
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::kernel::{flight::EventKind, flight::Flight, trap::Trap};
use lorentz_gas::numbers::real::Real;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::{Lattice, LatticeState, TriangularLattice};
use lorentz_gas::scenes::sampling::stream;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::scenes::triangular::equilibrium_state;
use lorentz_gas::statistics::{mean_se, normal_sigma_equivalent_t};

use crate::common::{t4_welch, z};
use lorentz_gas::verification::birkhoff::{birkhoff_jacobian, det2};
use lorentz_gas::verification::error_model::UNIT_ROUNDOFF;
use lorentz_gas::verification::replay::check_event;
use lorentz_gas::verification::reversibility::{
    Reversal, amplification, reversal_bound, reverse_and_return,
};
use rand::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;
use rug::Float;

/// `n` collisions forward, reversed and back, with the bound on the errors.
pub(crate) struct Reversed<T> {
    /// The errors of the return.
    pub r: Reversal<T>,
    /// The largest flow Jacobian max‖J‖ along the orbit.
    pub amp: f64,
    /// Events of the orbit.
    pub events: u64,
    /// 2·E·256u·max‖J‖ (E events, u the unit roundoff).
    pub bound: f64,
}

/// `n` collisions of `lat` from `start`, reversed and back, at the unit roundoff `u`.
pub(crate) fn reversal_with_bound<T: Real, K: CellKernel<T>>(
    lat: &Lattice<T, K>,
    start: &LatticeState<T>,
    n: u64,
    u: f64,
) -> Reversed<T> {
    let r = reverse_and_return(lat, start, n).unwrap();
    let (amp, events) = amplification(lat, start, n).unwrap();
    let bound = reversal_bound(u, events, amp);
    Reversed {
        r,
        amp,
        events,
        bound,
    }
}

/// f64: N collisions forward and back return within 2·E·256u·max‖J‖ (E events, J the flow
/// Jacobian along the orbit), for N up to 25 — where max‖J‖ has grown to ~1e10.
#[test]
fn f64_reversal_within_the_chaos_bound() {
    for (k, &w) in [0.05, 0.1, 0.2, 0.3].iter().enumerate() {
        let lat = TriangularLattice::new(w).unwrap();
        for n in [1u64, 5, 10, 25] {
            let start = equilibrium_state(lat.trap(), &mut stream(21, k as u64 * 100 + n));
            let Reversed { r, bound, .. } = reversal_with_bound(&lat, &start, n, UNIT_ROUNDOFF);
            assert!(
                r.position_error <= bound,
                "w={w} n={n}: {:e} > {bound:e}",
                r.position_error
            );
            assert!(
                r.velocity_error <= bound,
                "w={w} n={n}: {:e} > {bound:e}",
                r.velocity_error
            );
        }
    }
}

/// 256 bits: 50 collisions forward and back return to better than 1e-50 (and within the bound).
#[test]
fn mpfr256_fifty_collisions_return_below_1e_minus_50() {
    for (k, &w) in [0.1, 0.2].iter().enumerate() {
        let lat64 = TriangularLattice::new(w).unwrap();
        let start64 = equilibrium_state(lat64.trap(), &mut stream(22, k as u64));
        let lat = TriangularLattice::new(Float::with_val(256, w)).unwrap();
        let mut start = LatticeState::<Float>::convert_from_f64(256, &start64);
        start.flight.normalise_speed();
        let u = <Float as Real>::unit_roundoff(256);
        let Reversed { r, amp, bound, .. } = reversal_with_bound(&lat, &start, 50, u);
        let err = r.position_error.to_f64().max(r.velocity_error.to_f64());
        assert!(err < 1e-50, "w={w}: {err:e}");
        assert!(err <= bound, "w={w}: {err:e} > bound {bound:e}");
        eprintln!(
            "w={w}: 50 collisions at 256 bits return within {err:e} (bound {bound:e}, max|J| {amp:e})"
        );
    }
}

/// Liouville: the Birkhoff map (s, sin φ) ↦ (s', sin φ') has |det DT| = 1. Central differences
/// at 256 bits with h = 2⁻⁹⁰: truncation ~h²·|D³T| ≲ 1e-54·1e6, rounding ~u/h·|DT| ≲ 1e-50·1e3,
/// so 1e-40 is a bound with a wide margin (proofs-notes/liouville.md).
#[test]
fn birkhoff_map_preserves_phase_space_volume() {
    let dets = birkhoff_determinants(24, 23, |rng| {
        let w = 0.02 + 0.28 * rng.random::<f64>();
        let s = 0.05 + (std::f64::consts::FRAC_PI_3 - 0.1) * rng.random::<f64>();
        (TriangularScene::new(w).unwrap(), format!("w={w}"), s)
    });
    for (what, det) in dets {
        let dev = (det.clone().abs() - 1u32).abs().to_f64();
        assert!(dev < 1e-40, "{what}: det = {det}");
        // Orientation: with s counter-clockwise and φ from the outward normal, det = +1.
        assert!(det.is_sign_positive(), "det = {det}");
    }
}

/// det DT of the Birkhoff map by central differences at 256 bits (h = 2⁻⁹⁰) at `count` points
/// drawn from stream `seed`: `draw` gives the scene, its name for messages and the arc length s,
/// then sin φ is drawn uniform in [−0.95, 0.95]; a point whose next collision is out of reach is
/// drawn again.
pub(crate) fn birkhoff_determinants<S: Scene>(
    count: usize,
    seed: u64,
    mut draw: impl FnMut(&mut Xoshiro256PlusPlus) -> (S, String, f64),
) -> Vec<(String, Float)> {
    let bits = 256;
    let h = Float::with_val(bits, Float::i_exp(1, -90));
    let mut rng = stream(seed, 0);
    let mut dets = Vec::new();
    while dets.len() < count {
        let (scene, what, s) = draw(&mut rng);
        let s = Float::with_val(bits, s);
        let p = Float::with_val(bits, 1.9 * rng.random::<f64>() - 0.95);
        if let Some(j) = birkhoff_jacobian(&scene, bits, &s, &p, &h).unwrap() {
            dets.push((what, det2(&j)));
        }
    }
    dets
}

/// At collisions sin φ is uniform on [−1, 1] (the invariant measure cos φ dφ ds). Twenty bins,
/// frequencies from 16 independent trajectories: every bin within 4.5σ of 1/20 — the z-score of a
/// mean over 16 trajectories is Student-t with 15 dof, so "4.5σ" is its quantile at the normal's
/// two-sided 4.5σ tail probability 6.8·10⁻⁶ (6.73; 40 bins make a family-wise 2.7·10⁻⁴).
#[test]
fn sin_phi_is_uniform_at_collisions() {
    let bins = 20;
    for &w in &[0.05, 0.25] {
        let lat = TriangularLattice::new(w).unwrap();
        let mut freq: Vec<Vec<f64>> = vec![Vec::new(); bins];
        for b in 0..16 {
            let mut s = equilibrium_state(lat.trap(), &mut stream(24, b));
            let mut hist = vec![0u64; bins];
            let mut c = 0;
            while c < 250_000 {
                if let EventKind::Collision(m) = lat.step(&mut s).unwrap().kind {
                    c += 1;
                    let n = s.flight.pos.sub(&lat.trap().vertices()[m as usize]);
                    let sin_phi = n.cross(&s.flight.vel);
                    let k = (((sin_phi + 1.0) / 2.0 * bins as f64) as usize).min(bins - 1);
                    hist[k] += 1;
                }
            }
            for k in 0..bins {
                freq[k].push(hist[k] as f64 / c as f64);
            }
        }
        for (k, f) in freq.iter().enumerate() {
            let (m, se) = mean_se(f);
            let t = normal_sigma_equivalent_t(f.len() as f64 - 1.0, 4.5);
            assert!(
                (m - 0.05).abs() <= t * se,
                "w={w} bin {k}: {m} ± {se} (t = {:.2}, bound {t:.2})",
                (m - 0.05) / se
            );
        }
    }
}

/// f64 vs MPFR-256 on single events from random states: every event within the one-step error
/// model (time, contact point, outgoing velocity, and which obstacle).
#[test]
fn f64_events_replayed_in_mpfr_are_within_the_error_model() {
    let mut rng = stream(25, 0);
    let mut worst: f64 = 0.0;
    for i in 0..3000 {
        let w = 0.001 + 0.308 * rng.random::<f64>();
        let t64 = Trap::new(w).unwrap();
        let tr = Trap::new(Float::with_val(256, w)).unwrap();
        let lat = TriangularLattice::new(w).unwrap();
        let mut s = equilibrium_state(&t64, &mut rng);
        // Advance a few events so the state has exclusions and post-collision velocities.
        for _ in 0..(i % 7) {
            lat.step(&mut s).unwrap();
        }
        let c = check_event(&t64, &tr, &s.flight).unwrap();
        assert!(
            c.in_model,
            "event outside the model: {c:?} from {:?}",
            s.flight
        );
        // Where both choose the same event the time error is within its bound (the model's
        // claim, ratio ≤ 1); where they legitimately differ (an ambiguous choice) the two times
        // belong to different events and the ratio means nothing.
        if c.kind_f64 == c.kind_ref && c.time_bound > 0.0 {
            worst = worst.max(c.time_error / c.time_bound);
        }
    }
    eprintln!("largest time error / bound: {worst:.3e}");
    assert!(worst <= 1.0, "a time error beyond its bound: ratio {worst}");
}

/// The canonical hard case of the naive root: a start a hair off a disk surface, moving in.
#[test]
fn near_surface_start_replays_within_the_model() {
    let t64 = Trap::new(0.1).unwrap();
    let tr = Trap::new(Float::with_val(256, 0.1)).unwrap();
    for k in 1..50 {
        let eps = (-(k as f64)).exp2();
        let ang: f64 = 0.5;
        let p = Vec2::new((1.0 + eps) * ang.cos(), (1.0 + eps) * ang.sin());
        let v = Vec2::new(-(ang + 0.3).cos(), -(ang + 0.3).sin());
        let f = Flight::new(p, v);
        let c = check_event(&t64, &tr, &f).unwrap();
        assert!(c.in_model, "eps = 2^-{k}: {c:?}");
    }
}

/// The per-event audit of production trajectories: every replayed event inside the model; the
/// recorded worst events replay to the same verdict from their exact bit patterns.
#[test]
fn audit_of_production_trajectories_finds_nothing_outside_the_model() {
    use lorentz_gas::verification::shadow_audit::replay;
    for &w in &[0.02, 0.1, 0.3] {
        let scene = TriangularScene::new(w).unwrap();
        let r = crate::common::full_audit(&scene, 100_000, 7, None, Default::default());
        crate::common::assert_audit_clean(&r, 100_000, &format!("w={w}"));
        assert!(r.quantiles.time_error_over_bound.max <= 1.0);
        let worst = &r.summary.worst[0];
        let again = replay(&scene, worst, 128).unwrap();
        assert_eq!(again.time_error, worst.check.time_error);
        assert_eq!(again.kind_f64, worst.check.kind_f64);
    }
}

/// A production run audits itself on a sample of its events without changing its result.
#[test]
fn diffusion_self_audit_samples_events_and_leaves_d_unchanged() {
    use lorentz_gas::engine::options::AuditSpec;
    use lorentz_gas::estimators::diffusion::{DiffusionConfig, run};
    let mut cfg = DiffusionConfig::new(0.12);
    cfg.collisions = 2_000_000;
    cfg.batches = 4;
    cfg.window = "2:8".parse().unwrap();
    cfg.check_window = "4:16".parse().unwrap();
    let plain = run(&cfg, &crate::common::threads(2)).unwrap();
    let audit = Some(AuditSpec {
        rate: 0.01,
        bits: 128,
    });
    let opts = RunOptions {
        threads: 2,
        audit,
        ..RunOptions::default()
    };
    let audited = run(&cfg, &opts).unwrap();
    assert_eq!(plain.D.to_bits(), audited.D.to_bits());
    let a = audited.audit.unwrap();
    // Each event is replayed independently with probability r (the auditor's own stream), so
    // given the number of events E the count is Binomial(E, r). E = C + H: C collisions (fixed)
    // and H crossings, E[H] = C·3w/π exactly (Kac: π/(3w) collisions per hop). Over the law of H,
    //   Var(count) = E[E]·r(1 − r) + r²·Var(H),
    // Var(H) from the batch ratios ρ_b = C_b/H_b: H = Σ C_b/ρ_b, δH ≈ −(C/ρ²)·δρ̄, so
    // sd(H) ≈ C·se(ρ̄)/ρ² (a 0.2 % correction). At C = 2·10⁶, w = 0.12: σ ≈ 149; 5σ ≈ 743.
    // The count is ~2·10⁴, so the normal approximation is good far into the tails.
    let r = 0.01;
    let c = audited.collisions as f64;
    let events = c * (1.0 + 1.0 / audited.collisions_per_hop_exact);
    let sd_h = c * audited.collisions_per_hop_err / audited.collisions_per_hop.powi(2);
    let sigma = (events * r * (1.0 - r) + r * r * sd_h * sd_h).sqrt();
    let expected = r * events;
    assert!(
        (a.audited as f64 - expected).abs() <= 5.0 * sigma,
        "{} events audited, expected {expected:.0} ± {sigma:.0} ({:.1}σ)",
        a.audited,
        (a.audited as f64 - expected) / sigma
    );
    assert_eq!(a.outside, 0);
    let mut rug = cfg.clone();
    rug.precision = lorentz_gas::numbers::precision::Precision::Bits(128);
    assert!(run(&rug, &opts).is_err());
}

/// The growth rate of the deviation between a P-bit orbit and a 4096-bit reference (precision
/// divergence) equals the tangent-space Lyapunov exponent within 4 combined standard errors, per
/// collision and per unit time, at three gaps; and the divergence horizon grows with the bits by
/// ln 2/λ collisions per bit (f64 → 256 → 1024 bits).
/// Both errors are over 8 independent orbits/starts: "4σ" is the Student-t quantile at the
/// Welch–Satterthwaite dof (7 to 14) for the normal's two-sided 4σ tail probability. (All 8
/// starts give a finite rate at 1024 bits — checked: the fit range 10⁴u..10⁻³ is a growth by
/// e⁶⁹⁵, hundreds of collisions, far more than the 5 points a fit needs.)
#[test]
fn divergence_rate_matches_the_tangent_space_lyapunov_exponent() {
    use lorentz_gas::verification::divergence::{self, DivergenceConfig};
    use lorentz_gas::verification::lyapunov::{self, LyapunovConfig};
    const STARTS: u32 = 8;
    for &w in &[0.05, 0.15, 0.3] {
        let scene = TriangularScene::new(w).unwrap();
        let two = crate::common::threads(2);
        let cfg = LyapunovConfig {
            collisions_per_batch: 200_000,
            batches: 8,
            seed: 3,
            ..LyapunovConfig::new()
        };
        let l = lyapunov::run(&scene, &cfg, &two).unwrap();
        let cfg = DivergenceConfig {
            bits: vec![256, 1024],
            reference_bits: 4096,
            collisions: 1200,
            starts: STARTS,
            seed: 3,
        };
        let d = divergence::run(&scene, &cfg, &two).unwrap();
        let last = d.last().unwrap();
        // Within the 4σ bound of the two means (Welch–Satterthwaite degrees of freedom).
        let agree = |a: f64, ea: f64, b: f64, eb: f64| {
            z(a, ea, b, eb) < t4_welch(ea, STARTS, eb, l.batches)
        };
        assert!(
            agree(
                last.rate_per_collision,
                last.rate_per_collision_err,
                l.per_collision,
                l.per_collision_err
            ),
            "w={w}: {last:?} vs {l:?}"
        );
        assert!(
            agree(
                last.rate_per_time,
                last.rate_per_time_err,
                l.per_time,
                l.per_time_err
            ),
            "w={w}: {last:?} vs {l:?}"
        );
        // Horizons: f64 < 256 bits < 1024 bits, each roughly ∝ bits (ln 2·bits/λ).
        assert!(
            d[0].horizon < d[1].horizon && d[1].horizon < d[2].horizon,
            "{d:?}"
        );
        // The deviation of a P-bit orbit grows like C·2⁻ᴾ·e^{λk} from the same start, so the
        // horizon (first k with deviation > 10⁻³) is (P·ln 2 + ln 10⁻³ − ln C)/λ: the unknown
        // prefactor C cancels between two precisions, whose horizons differ by ΔP·ln 2/λ. The
        // horizons are means over the same 8 starts, each with its batch SE; their difference
        // has an SE of at most the sum of the two (whatever their correlation), to which the
        // error of λ adds ΔP·ln 2·SE(λ)/λ². Bound: the Student-t quantile with 7 dof at the
        // normal's 4σ tail probability (8 starts) times that SE.
        let t7 = normal_sigma_equivalent_t(STARTS as f64 - 1.0, 4.0);
        for (lo, hi, dp) in [(0, 1, 256.0 - 53.0), (1, 2, 1024.0 - 256.0)] {
            let predicted = dp * std::f64::consts::LN_2 / l.per_collision;
            let measured = d[hi].horizon - d[lo].horizon;
            let se = d[lo].horizon_err
                + d[hi].horizon_err
                + predicted * l.per_collision_err / l.per_collision;
            assert!(
                (measured - predicted).abs() <= t7 * se,
                "w={w}: horizon {} − {} = {measured} vs ΔP·ln2/λ = {predicted} (SE {se}, bound {:.1})",
                d[hi].precision,
                d[lo].precision,
                t7 * se
            );
        }
    }
}

/// Precision doubling certifies 300 collisions to 40 digits; the automatically chosen precision
/// is near λN/ln2 + 40·log₂10 bits, and the f64 orbit from the same start follows the certified
/// one for about (53·ln 2 + ln 10⁻³)/λ ≈ 33 collisions: its divergence horizon. That horizon is
/// measured independently by `verification::divergence` from the same start (stream (31, 0))
/// against a 256-bit reference, where the deviation is the sum of the four coordinates' and
/// certify's the largest of them: the sum passes 10⁻³ no later than the largest does, and the
/// largest no later than the sum passes 4·10⁻³, ln 4/λ collisions (plus one for the integer
/// step) after.
#[test]
fn precision_doubling_certifies_a_segment() {
    use lorentz_gas::verification::certify::{self, CertifyConfig};
    // The start of trajectory 0 of seed 31 (the scene's equilibrium sampler on stream (31, 0)).
    let cfg = CertifyConfig {
        collisions: 300,
        digits: 40,
        seed: 31,
    };
    let scene = TriangularScene::new(0.1).unwrap();
    let c = certify::run(&scene, &cfg, &RunOptions::default()).unwrap();
    assert!(c.digits_agreed >= 40.0, "{c:?}");
    assert!(c.bits >= 400 && c.bits <= 1024, "{c:?}");
    use lorentz_gas::verification::divergence::{self, DivergenceConfig};
    use lorentz_gas::verification::lyapunov::{self, LyapunovConfig};
    let one = DivergenceConfig {
        bits: vec![],
        reference_bits: 256,
        collisions: 300,
        starts: 1,
        seed: 31,
    };
    let horizon = divergence::run(&scene, &one, &RunOptions::default()).unwrap()[0].horizon;
    let lambda = lyapunov::run(
        &scene,
        &LyapunovConfig {
            collisions_per_batch: 100_000,
            batches: 4,
            seed: 3,
            ..LyapunovConfig::new()
        },
        &RunOptions::default(),
    )
    .unwrap();
    let lag = 4f64.ln() / (lambda.per_collision - 4.0 * lambda.per_collision_err) + 1.0;
    let faithful = c.f64_faithful_collisions as f64;
    assert!(
        faithful >= horizon && faithful <= horizon + lag,
        "f64 faithful for {faithful} collisions; the divergence horizon from the same start is {horizon} (+ at most {lag:.1}): {c:?}"
    );
    eprintln!(
        "f64 faithful for {faithful} collisions, divergence horizon {horizon}, (53 ln2 + ln 1e-3)/lambda = {:.1}",
        (53.0 * std::f64::consts::LN_2 + 1e-3f64.ln()) / lambda.per_collision
    );
}

/// Statistics do not depend on precision: D and the mean free path from an MPFR-128 run (fewer
/// collisions, larger errors) agree with the f64 values within 4 combined standard errors, and
/// the MPFR run's mean free path agrees with Santaló's value within 4σ. Both runs have 16
/// batches; "4σ" is the Student-t quantile at the normal's 4σ tail probability, with 15 dof
/// against the exact value and the Welch–Satterthwaite dof for the comparisons (with 4 batches it
/// would be t₃ = 32.6).
#[test]
fn statistics_do_not_move_with_precision() {
    use lorentz_gas::estimators::diffusion::{DiffusionConfig, run};
    use lorentz_gas::numbers::precision::Precision;
    let mut cfg = DiffusionConfig::new(0.2);
    cfg.batches = 16;
    cfg.window = "2:8".parse().unwrap();
    cfg.check_window = "4:16".parse().unwrap();
    cfg.collisions = 1_200_000;
    cfg.precision = Precision::Bits(128);
    let hi = run(&cfg, &crate::common::threads(2)).unwrap();
    cfg.collisions = 40_000_000;
    cfg.batches = 16;
    cfg.precision = Precision::F64;
    let lo = run(&cfg, &crate::common::threads(2)).unwrap();
    let (n_hi, n_lo) = (
        hi.meta.batches.unwrap() as u32,
        lo.meta.batches.unwrap() as u32,
    );
    let t4 = |ea: f64, eb: f64| t4_welch(ea, n_hi, eb, n_lo);
    assert!(
        z(hi.D, hi.D_err, lo.D, lo.D_err) < t4(hi.D_err, lo.D_err),
        "D: {} ± {} (128) vs {} ± {} (f64)",
        hi.D,
        hi.D_err,
        lo.D,
        lo.D_err
    );
    assert!(
        z(
            hi.mean_free_path,
            hi.mean_free_path_err,
            lo.mean_free_path,
            lo.mean_free_path_err
        ) < t4(hi.mean_free_path_err, lo.mean_free_path_err),
        "mean free path: {} ± {} (128) vs {} ± {} (f64)",
        hi.mean_free_path,
        hi.mean_free_path_err,
        lo.mean_free_path,
        lo.mean_free_path_err
    );
    let t_exact = normal_sigma_equivalent_t(hi.meta.batches.unwrap() as f64 - 1.0, 4.0);
    assert!(
        (hi.mean_free_path - hi.mean_free_path_exact).abs() < t_exact * hi.mean_free_path_err,
        "mean free path at 128 bits: {} ± {} vs {}",
        hi.mean_free_path,
        hi.mean_free_path_err,
        hi.mean_free_path_exact
    );
    eprintln!(
        "D(0.2): {} ± {} at 128 bits, {} ± {} at f64",
        hi.D, hi.D_err, lo.D, lo.D_err
    );
}
