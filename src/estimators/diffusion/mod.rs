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

use std::fs::OpenOptions;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::sync::Mutex;
use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::engine::metadata::RunMeta;
use crate::engine::simd::BLOCK;
use crate::engine::{drive, run_block, Engine, Resolved, SimdPath};
use crate::kernel::trap::Trap;
use crate::numbers::lanes::Lanes;
use crate::numbers::precision::AtPrecision;
use crate::observers::counters::{CounterLanes, Counters};
use crate::observers::msd::Msd;
use crate::observers::{EventLanes, Observer};
use crate::scenes::triangular::geometry::{check_diffusive_gap, Geometry};
use crate::Error;
/// Refuses a scene in which the diffusion coefficient does not exist: with an infinite horizon
/// (collision-free corridors) free flights have a distribution with ⟨ℓ²⟩ = ∞, the mean squared
/// displacement grows like t ln t and the Einstein limit ⟨Δr²⟩/4t diverges (Bleher 1992).
///
/// # Errors
/// For an infinite-horizon scene, with the reason.
pub fn require_finite_horizon<S: crate::scenes::Scene>(scene: &S) -> Result<(), Error> {
    if scene.finite_horizon() {
        return Ok(());
    }
    Err(Error::Invalid(format!(
        "{} has an infinite horizon (collision-free corridors): the mean squared displacement grows like t ln t and the diffusion coefficient does not exist; use the triangular scene with 0 < w < w_inf = 0.3094...",
        scene.label()
    )))
}

use crate::engine::options::{AuditSpec, RunOptions};
use crate::numbers::precision::Precision;
use crate::numbers::real::Real;
use crate::scenes::lattice::{Basis64, LatticeState, TriangularLattice};
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::triangular::{equilibrium_state, TriangularScene};
use crate::statistics::{linear_fit, mean_se};
use crate::verification::shadow_audit::{AuditLanes, AuditSummary, Auditor};

/// A fit window in units of the mean hop time τ.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Window {
    /// Start, in units of τ.
    pub lo: usize,
    /// End, in units of τ.
    pub hi: usize,
}

impl Window {
    /// Seven lags evenly spaced over the window (in units of τ).
    pub fn lags(&self) -> Vec<usize> {
        let mut v: Vec<usize> = (0..7)
            .map(|k| self.lo + ((self.hi - self.lo) * k + 3) / 6)
            .collect();
        v.dedup();
        v
    }
}

impl FromStr for Window {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        let bad = || {
            Error::Invalid(format!(
                "fit window '{s}' must be LO:HI in units of tau, 1 <= LO < HI <= 100000"
            ))
        };
        let (a, b) = s.split_once(':').ok_or_else(bad)?;
        let lo: usize = a.trim().parse().map_err(|_| bad())?;
        let hi: usize = b.trim().parse().map_err(|_| bad())?;
        if lo < 1 || hi <= lo || hi > 100_000 {
            return Err(bad());
        }
        Ok(Window { lo, hi })
    }
}

/// A batch must cover the end of the later fit window this many times (so that the MSD at the
/// longest lag averages over many independent time origins).
pub const MIN_HOPS_PER_LAG: usize = 20;

/// Everything that defines a diffusion run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DiffusionConfig {
    /// Gap w (the exact double given).
    pub w: f64,
    /// Total number of collisions over all batches.
    pub collisions: u64,
    /// Number of independent batches (trajectories).
    pub batches: u32,
    /// Seed of the random streams.
    pub seed: u64,
    /// Which run of this seed (0 for a single run; run r of sweep point i is i·runs + r): batch b
    /// uses the trajectory stream `(seed, run, b)` ([`crate::scenes::sampling::StreamKey`]).
    #[serde(default)]
    pub run: u64,
    /// Number type.
    pub precision: Precision,
    /// Fit window for D.
    pub window: Window,
    /// Later window, fitted as a check of the linear regime.
    pub check_window: Window,
}

