//! D on any table: the Einstein estimator of [`super`] for a billiard given as a [`Scene`], a
//! scene of the crate's or one defined outside it.
//!
//! The same batches, streams, observers, checkpoints and per-event audit as [`super::run`], at
//! any precision on the scalar engine, and in `f64` on the SIMD lanes where the scene's kernel is
//! the generic convex-cell kernel (a table given as data: [`crate::engine::cells`], the scalar
//! kernel's bits in every lane). The MSD's time grid is in units of the scene's crossing time τ = π|Q|/L
//! ([`Scene::crossing_time`]), or of the mean free time ⟨ℓ⟩ for a scene that does not supply
//! it. For the triangular scene τ is the paper's hop time, and the batches have the bits of
//! [`super::run`] on the scalar engine (`tests/numerics/scene_diffusion.rs`).
//!
//! Every result carries the scene's exact identities measured: the mean free path against
//! Santaló's π|Q|/|∂Q|, and (where the scene supplies τ) the mean crossing time and collisions
//! per crossing against τ and τ/⟨ℓ⟩, each as a Student-t statistic over the batches with its
//! 4σ-equivalent bound.

use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::execution::{BatchObservers, DiffusionKeeper, Job, Watch, curve_grid, in_blocks};
use super::summary::{merged_audit, msd_over_4t};
use super::{BatchResult, Sampling, open_keeper, time_unit};
use crate::Error;
use crate::engine::checkpoint::{drive_kept, run_block_kept};
use crate::engine::metadata::RunMeta;
use crate::engine::options::{AuditSpec, RunOption, RunOptions};
use crate::engine::simd::BLOCK;
use crate::engine::work::Work;
use crate::engine::{Engine, Resolved, SimdPath};
use crate::kernel::cell::ConvexCell;
use crate::numbers::precision::{AtPrecision, Precision};
use crate::numbers::real::Real;
use crate::observers::counters::Counters;
use crate::scenes::Scene;
use crate::scenes::lattice::Lattice;
use crate::statistics::{mean_se, normal_sigma_equivalent_t};
use crate::verification::shadow_audit::AuditSummary;

/// Kind of the records of a scene diffusion checkpoint.
const CHECKPOINT_KIND: &str = "scene diffusion trajectories";

impl Sampling {
    /// The lags (in time units) the MSD is accumulated at: those of both fit windows.
    fn lags(&self) -> Vec<usize> {
        super::config::lags(&self.window, &self.check_window)
    }

    /// Where the trajectories of a run on `scene` are watched.
    fn watch<S: Scene>(&self, scene: &S) -> Watch {
        Watch {
            tau: time_unit(scene),
            lags: self.lags(),
            curve: curve_grid(
                &self.msd_grid,
                scene.mean_free_path(),
                self.collisions,
                self.batches,
            ),
        }
    }

    fn jobs(&self) -> Vec<Job> {
        super::config::jobs(self.seed, self.run, self.collisions, self.batches).collect()
    }
}

/// One exact identity of the scene, measured: the batches' mean and standard error against the
/// closed form, as a Student-t statistic with its 4σ-equivalent bound.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Identity {
    /// What is measured ("mean free path", "crossing time", "collisions per crossing").
    pub name: String,
    /// Mean over the batches.
    pub measured: f64,
    /// Its standard error.
    pub err: f64,
    /// The closed form.
    pub exact: f64,
    /// (measured − exact)/err.
    pub t: f64,
    /// The Student-t equivalent of 4σ for batches − 1 degrees of freedom.
    pub bound: f64,
    /// |t| ≤ bound.
    pub agrees: bool,
}

