//! The MSD curve at the user's times (`--msd-grid 0,0.5,…`, `proofs-notes/msd-times.md`): from
//! t = 0 on, with MSD(0) = 0 exactly and the velocity autocorrelation ½ per component at 0; it
//! leaves D's bits alone, is the same on every engine, follows the exact short-time curve below
//! the gap w and gives the Einstein D by Green–Kubo.

use lorentz_gas::engine::Engine;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::diffusion::curve::MsdCurveReport;
use lorentz_gas::estimators::diffusion::{DiffusionConfig, DiffusionReport, MsdGrid, run};
use lorentz_gas::scenes::triangular::geometry::Geometry;

use crate::common::t4;

fn run_on(cfg: &DiffusionConfig, engine: Engine) -> DiffusionReport {
    let options = RunOptions {
        engine,
        ..crate::common::threads(2)
    };
    run(cfg, &options).unwrap()
}

fn curve(r: &DiffusionReport) -> &MsdCurveReport {
    r.msd_curve
        .as_ref()
        .expect("a run on the user's times reports its curve")
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// The times: 0, short ones inside the first flight (two below the gap w = 0.1), a few mean free
/// times, and eight in the fit window [10τ, 40τ].
fn times(w: f64) -> Vec<f64> {
    let g = Geometry::new(w).unwrap();
    let (ell, tau) = (g.mean_free_path(), g.hop_time());
    let mut t = vec![0.0, 0.03, 0.07, ell / 2.0, ell, 2.0 * ell, 5.0 * ell];
    t.extend((0..8).map(|k| tau * (10.0 + 30.0 * k as f64 / 7.0)));
    t
}

/// At t = 0 the MSD and the Green–Kubo integral are 0 exactly, the VACF is 1 (speed 1) and each
/// component ⟨v_x(0)²⟩, ⟨v_y(0)²⟩ is ½ within the Student-t 4σ equivalent of its error (16
/// batches); below the gap w the curve is the exact MSD = t²(1 − 4t/9ℓ),
/// C = 1 − 4t/3ℓ within that bound; D by Green–Kubo over the fit window agrees with the Einstein
/// D, paired, within it; D has the bits of the run on the fit grid. Broken on purpose (the x
/// component summed as v_x(0)v_y(t)), C_x(0) is 0 ± 0.0003 and the test fails.
#[test]
fn the_msd_starts_at_zero_and_the_vacf_at_one_half_per_component() {
    let w = 0.1;
    let cfg = DiffusionConfig {
        collisions: 8_000_000,
        batches: 16,
        msd_grid: MsdGrid::Times(times(w)),
        ..DiffusionConfig::new(w)
    };
    let r = run_on(&cfg, Engine::Auto);
    let (c, ell, k4) = (curve(&r), r.mean_free_path_exact, t4(16));
    assert_eq!(c.times, times(w));
    assert_eq!((c.msd[0], c.msd_err[0], c.green_kubo[0]), (0.0, 0.0, 0.0));
    assert!((c.vacf[0] - 1.0).abs() < 1e-14, "C(0) = {}", c.vacf[0]);
    for (name, v, e) in [
        ("x", &c.vacf_x, &c.vacf_x_err),
        ("y", &c.vacf_y, &c.vacf_y_err),
    ] {
        assert!(
            (v[0] - 0.5).abs() <= k4 * e[0] && e[0] > 0.0 && e[0] < 1e-3,
            "C_{name}(0) = {} ± {}",
            v[0],
            e[0]
        );
    }
    for k in 1..3 {
        let t = c.times[k];
        assert!(t < w);
        crate::common::short_time_curve(
            (t, t / ell, k4),
            (c.msd[k], c.msd_err[k]),
            (c.vacf[k], c.vacf_err[k]),
        );
    }
    let g = &r.green_kubo;
    let (diff, err) = (
        g.D_minus_D_green_kubo.unwrap(),
        g.D_minus_D_green_kubo_err.unwrap(),
    );
    assert!(diff.abs() <= k4 * err, "D - D_GK = {diff} ± {err}");
    let fit = run_on(
        &DiffusionConfig {
            msd_grid: MsdGrid::Fit,
            ..cfg.clone()
        },
        Engine::Auto,
    );
    assert_eq!(bits(&r.batch_D), bits(&fit.batch_D));
}

/// The curve at the user's times has the same bits on the scalar and the SIMD engine, and on a
/// `log:FROM,TO,PER_OCTAVE` grid it starts at 0 with its times as asked.
#[test]
fn the_user_grid_is_the_same_on_every_engine() {
    let cfg = DiffusionConfig {
        collisions: 2_000_000,
        batches: 4,
        msd_grid: "log:0.05,200,3".parse().unwrap(),
        ..DiffusionConfig::new(0.2)
    };
    let (a, b) = (run_on(&cfg, Engine::Scalar), run_on(&cfg, Engine::Auto));
    let (a, b) = (curve(&a), curve(&b));
    assert_eq!(a.times[..2], [0.0, 0.05]);
    assert_eq!(a.times.len(), 1 + 36);
    assert_eq!(bits(&a.msd), bits(&b.msd));
    assert_eq!(bits(&a.vacf_x), bits(&b.vacf_x));
    assert_eq!(bits(&a.green_kubo), bits(&b.green_kubo));
}

/// A grid beyond a hundredth of a batch's trajectory is refused, naming the longest time allowed.
#[test]
fn a_grid_longer_than_the_run_allows_is_refused() {
    let cfg = DiffusionConfig {
        collisions: 2_000_000,
        batches: 4,
        msd_grid: MsdGrid::Times(vec![0.0, 1e6]),
        ..DiffusionConfig::new(0.2)
    };
    let e = cfg.validate().unwrap_err().to_string();
    assert!(
        e.contains("msd_grid") && e.contains("times from 0 to"),
        "{e}"
    );
}
