//! `lorentz free-paths`: the free path between collisions against the Boltzmann–Grad limit law
//! (`proofs-notes/free-path-law.md`).

use lorentz_gas::engine::long_flight::Flights;
use lorentz_gas::estimators::free_paths::{self, FreePathConfig, FreePathReport};
use lorentz_gas::scenes::spec::SceneSpec;
use lorentz_gas::statistics::normal_sigma_equivalent_t;

fn measure(scene: SceneSpec, collisions: u64, threads: usize) -> FreePathReport {
    let cfg = FreePathConfig {
        collisions,
        batches: 16,
        seed: 5,
        ..FreePathConfig::new(scene)
    };
    free_paths::run(&cfg, &crate::common::threads(threads)).unwrap()
}

fn square(r: &str) -> SceneSpec {
    SceneSpec::Square { radius: r.into() }
}

/// At r = 10⁻⁴ (jumps; 1.6·10⁶ collisions, about a second) every bin of ξ = τ/⟨ℓ⟩ is the limit
/// law's within the Bonferroni bound over the 14 bins, ⟨ξ⟩ is 1 within 4σ (Student-t), and
/// ⟨ln ξ⟩ is 27ζ(3)/(2π²) − 3 ln 2 within 4σ plus r ln²r (the size of the finite-radius
/// correction of the Lyapunov exponent it belongs to). Broken on purpose (ξ measured in units
/// of 1.02⟨ℓ⟩): ⟨ξ⟩ is 17.8σ off and the largest bin's |z| is 25.8 against a bound of 7.0.
#[test]
fn the_free_paths_of_small_disks_follow_the_limit_law() {
    let r = 1e-4f64;
    let f = measure(square("1/10000"), 1_600_000, 2);
    print!("{}", lorentz_gas::report::text::free_paths::free_paths(&f));
    assert_eq!(f.flights, Flights::Jump);
    assert_eq!(f.samples, 1_600_000 - 16);
    assert!(f.mean_check.agrees(), "{:?}", f.mean_check);
    assert!(
        f.max_z <= f.max_z_bound,
        "largest |z| {} > {}",
        f.max_z,
        f.max_z_bound
    );
    let slack = normal_sigma_equivalent_t(15.0, 4.0) * f.ln_mean_err + r * r.ln().powi(2);
    assert!(
        (f.ln_mean - f.ln_mean_limit).abs() < slack,
        "<ln xi> {} ± {} against {}",
        f.ln_mean,
        f.ln_mean_err,
        f.ln_mean_limit
    );
}

/// At r = 1/10 the law is far from its limit (the largest |z| is over ten times its bound),
/// while ⟨ξ⟩ = 1 still holds: Santaló's formula is exact at every radius, and on the
/// triangular lattice too.
#[test]
fn at_a_large_radius_only_the_mean_is_exact() {
    let f = measure(square("1/10"), 800_000, 2);
    assert!(f.mean_check.agrees(), "{:?}", f.mean_check);
    assert!(f.max_z > 10.0 * f.max_z_bound, "{}", f.max_z);
    let t = measure(SceneSpec::Triangular { w: "0.1".into() }, 160_000, 2);
    assert_eq!(t.flights, Flights::Walk);
    assert!(t.mean_check.agrees(), "{:?}", t.mean_check);
}

/// Same seed, same bits, whatever the number of threads.
#[test]
fn free_paths_have_the_same_bits_on_any_number_of_threads() {
    let a = measure(square("1/1000"), 32_000, 1);
    let b = measure(square("1/1000"), 32_000, 2);
    assert_eq!(a.bins, b.bins);
    assert_eq!(
        (a.mean, a.ln_mean, a.longest),
        (b.mean, b.ln_mean, b.longest)
    );
}
