//! Trap hopping (paper Sec. III): Kac's lemma for injection, backscattering both ways, the
//! symmetries of the symbol statistics, collisionless flights, and the hop-level Green–Kubo D
//! against the Einstein D. Tolerances: 4 (combined) standard errors over independent batches.

use lorentz_gas::diffusion::{run, DiffusionConfig};
use lorentz_gas::hopping::{backscatter, hops};

fn z(a: f64, ea: f64, b: f64, eb: f64) -> f64 {
    (a - b).abs() / (ea * ea + eb * eb).sqrt()
}

#[test]
fn injection_obeys_kac_and_agrees_with_trajectories() {
    for &w in &[0.055, 0.2] {
        let inj = backscatter(w, 1_000_000, 16, 51, 2).unwrap();
        assert!(
            z(
                inj.mean_visit_time,
                inj.mean_visit_time_err,
                inj.mean_visit_time_exact,
                0.0
            ) < 4.0,
            "{inj:?}"
        );
        assert!(
            z(
                inj.mean_collisions_per_visit,
                inj.mean_collisions_per_visit_err,
                inj.mean_collisions_per_visit_exact,
                0.0
            ) < 4.0,
            "{inj:?}"
        );
        assert!(z(inj.p_l.value, inj.p_l.err, inj.p_r.value, inj.p_r.err) < 4.0);
        let tr = hops(w, 40_000_000, 16, 3, 52, 2).unwrap();
        assert!(
            z(inj.p_bs, inj.p_bs_err, tr.p_bs, tr.p_bs_err) < 4.0,
            "injection {} ± {} vs trajectory {} ± {}",
            inj.p_bs,
            inj.p_bs_err,
            tr.p_bs,
            tr.p_bs_err
        );
        // 2·(3 + 9 + 27) = 78 symmetry z-scores: a false alarm above 4.2 has probability < 0.3 %.
        assert!(
            tr.symmetry_max_z < 4.2,
            "symmetry violated: max z = {}",
            tr.symmetry_max_z
        );
        let total: f64 = tr.pairs.values().map(|e| e.value).sum();
        assert!((total - 1.0).abs() < 1e-12);
    }
}

#[test]
fn collisionless_visits_only_above_w0() {
    let below = hops(0.15, 4_000_000, 4, 1, 53, 2).unwrap();
    assert_eq!(below.p_cf, 0.0);
    let above = hops(0.25, 4_000_000, 4, 1, 54, 2).unwrap();
    assert!(
        above.p_cf > 10.0 * above.p_cf_err,
        "{} ± {}",
        above.p_cf,
        above.p_cf_err
    );
    let inj = backscatter(0.25, 400_000, 8, 55, 2).unwrap();
    assert!(
        z(inj.p_cf.value, inj.p_cf.err, above.p_cf, above.p_cf_err) < 4.0,
        "p_cf injection {:?} vs trajectory {}",
        inj.p_cf,
        above.p_cf
    );
}

/// D_GK = D_MZ (1 + 2 Σ_j C_j) is exact because the mean hop time is exact: a second, independent
/// estimator of D (built from trap indices only, not from positions).
#[test]
fn hop_level_green_kubo_matches_einstein() {
    for &w in &[0.05, 0.25] {
        let gk = hops(w, 60_000_000, 16, 1, 56, 2).unwrap();
        let mut cfg = DiffusionConfig::new(w);
        cfg.collisions = 60_000_000;
        cfg.batches = 16;
        cfg.seed = 57;
        let e = run(&cfg, 2, None, &|_| {}).unwrap();
        assert!(
            z(gk.D_GK, gk.D_GK_err, e.D, e.D_err) < 4.0,
            "w={w}: GK {} ± {} vs Einstein {} ± {}",
            gk.D_GK,
            gk.D_GK_err,
            e.D,
            e.D_err
        );
    }
}

/// p_bs does not depend on precision: injection at MPFR-128 (fewer visits) agrees with f64 within
/// 4 combined standard errors.
#[test]
fn backscattering_does_not_move_with_precision() {
    use lorentz_gas::diffusion::Precision;
    use lorentz_gas::hopping::backscatter_at;
    let hi = backscatter_at(0.1, 32_000, 8, 61, 2, Precision::Bits(128)).unwrap();
    let lo = backscatter_at(0.1, 1_000_000, 16, 62, 2, Precision::F64).unwrap();
    assert!(
        z(hi.p_bs, hi.p_bs_err, lo.p_bs, lo.p_bs_err) < 4.0,
        "{} ± {} vs {} ± {}",
        hi.p_bs,
        hi.p_bs_err,
        lo.p_bs,
        lo.p_bs_err
    );
    assert!(
        z(
            hi.mean_visit_time,
            hi.mean_visit_time_err,
            hi.mean_visit_time_exact,
            0.0
        ) < 4.0
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
    use lorentz_gas::geometry::Geometry;
    use lorentz_gas::stats::{normal_sigma_equivalent_t, welch_dof};
    use lorentz_gas::theory::markov::CorrelatedWalk;
    use lorentz_gas::theory::sequences::SequenceProbabilities;
    const K: usize = 16;
    for (i, &w) in [0.05, 0.15].iter().enumerate() {
        let g = Geometry::new(w).unwrap();
        let tables: Vec<Vec<f64>> = (0..K as u64)
            .map(|k| {
                let seed = 7100 + 100 * i as u64 + k; // distinct seeds, one per sub-run
                let h = hops(w, 40_000_000 / K as u64, 2, 4, seed, 2).unwrap();
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
        let se4 = ((kf - 1.0) / kf * loo.iter().map(|d| (d - mean_loo).powi(2)).sum::<f64>()).sqrt();
        let mut cfg = DiffusionConfig::new(w);
        cfg.collisions = 40_000_000;
        cfg.batches = 16;
        cfg.seed = 72;
        let e = run(&cfg, 2, None, &|_| {}).unwrap();
        let dof = welch_dof(se4, kf, e.D_err, e.batches as f64);
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
