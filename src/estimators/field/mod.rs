//! The diffusion tensor in a uniform magnetic field, with the orbits that never diffuse counted
//! exactly (`proofs-notes/magnetic-transport.md`, `proofs-notes/magnetic-localized.md`).
//!
//! The run is a diffusion run on any periodic array of disks (the triangular lattice at any gap,
//! the square one at any radius, a table given as data: in a field the horizon is finite,
//! corridors or not), with
//! collisions, batches, seed, precision and fit windows in units of the scene's crossing time τ
//! as for any [`DiffusionConfig`], whose table carries the field B. Each batch is one
//! trajectory started from the invariant measure restricted to the **diffusing** orbits (starts on
//! pinned or skipping orbits, decided by exact geometry, are drawn again). Along it the
//! displacement and the cumulative Lévy area are sampled every gτ, every sample a time origin,
//! and per batch
//!
//! * D_xx, D_yy: half the least-squares slopes of ⟨Δx²⟩, ⟨Δy²⟩ over the fit window;
//! * the symmetric off-diagonal part: half the slope of ⟨ΔxΔy⟩ (0 by the lattice's symmetry);
//! * the Hall part D_xy = −D_yx: half the slope of the mean Lévy area ⟨A⟩ (Green–Kubo:
//!   d⟨A⟩/dt → ∫ ⟨v_x(0)v_y(t) − v_y(0)v_x(t)⟩ dt = D_xy − D_yx).
//!
//! Errors are standard errors over batches. Over the whole phase space the localized orbits do not
//! move, so the tensor is (1 − f_localized) times the diffusing part's, with the exact share; where
//! every orbit is localized (2ρ ≤ A − 2r: each cyclotron circle either misses every disk or skips
//! round one) the tensor is exactly 0 and no trajectory is run. The sampled share of localized
//! phase points (binomial error) and Kac's mean free time of the diffusing part are measured
//! beside their exact values.

use crate::engine::work::Work;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::diffusion::time_unit;
use super::diffusion::{DiffusionConfig, Window};
use crate::Error;
use crate::engine::Resolved;
use crate::engine::metadata::RunMeta;
use crate::engine::options::{RunOption, RunOptions};
use crate::engine::parallel::{par_batches_watched, share};
use crate::numbers::exact::{nearest_f64, parse_exact};
use crate::numbers::precision::Precision;
use crate::numbers::real::Real;
use crate::observers::excursion::Excursion;
use crate::scenes::Scene;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::spec::Table;
use crate::scenes::spec::{SceneSpec, field_value};
use crate::statistics::{linear_fit, mean_se};
use crate::theory::magnetic::FieldGeometry;

mod components;
mod lanes;
pub mod lyapunov;
mod track;
mod walk;

pub use components::{Components, SPLIT_ALPHA};
pub use walk::FieldWalk;

use track::{Batch, Setup};

/// The field B of a run in a field, checked.
///
/// # Errors
/// A table without a field, or a field out of range ([`field_value`]).
pub fn field_of(cfg: &DiffusionConfig) -> Result<f64, Error> {
    cfg.table.field_value()?.ok_or(Error::missing(
        "field",
        "a run in a magnetic field needs the field B",
    ))
}

/// The gap of a triangular table or the radius of a square one, as the nearest doubles.
///
/// # Errors
/// A parameter that is not an exact decimal or fraction.
pub fn scene_parameters(table: &Table) -> Result<(Option<f64>, Option<f64>), Error> {
    Ok(match &table.scene {
        SceneSpec::Triangular { w } => {
            let w = parse_exact(w).map_err(|e| e.named("w"))?;
            (Some(nearest_f64(&w)), None)
        }
        SceneSpec::Square { radius } => {
            let r = parse_exact(radius).map_err(|e| e.named("radius"))?;
            (None, Some(nearest_f64(&r)))
        }
        SceneSpec::Table(_) | SceneSpec::Open(_) => (None, None),
    })
}

