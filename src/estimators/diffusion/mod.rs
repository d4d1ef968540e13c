//! D(w) by the Einstein formula, with error bars from independent batches.
//!
//! Each batch is one trajectory started from the invariant measure with its own random stream
//! ([`crate::scenes::sampling::stream`]). Along it the MSD is sampled every gτ (τ the exact mean hop
//! time, g the gcd of the fit lags in units of τ: 5 for the default windows; `proofs-notes/
//! msd-grid.md`) with every sample a time origin, and D_b is a quarter of the least-squares slope
//! of MSD(t)
//! over the fit window [lo·τ, hi·τ] (the slope, not MSD/4t at one t, so the intercept of the
//! transient does not bias D). D is the mean of the D_b and its error the standard error over
//! batches. A second, later window is fitted too and reported: the two agreeing within errors
//! shows that the fit window lies in the linear regime.
//!
//! Results do not depend on the number of threads or the engine: batch b's bits depend only on
//! (seed, run, b) — the SIMD engine runs 16 batches in vector lanes, each bit-identical to the
//! scalar engine ([`crate::engine`]) — and batches are combined in index order.

use std::path::Path;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::Engine;
use crate::engine::checkpoint::Quota;
use crate::engine::metadata::RunMeta;
use crate::engine::options::{AuditSpec, RunOption, RunOptions};
use crate::kernel::trap::Trap;
use crate::numbers::precision::Precision;
use crate::observers::counters::Counters;
use crate::scenes::lattice::LatticeState;
use crate::statistics::mean_se;
use crate::verification::shadow_audit::AuditSummary;

mod config;
pub mod curve;
mod execution;
mod plain;
pub mod plan;
mod resumed;
pub mod scene;
mod summary;

use execution::{DiffusionKeeper, Job, execute, setup};

// The configuration keeps its one public path, `estimators::diffusion::…` (its module is private).
pub use config::{
    DEFAULT_LOCALIZATION_SAMPLES, DiffusionConfig, MIN_HOPS_PER_LAG, MsdGrid, Sampling, Window,
    check_electric, lag_grid, refuse_rel_err, require_finite_horizon, time_unit,
};

/// Kind of the records of a diffusion checkpoint.
const CHECKPOINT_KIND: &str = "diffusion trajectories";

/// Kind of the records of a [`run_many`] journal.
const PACKED_KIND: &str = "packed diffusion trajectories";
use summary::{d_of_batch, summarise};

/// What one batch produced (also the unit of checkpointing).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BatchResult {
    /// Batch index (its random stream).
    pub index: u32,
    /// Event totals.
    pub counters: Counters,
    /// Lags in units of τ.
    pub lags: Vec<usize>,
    /// MSD at each lag.
    pub msd: Vec<f64>,
    /// The MSD curve on its logarithmic grid (runs with [`MsdGrid::Log`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curve: Option<crate::observers::msd_curve::CurveValues>,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Per-event shadow audit of a sample of this batch's events (f64 runs with `--audit`).
    #[serde(default)]
    pub audit: Option<AuditSummary>,
}

/// One estimate with its standard error.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// Value.
    pub value: f64,
    /// Standard error.
    pub err: f64,
}

