//! A scene from its name and its parameter (`w` for the triangular scene, `radius` for the
//! square one): the library's [`SceneSpec`], its refusals named in Python's terms.

use pyo3::PyResult;

use lorentz_gas::scenes::spec::{SceneChoice, SceneSpec};

use crate::inputs::exact;
use crate::py_err;

/// The scene `name` with its gap `w` or its radius (exact text), each checked.
pub fn resolve(name: &str, w: Option<&str>, radius: Option<&str>) -> PyResult<SceneChoice> {
    spec(name, w, radius)?.resolve().map_err(py_err)
}

/// The description of the scene `name` with its gap `w` or its radius, its parameter checked
/// as [`resolve`] checks it and kept exactly as typed.
pub fn spec(name: &str, w: Option<&str>, radius: Option<&str>) -> PyResult<SceneSpec> {
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