impl DiffusionConfig {
    /// The default run at `w`: 2·10⁹ collisions in 32 batches, windows [10τ, 40τ] and [20τ, 80τ].
    pub fn new(w: f64) -> Self {
        DiffusionConfig {
            w,
            collisions: 2_000_000_000,
            batches: 32,
            seed: 1,
            run: 0,
            precision: Precision::F64,
            window: Window { lo: 10, hi: 40 },
            check_window: Window { lo: 20, hi: 80 },
        }
    }

    /// Checks every parameter; errors name the valid range.
    pub fn validate(&self) -> Result<(), Error> {
        check_diffusive_gap(self.w)?;
        if self.collisions == 0 {
            return Err(Error::Zero { what: "collisions" });
        }
        if self.batches == 0 {
            return Err(Error::Zero { what: "batches" });
        }
        if self.batches < 2 {
            return Err(Error::TooFew {
                what: "batches",
                min: 2,
                got: self.batches as u64,
            });
        }
        crate::engine::parallel::check_batches("batches", self.batches)?;
        crate::engine::check_trajectory_length(self.collisions.div_ceil(self.batches as u64))?;
        if let Precision::Bits(b) = self.precision {
            <rug::Float as Real>::check_ctx(b)?;
        }
        // Each batch must be long enough to reach the far end of the check window many times.
        let g = Geometry::new(self.w)?;
        let need_hops = (MIN_HOPS_PER_LAG * self.window.hi.max(self.check_window.hi)) as f64;
        let min = need_hops * g.collisions_per_hop() * self.batches as f64;
        if (self.collisions as f64) < min {
            return Err(if min < u64::MAX as f64 {
                Error::TooFew {
                    what: "collisions (for this w, window and batch count)",
                    min: min.ceil() as u64,
                    got: self.collisions,
                }
            } else {
                Error::Invalid(format!(
                    "w = {:?} needs about {min:.1e} collisions for {} batches to reach the fit \
                     window (pi/(3w) = {:.1e} collisions per hop), more than any run can do \
                     (2^64 = 1.8e19): use a larger w",
                    self.w,
                    self.batches,
                    g.collisions_per_hop()
                ))
            });
        }
        Ok(())
    }

    /// The trajectories of this run: batch i follows the stream (seed, run, i) for its share of
    /// the collisions.
    fn jobs(&self) -> impl Iterator<Item = Job> + '_ {
        (0..self.batches).map(move |i| Job {
            seed: self.seed,
            run: self.run,
            index: i,
            collisions: crate::engine::parallel::share(self.collisions, self.batches, i),
        })
    }

    /// The lags (in units of τ) the MSD is accumulated at: those of both fit windows.
    pub fn lags(&self) -> Vec<usize> {
        let mut l = self.window.lags();
        l.extend(self.check_window.lags());
        l.sort_unstable();
        l.dedup();
        l
    }
}

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
            return Err(Error::Invalid(format!(
                "batch {i}: the run has batches 0 to {}",
                cfg.batches - 1
            )));
        }
    }
    let jobs: Vec<Job> = cfg.jobs().filter(|j| indices.contains(&j.index)).collect();
    let mut r = execute(&jobs, spec, &|_, _| Ok(()), progress)?;
    r.sort_by_key(|b| b.index);
    Ok(r)
}

/// The `f64` start of batch `index` of `cfg`: the state its trajectory starts from in the run
/// (the equilibrium state of its stream (seed, run, index)).
pub fn batch_start(cfg: &DiffusionConfig, index: u32) -> Result<LatticeState<f64>, Error> {
    let trap64 = Trap::new(cfg.w)?;
    let job = Job {
        seed: cfg.seed,
        run: cfg.run,
        index,
        collisions: 0,
    };
    Ok(job.start::<f64>(&trap64, ()))
}

