//! Trap hopping (paper Sec. III): Kac's lemma for injection, backscattering both ways, the
//! symmetries of the symbol statistics, collisionless flights, and the hop-level Green–Kubo D
//! against the Einstein D. Tolerances: "4σ" over independent batches. A z-score whose standard
//! error comes from the spread of n batch means is Student-t with n − 1 dof (Welch–Satterthwaite
//! dof for the difference of two such estimates), so "4σ" is the Student-t quantile at the
//! normal's two-sided 4σ tail probability 6.3·10⁻⁵ (`statistics::normal_sigma_equivalent_t`; 15 dof:
//! 5.48, 30 dof: 4.65).

use crate::common::{t4, t4_welch, z};
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::diffusion::run;
use lorentz_gas::estimators::hops::backscatter::{self, BackscatterConfig, BackscatterReport};
use lorentz_gas::estimators::hops::{self, HopsConfig};
use lorentz_gas::numbers::precision::Precision;
use lorentz_gas::scenes::spec::Table;
use lorentz_gas::statistics::{normal_sigma_equivalent_t, student_t_quantile, welch_dof};

/// A hop measurement of `collisions` in `batches` up to `order`, seed `seed`, run 0.
fn hop_cfg(w: f64, collisions: u64, batches: u32, order: usize, seed: u64) -> HopsConfig {
    HopsConfig {
        table: Table::triangular_at(w),
        collisions,
        batches,
        order,
        seed,
        run: 0,
    }
}

/// Injection of `visits` in `batches`, seed `seed`, at `precision`.
fn inject_cfg(
    w: f64,
    visits: u64,
    batches: u32,
    seed: u64,
    precision: Precision,
) -> BackscatterConfig {
    BackscatterConfig {
        particles: visits,
        batches,
        seed,
        precision,
        ..BackscatterConfig::new(Table::triangular_at(w))
    }
}

/// The injection report of `inject_cfg(w, visits, batches, seed, precision)` on two quiet threads.
fn inject(w: f64, visits: u64, batches: u32, seed: u64, precision: Precision) -> BackscatterReport {
    backscatter::run(
        &inject_cfg(w, visits, batches, seed, precision),
        &two_threads(&quiet),
    )
    .unwrap()
}

/// Two threads, reporting progress to `progress`.
fn two_threads(progress: &(dyn Fn(u64) + Sync)) -> RunOptions<'_> {
    RunOptions {
        threads: 2,
        progress,
        ..RunOptions::default()
    }
}

fn quiet(_: u64) {}

/// Batches of a result, from its metadata block.
fn nb(m: &lorentz_gas::engine::metadata::RunMeta) -> u32 {
    m.batches.expect("batches in the metadata") as u32
}

/// Asserts that two independent batch estimates `(value, error, batches)` agree within the
/// Welch "4σ" bound of their difference.
fn assert_agree(what: &str, a: (f64, f64, u32), b: (f64, f64, u32)) {
    let k = t4_welch(a.1, a.2, b.1, b.2);
    assert!(
        z(a.0, a.1, b.0, b.1) < k,
        "{what}: {} ± {} vs {} ± {} (bound {k:.2})",
        a.0,
        a.1,
        b.0,
        b.1
    );
}

/// Asserts that a batch estimate `value ± error` over `batches` is within "4σ" of `exact`.
fn assert_exact(value: f64, error: f64, exact: f64, batches: u32, what: &dyn std::fmt::Debug) {
    assert!(z(value, error, exact, 0.0) < t4(batches), "{what:?}");
}

