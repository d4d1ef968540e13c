//! A scene from its name and its parameter (`w` for the triangular scene, `radius` for the
//! square one): the library's [`SceneSpec`], its refusals named in Python's terms.

use pyo3::PyResult;

use lorentz_gas::scenes::spec::{SceneChoice, SceneSpec};

use crate::inputs::exact;
use crate::py_err;

/// The scene `name` with its gap `w` or its radius (exact text), each checked.
pub fn resolve(name: &str, w: Option<&str>, radius: Option<&str>) -> PyResult<SceneChoice> {
    // A value that is not a number is refused naming its keyword first, as everywhere.
    for (keyword, text) in [("w", w), ("radius", radius)] {
        if let Some(t) = text {
            exact(keyword, t)?;
        }
    }
    SceneSpec::parse(name, w, radius)
        .and_then(|s| s.resolve())
        .map_err(py_err)
}
