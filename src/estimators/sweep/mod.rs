//! D over a range of w: independent runs per point, resumable, with the paper's coarse- and
//! fine-scale analyses (Figs. 2, 7, 8): D against D_MZ and the measured crossing D = D_MZ; the
//! Boltzmann form D_Bo − ΔD = (3/16)(1/n − π) − ΔD fitted against 1/n (ΔD with the slope fixed
//! at 3/16, and the free slope); residuals of D from a straight line in w, with error bars.
//!
//! Errors: a point's error comes from the batch errors inside its runs (R runs of B batches:
//! R(B − 1) degrees of freedom), never from the spread of a handful of run values; that spread is
//! reported as a χ² consistency check. The fits downstream are weighted by these errors and report
//! χ²/dof (`proofs-notes/sweep-errors.md`).

pub mod analysis;
pub mod driven;
pub mod field;
pub mod field_grid;
pub mod file;
pub mod point_grid;
pub mod points;
pub mod stored;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::{RunOption, RunOptions};
use crate::estimators::diffusion::DiffusionConfig;
use crate::numbers::exact::decimal_grid;
use crate::numbers::precision::Precision;
use crate::statistics::fits::{LineFit, WeightedMean};

/// What defines a sweep: the grid it runs through and each point's run. One description of
/// every sweep, for the command line, Python, campaigns' parts and Slurm job arrays.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepConfig {
    /// What is swept (in JSON, the grid's keys beside the run's).
    #[serde(flatten)]
    pub grid: Grid,
    /// Collisions per run (serialized as `collisions_per_run`, the command line's name).
    #[serde(rename = "collisions_per_run")]
    pub collisions: u64,
    /// Batches per run (≥ 2): the error bar of a run is the standard error over its batches
    /// (serialized as `batches_per_run`, the command line's name).
    #[serde(rename = "batches_per_run")]
    pub batches: u32,
    /// Seed: run r of point i uses the streams of run i·runs + r of this seed.
    pub seed: u64,
}

/// What a sweep runs through.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Grid {
    /// D(w) of the triangular gas without a field at evenly spaced gaps ([`run`]).
    Gaps(GapGrid),
    /// The diffusion tensor in a field over tables × fields ([`field::run`]).
    InField(field::FieldGrid),
    /// The driven gas's steady state over gaps × fields E ([`driven::run`]).
    Driven(driven::DrivenGrid),
}

/// Evenly spaced gaps of the triangular gas, several runs at each.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GapGrid {
    /// First w, as the decimal typed (the grid is computed exactly: [`crate::numbers::exact`]).
    pub w_from: String,
    /// Last w, as typed.
    pub w_to: String,
    /// Number of points (≥ 2).
    pub steps: u32,
    /// Independent runs per point (≥ 1; with ≥ 2 their spread is checked against their errors).
    pub runs: u32,
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Serialize, Deserialize)]
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
    /// distributed (NaN for one run, written as JSON `null`).
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub runs_f: f64,
    /// Its numerator degrees of freedom, R − 1.
    pub runs_f_dof1: u32,
    /// Its denominator degrees of freedom, R(B − 1).
    pub runs_f_dof2: u64,
    /// Probability of an F at least this large if the runs agree within their errors (NaN for
    /// one run, written as JSON `null`).
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub runs_p_value: f64,
    /// Machta–Zwanzig.
    pub D_MZ: f64,
    /// Boltzmann.
    pub D_Bo: f64,
    /// D minus the weighted straight-line fit.
    pub residual: f64,
    /// Each run's D, in run order (also `sweep-runs.csv`).
    pub run_D: Vec<f64>,
    /// Each run's standard error over its batches, in run order: with `run_D`, everything the
    /// row and the fits are computed from (`lorentz report` recomputes them).
    pub run_D_err: Vec<f64>,
}