/// The result of [`run_on`].
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SceneDiffusionReport {
    /// The scene's label.
    pub scene: String,
    /// The table as written, for a table given as data ([`Scene::table_spec`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<crate::scenes::table::spec::TableSpec>,
    /// The time unit of the windows and the MSD grid (τ, or ⟨ℓ⟩ without one).
    pub time_unit: f64,
    /// What the time unit is: `"mean crossing time tau"` (the scene's τ) or `"mean free time"`.
    pub time_unit_name: String,
    /// Diffusion coefficient (fit window `config.window`).
    pub D: f64,
    /// Its standard error over batches.
    pub D_err: f64,
    /// D from the later window (check of the linear regime).
    pub D_check: f64,
    /// Its standard error.
    pub D_check_err: f64,
    /// D − D_check paired over the batches (same trajectories: never added in quadrature).
    pub D_minus_D_check: f64,
    /// Its standard error.
    pub D_minus_D_check_err: f64,
    /// The exact identities measured (mean free path; crossing time and collisions per
    /// crossing where the scene supplies τ).
    pub identities: Vec<Identity>,
    /// Lag times at which the MSD was measured.
    pub msd_times: Vec<f64>,
    /// MSD/(4t) at those times (mean over batches).
    pub msd_over_4t: Vec<f64>,
    /// Its standard errors.
    pub msd_over_4t_err: Vec<f64>,
    /// The MSD curve on its logarithmic grid, with D by Green–Kubo (runs with
    /// [`super::MsdGrid::Log`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub msd_curve: Option<super::curve::MsdCurveReport>,
    /// D by Green–Kubo from the MSD curve against the Einstein D (runs with
    /// [`super::MsdGrid::Log`]).
    #[serde(flatten)]
    pub green_kubo: super::curve::GreenKuboD,
    /// Longest free path seen in the run.
    pub longest_free_path: f64,
    /// Total collisions.
    pub collisions: u64,
    /// Wall-clock seconds of this invocation.
    pub seconds: f64,
    /// Batches reused from a checkpoint.
    pub resumed_batches: u32,
    /// The self-audit, if requested.
    pub audit: Option<AuditSummary>,
    /// D of each batch, in batch order.
    pub batch_D: Vec<f64>,
    /// D of each batch in the check window.
    pub batch_D_check: Vec<f64>,
    /// The configuration.
    pub config: Sampling,
    /// Version, seed, batches, precision, engine, threads.
    pub meta: RunMeta,
}

impl SceneDiffusionReport {
    /// The identity named `name`, if measured.
    pub fn identity(&self, name: &str) -> Option<&Identity> {
        self.identities.iter().find(|i| i.name == name)
    }
}

/// The configuration a checkpoint of [`run_on`] is opened with: the scene's label beside the
/// run's parameters, so a checkpoint of another table is refused.
#[derive(Serialize)]
struct Header<'a> {
    scene: String,
    config: &'a Sampling,
}

/// D of `scene` by the Einstein formula (see the module documentation). `options`: `threads`,
/// `progress`, `resume` (a checkpoint file, as in [`super::run`]), `checkpoint_every`, `stop`,
/// and `audit` (`f64` runs); `engine` must be [`Engine::Auto`] or [`Engine::Scalar`].
///
/// # Errors
/// An invalid configuration or options, an infinite-horizon scene, a checkpoint of another run,
/// an I/O error, or a resumed run failing the scene's exact identities.
pub fn run_on<S: Scene>(
    scene: &S,
    cfg: &Sampling,
    options: &RunOptions,
) -> Result<SceneDiffusionReport, Error> {
    options.accept("diffusion", &RunOption::ALL)?;
    cfg.validate(scene)?;
    Work::new(
        "diffusion",
        super::work_lower(cfg.precision),
        cfg.collisions as f64,
    )
    .walking(scene)
    .at(cfg.precision)
    .audited(options.audit)
    .check(options.threads)?;
    let engine = engine_on(scene, cfg.precision, options.engine)?;
    super::check_audit(options, cfg.precision)?;
    let start = Instant::now();
    let jobs = cfg.jobs();
    let meta = RunMeta::new(
        Some(cfg.seed),
        Some(cfg.batches as u64),
        cfg.precision,
        None,
    );
    let header = Header {
        scene: scene.label(),
        config: cfg,
    };
    let keep = open_keeper(options, CHECKPOINT_KIND, &header, Some(meta), &jobs)?;
    let resumed = keep.finished().count() as u32;
    let todo: Vec<Job> = jobs
        .into_iter()
        .filter(|j| !keep.is_finished(&j.quota()))
        .collect();
    let new = match engine {
        Resolved::Simd(path) => lanes_on(scene, cfg, &todo, (path, options), &keep)?,
        Resolved::Scalar => execute_on(scene, cfg, &todo, options, &keep)?,
    };
    let mut done: Vec<BatchResult> = keep.finished().map(|(_, b)| b.clone()).collect();
    done.extend(new);
    done.sort_by_key(|b| b.index);
    let meta = RunMeta::new(
        Some(cfg.seed),
        Some(cfg.batches as u64),
        cfg.precision,
        Some(options.threads),
    )
    .with_engine(engine);
    let seconds = start.elapsed().as_secs_f64();
    let rep = summarise(scene, cfg, &done, seconds, resumed, meta)?;
    if (resumed > 0 || keep.in_flight_count() > 0)
        && let Some(i) = rep.identities.iter().find(|i| !i.agrees)
    {
        return Err(Error::Failed(format!(
            "the run resumed from its checkpoint fails an exact identity: {} {} is {:+.1} \
                 standard errors from its closed form {} (bound {:.2}): the checkpoint holds \
                 work of another configuration; delete it and run again",
            i.name, i.measured, i.t, i.exact, i.bound
        )));
    }
    Ok(rep)
}

