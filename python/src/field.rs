//! Analyses in a magnetic field beside `diffusion(field=)`: `sweep(w=..., fields=[...])` and
//! `sweep(w_from=..., w_to=..., field=...)` (the tensor over gaps and fields,
//! `estimators::field::sweep`), and `lyapunov(field=)` (`estimators::field::lyapunov`).

use std::path::PathBuf;

use pyo3::prelude::*;

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::field::sweep::{self, FieldSweepConfig};

use lorentz_gas::estimators::field::lyapunov::{self as field_lyapunov, FieldLyapunovConfig};
use pyo3::exceptions::PyValueError;

use crate::inputs::{self, count_u32, count_u64};
use crate::scenes::resolve;
use crate::watch::{compute, json};

#[pyfunction]
#[pyo3(name = "field_sweep", signature = (scene, w, radius, w_from, w_to, steps, field, fields, collisions_per_run, batches_per_run, seed, threads, engine, localization_samples, out, progress))]
#[allow(clippy::too_many_arguments)]
fn py_field_sweep(
    py: Python<'_>,
    scene: &str,
    w: Option<&str>,
    radius: Option<&str>,
    w_from: Option<&str>,
    w_to: Option<&str>,
    steps: &str,
    field: Option<&str>,
    fields: Vec<String>,
    collisions_per_run: &str,
    batches_per_run: &str,
    seed: &str,
    threads: Option<&str>,
    engine: &str,
    localization_samples: &str,
    out: Option<PathBuf>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let steps = count_u32("steps", steps)?;
    // A table given as data arrives as its JSON in place of the scene's name (`table=`).
    let table = if scene.trim_start().starts_with('{') {
        Some(lorentz_gas::scenes::table::spec::TableSpec::from_json(scene).map_err(crate::py_err)?)
    } else {
        None
    };
    let name = if table.is_some() { "table" } else { scene };
    let sweep::SweepGrid {
        gaps,
        radius,
        fields,
    } = sweep::scene_grid(name, (w, radius), (w_from, w_to, steps), field, &fields)
        .map_err(crate::py_err)?;
    let cfg = FieldSweepConfig {
        gaps,
        radius,
        fields,
        collisions: count_u64("collisions_per_run", collisions_per_run)?,
        batches: count_u32("batches_per_run", batches_per_run)?,
        seed: count_u64("seed", seed)?,
        localization_samples: count_u64("localization_samples", localization_samples)?,
        table,
    };
    cfg.validate().map_err(crate::py_err)?;
    let threads = inputs::threads(threads)?;
    let engine = inputs::engine(engine)?;
    let r = compute(py, progress, |ctl| {
        let opts = RunOptions {
            engine,
            threads,
            progress: ctl.progress,
            stop: Some(ctl.stop.clone()),
            resume: out.clone(),
            ..RunOptions::default()
        };
        let r = sweep::run(&cfg, &opts)?;
        if let Some(dir) = &out {
            sweep::write_tables(&r, dir)?;
        }
        Ok(r)
    })?;
    json(&r)
}

/// `lyapunov(field=B)`: the tangent-space exponent on arcs (the command line's `--field`).
pub fn lyapunov_in_field(
    py: Python<'_>,
    (scene, w, radius): (&str, Option<&str>, Option<&str>),
    (collisions_per_batch, batches, starts, seed, threads): (&str, &str, &str, &str, Option<&str>),
    field: &str,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    if count_u32("starts", starts)? > 0 {
        return Err(PyValueError::new_err(
            "starts (the divergence of finite-precision orbits) is not measured in a field: give starts=0",
        ));
    }
    let choice = resolve(scene, w, radius)?;
    let cfg = FieldLyapunovConfig {
        collisions_per_batch: count_u64("collisions_per_batch", collisions_per_batch)?,
        batches: count_u32("batches", batches)?,
        seed: count_u64("seed", seed)?,
        field: field.trim().to_string(),
    };
    let threads = inputs::threads(threads)?;
    let r = compute(py, progress, |ctl| {
        let opts = RunOptions {
            threads,
            progress: ctl.progress,
            stop: Some(ctl.stop.clone()),
            ..RunOptions::default()
        };
        lorentz_gas::with_scene!(&choice, |s| field_lyapunov::run(s, &cfg, &opts))
    })?;
    json(&r)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(py_field_sweep, m)?)
}
