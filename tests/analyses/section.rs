//! The Poincaré section (`estimators::section`), against what is exactly true of its points:
//!
//! * a skipping orbit keeps its incidence angle (`proofs-notes/poincare-section.md`): its points
//!   lie on one line p = const, up to the rounding of its collisions (bounded below);
//! * |p| ≤ 1 and θ ∈ [−π, π) at every point, on disks of radius 1 and 2/5;
//! * without a field the billiard map preserves cos α dα dθ = dp dθ: the p of one late collision
//!   per orbit is uniform on [−1, 1] and θ uniform on [−π, π) (χ² over 20 bins each, below its
//!   0.999 quantile);
//! * at w = 0.2, B = 5/2 regular islands are found (bounded orbits within the limit);
//! * the same seed gives the same bits on one thread and on two;
//! * bad counts are refused.

use lorentz_gas::ErrorKind;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::section::{self, Component, SectionConfig, SectionResult};
use lorentz_gas::scenes::spec::{Motion, SceneSpec, Table};

fn config(
    w: &str,
    field: &str,
    trajectories: u32,
    collisions: u64,
    classify: u64,
) -> SectionConfig {
    SectionConfig {
        trajectories,
        collisions,
        classify_collisions: classify,
        seed: 7,
        ..SectionConfig::new(Table::triangular(w).unwrap().in_field(field))
    }
}

fn run(cfg: &SectionConfig, threads: usize) -> SectionResult {
    section::run(
        cfg,
        &RunOptions {
            threads,
            ..RunOptions::default()
        },
    )
    .unwrap()
}

/// The points (θ, p) of orbit `o`.
fn points(r: &SectionResult, o: u32) -> Vec<(f64, f64)> {
    (0..r.theta.len())
        .filter(|&i| r.trajectory[i] == o)
        .map(|i| (r.theta[i], r.p[i]))
        .collect()
}

/// Each collision of a skipping orbit rounds its contact point and its reflected velocity,
/// each to a few ulps; the incidence angle it carries on is off by at most a few ε per
/// collision, and the errors add up at worst linearly (the orbit is neutral: nothing
/// amplifies them). The bound allows 8ε per collision.
const SKIPPING_ULPS_PER_COLLISION: f64 = 8.0;

#[test]
fn a_skipping_orbit_keeps_its_incidence_angle() {
    let r = run(&config("0.2", "5/2", 48, 2_000, 2_000), 2);
    let skipping: Vec<u32> = (0..48)
        .filter(|&o| r.component[o as usize] == Component::Skipping)
        .collect();
    assert!(skipping.len() >= 3, "{} skipping orbits", skipping.len());
    let mut worst = 0.0f64;
    for o in skipping {
        let pts = points(&r, o);
        assert_eq!(pts.len(), 2_000);
        let p0 = pts[0].1;
        for (k, (_, p)) in pts.iter().enumerate() {
            let bound = SKIPPING_ULPS_PER_COLLISION * f64::EPSILON * (k as f64 + 1.0);
            assert!(
                (p - p0).abs() <= bound,
                "orbit {o}, collision {k}: p {p} against {p0}"
            );
            worst = worst.max((p - p0).abs() / f64::EPSILON / (k as f64 + 1.0));
        }
    }
    eprintln!("skipping orbits: largest drift of p {worst:.2} ε per collision");
}

#[test]
fn every_point_is_in_the_birkhoff_rectangle() {
    let square = |b: &str| SectionConfig {
        table: Table {
            scene: SceneSpec::Square {
                radius: "2/5".into(),
            },
            motion: Motion::in_field(b),
        },
        ..config("0.2", "0", 16, 2_000, 2_000)
    };
    let mut cases: Vec<SectionConfig> = ["0", "5/2", "-1"]
        .iter()
        .map(|b| config("0.2", b, 16, 2_000, 2_000))
        .collect();
    cases.extend([square("0"), square("2")]);
    for cfg in &cases {
        let r = run(cfg, 2);
        assert!(!r.p.is_empty());
        for (t, p) in r.theta.iter().zip(&r.p) {
            assert!(p.abs() <= 1.0, "p = {p}");
            assert!(
                (-std::f64::consts::PI..std::f64::consts::PI).contains(t),
                "θ = {t}"
            );
        }
    }
}

