//! One function per analysis: the values as typed, the library's configuration (checked by its
//! `validate`), `run(&config, &options)` on a worker thread, the result as the command line's
//! JSON.

use std::path::PathBuf;
use std::time::Duration;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lorentz_gas::engine::Engine;
use lorentz_gas::engine::options::{AuditSpec, MAX_CHECKPOINT_EVERY, RunOptions};
use lorentz_gas::estimators::diffusion::scene::SceneDiffusionConfig;
use lorentz_gas::estimators::diffusion::{self, DiffusionConfig, Window};
use lorentz_gas::estimators::escape::{self, EscapeConfig};
use lorentz_gas::estimators::field::{self, FieldConfig};
use lorentz_gas::estimators::free_paths::{self, FreePathConfig};
use lorentz_gas::estimators::hops::backscatter::{self, BackscatterConfig};
use lorentz_gas::estimators::hops::{self, HopsConfig};
use lorentz_gas::estimators::superdiffusion::{self, SuperdiffusionConfig};
use lorentz_gas::estimators::sweep::{self, SweepConfig};
use lorentz_gas::report::publication::{self, AuditConfig as PublicationConfig};
use lorentz_gas::scenes::spec::{SceneChoice, SceneSpec};
use lorentz_gas::scenes::table::PeriodicTable;
use lorentz_gas::theory::constants::{self, ConstantsConfig};

use crate::inputs::{self, count_u32, count_u64, count_usize, exact};
use crate::watch::{Ctl, compute, json};

/// The run options of a computation watched by `ctl`.
pub(crate) fn options<'a>(ctl: &'a Ctl<'a>, threads: usize, engine: Engine) -> RunOptions<'a> {
    RunOptions {
        engine,
        threads,
        progress: ctl.progress,
        stop: Some(ctl.stop.clone()),
        ..RunOptions::default()
    }
}

/// A fit window in units of τ, as the command line's `LO:HI`.
fn window(name: &str, (lo, hi): (f64, f64)) -> PyResult<Window> {
    format!("{lo}:{hi}")
        .parse::<Window>()
        .map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
}

/// A checkpoint interval in seconds, 0 to a day.
fn interval(seconds: f64) -> PyResult<Duration> {
    let max = MAX_CHECKPOINT_EVERY.as_secs_f64();
    if !(0.0..=max).contains(&seconds) {
        return Err(PyValueError::new_err(format!(
            "checkpoint_every = {seconds} s is out of range: use 0 to {max} s"
        )));
    }
    Ok(Duration::from_secs_f64(seconds))
}

#[pyfunction]
#[pyo3(name = "diffusion", signature = (scene, w, radius, collisions, batches, seed, threads, engine, precision, window, check_window, checkpoint, checkpoint_every, audit, reference_bits, field, localization_samples, progress, rel_err, msd_grid = "fit"))]
#[allow(clippy::too_many_arguments)]
fn py_diffusion(
    py: Python<'_>,
    scene: &str,
    w: Option<&str>,
    radius: Option<&str>,
    collisions: Option<&str>,
    batches: &str,
    seed: &str,
    threads: Option<&str>,
    engine: &str,
    precision: &str,
    window: (f64, f64),
    check_window: (f64, f64),
    checkpoint: Option<PathBuf>,
    checkpoint_every: f64,
    audit: Option<f64>,
    reference_bits: &str,
    field: Option<&str>,
    localization_samples: &str,
    progress: Option<Bound<'_, PyAny>>,
    rel_err: Option<f64>,
    msd_grid: &str,
) -> PyResult<String> {
    let spec = crate::scenes::spec(scene, w, radius)?;
    let plain = DiffusionConfig {
        collisions: match collisions {
            Some(c) => count_u64("collisions", c)?,
            None => diffusion::plan::default_collisions(rel_err),
        },
        batches: count_u32("batches", batches)?,
        seed: count_u64("seed", seed)?,
        precision: inputs::precision(precision)?,
        window: self::window("window", window)?,
        check_window: self::window("check_window", check_window)?,
        rel_err,
        msd_grid: msd_grid.parse().map_err(crate::py_err)?,
        ..DiffusionConfig::new(0.1)
    };
    let samples = count_u64("localization_samples", localization_samples)?;
    let cfg = configs(spec, plain, field, samples)?;
    let audit = match audit {
        Some(rate) => Some(
            AuditSpec::new(rate, count_u32("reference_bits", reference_bits)?)
                .map_err(crate::py_err)?,
        ),
        None => None,
    };
    let (threads, engine) = (inputs::threads(threads)?, inputs::engine(engine)?);
    let every = interval(checkpoint_every)?;
    let r = compute(py, progress, |ctl| {
        let opts = RunOptions {
            resume: checkpoint,
            audit,
            checkpoint_every: every,
            ..options(ctl, threads, engine)
        };
        Ok(match &cfg {
            Either::Field(fc) => Either::Field(field::run(fc, &opts)?),
            Either::Plain(c) => Either::Plain(diffusion::run(c, &opts)?),
            Either::Table(c, t) => Either::Table(diffusion::scene::run_on(&**t, c, &opts)?, ()),
        })
    })?;
    match r {
        Either::Field(r) => json(&r),
        Either::Plain(r) => json(&r),
        Either::Table(r, ()) => json(&r),
    }
}

