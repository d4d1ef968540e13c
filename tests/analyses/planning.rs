//! Precision planning (`estimators::diffusion::plan`): a run planned for a relative error is the
//! plain run of the size its pilot plans, bit for bit, and reaches the target within the
//! statistics of the pilot's own error estimate.

use lorentz_gas::estimators::diffusion::{self, DiffusionConfig, plan};
use lorentz_gas::statistics::f_p_value;

/// The pilot (1.28·10⁷ collisions at w = 0.2 in 128 batches) planned down to a quarter of its
/// relative error: about 16 times its size. The result is bit for bit the plain run of the
/// planned size, and (relative error reached / target)² is an F ratio of two 127-dof variance
/// estimates — conservatively, since the planned trajectories continue the pilot's — so its
/// two-sided p-value must exceed 10⁻³. It reaches 1.011·10⁻³ for 1.030·10⁻³ (F = 0.96,
/// p = 0.83). Breaking it on purpose — planning N·r/ρ instead of N·(r/ρ)², with the size check
/// below removed — reaches 2.15·10⁻³ (F = 4.36, p = 2·10⁻¹⁵) and fails.
#[test]
fn a_planned_run_is_the_plain_run_of_its_size_and_reaches_its_target() {
    let pilot_size = 12_800_000;
    let base = DiffusionConfig {
        collisions: pilot_size,
        batches: 128,
        ..DiffusionConfig::new(0.2)
    };
    let pilot = diffusion::run(&base, &crate::common::threads(2)).unwrap();
    let pilot_rel = pilot.D_err / pilot.D;
    let target = pilot_rel / 4.0;
    let planned = diffusion::run(
        &DiffusionConfig {
            rel_err: Some(target),
            ..base.clone()
        },
        &crate::common::threads(2),
    )
    .unwrap();
    let p = planned.pilot.expect("a planned run records its pilot");
    assert!(
        p.continued,
        "the planned run continues the pilot's trajectories"
    );
    assert_eq!(p.rel_err.to_bits(), pilot_rel.to_bits());
    assert_eq!((p.collisions, p.rel_err_target), (pilot_size, target));
    assert_eq!(
        Some(p.planned_collisions),
        plan::collisions_for(pilot_size, 128, pilot_rel, target)
    );
    assert!(p.planned_collisions > 15 * pilot_size, "{p:?}");
    let plain = diffusion::run(
        &DiffusionConfig {
            collisions: p.planned_collisions,
            ..base
        },
        &crate::common::threads(2),
    )
    .unwrap();
    assert_eq!(planned.D.to_bits(), plain.D.to_bits());
    assert_eq!(planned.batch_D, plain.batch_D);
    assert_eq!(
        planned.config.as_ref().unwrap().collisions,
        p.planned_collisions
    );
    assert_eq!(planned.config.as_ref().unwrap().rel_err, None);
    let reached = planned.D_err / planned.D;
    let f = (reached / target).powi(2);
    let p_two_sided = 2.0 * f_p_value(f.max(1.0 / f), 127.0, 127.0);
    eprintln!("reached {reached:.3e} for {target:.3e}: F = {f:.3}, p = {p_two_sided:.1e}");
    assert!(
        p_two_sided > 1e-3,
        "reached {reached:.3e} for {target:.3e}: F = {f:.3}, p = {p_two_sided:.1e}"
    );
}

/// A pilot that already meets its target is the result: no second run.
#[test]
fn a_pilot_that_meets_its_target_is_the_run() {
    let base = DiffusionConfig {
        collisions: 4_000_000,
        ..DiffusionConfig::new(0.2)
    };
    let plain = diffusion::run(&base, &crate::common::threads(2)).unwrap();
    let planned = diffusion::run(
        &DiffusionConfig {
            rel_err: Some(0.5),
            ..base
        },
        &crate::common::threads(2),
    )
    .unwrap();
    assert_eq!(planned.D.to_bits(), plain.D.to_bits());
    assert_eq!(planned.collisions, 4_000_000);
    assert_eq!(planned.pilot.unwrap().planned_collisions, 4_000_000);
}