/// One trajectory of a run: which stream starts it and how many collisions it makes.
#[derive(Debug, Clone, Copy)]
struct Job {
    seed: u64,
    run: u64,
    index: u32,
    collisions: u64,
}

impl Job {
    /// The start: a point of the invariant measure from the trajectory stream `(seed, run,
    /// index)`, its speed normalised at the working precision.
    fn start<T: Real>(&self, trap64: &Trap<f64>, ctx: T::Ctx) -> LatticeState<T> {
        let mut rng = StreamKey::new(self.seed, Purpose::Trajectory, self.index as u64)
            .in_run(self.run)
            .rng();
        let s64 = equilibrium_state(trap64, &mut rng);
        let mut s = LatticeState::<T>::convert_from_f64(ctx, &s64);
        s.flight.normalise_speed();
        s
    }

    fn auditor(
        &self,
        trap64: &Trap<f64>,
        audit: Option<AuditSpec>,
    ) -> Result<Option<Auditor<TriangularScene>>, Error> {
        audit
            .map(|a| {
                Auditor::new(
                    &TriangularScene::new(trap64.w)?,
                    a.rate,
                    a.bits,
                    StreamKey::new(self.seed, Purpose::Audit, self.index as u64)
                        .in_run(self.run)
                        .rng(),
                )
            })
            .transpose()
    }
}

/// What a diffusion run watches along each trajectory: counters, the MSD, and optionally the
/// per-event shadow audit.
struct BatchObservers {
    counters: CounterLanes,
    msd: Msd,
    audit: Option<AuditLanes<TriangularScene>>,
}

impl BatchObservers {
    fn new(
        jobs: &[Job],
        lanes: usize,
        trap64: &Trap<f64>,
        basis: Basis64,
        tau: f64,
        lags: &[usize],
        audit: Option<AuditSpec>,
    ) -> Result<Self, Error> {
        let audit = match audit {
            Some(_) => {
                let mut v = Vec::with_capacity(lanes);
                for j in jobs {
                    v.push(j.auditor(trap64, audit)?);
                }
                v.resize_with(lanes, || None);
                Some(AuditLanes {
                    lanes: v,
                    error: None,
                })
            }
            None => None,
        };
        Ok(BatchObservers {
            counters: CounterLanes::new(lanes),
            msd: Msd::new(tau, lags, basis, lanes),
            audit,
        })
    }

    /// The results of the jobs, lane by lane.
    fn results(mut self, jobs: &[Job], seconds: f64) -> Result<Vec<BatchResult>, Error> {
        if let Some(e) = self.audit.as_mut().and_then(|a| a.error.take()) {
            return Err(e);
        }
        let mut audits = self.audit.map(|a| a.lanes);
        Ok(jobs
            .iter()
            .enumerate()
            .map(|(l, j)| BatchResult {
                index: j.index,
                counters: self.counters.lane(l),
                lags: self.msd.lags().to_vec(),
                msd: self.msd.values(l),
                seconds,
                audit: audits.as_mut().and_then(|a| a[l].take()).map(|a| a.summary),
            })
            .collect())
    }
}

impl<const L: usize> Observer<L> for BatchObservers {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        self.counters.observe::<V>(steps);
        self.msd.observe::<V>(steps);
        if let Some(a) = self.audit.as_mut() {
            a.observe::<V>(steps);
        }
    }
}

