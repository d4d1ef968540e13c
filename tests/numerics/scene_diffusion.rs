//! D on any scene (`estimators::diffusion::scene::run_on`): on the triangular scene it gives the
//! bits of `diffusion::run` on the scalar engine, at `f64` and at an MPFR precision; on a table
//! the crate does not ship (the two-radius square of `examples/tables/`, given as data) its exact
//! identities hold within their Student-t bounds and its audited events stay inside the error
//! model; infinite horizons, the SIMD engine on the trap's fused kernel and MPFR audits are
//! refused; a checkpoint resumes to the uninterrupted bits and refuses another scene's.

use lorentz_gas::Error;
use lorentz_gas::engine::Engine;
use lorentz_gas::engine::options::{AuditSpec, RunOptions};
use lorentz_gas::estimators::diffusion::Sampling;
use lorentz_gas::estimators::diffusion::scene::run_on;
use lorentz_gas::estimators::diffusion::{self, DiffusionConfig};
use lorentz_gas::numbers::precision::Precision;
use lorentz_gas::scenes::square::SquareScene;
use lorentz_gas::scenes::triangular::TriangularScene;
use rug::Rational;

use lorentz_gas::scenes::table::PeriodicTable;
use lorentz_gas::scenes::table::spec::TableSpec;

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
        table: lorentz_gas::scenes::spec::Table::triangular(w).unwrap(),
        collisions,
        batches: 4,
        seed: 3,
        precision,
        ..DiffusionConfig::new(w64)
    };
    let general = Sampling {
        collisions,
        batches: 4,
        seed: 3,
        run: 0,
        precision,
        window: tri.window,
        check_window: tri.check_window,
        msd_grid: tri.msd_grid.clone(),
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

/// The unit square lattice with disks of radius `rc` at the corners and `rm` at the centres.
fn two_radii(rc: &str, rm: &str) -> PeriodicTable {
    let text = format!(
        "[lattice]\ne1 = [1, 0]\ne2 = [0, 1]\n[[disks]]\ncentre = [0, 0]\nradius = \"{rc}\"\n\
         [[disks]]\ncentre = [\"1/2\", \"1/2\"]\nradius = \"{rm}\"\n"
    );
    PeriodicTable::new(&TableSpec::from_toml(&text).unwrap()).unwrap()
}

/// The two-radius square of `examples/tables/two-radius-square.toml`.
pub(super) fn two_radius() -> PeriodicTable {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/tables/two-radius-square.toml"
    );
    PeriodicTable::new(&TableSpec::read(path.as_ref()).unwrap()).unwrap()
}

#[test]
fn a_table_the_crate_does_not_ship_meets_its_identities_and_its_error_model() {
    let cfg = Sampling {
        collisions: 4_000_000,
        batches: 8,
        seed: 11,
        ..Sampling::default()
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
    let cfg = Sampling {
        collisions: 1_000_000,
        batches: 4,
        ..Sampling::default()
    };
    let square = SquareScene::new(0.25).unwrap();
    let e = run_on(&square, &cfg, &scalar(1)).unwrap_err();
    assert!(e.to_string().contains("lacks a finite horizon"), "{e}");
    // Corner radius 1/3 leaves the (1, 1) corridors open (2rc < 1/√2).
    let open = two_radii("1/3", "1/5");
    assert!(run_on(&open, &cfg, &scalar(1)).is_err());
    let simd = RunOptions {
        engine: Engine::Simd,
        ..scalar(1)
    };
    // The SIMD engine runs a table's generic kernel (`cell_engine.rs`), not the trap's fused one
    // through a scene.
    let triangular = TriangularScene::new(0.1).unwrap();
    let e = run_on(&triangular, &cfg, &simd).unwrap_err();
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
    let mpfr = Sampling {
        precision: Precision::Bits(128),
        ..cfg.clone()
    };
    let audited = RunOptions {
        audit: Some(AuditSpec::new(1e-3, 256).unwrap()),
        ..scalar(1)
    };
    assert!(run_on(&two_radius(), &mpfr, &audited).is_err());
    let short = Sampling {
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
    let cfg = Sampling {
        collisions: 800_000,
        batches: 4,
        seed: 5,
        ..Sampling::default()
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
    let other = two_radii("2/5", "3/20");
    let e = run_on(&other, &cfg, &kept).unwrap_err();
    assert!(e.to_string().contains("scene"), "{e}");
}