/// A diffusion run's result: without a field, in one, or on a table given as data.
enum Either<P, F, S, T> {
    Plain(P),
    Field(F),
    Table(S, T),
}

/// The configurations of a diffusion run.
type Configs = Either<DiffusionConfig, FieldConfig, SceneDiffusionConfig, Box<PeriodicTable>>;

/// The run of `scene` the statistics of `plain` ask for (validated): in the field, unless it is
/// absent or exactly zero, on either scene; else the run without a field, on the triangular
/// scene below w_inf (elsewhere the diffusion coefficient does not exist).
fn configs(
    scene: SceneSpec,
    plain: DiffusionConfig,
    field: Option<&str>,
    samples: u64,
) -> PyResult<Configs> {
    let statistics = SceneDiffusionConfig {
        collisions: plain.collisions,
        batches: plain.batches,
        seed: plain.seed,
        precision: plain.precision,
        window: plain.window,
        check_window: plain.check_window,
        msd_grid: plain.msd_grid,
    };
    let b = match field {
        Some(b) if lorentz_gas::numbers::exact::parse_exact(b).map_err(crate::py_err)? != 0 => b,
        _ => {
            if let SceneChoice::Table(t) = scene.resolve().map_err(crate::py_err)? {
                diffusion::scene::refuse_rel_err(plain.rel_err).map_err(crate::py_err)?;
                statistics.validate(&*t).map_err(crate::py_err)?;
                return Ok(Either::Table(statistics, t));
            }
            return plain_config(&scene, plain).map(Either::Plain);
        }
    };
    field::refuse_zero_field_options(plain.rel_err, plain.msd_grid).map_err(crate::py_err)?;
    let fc = FieldConfig {
        statistics,
        localization_samples: samples,
        ..FieldConfig::new(scene, b)
    };
    fc.validate().map_err(crate::py_err)?;
    Ok(Either::Field(fc))
}

/// The run without a field: the triangular scene's gap checked for a finite horizon.
fn plain_config(scene: &SceneSpec, plain: DiffusionConfig) -> PyResult<DiffusionConfig> {
    let w = match scene {
        SceneSpec::Triangular { w } => inputs::diffusive_gap(w)?,
        SceneSpec::Square { .. } | SceneSpec::Table(_) => {
            let choice = scene.resolve().map_err(crate::py_err)?;
            lorentz_gas::with_scene!(&choice, |s| diffusion::require_finite_horizon(s))
                .map_err(crate::py_err)?;
            return Err(PyValueError::new_err(
                "the square scene has no diffusion coefficient without a field",
            ));
        }
    };
    let cfg = DiffusionConfig {
        w: w.value,
        w_exact: w.exact_text(),
        ..plain
    };
    cfg.validate().map_err(crate::py_err)?;
    Ok(cfg)
}

#[pyfunction]
#[pyo3(name = "hops", signature = (w, collisions, batches, order, seed, threads, engine, checkpoint, checkpoint_every, progress))]
#[allow(clippy::too_many_arguments)]
fn py_hops(
    py: Python<'_>,
    w: &str,
    collisions: &str,
    batches: &str,
    order: &str,
    seed: &str,
    threads: Option<&str>,
    engine: &str,
    checkpoint: Option<PathBuf>,
    checkpoint_every: f64,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let cfg = hop_config(w, collisions, batches, order, seed)?;
    let engine = inputs::engine(engine)?;
    let kept = Kept::new(threads, checkpoint, checkpoint_every)?;
    let r = compute(py, progress, |ctl| {
        hops::run(&cfg, &kept.options(ctl, engine))
    })?;
    json(&r)
}