/// Runs one trajectory on the scalar engine at number type `T`.
fn run_scalar<T: Real>(
    lat: &TriangularLattice<T>,
    trap64: &Trap<f64>,
    job: Job,
    tau: f64,
    lags: &[usize],
    audit: Option<AuditSpec>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<BatchResult, Error> {
    let start = Instant::now();
    let mut s = job.start::<T>(trap64, lat.trap().a.ctx());
    let mut obs = BatchObservers::new(&[job], 1, trap64, lat.basis_f64(), tau, lags, audit)?;
    drive(lat, &mut s, job.collisions, &mut obs, progress)?;
    let mut r = obs.results(&[job], start.elapsed().as_secs_f64())?;
    Ok(r.remove(0))
}

/// Runs up to [`BLOCK`] trajectories together on the SIMD engine (`f64`, bit-identical to
/// [`run_scalar`] lane by lane).
fn run_simd(
    path: SimdPath,
    trap64: &Trap<f64>,
    jobs: &[Job],
    tau: f64,
    lags: &[usize],
    audit: Option<AuditSpec>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<BatchResult>, Error> {
    let start = Instant::now();
    let mut states: Vec<LatticeState<f64>> = jobs.iter().map(|j| j.start(trap64, ())).collect();
    let quotas: Vec<u64> = jobs.iter().map(|j| j.collisions).collect();
    // The basis the scalar engine's f64 lattice has (`Lattice::basis_f64`).
    let basis = TriangularLattice::from_kernel(trap64.clone()).basis_f64();
    let mut obs = BatchObservers::new(jobs, BLOCK, trap64, basis, tau, lags, audit)?;
    run_block(path, trap64, &mut states, &quotas, &mut obs, progress)?;
    // The block's wall time, shared out: each batch's `seconds` is its part of the block.
    let seconds = start.elapsed().as_secs_f64() / jobs.len() as f64;
    obs.results(jobs, seconds)
}

fn d_of_batch(b: &BatchResult, tau: f64, win: &Window) -> f64 {
    let (mut x, mut y) = (Vec::new(), Vec::new());
    for (lag, m) in b.lags.iter().zip(&b.msd) {
        if *lag >= win.lo && *lag <= win.hi {
            x.push(*lag as f64 * tau);
            y.push(*m);
        }
    }
    linear_fit(&x, &y).1 / 4.0
}

/// What a run (or runs packed together) at `cfg`'s w and windows needs before its trajectories
/// start: how they execute (the engine that will run them, τ, the MSD lags, the audit) and the
/// geometry.
fn setup(
    cfg: &DiffusionConfig,
    engine: Engine,
    threads: usize,
    audit: Option<AuditSpec>,
) -> Result<(ExecSpec, Geometry<f64>), Error> {
    if threads == 0 {
        return Err(Error::Zero { what: "threads" });
    }
    let g = Geometry::new(cfg.w)?;
    let spec = ExecSpec {
        w: cfg.w,
        precision: cfg.precision,
        engine: engine.resolve(cfg.precision == Precision::F64)?,
        threads,
        tau: g.hop_time(),
        lags: cfg.lags(),
        audit,
    };
    Ok((spec, g))
}

/// Runs the configured computation. The result has the same bits on every engine and at every
/// thread count; only `seconds`, the speed and the metadata's engine differ.
///
/// `options.progress` receives collision counts as they are done. With `options.resume` (a
/// checkpoint file), every finished batch is appended to it at once and batches already there
/// (from the same configuration) are not run again. `options.audit` replays a fraction of the
/// events in MPFR as the run goes (`f64` runs only).
///
/// # Errors
/// An invalid configuration or options (before any work), a checkpoint of another
/// configuration, or an I/O error.
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
    options.validate()?;
    let (engine, threads, audit, progress) = (
        options.engine,
        options.threads,
        options.audit,
        options.progress,
    );
    let checkpoint = options.resume.as_ref();
    cfg.validate()?;
    if audit.is_some() && cfg.precision != Precision::F64 {
        return Err(Error::Invalid(
            "--audit replays f64 events in MPFR: it applies to f64 runs only".into(),
        ));
    }
    let (spec, g) = setup(cfg, engine, threads, audit)?;
    let (resolved, tau) = (spec.engine, spec.tau);
    let start = Instant::now();

    let mut done: Vec<BatchResult> = match checkpoint {
        Some(p) => load_checkpoint(p, cfg)?,
        None => Vec::new(),
    };
    let resumed = done.len() as u32;
    for b in &done {
        progress(b.counters.collisions);
    }
    let todo: Vec<Job> = cfg
        .jobs()
        .filter(|j| !done.iter().any(|b| b.index == j.index))
        .collect();
    let writer = match checkpoint {
        Some(p) => Some(Mutex::new(open_checkpoint(p, cfg)?)),
        None => None,
    };
    let record = |_: &Job, r: &BatchResult| append_line(writer.as_ref(), "checkpoint", r);
    let new = execute(&todo, spec, &record, progress)?;
    let run_now: u64 = new.iter().map(|b| b.counters.collisions).sum();
    done.extend(new);
    done.sort_by_key(|b| b.index);
    let seconds = start.elapsed().as_secs_f64();
    let mut rep = summarise(cfg, &g, tau, &done, threads, seconds, resumed, run_now);
    rep.meta = rep.meta.with_engine(resolved);
    Ok(rep)
}

/// Appends `v` as one JSON line to the checkpoint or journal `writer` (if any) and flushes it, so
/// that a finished batch survives an interruption; `what` names the file in errors.
fn append_line<T: Serialize>(
    writer: Option<&Mutex<std::fs::File>>,
    what: &str,
    v: &T,
) -> Result<(), Error> {
    if let Some(wr) = writer {
        let mut f = wr
            .lock()
            .map_err(|_| Error::Io(format!("{what} lock poisoned")))?;
        writeln!(
            f,
            "{}",
            serde_json::to_string(v).map_err(|e| Error::Io(e.to_string()))?
        )?;
        f.flush()?;
    }
    Ok(())
}

/// Header of a [`run_many`] journal: the configurations it belongs to.
#[derive(Serialize, Deserialize)]
struct JournalHeader {
    format: u32,
    configs: Vec<DiffusionConfig>,
}

/// One finished batch in a [`run_many`] journal.
#[derive(Serialize, Deserialize)]
struct JournalEntry {
    run: u64,
    batch: BatchResult,
}

/// The finished batches of a journal written for `cfgs`, by (run, batch index); a line torn by an
/// interruption is ignored (that batch runs again).
fn load_journal(p: &std::path::Path, cfgs: &[DiffusionConfig]) -> Result<Vec<JournalEntry>, Error> {
    let f = match std::fs::File::open(p) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e.into()),
    };
    let mut lines = BufReader::new(f).lines();
    let Some(header) = lines.next() else {
        return Ok(Vec::new());
    };
    let h: JournalHeader = serde_json::from_str(&header?)
        .map_err(|e| Error::Io(format!("{}: not a lorentz journal ({e})", p.display())))?;
    if h.format != CHECKPOINT_FORMAT || h.configs != cfgs {
        return Err(Error::Invalid(format!(
            "{} belongs to other runs (or another version): use another directory",
            p.display()
        )));
    }
    let mut out: Vec<JournalEntry> = Vec::new();
    for l in lines {
        if let Ok(e) = serde_json::from_str::<JournalEntry>(&l?) {
            if !out
                .iter()
                .any(|o| o.run == e.run && o.batch.index == e.batch.index)
            {
                out.push(e);
            }
        }
    }
    Ok(out)
}

