//! A result's text as the command line prints it (`str()` of a Python result).

use pyo3::prelude::*;

/// The command line's text of the result `json` of kind `kind`, or `None` for a kind whose text
/// the library does not render yet.
#[pyfunction]
#[pyo3(name = "text", signature = (kind, json))]
fn py_text(kind: &str, json: &str) -> PyResult<Option<String>> {
    lorentz_gas::report::text::of_json(kind, json).map_err(crate::py_err)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(py_text, m)?)
}