/// The engine of a run on `scene`: the SIMD lanes where the scene's `f64` kernel is the generic
/// convex-cell kernel itself (a table given as data, the square cell), which they reproduce bit
/// for bit ([`crate::engine::cells`]), and the cell fits them; the scalar engine otherwise, and
/// at MPFR precision. `engine = simd` on a scene without them is refused.
///
/// # Errors
/// The SIMD engine asked for where it cannot run, or a SIMD path this CPU lacks.
fn engine_on<S: Scene>(scene: &S, precision: Precision, engine: Engine) -> Result<Resolved, Error> {
    let f64_run = precision == Precision::F64;
    let lanes = f64_run && lanes_run(scene)?;
    match engine {
        Engine::Simd if !lanes => Err(Error::out_of_range(
            "engine",
            "simd",
            "use auto or scalar: the SIMD engine runs f64 trajectories of the triangular trap and \
             of a convex cell of the generic kernel with at most 16 disks (a table given as data)",
        )),
        Engine::Auto if !lanes => Ok(Resolved::Scalar),
        e => e.resolve(f64_run),
    }
}

/// `true` if the lanes reproduce `scene`'s kernel: its kernel type is the generic
/// [`ConvexCell`] (decided by type identity, never by a flag) and the cell fits the lanes.
///
/// # Errors
/// A scene whose `f64` lattice cannot be built.
fn lanes_run<S: Scene>(scene: &S) -> Result<bool, Error> {
    use std::any::TypeId;
    if TypeId::of::<S::Kernel<f64>>() != TypeId::of::<ConvexCell<f64>>() {
        return Ok(false);
    }
    Ok(crate::engine::cells::fits(scene.lattice::<f64>(())?.cell()))
}

/// Runs `jobs` in blocks of [`BLOCK`] on the SIMD lanes of `scene`'s cell (`f64`, every lane the
/// scalar kernel's bits), in parallel, handing each finished batch to `keep`.
fn lanes_on<S: Scene>(
    scene: &S,
    cfg: &Sampling,
    jobs: &[Job],
    (path, options): (SimdPath, &RunOptions),
    keep: &DiffusionKeeper,
) -> Result<Vec<BatchResult>, Error> {
    // `engine_on` chose the lanes: the kernel is the generic cell's and the cell fits them.
    let lat = scene.lattice::<f64>(())?;
    let (cell, basis) = (lat.cell(), lat.basis_f64());
    let watch = cfg.watch(scene);
    let pool = crate::engine::parallel::thread_pool(options.threads)?;
    in_blocks(&pool, jobs, keep, |b| {
        let start = Instant::now();
        let audit = options.audit.map(|a| (a, scene));
        let mut obs = BatchObservers::<S>::new(b, BLOCK, basis, &watch, audit)?;
        let quotas: Vec<_> = b.iter().map(Job::quota).collect();
        let begin = |l: usize| b[l].start_in::<S, f64>(scene, ());
        run_block_kept(path, cell, &quotas, begin, &mut obs, keep, options.progress)?;
        obs.results(b, start.elapsed().as_secs_f64() / b.len() as f64)
    })
}

/// Runs `jobs` on the scalar engine at the configured precision, in parallel, handing each
/// finished batch to `keep`. Results come back in job order.
fn execute_on<S: Scene>(
    scene: &S,
    cfg: &Sampling,
    jobs: &[Job],
    options: &RunOptions,
    keep: &DiffusionKeeper,
) -> Result<Vec<BatchResult>, Error> {
    let pool = crate::engine::parallel::thread_pool(options.threads)?;
    cfg.precision.dispatch(OnScene {
        scene,
        jobs,
        watch: cfg.watch(scene),
        audit: options.audit,
        pool: &pool,
        keep,
        progress: options.progress,
    })
}

/// The jobs of [`execute_on`] at the number type of the run's precision.
struct OnScene<'a, S: Scene> {
    scene: &'a S,
    jobs: &'a [Job],
    watch: Watch,
    audit: Option<AuditSpec>,
    pool: &'a rayon::ThreadPool,
    keep: &'a DiffusionKeeper,
    progress: &'a (dyn Fn(u64) + Sync),
}