/// Several runs at the same w and fit windows (a sweep point's independent runs), their
/// trajectories packed together into SIMD blocks: each report has the same bits as [`run`]
/// of its configuration alone. With a journal file (`options.resume`), every finished batch is appended to it at
/// once and batches already there (for the same configurations) are not run again, so an
/// interrupted point loses at most the blocks in flight.
///
/// # Errors
/// If the configurations differ in w, precision or windows, any is invalid, or the journal
/// belongs to other configurations.
pub fn run_many(
    cfgs: &[DiffusionConfig],
    options: &RunOptions,
) -> Result<Vec<DiffusionReport>, Error> {
    options.validate()?;
    let (engine, threads, progress) = (options.engine, options.threads, options.progress);
    let journal = options.resume.as_deref();
    let Some(first) = cfgs.first() else {
        return Ok(Vec::new());
    };
    for c in cfgs {
        c.validate()?;
        if c.w != first.w
            || c.precision != first.precision
            || c.window != first.window
            || c.check_window != first.check_window
        {
            return Err(Error::Invalid(
                "runs packed together must share w, precision and fit windows".into(),
            ));
        }
    }
    let (spec, g) = setup(first, engine, threads, None)?;
    let (resolved, tau) = (spec.engine, spec.tau);
    let start = Instant::now();
    let jobs: Vec<Job> = cfgs.iter().flat_map(DiffusionConfig::jobs).collect();
    let finished = match journal {
        Some(p) => load_journal(p, cfgs)?,
        None => Vec::new(),
    };
    for e in &finished {
        progress(e.batch.counters.collisions);
    }
    let todo: Vec<Job> = jobs
        .iter()
        .filter(|j| {
            !finished
                .iter()
                .any(|e| e.run == j.run && e.batch.index == j.index)
        })
        .copied()
        .collect();
    let writer = match journal {
        Some(p) => Some(Mutex::new(open_appending(
            p,
            &JournalHeader {
                format: CHECKPOINT_FORMAT,
                configs: cfgs.to_vec(),
            },
        )?)),
        None => None,
    };
    let record = |j: &Job, r: &BatchResult| {
        let e = JournalEntry {
            run: j.run,
            batch: r.clone(),
        };
        append_line(writer.as_ref(), "journal", &e)
    };
    let new = execute(&todo, spec, &record, progress)?;
    let seconds = start.elapsed().as_secs_f64();
    let run_now: u64 = new.iter().map(|b| b.counters.collisions).sum();
    let mut all: Vec<(u64, BatchResult)> = finished.into_iter().map(|e| (e.run, e.batch)).collect();
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
        let mut rep = summarise(c, &g, tau, &done, threads, seconds, resumed, n);
        rep.collisions_per_second = run_now as f64 / seconds;
        rep.meta = rep.meta.with_engine(resolved);
        out.push(rep);
    }
    Ok(out)
}