#[test]
fn injection_obeys_kac_and_agrees_with_trajectories() {
    for &w in &[0.055, 0.2] {
        let inj = inject(w, 1_000_000, 16, 51, Precision::F64);
        assert_exact(
            inj.mean_visit_time,
            inj.mean_visit_time_err,
            inj.mean_visit_time_exact,
            nb(&inj.meta),
            &inj,
        );
        assert_exact(
            inj.mean_collisions_per_visit,
            inj.mean_collisions_per_visit_err,
            inj.mean_collisions_per_visit_exact,
            nb(&inj.meta),
            &inj,
        );
        // p_l = p_r. The two come from the same visits, whose exits are independent multinomial
        // draws, so the difference has the exact variance (p_l + p_r − (p_l − p_r)²)/N — larger
        // than σ_l² + σ_r² (the covariance −p_l·p_r/N is negative). N = 10⁶: normal, 4σ — not
        // Student-t, as the variance is the multinomial's, not estimated from a few batches.
        let (pl, pr) = (inj.p_l, inj.p_r);
        let sd = ((pl + pr - (pl - pr).powi(2)) / inj.particles as f64).sqrt();
        assert!(
            (pl - pr).abs() < 4.0 * sd,
            "p_l {pl} vs p_r {pr}: {:.2}σ",
            (pl - pr) / sd
        );
        let tr = hops::run(&hop_cfg(w, 40_000_000, 16, 3, 52), &two_threads(&quiet)).unwrap();
        assert_agree(
            "p_bs injection vs trajectory",
            (inj.p_bs, inj.p_bs_err, nb(&inj.meta)),
            (tr.p_bs, tr.p_bs_err, nb(&tr.meta)),
        );
        // 2·(3 + 9 + 27) = 78 symmetry z-scores, each Student-t with 15 dof: the bound is the
        // t₁₅ quantile at two-sided probability 0.003/78 (Bonferroni), so that a false alarm
        // anywhere has probability < 0.3 %.
        let k = student_t_quantile(nb(&tr.meta) as f64 - 1.0, 0.003 / (2.0 * 78.0));
        assert!(
            tr.symmetry_max_z < k,
            "symmetry violated: max z = {} (bound {k:.2})",
            tr.symmetry_max_z
        );
        let total: f64 = tr.pairs.values().sum();
        assert!((total - 1.0).abs() < 1e-12);
    }
}

#[test]
fn collisionless_visits_only_above_w0() {
    let below = hops::run(&hop_cfg(0.15, 4_000_000, 4, 1, 53), &two_threads(&quiet)).unwrap();
    assert_eq!(below.p_cf, 0.0);
    let above = hops::run(&hop_cfg(0.25, 4_000_000, 16, 1, 54), &two_threads(&quiet)).unwrap();
    assert!(
        above.p_cf > 10.0 * above.p_cf_err,
        "{} ± {}",
        above.p_cf,
        above.p_cf_err
    );
    let inj = inject(0.25, 400_000, 16, 55, Precision::F64);
    assert_agree(
        "p_cf injection vs trajectory",
        (inj.p_cf, inj.p_cf_err, nb(&inj.meta)),
        (above.p_cf, above.p_cf_err, nb(&above.meta)),
    );
}

/// D_GK = D_MZ (1 + 2 Σ_j C_j) is exact because the mean hop time is exact: a second, independent
/// estimator of D (built from trap indices only, not from positions).
#[test]
fn hop_level_green_kubo_matches_einstein() {
    for &w in &[0.05, 0.25] {
        let gk = hops::run(&hop_cfg(w, 60_000_000, 16, 1, 56), &two_threads(&quiet)).unwrap();
        let cfg = crate::common::diffusion_config(w, 60_000_000, 16, 57);
        let e = run(&cfg, &crate::common::threads(2)).unwrap();
        assert_agree(
            &format!("w={w}: GK vs Einstein"),
            (gk.D_GK, gk.D_GK_err, nb(&gk.meta)),
            (e.D, e.D_err, nb(&e.meta)),
        );
    }
}

/// p_bs does not depend on precision: injection at MPFR-128 (fewer visits) agrees with f64 within
/// 4 combined standard errors.
#[test]
fn backscattering_does_not_move_with_precision() {
    let hi = inject(0.1, 32_000, 16, 61, Precision::Bits(128));
    let lo = inject(0.1, 1_000_000, 16, 62, Precision::F64);
    assert_agree(
        "p_bs MPFR-128 vs f64",
        (hi.p_bs, hi.p_bs_err, nb(&hi.meta)),
        (lo.p_bs, lo.p_bs_err, nb(&lo.meta)),
    );
    assert_exact(
        hi.mean_visit_time,
        hi.mean_visit_time_err,
        hi.mean_visit_time_exact,
        nb(&hi.meta),
        &hi,
    );
}