/// The configuration of a hop analysis (hops, theory, lattice walks) from the values as typed.
fn hop_config(
    w: &str,
    collisions: &str,
    batches: &str,
    order: &str,
    seed: &str,
) -> PyResult<HopsConfig> {
    Ok(HopsConfig {
        w: inputs::diffusive_gap(w)?.value,
        collisions: count_u64("collisions", collisions)?,
        batches: count_u32("batches", batches)?,
        order: count_usize("order", order)?,
        seed: count_u64("seed", seed)?,
        run: 0,
    })
}

/// The threads and the checkpoint of a resumable analysis, checked before any work.
struct Kept {
    threads: usize,
    checkpoint: Option<PathBuf>,
    every: Duration,
}

impl Kept {
    fn new(threads: Option<&str>, checkpoint: Option<PathBuf>, every: f64) -> PyResult<Self> {
        Ok(Kept {
            threads: inputs::threads(threads)?,
            checkpoint,
            every: interval(every)?,
        })
    }

    fn options<'a>(&self, ctl: &'a Ctl<'a>, engine: Engine) -> RunOptions<'a> {
        RunOptions {
            resume: self.checkpoint.clone(),
            checkpoint_every: self.every,
            ..options(ctl, self.threads, engine)
        }
    }
}

#[pyfunction]
#[pyo3(name = "theory", signature = (w, collisions, batches, order, seed, threads, checkpoint, checkpoint_every, progress))]
#[allow(clippy::too_many_arguments)]
fn py_theory(
    py: Python<'_>,
    w: &str,
    collisions: &str,
    batches: &str,
    order: &str,
    seed: &str,
    threads: Option<&str>,
    checkpoint: Option<PathBuf>,
    checkpoint_every: f64,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let cfg = hop_config(w, collisions, batches, order, seed)?;
    let kept = Kept::new(threads, checkpoint, checkpoint_every)?;
    let r = compute(py, progress, |ctl| {
        hops::theory::run(&cfg, &kept.options(ctl, Engine::Auto))
    })?;
    json(&r)
}

#[pyfunction]
#[pyo3(name = "lattice_walk", signature = (w, collisions, batches, order, seed, threads, checkpoint, checkpoint_every, progress))]
#[allow(clippy::too_many_arguments)]
fn py_lattice_walk(
    py: Python<'_>,
    w: &str,
    collisions: &str,
    batches: &str,
    order: &str,
    seed: &str,
    threads: Option<&str>,
    checkpoint: Option<PathBuf>,
    checkpoint_every: f64,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let cfg = hop_config(w, collisions, batches, order, seed)?;
    let kept = Kept::new(threads, checkpoint, checkpoint_every)?;
    let r = compute(py, progress, |ctl| {
        hops::lattice_walks::run(&cfg, &kept.options(ctl, Engine::Auto))
    })?;
    json(&r)
}

#[pyfunction]
#[pyo3(name = "backscatter", signature = (w, particles, batches, seed, threads, precision, progress))]
#[allow(clippy::too_many_arguments)]
fn py_backscatter(
    py: Python<'_>,
    w: &str,
    particles: &str,
    batches: &str,
    seed: &str,
    threads: Option<&str>,
    precision: &str,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let w = exact("w", w)?;
    let cfg = BackscatterConfig {
        w: w.value,
        w_exact: w.exact_text(),
        particles: count_u64("particles", particles)?,
        batches: count_u32("batches", batches)?,
        seed: count_u64("seed", seed)?,
        run: 0,
        precision: inputs::precision(precision)?,
    };
    let threads = inputs::threads(threads)?;
    let r = compute(py, progress, |ctl| {
        backscatter::run(&cfg, &options(ctl, threads, Engine::Auto))
    })?;
    json(&r)
}

