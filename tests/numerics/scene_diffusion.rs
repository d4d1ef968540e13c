//! D on any scene (`estimators::diffusion::scene::run_on`): on the triangular scene it gives the
//! bits of `diffusion::run` on the scalar engine, at `f64` and at an MPFR precision; on a table
//! defined outside the crate (the two-radius square of `examples/custom_scene.rs`) its exact
//! identities hold within their Student-t bounds and its audited events stay inside the error
//! model; infinite horizons, the SIMD engine and MPFR audits are refused; a checkpoint resumes
//! to the uninterrupted bits and refuses another scene's.

use lorentz_gas::Error;
use lorentz_gas::engine::Engine;
use lorentz_gas::engine::options::{AuditSpec, RunOptions};
use lorentz_gas::estimators::diffusion::scene::{SceneDiffusionConfig, run_on};
use lorentz_gas::estimators::diffusion::{self, DiffusionConfig};
use lorentz_gas::numbers::precision::Precision;
use lorentz_gas::scenes::square::SquareScene;
use lorentz_gas::scenes::triangular::TriangularScene;
use rug::Rational;

#[path = "../../examples/custom_scene.rs"]
#[allow(dead_code)]
mod custom_scene;
use custom_scene::TwoRadiusSquare;

fn scalar(threads: usize) -> RunOptions<'static> {
    RunOptions {
        engine: Engine::Scalar,
        threads,
        ..RunOptions::default()
    }
}

/// The generic path's batches on the triangular scene are `diffusion::run`'s, bit for bit.
fn same_bits_as_the_triangular_estimator(w: &str, precision: Precision, collisions: u64) {
    let q: Rational = lorentz_gas::numbers::exact::parse_exact(w).unwrap();
    let w64 = lorentz_gas::numbers::exact::nearest_f64(&q);
    let tri = DiffusionConfig {
        w: w64,
        w_exact: Some(w.to_string()),
        collisions,
        batches: 4,
        seed: 3,
        precision,
        ..DiffusionConfig::new(w64)
    };
    let general = SceneDiffusionConfig {
        collisions,
        batches: 4,
        seed: 3,
        precision,
        window: tri.window,
        check_window: tri.check_window,
        msd_grid: tri.msd_grid,
    };
    let a = diffusion::run(&tri, &scalar(2)).unwrap();
    let b = run_on(&TriangularScene::exact(q).unwrap(), &general, &scalar(1)).unwrap();
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.batch_D), bits(&b.batch_D), "w = {w} at {precision}");
    assert_eq!(bits(&a.batch_D_check), bits(&b.batch_D_check));
    assert_eq!(a.D.to_bits(), b.D.to_bits());
    assert_eq!(a.D_err.to_bits(), b.D_err.to_bits());
    let mfp = b.identity("mean free path").unwrap();
    assert_eq!(mfp.measured.to_bits(), a.mean_free_path.to_bits());
    let tau = b.identity("crossing time").unwrap();
    assert_eq!(tau.exact.to_bits(), a.tau_hop_exact.to_bits());
    assert_eq!(tau.measured.to_bits(), a.tau_hop.to_bits());
}

#[test]
fn triangular_scene_gives_the_bits_of_the_triangular_estimator() {
    same_bits_as_the_triangular_estimator("0.2", Precision::F64, 400_000);
    same_bits_as_the_triangular_estimator("1/10", Precision::F64, 400_000);
    same_bits_as_the_triangular_estimator("0.25", Precision::Bits(128), 40_000);
}

fn two_radius() -> TwoRadiusSquare {
    TwoRadiusSquare::new(Rational::from((2, 5)), Rational::from((1, 5))).unwrap()
}

#[test]
fn a_scene_defined_outside_the_crate_meets_its_identities_and_its_error_model() {
    let cfg = SceneDiffusionConfig {
        collisions: 4_000_000,
        batches: 8,
        seed: 11,
        ..SceneDiffusionConfig::default()
    };
    let opts = RunOptions {
        audit: Some(AuditSpec::new(2e-3, 192).unwrap()),
        ..scalar(2)
    };
    let r = run_on(&two_radius(), &cfg, &opts).unwrap();
    assert_eq!(r.identities.len(), 3);
    for i in &r.identities {
        assert!(i.agrees, "{i:?}");
        assert!(i.err > 0.0 && i.err < 1e-2 * i.exact, "{i:?}");
    }
    let audit = r.audit.as_ref().unwrap();
    assert!(audit.audited > 4000, "{audit:?}");
    assert_eq!(audit.outside, 0, "{:?}", audit.outside_events);
    // Finite horizon: a positive D, resolved, with the two windows agreeing paired.
    assert!(r.D > 0.0 && r.D_err < 0.05 * r.D, "{} ± {}", r.D, r.D_err);
    let t = r.D_minus_D_check / r.D_minus_D_check_err;
    let bound = lorentz_gas::statistics::normal_sigma_equivalent_t(7.0, 4.0);
    assert!(t.abs() <= bound, "windows differ by {t} sigma");
    // Same seed, any thread count: the same bits.
    let again = run_on(&two_radius(), &cfg, &RunOptions { threads: 1, ..opts }).unwrap();
    assert_eq!(r.D.to_bits(), again.D.to_bits());
}