/// Every run says what the next decade of relative error needs: N·(r/ρ)², the decade ρ just
/// below its own error r, two significant digits and a multiple of the batches.
#[test]
fn every_run_plans_the_next_decade() {
    let r = diffusion::run(
        &DiffusionConfig {
            collisions: 4_000_000,
            ..DiffusionConfig::new(0.2)
        },
        &crate::common::threads(2),
    )
    .unwrap();
    let rel = r.D_err / r.D;
    let p = r.plan.unwrap();
    assert!(p.rel_err < rel && rel <= 10.0 * p.rel_err, "{rel} {p:?}");
    let exact = 4e6 * (rel / p.rel_err).powi(2);
    let n = p.collisions as f64;
    assert!(n >= exact && n <= exact * 1.1 + 32.0, "{n} for {exact}");
    assert_eq!(p.collisions % 32, 0);
    assert!((p.seconds - n / r.collisions_per_second).abs() <= 1e-9 * p.seconds);
}

/// A planned run kept in a checkpoint records its pilot in the checkpoint's header: reopened, it
/// runs neither the pilot (the progress it reports is the planned run's collisions exactly, not
/// the pilot's besides) nor any batch again, and prints the same result with the same keys, its
/// plan for the next decade included. Breaking it on purpose — dropping the pilot from the
/// header — reports the pilot's 4·10⁶ collisions as well and fails.
#[test]
fn a_reopened_planned_run_runs_neither_its_pilot_nor_its_batches_again() {
    use lorentz_gas::engine::options::RunOptions;
    use std::sync::atomic::{AtomicU64, Ordering};
    let tmp = crate::common::scratch();
    let cfg = DiffusionConfig {
        collisions: 4_000_000,
        batches: 8,
        rel_err: Some(2e-3),
        ..DiffusionConfig::new(0.2)
    };
    let path = tmp.path().join("planned.jsonl");
    let opts = RunOptions {
        resume: Some(path.clone()),
        ..crate::common::threads(2)
    };
    let first = diffusion::run(&cfg, &opts).unwrap();
    let p = first.pilot.unwrap();
    assert!(
        p.continued && p.planned_collisions > cfg.collisions,
        "{p:?}"
    );
    let reported = AtomicU64::new(0);
    let count = |n: u64| {
        reported.fetch_add(n, Ordering::Relaxed);
    };
    let again = diffusion::run(
        &cfg,
        &RunOptions {
            progress: &count,
            ..opts.clone()
        },
    )
    .unwrap();
    assert_eq!(reported.load(Ordering::Relaxed), p.planned_collisions);
    assert_eq!(again.resumed_batches, 8);
    assert_eq!(again.D.to_bits(), first.D.to_bits());
    assert_eq!(again.pilot, first.pilot);
    let keys = |r: &diffusion::DiffusionReport| {
        let v = serde_json::to_value(r).unwrap();
        let o = v.as_object().unwrap().clone();
        o.into_iter()
            .filter(|(_, x)| !x.is_null())
            .map(|(k, _)| k)
            .collect::<Vec<_>>()
    };
    assert_eq!(keys(&again), keys(&first));
    assert_eq!(
        again.plan.map(|p| p.collisions),
        first.plan.map(|p| p.collisions)
    );
}

/// The plan alone: the pilot's result, with the pilot and the plan for the target, which a
/// planned run of the same pilot then runs to (the same collisions).
#[test]
fn the_plan_alone_is_the_pilot_with_the_plan_for_the_target() {
    let cfg = DiffusionConfig {
        collisions: 4_000_000,
        batches: 8,
        rel_err: Some(2e-3),
        ..DiffusionConfig::new(0.2)
    };
    let only = plan::plan_only(&cfg, &crate::common::threads(2)).unwrap();
    let p = only.pilot.unwrap();
    let plan = only.plan.unwrap();
    assert_eq!(only.collisions, cfg.collisions);
    assert_eq!(
        (plan.rel_err, plan.collisions),
        (2e-3, p.planned_collisions)
    );
    assert!(plan.seconds > 0.0);
    let planned = diffusion::run(&cfg, &crate::common::threads(2)).unwrap();
    assert_eq!(planned.collisions, plan.collisions);
}
