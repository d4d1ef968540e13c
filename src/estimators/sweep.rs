//! D over a range of w: independent runs per point, resumable, with the paper's coarse- and
//! fine-scale analyses (Figs. 2, 7, 8): D against D_MZ and the measured crossing D = D_MZ; the
//! Boltzmann form D_Bo − ΔD = (3/16)(1/n − π) − ΔD fitted against 1/n (ΔD with the slope fixed
//! at 3/16, and the free slope); residuals of D from a straight line in w, with error bars.
//!
//! Errors: a point's error comes from the batch errors inside its runs (R runs of B batches:
//! R(B − 1) degrees of freedom), never from the spread of a handful of run values; that spread is
//! reported as a χ² consistency check. The fits downstream are weighted by these errors and report
//! χ²/dof (`proofs-notes/sweep-errors.md`).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::Engine;
use crate::estimators::diffusion::{run_many, DiffusionConfig};
use crate::numbers::exact::decimal_grid;
use crate::numbers::precision::Precision;
use crate::scenes::triangular::geometry::Geometry;
use crate::statistics::{
    f_p_value, weighted_line_fit, weighted_mean, weighted_polynomial_chi2, weighted_quadratic_fit,
    LineFit, WeightedMean,
};
use crate::Error;

/// What defines a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepConfig {
    /// First w, as the decimal typed (the grid is computed exactly: [`crate::numbers::exact`]).
    pub w_from: String,
    /// Last w, as typed.
    pub w_to: String,
    /// Number of points (≥ 2).
    pub steps: u32,
    /// Independent runs per point (≥ 1; with ≥ 2 their spread is checked against their errors).
    pub runs: u32,
    /// Collisions per run.
    pub collisions: u64,
    /// Batches per run (≥ 2): the error bar of a run is the standard error over its batches.
    pub batches: u32,
    /// Seed: run r of point i uses the streams of run i·runs + r of this seed.
    pub seed: u64,
}

/// One run of one point.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RunValue {
    /// D of the run (mean over its batches).
    pub D: f64,
    /// Its standard error over the run's batches.
    pub D_err: f64,
}

/// Most points of a sweep: each point is at least two diffusion runs, so 10⁴ points is already far
/// beyond a campaign; more is a typo, refused before the grid is allocated.
pub const MAX_SWEEP_POINTS: u32 = 10_000;

/// Part `index` of `count` of a sweep's points: point i belongs to part i mod `count` (parts
/// 0 … count − 1, as Slurm numbers the tasks of `--array=0-(count−1)`). Round-robin, so every
/// part spans the whole w range and the parts take about equal time (the cost per collision
/// varies with w). A part's points are the same bits as those points of the whole sweep: a point
/// depends only on the configuration and its index.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which part, 0 … count − 1.
    pub index: u32,
    /// Into how many parts the points are dealt.
    pub count: u32,
}