/// How the trajectories of [`execute`] run.
struct ExecSpec {
    w: f64,
    precision: Precision,
    engine: Resolved,
    threads: usize,
    tau: f64,
    lags: Vec<usize>,
    audit: Option<AuditSpec>,
}

/// Runs `jobs` on `spec.threads` threads — one job per task on the scalar engine, blocks of
/// [`BLOCK`] jobs on the SIMD engine — handing each finished result to `record` at once.
/// Results come back in job order.
fn execute(
    jobs: &[Job],
    spec: ExecSpec,
    record: &(dyn Fn(&Job, &BatchResult) -> Result<(), Error> + Sync),
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<BatchResult>, Error> {
    for j in jobs {
        crate::engine::check_trajectory_length(j.collisions)?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(spec.threads)
        .build()
        .map_err(|e| Error::Invalid(format!("thread pool: {e}")))?;
    let trap64 = Trap::new(spec.w)?;
    match spec.engine {
        Resolved::Simd(path) => {
            let blocks: Vec<&[Job]> = jobs.chunks(BLOCK).collect();
            let out: Vec<Vec<BatchResult>> = pool.install(|| {
                blocks
                    .par_iter()
                    .map(|b| {
                        let r =
                            run_simd(path, &trap64, b, spec.tau, &spec.lags, spec.audit, progress)?;
                        for (j, x) in b.iter().zip(&r) {
                            record(j, x)?;
                        }
                        Ok(r)
                    })
                    .collect::<Result<_, Error>>()
            })?;
            Ok(out.into_iter().flatten().collect())
        }
        Resolved::Scalar => spec.precision.dispatch(RunScalar {
            jobs,
            w: spec.w,
            trap64: &trap64,
            tau: spec.tau,
            lags: &spec.lags,
            audit: spec.audit,
            pool: &pool,
            record,
            progress,
        }),
    }
}

/// The jobs on the scalar engine, at the number type of the run's precision.
struct RunScalar<'a> {
    jobs: &'a [Job],
    w: f64,
    trap64: &'a Trap<f64>,
    tau: f64,
    lags: &'a [usize],
    audit: Option<AuditSpec>,
    pool: &'a rayon::ThreadPool,
    record: &'a (dyn Fn(&Job, &BatchResult) -> Result<(), Error> + Sync),
    progress: &'a (dyn Fn(u64) + Sync),
}

impl AtPrecision for RunScalar<'_> {
    type Output = Result<Vec<BatchResult>, Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Self::Output {
        let lat = TriangularLattice::new(T::from_f64(ctx, self.w))?;
        self.pool.install(|| {
            self.jobs
                .par_iter()
                .map(|&j| {
                    let r = run_scalar(
                        &lat,
                        self.trap64,
                        j,
                        self.tau,
                        self.lags,
                        self.audit,
                        self.progress,
                    )?;
                    (self.record)(&j, &r)?;
                    Ok(r)
                })
                .collect()
        })
    }
}