/// The exact geometry of the localized orbits of a run's table in its field.
///
/// # Errors
/// A bad table or field.
pub fn geometry(cfg: &DiffusionConfig) -> Result<FieldGeometry, Error> {
    let scene = cfg.table.scene.resolve()?;
    crate::with_scene!(&scene, |s| geometry_of(s, field_of(cfg)?))
}

/// Estimates with their standard errors over batches.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Tensor {
    /// D_xx: half the slope of ⟨Δx²⟩.
    pub D_xx: f64,
    /// Its standard error.
    pub D_xx_err: f64,
    /// D_yy: half the slope of ⟨Δy²⟩ (equal to D_xx by the lattice's symmetry).
    pub D_yy: f64,
    /// Its standard error.
    pub D_yy_err: f64,
    /// The Hall part D_xy = −D_yx: half the slope of the mean Lévy area.
    pub D_xy: f64,
    /// Its standard error.
    pub D_xy_err: f64,
    /// The symmetric off-diagonal part: half the slope of ⟨ΔxΔy⟩ (0 by symmetry).
    pub D_xy_symmetric: f64,
    /// Its standard error.
    pub D_xy_symmetric_err: f64,
}

/// What a transport run in a field measured, the point of a field sweep
/// ([`crate::estimators::sweep::field::FieldSweepRow`]): its place and field, the tensor over the
/// whole phase space, the localized shares, the mean free time and the batches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct FieldPoint {
    /// Gap w of the triangular scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub w: Option<f64>,
    /// Disk radius of the square scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// The field B (nearest double of the exact value in `config`).
    pub field: f64,
    /// Cyclotron radius 1/|B|.
    pub cyclotron_radius: f64,
    /// D_xx over the whole phase space: (1 − bounded share) × the diffusing part's, the mean
    /// of D_xx and D_yy — the isotropic D where the scene's symmetry makes the tensor isotropic
    /// ([`Scene::isotropic`]: the presets, a table a quarter turn maps onto itself), half its
    /// trace otherwise (`diffusing` has each).
    pub D_xx: f64,
    /// Its standard error.
    pub D_xx_err: f64,
    /// The Hall part D_xy over the whole phase space.
    pub D_xy: f64,
    /// Its standard error.
    pub D_xy_err: f64,
    /// Exact share of phase space in pinned orbits.
    pub pinned_fraction_exact: f64,
    /// Exact share in skipping orbits.
    pub skipping_fraction_exact: f64,
    /// Exact localized share (pinned + skipping).
    pub localized_fraction_exact: f64,
    /// The sampled localized share of `localization_samples` phase points.
    pub localized_fraction: f64,
    /// Its binomial standard error.
    pub localized_fraction_err: f64,
    /// Every orbit is localized (2ρ ≤ A − 2r): D = 0 exactly, no trajectory run.
    pub all_localized: bool,
    /// Mean free time between collisions of the diffusing part: the inverse of the collision rate
    /// averaged over batches of equal duration (infinite where every orbit is localized).
    #[serde(deserialize_with = "infinite_if_null")]
    pub mean_free_time: f64,
    /// Its standard error (the rate's, propagated).
    #[serde(deserialize_with = "nan_if_null")]
    pub mean_free_time_err: f64,
    /// Kac's closed form for it (infinite where every orbit is localized).
    #[serde(deserialize_with = "infinite_if_null")]
    pub mean_free_time_exact: f64,
    /// Per-batch D_xx (mean of xx and yy), every batch (bounded ones too: see `components`).
    pub batch_D_xx: Vec<f64>,
    /// Per-batch Hall D_xy, every batch.
    pub batch_D_xy: Vec<f64>,
    /// The batches by component: the bounded ones set aside, the diffusing ones tested for one
    /// distribution.
    pub components: Components,
}

impl FieldPoint {
    /// The point's scene parameter: its gap w, or its radius on the square lattice (0 on a
    /// table, which has none).
    pub fn place(&self) -> f64 {
        self.w.or(self.radius).unwrap_or(0.0)
    }
}