impl Shard {
    /// Parses `I/N` (0 ≤ I < N), as in `--shard 3/8`.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::estimators::sweep::Shard;
    /// let s = Shard::parse("1/4").unwrap();
    /// assert_eq!((s.index, s.count), (1, 4));
    /// assert!(s.owns(5) && !s.owns(4));
    /// assert!(Shard::parse("4/4").is_err());
    /// ```
    pub fn parse(text: &str) -> Result<Shard, Error> {
        let bad = || {
            Error::Invalid(format!(
                "shard = {text:?}: expected I/N with N from 1 to {MAX_SWEEP_POINTS} and I from 0 to N-1 (Slurm: --shard $SLURM_ARRAY_TASK_ID/N with --array=0-(N-1))"
            ))
        };
        let (i, n) = text.trim().split_once('/').ok_or_else(bad)?;
        let index: u32 = i.trim().parse().map_err(|_| bad())?;
        let count: u32 = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || count > MAX_SWEEP_POINTS || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// Whether point `i` belongs to this part.
    pub fn owns(&self, i: u32) -> bool {
        i % self.count == self.index
    }

    /// Checks that every part of `cfg`'s points gets at least one point.
    pub fn validate(&self, cfg: &SweepConfig) -> Result<(), Error> {
        if self.count > cfg.steps || self.index >= self.count {
            return Err(Error::Invalid(format!(
                "shard = {}/{}: a sweep of {} points has parts 0 to N-1 with N from 1 to {} (every part needs a point)",
                self.index, self.count, cfg.steps, cfg.steps
            )));
        }
        Ok(())
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// What one part of a sharded sweep leaves in its directory (`shard.json`, next to `points/`):
/// the part's identity for [`merge`].
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ShardReport {
    /// The whole sweep's configuration.
    pub config: SweepConfig,
    /// Which part.
    pub shard: Shard,
    /// Indices of the part's points, all finished.
    pub points: Vec<u32>,
    /// Of them, reused from an earlier, interrupted run of the part.
    pub resumed_points: u32,
    /// Version, seed, engine, threads, command line of this part's process.
    pub meta: RunMeta,
}

/// One finished point (the unit of resumption).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SweepPoint {
    /// Configuration the point belongs to.
    pub config: SweepConfig,
    /// Index of the point in the grid.
    pub index: u32,
    /// Gap.
    pub w: f64,
    /// Each run's D and error.
    pub runs: Vec<RunValue>,
}

/// The analysis of a finished sweep.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize)]
pub struct SweepReport {
    /// The configuration.
    pub config: SweepConfig,
    /// One row per point.
    pub rows: Vec<SweepRow>,
    /// Weighted straight line D = c₀ + c₁w over the range (the residuals of Fig. 8 are from it);
    /// its χ²/dof measures structure beyond a straight line.
    pub linear_fit: LineFit,
    /// χ² and degrees of freedom of weighted polynomials of degree 1 … 7 (as far as the points
    /// allow): structure that no low-degree polynomial absorbs within the errors is fine structure,
    /// not curvature.
    #[serde(default)]
    pub polynomial_chi2: Vec<PolynomialChi2>,
    /// Boltzmann offset ΔD in D = D_Bo − ΔD with the slope fixed at 3/16: the weighted mean of
    /// D_Bo − D, with χ² of the points about it.
    pub boltzmann_offset: WeightedMean,
    /// ΔD's error scaled by √(χ²/dof) when χ²/dof > 1 (the form is not exact over the range; the
    /// scatter, not the statistical errors, then sets the uncertainty).
    pub boltzmann_offset_err_scaled: f64,
    /// Weighted straight line D = c₀ + c₁(1/n) (compare c₁ with 3/16 = 0.1875).
    pub boltzmann_free_fit: LineFit,
    /// Where D − D_MZ changes sign, from a weighted straight line through the points around the
    /// sign change, if the sign changes in the range.
    pub mz_crossing: Option<Crossing>,
    /// Points reused from earlier runs of the same sweep.
    pub resumed_points: u32,
    /// Version, seed, runs, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// The χ² of one weighted polynomial fit of D(w).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PolynomialChi2 {
    /// Degree.
    pub degree: usize,
    /// χ².
    pub chi2: f64,
    /// Degrees of freedom (points − degree − 1).
    pub dof: usize,
}

/// Highest polynomial degree tried in [`SweepReport::polynomial_chi2`].
pub const MAX_POLYNOMIAL_DEGREE: usize = 7;

/// A zero of D − D_MZ.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Crossing {
    /// w at the crossing.
    pub w: f64,
    /// Its standard error, propagated from the local fit's covariance.
    pub err: f64,
    /// The error scaled by √(χ²/dof) when χ²/dof > 1 (the local form does not describe the points
    /// within their errors; the scatter then sets the uncertainty).
    pub err_scaled: f64,
    /// χ² of the local fit.
    pub chi2: f64,
    /// Its degrees of freedom (points − parameters).
    pub dof: usize,
    /// Points used.
    pub points: usize,
}

/// Points on each side of the sign change used for the local fit of the crossing: a quadratic
/// through 3 + 3 points follows the curvature of D − D_MZ (a straight line through 2 + 2 points
/// of the 0.02-spaced paper grid is biased by it by several of its own errors) and leaves 3
/// degrees of freedom for its χ².
pub const CROSSING_POINTS_PER_SIDE: usize = 3;

/// One row of the sweep.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize)]
pub struct SweepRow {
    /// Gap.
    pub w: f64,
    /// Inverse density 1/n = √3a²/2.
    pub inv_n: f64,
    /// D: mean over runs (equal weights; every run has the same collisions).
    pub D: f64,
    /// Its standard error from the batch errors inside the runs: √(Σ_r σ_r²)/R.
    pub D_err: f64,
    /// Degrees of freedom of D_err: R·(B − 1).
    pub D_err_dof: u64,
    /// The consistency check of the runs: F = s²_between / mean_r σ̂_r², the variance of the run
    /// values over the mean of their squared batch errors. Every run has the same collisions and
    /// batches, so under "the runs agree within their errors" F is exactly F(R − 1, R(B − 1))
    /// distributed (NaN for one run).
    pub runs_f: f64,
    /// Its degrees of freedom (R − 1, R(B − 1)).
    pub runs_f_dof: (u32, u64),
    /// Probability of an F at least this large if the runs agree within their errors.
    pub runs_p_value: f64,
    /// Machta–Zwanzig.
    pub D_MZ: f64,
    /// Boltzmann.
    pub D_Bo: f64,
    /// D minus the weighted straight-line fit.
    pub residual: f64,
    /// Each run's D.
    pub run_D: Vec<f64>,
}

impl SweepConfig {
    /// The grid of w, exact decimals rounded once.
    pub fn points(&self) -> Result<Vec<f64>, Error> {
        decimal_grid(&self.w_from, &self.w_to, self.steps)
    }

