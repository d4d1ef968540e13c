//! The diffusion tensor in a magnetic field (`estimators::field`), against symmetry, continuity
//! and the exact geometry of its localized orbits:
//!
//! * Onsager–Casimir: D_xx(B) − D_xx(−B) and D_xy(B) + D_xy(−B) consistent with 0 (Welch 4σ);
//! * B → 0 joins D(w) of the run without a field (Welch 4σ);
//! * where every orbit is localized the tensor is exactly 0 and every sampled point is localized;
//! * the symmetric off-diagonal part and D_xx − D_yy are 0 by the lattice's symmetry, Kac's mean
//!   free time of the diffusing part holds (4σ);
//! * the same seed gives the same bits on one thread and on two, on the scalar kernel and on
//!   the SIMD arc engine.

use lorentz_gas::estimators::diffusion::{self, DiffusionConfig};
use lorentz_gas::estimators::field::{self, FieldReport};
use lorentz_gas::scenes::spec::SceneSpec;
use lorentz_gas::scenes::spec::{Motion, Table};

use crate::common::{physics_only, t4, t4_welch, threads};

const BATCHES: u32 = 16;

fn config(w: f64, b: &str, collisions: u64) -> DiffusionConfig {
    scene_config(
        SceneSpec::Triangular {
            w: format!("{w:?}"),
        },
        b,
        collisions,
    )
}

fn scene_config(scene: SceneSpec, b: &str, collisions: u64) -> DiffusionConfig {
    let table = Table {
        scene,
        motion: Motion::Field(b.into()),
    };
    DiffusionConfig {
        localization_samples: Some(100_000),
        collisions,
        batches: BATCHES,
        seed: 11,
        ..DiffusionConfig::on(table)
    }
}

fn run(w: f64, b: &str, collisions: u64) -> FieldReport {
    field::run(&config(w, b, collisions), &threads(2)).unwrap()
}

/// The shipped table: the unit square lattice, radius 2/5 at the corners and 1/5 at the centre
/// (the square's symmetry: D_xx = D_yy, no symmetric off-diagonal part).
fn two_radius() -> SceneSpec {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/tables/two-radius-square.toml"
    ))
    .unwrap();
    SceneSpec::Table(lorentz_gas::scenes::table::spec::TableSpec::from_toml(&text).unwrap())
}

fn square(radius: &str) -> SceneSpec {
    SceneSpec::Square {
        radius: radius.into(),
    }
}

/// |x| within the Welch 4σ bound of two independent estimates' errors.
fn consistent_with_zero(x: f64, ea: f64, eb: f64) -> bool {
    x.abs() <= t4_welch(ea, BATCHES, eb, BATCHES) * (ea * ea + eb * eb).sqrt()
}

/// Asserts [`consistent_with_zero`] of `x`, a combination of the estimates `a` and `b` (value,
/// standard error), naming `what` and both estimates if not.
fn assert_zero_within(what: &str, x: f64, (a, ea): (f64, f64), (b, eb): (f64, f64)) {
    assert!(
        consistent_with_zero(x, ea, eb),
        "{what}: {a} ± {ea} vs {b} ± {eb}"
    );
}

#[test]
#[ignore = "slow tier: CI runs it with `cargo test --release --test analyses slow_tier -- --ignored`"]
fn slow_tier_d_xx_is_even_and_the_hall_part_odd_in_the_field() {
    for (w, b) in [
        (0.1, "0.5"),
        (0.1, "1"),
        (0.1, "2"),
        (0.3, "1/2"),
        (0.3, "1"),
        (0.3, "3"),
    ] {
        let tri = SceneSpec::Triangular {
            w: format!("{w:?}"),
        };
        onsager_casimir(&tri, b, 8_000_000);
    }
}

/// Every scene has a finite horizon in a field: the square lattice, whose corridors make D
/// infinite without one, and the triangular lattice beyond w_inf have a tensor with the
/// symmetries, Kac's mean free time and the exact localized share; so has a table of two radii
/// given as data (at B = 3 an eighth of its phase space skips round its disks).
#[test]
fn scenes_with_corridors_diffuse_in_a_field_with_the_symmetries() {
    for (scene, b) in [
        (square("1/4"), "1"),
        (square("1/4"), "1/2"),
        (square("2/5"), "1"),
        (SceneSpec::Triangular { w: "1/2".into() }, "1"),
        (two_radius(), "1"),
        (two_radius(), "3"),
    ] {
        onsager_casimir(&scene, b, 4_000_000);
    }
}