/// Fig. 6b, made exact: the order-4 correlated walk with the measured sequence table has the D
/// of the Lorentz gas (Einstein) within 4σ-equivalent of the combined standard error.
///
/// d₄ = D(order-4 walk of the table) is a nonlinear function of the measured table, so its
/// standard error comes from the jackknife over K = 16 independent sub-runs (each a `hops` run
/// of two trajectories with its own seed; the table is their mean, as in `theory`):
/// SE² = (K − 1)/K·Σₖ(d₋ₖ − d̄)², d₋ₖ from the table without sub-run k (Student-t, K − 1 dof).
/// The Einstein D has the standard error of its 16 batches; the two are independent, so
/// z = (d₄ − D)/√(SE_J² + SE_E²) is compared with the Student-t quantile at the Welch–Satterthwaite
/// dof. Memory beyond four hops, a wrong table or a wrong resolvent shows up as a larger z.
#[test]
fn order_four_lattice_walk_reproduces_the_lorentz_gas_d() {
    use lorentz_gas::scenes::triangular::geometry::Geometry;
    use lorentz_gas::theory::markov::CorrelatedWalk;
    use lorentz_gas::theory::sequences::SequenceProbabilities;
    const K: usize = 16;
    for (i, &w) in [0.05, 0.15].iter().enumerate() {
        let g = Geometry::new(w).unwrap();
        let tables: Vec<Vec<f64>> = (0..K as u64)
            .map(|k| {
                // Sub-run k of gap i: run i·K + k of seed 71 (distinct streams, no seed arithmetic).
                let run = (i * K) as u64 + k;
                let cfg = HopsConfig {
                    run,
                    ..hop_cfg(w, 40_000_000 / K as u64, 2, 4, 71)
                };
                let h = hops::run(&cfg, &two_threads(&quiet)).unwrap();
                h.table(4).unwrap().probabilities().to_vec()
            })
            .collect();
        let d4_of = |skip: Option<usize>| -> f64 {
            let mut p = vec![0.0; tables[0].len()];
            for (k, t) in tables.iter().enumerate() {
                if Some(k) != skip {
                    p.iter_mut().zip(t).for_each(|(a, b)| *a += b);
                }
            }
            let t = SequenceProbabilities::from_weights(4, p).unwrap();
            CorrelatedWalk::new(&t).unwrap().d(&g).unwrap()
        };
        let d4 = d4_of(None);
        let loo: Vec<f64> = (0..K).map(|k| d4_of(Some(k))).collect();
        let mean_loo = loo.iter().sum::<f64>() / K as f64;
        let kf = K as f64;
        let se4 =
            ((kf - 1.0) / kf * loo.iter().map(|d| (d - mean_loo).powi(2)).sum::<f64>()).sqrt();
        let cfg = crate::common::diffusion_config(w, 40_000_000, 16, 72);
        let e = run(&cfg, &crate::common::threads(2)).unwrap();
        let dof = welch_dof(se4, kf, e.D_err, nb(&e.meta) as f64);
        let t_max = normal_sigma_equivalent_t(dof, 4.0);
        let zz = z(d4, se4, e.D, e.D_err);
        eprintln!(
            "w={w}: order-4 walk {d4:.6} ± {se4:.6} vs Einstein {:.6} ± {:.6}: |z| = {zz:.2} \
             (4σ-equivalent at {dof:.1} dof: {t_max:.2})",
            e.D, e.D_err
        );
        assert!(
            zz < t_max,
            "w={w}: order-4 walk {d4} ± {se4} vs Einstein {} ± {}: |z| = {zz:.2} > {t_max:.2}",
            e.D,
            e.D_err
        );
    }
}

/// Bad input is refused before any work, with the valid range in the message: `order` 0 or
/// above the one limit `symbols::MAX_ORDER` (theory, hops, lattice walks), too few collisions
/// per batch for the Green–Kubo window.
#[test]
fn bad_orders_and_counts_are_refused_up_front() {
    use lorentz_gas::estimators::hops::{lattice_walks, min_collisions_per_batch, theory};
    use lorentz_gas::scenes::symbols::MAX_ORDER;
    use std::sync::atomic::{AtomicU64, Ordering};
    let work = AtomicU64::new(0);
    let p = |n: u64| {
        work.fetch_add(n, Ordering::Relaxed);
    };
    let range = format!("is out of range: use 1 to {MAX_ORDER} (");
    for order in [0, MAX_ORDER + 1, 100] {
        let e =
            theory::run(&hop_cfg(0.1, 1_000_000_000, 8, order, 1), &two_threads(&p)).unwrap_err();
        assert!(e.to_string().contains(&range), "{e}");
        let e = hops::run(&hop_cfg(0.1, 1_000_000_000, 8, order, 1), &two_threads(&p)).unwrap_err();
        assert!(e.to_string().contains(&range), "{e}");
        let e = lattice_walks::run(&hop_cfg(0.1, 1_000_000_000, 8, order, 1), &two_threads(&p))
            .unwrap_err();
        assert!(e.to_string().contains(&range), "{e}");
    }
    let min = min_collisions_per_batch(0.1).unwrap();
    let e = hops::run(&hop_cfg(0.1, 4 * min - 4, 4, 2, 1), &two_threads(&p)).unwrap_err();
    assert!(
        e.to_string()
            .contains(&format!("{min} collisions per batch")),
        "{e}"
    );
    assert!(hops::run(&hop_cfg(0.1, 1_000_000_000, 1, 2, 1), &two_threads(&p)).is_err());
    assert!(hops::run(&hop_cfg(0.4, 1_000_000_000, 8, 2, 1), &two_threads(&p)).is_err());
    assert_eq!(work.load(Ordering::Relaxed), 0, "no work before validation");
}

