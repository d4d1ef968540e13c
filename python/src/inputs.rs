//! The values a Python caller passes, parsed exactly as the command line parses them (one
//! implementation, one message naming the valid range).

use pyo3::PyResult;
use pyo3::exceptions::PyValueError;

use lorentz_gas::engine::Engine;
use lorentz_gas::numbers::count;
use lorentz_gas::numbers::exact::ExactInput;
use lorentz_gas::numbers::precision::Precision;

use crate::py_err;

/// `name` = `text`: an exact decimal or fraction (`0.1`, `1/10`), as `--w` parses it.
pub fn exact(name: &str, text: &str) -> PyResult<ExactInput> {
    ExactInput::parse(text).map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
}

/// `w` = `text`: a gap at which D exists, decided on the exact text (0 < w < w_inf), as the
/// command line's `--w` of the hop analyses decides it.
pub fn diffusive_gap(text: &str) -> PyResult<ExactInput> {
    let w = exact("w", text)?;
    lorentz_gas::scenes::triangular::geometry::check_diffusive_gap_exact(
        w.value,
        w.exact.is_some().then_some(w.text.as_str()),
    )
    .map_err(crate::py_err)?;
    Ok(w)
}

/// `name` = `text`: a count (`2e9`, `2_000_000_000`), as the command line parses it.
pub fn count_u64(name: &str, text: &str) -> PyResult<u64> {
    count::parse_count(text).map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
}

/// A count that fits in 32 bits.
pub fn count_u32(name: &str, text: &str) -> PyResult<u32> {
    count::parse_count_u32(text).map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
}

/// A count that indexes memory.
pub fn count_usize(name: &str, text: &str) -> PyResult<usize> {
    count::parse_count_usize(text).map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
}

/// Worker threads: `None` is every core this process may use.
pub fn threads(text: Option<&str>) -> PyResult<usize> {
    match text {
        None => Ok(count::cores()),
        Some(t) => {
            count::parse_threads(t).map_err(|e| PyValueError::new_err(format!("threads: {e}")))
        }
    }
}

/// `auto`, `scalar` or `simd`.
pub fn engine(text: &str) -> PyResult<Engine> {
    match text {
        "auto" => Ok(Engine::Auto),
        "scalar" => Ok(Engine::Scalar),
        "simd" => Ok(Engine::Simd),
        _ => Err(PyValueError::new_err(format!(
            "engine '{text}' is not one of 'auto', 'scalar', 'simd'"
        ))),
    }
}

/// `auto`, `walk` or `jump`: how straight flights cross the lattice.
pub fn flights(text: &str) -> PyResult<lorentz_gas::engine::long_flight::Flights> {
    text.parse().map_err(py_err)
}

/// `f64` or a number of MPFR bits (53 or more).
pub fn precision(text: &str) -> PyResult<Precision> {
    text.parse::<Precision>().map_err(py_err)
}