/// D_xx(B) − D_xx(−B) and D_xy(B) + D_xy(−B) consistent with 0, a Hall part that is there,
/// the lattice's symmetries, Kac's mean free time and the sampled localized share.
fn onsager_casimir(scene: &SceneSpec, b: &str, collisions: u64) {
    let run =
        |b: &str| field::run(&scene_config(scene.clone(), b, collisions), &threads(2)).unwrap();
    let (plus, minus) = (run(b), run(&format!("-{b}")));
    let at = format!("{scene:?} B=±{b}");
    assert_zero_within(
        &format!("{at}: D_xx"),
        plus.point.D_xx - minus.point.D_xx,
        (plus.point.D_xx, plus.point.D_xx_err),
        (minus.point.D_xx, minus.point.D_xx_err),
    );
    assert_zero_within(
        &format!("{at}: D_xy"),
        plus.point.D_xy + minus.point.D_xy,
        (plus.point.D_xy, plus.point.D_xy_err),
        (minus.point.D_xy, minus.point.D_xy_err),
    );
    // The Hall part is there (not 0 by accident of the estimator) and turns with the field.
    assert!(
        plus.point.D_xy.abs() > 4.0 * plus.point.D_xy_err,
        "{at}: {}",
        plus.point.D_xy
    );
    for r in [&plus, &minus] {
        symmetric_and_kac(r, &at);
    }
}

/// The symmetric off-diagonal part and D_xx − D_yy are 0 by the lattice's symmetry, Kac's mean
/// free time holds, and the sampled localized share is the exact one (binomial 4σ).
fn symmetric_and_kac(r: &FieldReport, at: &str) {
    let t = &r.diffusing;
    let bound = t4(BATCHES);
    assert!(
        t.D_xy_symmetric.abs() <= bound * t.D_xy_symmetric_err,
        "{at}: {t:?}"
    );
    assert!(
        consistent_with_zero(t.D_xx - t.D_yy, t.D_xx_err, t.D_yy_err),
        "{at}: {t:?}"
    );
    let kac = r.point.mean_free_time - r.point.mean_free_time_exact;
    assert!(
        kac.abs() <= bound * r.point.mean_free_time_err,
        "{at} B={}: Kac {kac:e}",
        r.point.field
    );
    let f = r.point.localized_fraction_exact;
    let n = r.config.localization_samples.unwrap_or(0) as f64;
    let bin = 4.0 * (f * (1.0 - f) / n).sqrt() + 1.0 / n;
    assert!(
        (r.point.localized_fraction - f).abs() <= bin,
        "{at}: {} vs {f}",
        r.point.localized_fraction
    );
}

#[test]
fn a_weak_field_joins_d_of_w() {
    let w = 0.2;
    let weak = run(w, "1/1000", 8_000_000);
    let cfg = DiffusionConfig {
        collisions: 8_000_000,
        batches: BATCHES,
        seed: 11,
        ..DiffusionConfig::new(w)
    };
    let zero = diffusion::run(&cfg, &threads(2)).unwrap();
    assert_eq!(weak.point.localized_fraction_exact, 0.0);
    assert_zero_within(
        "D_xx(B = 0.001) vs D(w)",
        weak.point.D_xx - zero.D,
        (weak.point.D_xx, weak.point.D_xx_err),
        (zero.D, zero.D_err),
    );
}

#[test]
fn where_every_orbit_is_localized_the_tensor_is_exactly_zero() {
    // w = 0.1: every orbit is localized once 2ρ ≤ A − 2r = 0.1, i.e. B ≥ 20.
    let r = run(0.1, "25", 8_000_000);
    assert!(r.point.all_localized);
    assert_eq!((r.point.D_xx, r.point.D_xy, r.collisions), (0.0, 0.0, 0));
    assert_eq!(r.point.localized_fraction, 1.0);
    assert!(
        (r.point.localized_fraction_exact - 1.0).abs() < 1e-11,
        "{}",
        r.point.localized_fraction_exact
    );
    // Just below, some orbits diffuse.
    let r = run(0.1, "19", 8_000_000);
    assert!(
        !r.point.all_localized && r.point.localized_fraction < 1.0 && r.point.D_xx > 0.0,
        "{r:?}"
    );
}