/// The result of a transport run in a field.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FieldReport {
    /// The scene ([`Scene::label`]).
    pub scene: String,
    /// What it measured (flattened: `w` … `components`).
    #[serde(flatten)]
    pub point: FieldPoint,
    /// The tensor of the diffusing part (the diffusing batches only), over the fit window.
    pub diffusing: Tensor,
    /// The same over the later check window (the linear regime's check).
    pub diffusing_check: Tensor,
    /// Localized starts drawn and set aside before the batches' diffusing starts.
    pub rejected_starts: u64,
    /// Fit window (units of the scene's crossing time τ).
    pub window: Window,
    /// Check window.
    pub check_window: Window,
    /// The time unit τ: the scene's crossing time ([`Scene::crossing_time`]; the zero-field
    /// mean hop time πA/(3w) of the triangular scene).
    pub tau: f64,
    /// Collisions in all.
    pub collisions: u64,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// Collisions per wall-clock second, end to end (0 in files written before it was kept).
    #[serde(default)]
    pub collisions_per_second: f64,
    /// The configuration.
    pub config: DiffusionConfig,
    /// Provenance.
    pub meta: RunMeta,
}

/// Runs the transport analysis in a field.
///
/// # Errors
/// An invalid configuration, options the analysis does not use (a checkpoint, an audit, an
/// engine other than the scalar one it runs on), or an interruption.
pub fn run(cfg: &DiffusionConfig, opts: &RunOptions) -> Result<FieldReport, Error> {
    cfg.validate()?;
    opts.accept("diffusion in a field", &[RunOption::Engine])?;
    let scene = cfg.table.scene.resolve()?;
    crate::with_scene!(&scene, |s| run_on(s, cfg, opts))
}

/// The run on the resolved scene.
fn run_on<S: Scene>(
    scene: &S,
    cfg: &DiffusionConfig,
    opts: &RunOptions,
) -> Result<FieldReport, Error> {
    let geometry = geometry_of(scene, field_of(cfg)?)?;
    let f64_run = cfg.precision == Precision::F64;
    let engine = opts.engine.resolve(f64_run)?;
    work_on(scene, cfg, &geometry, matches!(engine, Resolved::Simd(_))).check(opts.threads)?;
    let started = Instant::now();
    let (localized, samples) = classify(cfg, scene, &geometry, opts)?;
    let batches = if geometry.all_localized() {
        Vec::new()
    } else {
        match (cfg.precision, engine) {
            (Precision::F64, Resolved::Simd(path)) => {
                with_setup::<f64, S, _>(cfg, scene, &geometry, (), opts, |su, keys, d| {
                    lanes::batches(su, path, keys, d, opts.threads)
                })?
            }
            (Precision::F64, _) => scalar_batches::<f64, S>(cfg, scene, &geometry, (), opts)?,
            (Precision::Bits(bits), _) => {
                scalar_batches::<rug::Float, S>(cfg, scene, &geometry, bits, opts)?
            }
        }
    };
    let tau = time_unit(scene);
    let mut report = summarise(
        cfg,
        (scene, &geometry),
        tau,
        &batches,
        (localized, samples),
        started,
        opts,
    )?;
    report.meta = report.meta.with_engine(engine);
    Ok(report)
}

/// The work of the run `cfg` in a field (on the SIMD arc engine if `simd`), before it starts: its
/// collisions on arcs at its precision, the classification of its localization samples and the
/// exact pinned share.
///
/// # Errors
/// A bad table or field.
pub fn work(cfg: &DiffusionConfig, simd: bool) -> Result<Work<'static>, Error> {
    let scene = cfg.table.scene.resolve()?;
    crate::with_scene!(&scene, |s| Ok(work_on(
        s,
        cfg,
        &geometry_of(s, field_of(cfg)?)?,
        simd
    )))
}