impl SweepConfig {
    /// The gaps of a sweep over w without a field.
    ///
    /// # Errors
    /// A sweep in a field (which [`field::run`] runs).
    pub fn gap_grid(&self) -> Result<&GapGrid, Error> {
        match &self.grid {
            Grid::Gaps(g) => Ok(g),
            Grid::InField(f) => Err(Error::parameter(
                "fields",
                f.fields.join(","),
                "a sweep in a field has its own analysis (the tensor and Onsager-Casimir), not \
                 the fits of D(w) without a field",
            )),
            Grid::Driven(d) => Err(Error::parameter(
                "electric",
                d.electric.join(","),
                "a driven sweep has its own analysis (the mobility), not the fits of D(w) \
                 without a field",
            )),
        }
    }

    /// The tables and fields of a sweep in a field.
    ///
    /// # Errors
    /// A sweep without a field.
    pub fn field_grid(&self) -> Result<&field::FieldGrid, Error> {
        match &self.grid {
            Grid::InField(f) => Ok(f),
            Grid::Gaps(_) | Grid::Driven(_) => Err(Error::missing(
                "fields",
                "a sweep in a field needs its fields",
            )),
        }
    }

    /// Independent runs per point (one in a field).
    pub fn runs(&self) -> u32 {
        match &self.grid {
            Grid::Gaps(g) => g.runs,
            Grid::InField(_) | Grid::Driven(_) => 1,
        }
    }

    /// Its points (each belongs to one part of a campaign).
    pub fn steps(&self) -> u32 {
        match &self.grid {
            Grid::Gaps(g) => g.steps,
            Grid::InField(f) => f.points() as u32,
            Grid::Driven(d) => d.points() as u32,
        }
    }

    /// The grid of w of a sweep without a field, exact decimals rounded once.
    ///
    /// # Errors
    /// A sweep in a field, or ends that are not exact numbers.
    pub fn points(&self) -> Result<Vec<f64>, Error> {
        let g = self.gap_grid()?;
        decimal_grid(&g.w_from, &g.w_to, g.steps)
    }

    /// The diffusion run r of point i at the gap w, without a field.
    pub fn run_config(&self, i: u32, w: f64, r: u32) -> DiffusionConfig {
        let mut c = DiffusionConfig::new(w);
        c.collisions = self.collisions;
        c.batches = self.batches;
        c.seed = self.seed;
        // u32·u32 + u32 < 2⁶⁴: cannot overflow, and distinct (i, r) give distinct runs.
        c.run = i as u64 * self.runs() as u64 + r as u64;
        c.precision = Precision::F64;
        c
    }

    /// Checks every parameter (every point's run) before anything runs or is written.
    ///
    /// # Errors
    /// What the grid's checks refuse, naming the range.
    pub fn validate(&self) -> Result<(), Error> {
        match &self.grid {
            Grid::Gaps(g) => self.validate_gaps(g),
            Grid::InField(f) => f.validate(self),
            Grid::Driven(d) => d.validate(self),
        }
    }

    /// The checks of a sweep over w without a field.
    fn validate_gaps(&self, g: &GapGrid) -> Result<(), Error> {
        if g.steps < 2 || g.steps > MAX_SWEEP_POINTS {
            return Err(Error::out_of_range(
                "steps",
                g.steps,
                format!("use 2 to {MAX_SWEEP_POINTS} points (a sweep needs at least 2)"),
            ));
        }
        if g.runs == 0 {
            return Err(Error::Zero { what: "runs" });
        }
        crate::engine::parallel::check_batches("runs", g.runs)?;
        // The ends exactly as typed: every point lies between them.
        for (name, end) in [("w_from", &g.w_from), ("w_to", &g.w_to)] {
            let w = (crate::numbers::exact::ExactInput::parse(end))
                .map_err(|e| e.named(name))?
                .value;
            crate::scenes::triangular::geometry::check_diffusive_gap_exact(w, Some(end))?;
        }
        let points = self.points()?;
        if let Some(k) = points.windows(2).position(|p| p[0] == p[1]) {
            return Err(Error::parameter(
                "steps",
                g.steps,
                format!(
                    "from w_from = {} to w_to = {} gives w = {} at points {k} and {}: the fits \
                     need distinct w, use ends that differ by more than the steps resolve",
                    g.w_from,
                    g.w_to,
                    points[k],
                    k + 1
                ),
            ));
        }
        for (i, w) in points.into_iter().enumerate() {
            self.run_config(i as u32, w, 0).validate()?;
        }
        Ok(())
    }
}

