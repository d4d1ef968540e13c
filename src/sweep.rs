//! D over a range of w: independent runs per point, resumable, with the paper's coarse- and
//! fine-scale analyses (Figs. 2, 7, 8): D against D_MZ and the measured crossing D = D_MZ; the
//! Boltzmann form D_Bo − ΔD = (3/16)(1/n − π) − ΔD fitted against 1/n (ΔD with the slope fixed
//! at 3/16, and the free slope); residuals of D from a straight line in w, with error bars.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::diffusion::{run, DiffusionConfig, Precision};
use crate::error::Error;
use crate::figures::{plot, PlotSpec, Series};
use crate::geometry::Geometry;
use crate::stats::{linear_fit, mean_se};

/// What defines a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepConfig {
    /// First w.
    pub w_from: f64,
    /// Last w.
    pub w_to: f64,
    /// Number of points (≥ 2).
    pub steps: u32,
    /// Independent runs per point.
    pub runs: u32,
    /// Collisions per run.
    pub collisions: u64,
    /// Batches per run.
    pub batches: u32,
    /// Base seed (run r of point i uses seed + 1000·i + r).
    pub seed: u64,
}

/// One finished point (the unit of resumption).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SweepPoint {
    /// Configuration the point belongs to.
    pub config: SweepConfig,
    /// Gap.
    pub w: f64,
    /// D and its error for each run.
    pub runs: Vec<(f64, f64)>,
}

/// The analysis of a finished sweep.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize)]
pub struct SweepReport {
    /// The configuration.
    pub config: SweepConfig,
    /// Rows: w, 1/n, D (mean over runs), its standard error, D_MZ, D_Bo, residual from the linear fit.
    pub rows: Vec<SweepRow>,
    /// Straight line D = c₀ + c₁ w over the range (for the residuals).
    pub linear_fit: (f64, f64),
    /// Boltzmann offset ΔD with the slope fixed at 3/16 (equal-weight least squares over the sweep's
    /// range), and the standard error of that mean.
    pub boltzmann_offset: (f64, f64),
    /// Free least-squares slope of D against 1/n (compare with 3/16 = 0.1875) and intercept.
    pub boltzmann_free_fit: (f64, f64),
    /// w where D − D_MZ changes sign (linear interpolation), if inside the range, with its error.
    pub mz_crossing: Option<(f64, f64)>,
    /// Points reused from earlier runs of the same sweep.
    pub resumed_points: u32,
    /// Crate version.
    pub version: String,
}

/// One row of the sweep.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize)]
pub struct SweepRow {
    /// Gap.
    pub w: f64,
    /// Inverse density 1/n = √3a²/2.
    pub inv_n: f64,
    /// Mean D over runs.
    pub D: f64,
    /// Standard error over runs.
    pub D_err: f64,
    /// Machta–Zwanzig.
    pub D_MZ: f64,
    /// Boltzmann.
    pub D_Bo: f64,
    /// D minus the straight-line fit.
    pub residual: f64,
    /// Each run's D.
    pub run_D: Vec<f64>,
}

impl SweepConfig {
    fn points(&self) -> Vec<f64> {
        (0..self.steps)
            .map(|i| self.w_from + (self.w_to - self.w_from) * i as f64 / (self.steps - 1) as f64)
            .collect()
    }
    fn validate(&self) -> Result<(), Error> {
        if self.steps < 2 || self.runs < 2 {
            return Err(Error::Invalid(
                "a sweep needs --steps >= 2 and --runs >= 2 (the error bar is over runs)".into(),
            ));
        }
        for w in self.points() {
            let mut c = DiffusionConfig::new(w);
            c.collisions = self.collisions;
            c.batches = self.batches;
            c.validate()?;
        }
        Ok(())
    }
}

fn point_path(dir: &Path, i: usize) -> PathBuf {
    dir.join("points").join(format!("point-{i:04}.json"))
}