/// [`work`] on the resolved scene and geometry.
fn work_on<S: Scene>(
    scene: &S,
    cfg: &DiffusionConfig,
    geometry: &FieldGeometry,
    simd: bool,
) -> Work<'static> {
    let lower = crate::estimators::diffusion::work_lower(cfg.precision);
    let samples = cfg.localization_samples.unwrap_or(0) as f64;
    let rho = geometry.cyclotron_radius();
    let collisions = if geometry.all_localized() {
        0.0
    } else {
        cfg.collisions as f64
    };
    let w = Work::new("diffusion in a field", lower, collisions)
        .in_field(scene, rho, simd, geometry.setup_seconds(samples))
        .at(cfg.precision);
    // A stronger field shortens the arcs and the rows within ρ + r of the pinned share.
    if w.serial > 0.0 || w.crossings > 1.0 {
        w.or_raise("field")
    } else {
        w
    }
}

/// The exact geometry of `scene` in the field `b`.
fn geometry_of<S: Scene>(scene: &S, b: f64) -> Result<FieldGeometry, Error> {
    let disks = crate::scenes::require_disk_lattice(scene, "field")?;
    FieldGeometry::new(disks, b)
}

/// The sampled localized share: `localization_samples` phase points in 64 chunks of their own
/// streams (the same bits at any thread count), stopped by `opts.stop` within a few
/// milliseconds.
fn classify<S: Scene>(
    cfg: &DiffusionConfig,
    scene: &S,
    geometry: &FieldGeometry,
    opts: &RunOptions,
) -> Result<(u64, u64), Error> {
    const CHUNKS: u32 = 64;
    let n = cfg.localization_samples.unwrap_or(0);
    let stop = opts.stop.as_ref();
    let counts = par_batches_watched(opts.threads, CHUNKS, stop, |c| {
        let key = track::classification_key(cfg.seed, cfg.run, c as u64);
        track::classify_chunk(scene, geometry, key, share(n, CHUNKS, c), stop)
    })?;
    Ok((counts.iter().sum(), n))
}

