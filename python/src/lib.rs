//! `lorentz_gas._native`: the crate's analyses for Python. Each analysis takes one dict of its
//! Python function's keyword parameters (`params.rs`: gaps and counts as the text the command
//! line parses, so that both parse them with one implementation and refuse them with one
//! message; a key the analysis does not read is refused), runs the library's
//! `run(&config, &options)` with the GIL released, and returns the result as the command line's
//! JSON (same serializer, so the same bits) or as numpy arrays. The Python package
//! (`python/lorentz_gas/`) wraps them in keyword functions and result objects.

mod analyses;
mod bench;
mod campaigns;
mod cycles;
mod diffusion;
mod events;
mod field;
mod figures;
mod inputs;
mod natives;
mod params;
mod plan;
mod scenes;
mod section;
mod text;
mod verification;
mod watch;

use pyo3::create_exception;
use pyo3::exceptions::{PyKeyboardInterrupt, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use lorentz_gas::{Error, ErrorKind};

create_exception!(
    _native,
    CheckFailedError,
    PyRuntimeError,
    "A verification ran and its verdict is FAIL (the command line's exit status 1)."
);
create_exception!(
    _native,
    ComputationError,
    PyRuntimeError,
    "A computation that started could not finish correctly (the command line's exit status 4)."
);

/// The Python exception of a library error: bad input is `ValueError` (its one line names the
/// valid range, as on the command line), I/O is `OSError` (naming the path), a FAIL verdict is
/// `CheckFailedError`, a stopped run `KeyboardInterrupt`, anything else `ComputationError`.
pub(crate) fn py_err(e: Error) -> PyErr {
    let text = e.presented(&keyword);
    match e.kind() {
        ErrorKind::BadInput => PyValueError::new_err(text),
        ErrorKind::Io => PyOSError::new_err(text),
        ErrorKind::CheckFailed | ErrorKind::Incomplete => CheckFailedError::new_err(text),
        ErrorKind::Interrupted => PyKeyboardInterrupt::new_err(text),
        ErrorKind::Failed => ComputationError::new_err(text),
    }
}

/// The keyword of a parameter the library names (`resume` is `checkpoint=` here).
fn keyword(parameter: &str) -> String {
    match parameter {
        "resume" => "checkpoint=".into(),
        p => format!("{p}="),
    }
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("CheckFailedError", m.py().get_type::<CheckFailedError>())?;
    m.add("ComputationError", m.py().get_type::<ComputationError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    natives::register(m)?;
    analyses::register(m)?;
    plan::register(m)?;
    events::register(m)?;
    text::register(m)?;
    m.add_function(wrap_pyfunction!(scenes::read_table, m)?)?;
    m.add_function(wrap_pyfunction!(campaigns::merge_parts, m)?)?;
    Ok(())
}
