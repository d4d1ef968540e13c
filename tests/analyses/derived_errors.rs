//! The errors of numbers derived from measured tables (jackknife over batches) and the symmetry
//! bound are honest: over independent runs, the spread of each derived value matches the error
//! each run reports.

use lorentz_gas::estimators::hops::{self, HopsConfig, theory};
use lorentz_gas::scenes::spec::Table;

/// Runs of the theory from disjoint streams of one seed.
const RUNS: u64 = 24;
/// Batches per run: the jackknife error has 7 dof.
const BATCHES: u32 = 8;

/// For D_1, D_2, D_3 (the hierarchy), the exact order-2 and order-3 walks and D_2 − D_GK: the
/// variance of the 24 run values against the mean of their squared jackknife errors is, if the
/// errors are right, F(23, 24·7)-distributed (the jackknife variance of a smooth function of
/// batch means has about n − 1 dof, like a batch-means variance). Each ratio must lie within the
/// central 1 − p of that F, p the normal 4σ two-sided tail over the 6 quantities (Bonferroni):
/// errors too small by a factor 2 or too large by 2 fail. (Breaking it on purpose: jackknife_se
/// without its (n − 1)/n·n factor, i.e. the plain standard deviation of the leave-one-out values
/// divided by √n, makes the errors 7 times too small: the ratios came out 33 to 43 and the test
/// failed at once.)
#[test]
fn jackknife_errors_of_the_hierarchy_match_the_spread_of_independent_runs() {
    let reports: Vec<theory::TheoryReport> = (0..RUNS)
        .map(|run| {
            let cfg = HopsConfig {
                collisions: 2_000_000,
                batches: BATCHES,
                order: 3,
                seed: 11,
                run,
                ..HopsConfig::new(Table::triangular_at(0.15))
            };
            theory::run(&cfg, &crate::common::threads(2)).unwrap()
        })
        .collect();
    type Pick = fn(&theory::TheoryReport) -> (f64, f64);
    let quantities: [(&str, Pick); 6] = [
        ("D_1", |r| (r.D_1, r.D_1_err)),
        ("D_2", |r| (r.orders[1].D_k, r.orders[1].D_k_err)),
        ("D_3", |r| (r.orders[2].D_k, r.orders[2].D_k_err)),
        ("walk 2", |r| {
            (r.orders[1].D_lattice_walk, r.orders[1].D_lattice_walk_err)
        }),
        ("walk 3", |r| {
            (r.orders[2].D_lattice_walk, r.orders[2].D_lattice_walk_err)
        }),
        ("D_2 - D_GK", |r| {
            let o = &r.orders[1];
            (o.D_k_combined_minus_D_GK, o.D_k_combined_minus_D_GK_err)
        }),
    ];
    let error_dof = (RUNS * (BATCHES as u64 - 1)) as f64;
    crate::common::assert_errors_match_their_spread(&reports, &quantities, error_dof);
}

/// The symmetry bound is what its documentation says: the largest |z| over the reported number
/// of comparisons, at the 4σ tail over that number, and a correct run stays below it.
#[test]
fn symmetry_bound_is_the_bonferroni_t_over_the_comparisons_and_holds() {
    let cfg = HopsConfig {
        collisions: 20_000_000,
        batches: 16,
        order: 3,
        seed: 5,
        ..HopsConfig::new(Table::triangular_at(0.2))
    };
    let r = hops::run(&cfg, &crate::common::threads(2)).unwrap();
    // Order 3: 3 + 9 + 27 sequences; mirror and reversed-mirror partners give at most 39 pairs,
    // fewer where a sequence is its own partner.
    assert!(
        r.symmetry_comparisons > 10 && r.symmetry_comparisons <= 39,
        "{}",
        r.symmetry_comparisons
    );
    let want = lorentz_gas::statistics::comparison::largest_of_bound(15.0, r.symmetry_comparisons);
    assert_eq!(r.symmetry_bound, want);
    assert!(r.symmetry_bound > lorentz_gas::statistics::comparison::agreement_bound(15.0));
    assert!(
        r.symmetry_max_z <= r.symmetry_bound,
        "max |z| {} above {}",
        r.symmetry_max_z,
        r.symmetry_bound
    );
}
