//! Precision planning for results in Python: the library's planner itself, so that
//! `DiffusionResult.collisions_for` plans exactly as `rel_err=` and `--rel-err` do.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lorentz_gas::estimators::diffusion::plan;

/// The collisions (in `batches` batches) that the relative error `target` needs after a run of
/// `collisions` that reached `achieved` ([`plan::collisions_for`]).
#[pyfunction]
#[pyo3(name = "collisions_for")]
fn py_collisions_for(collisions: u64, batches: u32, achieved: f64, target: f64) -> PyResult<u64> {
    plan::check_rel_err(target).map_err(crate::py_err)?;
    plan::collisions_for(collisions, batches, achieved, target).ok_or_else(|| {
        PyValueError::new_err(format!(
            "a relative error of {achieved:e} cannot be planned down to {target:e}: it would need \
             more than 2^64 collisions"
        ))
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(py_collisions_for, m)?)
}
