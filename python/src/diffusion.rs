//! `diffusion`: D by the Einstein formula without a field, the tensor in one, or D on a table
//! given as data, each the command line's run with its bits.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lorentz_gas::engine::options::{AuditSpec, RunOptions};
use lorentz_gas::estimators::diffusion::{self, DiffusionConfig, MsdGrid, Window};
use lorentz_gas::estimators::transport;
use lorentz_gas::scenes::spec::{Motion, SceneSpec, Table};

use crate::analyses::options;
use crate::inputs::count_u32;
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
    let plan_only = p.flag("plan_only")?;
    let collisions = p.opt_count_u64("collisions")?;
    let (batches, seed) = (p.count_u32("batches")?, p.count_u64("seed")?);
    let precision = p.precision()?;
    let windows = (p.pair("window")?, p.pair("check_window")?);
    let msd_grid: MsdGrid = p.parsed("msd_grid", MsdGrid::Fit, |t| {
        t.parse().map_err(crate::py_err)
    })?;
    let samples = p.count_u64("localization_samples")?;
    let field = p.opt_text("field")?;
    let electric = p.opt_text("electric")?;
    let electric_angle = p.text("electric_angle")?;
    let (audit, reference_bits) = (p.opt_number("audit")?, p.text("reference_bits")?);
    let (threads, engine) = (p.threads()?, p.engine()?);
    let (checkpoint, every) = (p.opt_path("checkpoint")?, p.checkpoint_every()?);
    Ok(work(move |py, progress| {
        // Python's angle defaults to 0: it is the motion's only with `electric`.
        let angle = electric.as_ref().map(|_| electric_angle.clone());
        let motion = crate::analyses::motion_shape(&field, &electric, &angle)?;
        let table = Table {
            scene: place.spec()?,
            motion,
        };
        let cfg = DiffusionConfig {
            batches,
            seed,
            precision,
            window: window("window", windows.0)?,
            check_window: window("check_window", windows.1)?,
            msd_grid,
            ..DiffusionConfig::sized(table, collisions, rel_err, samples)
        };
        cfg.validate().map_err(crate::py_err)?;
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
            let trap = |r| transport::Transport::Trap(Box::new(r));
            match plan_only {
                true => diffusion::plan::plan_only(&cfg, &opts).map(trap),
                false if planned_on_the_trap(&cfg) => planned(&cfg, &opts, ctl).map(trap),
                false => transport::run(&cfg, &opts),
            }
        })?;
        json(&r)
    }))
}

/// Whether `cfg` is a run for a relative error on the triangular lattice without a field: a
/// pilot, then the run it plans ([`planned`]).
fn planned_on_the_trap(cfg: &DiffusionConfig) -> bool {
    cfg.rel_err.is_some()
        && cfg.table.motion == Motion::Straight
        && matches!(cfg.table.scene, SceneSpec::Triangular { .. })
}

/// The pilot, then the run it plans with the progress started again over the planned
/// collisions (the command line's two bars), so that a bar's time estimate is the planned run's
/// at its measured speed: `diffusion::plan::run` in two steps.
fn planned(
    cfg: &DiffusionConfig,
    opts: &RunOptions,
    ctl: &crate::watch::Ctl<'_>,
) -> Result<diffusion::DiffusionReport, lorentz_gas::Error> {
    let first = diffusion::plan::pilot(cfg, opts)?;
    if let Some(full) = diffusion::plan::planned_config(cfg, &first.pilot) {
        (ctl.restart)(full.collisions);
    }
    diffusion::plan::finish(cfg, first, opts)
}
