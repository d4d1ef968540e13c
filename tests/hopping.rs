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
        let tr = hops(w, 40_000_000, 16, 3, 52, 2, &|_| {}).unwrap();
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
    let below = hops(0.15, 4_000_000, 4, 1, 53, 2, &|_| {}).unwrap();
    assert_eq!(below.p_cf, 0.0);
    let above = hops(0.25, 4_000_000, 4, 1, 54, 2, &|_| {}).unwrap();
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
        let gk = hops(w, 60_000_000, 16, 1, 56, 2, &|_| {}).unwrap();
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
    let hi = backscatter_at(0.1, 32_000, 8, 61, 2, Precision::Bits(128), &|_| {}).unwrap();
    let lo = backscatter_at(0.1, 1_000_000, 16, 62, 2, Precision::F64, &|_| {}).unwrap();
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

/// Fig. 6b, made exact: the order-4 correlated walk with the measured sequence table has a D within
/// 1 % of the Lorentz gas's (Einstein) D, computed by linear algebra on its chain.
#[test]
fn order_four_lattice_walk_reproduces_the_lorentz_gas_d() {
    use lorentz_gas::hopping::theory;
    for &w in &[0.05, 0.15] {
        let t = theory(w, 40_000_000, 8, 4, 71, 2, &|_| {}).unwrap();
        let mut cfg = DiffusionConfig::new(w);
        cfg.collisions = 40_000_000;
        cfg.batches = 16;
        cfg.seed = 72;
        let e = run(&cfg, 2, None, &|_| {}).unwrap();
        let d4 = t.lattice_gas_exact[3].1;
        assert!(
            (d4 - e.D).abs() < 0.01 * e.D,
            "w={w}: order-4 walk {d4} vs Einstein {} ± {}",
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
    use lorentz_gas::hopping::{lattice_walks, min_collisions_per_batch, theory};
    use lorentz_gas::symbols::MAX_ORDER;
    use std::sync::atomic::{AtomicU64, Ordering};
    let work = AtomicU64::new(0);
    let p = |n: u64| {
        work.fetch_add(n, Ordering::Relaxed);
    };
    let range = format!("1 <= order <= {MAX_ORDER}");
    for order in [0, MAX_ORDER + 1, 100] {
        let e = theory(0.1, 1_000_000_000, 8, order, 1, 2, &p).unwrap_err();
        assert!(e.to_string().contains(&range), "{e}");
        let e = hops(0.1, 1_000_000_000, 8, order, 1, 2, &p).unwrap_err();
        assert!(e.to_string().contains(&range), "{e}");
        let e = lattice_walks(0.1, 1_000_000_000, 8, order, 1, 2, &p).unwrap_err();
        assert!(e.to_string().contains(&range), "{e}");
    }
    let min = min_collisions_per_batch(0.1).unwrap();
    let e = hops(0.1, 4 * min - 4, 4, 2, 1, 2, &p).unwrap_err();
    assert!(
        e.to_string()
            .contains(&format!("{min} collisions per batch")),
        "{e}"
    );
    assert!(hops(0.1, 1_000_000_000, 1, 2, 1, 2, &p).is_err());
    assert!(hops(0.4, 1_000_000_000, 8, 2, 1, 2, &p).is_err());
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
    let mut r = hops(0.2, 3_000_001, 3, 2, 5, 2, &p).unwrap();
    assert_eq!(done.load(Ordering::Relaxed), r.collisions);
    assert_eq!(r.collisions, 3 * 1_000_001);
    assert!(r.table(2).is_ok());
    let v = r.sequences[1].remove("zl").unwrap();
    r.sequences[1].insert("zx".into(), v);
    let e = r.table(2).unwrap_err().to_string();
    assert!(e.contains("'x'") && e.contains("z, l, r"), "{e}");
    let done = AtomicU64::new(0);
    let p = |n: u64| {
        done.fetch_add(n, Ordering::Relaxed);
    };
    let b = backscatter_at_f64(0.1, 200_003, 4, 6, &p);
    assert_eq!(done.load(Ordering::Relaxed), b.visits);
}

fn backscatter_at_f64(
    w: f64,
    visits: u64,
    batches: u32,
    seed: u64,
    progress: &(dyn Fn(u64) + Sync),
) -> lorentz_gas::hopping::BackscatterReport {
    use lorentz_gas::diffusion::Precision;
    lorentz_gas::hopping::backscatter_at(w, visits, batches, seed, 2, Precision::F64, progress)
        .unwrap()
}

/// Fig. 6b by simulation from the library: each order-k walk driven by the measured table is
/// simulated within 4σ of its exact D, and the exact order-4 D is within 4σ of the gas's hop-level D.
#[test]
fn lattice_walks_agree_with_their_exact_d() {
    use lorentz_gas::hopping::lattice_walks;
    let r = lattice_walks(0.1, 20_000_000, 8, 4, 81, 2, &|_| {}).unwrap();
    assert_eq!(r.walks.len(), 4);
    for row in &r.walks {
        assert!(
            z(row.D_simulated, row.D_simulated_err, row.D_exact, 0.0) < 4.0,
            "{row:?}"
        );
    }
    // The fit window of the simulated walks is long enough: for the same measured tables (same
    // seed), the exact fit bias is below a tenth of the statistical error.
    use lorentz_gas::hopping::{WALK_BATCHES, WALK_HOPS, WALK_WALKERS};
    use lorentz_gas::theory::lattice_walk::{fit_bias, LatticeWalkConfig};
    use lorentz_gas::theory::markov::CorrelatedWalk;
    let h = hops(0.1, 20_000_000, 8, 4, 81, 2, &|_| {}).unwrap();
    let cfg = LatticeWalkConfig::new(WALK_BATCHES, WALK_WALKERS, WALK_HOPS, 81);
    for row in &r.walks {
        let walk = CorrelatedWalk::new(&h.table(row.order).unwrap()).unwrap();
        assert_eq!(
            walk.d(&lorentz_gas::geometry::Geometry::new(0.1).unwrap())
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
    let d4 = r.walks[3].D_exact;
    assert!(
        z(d4, 0.0, r.D_GK, r.D_GK_err) < 4.0,
        "{d4} vs {} ± {}",
        r.D_GK,
        r.D_GK_err
    );
}
