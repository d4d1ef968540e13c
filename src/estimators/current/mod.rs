//! The steady state of the driven Lorentz gas: the current J = ⟨v⟩ under a Gaussian-thermostatted
//! electric field E, its mobility J/E, the entropy production E·J, the diffusion tensor about the
//! drift and the distribution of the velocity angle (`proofs-notes/thermostat-current.md`).
//!
//! The run is a diffusion run ([`DiffusionConfig`]) whose table carries the thermostat
//! ([`Motion::Thermostat`](crate::scenes::spec::Motion::Thermostat)) on any periodic array of disks with a finite horizon. Each batch
//! is one trajectory started from the field-free invariant measure (its stream is the straight
//! run's), flown for a warm-up of 1/[`WARM_UP_SHARE`] of its stretch towards the steady state, then
//! observed for the flight time T = (collisions per batch) × ⟨ℓ⟩ rounded to the sampling grid
//! (⟨ℓ⟩ Santaló's field-free mean free path). Per batch:
//!
//! * J = X(T)/T, X the displacement over the observed stretch;
//! * the phase-space contraction averaged over it, ⟨α⟩ = ε ξ(T)/T = E·J exactly (∫α dt = εξ,
//!   ξ the displacement along E: the entropy production is the field's work);
//! * D_ij: half the least-squares slopes of ⟨Δx_iΔx_j⟩ − ⟨Δx_i⟩⟨Δx_j⟩ over the fit window,
//!   every grid sample a time origin;
//! * the velocity angle from E at the grid samples, binned.
//!
//! Errors are standard errors over batches. The Einstein relation J/E → D as E → 0 (the
//! straight gas's D, the contraction being the dissipation function) and J(−E) = −J(E) are the
//! checks (`tests/analyses/current.rs`).

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::diffusion::{DiffusionConfig, Estimate, Window, lag_grid, time_unit};
use crate::Error;
use crate::engine::Resolved;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::parallel::par_batches_watched;
use crate::kernel::thermostat::Thermostat;
use crate::numbers::precision::Precision;
use crate::numbers::real::Real;
use crate::scenes::Scene;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::thermostat::CellFields;
use crate::statistics::{linear_fit, mean_se};

pub mod lyapunov;
mod summary;
mod tangent;
mod track;

pub use summary::{DriftTensor, Steady};
pub use track::ANGLE_BINS;
use track::{Batch, Setup};

/// The warm-up is 1/`WARM_UP_SHARE` of a batch's observed stretch.
pub const WARM_UP_SHARE: f64 = 64.0;

/// The result of a run under the thermostatted field.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct CurrentReport {
    /// The scene ([`Scene::label`]).
    pub scene: String,
    /// The field's strength ε = |E| (nearest double of the exact value in `config`; a negative
    /// field as typed is the positive one turned by 180°).
    pub electric: f64,
    /// Its direction ê = E/|E| in the world (x, y).
    pub direction: [f64; 2],
    /// The steady state's numbers with their standard errors (flattened: J_x … mean_free_time).
    #[serde(flatten)]
    pub steady: Steady,
    /// The same over the check window.
    pub diffusion_check: DriftTensor,
    /// Centres of the velocity angle's bins (radians from E, over (−π, π]).
    pub angle_bins: Vec<f64>,
    /// The angle's probability density per radian in each bin (time average).
    pub angle_density: Vec<f64>,
    /// Its standard error over the batches.
    pub angle_density_err: Vec<f64>,
    /// The field-free mean free time ⟨ℓ⟩ (Santaló), which sets the batches' duration.
    pub mean_free_time_no_field: f64,
    /// Fit window (units of the scene's crossing time τ).
    pub window: Window,
    /// Check window.
    pub check_window: Window,
    /// The time unit τ.
    pub tau: f64,
    /// Flight time of each batch's warm-up.
    pub warm_up: f64,
    /// Flight time of each batch's observed stretch.
    pub measured_time: f64,
    /// Collisions within the observed stretches.
    pub collisions: u64,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Collisions (observed) per wall-clock second, end to end.
    pub collisions_per_second: f64,
    /// Per-batch J_parallel.
    pub batch_J_parallel: Vec<f64>,
    /// Per-batch J_perp.
    pub batch_J_perp: Vec<f64>,
    /// The configuration.
    pub config: DiffusionConfig,
    /// Provenance.
    pub meta: RunMeta,
}

/// The field of a configuration's table in the world's frame at precision `ctx`.
///
/// # Errors
/// A table without the thermostat, or a field that is not an exact decimal or fraction.
pub fn field_at<T: Real>(cfg: &DiffusionConfig, ctx: T::Ctx) -> Result<Thermostat<T>, Error> {
    cfg.table
        .motion
        .thermostat_at::<T>(ctx)?
        .ok_or(Error::missing(
            "electric",
            "a run under the thermostat needs a nonzero field E",
        ))
}

/// Runs the analysis of the steady state under the thermostat (scalar engine; no checkpoint or
/// audit yet).
///
/// # Errors
/// An invalid configuration, options the analysis does not use, or an interruption.
pub fn run(cfg: &DiffusionConfig, opts: &RunOptions) -> Result<CurrentReport, Error> {
    cfg.validate()?;
    opts.accept("diffusion under the thermostat", &[])?;
    work(cfg).check(opts.threads)?;
    let scene = cfg.table.scene.resolve()?;
    crate::with_scene!(&scene, |s| run_on(s, cfg, opts))
}