#[pyfunction]
#[pyo3(name = "sweep", signature = (w_from, w_to, steps, runs, collisions_per_run, batches_per_run, seed, threads, engine, out, checkpoint_every, progress))]
#[allow(clippy::too_many_arguments)]
fn py_sweep(
    py: Python<'_>,
    w_from: &str,
    w_to: &str,
    steps: &str,
    runs: &str,
    collisions_per_run: &str,
    batches_per_run: &str,
    seed: &str,
    threads: Option<&str>,
    engine: &str,
    out: Option<PathBuf>,
    checkpoint_every: f64,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let cfg = SweepConfig {
        w_from: w_from.trim().to_string(),
        w_to: w_to.trim().to_string(),
        steps: count_u32("steps", steps)?,
        runs: count_u32("runs", runs)?,
        collisions: count_u64("collisions_per_run", collisions_per_run)?,
        batches: count_u32("batches_per_run", batches_per_run)?,
        seed: count_u64("seed", seed)?,
    };
    cfg.validate().map_err(crate::py_err)?;
    let (threads, engine) = (inputs::threads(threads)?, inputs::engine(engine)?);
    let every = interval(checkpoint_every)?;
    let r = compute(py, progress, |ctl| {
        let opts = RunOptions {
            resume: out.clone(),
            checkpoint_every: every,
            ..options(ctl, threads, engine)
        };
        let r = sweep::run(&cfg, &opts)?;
        if let Some(dir) = &out {
            sweep::write_tables(&r, dir)?;
        }
        Ok(r)
    })?;
    json(&r)
}

#[pyfunction]
#[pyo3(name = "escape", signature = (w, widths, particles_per_width, seed, threads, checkpoint, checkpoint_every, progress))]
#[allow(clippy::too_many_arguments)]
fn py_escape(
    py: Python<'_>,
    w: &str,
    widths: Option<Vec<f64>>,
    particles_per_width: &str,
    seed: &str,
    threads: Option<&str>,
    checkpoint: Option<PathBuf>,
    checkpoint_every: f64,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let w = inputs::diffusive_gap(w)?.value;
    let cfg = EscapeConfig {
        w,
        widths: widths.unwrap_or_else(|| escape::default_widths(w)),
        particles_per_width: count_u64("particles_per_width", particles_per_width)?,
        seed: count_u64("seed", seed)?,
    };
    cfg.validate().map_err(crate::py_err)?;
    let threads = inputs::threads(threads)?;
    let every = interval(checkpoint_every)?;
    let r = compute(py, progress, |ctl| {
        let opts = RunOptions {
            resume: checkpoint,
            checkpoint_every: every,
            ..options(ctl, threads, Engine::Auto)
        };
        escape::run(&cfg, &opts)
    })?;
    json(&r)
}

#[pyfunction]
#[pyo3(name = "superdiffusion", signature = (scene, w, radius, collisions, batches, octaves, points_per_octave, tail_fit_from, vacf_fit, msd_fit, seed, flights, threads, checkpoint, checkpoint_every, progress))]
#[allow(clippy::too_many_arguments)]
fn py_superdiffusion(
    py: Python<'_>,
    scene: &str,
    w: Option<&str>,
    radius: Option<&str>,
    collisions: &str,
    batches: &str,
    octaves: &str,
    points_per_octave: &str,
    tail_fit_from: f64,
    vacf_fit: Option<[f64; 2]>,
    msd_fit: Option<[f64; 2]>,
    seed: &str,
    flights: &str,
    threads: Option<&str>,
    checkpoint: Option<PathBuf>,
    checkpoint_every: f64,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    // The scene and its parameter checked as every analysis checks them, kept as typed.
    let scene = crate::scenes::spec(scene, w, radius)?;
    let every = interval(checkpoint_every)?;
    let windows = SuperdiffusionConfig::new(scene).with_octaves(count_u32("octaves", octaves)?);
    let cfg = SuperdiffusionConfig {
        collisions: count_u64("collisions", collisions)?,
        batches: count_u32("batches", batches)?,
        points_per_octave: count_u32("points_per_octave", points_per_octave)?,
        tail_fit_from,
        vacf_fit: vacf_fit.unwrap_or(windows.vacf_fit),
        msd_fit: msd_fit.unwrap_or(windows.msd_fit),
        seed: count_u64("seed", seed)?,
        flights: inputs::flights(flights)?,
        ..windows
    };
    let threads = inputs::threads(threads)?;
    let r = compute(py, progress, |ctl| {
        let opts = RunOptions {
            resume: checkpoint,
            checkpoint_every: every,
            ..options(ctl, threads, Engine::Auto)
        };
        superdiffusion::run(&cfg, &opts)
    })?;
    json(&r)
}

