//! `bench`: the engine's throughput on this machine (`lorentz bench`), bare or with the
//! observers of an analysis, straight or in a magnetic field.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lorentz_gas::estimators::throughput::long_flights::{self, LongFlightBenchConfig};
use lorentz_gas::estimators::throughput::{self, Observe, ThroughputConfig};

use crate::analyses::options;
use crate::inputs::{self, count_u64, count_usize};
use crate::watch::{compute, json};

/// The observers, by the command line's names.
fn observe(text: &str) -> PyResult<Observe> {
    serde_json::from_value(serde_json::Value::String(text.into())).map_err(|_| {
        PyValueError::new_err(format!(
            "observe '{text}' is not one of 'none', 'counters', 'msd', 'diffusion', 'hops'"
        ))
    })
}

#[pyfunction]
#[pyo3(name = "bench", signature = (w, collisions_per_thread, repetitions, precision, engine, observe, seed, threads, field, straight_beside, oracle_floor, progress))]
#[allow(clippy::too_many_arguments)]
fn py_bench(
    py: Python<'_>,
    w: &str,
    collisions_per_thread: &str,
    repetitions: &str,
    precision: &str,
    engine: &str,
    observe: &str,
    seed: &str,
    threads: &str,
    field: Option<&str>,
    straight_beside: bool,
    oracle_floor: bool,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let field = match field {
        Some(b) => Some(inputs::exact("field", b)?.value).filter(|b| *b != 0.0),
        None => None,
    };
    let cfg = ThroughputConfig {
        w: inputs::exact("w", w)?.value,
        precision: inputs::precision(precision)?,
        observe: self::observe(observe)?,
        collisions_per_thread: count_u64("collisions_per_thread", collisions_per_thread)?,
        repetitions: count_usize("repetitions", repetitions)?,
        seed: count_u64("seed", seed)?,
        field,
        straight_beside,
        oracle_floor,
        table: None,
    };
    let (threads, engine) = (inputs::threads(Some(threads))?, inputs::engine(engine)?);
    let r = compute(py, progress, |ctl| {
        throughput::run(&cfg, &options(ctl, threads, engine))
    })?;
    json(&r)
}

/// `bench(long_flights=...)`: a collision's cost against its flight's length on the square
/// scene (the command line's `--long-flights`), one thread.
#[pyfunction]
#[pyo3(name = "bench_long_flights", signature = (scene, values, collisions_per_radius, walk_collisions, repetitions, seed, progress))]
#[allow(clippy::too_many_arguments)]
fn py_bench_long_flights(
    py: Python<'_>,
    scene: &str,
    values: Vec<String>,
    collisions_per_radius: &str,
    walk_collisions: &str,
    repetitions: &str,
    seed: &str,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let (radii, gaps) = match scene {
        "square" => (values, Vec::new()),
        "triangular" => (Vec::new(), values),
        _ => {
            return Err(PyValueError::new_err(format!(
                "scene = {scene}: use square or triangular"
            )));
        }
    };
    let cfg = LongFlightBenchConfig {
        radii,
        gaps,
        collisions: count_u64("collisions_per_radius", collisions_per_radius)?,
        walk_collisions: count_u64("walk_collisions", walk_collisions)?,
        repetitions: count_usize("repetitions", repetitions)?,
        seed: count_u64("seed", seed)?,
    };
    cfg.scenes()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let r = compute(py, progress, |ctl| {
        long_flights::run(&cfg, &options(ctl, 1, lorentz_gas::engine::Engine::Auto))
    })?;
    json(&r)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(py_bench, m)?)?;
    m.add_function(wrap_pyfunction!(py_bench_long_flights, m)?)
}