/// Calls `f` with the setup of the batches at number type `T`, every batch's stream and their
/// duration: every batch flies the same time, its share of the collisions at Kac's mean free
/// time.
fn with_setup<T: Real, S: Scene, R>(
    cfg: &DiffusionConfig,
    scene: &S,
    geometry: &FieldGeometry,
    ctx: T::Ctx,
    opts: &RunOptions,
    f: impl FnOnce(&Setup<'_, T, S>, &[StreamKey], f64) -> Result<R, Error>,
) -> Result<R, Error> {
    let lattice = scene.lattice::<T>(ctx)?;
    let exact = parse_exact(cfg.table.field().unwrap_or("0")).map_err(|e| e.named("field"))?;
    let field = T::from_rational(ctx, &exact);
    let tau = time_unit(scene);
    let (grid, steps) = crate::estimators::diffusion::lag_grid(tau, &cfg.lags());
    let setup = Setup {
        scene,
        lattice: &lattice,
        geometry,
        field: (&field, field.to_f64()),
        ctx,
        grid,
        steps: &steps,
        stop: opts.stop.as_ref(),
        progress: opts.progress,
    };
    let duration =
        (cfg.collisions / cfg.batches as u64) as f64 * geometry.diffusing_mean_free_time();
    let keys: Vec<StreamKey> = (0..cfg.batches)
        .map(|i| StreamKey::new(cfg.seed, Purpose::Trajectory, i as u64).in_run(cfg.run))
        .collect();
    f(&setup, &keys, duration)
}

/// Every batch at number type `T` on the scalar kernel, one per task.
fn scalar_batches<T: Real, S: Scene>(
    cfg: &DiffusionConfig,
    scene: &S,
    geometry: &FieldGeometry,
    ctx: T::Ctx,
    opts: &RunOptions,
) -> Result<Vec<Batch>, Error> {
    with_setup::<T, S, _>(cfg, scene, geometry, ctx, opts, |setup, keys, duration| {
        par_batches_watched(opts.threads, keys.len() as u32, opts.stop.as_ref(), |i| {
            track::batch(setup, keys[i as usize], duration)
        })
    })
}

/// One batch's tensor over `win`: [D_xx, D_yy, D_xy (Hall), D_xy (symmetric)].
fn tensor_of(b: &Batch, lags: &[usize], tau: f64, win: &Window) -> [f64; 4] {
    let mut out = [0.0; 4];
    for (k, o) in [(0, 0), (1, 1), (3, 2), (2, 3)] {
        let (x, y): (Vec<f64>, Vec<f64>) = lags
            .iter()
            .zip(&b.means)
            .filter(|(l, _)| **l >= win.lo && **l <= win.hi)
            .map(|(l, m)| (*l as f64 * tau, m[k]))
            .unzip();
        out[o] = linear_fit(&x, &y).1 / 2.0;
    }
    out
}

/// The tensor over `win` from the batches `keep` selects, with standard errors (zero if none).
fn tensor(
    batches: &[Batch],
    lags: &[usize],
    tau: f64,
    win: &Window,
    keep: impl Fn(usize) -> bool,
) -> Tensor {
    let per: Vec<[f64; 4]> = (batches.iter().enumerate())
        .filter(|(i, _)| keep(*i))
        .map(|(_, b)| tensor_of(b, lags, tau, win))
        .collect();
    if per.is_empty() {
        return Tensor::default();
    }
    let stat = |k: usize| mean_se(&per.iter().map(|t| t[k]).collect::<Vec<_>>());
    let ((xx, xx_e), (yy, yy_e), (h, h_e), (s, s_e)) = (stat(0), stat(1), stat(2), stat(3));
    Tensor {
        D_xx: xx,
        D_xx_err: xx_e,
        D_yy: yy,
        D_yy_err: yy_e,
        D_xy: h,
        D_xy_err: h_e,
        D_xy_symmetric: s,
        D_xy_symmetric_err: s_e,
    }
}

/// A number of the JSON where `null` stands for what JSON cannot write, read back as NaN.
pub(crate) fn nan_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(<Option<f64> as serde::Deserialize>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// A mean free time of the JSON where `null` stands for the infinity JSON cannot write: where
/// every orbit is localized nothing collides, measured or exact. Read back as infinity, so a
/// record re-read has the bits it was written with.
pub(crate) fn infinite_if_null<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(<Option<f64> as serde::Deserialize>::deserialize(d)?.unwrap_or(f64::INFINITY))
}

/// The diffusing part's mean free time and its error: collision rates of batches of equal
/// duration average to Kac's 1/τ whatever the components (infinite where nothing was run).
fn mean_free_time(batches: &[Batch]) -> (f64, f64) {
    let rates: Vec<f64> = batches
        .iter()
        .map(|b| b.collisions as f64 / b.time)
        .collect();
    if rates.is_empty() {
        return (f64::INFINITY, 0.0);
    }
    let (r, e) = mean_se(&rates);
    (1.0 / r, e / (r * r))
}

/// The whole phase space's D from the diffusing part's `(d, se)`: times the share that diffuses,
/// (1 − localized)(1 − p) with p the bounded batches' share, the error of p propagated.
fn whole(d: (f64, f64), c: &Components, keep: f64) -> (f64, f64) {
    let n = c.batch_component.len().max(1) as f64;
    let p = f64::from(c.bounded) / n;
    let share = keep * (1.0 - p);
    if c.bounded_fraction_err == 0.0 {
        return (share * d.0, share * d.1);
    }
    let e = (share * d.1).hypot(d.0 * c.bounded_fraction_err);
    (share * d.0, e)
}

/// Every batch's D_xx (mean of xx and yy) and Hall D_xy over the fit window `win`, and the
/// batches by component (their reaches at the table's excursion limit).
fn classified(
    batches: &[Batch],
    geometry: &FieldGeometry,
    (lags, tau, win): (&[usize], f64, &Window),
) -> (Vec<f64>, Vec<f64>, Components) {
    let per: Vec<[f64; 4]> = batches
        .iter()
        .map(|b| tensor_of(b, lags, tau, win))
        .collect();
    let batch_xx: Vec<f64> = per.iter().map(|t| (t[0] + t[1]) / 2.0).collect();
    let batch_xy: Vec<f64> = per.iter().map(|t| t[2]).collect();
    let reaches: Vec<_> = batches.iter().map(|b| b.reach).collect();
    let excursion = Excursion::of(geometry.lattice(), geometry.cyclotron_radius());
    let localized = geometry.localized_fraction();
    let components = Components::of(excursion, &reaches, (&batch_xx, &batch_xy), localized);
    (batch_xx, batch_xy, components)
}

fn summarise<S: Scene>(
    cfg: &DiffusionConfig,
    (scene, geometry): (&S, &FieldGeometry),
    tau: f64,
    batches: &[Batch],
    (localized, samples): (u64, u64),
    started: Instant,
    opts: &RunOptions,
) -> Result<FieldReport, Error> {
    let d = cfg;
    let lags = cfg.lags();
    let (batch_xx, batch_xy, components) = classified(batches, geometry, (&lags, tau, &d.window));
    // The diffusing share (exactly 0 where every orbit is localized, never −0 from rounding).
    let keep = if geometry.all_localized() {
        0.0
    } else {
        (1.0 - geometry.localized_fraction()).max(0.0)
    };
    let diffusing = tensor(batches, &lags, tau, &d.window, |i| components.diffusing(i));
    let check = tensor(batches, &lags, tau, &d.check_window, |i| {
        components.diffusing(i)
    });
    let kept: Vec<f64> = (batch_xx.iter().enumerate())
        .filter(|(i, _)| components.diffusing(*i))
        .map(|(_, v)| *v)
        .collect();
    let xx = if kept.is_empty() {
        (0.0, 0.0)
    } else {
        mean_se(&kept)
    };
    let (xx, xx_err) = whole(xx, &components, keep);
    let (xy, xy_err) = whole((diffusing.D_xy, diffusing.D_xy_err), &components, keep);
    let (mft, mft_err) = mean_free_time(batches);
    let f = localized as f64 / samples as f64;
    let collisions: u64 = batches.iter().map(|b| b.collisions).sum();
    let seconds = started.elapsed().as_secs_f64();
    let (w, radius) = scene_parameters(&cfg.table)?;
    Ok(FieldReport {
        scene: scene.label(),
        point: FieldPoint {
            w,
            radius,
            field: field_of(cfg)?,
            cyclotron_radius: geometry.cyclotron_radius(),
            D_xx: xx,
            D_xx_err: xx_err,
            D_xy: xy,
            D_xy_err: xy_err,
            pinned_fraction_exact: geometry.pinned_fraction(),
            skipping_fraction_exact: geometry.skipping_fraction(),
            localized_fraction_exact: geometry.localized_fraction(),
            localized_fraction: f,
            localized_fraction_err: (f * (1.0 - f) / samples as f64).sqrt(),
            all_localized: geometry.all_localized(),
            mean_free_time: mft,
            mean_free_time_err: mft_err,
            mean_free_time_exact: geometry.diffusing_mean_free_time(),
            batch_D_xx: batch_xx,
            batch_D_xy: batch_xy,
            components,
        },
        diffusing,
        diffusing_check: check,
        rejected_starts: batches.iter().map(|b| b.rejected).sum(),
        window: d.window,
        check_window: d.check_window,
        tau,
        collisions,
        seconds,
        collisions_per_second: collisions as f64 / seconds,
        config: cfg.clone(),
        meta: RunMeta::new(
            Some(d.seed),
            Some(d.batches as u64),
            d.precision,
            Some(opts.threads),
        ),
    })
}