#[test]
fn on_the_square_lattice_every_orbit_is_localized_once_2rho_reaches_1_minus_2r() {
    // r = 1/4 at unit spacing: every orbit is localized once 2ρ ≤ 1 − 2r = 1/2, i.e. B ≥ 4.
    let cfg = |b: &str| scene_config(square("1/4"), b, 4_000_000);
    let r = field::run(&cfg("4"), &threads(2)).unwrap();
    assert!(r.point.all_localized);
    assert_eq!((r.point.D_xx, r.point.D_xy, r.collisions), (0.0, 0.0, 0));
    assert_eq!(
        (r.point.localized_fraction, r.point.radius, r.point.w),
        (1.0, Some(0.25), None)
    );
    // Just below, some orbits diffuse, and the share is still the exact one.
    let r = field::run(&cfg("7/2"), &threads(2)).unwrap();
    assert!(!r.point.all_localized && r.point.D_xx > 0.0, "{r:?}");
    symmetric_and_kac(&r, "square r=1/4 B=7/2");
}

#[test]
fn same_seed_same_bits_on_every_engine_and_thread_count() {
    use lorentz_gas::engine::Engine;
    let on = crate::common::on_engine;
    for cfg in [
        config(0.15, "-3/4", 2_000_000),
        scene_config(square("1/3"), "3/2", 1_000_000),
        scene_config(two_radius(), "-5/2", 1_000_000),
    ] {
        let one = field::run(&cfg, &on(Engine::Scalar, 1)).unwrap();
        let json = |r: &FieldReport| physics_only(serde_json::to_value(r).unwrap());
        // The SIMD arc engine in blocks of 16, and of 6, 6 and 4 batches (three threads): every
        // batch has the scalar kernel's bits, whichever lanes it flies in.
        for threads in [1, 2, 3] {
            let simd = field::run(&cfg, &on(Engine::Simd, threads)).unwrap();
            assert_eq!(simd.meta.engine, "simd");
            assert_eq!(json(&one), json(&simd), "{threads} threads");
        }
        let two = field::run(&cfg, &on(Engine::Scalar, 2)).unwrap();
        assert_eq!(json(&one), json(&two));
    }
}

