//! A scene from its name and its parameter (`w` for the triangular scene, `radius` for the
//! square one), or a table given as data (`table`: the Python layer passes its JSON): the
//! library's [`SceneSpec`], its refusals named in Python's terms.

use pyo3::prelude::*;

use lorentz_gas::scenes::spec::{SceneChoice, SceneSpec};
use lorentz_gas::scenes::table::spec::TableSpec;

use crate::inputs::exact;
use crate::params::Params;
use crate::py_err;

/// The table in the TOML file `path`, as the JSON the analyses take as `table`.
#[pyfunction]
pub fn read_table(path: std::path::PathBuf) -> PyResult<String> {
    let table = TableSpec::read(&path).map_err(py_err)?;
    serde_json::to_string(&table).map_err(|e| py_err(lorentz_gas::Error::encode(e)))
}

/// The scene of a call as typed: `scene` (its name), `table` (a table given as data, as JSON),
/// `w` and `radius`.
pub struct Where {
    pub name: String,
    pub table: Option<String>,
    pub w: Option<String>,
    pub radius: Option<String>,
}

impl Where {
    /// `scene`, `table`, `w` and `radius`.
    pub fn read(p: &Params<'_, '_>) -> PyResult<Self> {
        Ok(Where {
            name: p.text("scene")?,
            table: p.opt_text("table")?,
            w: p.opt_text("w")?,
            radius: p.opt_text("radius")?,
        })
    }

    /// `scene`, `w` and `radius` (an analysis that takes no table).
    pub fn read_without_table(p: &Params<'_, '_>) -> PyResult<Self> {
        Ok(Where {
            name: p.text("scene")?,
            table: None,
            w: p.opt_text("w")?,
            radius: p.opt_text("radius")?,
        })
    }

    /// The scene, resolved (its parameter checked).
    pub fn resolve(&self) -> PyResult<SceneChoice> {
        self.spec()?.resolve().map_err(py_err)
    }

    /// The description of the scene, its parameter checked as [`Where::resolve`] checks it and
    /// kept exactly as typed.
    pub fn spec(&self) -> PyResult<SceneSpec> {
        let (w, radius) = (self.w.as_deref(), self.radius.as_deref());
        if let Some(table) = &self.table {
            if w.is_some() || radius.is_some() {
                return Err(pyo3::exceptions::PyValueError::new_err(
                    "table= gives the whole table: leave out w= and radius=",
                ));
            }
            let spec = SceneSpec::Table(TableSpec::from_json(table).map_err(py_err)?);
            spec.resolve().map_err(py_err)?;
            return Ok(spec);
        }
        // A value that is not a number is refused naming its keyword first, as everywhere.
        for (keyword, text) in [("w", w), ("radius", radius)] {
            if let Some(t) = text {
                exact(keyword, t)?;
            }
        }
        let spec = SceneSpec::parse(&self.name, w, radius).map_err(py_err)?;
        spec.resolve().map_err(py_err)?;
        Ok(spec)
    }
}