#[allow(clippy::too_many_arguments)]
fn summarise(
    cfg: &DiffusionConfig,
    g: &Geometry<f64>,
    tau: f64,
    done: &[BatchResult],
    threads: usize,
    seconds: f64,
    resumed: u32,
    run_now: u64,
) -> DiffusionReport {
    let ds: Vec<f64> = done
        .iter()
        .map(|b| d_of_batch(b, tau, &cfg.window))
        .collect();
    let dc: Vec<f64> = done
        .iter()
        .map(|b| d_of_batch(b, tau, &cfg.check_window))
        .collect();
    let ratio = |f: &dyn Fn(&Counters) -> f64| {
        mean_se(&done.iter().map(|b| f(&b.counters)).collect::<Vec<_>>())
    };
    let (d, d_err) = mean_se(&ds);
    let (dcv, dce) = mean_se(&dc);
    let (mfp, mfp_e) = ratio(&|c| c.time / c.collisions as f64);
    let (th, th_e) = ratio(&|c| c.time / c.crossings as f64);
    let (cph, cph_e) = ratio(&|c| c.collisions as f64 / c.crossings as f64);
    let lags = &done[0].lags;
    let msd_times: Vec<f64> = lags.iter().map(|&l| l as f64 * tau).collect();
    let msd_over_4t: Vec<Estimate> = (0..lags.len())
        .map(|k| {
            let v: Vec<f64> = done
                .iter()
                .map(|b| b.msd[k] / (4.0 * msd_times[k]))
                .collect();
            let (value, err) = mean_se(&v);
            Estimate { value, err }
        })
        .collect();
    let total: u64 = done.iter().map(|b| b.counters.collisions).sum();
    let audit =
        done.iter()
            .filter_map(|b| b.audit.as_ref())
            .fold(None, |acc: Option<AuditSummary>, a| {
                let mut m = acc.unwrap_or_default();
                m.merge(a);
                Some(m)
            });
    DiffusionReport {
        w: cfg.w,
        D: d,
        D_err: d_err,
        window: cfg.window,
        D_check: dcv,
        D_check_err: dce,
        check_window: cfg.check_window,
        D_MZ: g.d_mz(),
        D_Bo: g.d_bo(),
        mean_free_path: mfp,
        mean_free_path_err: mfp_e,
        mean_free_path_exact: g.mean_free_path(),
        tau_hop: th,
        tau_hop_err: th_e,
        tau_hop_exact: tau,
        collisions_per_hop: cph,
        collisions_per_hop_err: cph_e,
        collisions_per_hop_exact: g.collisions_per_hop(),
        msd_times,
        msd_over_4t: msd_over_4t.iter().map(|e| e.value).collect(),
        msd_over_4t_err: msd_over_4t.iter().map(|e| e.err).collect(),
        longest_free_path: done
            .iter()
            .map(|b| b.counters.longest_free_path)
            .fold(0.0, f64::max),
        collisions: total,
        seconds,
        collisions_per_second: run_now as f64 / seconds,
        resumed_batches: resumed,
        audit,
        config: Some(cfg.clone()),
        batch_D: ds,
        batch_D_check: dc,
        batch_msd: done.iter().map(|b| b.msd.clone()).collect(),
        meta: RunMeta::new(
            Some(cfg.seed),
            Some(cfg.batches as u64),
            cfg.precision,
            Some(threads),
        ),
    }
}