#[test]
fn the_arc_kernel_has_a_benchmark_and_it_refuses_what_it_cannot_time() {
    use lorentz_gas::engine::Engine;
    use lorentz_gas::estimators::throughput::{self, Observe, ThroughputConfig};
    use lorentz_gas::numbers::precision::Precision;
    let cfg = ThroughputConfig {
        collisions_per_thread: 20_000,
        repetitions: 1,
        field: Some(1.0),
        ..ThroughputConfig::new(Table::triangular_at(0.1))
    };
    let t = throughput::run(&cfg, &threads(1)).unwrap();
    assert_eq!(t.field, Some(1.0));
    // `auto`: the SIMD arc engine where the CPU has AVX2 or AVX-512, else the scalar kernel.
    assert_eq!(t.meta.engine, Engine::Auto.resolve(true).unwrap().name());
    assert!(t.collisions_per_second > 0.0 && t.crossings_per_collision > 0.0);
    for (engine, name, lanes) in [(Engine::Scalar, "scalar", 1), (Engine::Simd, "simd", 16)] {
        let r = throughput::run(&cfg, &crate::common::on_engine(engine, 1)).unwrap();
        assert_eq!(
            (r.meta.engine.as_str(), r.trajectories_per_thread),
            (name, lanes)
        );
    }
    let mpfr = ThroughputConfig {
        precision: Precision::Bits(128),
        ..cfg.clone()
    };
    assert!(throughput::run(&mpfr, &threads(1)).is_err());
    let observed = ThroughputConfig {
        observe: Observe::Counters,
        ..cfg.clone()
    };
    assert!(throughput::run(&observed, &threads(1)).is_err());
    // A zero field is the straight benchmark.
    let zero = ThroughputConfig {
        field: Some(0.0),
        ..cfg.clone()
    };
    assert_eq!(throughput::run(&zero, &threads(1)).unwrap().field, None);
    // Side by side: a straight repetition after each arc repetition, and their ratios.
    let beside = ThroughputConfig {
        repetitions: 3,
        straight_beside: true,
        ..cfg.clone()
    };
    let b = throughput::run(&beside, &threads(1)).unwrap();
    let s = b.straight.as_ref().unwrap();
    assert_eq!(s.samples.len(), 3);
    let median = |v: &[f64]| {
        let mut v = v.to_vec();
        v.sort_by(f64::total_cmp);
        v[1]
    };
    assert_eq!(
        s.arcs_over_straight,
        median(&b.samples) / median(&s.samples)
    );
    assert!(s.paired_ratio > 0.0 && s.collisions_per_second_per_thread > 0.0);
    let no_field = ThroughputConfig {
        field: None,
        ..beside
    };
    assert!(throughput::run(&no_field, &threads(1)).is_err());
    // The winner-only floor: one tape of the engine's own events (⌊collisions/16⌋ steps, every
    // lane an event per step), timed on both engines (the fed one checked bit for bit); refused
    // without a field or on the scalar engine.
    let oracle = ThroughputConfig {
        repetitions: 3,
        oracle_floor: true,
        ..cfg.clone()
    };
    if Engine::Auto.resolve(true).unwrap().simd().is_some() {
        let o = throughput::run(&oracle, &threads(1))
            .unwrap()
            .oracle
            .unwrap();
        assert_eq!(o.steps as u64, cfg.collisions_per_thread / 16);
        assert_eq!(o.events, 16.0 * o.steps as f64);
        assert!(o.collisions > 0.5 * o.events && o.collisions < o.events);
        assert_eq!(
            o.times.floor_collisions_per_second,
            1e9 / o.times.floor_ns_per_collision
        );
        assert!(o.times.paired_ratio > 0.0 && o.times.full_ns_per_collision > 0.0);
    }
    assert!(throughput::run(&oracle, &crate::common::on_engine(Engine::Scalar, 1)).is_err());
    let no_field = ThroughputConfig {
        field: None,
        ..oracle
    };
    assert!(throughput::run(&no_field, &threads(1)).is_err());
}

/// The Lyapunov exponent in a field (`estimators::field::lyapunov`): even in B (the mirror
/// y → −y maps the lattice to itself and B to −B), joining the exponent without a field as
/// B → 0, and lower than it at B = 1 (cyclotron radius of the order of the lattice: focusing
/// arcs), each by the Welch 4σ bound of independent orbits.
#[test]
fn the_lyapunov_exponent_is_even_in_b_and_joins_the_zero_field_one() {
    use lorentz_gas::estimators::field::lyapunov as fl;
    use lorentz_gas::scenes::triangular::TriangularScene;
    use lorentz_gas::verification::lyapunov::{self, LyapunovConfig};
    const ORBITS: u32 = 8;
    let scene = TriangularScene::new(0.1).unwrap();
    let cfg = |b: &str, seed: u64| {
        LyapunovConfig {
            collisions_per_batch: 200_000,
            batches: ORBITS,
            seed,
            ..LyapunovConfig::new()
        }
        .in_field(b)
    };
    let run = |b: &str, seed: u64| fl::run(&scene, &cfg(b, seed), &threads(2)).unwrap().tangent;
    let zero = lyapunov::run(
        &scene,
        &LyapunovConfig {
            collisions_per_batch: 200_000,
            batches: ORBITS,
            seed: 3,
            ..LyapunovConfig::new()
        },
        &threads(2),
    )
    .unwrap();
    let agree = |a: &lorentz_gas::verification::lyapunov::LyapunovReport,
                 b: &lorentz_gas::verification::lyapunov::LyapunovReport| {
        let (ea, eb) = (a.per_collision_err, b.per_collision_err);
        (a.per_collision - b.per_collision).abs() <= t4_welch(ea, ORBITS, eb, ORBITS) * ea.hypot(eb)
    };
    let weak = run("1/1000", 5);
    assert!(agree(&weak, &zero), "{weak:?} vs {zero:?}");
    let (plus, minus) = (run("1", 5), run("-1", 6));
    assert!(agree(&plus, &minus), "{plus:?} vs {minus:?}");
    // The field changes the exponent: B = 1 is not B = 0 (far outside the bound).
    assert!(!agree(&plus, &zero), "{plus:?} vs {zero:?}");
    assert!(plus.per_collision < zero.per_collision);
}