#[test]
fn open_corridors_the_simd_engine_and_mpfr_audits_are_refused() {
    let cfg = SceneDiffusionConfig {
        collisions: 1_000_000,
        batches: 4,
        ..SceneDiffusionConfig::default()
    };
    let square = SquareScene::new(0.25).unwrap();
    let e = run_on(&square, &cfg, &scalar(1)).unwrap_err();
    assert!(e.to_string().contains("infinite horizon"), "{e}");
    // Corner radius 1/3 leaves the (1, 1) corridors open (2rc < 1/√2).
    let open = TwoRadiusSquare::new(Rational::from((1, 3)), Rational::from((1, 5))).unwrap();
    assert!(run_on(&open, &cfg, &scalar(1)).is_err());
    let simd = RunOptions {
        engine: Engine::Simd,
        ..scalar(1)
    };
    let e = run_on(&two_radius(), &cfg, &simd).unwrap_err();
    assert!(
        matches!(
            e,
            Error::OutOfRange {
                parameter: "engine",
                ..
            }
        ),
        "{e}"
    );
    let mpfr = SceneDiffusionConfig {
        precision: Precision::Bits(128),
        ..cfg.clone()
    };
    let audited = RunOptions {
        audit: Some(AuditSpec::new(1e-3, 256).unwrap()),
        ..scalar(1)
    };
    assert!(run_on(&two_radius(), &mpfr, &audited).is_err());
    let short = SceneDiffusionConfig {
        collisions: 1000,
        ..cfg
    };
    let e = run_on(&two_radius(), &short, &scalar(1)).unwrap_err();
    assert!(matches!(e, Error::TooFew { .. }), "{e}");
}

#[test]
fn a_checkpoint_resumes_to_the_same_bits_and_refuses_another_scene() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scene.ckpt");
    let cfg = SceneDiffusionConfig {
        collisions: 800_000,
        batches: 4,
        seed: 5,
        ..SceneDiffusionConfig::default()
    };
    let plain = run_on(&two_radius(), &cfg, &scalar(2)).unwrap();
    let kept = RunOptions {
        resume: Some(path.clone()),
        ..scalar(2)
    };
    let first = run_on(&two_radius(), &cfg, &kept).unwrap();
    assert_eq!(first.D.to_bits(), plain.D.to_bits());
    let resumed = run_on(&two_radius(), &cfg, &kept).unwrap();
    assert_eq!(resumed.resumed_batches, 4);
    assert_eq!(resumed.D.to_bits(), plain.D.to_bits());
    let other = TwoRadiusSquare::new(Rational::from((2, 5)), Rational::from((3, 20))).unwrap();
    let e = run_on(&other, &cfg, &kept).unwrap_err();
    assert!(e.to_string().contains("scene"), "{e}");
}

/// The table file `examples/tables/two-radius-square.toml` is the hand-written scene of
/// `examples/custom_scene.rs` as data: the same cell, edges and disks (in another order), so the
/// same starts and the same events bit for bit at `f64` and at 96 bits, and the same horizon. (D
/// itself differs in its last bits: the closed forms of the time unit are rounded in another
/// order.)
#[test]
fn the_two_radius_table_file_flies_the_hand_written_scenes_orbits_bit_for_bit() {
    use lorentz_gas::numbers::real::Real;
    use lorentz_gas::scenes::Scene;
    use lorentz_gas::scenes::lattice::{Lattice, LatticeState};
    use lorentz_gas::scenes::table::PeriodicTable;
    use lorentz_gas::scenes::table::spec::TableSpec;
    use rand::SeedableRng;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/tables/two-radius-square.toml");
    let table = PeriodicTable::new(&TableSpec::read(&path).unwrap()).unwrap();
    let hand = two_radius();
    assert_eq!(table.finite_horizon(), hand.finite_horizon());
    let (a, b) = (table.mean_free_path(), hand.mean_free_path());
    assert!((a - b).abs() <= 4.0 * f64::EPSILON * b, "{a} {b}");
    fn orbit<T: Real, S: Scene>(scene: &S, ctx: T::Ctx, seed: u64, n: usize) -> Vec<[f64; 4]> {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
        let lat = Lattice::from_kernel(scene.kernel::<T>(ctx).unwrap());
        let mut s = LatticeState::<T>::convert_from_f64(ctx, &scene.sample(&mut rng));
        (0..n)
            .map(|_| {
                lat.step(&mut s).unwrap();
                let p = lat.world(&s);
                [
                    p.x.to_f64(),
                    p.y.to_f64(),
                    s.flight.vel.x.to_f64(),
                    s.flight.vel.y.to_f64(),
                ]
            })
            .collect()
    }
    for seed in 0..8 {
        let (x, y) = (
            orbit::<f64, _>(&table, (), seed, 20_000),
            orbit::<f64, _>(&hand, (), seed, 20_000),
        );
        assert!(
            x.iter()
                .zip(&y)
                .all(|(p, q)| p.map(f64::to_bits) == q.map(f64::to_bits)),
            "seed {seed}"
        );
        let (x, y) = (
            orbit::<rug::Float, _>(&table, 96, seed, 2_000),
            orbit::<rug::Float, _>(&hand, 96, seed, 2_000),
        );
        assert!(
            x.iter()
                .zip(&y)
                .all(|(p, q)| p.map(f64::to_bits) == q.map(f64::to_bits)),
            "seed {seed} at 96 bits"
        );
    }
    // A run's batches agree to the rounding of its time unit.
    let cfg = SceneDiffusionConfig {
        collisions: 400_000,
        batches: 4,
        seed: 11,
        ..SceneDiffusionConfig::default()
    };
    let (ra, rb) = (
        run_on(&table, &cfg, &scalar(2)).unwrap(),
        run_on(&hand, &cfg, &scalar(1)).unwrap(),
    );
    for (x, y) in ra.batch_D.iter().zip(&rb.batch_D) {
        assert!((x - y).abs() <= 1e-12 * y.abs(), "{x} {y}");
    }
}