/// The work of a run under the thermostat: its collisions and warm-ups on the scalar engine, at
/// the thermostat's floor per collision ([`crate::engine::work::THERMOSTAT_SECONDS_PER_COLLISION`]).
pub fn work(cfg: &DiffusionConfig) -> crate::engine::work::Work<'static> {
    let lower = crate::estimators::diffusion::work_lower(cfg.precision);
    let collisions = cfg.collisions as f64 * (1.0 + 1.0 / WARM_UP_SHARE);
    crate::engine::work::Work::new("diffusion under the thermostat", lower, collisions)
        .costing(crate::engine::work::THERMOSTAT_SECONDS_PER_COLLISION)
        .at(cfg.precision)
}

/// Batch `i` of the run of `cfg` alone: its current along and across E, the bits of the whole
/// run's `batch_J_parallel[i]` and `batch_J_perp[i]` (the audit's quick re-run).
///
/// # Errors
/// As [`run`], and a batch outside 0 … batches − 1.
pub fn rerun_batch(cfg: &DiffusionConfig, i: u32, opts: &RunOptions) -> Result<[f64; 2], Error> {
    cfg.validate()?;
    Error::unless_in("batch", i, 0..=cfg.batches.saturating_sub(1), "")?;
    let scene = cfg.table.scene.resolve()?;
    let b = crate::with_scene!(&scene, |s| match cfg.precision {
        Precision::F64 => batches::<f64, _>(s, cfg, (), opts, Some(i)),
        Precision::Bits(bits) => batches::<rug::Float, _>(s, cfg, bits, opts, Some(i)),
    })?;
    let world = field_at::<f64>(cfg, ())?;
    Ok(summary::along_across([world.dir.x, world.dir.y], &b[0]))
}

/// The run on the resolved scene.
fn run_on<S: Scene>(
    scene: &S,
    cfg: &DiffusionConfig,
    opts: &RunOptions,
) -> Result<CurrentReport, Error> {
    let started = Instant::now();
    let batches = match cfg.precision {
        Precision::F64 => batches::<f64, S>(scene, cfg, (), opts, None)?,
        Precision::Bits(bits) => batches::<rug::Float, S>(scene, cfg, bits, opts, None)?,
    };
    let world = field_at::<f64>(cfg, ())?;
    let meta = RunMeta::new(
        Some(cfg.seed),
        Some(u64::from(cfg.batches)),
        cfg.precision,
        Some(opts.threads),
    )
    .with_engine(Resolved::Scalar);
    let seconds = started.elapsed().as_secs_f64();
    Ok(summary::summarise(
        scene,
        cfg,
        &world,
        &batches,
        (seconds, meta),
    ))
}

/// The grid of a run: the lags' sampling grid ([`lag_grid`]) and the grid steps of a batch's
/// observed stretch.
fn grid<S: Scene>(scene: &S, cfg: &DiffusionConfig) -> (f64, Vec<usize>, u64) {
    let (spacing, steps) = lag_grid(time_unit(scene), &cfg.lags());
    let stretch = (cfg.collisions / u64::from(cfg.batches)) as f64 * scene.mean_free_path();
    let samples = (stretch / spacing).round().max(1.0) as u64;
    (spacing, steps, samples)
}

/// Every batch at number type `T` on the scalar kernel, one per task (the same bits at any
/// thread count: each batch is its own stream), or batch `only` alone.
fn batches<T: Real, S: Scene>(
    scene: &S,
    cfg: &DiffusionConfig,
    ctx: T::Ctx,
    opts: &RunOptions,
    only: Option<u32>,
) -> Result<Vec<Batch>, Error> {
    let lattice = scene.lattice::<T>(ctx)?;
    let fields = CellFields::new(field_at::<T>(cfg, ctx)?);
    let world = field_at::<f64>(cfg, ())?;
    let (spacing, steps, samples) = grid(scene, cfg);
    let setup = Setup {
        scene,
        lattice: &lattice,
        fields: &fields,
        world: &world,
        ctx,
        grid: spacing,
        steps: &steps,
        warm_up: samples as f64 * spacing / WARM_UP_SHARE,
        samples,
        stop: opts.stop.as_ref(),
        progress: opts.progress,
    };
    let key = |i: u32| StreamKey::new(cfg.seed, Purpose::Trajectory, u64::from(i)).in_run(cfg.run);
    match only {
        Some(i) => Ok(vec![track::batch(&setup, key(i))?]),
        None => par_batches_watched(opts.threads, cfg.batches, opts.stop.as_ref(), |i| {
            track::batch(&setup, key(i))
        }),
    }
}

/// One batch's slope over `win` of the moment `f` of its lag means (against the lag in time).
fn slope(b: &Batch, lags: &[usize], tau: f64, win: &Window, f: impl Fn(&[f64; 5]) -> f64) -> f64 {
    let (x, y): (Vec<f64>, Vec<f64>) = lags
        .iter()
        .zip(&b.means)
        .filter(|(l, _)| **l >= win.lo && **l <= win.hi)
        .map(|(l, m)| (*l as f64 * tau, f(m)))
        .unzip();
    linear_fit(&x, &y).1
}

/// The mean and standard error of `xs` as an [`Estimate`].
fn mean_of(xs: &[f64]) -> Estimate {
    let (value, err) = mean_se(xs);
    Estimate { value, err }
}