/// The exponent in a field on the square lattice, whose corridors the field closes: even in B (the
/// mirror y → −y maps the square lattice to itself) and far from the exponent without a field
/// at B = 1, each by the Welch 4σ bound of independent orbits.
#[test]
fn on_the_square_lattice_the_field_exponent_is_even_in_b() {
    use lorentz_gas::estimators::field::lyapunov as fl;
    use lorentz_gas::scenes::square::SquareScene;
    use lorentz_gas::verification::lyapunov::{self, LyapunovConfig, LyapunovReport};
    const ORBITS: u32 = 8;
    let scene = SquareScene::new(0.25).unwrap();
    let run = |b: &str, seed: u64| {
        let cfg = LyapunovConfig {
            collisions_per_batch: 100_000,
            batches: ORBITS,
            seed,
            ..LyapunovConfig::new()
        }
        .in_field(b);
        fl::run(&scene, &cfg, &threads(2)).unwrap().tangent
    };
    let zero = LyapunovConfig {
        collisions_per_batch: 100_000,
        batches: ORBITS,
        seed: 3,
        ..LyapunovConfig::new()
    };
    let zero = lyapunov::run(&scene, &zero, &threads(2)).unwrap();
    let agree = |a: &LyapunovReport, b: &LyapunovReport| {
        let (ea, eb) = (a.per_collision_err, b.per_collision_err);
        (a.per_collision - b.per_collision).abs() <= t4_welch(ea, ORBITS, eb, ORBITS) * ea.hypot(eb)
    };
    let (plus, minus) = (run("1", 5), run("-1", 6));
    assert!(plus.scene.starts_with("square"), "{}", plus.scene);
    assert!(agree(&plus, &minus), "{plus:?} vs {minus:?}");
    assert!(!agree(&plus, &zero), "{plus:?} vs {zero:?}");
}

/// The exponent in a field on the SIMD arc engine (blocks of 16, and of 6, 6 and 4 orbits on
/// three threads) has the scalar kernel's bits on the triangular and square lattices and a table
/// of two radii: every orbit is fed the same events with the same arrival velocities.
#[test]
fn the_field_exponent_has_the_same_bits_on_every_engine_and_thread_count() {
    use lorentz_gas::engine::Engine;
    use lorentz_gas::engine::options::RunOptions;
    use lorentz_gas::estimators::field::lyapunov as fl;
    let on = crate::common::on_engine;
    let triangular = SceneSpec::Triangular { w: "0.15".into() };
    for (scene, b) in [
        (triangular, "-3/4"),
        (square("1/3"), "3/2"),
        (two_radius(), "1"),
    ] {
        let cfg = lorentz_gas::verification::lyapunov::LyapunovConfig {
            collisions_per_batch: 20_000,
            batches: 16,
            seed: 7,
            ..Default::default()
        }
        .in_field(b);
        let choice = scene.resolve().unwrap();
        let run =
            |o: &RunOptions| lorentz_gas::with_scene!(&choice, |s| fl::run(s, &cfg, o)).unwrap();
        let one = run(&on(Engine::Scalar, 1));
        assert_eq!(one.tangent.meta.engine, "scalar");
        let bits = |r: &fl::FieldLyapunovReport| {
            let t = &r.tangent;
            [
                t.per_collision,
                t.per_collision_err,
                t.per_time,
                t.per_time_err,
            ]
            .map(f64::to_bits)
        };
        for threads in [1, 2, 3] {
            let simd = run(&on(Engine::Simd, threads));
            assert_eq!(simd.tangent.meta.engine, "simd");
            assert_eq!(
                bits(&one),
                bits(&simd),
                "{scene:?} B={b}, {threads} threads"
            );
            assert_eq!(one.rejected_starts, simd.rejected_starts);
        }
    }
}
