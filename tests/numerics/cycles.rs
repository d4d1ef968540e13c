//! Certified periodic orbits of open tables and the cycle expansions of the three-disk repeller
//! (`proofs-notes/cycles.md`).

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::verification::cycles::repeller::{RepellerConfig, fundamental_cycle, run};
use lorentz_gas::verification::cycles::symbols::{full_space, full_space_prime_count, prime_words};
use lorentz_gas::verification::cycles::{Disks, certify_cycle};
use rug::Float;

const BITS: u32 = 256;

/// The escape rate of the three-disk repeller at R:a = 6 (a = 1, unit speed), the value the
/// issue's brief quotes from ChaosBook (`proofs-notes/cycles.md` on its provenance).
const GAMMA_R6: &str = "0.4103384077693464893384613078192";

/// The two-disk cycle: T = 2(R − 2a) and, per bounce, Λ₁ = −[(R/a − 1) + √((R/a − 1)² − 1)]
/// (a reflection reverses the orientation), so Λ_p = Λ₁², each to the certificate's bounds.
#[test]
fn the_two_disk_cycle_has_its_closed_form_period_and_stability() {
    let cases = [
        Disks::three_disk(6, 1),
        Disks::Explicit {
            centres: vec![[0.0, 0.0], [2.625, 0.0]],
            radius: 0.75,
        },
        Disks::Explicit {
            centres: vec![[1.0, -2.0], [1.0 + 12.0, -2.0 + 5.0]],
            radius: 2.5,
        },
    ];
    for disks in &cases {
        let c = certify_cycle(disks, &[0, 1], BITS).unwrap();
        assert!(c.certified, "{:?}", c.failure);
        let centres = disks.centres(BITS);
        let r =
            (centres[1].x.clone() - &centres[0].x).hypot(&(centres[1].y.clone() - &centres[0].y));
        let a = Float::with_val(BITS, disks.radius());
        let period = (r.clone() - &(a.clone() * 2u32)) * 2u32;
        let t_err = (c.period_exact.clone().unwrap() - &period).abs().to_f64();
        assert!(
            t_err <= c.period_bound,
            "T error {t_err:e} > bound {:e}",
            c.period_bound
        );
        let q = r / &a - 1u32;
        let per_bounce = -(q.clone() + &(q.square() - 1u32).sqrt());
        let one = c.partial_stability(1);
        let two = c.partial_stability(2);
        let e1 = (one - &per_bounce).abs().to_f64();
        let e2 = (two - &per_bounce.square()).abs().to_f64();
        assert!(
            e1 <= c.stability_bound,
            "Λ₁ error {e1:e} > {:e}",
            c.stability_bound
        );
        assert!(
            e2 <= c.stability_bound,
            "Λ_p error {e2:e} > {:e}",
            c.stability_bound
        );
        assert!(c.radius < 1e-70 && c.stability_bound < 1e-60, "{c:?}");
    }
}

/// Disks 0 and 1 face each other across disk 2, whose centre lies 0.5 off their line: Newton's
/// map (which knows only the recorded disks) converges to the 0–1 bounce, and the kernel refuses
/// it; the cycle 0–2 beside it is certified.
#[test]
fn a_cycle_through_a_third_disk_is_pruned_by_the_kernel() {
    let disks = Disks::Explicit {
        centres: vec![[0.0, 0.0], [6.0, 0.0], [3.0, 0.5]],
        radius: 1.0,
    };
    let blocked = certify_cycle(&disks, &[0, 1], BITS).unwrap();
    assert!(blocked.residual < 1e-60, "Newton converged: {blocked:?}");
    let why = blocked
        .pruned
        .as_deref()
        .expect("the kernel must refuse the 0-1 cycle");
    assert!(why.contains("passes through disk 2"), "{why}");
    assert!(!blocked.certified);
    let free = certify_cycle(&disks, &[0, 2], BITS).unwrap();
    assert!(free.certified && free.pruned.is_none(), "{free:?}");
    // The three-disk repeller prunes nothing at R/a = 6: its 0–1 bounce is certified.
    let open = certify_cycle(&Disks::three_disk(6, 1), &[0, 1, 2, 1], BITS).unwrap();
    assert!(open.certified, "{:?}", open.failure);
}

