//! Analyses in a field beside `diffusion(field=)` and `diffusion(electric=)`:
//! `sweep(w=..., fields=[...])` and `sweep(w_from=..., w_to=..., field=...)` (the tensor over gaps
//! and fields, `estimators::sweep::field`), `sweep(w=..., electric=[...])` (the driven gas over E,
//! `estimators::sweep::driven`); `lyapunov(field=)` is read with the other exponents
//! (`verification.rs`).

use pyo3::prelude::*;

use lorentz_gas::estimators::sweep::Grid;
use lorentz_gas::estimators::sweep::driven::DrivenGrid;
use lorentz_gas::estimators::sweep::field::FieldGrid;
use lorentz_gas::estimators::sweep::field_grid::{self, SweepGrid};
use lorentz_gas::scenes::table::spec::TableSpec;

use crate::params::{Params, Work, work};
use crate::scenes::Where;

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
