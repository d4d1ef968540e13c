//! The verification analyses' Python bindings: `lyapunov` (with `field=`), `audit`, `shadow`,
//! `certify` and `trajectory`, each the command line's analysis with its bits.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lorentz_gas::engine::Engine;
use lorentz_gas::engine::long_flight::Flights;
use lorentz_gas::estimators::trajectory::{self, MAX_DIGITS, TrajectoryInput};
use lorentz_gas::numbers::exact::parse_exact;
use lorentz_gas::report::text::lyapunov::LyapunovResult;
use lorentz_gas::scenes::Scene;
use lorentz_gas::verification::certify::{self, CertifyConfig};
use lorentz_gas::verification::divergence::{self, DivergenceConfig};
use lorentz_gas::verification::lyapunov::{self, LyapunovConfig};
use lorentz_gas::verification::shadow_audit::{self, AuditConfig};
use lorentz_gas::verification::shadowing::{self, ShadowConfig};

use crate::inputs::{self, count_u32, count_u64, count_usize, exact};
use crate::scenes::resolve;
use crate::watch::{compute, json};
use lorentz_gas::scenes::spec::SceneChoice;
use lorentz_gas::with_scene;

use crate::analyses::options;

/// Most divergence starts: each costs about a second of MPFR work at 4096 bits.
const MAX_STARTS: u32 = 10_000;

#[pyfunction]
#[pyo3(name = "lyapunov", signature = (scene, w, radius, collisions_per_batch, batches, starts, seed, threads, field, flights, progress))]
#[allow(clippy::too_many_arguments)]
fn py_lyapunov(
    py: Python<'_>,
    scene: &str,
    w: Option<&str>,
    radius: Option<&str>,
    collisions_per_batch: &str,
    batches: &str,
    starts: Option<&str>,
    seed: &str,
    threads: Option<&str>,
    field: Option<&str>,
    flights: &str,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let flights = inputs::flights(flights)?;
    if let Some(b) = field.filter(|b| parse_exact(b).is_ok_and(|q| q != 0)) {
        if flights == Flights::Jump {
            return Err(PyValueError::new_err(
                "flights = jump: arcs in a field cross the lattice cell by cell; use walk or auto",
            ));
        }
        return crate::field::lyapunov_in_field(
            py,
            (scene, w, radius),
            (
                collisions_per_batch,
                batches,
                starts.unwrap_or("0"),
                seed,
                threads,
            ),
            b,
            progress,
        );
    }
    let choice = resolve(scene, w, radius)?;
    let starts = match starts {
        Some(s) => count_u32("starts", s)?,
        None => with_scene!(&choice, |s| divergence::default_starts(s, flights))
            .map_err(|e| PyValueError::new_err(e.to_string()))?,
    };
    if starts == 1 || starts > MAX_STARTS {
        return Err(PyValueError::new_err(format!(
            "starts = {starts}: use 0 (no divergence measurement) or 2 to {MAX_STARTS} (the error \
             bars are over the starts, reliable from 4; each costs about a second)"
        )));
    }
    let seed = count_u64("seed", seed)?;
    let cfg = LyapunovConfig {
        collisions_per_batch: count_u64("collisions_per_batch", collisions_per_batch)?,
        batches: count_u32("batches", batches)?,
        seed,
        flights,
    };
    let threads = inputs::threads(threads)?;
    let r = compute(py, progress, |ctl| {
        let opts = options(ctl, threads, Engine::Auto);
        let tangent = with_scene!(&choice, |s| lyapunov::run(s, &cfg, &opts))?;
        let divergence = if starts > 0 {
            let d = DivergenceConfig {
                starts,
                seed,
                ..DivergenceConfig::new()
            };
            let one = options(ctl, 1, Engine::Auto);
            with_scene!(&choice, |s| divergence::run(s, &d, &one))?
        } else {
            Vec::new()
        };
        Ok(LyapunovResult {
            tangent,
            divergence,
        })
    })?;
    json(&r)
}

#[pyfunction]
#[pyo3(name = "audit", signature = (scene, w, radius, collisions, batches, sample, reference_bits, seed, field, flights, threads, progress))]
#[allow(clippy::too_many_arguments)]
fn py_audit(
    py: Python<'_>,
    scene: &str,
    w: Option<&str>,
    radius: Option<&str>,
    collisions: &str,
    batches: &str,
    sample: f64,
    reference_bits: &str,
    seed: &str,
    field: Option<&str>,
    flights: &str,
    threads: Option<&str>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let choice = resolve(scene, w, radius)?;
    let flights = inputs::flights(flights)?;
    let cfg = AuditConfig {
        scene: with_scene!(&choice, |s| s.label()),
        collisions: count_u64("collisions", collisions)?,
        batches: count_u32("batches", batches)?,
        sample,
        reference_bits: count_u32("reference_bits", reference_bits)?,
        seed: count_u64("seed", seed)?,
        field: field.map(str::to_string),
        flights,
    };
    let threads = inputs::threads(threads)?;
    let r = compute(py, progress, |ctl| {
        let opts = options(ctl, threads, Engine::Auto);
        with_scene!(&choice, |s| shadow_audit::run(s, &cfg, &opts))
    })?;
    json(&r)
}

