//! `diffusion`: D by the Einstein formula without a field, the tensor in one, or D on a table
//! given as data, each the command line's run with its bits.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lorentz_gas::engine::options::{AuditSpec, RunOptions};
use lorentz_gas::estimators::diffusion::scene::SceneDiffusionConfig;
use lorentz_gas::estimators::diffusion::{self, DiffusionConfig, MsdGrid, Window};
use lorentz_gas::estimators::field::{self, FieldConfig};
use lorentz_gas::scenes::spec::{SceneChoice, SceneSpec};
use lorentz_gas::scenes::table::PeriodicTable;

use crate::analyses::options;
use crate::inputs::{self, count_u32};
use crate::params::{Params, Work, work};
use crate::scenes::Where;
use crate::watch::{compute, json};

/// A fit window in units of τ, as the command line's `LO:HI`.
fn window(name: &str, (lo, hi): (f64, f64)) -> PyResult<Window> {
    format!("{lo}:{hi}")
        .parse::<Window>()
        .map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
}

/// `diffusion(params, progress)`.
pub fn read(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let place = Where::read(p)?;
    let rel_err = p.opt_number("rel_err")?;
    let collisions = p.opt_count_u64("collisions")?;
    let (batches, seed) = (p.count_u32("batches")?, p.count_u64("seed")?);
    let precision = p.precision()?;
    let windows = (p.pair("window")?, p.pair("check_window")?);
    let msd_grid: MsdGrid = p.parsed("msd_grid", MsdGrid::Fit, |t| {
        t.parse().map_err(crate::py_err)
    })?;
    let samples = p.count_u64("localization_samples")?;
    let field = p.opt_text("field")?;
    let (audit, reference_bits) = (p.opt_number("audit")?, p.text("reference_bits")?);
    let (threads, engine) = (p.threads()?, p.engine()?);
    let (checkpoint, every) = (p.opt_path("checkpoint")?, p.checkpoint_every()?);
    Ok(work(move |py, progress| {
        let spec = place.spec()?;
        let plain = DiffusionConfig {
            collisions: collisions.unwrap_or_else(|| diffusion::plan::default_collisions(rel_err)),
            batches,
            seed,
            precision,
            window: window("window", windows.0)?,
            check_window: window("check_window", windows.1)?,
            rel_err,
            msd_grid,
            ..DiffusionConfig::new(0.1)
        };
        let cfg = configs(spec, plain, field.as_deref(), samples)?;
        let audit = match audit {
            Some(rate) => Some(
                AuditSpec::new(rate, count_u32("reference_bits", &reference_bits)?)
                    .map_err(crate::py_err)?,
            ),
            None => None,
        };
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
    }))
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