/// χ² of `values` over `bins` equal bins of [lo, hi).
fn chi2(values: &[f64], bins: usize, (lo, hi): (f64, f64)) -> f64 {
    let mut count = vec![0.0; bins];
    for v in values {
        let k = (((v - lo) / (hi - lo)) * bins as f64).floor() as usize;
        count[k.min(bins - 1)] += 1.0;
    }
    let e = values.len() as f64 / bins as f64;
    count.iter().map(|c| (c - e) * (c - e) / e).sum()
}

/// The 0.999 quantile of χ² with 19 degrees of freedom.
const CHI2_19_Q999: f64 = 43.82;

#[test]
fn without_a_field_p_and_theta_are_uniform() {
    // One point per orbit, its 20th collision (independent orbits; the start's bias towards
    // collisions after long flights long forgotten), 20 000 orbits.
    let collisions = 20;
    let r = run(&config("0.2", "0", 20_000, collisions, collisions), 2);
    assert_eq!(r.diffusing, 20_000);
    let last = |v: &[f64]| -> Vec<f64> {
        v.chunks(collisions as usize)
            .map(|c| c[c.len() - 1])
            .collect()
    };
    let (p, theta) = (last(&r.p), last(&r.theta));
    let pi = std::f64::consts::PI;
    let (cp, ct) = (chi2(&p, 20, (-1.0, 1.0)), chi2(&theta, 20, (-pi, pi)));
    eprintln!("χ²(p) = {cp:.2}, χ²(θ) = {ct:.2} (19 dof, 0.999 quantile {CHI2_19_Q999})");
    assert!(cp < CHI2_19_Q999, "χ²(p) = {cp}");
    assert!(ct < CHI2_19_Q999, "χ²(θ) = {ct}");
}

#[test]
fn islands_are_found_at_w_0_2_and_b_5_2() {
    let r = run(&config("0.2", "5/2", 32, 1_000, 100_000), 2);
    let limit = r.limit.unwrap();
    assert!(r.bounded >= 1, "no bounded orbit: {:?}", r.component);
    assert_eq!(r.pinned + r.skipping + r.bounded + r.diffusing, 32);
    for (c, reach) in r.component.iter().zip(&r.reach) {
        match c {
            Component::Bounded => assert!(*reach <= limit),
            Component::Diffusing => assert!(*reach > limit),
            _ => {}
        }
    }
}

#[test]
fn the_same_seed_gives_the_same_bits_on_one_thread_and_on_two() {
    let cfg = config("0.2", "5/2", 12, 500, 20_000);
    let (a, b) = (run(&cfg, 1), run(&cfg, 2));
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.theta), bits(&b.theta));
    assert_eq!(bits(&a.p), bits(&b.p));
    assert_eq!(bits(&a.reach), bits(&b.reach));
    assert_eq!(
        (a.trajectory, a.disk, a.component),
        (b.trajectory, b.disk, b.component)
    );
}

#[test]
fn bad_counts_are_refused() {
    for cfg in [
        config("0.2", "5/2", 0, 10, 10),
        config("0.2", "5/2", 4, 0, 10),
        config("0.2", "5/2", 4, 100, 10),
        config("0.2", "5/2", 100_000, 1_000, 1_000),
        config("0.2", "nan", 4, 10, 10),
        config("-1", "1", 4, 10, 10),
    ] {
        let e = section::run(&cfg, &RunOptions::default()).unwrap_err();
        assert_eq!(e.kind(), ErrorKind::BadInput, "{e}");
    }
}