#[pyfunction]
#[pyo3(name = "shadow", signature = (scene, w, radius, collisions_per_segment, segments, reference_bits, seed, field, threads, progress))]
#[allow(clippy::too_many_arguments)]
fn py_shadow(
    py: Python<'_>,
    scene: &str,
    w: Option<&str>,
    radius: Option<&str>,
    collisions_per_segment: &str,
    segments: &str,
    reference_bits: &str,
    seed: &str,
    field: Option<&str>,
    threads: Option<&str>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    // The triangular scene's gap as the command line's `shadow --w` takes it: 0 < w < w_inf.
    if let (Some(w), "triangular") = (w, scene) {
        inputs::diffusive_gap(w)?;
    }
    let choice = resolve(scene, w, radius)?;
    let request = ShadowConfig {
        collisions_per_segment: count_usize("collisions_per_segment", collisions_per_segment)?,
        segments: count_u32("segments", segments)?,
        seed: count_u64("seed", seed)?,
        reference_bits: count_u32("reference_bits", reference_bits)?,
        field: field.map(str::to_string),
    };
    request.validate().map_err(crate::py_err)?;
    let threads = inputs::threads(threads)?;
    let r = compute(py, progress, |ctl| {
        let opts = options(ctl, threads, Engine::Auto);
        with_scene!(&choice, |s| shadowing::run(s, &request, &opts))
    })?;
    json(&r)
}

#[pyfunction]
#[pyo3(name = "certify", signature = (scene, w, radius, collisions, digits, seed, progress))]
#[allow(clippy::too_many_arguments)]
fn py_certify(
    py: Python<'_>,
    scene: &str,
    w: Option<&str>,
    radius: Option<&str>,
    collisions: &str,
    digits: &str,
    seed: &str,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    let choice = resolve(scene, w, radius)?;
    let cfg = CertifyConfig {
        collisions: count_usize("collisions", collisions)?,
        digits: count_u32("digits", digits)?,
        seed: count_u64("seed", seed)?,
    };
    let r = compute(py, progress, |ctl| {
        let opts = options(ctl, 1, Engine::Auto);
        with_scene!(&choice, |s| certify::run(s, &cfg, &opts))
    })?;
    json(&r)
}

/// One exact number of a trajectory's input, named for its message.
fn exact_q(name: &str, text: &str) -> PyResult<rug::Rational> {
    parse_exact(text).map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
}

#[pyfunction]
#[pyo3(name = "trajectory", signature = (scene, w, radius, start, direction, time, digits, events, field, progress))]
#[allow(clippy::too_many_arguments)]
fn py_trajectory(
    py: Python<'_>,
    scene: &str,
    w: Option<&str>,
    radius: Option<&str>,
    start: (String, String),
    direction: (String, String),
    time: &str,
    digits: &str,
    events: bool,
    field: Option<&str>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<(String, String)> {
    let digits = count_u32("digits", digits)?;
    if digits == 0 || digits > MAX_DIGITS {
        return Err(PyValueError::new_err(format!(
            "digits = {digits} is out of range: use 1 to {MAX_DIGITS}"
        )));
    }
    let input = TrajectoryInput {
        x: exact_q("start", &start.0)?,
        y: exact_q("start", &start.1)?,
        dx: exact_q("direction", &direction.0)?,
        dy: exact_q("direction", &direction.1)?,
        time: exact_q("time", time)?,
        digits,
        record_events: events,
        field: field.map(|b| exact_q("field", b)).transpose()?,
    };
    // Any gap w > 0 (the trajectory is one orbit: no diffusive range is needed).
    let choice = match (scene, w) {
        ("triangular", Some(w)) => {
            let q = exact("w", w)?.rational("w").map_err(crate::py_err)?;
            if q <= 0 {
                return Err(PyValueError::new_err(format!(
                    "w = {} is out of range: use w > 0 (at w <= 0 the disks touch)",
                    lorentz_gas::numbers::exact::nearest_f64(&q)
                )));
            }
            SceneChoice::Triangular(Box::new(
                lorentz_gas::scenes::triangular::TriangularScene::exact(q)
                    .map_err(crate::py_err)?,
            ))
        }
        _ => resolve(scene, w, radius)?,
    };
    let r = compute(py, progress, |ctl| {
        let opts = options(ctl, 1, Engine::Auto);
        with_scene!(&choice, |s| trajectory::run(s, &input, &opts))
    })?;
    Ok((
        json(&r)?,
        lorentz_gas::report::text::trajectory::trajectory(&r, time),
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(py_lyapunov, m)?)?;
    m.add_function(wrap_pyfunction!(py_audit, m)?)?;
    m.add_function(wrap_pyfunction!(py_shadow, m)?)?;
    m.add_function(wrap_pyfunction!(py_certify, m)?)?;
    m.add_function(wrap_pyfunction!(py_trajectory, m)?)
}
