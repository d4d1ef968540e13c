//! The escape rate of an open table by survival (`estimators::escape::survival`): the
//! three-disk repeller's γ, λ and h_KS at R/a = 6 against its certified cycle expansion
//! (`lorentz cycles`, N = 12: truncation below 10⁻¹⁹), within the Student-t quantile of the
//! 32 batches at the normal's 3σ tail probability; and the same bits on 1 and 2 threads.

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::escape::survival::{self, BATCHES, SurvivalConfig, SurvivalReport};
use lorentz_gas::scenes::open::OpenSpec;
use lorentz_gas::statistics::normal_sigma_equivalent_t;

/// The cycle expansion's values at R/a = 6 (docs/guide/cycles.md).
const GAMMA: f64 = 0.410338407769346;
const LYAPUNOV: f64 = 0.577552578771879;
const H_KS: f64 = 0.167214171002532;

fn run(particles: u64, threads: usize) -> SurvivalReport {
    let cfg = SurvivalConfig {
        particles,
        ..SurvivalConfig::new(OpenSpec::repeller("6", "1").unwrap())
    };
    let opts = RunOptions {
        threads,
        ..RunOptions::default()
    };
    survival::run(&cfg, &opts).unwrap()
}

/// γ, λ and h_KS from 2·10⁷ particles (σ_γ ≈ 7·10⁻⁴, the window's transient ≈ 3·10⁻⁵) agree with
/// the cycles within t·SE; the window one collision later agrees with the first.
#[test]
fn the_repeller_escapes_at_its_cycle_rate() {
    let r = run(20_000_000, 2);
    let t = normal_sigma_equivalent_t(f64::from(BATCHES - 1), 3.0);
    for (what, x, err, exact) in [
        ("gamma", r.gamma, r.gamma_err, GAMMA),
        ("lambda", r.lyapunov, r.lyapunov_err, LYAPUNOV),
        ("h_KS", r.entropy, r.entropy_err, H_KS),
    ] {
        assert!(
            (x - exact).abs() <= t * err,
            "{what} = {x} ± {err}, cycles {exact}: {:.2} SE, bound {t:.2}",
            (x - exact) / err
        );
    }
    assert!(
        r.window_check_sigma.abs() <= 3.0,
        "{}",
        r.window_check_sigma
    );
}

/// Same seed, same bits on 1 and 2 threads: every batch is a fixed set of particles with its
/// own stream, summed in index order.
#[test]
fn the_same_seed_gives_the_same_bits_on_any_thread_count() {
    let (one, two) = (run(1_000_000, 1), run(1_000_000, 2));
    assert_eq!(one.gamma.to_bits(), two.gamma.to_bits());
    assert_eq!(one.lyapunov.to_bits(), two.lyapunov.to_bits());
    assert_eq!(one.gamma_err.to_bits(), two.gamma_err.to_bits());
    assert_eq!(one.survival, two.survival);
    assert_eq!(one.collisions, two.collisions);
    let bits = |r: &SurvivalReport| serde_json::to_value(&r.windows).unwrap();
    assert_eq!(bits(&one), bits(&two));
}
