//! Analyses in a field beside `diffusion(field=)` and `diffusion(electric=)`:
//! `sweep(w=..., fields=[...])` and `sweep(w_from=..., w_to=..., field=...)` (the tensor over gaps
//! and fields, `estimators::sweep::field`), `sweep(w=..., electric=[...])` (the driven gas over E,
//! `estimators::sweep::driven`), and `lyapunov(field=)` (`estimators::field::lyapunov`).

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::field::lyapunov as field_lyapunov;
use lorentz_gas::estimators::sweep::Grid;
use lorentz_gas::estimators::sweep::driven::DrivenGrid;
use lorentz_gas::estimators::sweep::field::FieldGrid;
use lorentz_gas::estimators::sweep::field_grid::{self, SweepGrid};
use lorentz_gas::scenes::table::spec::TableSpec;
use lorentz_gas::verification::lyapunov::LyapunovConfig;

use crate::params::{Params, Progress, Work, work};
use crate::scenes::Where;
use crate::watch::{compute, json};

/// `field_sweep(params, progress)`: the tensor over gaps (or radii) and fields.
pub fn sweep(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let place = Where::read(p)?;
    let (w_from, w_to) = (p.opt_text("w_from")?, p.opt_text("w_to")?);
    let steps = p.count_u32("steps")?;
    let (field, fields) = (p.opt_text("field")?, p.texts("fields")?);
    let (sizes, localization_samples) = (
        crate::campaigns::sizes(p)?,
        p.count_u64("localization_samples")?,
    );
    let how = crate::campaigns::SweepRun::read(p)?;
    Ok(work(move |py, progress| {
        // A table given as data is the scene `table` of the grid.
        let table = match &place.table {
            Some(t) => Some(TableSpec::from_json(t).map_err(crate::py_err)?),
            None => None,
        };
        let name = if table.is_some() {
            "table"
        } else {
            &place.name
        };
        let SweepGrid {
            gaps,
            radius,
            fields,
        } = field_grid::scene_grid(
            name,
            (place.w.as_deref(), place.radius.as_deref()),
            (w_from.as_deref(), w_to.as_deref(), steps),
            field.as_deref(),
            &fields,
        )
        .map_err(crate::py_err)?;
        let grid = Grid::InField(FieldGrid {
            gaps,
            radius,
            fields,
            localization_samples,
            table,
        });
        crate::campaigns::run_grid(py, progress, grid, sizes, how)
    }))
}

/// `driven_sweep(params, progress)`: the driven gas over the fields E at one gap.
pub fn driven_sweep(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let gaps = vec![p.text("w")?];
    let (electric, electric_angle) = (p.texts("electric")?, p.text("electric_angle")?);
    let (sizes, how) = (
        crate::campaigns::sizes(p)?,
        crate::campaigns::SweepRun::read(p)?,
    );
    Ok(work(move |py, progress| {
        let grid = Grid::Driven(DrivenGrid {
            gaps,
            electric,
            electric_angle,
        });
        crate::campaigns::run_grid(py, progress, grid, sizes, how)
    }))
}

/// `lyapunov(field=B)`: the tangent-space exponent on arcs (the command line's `--field`), with
/// `starts` as typed (`None`: 0).
pub fn lyapunov_in_field(
    py: Python<'_>,
    progress: Progress<'_>,
    place: &Where,
    cfg: LyapunovConfig,
    (starts, threads): (Option<&str>, usize),
) -> PyResult<String> {
    if crate::inputs::count_u32("starts", starts.unwrap_or("0"))? > 0 {
        return Err(PyValueError::new_err(
            "starts (the divergence of finite-precision orbits) is not measured in a field: give starts=0",
        ));
    }
    let choice = place.resolve()?;
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
