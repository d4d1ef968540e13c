//! A scene from its name and its parameter (`w` for the triangular scene, `radius` for the
//! square one), or a table given as data (the Python layer passes its JSON where the name goes):
//! the library's [`SceneSpec`], its refusals named in Python's terms.

use pyo3::prelude::*;

use lorentz_gas::scenes::spec::{SceneChoice, SceneSpec};
use lorentz_gas::scenes::table::spec::TableSpec;

use crate::inputs::exact;
use crate::py_err;

/// The table in the TOML file `path`, as the JSON the analyses take where a scene's name goes.
#[pyfunction]
pub fn read_table(path: std::path::PathBuf) -> PyResult<String> {
    let table = TableSpec::read(&path).map_err(py_err)?;
    serde_json::to_string(&table).map_err(|e| py_err(lorentz_gas::Error::encode(e)))
}

/// The scene `name` with its gap `w` or its radius (exact text), each checked.
pub fn resolve(name: &str, w: Option<&str>, radius: Option<&str>) -> PyResult<SceneChoice> {
    spec(name, w, radius)?.resolve().map_err(py_err)
}

/// The description of the scene `name` with its gap `w` or its radius, its parameter checked
/// as [`resolve`] checks it and kept exactly as typed.
pub fn spec(name: &str, w: Option<&str>, radius: Option<&str>) -> PyResult<SceneSpec> {
    if name.trim_start().starts_with('{') {
        if w.is_some() || radius.is_some() {
            return Err(pyo3::exceptions::PyValueError::new_err(
                "table= gives the whole table: leave out w= and radius=",
            ));
        }
        let spec = SceneSpec::Table(TableSpec::from_json(name).map_err(py_err)?);
        spec.resolve().map_err(py_err)?;
        return Ok(spec);
    }
    // A value that is not a number is refused naming its keyword first, as everywhere.
    for (keyword, text) in [("w", w), ("radius", radius)] {
        if let Some(t) = text {
            exact(keyword, t)?;
        }
    }
    let spec = SceneSpec::parse(name, w, radius).map_err(py_err)?;
    spec.resolve().map_err(py_err)?;
    Ok(spec)
}