/// The result of a diffusion run (the CLI's `--json`).
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DiffusionReport {
    /// Gap w.
    pub w: f64,
    /// Diffusion coefficient (fit window `window`).
    pub D: f64,
    /// Its standard error over batches.
    pub D_err: f64,
    /// Fit window of D, in units of τ.
    pub window: Window,
    /// D from the later window (check of the linear regime).
    pub D_check: f64,
    /// Its standard error.
    pub D_check_err: f64,
    /// The later window.
    pub check_window: Window,
    /// D − D_check, paired over the batches (the mean of the per-batch differences): both come
    /// from the same trajectories, so their errors must not be added in quadrature.
    pub D_minus_D_check: f64,
    /// Its standard error (of the per-batch differences; `meta.batches` − 1 dof).
    pub D_minus_D_check_err: f64,
    /// Machta–Zwanzig value (eq. 2).
    pub D_MZ: f64,
    /// Boltzmann value (eq. 8).
    pub D_Bo: f64,
    /// Measured mean free path (total time / collisions).
    pub mean_free_path: f64,
    /// Its standard error.
    pub mean_free_path_err: f64,
    /// Santaló's exact value π|Q|/|∂Q|.
    pub mean_free_path_exact: f64,
    /// Measured mean hop time (total time / crossings).
    pub tau_hop: f64,
    /// Its standard error.
    pub tau_hop_err: f64,
    /// Exact τ = πA/(3w).
    pub tau_hop_exact: f64,
    /// Measured collisions per hop.
    pub collisions_per_hop: f64,
    /// Its standard error.
    pub collisions_per_hop_err: f64,
    /// Exact π/(3w).
    pub collisions_per_hop_exact: f64,
    /// Lag times (in time units) at which the MSD was measured.
    pub msd_times: Vec<f64>,
    /// MSD/(4t) at those times (mean over batches): approaches D from one side.
    pub msd_over_4t: Vec<f64>,
    /// Its standard errors, time by time.
    pub msd_over_4t_err: Vec<f64>,
    /// The MSD, the velocity autocorrelation and the running Green–Kubo integral on the
    /// logarithmic grid, with D by Green–Kubo (runs with [`MsdGrid::Log`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub msd_curve: Option<curve::MsdCurveReport>,
    /// D by Green–Kubo from the MSD curve against the Einstein D (runs with
    /// [`MsdGrid::Log`]).
    #[serde(flatten)]
    pub green_kubo: curve::GreenKuboD,
    /// Longest free path seen in the run.
    pub longest_free_path: f64,
    /// Total collisions.
    pub collisions: u64,
    /// Wall-clock seconds of this invocation.
    pub seconds: f64,
    /// Collisions per wall-clock second in this invocation.
    pub collisions_per_second: f64,
    /// Batches reused from a checkpoint.
    pub resumed_batches: u32,
    /// Collisions done by earlier invocations (finished batches and trajectories resumed in
    /// flight); `collisions_per_second` counts only this invocation's.
    #[serde(default)]
    pub resumed_collisions: u64,
    /// The self-audit, if requested: events replayed, outside the model, error quantiles.
    pub audit: Option<crate::verification::shadow_audit::AuditSummary>,
    /// The configuration that produced the result (what `lorentz report` re-runs batches from).
    #[serde(default)]
    pub config: Option<DiffusionConfig>,
    /// D of each batch, in batch order (D is their mean, D_err their standard error).
    #[serde(default)]
    pub batch_D: Vec<f64>,
    /// D of each batch in the check window.
    #[serde(default)]
    pub batch_D_check: Vec<f64>,
    /// Each batch's MSD at `msd_times` (batch order).
    #[serde(default)]
    pub batch_msd: Vec<Vec<f64>>,
    /// How many collisions the next decade of relative error needs, and how long they take at
    /// this run's speed ([`plan::next_decade`]).
    #[serde(default)]
    pub plan: Option<plan::Plan>,
    /// The pilot of a run planned for a relative error (`rel_err`), `None` for a plain run.
    #[serde(default)]
    pub pilot: Option<plan::Pilot>,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

impl DiffusionReport {
    /// D and D_err recomputed from the batch values exactly as the run computed them (the same
    /// operations in the same order, so the same bits).
    pub fn d_from_batches(&self) -> ((f64, f64), (f64, f64)) {
        (mean_se(&self.batch_D), mean_se(&self.batch_D_check))
    }
}

/// D of one batch in `window` and in `check`: the slope of its MSD against time over the lags of
/// each window, divided by 4.
pub fn batch_d(b: &BatchResult, tau: f64, window: &Window, check: &Window) -> (f64, f64) {
    (d_of_batch(b, tau, window), d_of_batch(b, tau, check))
}

/// D over the batches `done`, in the fit window and in the check window, and their paired
/// difference.
pub(crate) struct WindowDs {
    /// Each batch's D in the fit window.
    pub ds: Vec<f64>,
    /// Their mean and its standard error.
    pub d: (f64, f64),
    /// Each batch's D in the check window.
    pub dc: Vec<f64>,
    /// Their mean and its standard error.
    pub check: (f64, f64),
    /// D − D_check, paired over the batches.
    pub diff: crate::statistics::comparison::Comparison,
}

/// [`WindowDs`] of the batches `done` with the time unit `tau`.
///
/// # Errors
/// Fewer than two batches.
pub(crate) fn window_ds(
    done: &[BatchResult],
    tau: f64,
    window: &Window,
    check: &Window,
) -> Result<WindowDs, Error> {
    let (ds, dc): (Vec<f64>, Vec<f64>) =
        done.iter().map(|b| batch_d(b, tau, window, check)).unzip();
    Ok(WindowDs {
        d: mean_se(&ds),
        check: mean_se(&dc),
        diff: crate::statistics::comparison::paired(&ds, &dc)?,
        ds,
        dc,
    })
}

/// Runs only the batches `indices` of `cfg` (their own streams and collision shares, so each gives
/// the bits it gave in the full run), on `engine`, replaying a fraction of their events in MPFR
/// when `audit` is given. For re-checking a recorded result batch by batch.
pub fn rerun_batches(
    cfg: &DiffusionConfig,
    indices: &[u32],
    engine: Engine,
    threads: usize,
    audit: Option<AuditSpec>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<BatchResult>, Error> {
    cfg.validate()?;
    let (spec, _) = setup(cfg, engine, threads, audit)?;
    for &i in indices {
        if i >= cfg.batches {
            return Err(Error::Failed(format!(
                "batch {i}: the run has batches 0 to {}",
                cfg.batches - 1
            )));
        }
    }
    let jobs: Vec<Job> = cfg.jobs().filter(|j| indices.contains(&j.index)).collect();
    let mut r = execute(&jobs, spec, &DiffusionKeeper::none(), progress)?;
    r.sort_by_key(|b| b.index);
    Ok(r)
}

/// The `f64` start of batch `index` of `cfg`: the state its trajectory starts from in the run
/// (the equilibrium state of its stream (seed, run, index)).
pub fn batch_start(cfg: &DiffusionConfig, index: u32) -> Result<LatticeState<f64>, Error> {
    let trap64 = Trap::new(cfg.gap()?)?;
    let job = Job {
        seed: cfg.seed,
        run: cfg.run,
        index,
        collisions: 0,
    };
    Ok(job.start::<f64>(&trap64, ()))
}

/// Runs the configured computation. The result has the same bits on every engine and at every
/// thread count; only `seconds`, the speed and the metadata's engine differ.
///
/// `options.progress` receives collision counts as they are done. With `options.resume` (a
/// checkpoint file), every finished batch is appended to it at once, and every
/// `options.checkpoint_every` the whole state of each trajectory in flight; batches already
/// there (from the same configuration) are not run again and trajectories in flight continue
/// from their saved state, to the uninterrupted bits. A resumed run whose exact identities then
/// fail stops with an error. `options.audit` replays a fraction of the events in MPFR as the run
/// goes (`f64` runs only; with it, only finished batches are kept).
///
/// # Errors
/// An invalid configuration or options (before any work), a checkpoint of another
/// configuration or an edited one (naming the file and line), an I/O error, or a resumed run
/// failing its exact identities.
///
/// # Examples
///
/// ```
/// use lorentz_gas::engine::options::RunOptions;
/// use lorentz_gas::estimators::diffusion::{self, DiffusionConfig};
/// let cfg = DiffusionConfig { collisions: 2_000_000, batches: 4, ..DiffusionConfig::new(0.2) };
/// let r = diffusion::run(&cfg, &RunOptions::default()).unwrap();
/// assert!((r.D - 0.17).abs() < 8.0 * r.D_err + 0.02);
/// ```
pub fn run(cfg: &DiffusionConfig, options: &RunOptions) -> Result<DiffusionReport, Error> {
    options.accept("diffusion", &RunOption::ALL)?;
    cfg.validate()?;
    if cfg.rel_err.is_some() {
        return plan::run(cfg, options);
    }
    plain::run(cfg, options, plain::Planned::Alone).map(|(r, _)| r)
}

/// Refuses a run `c` that cannot be packed with `first`: another MSD grid than the fit one, or
/// another w, precision or fit windows.
fn check_packable(first: &DiffusionConfig, c: &DiffusionConfig) -> Result<(), Error> {
    if c.msd_grid != MsdGrid::Fit {
        return Err(Error::parameter(
            "msd_grid",
            &c.msd_grid,
            "runs packed together keep the MSD on the fit grid only: use fit",
        ));
    }
    let differs = [
        ("w", c.table != first.table, c.table.title()),
        (
            "precision",
            c.precision != first.precision,
            c.precision.to_string(),
        ),
        ("window", c.window != first.window, c.window.to_string()),
        (
            "check_window",
            c.check_window != first.check_window,
            c.check_window.to_string(),
        ),
    ];
    match differs.into_iter().find(|d| d.1) {
        Some((parameter, _, value)) => Err(Error::parameter(
            parameter,
            value,
            "runs packed together must share w, precision and fit windows",
        )),
        None => Ok(()),
    }
}

/// Refuses a per-event audit of an MPFR run (the audit replays `f64` events in MPFR).
/// The parameters a diffusion run refused for its work lowers: its collisions, and its precision
/// in MPFR.
pub(crate) fn work_lower(precision: Precision) -> &'static [&'static str] {
    match precision {
        Precision::F64 => &["collisions"],
        Precision::Bits(_) => &["collisions", "precision"],
    }
}

fn check_audit(options: &RunOptions, precision: Precision) -> Result<(), Error> {
    if options.audit.is_some() && precision != Precision::F64 {
        return Err(Error::parameter(
            "precision",
            precision,
            "the per-event audit replays f64 events in MPFR: it applies to f64 runs only",
        ));
    }
    Ok(())
}

/// The work kept at `options.resume` (nothing without it), with the trajectories in flight saved
/// at `options.checkpoint_every` (finished batches only with a per-event audit).
fn open_keeper<C: Serialize>(
    options: &RunOptions,
    kind: &str,
    config: &C,
    meta: Option<RunMeta>,
    jobs: &[Job],
) -> Result<DiffusionKeeper, Error> {
    let every = options.audit.is_none().then_some(options.checkpoint_every);
    let quotas: Vec<_> = jobs.iter().map(Job::quota).collect();
    let fits =
        |q: &Quota, b: &BatchResult| b.index == q.index && b.counters.collisions == q.collisions;
    let keep = DiffusionKeeper::open(
        options.resume.as_deref(),
        kind,
        config,
        meta,
        &quotas,
        every,
        &fits,
    )?
    .watching(options.stop.as_ref());
    (options.progress)(keep.collisions_done(&quotas));
    Ok(keep)
}

/// A resumed run's exact identities (mean free path, hop time, collisions per hop against their
/// closed forms), each within the Student-t equivalent of 4σ for its batches: work taken from a
/// checkpoint that measured something else (another gap, an edited value) fails them.
fn check_resumed_identities(rep: &DiffusionReport, path: Option<&Path>) -> Result<(), Error> {
    let n = rep.batch_D.len();
    if n < 2 {
        return Ok(());
    }
    let bound = crate::statistics::normal_sigma_equivalent_t(n as f64 - 1.0, 4.0);
    let checks = [
        (
            "mean free path",
            rep.mean_free_path,
            rep.mean_free_path_err,
            rep.mean_free_path_exact,
        ),
        (
            "mean hop time",
            rep.tau_hop,
            rep.tau_hop_err,
            rep.tau_hop_exact,
        ),
        (
            "collisions per hop",
            rep.collisions_per_hop,
            rep.collisions_per_hop_err,
            rep.collisions_per_hop_exact,
        ),
    ];
    for (what, x, err, exact) in checks {
        let t = (x - exact) / err;
        if t.is_nan() || t.abs() > bound {
            return Err(Error::Failed(format!(
                "the run resumed from {} fails an exact identity: {what} {x} is {t:+.1} standard \
                 errors from its closed form {exact} (bound {bound:.2} for {n} batches): the \
                 checkpoint holds work of another configuration; delete it and run again",
                path.map_or_else(|| "its checkpoint".into(), |p| p.display().to_string())
            )));
        }
    }
    Ok(())
}

/// Several runs at the same w and fit windows (a sweep point's independent runs), their
/// trajectories packed together into SIMD blocks: each report has the same bits as [`run`]
/// of its configuration alone. With a journal file (`options.resume`), every finished batch is
/// appended to it at once and the trajectories in flight every `options.checkpoint_every`, and
/// work already there (for the same configurations) continues, so an interrupted point loses at
/// most one interval.
///
/// # Errors
/// If the configurations differ in w, precision or windows, any is invalid, or the journal
/// belongs to other configurations or was edited.
pub fn run_many(
    cfgs: &[DiffusionConfig],
    options: &RunOptions,
) -> Result<Vec<DiffusionReport>, Error> {
    options.accept(
        "diffusion (packed runs)",
        &[
            RunOption::Engine,
            RunOption::Resume,
            RunOption::CheckpointEvery,
        ],
    )?;
    let Some(first) = cfgs.first() else {
        return Ok(Vec::new());
    };
    for c in cfgs {
        c.validate()?;
        check_packable(first, c)?;
    }
    let (spec, g) = setup(first, options.engine, options.threads, None)?;
    let (resolved, tau) = (spec.engine, spec.watch.tau);
    let start = Instant::now();
    let jobs: Vec<Job> = cfgs.iter().flat_map(DiffusionConfig::jobs).collect();
    let keep = open_keeper(options, PACKED_KIND, &cfgs, None, &jobs)?;
    resumed::recheck_one_batch(
        &keep,
        &jobs,
        cfgs,
        (options.engine, options.stop.as_ref()),
        options.resume.as_deref(),
    )?;
    let todo: Vec<Job> = jobs
        .into_iter()
        .filter(|j| !keep.is_finished(&j.quota()))
        .collect();
    let new = execute(&todo, spec, &keep, options.progress)?;
    let seconds = start.elapsed().as_secs_f64();
    let run_now: u64 = new
        .iter()
        .map(|b| b.counters.collisions)
        .sum::<u64>()
        .saturating_sub(keep.in_flight_collisions(None));
    let mut all: Vec<(u64, BatchResult)> = keep.finished().map(|(r, b)| (r, b.clone())).collect();
    all.extend(todo.iter().map(|j| j.run).zip(new));
    let mut out = Vec::with_capacity(cfgs.len());
    for c in cfgs {
        let mut done: Vec<BatchResult> = all
            .iter()
            .filter(|(r, _)| *r == c.run)
            .map(|(_, b)| b.clone())
            .collect();
        done.sort_by_key(|b| b.index);
        let resumed = done.len() as u32 - todo.iter().filter(|j| j.run == c.run).count() as u32;
        let n: u64 = done.iter().map(|b| b.counters.collisions).sum();
        let mut rep = summarise(c, &g, tau, &done, options.threads, seconds, resumed, n)?;
        rep.collisions_per_second = run_now as f64 / seconds;
        rep.resumed_collisions = keep.in_flight_collisions(Some(c.run))
            + keep
                .finished()
                .filter(|(r, _)| *r == c.run)
                .map(|(_, b)| b.counters.collisions)
                .sum::<u64>();
        rep.meta = rep.meta.with_engine(resolved);
        if resumed > 0 || keep.in_flight_count() > 0 {
            check_resumed_identities(&rep, options.resume.as_deref())?;
        }
        out.push(rep);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn precision_parsing() {
        assert_eq!("f64".parse::<Precision>().unwrap(), Precision::F64);
        assert_eq!("256".parse::<Precision>().unwrap(), Precision::Bits(256));
        assert!("52".parse::<Precision>().is_err());
        assert!("abc".parse::<Precision>().is_err());
    }

    #[test]
    fn window_lags() {
        let w: Window = "10:40".parse().unwrap();
        assert_eq!(w.lags(), vec![10, 15, 20, 25, 30, 35, 40]);
        assert!("40:10".parse::<Window>().is_err());
        assert!("0:10".parse::<Window>().is_err());
    }
}
