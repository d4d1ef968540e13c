//! The sweep: resumable without redoing finished points, bit-identical on resume; writes its data
//! and figures; errors of the size its collisions warrant; the Machta–Zwanzig crossing with an
//! error bar that covers the true crossing as often as it should.

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::diffusion::{DiffusionConfig, run};
use lorentz_gas::estimators::sweep::analysis::mz_crossing;
use lorentz_gas::estimators::sweep::{self, SweepConfig, SweepRow};
use lorentz_gas::report::figures::sweep::write_sweep_figures;
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};
use statrs::distribution::{ContinuousCDF, FisherSnedecor};

/// Two-sided tail probability of 4σ of a normal: the "4σ" of every bound in this file.
const P_4_SIGMA: f64 = 6.334e-5;

/// The sweep as `lorentz sweep --out dir` runs it: points kept in `dir`, tables and figures
/// written there.
fn sweep_into(cfg: &SweepConfig, dir: &std::path::Path, threads: usize) -> sweep::SweepReport {
    let opts = RunOptions {
        threads,
        resume: Some(dir.to_path_buf()),
        ..RunOptions::default()
    };
    let r = sweep::run(cfg, &opts).unwrap();
    sweep::write_tables(&r, dir).unwrap();
    write_sweep_figures(&r, dir).unwrap();
    r
}