    /// The diffusion run r of point i.
    pub fn run_config(&self, i: u32, w: f64, r: u32) -> DiffusionConfig {
        let mut c = DiffusionConfig::new(w);
        c.collisions = self.collisions;
        c.batches = self.batches;
        c.seed = self.seed;
        // u32·u32 + u32 < 2⁶⁴: cannot overflow, and distinct (i, r) give distinct runs.
        c.run = i as u64 * self.runs as u64 + r as u64;
        c.precision = Precision::F64;
        c
    }

    /// Checks every parameter before anything runs or is written.
    pub fn validate(&self) -> Result<(), Error> {
        if self.steps < 2 {
            return Err(Error::Invalid(format!(
                "steps = {}: a sweep needs at least 2 points",
                self.steps
            )));
        }
        if self.runs == 0 {
            return Err(Error::Zero { what: "runs" });
        }
        if self.steps > MAX_SWEEP_POINTS {
            return Err(Error::Invalid(format!(
                "steps = {} is too many: use 2 to {MAX_SWEEP_POINTS} points",
                self.steps
            )));
        }
        crate::engine::parallel::check_batches("runs", self.runs)?;
        for (i, w) in self.points()?.into_iter().enumerate() {
            self.run_config(i as u32, w, 0).validate()?;
        }
        Ok(())
    }
}

fn point_path(dir: &Path, i: usize) -> PathBuf {
    dir.join("points").join(format!("point-{i:04}.json"))
}

/// Runs (or resumes) the sweep, writing `points/` as each point finishes, then `sweep.csv`,
/// `sweep.json` and the figures into `dir`. `progress` receives collision counts. Nothing is
/// written before the configuration has been checked.
pub fn sweep(
    cfg: &SweepConfig,
    dir: &Path,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<SweepReport, Error> {
    sweep_on(cfg, dir, Engine::Auto, threads, progress)
}

/// As [`sweep`], on the engine `engine` (the same bits on every engine). A point's runs are
/// packed together ([`run_many`]), so that R runs of B batches fill R·B SIMD lanes.
pub fn sweep_on(
    cfg: &SweepConfig,
    dir: &Path,
    engine: Engine,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<SweepReport, Error> {
    cfg.validate()?;
    let resolved = engine.resolve(true)?;
    let (points, resumed) = run_points(cfg, dir, engine, threads, progress, |_| true)?;
    let mut report = analyse(cfg, &points, resumed, threads)?;
    report.meta = report.meta.with_engine(resolved);
    write_outputs(&report, dir)?;
    Ok(report)
}

/// Part `shard` of the sweep `cfg`: its points only (resumable, as [`sweep_on`]), written to
/// `dir/points/` with `dir/shard.json`; the analysis waits for [`merge`]. `progress` receives
/// collision counts.
pub fn sweep_shard(
    cfg: &SweepConfig,
    shard: Shard,
    dir: &Path,
    engine: Engine,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<ShardReport, Error> {
    cfg.validate()?;
    shard.validate(cfg)?;
    let resolved = engine.resolve(true)?;
    let (points, resumed) = run_points(cfg, dir, engine, threads, progress, |i| shard.owns(i))?;
    let report = ShardReport {
        config: cfg.clone(),
        shard,
        points: points.iter().map(|p| p.index).collect(),
        resumed_points: resumed,
        meta: RunMeta::new(
            Some(cfg.seed),
            Some(cfg.runs as u64 * cfg.batches as u64),
            Precision::F64,
            Some(threads),
        )
        .with_engine(resolved),
    };
    write_atomically(&dir.join("shard.json"), &to_json(&report)?)?;
    Ok(report)
}

/// Runs (or reuses) the points i of `cfg` with `owns(i)`, in index order, each written to
/// `dir/points/` as it finishes; returns them and how many were reused.
fn run_points(
    cfg: &SweepConfig,
    dir: &Path,
    engine: Engine,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
    owns: impl Fn(u32) -> bool,
) -> Result<(Vec<SweepPoint>, u32), Error> {
    std::fs::create_dir_all(dir.join("points"))?;
    let mut points = Vec::new();
    let mut resumed = 0;
    for (i, w) in cfg.points()?.into_iter().enumerate() {
        if !owns(i as u32) {
            continue;
        }
        let path = point_path(dir, i);
        if let Ok(text) = std::fs::read_to_string(&path) {
            if let Ok(p) = serde_json::from_str::<SweepPoint>(&text) {
                if p.config == *cfg && p.w == w && p.index as usize == i {
                    progress(cfg.collisions.saturating_mul(cfg.runs as u64));
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
        let cfgs: Vec<DiffusionConfig> = (0..cfg.runs)
            .map(|r| cfg.run_config(i as u32, w, r))
            .collect();
        // Finished batches of this point are journalled as they come, so that an interruption
        // loses at most the blocks in flight, not the point's finished runs.
        let journal = path.with_extension("partial");
        let opts = RunOptions {
            engine,
            threads,
            progress,
            resume: Some(journal.clone()),
            audit: None,
        };
        let runs = run_many(&cfgs, &opts)?
            .into_iter()
            .map(|rep| RunValue {
                D: rep.D,
                D_err: rep.D_err,
            })
            .collect();
        let p = SweepPoint {
            config: cfg.clone(),
            index: i as u32,
            w,
            runs,
        };
        write_atomically(
            &path,
            &serde_json::to_string(&p).map_err(|e| Error::Io(e.to_string()))?,
        )?;
        let _ = std::fs::remove_file(&journal);
        points.push(p);
    }
    Ok((points, resumed))
}

fn to_json<T: Serialize>(x: &T) -> Result<String, Error> {
    serde_json::to_string_pretty(x).map_err(|e| Error::Io(e.to_string()))
}

/// Write-then-rename: an interruption never leaves a half-written file.
fn write_atomically(path: &Path, text: &str) -> Result<(), Error> {
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, text)?;
    std::fs::rename(&tmp, path)?;
    Ok(())
}

/// Combines the directories of a sharded sweep (each from [`sweep_shard`], or any directory of
/// finished points of the same sweep) into `out`: the points are copied to `out/points/` (so
/// that `lorentz sweep` with the same configuration and `--out out` resumes all of them) and the
/// analysis, `sweep.csv`, `sweep.json` and the figures are written as [`sweep_on`] writes them —
/// the same bits, apart from `meta` (this process) and `resumed_points` (every point merged).
///
/// # Errors
/// A directory without points, points or parts of different configurations, a point or part
/// present twice, parts of different counts, or missing points (named, with the part that owns
/// each) — before anything is written.
pub fn merge(dirs: &[PathBuf], out: &Path, threads: usize) -> Result<SweepReport, Error> {
    if dirs.is_empty() {
        return Err(Error::Invalid(
            "merge needs at least one directory of sweep points".into(),
        ));
    }
    let mut cfg: Option<(SweepConfig, PathBuf)> = None;
    let mut shards: std::collections::BTreeMap<u32, (Shard, PathBuf)> = Default::default();
    let mut found: std::collections::BTreeMap<u32, (SweepPoint, PathBuf)> = Default::default();
    // The engines that ran the parts (informational: every engine gives the same bits).
    let mut engines: Vec<(String, Option<String>)> = Vec::new();
    let same = |c: &SweepConfig, d: &Path, cfg: &mut Option<(SweepConfig, PathBuf)>| match cfg {
        None => {
            *cfg = Some((c.clone(), d.to_path_buf()));
            Ok(())
        }
        Some((c0, d0)) if c0 != c => Err(Error::Invalid(format!(
            "{} and {} hold different sweeps ({}): merge only parts of one sweep",
            d0.display(),
            d.display(),
            config_difference(c0, c)
        ))),
        Some(_) => Ok(()),
    };
    for d in dirs {
        let manifest = d.join("shard.json");
        if manifest.exists() {
            let text = std::fs::read_to_string(&manifest)?;
            let m: ShardReport = serde_json::from_str(&text).map_err(|e| {
                Error::Invalid(format!(
                    "{} is not a shard manifest: {e}",
                    manifest.display()
                ))
            })?;
            same(&m.config, d, &mut cfg)?;
            if let Some((s0, d0)) = shards.values().next() {
                if s0.count != m.shard.count {
                    return Err(Error::Invalid(format!(
                        "{} is part {} but {} is part {}: merge parts of one split",
                        d0.display(),
                        s0,
                        d.display(),
                        m.shard
                    )));
                }
            }
            if let Some((_, d0)) = shards.get(&m.shard.index) {
                return Err(Error::Invalid(format!(
                    "part {} is in both {} and {}",
                    m.shard,
                    d0.display(),
                    d.display()
                )));
            }
            shards.insert(m.shard.index, (m.shard, d.clone()));
            let e = (m.meta.engine, m.meta.simd);
            if !engines.contains(&e) {
                engines.push(e);
            }
        }
        let pdir = d.join("points");
        let entries = std::fs::read_dir(&pdir).map_err(|e| {
            Error::Invalid(format!(
                "{}: no sweep points here ({e}); give the directories that lorentz sweep --shard wrote",
                d.display()
            ))
        })?;
        let mut names: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .collect();
        names.sort();
        for path in names {
            let text = std::fs::read_to_string(&path)?;
            let p: SweepPoint = serde_json::from_str(&text).map_err(|e| {
                Error::Invalid(format!("{} is not a sweep point: {e}", path.display()))
            })?;
            same(&p.config, d, &mut cfg)?;
            if let Some((_, d0)) = found.get(&p.index) {
                return Err(Error::Invalid(format!(
                    "point {} (w = {}) is in both {} and {}",
                    p.index,
                    p.w,
                    d0.display(),
                    d.display()
                )));
            }
            found.insert(p.index, (p, d.clone()));
        }
    }
    let Some((cfg, _)) = cfg else {
        return Err(Error::Invalid(format!(
            "no sweep points in {}",
            dirs.iter()
                .map(|d| d.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    };
    cfg.validate()?;
    let grid = cfg.points()?;
    let missing: Vec<u32> = (0..cfg.steps).filter(|i| !found.contains_key(i)).collect();
    if !missing.is_empty() {
        let count = shards.values().next().map(|(s, _)| s.count);
        let list = missing
            .iter()
            .take(10)
            .map(|&i| match count {
                Some(n) => format!("{i} (w = {}, part {}/{n})", grid[i as usize], i % n),
                None => format!("{i} (w = {})", grid[i as usize]),
            })
            .collect::<Vec<_>>()
            .join(", ");
        let more = if missing.len() > 10 { ", …" } else { "" };
        return Err(Error::Invalid(format!(
            "{} of {} points missing: {list}{more}; run (or finish) those parts first",
            missing.len(),
            cfg.steps
        )));
    }
    let mut points = Vec::with_capacity(found.len());
    for (i, (p, _)) in found {
        if p.w != grid[i as usize] {
            return Err(Error::Invalid(format!(
                "point {i} has w = {} but the grid has {}: a damaged point file",
                p.w, grid[i as usize]
            )));
        }
        points.push(p);
    }
    std::fs::create_dir_all(out.join("points"))?;
    for p in &points {
        write_atomically(
            &point_path(out, p.index as usize),
            &serde_json::to_string(p).map_err(|e| Error::Io(e.to_string()))?,
        )?;
    }
    let n = points.len() as u32;
    let mut report = analyse(&cfg, &points, n, threads)?;
    if let [(engine, simd)] = &engines[..] {
        report.meta.engine = engine.clone();
        report.meta.simd = simd.clone();
    } else if !engines.is_empty() {
        report.meta.engine = engines
            .iter()
            .map(|(e, s)| s.as_ref().map_or(e.clone(), |s| format!("{e} ({s})")))
            .collect::<Vec<_>>()
            .join(" + ");
    }
    write_outputs(&report, out)?;
    Ok(report)
}

/// The first field in which two sweep configurations differ, as `field: a ≠ b`.
fn config_difference(a: &SweepConfig, b: &SweepConfig) -> String {
    let fields = [
        ("w_from", a.w_from.clone(), b.w_from.clone()),
        ("w_to", a.w_to.clone(), b.w_to.clone()),
        ("steps", a.steps.to_string(), b.steps.to_string()),
        ("runs", a.runs.to_string(), b.runs.to_string()),
        (
            "collisions",
            a.collisions.to_string(),
            b.collisions.to_string(),
        ),
        ("batches", a.batches.to_string(), b.batches.to_string()),
        ("seed", a.seed.to_string(), b.seed.to_string()),
    ];
    fields
        .iter()
        .find(|(_, x, y)| x != y)
        .map(|(f, x, y)| format!("{f}: {x} vs {y}"))
        .unwrap_or_else(|| "their configurations differ".into())
}

/// One point's D, its error from the batch errors inside the runs, and the runs' χ².
fn combine(cfg: &SweepConfig, p: &SweepPoint) -> Result<SweepRow, Error> {
    let g = Geometry::new(p.w)?;
    let r = p.runs.len() as f64;
    let d = p.runs.iter().map(|x| x.D).sum::<f64>() / r;
    let d_err = p.runs.iter().map(|x| x.D_err * x.D_err).sum::<f64>().sqrt() / r;
    let dof1 = p.runs.len() as u32 - 1;
    let dof2 = p.runs.len() as u64 * (cfg.batches as u64 - 1);
    let between = p.runs.iter().map(|x| (x.D - d).powi(2)).sum::<f64>() / dof1 as f64;
    let within = p.runs.iter().map(|x| x.D_err * x.D_err).sum::<f64>() / r;
    let f = between / within;
    Ok(SweepRow {
        w: p.w,
        inv_n: 1.0 / g.density(),
        D: d,
        D_err: d_err,
        D_err_dof: dof2,
        runs_f: f,
        runs_f_dof: (dof1, dof2),
        runs_p_value: f_p_value(f, dof1 as f64, dof2 as f64),
        D_MZ: g.d_mz(),
        D_Bo: g.d_bo(),
        residual: 0.0,
        run_D: p.runs.iter().map(|x| x.D).collect(),
    })
}

/// The crossing of D − D_MZ, from a weighted least-squares quadratic through up to
/// [`CROSSING_POINTS_PER_SIDE`] points on each side of the first sign change (a straight line when
/// only two points exist). The root is the one nearest the sign change; its error is
/// (gᵀ Σ g)^½ / |f′(w*)| with g = (1, t*, t*²) and Σ the fit's covariance.
pub fn mz_crossing(rows: &[SweepRow]) -> Result<Option<Crossing>, Error> {
    let f: Vec<f64> = rows.iter().map(|r| r.D - r.D_MZ).collect();
    let Some(k) = (0..f.len().saturating_sub(1)).find(|&k| f[k].signum() != f[k + 1].signum())
    else {
        return Ok(None);
    };
    let lo = (k + 1).saturating_sub(CROSSING_POINTS_PER_SIDE);
    let hi = (k + 1 + CROSSING_POINTS_PER_SIDE).min(rows.len());
    let sel = &rows[lo..hi];
    let x: Vec<f64> = sel.iter().map(|r| r.w).collect();
    let y: Vec<f64> = sel.iter().map(|r| r.D - r.D_MZ).collect();
    let e: Vec<f64> = sel.iter().map(|r| r.D_err).collect();
    // Centre on the linear interpolation between the two points that change sign.
    let x0 = rows[k].w + (rows[k + 1].w - rows[k].w) * f[k] / (f[k] - f[k + 1]);
    let (t, err, chi2, dof) = if sel.len() >= 3 {
        let q = weighted_quadratic_fit(&x, &y, &e, x0)?;
        let (t, err) = q.root_near_zero().ok_or_else(|| {
            Error::Invalid("the local quadratic of D - D_MZ has no real root".into())
        })?;
        (t, err, q.chi2, q.dof)
    } else {
        let l = weighted_line_fit(&x, &y, &e)?;
        let (w, err) = l.root();
        (w - x0, err, l.chi2, l.dof)
    };
    let scale = if dof > 0 {
        (chi2 / dof as f64).max(1.0).sqrt()
    } else {
        1.0
    };
    Ok(Some(Crossing {
        w: x0 + t,
        err,
        err_scaled: err * scale,
        chi2,
        dof,
        points: sel.len(),
    }))
}

fn analyse(
    cfg: &SweepConfig,
    points: &[SweepPoint],
    resumed: u32,
    threads: usize,
) -> Result<SweepReport, Error> {
    let mut rows = points
        .iter()
        .map(|p| combine(cfg, p))
        .collect::<Result<Vec<_>, _>>()?;
    let col = |f: &dyn Fn(&SweepRow) -> f64| rows.iter().map(f).collect::<Vec<f64>>();
    let (ws, ds, es, inv_n) = (
        col(&|r| r.w),
        col(&|r| r.D),
        col(&|r| r.D_err),
        col(&|r| r.inv_n),
    );
    let lin = weighted_line_fit(&ws, &ds, &es)?;
    let boltz = weighted_mean(&col(&|r| r.D_Bo - r.D), &es)?;
    let scale = if boltz.dof > 0 {
        (boltz.chi2 / boltz.dof as f64).max(1.0).sqrt()
    } else {
        1.0
    };
    let free = weighted_line_fit(&inv_n, &ds, &es)?;
    for r in &mut rows {
        r.residual = r.D - lin.at(r.w);
    }
    let crossing = mz_crossing(&rows)?;
    let mut polynomial_chi2 = Vec::new();
    for degree in 1..=MAX_POLYNOMIAL_DEGREE {
        if ws.len() < degree + 2 {
            break;
        }
        let (chi2, dof) = weighted_polynomial_chi2(&ws, &ds, &es, degree)?;
        polynomial_chi2.push(PolynomialChi2 { degree, chi2, dof });
    }
    Ok(SweepReport {
        polynomial_chi2,
        config: cfg.clone(),
        rows,
        linear_fit: lin,
        boltzmann_offset: boltz,
        boltzmann_offset_err_scaled: boltz.err * scale,
        boltzmann_free_fit: free,
        mz_crossing: crossing,
        resumed_points: resumed,
        meta: RunMeta::new(
            Some(cfg.seed),
            Some(cfg.runs as u64 * cfg.batches as u64),
            Precision::F64,
            Some(threads),
        ),
    })
}

/// Writes `sweep.csv` and `sweep.json` (the figures are
/// [`write_sweep_figures`](crate::report::figures::sweep::write_sweep_figures)).
fn write_outputs(r: &SweepReport, dir: &Path) -> Result<(), Error> {
    let mut csv =
        String::from("w,inv_n,D,D_err,D_err_dof,runs_F,runs_F_dof1,runs_F_dof2,runs_p_value,D_MZ,D_Bo,residual,runs\n");
    for row in &r.rows {
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            row.w,
            row.inv_n,
            row.D,
            row.D_err,
            row.D_err_dof,
            row.runs_f,
            row.runs_f_dof.0,
            row.runs_f_dof.1,
            row.runs_p_value,
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
    Ok(())
}
