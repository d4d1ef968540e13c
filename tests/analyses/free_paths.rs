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

/// The Wilson–Hilferty approximation of the chi-square quantile of `dof` degrees of freedom at
/// the standard normal quantile `z` (relative error below 1 % for dof ≥ 3 in the upper tail).
fn chi2_quantile(dof: f64, z: f64) -> f64 {
    let a = 2.0 / (9.0 * dof);
    dof * (1.0 - a + z * a.sqrt()).powi(3)
}

/// The done-when of the user's bins: at r = 10⁻⁴ (jumps, 1.6·10⁶ collisions) 20 000 free-path
/// samples kept (every 80th flight of each batch, so nearly independent) histogram to the
/// Boltzmann–Grad limit law in the user's 16 bins (and the rest, ξ ≥ 6): Pearson's chi-square
/// over the 17 cells is below its 1 − 10⁻⁴ quantile for 16 degrees of freedom (z = 3.719,
/// Wilson–Hilferty: 46.2). The report's own bins are the user's, each within the Bonferroni
/// bound. Broken on purpose (samples in units of 1.05⟨ℓ⟩, i.e. each ξ divided by 1.05), the
/// chi-square is 149 (against 15.2 unbroken) and the test fails.
#[test]
fn free_path_samples_follow_the_limit_law_in_the_users_bins() {
    let edges: Vec<f64> = (0..=12)
        .map(|k| 0.25 * k as f64)
        .chain([3.5, 4.0, 5.0, 6.0])
        .collect();
    let cfg = FreePathConfig {
        collisions: 1_600_000,
        batches: 16,
        seed: 5,
        bins: Some(edges.clone()),
        keep_samples: 20_000,
        ..FreePathConfig::new(square("1/10000"))
    };
    let f = free_paths::run(&cfg, &crate::common::threads(2)).unwrap();
    assert_eq!(f.bins.len(), edges.len() - 1);
    assert_eq!((f.bins[0].lo, f.bins[15].hi), (0.0, Some(6.0)));
    assert!(f.max_z <= f.max_z_bound, "{} > {}", f.max_z, f.max_z_bound);
    let xi = &f.free_path_samples;
    assert_eq!(xi.len(), 20_000);
    let n = xi.len() as f64;
    let mut chi2 = 0.0;
    for k in 0..=edges.len() - 1 {
        let (lo, hi) = (edges[k], edges.get(k + 1).copied().unwrap_or(f64::INFINITY));
        let seen = xi.iter().filter(|&&x| lo <= x && x < hi).count() as f64;
        let expected = n * lorentz_gas::theory::free_paths::probability(lo, hi);
        assert!(expected >= 20.0, "bin [{lo}, {hi}) expects {expected}");
        chi2 += (seen - expected).powi(2) / expected;
    }
    let bound = chi2_quantile((edges.len() - 1) as f64, 3.719);
    println!(
        "chi-square {chi2:.1} over {} cells, bound {bound:.1}",
        edges.len()
    );
    assert!(
        chi2 < bound,
        "chi-square {chi2} over {} cells > {bound}",
        edges.len()
    );
}

/// Bad bins and too many samples are refused, naming the valid range.
#[test]
fn bad_bins_and_too_many_samples_are_refused() {
    for bins in [
        vec![0.0],
        vec![1.0, 0.5],
        vec![-1.0, 1.0],
        vec![0.0, f64::INFINITY],
    ] {
        let cfg = FreePathConfig {
            bins: Some(bins.clone()),
            ..FreePathConfig::new(square("1/10"))
        };
        let e = cfg.validate().unwrap_err().to_string();
        assert!(
            e.contains("bins") && e.contains("2 to 1001"),
            "{bins:?}: {e}"
        );
    }
    let cfg = FreePathConfig {
        keep_samples: 2_000_000,
        ..FreePathConfig::new(square("1/10"))
    };
    let e = cfg.validate().unwrap_err().to_string();
    assert!(
        e.contains("keep_samples") && e.contains("0 to 1000000"),
        "{e}"
    );
}