/// Binary prime cycles of the fundamental domain: their number per length, the full-space
/// cycles they stand for (6/h each) against a brute-force count, and Λ_p̃^h = Λ_p, h·T_p̃ = T_p
/// with Λ₀ = +(5 + √24) > 0 and Λ₁ < 0 (a reflection is −I in Birkhoff coordinates).
#[test]
fn fundamental_cycles_stand_for_the_full_space_ones() {
    let words = prime_words(12);
    let per_length: Vec<usize> = (1..=12)
        .map(|n| words.iter().filter(|w| w.len() == n).count())
        .collect();
    assert_eq!(per_length, [2, 1, 2, 3, 6, 9, 18, 30, 56, 99, 186, 335]);
    for n in 2..=12 {
        let from_words: usize = words
            .iter()
            .map(|w| full_space(w))
            .filter(|(seq, _)| seq.len() == n)
            .map(|(_, h)| 6 / h)
            .sum();
        assert_eq!(from_words, full_space_prime_count(n), "length {n}");
    }
    let disks = Disks::three_disk(6, 1);
    for w in prime_words(5) {
        let f = fundamental_cycle(&disks, &w, BITS).unwrap();
        assert!(f.cycle.certified, "{}: {:?}", f.word, f.cycle.failure);
        let lam_p = f.cycle.partial_stability(f.cycle.disks.len());
        let rel = ((f.stability.powi(f.order as i32) - lam_p.to_f64()) / lam_p.to_f64()).abs();
        assert!(
            rel < 1e-13,
            "{}: Λ^h = {:e} against Λ_p = {:e}",
            f.word,
            f.stability.powi(f.order as i32),
            lam_p.to_f64()
        );
        assert!((f.period * f.order as f64 - f.cycle.period).abs() < 1e-13 * f.cycle.period);
    }
    let zero = fundamental_cycle(&disks, &[0], BITS).unwrap();
    assert!((zero.stability - (5.0 + 24f64.sqrt())).abs() < 1e-13);
    assert!(fundamental_cycle(&disks, &[1], BITS).unwrap().stability < -1.0);
}

/// The escape rate of the three-disk repeller at R:a = 6 from the spectral determinant's
/// curvature expansion, every cycle certified: at the first N whose truncation error estimate
/// |γ_N − γ_{N−1}| is below 10⁻¹² (N ≤ 12), γ_N agrees with the known value within that
/// estimate; the dynamical zeta function converges to the same value, more slowly.
#[test]
fn the_three_disk_escape_rate_at_r_over_a_6_is_the_known_value() {
    let config = RepellerConfig {
        max_length: 8,
        bits: BITS,
        ..RepellerConfig::new("6", "1")
    };
    let report = run(&config, &RunOptions::default()).unwrap();
    assert_eq!(report.certified, prime_words(8).len());
    let known = Float::with_val(128, Float::parse(GAMMA_R6).unwrap());
    let det = &report.spectral_determinant;
    let row = det
        .iter()
        .find(|t| t.escape_rate_error <= 1e-12)
        .expect("converged to 1e-12 by N = 8");
    let exact = row.escape_rate_exact.clone().unwrap();
    let off = (exact - &known).abs().to_f64();
    eprintln!(
        "N = {}: |gamma_N - known| = {off:.3e}, estimate {:.3e}",
        row.max_length, row.escape_rate_error
    );
    assert!(
        off <= row.escape_rate_error,
        "N = {}: |γ − known| = {off:e} > {:e}",
        row.max_length,
        row.escape_rate_error
    );
    let last = det.last().unwrap();
    let off_last = (last.escape_rate_exact.clone().unwrap() - &known)
        .abs()
        .to_f64();
    eprintln!(
        "N = 8: |gamma_N - known| = {off_last:.3e}, estimate {:.3e}",
        last.escape_rate_error
    );
    assert!(
        off_last <= last.escape_rate_error.max(1e-30),
        "N = 8: {off_last:e}"
    );
    let zeta = report.zeta_function.last().unwrap();
    let off_zeta = (zeta.escape_rate - known.to_f64()).abs();
    assert!(
        off_zeta <= zeta.escape_rate_error,
        "zeta: {off_zeta:e} > {:e}",
        zeta.escape_rate_error
    );
    assert!(
        zeta.escape_rate_error > 1e3 * last.escape_rate_error,
        "the determinant converges faster"
    );
    // h_KS = λ − γ, both from the same determinant.
    assert!((last.entropy - (last.lyapunov - last.escape_rate)).abs() < 1e-15);
}

#[test]
fn cycles_that_are_not_cycles_are_refused() {
    let disks = Disks::three_disk(6, 1);
    assert!(certify_cycle(&disks, &[0, 1, 1], BITS).is_err());
    assert!(certify_cycle(&disks, &[0, 1, 0], BITS).is_err()); // 0 follows 0 cyclically
    assert!(certify_cycle(&disks, &[0, 3], BITS).is_err());
    assert!(certify_cycle(&disks, &[0, 1], 64).is_err());
    assert!(
        certify_cycle(
            &Disks::three_disk(rug::Rational::from((3, 2)), 1),
            &[0, 1],
            BITS
        )
        .is_err()
    );
}