/// Runs the sweep and analyses it. With `options.resume` (a directory), every finished point is
/// kept in `DIR/points/` as it finishes (and a point's finished batches in a journal beside it),
/// and points already there (of the same configuration) are reused, so an interrupted sweep
/// continues where it stopped. `options.progress` receives collision counts. A point's runs are
/// packed together ([`crate::estimators::diffusion::run_many`]), so that R runs of B batches fill
/// R·B SIMD lanes; the same bits on every engine and at every thread count.
///
/// The tables and figures are written by [`write_tables`] and
/// [`write_sweep_figures`](crate::report::figures::sweep::write_sweep_figures).
///
/// # Errors
/// An invalid configuration or options (before any work or file), a directory holding another
/// sweep's points, or an I/O error.
pub fn run(cfg: &SweepConfig, options: &RunOptions) -> Result<SweepReport, Error> {
    cfg.validate()?;
    options.accept(
        "sweep",
        &[
            RunOption::Engine,
            RunOption::Resume,
            RunOption::CheckpointEvery,
        ],
    )?;
    let collisions = cfg.steps() as f64 * cfg.runs() as f64 * cfg.collisions as f64;
    crate::engine::work::Work::new(
        "sweep",
        &["steps", "runs", "collisions_per_run"],
        collisions,
    )
    .simd()
    .check(options.threads)?;
    let resolved = options.engine.resolve(true)?;
    let (points, resumed) = points::run_points(cfg, options, |_| true)?;
    let mut report = analysis::analyse(cfg, &points, resumed, options.threads)?;
    report.meta = report.meta.with_engine(resolved);
    Ok(report)
}

/// The files [`write_tables`] writes.
pub const TABLE_FILES: [&str; 3] = ["sweep.csv", "sweep-runs.csv", "sweep.json"];

/// Writes `sweep.csv` (one line per point; its columns are the keys of `sweep.json`'s rows),
/// `sweep-runs.csv` (one line per run: `w,run,run_D`) and `sweep.json` into `dir` (the figures
/// are [`write_sweep_figures`](crate::report::figures::sweep::write_sweep_figures)).
pub fn write_tables(r: &SweepReport, dir: &Path) -> Result<(), Error> {
    let mut csv = String::from(
        "w,inv_n,D,D_err,D_err_dof,runs_f,runs_f_dof1,runs_f_dof2,runs_p_value,D_MZ,D_Bo,residual\n",
    );
    let mut runs = String::from("w,run,run_D\n");
    for row in &r.rows {
        for (k, d) in row.run_D.iter().enumerate() {
            runs.push_str(&format!("{},{k},{d}\n", row.w));
        }
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{}\n",
            row.w,
            row.inv_n,
            row.D,
            row.D_err,
            row.D_err_dof,
            row.runs_f,
            row.runs_f_dof1,
            row.runs_f_dof2,
            row.runs_p_value,
            row.D_MZ,
            row.D_Bo,
            row.residual,
        ));
    }
    crate::files::write(dir.join("sweep.csv"), csv)?;
    crate::files::write(dir.join("sweep-runs.csv"), runs)?;
    crate::files::write(
        dir.join("sweep.json"),
        serde_json::to_string_pretty(r).map_err(Error::encode)?,
    )?;
    Ok(())
}