/// Runs (or resumes) the sweep, writing `points/` as each point finishes, then `sweep.csv`,
/// `sweep.json` and the figures into `dir`. `progress` receives collision counts.
pub fn sweep(
    cfg: &SweepConfig,
    dir: &Path,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<SweepReport, Error> {
    cfg.validate()?;
    std::fs::create_dir_all(dir.join("points"))?;
    let mut points = Vec::new();
    let mut resumed = 0;
    for (i, w) in cfg.points().into_iter().enumerate() {
        let path = point_path(dir, i);
        if let Ok(text) = std::fs::read_to_string(&path) {
            if let Ok(p) = serde_json::from_str::<SweepPoint>(&text) {
                if p.config == *cfg && p.w == w {
                    progress(cfg.collisions * cfg.runs as u64);
                    points.push(p);
                    resumed += 1;
                    continue;
                }
            }
            return Err(Error::Invalid(format!(
                "{} belongs to another sweep: use another --out",
                path.display()
            )));
        }
        let mut runs = Vec::new();
        for r in 0..cfg.runs {
            let mut c = DiffusionConfig::new(w);
            c.collisions = cfg.collisions;
            c.batches = cfg.batches;
            c.seed = cfg.seed + 1000 * i as u64 + r as u64;
            c.precision = Precision::F64;
            let rep = run(&c, threads, None, progress)?;
            runs.push((rep.D, rep.D_err));
        }
        let p = SweepPoint {
            config: cfg.clone(),
            w,
            runs,
        };
        // Write-then-rename: an interruption never leaves a half-written point.
        let tmp = path.with_extension("tmp");
        std::fs::write(
            &tmp,
            serde_json::to_string(&p).map_err(|e| Error::Io(e.to_string()))?,
        )?;
        std::fs::rename(&tmp, &path)?;
        points.push(p);
    }
    let report = analyse(cfg, &points, resumed)?;
    write_outputs(&report, dir)?;
    Ok(report)
}

fn analyse(cfg: &SweepConfig, points: &[SweepPoint], resumed: u32) -> Result<SweepReport, Error> {
    let mut rows = Vec::new();
    for p in points {
        let g = Geometry::new(p.w)?;
        let ds: Vec<f64> = p.runs.iter().map(|r| r.0).collect();
        let (d, e) = mean_se(&ds);
        rows.push(SweepRow {
            w: p.w,
            inv_n: 1.0 / g.density(),
            D: d,
            D_err: e,
            D_MZ: g.d_mz(),
            D_Bo: g.d_bo(),
            residual: 0.0,
            run_D: ds,
        });
    }
    let ws: Vec<f64> = rows.iter().map(|r| r.w).collect();
    let ds: Vec<f64> = rows.iter().map(|r| r.D).collect();
    let lin = linear_fit(&ws, &ds);
    for r in &mut rows {
        r.residual = r.D - (lin.0 + lin.1 * r.w);
    }
    // Boltzmann with slope 3/16: the one-parameter least-squares fit of D = D_Bo − ΔD with equal
    // weights (the form is not exact, so 1/σ² weights would let the best-measured points decide):
    // ΔD = mean of (D_Bo − D), error the standard error of that mean.
    let (off, off_err) = mean_se(&rows.iter().map(|r| r.D_Bo - r.D).collect::<Vec<_>>());
    let free = linear_fit(&rows.iter().map(|r| r.inv_n).collect::<Vec<_>>(), &ds);
    let mut crossing = None;
    for pair in rows.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        let (fa, fb) = (a.D - a.D_MZ, b.D - b.D_MZ);
        if fa.signum() != fb.signum() {
            let x = a.w + (b.w - a.w) * fa / (fa - fb);
            // Error by propagation of the two D errors through the interpolation.
            let dxdfa = (b.w - a.w) * (-fb) / (fa - fb).powi(2);
            let dxdfb = (b.w - a.w) * fa / (fa - fb).powi(2);
            crossing = Some((
                x,
                ((dxdfa * a.D_err).powi(2) + (dxdfb * b.D_err).powi(2)).sqrt(),
            ));
        }
    }
    Ok(SweepReport {
        config: cfg.clone(),
        rows,
        linear_fit: lin,
        boltzmann_offset: (off, off_err),
        boltzmann_free_fit: (free.1, free.0),
        mz_crossing: crossing,
        resumed_points: resumed,
        version: env!("CARGO_PKG_VERSION").into(),
    })
}

fn write_outputs(r: &SweepReport, dir: &Path) -> Result<(), Error> {
    let mut csv = String::from("w,inv_n,D,D_err,D_MZ,D_Bo,residual,runs\n");
    for row in &r.rows {
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},{}\n",
            row.w,
            row.inv_n,
            row.D,
            row.D_err,
            row.D_MZ,
            row.D_Bo,
            row.residual,
            row.run_D
                .iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        ));
    }
    std::fs::write(dir.join("sweep.csv"), csv)?;
    std::fs::write(
        dir.join("sweep.json"),
        serde_json::to_string_pretty(r).map_err(|e| Error::Io(e.to_string()))?,
    )?;
    let pts = |f: &dyn Fn(&SweepRow) -> (f64, f64, f64)| r.rows.iter().map(f).collect::<Vec<_>>();
    let s = |label: &str, points| Series {
        label: label.into(),
        points,
        notes: Vec::new(),
        line: true,
    };
    plot(
        &dir.join("fig2-D-vs-w"),
        &PlotSpec {
            title: "Diffusion coefficient D(w) (paper Fig. 2)",
            x_label: "gap w",
            y_label: "D",
            log_x: false,
            log_y: false,
        },
        &[
            s("D (Einstein, this crate)", pts(&|x| (x.w, x.D, x.D_err))),
            s("Machta-Zwanzig D_MZ", pts(&|x| (x.w, x.D_MZ, 0.0))),
        ],
    )?;
    let (off, _) = r.boltzmann_offset;
    plot(
        &dir.join("fig7-boltzmann"),
        &PlotSpec {
            title: &format!("D against 1/n (paper Fig. 7); D_Bo - {off:.4}"),
            x_label: "1/n",
            y_label: "D",
            log_x: false,
            log_y: false,
        },
        &[
            s("D", pts(&|x| (x.inv_n, x.D, x.D_err))),
            s(
                &format!("Boltzmann (3/16)(1/n - pi) - {off:.4}"),
                pts(&|x| (x.inv_n, x.D_Bo - off, 0.0)),
            ),
            s("Machta-Zwanzig", pts(&|x| (x.inv_n, x.D_MZ, 0.0))),
        ],
    )?;
    let mut runs = Vec::new();
    for row in &r.rows {
        for d in &row.run_D {
            runs.push((row.w, d - (r.linear_fit.0 + r.linear_fit.1 * row.w), 0.0));
        }
    }
    plot(
        &dir.join("fig8-residuals"),
        &PlotSpec {
            title: "Residuals of D from a linear fit in w (paper Fig. 8)",
            x_label: "gap w",
            y_label: "D - linear fit",
            log_x: false,
            log_y: false,
        },
        &[
            s(
                "mean over runs (error bar: SE)",
                pts(&|x| (x.w, x.residual, x.D_err)),
            ),
            Series {
                label: "single runs".into(),
                points: runs,
                notes: Vec::new(),
                line: false,
            },
        ],
    )?;
    Ok(())
}