/// The convergence table to N = 12 with its cost (not run by default: the numbers of the
/// report, `cargo test --release --test numerics repeller_table -- --ignored --nocapture`).
#[test]
#[ignore]
fn repeller_table_to_12() {
    for side in ["6", "3"] {
        let config = RepellerConfig {
            max_length: 12,
            bits: BITS,
            ..RepellerConfig::new(side, "1")
        };
        let start = std::time::Instant::now();
        let report = run(&config, &RunOptions::default()).unwrap();
        eprintln!(
            "R/a = {side}: {} cycles certified in {:.1} s",
            report.certified,
            start.elapsed().as_secs_f64()
        );
        let worst = report
            .cycles
            .iter()
            .map(|c| c.cycle.radius)
            .fold(0.0, f64::max);
        eprintln!("largest certificate radius {worst:.3e}");
        let most = |f: fn(&lorentz_gas::verification::cycles::Cycle) -> f64| {
            report
                .cycles
                .iter()
                .map(|c| f(&c.cycle))
                .fold(0.0, f64::max)
        };
        eprintln!(
            "largest K {:.3e}, largest M {:.3e}, largest 2MK^2 eps {:.3e}, smallest clearance {:.3e}",
            most(|c| c.inverse_bound),
            most(|c| c.lipschitz),
            most(|c| 2.0 * c.lipschitz * c.inverse_bound * c.inverse_bound * c.residual),
            report
                .cycles
                .iter()
                .map(|c| c.cycle.min_clearance)
                .fold(f64::INFINITY, f64::min)
        );
        let known = Float::with_val(128, Float::parse(GAMMA_R6).unwrap());
        for (d, z) in report
            .spectral_determinant
            .iter()
            .zip(&report.zeta_function)
        {
            if side == "6" {
                let off = (d.escape_rate_exact.clone().unwrap() - &known).abs();
                eprintln!(
                    "N={:2} |gamma_N - known| = {:.3e}",
                    d.max_length,
                    off.to_f64()
                );
            }
            eprintln!(
                "N={:2} det: gamma={:.18} err={:.2e} lambda={:.15} (err {:.1e}) h_KS={:.15} d={:.15} (err {:.1e}) | zeta: gamma={:.15} err={:.2e}",
                d.max_length,
                d.escape_rate,
                d.escape_rate_error,
                d.lyapunov,
                d.lyapunov_error,
                d.entropy,
                d.partial_dimension,
                d.partial_dimension_error,
                z.escape_rate,
                z.escape_rate_error
            );
        }
    }
}

/// R and a are taken exactly as typed: R = 2, a = 1/3 is the repeller of R/a = 6 scaled by 1/3,
/// so its γ is 3·γ(R = 6, a = 1) at every N to the expansion's 128 bits (a = 1/3 rounded to a
/// double first would move γ by ~10⁻¹⁷ relative); bad text, NaN, a ≤ 0 and R ≤ 2a are refused
/// naming the valid range.
#[test]
fn side_and_radius_are_exact_as_typed() {
    let at = |side: &str, radius: &str| {
        let config = RepellerConfig {
            max_length: 4,
            ..RepellerConfig::new(side, radius)
        };
        run(&config, &RunOptions::default()).unwrap()
    };
    let (unit, third) = (at("6", "1"), at("2", "1/3"));
    for (u, t) in unit
        .spectral_determinant
        .iter()
        .zip(&third.spectral_determinant)
    {
        let u = u.escape_rate_exact.clone().unwrap() * 3u32;
        let t = t.escape_rate_exact.clone().unwrap();
        let rel = ((t - &u) / &u).abs().to_f64();
        assert!(rel < 1e-30, "3 gamma(6, 1) against gamma(2, 1/3): {rel:e}");
    }
    let refused = |side: &str, radius: &str| {
        RepellerConfig::new(side, radius)
            .validate()
            .unwrap_err()
            .to_string()
    };
    assert_eq!(
        refused("2", "1"),
        "side = 2 is out of range: use a finite side R > 2a = 2 (disjoint disks)"
    );
    assert_eq!(
        refused("0.2", "0.1"),
        "side = 0.2 is out of range: use a finite side R > 2a = 0.2 (disjoint disks)"
    );
    assert!(refused("6", "0").contains("use a finite radius a > 0"));
    assert!(refused("6", "-1/2").contains("use a finite radius a > 0"));
    assert!(refused("nan", "1").contains("use a finite side R > 2a"));
    assert!(refused("6", "inf").contains("use a finite radius a > 0"));
    assert!(refused("six", "1").starts_with("side = six"));
    let long = RepellerConfig {
        max_length: 17,
        ..RepellerConfig::new("6", "1")
    };
    assert!(
        long.validate()
            .unwrap_err()
            .to_string()
            .contains("use 1 to 16")
    );
}