/// Progress increments add up to the work reported, and a sequence name that is not a word
/// over z, l, r is an error in `HopsReport::table` (never read as z).
#[test]
fn progress_adds_up_and_tables_reject_unknown_symbols() {
    use std::sync::atomic::{AtomicU64, Ordering};
    let done = AtomicU64::new(0);
    let p = |n: u64| {
        done.fetch_add(n, Ordering::Relaxed);
    };
    let mut r = hops::run(&hop_cfg(0.2, 3_000_001, 3, 2, 5), &two_threads(&p)).unwrap();
    assert_eq!(done.load(Ordering::Relaxed), r.collisions);
    assert_eq!(r.collisions, 3_000_001, "exactly the collisions asked for");
    assert!(r.table(2).is_ok());
    let v = r.sequences.remove("zl").unwrap();
    r.sequences.insert("zx".into(), v);
    let e = r.table(2).unwrap_err().to_string();
    assert!(e.contains("'x'") && e.contains("z, l, r"), "{e}");
    let done = AtomicU64::new(0);
    let p = |n: u64| {
        done.fetch_add(n, Ordering::Relaxed);
    };
    let b = backscatter_at_f64(0.1, 200_003, 4, 6, &p);
    assert_eq!(done.load(Ordering::Relaxed), b.particles);
}

fn backscatter_at_f64(
    w: f64,
    visits: u64,
    batches: u32,
    seed: u64,
    progress: &(dyn Fn(u64) + Sync),
) -> BackscatterReport {
    let cfg = inject_cfg(w, visits, batches, seed, Precision::F64);
    backscatter::run(&cfg, &two_threads(progress)).unwrap()
}

/// Fig. 6b by simulation from the library: each order-k walk driven by the measured table is
/// simulated within 4σ of its exact D, and the exact order-4 D is within 4σ of the gas's hop-level D.
#[test]
fn lattice_walks_agree_with_their_exact_d() {
    use lorentz_gas::estimators::hops::lattice_walks;
    let r = lattice_walks::run(&hop_cfg(0.1, 20_000_000, 8, 4, 81), &two_threads(&quiet)).unwrap();
    assert_eq!(r.walks.len(), 4);
    for row in &r.walks {
        // D_simulated_err is the spread of WALK_BATCHES batch means: Student-t.
        assert!(
            z(row.D_simulated, row.D_simulated_err, row.D_exact, 0.0)
                < t4(lattice_walks::WALK_BATCHES as u32),
            "{row:?}"
        );
    }
    // The fit window of the simulated walks is long enough: for the same measured tables (same
    // seed), the exact fit bias is below a tenth of the statistical error.
    use lorentz_gas::estimators::hops::lattice_walks::{WALK_BATCHES, WALK_HOPS, WALK_WALKERS};
    use lorentz_gas::theory::lattice_walk::{LatticeWalkConfig, fit_bias};
    use lorentz_gas::theory::markov::CorrelatedWalk;
    let h = hops::run(&hop_cfg(0.1, 20_000_000, 8, 4, 81), &two_threads(&quiet)).unwrap();
    let cfg = LatticeWalkConfig::new(WALK_BATCHES, WALK_WALKERS, WALK_HOPS, 81);
    for row in &r.walks {
        let walk = CorrelatedWalk::new(&h.table(row.order).unwrap()).unwrap();
        assert_eq!(
            walk.d(&lorentz_gas::scenes::triangular::geometry::Geometry::new(0.1).unwrap())
                .unwrap(),
            row.D_exact
        );
        let bias = fit_bias(&walk, &cfg).unwrap() * r.D_MZ;
        assert!(
            bias.abs() < 0.1 * row.D_simulated_err,
            "order {}: fit bias {bias}",
            row.order
        );
    }
    // D_GK_err is the spread of the hops run's 8 batches: Student-t with 7 dof. The exact D of
    // the walk driven by the measured table has a statistical error of its own (from the same
    // table), which this neglects: the bound is, if anything, too strict.
    let d4 = r.walks[3].D_exact;
    assert!(
        z(d4, 0.0, r.D_GK, r.D_GK_err) < t4(nb(&h.meta)),
        "{d4} vs {} ± {}",
        r.D_GK,
        r.D_GK_err
    );
}