#[pyfunction]
#[pyo3(name = "free_paths", signature = (scene, w, radius, collisions, batches, seed, flights, threads, progress))]
#[allow(clippy::too_many_arguments)]
fn py_free_paths(
    py: Python<'_>,
    scene: &str,
    w: Option<&str>,
    radius: Option<&str>,
    collisions: &str,
    batches: &str,
    seed: &str,
    flights: &str,
    threads: Option<&str>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let cfg = FreePathConfig {
        collisions: count_u64("collisions", collisions)?,
        batches: count_u32("batches", batches)?,
        seed: count_u64("seed", seed)?,
        flights: inputs::flights(flights)?,
        ..FreePathConfig::new(crate::scenes::spec(scene, w, radius)?)
    };
    let threads = inputs::threads(threads)?;
    let r = compute(py, progress, |ctl| {
        free_paths::run(&cfg, &options(ctl, threads, Engine::Auto))
    })?;
    json(&r)
}

#[pyfunction]
#[pyo3(name = "report", signature = (result, out, quick, reference_bits, max_rerun_collisions, threads, progress))]
#[allow(clippy::too_many_arguments)]
fn py_report(
    py: Python<'_>,
    result: PathBuf,
    out: Option<PathBuf>,
    quick: bool,
    reference_bits: &str,
    max_rerun_collisions: Option<&str>,
    threads: Option<&str>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<(String, String)> {
    let out = out.unwrap_or_else(|| {
        let stem = result
            .file_stem()
            .map_or("result".into(), |s| s.to_string_lossy().to_string());
        result.with_file_name(format!("{stem}-report"))
    });
    let cfg = PublicationConfig {
        result,
        out: out.clone(),
        quick,
        reference_bits: count_u32("reference_bits", reference_bits)?,
        max_rerun_collisions: max_rerun_collisions
            .map(|m| count_u64("max_rerun_collisions", m))
            .transpose()?,
    };
    let threads = inputs::threads(threads)?;
    let r = compute(py, progress, |ctl| {
        publication::run(&cfg, &options(ctl, threads, Engine::Auto))
    })?;
    Ok((
        json(&r)?,
        lorentz_gas::report::text::publication::publication(&r, &out),
    ))
}

/// Registers the analyses in the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(py_diffusion, m)?)?;
    m.add_function(wrap_pyfunction!(py_hops, m)?)?;
    m.add_function(wrap_pyfunction!(py_theory, m)?)?;
    m.add_function(wrap_pyfunction!(py_lattice_walk, m)?)?;
    m.add_function(wrap_pyfunction!(py_backscatter, m)?)?;
    m.add_function(wrap_pyfunction!(py_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(py_escape, m)?)?;
    m.add_function(wrap_pyfunction!(py_superdiffusion, m)?)?;
    m.add_function(wrap_pyfunction!(py_free_paths, m)?)?;
    m.add_function(wrap_pyfunction!(py_report, m)?)?;
    m.add_function(wrap_pyfunction!(py_constants, m)?)?;
    m.add_function(wrap_pyfunction!(py_agreement_bound, m)?)?;
    Ok(())
}

#[pyfunction]
#[pyo3(name = "constants", signature = (w, radius, precision))]
fn py_constants(
    w: Option<&str>,
    radius: Option<&str>,
    precision: &str,
) -> PyResult<(String, String)> {
    // Either parameter names the scene; both, or neither, is refused by the scene's own check.
    let name = if radius.is_some() && w.is_none() {
        "square"
    } else {
        "triangular"
    };
    let scene = crate::scenes::spec(name, w, radius)?;
    let r = constants::run(&ConstantsConfig {
        scene,
        precision: inputs::precision(precision)?,
    })
    .map_err(crate::py_err)?;
    Ok((
        r.to_json().map_err(crate::py_err)?,
        lorentz_gas::report::text::constants::constants(&r),
    ))
}

/// The crate's agreement bound: the Student-t quantile with `dof` degrees of freedom whose
/// two-sided tail equals that of 4 normal σ (6.3·10⁻⁵), for comparing a value with an error
/// from `dof + 1` batches (`statistics::comparison::agreement_bound`).
#[pyfunction]
#[pyo3(name = "agreement_bound", signature = (dof))]
fn py_agreement_bound(dof: f64) -> PyResult<f64> {
    if dof.is_nan() || dof < 1.0 {
        return Err(PyValueError::new_err(format!(
            "dof = {dof} is out of range: use 1 or more (inf for the normal 4σ)"
        )));
    }
    Ok(lorentz_gas::statistics::comparison::agreement_bound(dof))
}