#[derive(Serialize, Deserialize)]
struct CheckpointHeader {
    /// [`CHECKPOINT_FORMAT`]; absent in files of the old stream scheme.
    #[serde(default)]
    format: u32,
    config: DiffusionConfig,
    meta: Option<RunMeta>,
}

/// Format of checkpoint files: 2 since random streams are named by keys
/// ([`crate::scenes::sampling::StreamKey`]), 3 since the MSD's time origins are every gcd(lags)·τ
/// ([`Msd`]). A file of another format holds batches of another estimator or other streams and
/// is refused rather than mixed with new ones.
const CHECKPOINT_FORMAT: u32 = 3;

fn load_checkpoint(p: &PathBuf, cfg: &DiffusionConfig) -> Result<Vec<BatchResult>, Error> {
    let f = match std::fs::File::open(p) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e.into()),
    };
    let mut lines = BufReader::new(f).lines();
    let header = match lines.next() {
        Some(l) => l?,
        None => return Ok(Vec::new()),
    };
    let h: CheckpointHeader = serde_json::from_str(&header)
        .map_err(|e| Error::Io(format!("{}: not a lorentz checkpoint ({e})", p.display())))?;
    if h.format != CHECKPOINT_FORMAT {
        return Err(Error::Invalid(format!(
            "checkpoint {} has format {} (this version writes {CHECKPOINT_FORMAT}, with other random \
             streams): its batches cannot be combined with new ones; use another file",
            p.display(),
            h.format
        )));
    }
    if h.config != *cfg {
        return Err(Error::Invalid(format!(
            "checkpoint {} belongs to another run ({:?}); use another file or the same parameters",
            p.display(),
            h.config
        )));
    }
    let mut out: Vec<BatchResult> = Vec::new();
    for l in lines {
        let l = l?;
        // A line cut short by an interruption is ignored: that batch is simply run again.
        if let Ok(b) = serde_json::from_str::<BatchResult>(&l) {
            if !out.iter().any(|o| o.index == b.index) {
                out.push(b);
            }
        }
    }
    Ok(out)
}

fn open_checkpoint(p: &Path, cfg: &DiffusionConfig) -> Result<std::fs::File, Error> {
    open_appending(
        p,
        &CheckpointHeader {
            format: CHECKPOINT_FORMAT,
            config: cfg.clone(),
            meta: Some(RunMeta::new(
                Some(cfg.seed),
                Some(cfg.batches as u64),
                cfg.precision,
                None,
            )),
        },
    )
}

/// Opens the checkpoint or journal `p` for appending: a new (or empty) file gets `header` as its
/// first line; an existing one gets a newline first, so that a line cut short by an
/// interruption does not swallow the next record.
fn open_appending<H: Serialize>(p: &Path, header: &H) -> Result<std::fs::File, Error> {
    let fresh = std::fs::metadata(p).map(|m| m.len() == 0).unwrap_or(true);
    let mut f = OpenOptions::new().create(true).append(true).open(p)?;
    if fresh {
        writeln!(
            f,
            "{}",
            serde_json::to_string(header).map_err(|e| Error::Io(e.to_string()))?
        )?;
    } else {
        writeln!(f)?;
    }
    Ok(f)
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