impl<S: Scene> AtPrecision for OnScene<'_, S> {
    type Output = Result<Vec<BatchResult>, Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Self::Output {
        let lat = self.scene.lattice::<T>(ctx)?;
        self.pool.install(|| {
            self.jobs
                .par_iter()
                .map(|&j| {
                    let r = self.one(&lat, ctx, j)?;
                    self.keep.finish(&j.quota(), &r)?;
                    Ok(r)
                })
                .collect()
        })
    }
}

impl<S: Scene> OnScene<'_, S> {
    /// One trajectory, from its saved state if it was in flight.
    fn one<T: Real>(
        &self,
        lat: &Lattice<T, S::Kernel<T>>,
        ctx: T::Ctx,
        job: Job,
    ) -> Result<BatchResult, Error> {
        let start = Instant::now();
        let audit = self.audit.map(|a| (a, self.scene));
        let mut obs = BatchObservers::<S>::new(&[job], 1, lat.basis_f64(), &self.watch, audit)?;
        let begin = || job.start_in::<S, T>(self.scene, ctx);
        let (keep, progress) = (self.keep, self.progress);
        drive_kept(lat, ctx, &job.quota(), begin, &mut obs, keep, progress)?;
        let mut r = obs.results(&[job], start.elapsed().as_secs_f64())?;
        Ok(r.remove(0))
    }
}

/// The report of finished batches.
fn summarise<S: Scene>(
    scene: &S,
    cfg: &Sampling,
    done: &[BatchResult],
    seconds: f64,
    resumed: u32,
    meta: RunMeta,
) -> Result<SceneDiffusionReport, Error> {
    let tau = time_unit(scene);
    let super::WindowDs {
        ds,
        dc,
        d: (d, d_err),
        check: (dcv, dce),
        diff,
    } = super::window_ds(done, tau, &cfg.window, &cfg.check_window)?;
    let (msd_times, over) = msd_over_4t(done, tau);
    let times = cfg.watch(scene).curve.map(|g| g.times());
    let (msd_curve, green_kubo) = super::curve::summarise(times, done, tau, &cfg.window, &ds)?;
    let audit = merged_audit(done);
    Ok(SceneDiffusionReport {
        scene: scene.label(),
        table: scene.table_spec().cloned(),
        time_unit: tau,
        time_unit_name: match scene.crossing_time() {
            Some(_) => "mean crossing time tau",
            None => "mean free time",
        }
        .to_string(),
        D: d,
        D_err: d_err,
        D_check: dcv,
        D_check_err: dce,
        D_minus_D_check: diff.difference,
        D_minus_D_check_err: diff.err,
        identities: identities(scene, done),
        msd_times,
        msd_over_4t: over.iter().map(|e| e.value).collect(),
        msd_over_4t_err: over.iter().map(|e| e.err).collect(),
        msd_curve,
        green_kubo,
        longest_free_path: super::summary::longest_free_path(done),
        collisions: done.iter().map(|b| b.counters.collisions).sum(),
        seconds,
        resumed_batches: resumed,
        audit,
        batch_D: ds,
        batch_D_check: dc,
        config: cfg.clone(),
        meta,
    })
}

/// The scene's exact identities against the batches' counters.
fn identities<S: Scene>(scene: &S, done: &[BatchResult]) -> Vec<Identity> {
    let bound = normal_sigma_equivalent_t(done.len().saturating_sub(1).max(1) as f64, 4.0);
    let measure = |name: &str, f: &dyn Fn(&Counters) -> f64, exact: f64| {
        let (measured, err) = mean_se(&done.iter().map(|b| f(&b.counters)).collect::<Vec<_>>());
        let t = (measured - exact) / err;
        Identity {
            name: name.into(),
            measured,
            err,
            exact,
            t,
            bound,
            agrees: t.abs() <= bound,
        }
    };
    let mfp = scene.mean_free_path();
    let mut out = vec![measure(
        "mean free path",
        &|c| c.time / c.collisions as f64,
        mfp,
    )];
    if let Some(tau) = scene.crossing_time() {
        out.push(measure(
            "crossing time",
            &|c| c.time / c.crossings as f64,
            tau,
        ));
        out.push(measure(
            "collisions per crossing",
            &|c| c.collisions as f64 / c.crossings as f64,
            tau / mfp,
        ));
    }
    out
}