#[test]
fn an_interrupted_sweep_resumes_without_redoing_points() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let _ = std::fs::remove_dir_all(&dir);
    let cfg = SweepConfig {
        grid: lorentz_gas::estimators::sweep::Grid::Gaps(lorentz_gas::estimators::sweep::GapGrid {
            w_from: "0.08".into(),
            w_to: "0.16".into(),
            steps: 3,
            runs: 2,
        }),
        collisions: 3_000_000,
        batches: 4,
        seed: 9,
    };
    let first = sweep_into(&cfg, &dir, 2);
    assert_eq!(first.resumed_points, 0);
    assert_eq!(
        first.rows[1].w, 0.12,
        "the grid point is the decimal asked for"
    );
    for f in [
        "sweep.csv",
        "sweep-runs.csv",
        "sweep.json",
        "fig2-D-vs-w.png",
        "fig2-D-vs-w.svg",
        "fig7-boltzmann.png",
        "fig8-residuals.svg",
    ] {
        assert!(dir.join(f).metadata().unwrap().len() > 100, "{f}");
    }
    let csv = std::fs::read_to_string(dir.join("sweep.csv")).unwrap();
    assert!(csv.contains("\n0.12,"));
    // The CSV's columns are the keys of the JSON's rows, and no field holds a list.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("sweep.json")).unwrap()).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    for k in &header {
        assert!(
            json["rows"][0].get(*k).is_some(),
            "column {k} is not a row key"
        );
    }
    assert!(csv.lines().all(|l| !l.contains(' ')), "{csv}");
    let runs = std::fs::read_to_string(dir.join("sweep-runs.csv")).unwrap();
    assert_eq!(runs.lines().next(), Some("w,run,run_D"));
    assert_eq!(
        runs.lines().count(),
        1 + first.rows.len() * cfg.runs() as usize
    );
    // "Interrupt": lose the last point; the rerun redoes only that one and gives the same bits.
    std::fs::remove_file(dir.join("points").join("point-0002.json")).unwrap();
    let second = sweep_into(&cfg, &dir, 1);
    assert_eq!(second.resumed_points, 2);
    for (a, b) in first.rows.iter().zip(&second.rows) {
        assert_eq!(a.D.to_bits(), b.D.to_bits());
        assert_eq!(a.D_err.to_bits(), b.D_err.to_bits());
    }
    // The error of a two-run point is the size its collisions warrant. A single run with the same
    // total collisions and the same batch length (8 batches of 7.5·10⁵) has the same true error;
    // the ratio of the two squared error estimates (6 and 7 degrees of freedom) is F(6, 7)
    // distributed. The old estimator (the spread of two run values) fails this by 30–100×.
    let row = &first.rows[1];
    assert_eq!(row.D_err_dof, 2 * 3);
    // By definition it combines the batch errors of the point's two runs (runs 2 and 3 of seed 9:
    // point 1, two runs per point), not the spread of their two values.
    let runs: Vec<_> = (2..4)
        .map(|r| {
            let mut c = DiffusionConfig::new(0.12);
            c.collisions = cfg.collisions;
            c.batches = cfg.batches;
            c.seed = cfg.seed;
            c.run = r;
            run(&c, &crate::common::threads(2)).unwrap()
        })
        .collect();
    assert_eq!(row.run_D, vec![runs[0].D, runs[1].D]);
    let within = (runs[0].D_err.powi(2) + runs[1].D_err.powi(2)).sqrt() / 2.0;
    assert_eq!(row.D_err, within);
    let mut single = DiffusionConfig::new(0.12);
    single.collisions = 6_000_000;
    single.batches = 8;
    single.seed = 1234;
    let s = run(&single, &crate::common::threads(2)).unwrap();
    let f = FisherSnedecor::new(6.0, 7.0).unwrap();
    let (lo, hi) = (
        f.inverse_cdf(P_4_SIGMA / 2.0),
        f.inverse_cdf(1.0 - P_4_SIGMA / 2.0),
    );
    let ratio = (row.D_err / s.D_err).powi(2);
    assert!(ratio > lo && ratio < hi, "{ratio} not in [{lo}, {hi}]");
    // A different sweep refuses the directory.
    let other = SweepConfig { seed: 10, ..cfg };
    let opts = RunOptions {
        threads: 2,
        resume: Some(dir.clone()),
        ..RunOptions::default()
    };
    assert!(sweep::run(&other, &opts).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

fn synthetic_rows(
    ws: &[f64],
    sigma: &[f64],
    truth: &dyn Fn(f64) -> f64,
    rng: &mut impl Rng,
) -> Vec<SweepRow> {
    ws.iter()
        .zip(sigma)
        .map(|(&w, &s)| {
            let noise: f64 = StandardNormal.sample(rng);
            SweepRow {
                w,
                inv_n: 0.0,
                D: truth(w) + s * noise,
                D_err: s,
                D_err_dof: 1000,
                runs_f: f64::NAN,
                runs_f_dof1: 0,
                runs_f_dof2: 1000,
                runs_p_value: f64::NAN,
                D_MZ: 0.0,
                D_Bo: 0.0,
                residual: 0.0,
                run_D: Vec::new(),
                run_D_err: Vec::new(),
            }
        })
        .collect()
}

/// The crossing's error bar is honest: over many synthetic sweeps with Gaussian errors around a
/// curve through a known crossing — with the slope and curvature of the measured D − D_MZ
/// (0.2 and 1.5 near w = 0.117) and its errors — the pulls (w − w*)/err have mean 0 and standard
/// deviation 1 within their sampling errors (4σ: 4/√M for the mean, 4/√(2M) for the standard
/// deviation). (An interpolation between the two points at the sign change always lies between
/// them: that test could not fail; this one does when the propagated error is wrong, or when the
/// local form cannot follow the curvature.)
#[test]
fn mz_crossing_error_bar_covers_the_true_crossing() {
    let truth_w = 0.1178;
    let truth = |w: f64| 0.2 * (w - truth_w) + 1.5 * (w - truth_w).powi(2);
    let ws: Vec<f64> = (0..15).map(|i| 0.02 * (i + 1) as f64).collect();
    let sigma: Vec<f64> = ws.iter().map(|w| 1e-4 * (1.0 + 4.0 * w)).collect();
    let mut rng = lorentz_gas::scenes::sampling::stream(2024, 0);
    let m = 2000;
    let pulls: Vec<f64> = (0..m)
        .map(|_| {
            let rows = synthetic_rows(&ws, &sigma, &truth, &mut rng);
            let c = mz_crossing(&rows).unwrap().expect("a sign change");
            (c.w - truth_w) / c.err
        })
        .collect();
    let mean = pulls.iter().sum::<f64>() / m as f64;
    let sd = (pulls.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / (m - 1) as f64).sqrt();
    assert!(mean.abs() < 4.0 / (m as f64).sqrt(), "mean pull {mean}");
    assert!(
        (sd - 1.0).abs() < 4.0 / (2.0 * m as f64).sqrt(),
        "pull standard deviation {sd}"
    );
    // No sign change, no crossing.
    let rows = synthetic_rows(&ws, &sigma, &|_| 1.0, &mut rng);
    assert!(mz_crossing(&rows).unwrap().is_none());
}
