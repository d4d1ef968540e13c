//! The verification analyses' readers: `lyapunov` (with `field=`), `audit`, `shadow`,
//! `certify` and `trajectory`, each the command line's analysis with its bits.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lorentz_gas::engine::Engine;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::current::lyapunov as driven;
use lorentz_gas::estimators::field::lyapunov as field_lyapunov;
use lorentz_gas::estimators::trajectory::{self, MAX_DIGITS, TrajectoryInput};
use lorentz_gas::numbers::exact::parse_exact;
use lorentz_gas::report::text::lyapunov::LyapunovResult;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::motion::MotionInput;
use lorentz_gas::scenes::spec::Motion;
use lorentz_gas::scenes::spec::SceneChoice;
use lorentz_gas::verification::certify::{self, CertifyConfig};
use lorentz_gas::verification::divergence::{self, DivergenceConfig};
use lorentz_gas::verification::lyapunov::{self, LyapunovConfig};
use lorentz_gas::verification::shadow_audit::{self, AuditConfig};
use lorentz_gas::verification::shadowing::{self, ShadowConfig};
use lorentz_gas::with_scene;

use crate::analyses::options;
use crate::inputs::{self, count_u32, exact};
use crate::params::{Params, Progress, Work, work};
use crate::scenes::Where;
use crate::watch::{compute, json};

/// Most divergence starts: each costs about a second of MPFR work at 4096 bits.
const MAX_STARTS: u32 = 10_000;

/// `lyapunov(params, progress)`: in a nonzero `field` on arcs, else the tangent dynamics of
/// straight flights and the divergence of finite-precision orbits.
pub fn lyapunov(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let place = Where::read(p)?;
    let collisions_per_batch = p.count_u64("collisions_per_batch")?;
    let batches = p.count_u32("batches")?;
    let starts = p.opt_text("starts")?;
    let seed = p.count_u64("seed")?;
    let threads = p.threads()?;
    let field = p.opt_text("field")?;
    let (electric, electric_angle) = (p.opt_text("electric")?, p.opt_text("electric_angle")?);
    let flights = p.flights()?;
    Ok(work(move |py, progress| {
        let cfg = LyapunovConfig {
            collisions_per_batch,
            batches,
            seed,
            flights,
            ..LyapunovConfig::new()
        };
        // Zero fields are straight flights, recorded as such (`MotionInput::with_field`); the
        // shape is checked by `resolve()` below, as for every configuration.
        let motion = match (&electric, &electric_angle) {
            (Some(e), a) => MotionInput::default().with_electric(e, a.as_deref().unwrap_or("0")),
            (None, a) => MotionInput {
                electric_angle: a.clone(),
                ..Default::default()
            },
        }
        .with_field(field.as_deref().unwrap_or("0"));
        let moving = LyapunovConfig { motion, ..cfg };
        let starts = (starts.as_deref(), threads);
        match moving.motion.resolve().map_err(crate::py_err)? {
            Motion::Field(_) => {
                without_divergence(py, progress, &place, starts, "in a field", |c, o| {
                    with_scene!(c, |s| field_lyapunov::run(s, &moving, o))
                })
            }
            Motion::Thermostat { .. } => without_divergence(
                py,
                progress,
                &place,
                starts,
                "under the thermostat",
                |c, o| with_scene!(c, |s| driven::run(s, &moving, o)),
            ),
            _ => straight_lyapunov(py, progress, &place, cfg, starts),
        }
    }))
}

/// An exponent whose divergence of finite-precision orbits is not measured (`starts` as typed:
/// `None` or 0; `within` says where, for the refusal): `run` on the place's scene with the
/// call's options (the command line's `--field` and `--electric`).
fn without_divergence<R: serde::Serialize + Send>(
    py: Python<'_>,
    progress: Progress<'_>,
    place: &Where,
    (starts, threads): (Option<&str>, usize),
    within: &str,
    run: impl FnOnce(&SceneChoice, &RunOptions<'_>) -> Result<R, lorentz_gas::Error> + Send,
) -> PyResult<String> {
    if count_u32("starts", starts.unwrap_or("0"))? > 0 {
        return Err(PyValueError::new_err(format!(
            "starts (the divergence of finite-precision orbits) is not measured {within}: give \
             starts=0"
        )));
    }
    let choice = place.resolve()?;
    let r = compute(py, progress, |ctl| {
        run(&choice, &options(ctl, threads, Engine::Auto))
    })?;
    json(&r)
}

/// The exponent of straight flights, with the divergence of `starts` finite-precision orbits
/// (`None`: the scene's default).
fn straight_lyapunov(
    py: Python<'_>,
    progress: Progress<'_>,
    place: &Where,
    cfg: LyapunovConfig,
    (starts, threads): (Option<&str>, usize),
) -> PyResult<String> {
    let choice = place.resolve()?;
    let starts = match starts {
        Some(s) => count_u32("starts", s)?,
        None => with_scene!(&choice, |s| divergence::default_starts(s, cfg.flights))
            .map_err(|e| PyValueError::new_err(e.to_string()))?,
    };
    if starts == 1 || starts > MAX_STARTS {
        return Err(PyValueError::new_err(format!(
            "starts = {starts}: use 0 (no divergence measurement) or 2 to {MAX_STARTS} (the error \
             bars are over the starts, reliable from 4; each costs about a second)"
        )));
    }
    let r = compute(py, progress, |ctl| {
        let opts = options(ctl, threads, Engine::Auto);
        let tangent = with_scene!(&choice, |s| lyapunov::run(s, &cfg, &opts))?;
        let divergence = if starts > 0 {
            let d = DivergenceConfig {
                starts,
                seed: cfg.seed,
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

/// `audit(params, progress)`: f64 events replayed in MPFR.
pub fn audit(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let place = Where::read(p)?;
    let collisions = p.count_u64("collisions")?;
    let batches = p.count_u32("batches")?;
    let sample = p.number("sample")?;
    let reference_bits = p.count_u32("reference_bits")?;
    let seed = p.count_u64("seed")?;
    let field = p.opt_text("field")?;
    let electric = p.opt_text("electric")?;
    let electric_angle = p.opt_text("electric_angle")?;
    let flights = p.flights()?;
    let threads = p.threads()?;
    Ok(work(move |py, progress| {
        let choice = place.resolve()?;
        let cfg = AuditConfig {
            scene: with_scene!(&choice, |s| s.label()),
            collisions,
            batches,
            sample,
            reference_bits,
            seed,
            motion: MotionInput {
                field,
                electric,
                electric_angle,
            },
            flights,
        };
        json(&compute(py, progress, |ctl| {
            let opts = options(ctl, threads, Engine::Auto);
            with_scene!(&choice, |s| shadow_audit::run(s, &cfg, &opts))
        })?)
    }))
}

/// `shadow(params, progress)`: true orbits shadowing f64 segments.
pub fn shadow(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let place = Where::read(p)?;
    // E = 0 is the run without a field, recorded as such (the command line's rule).
    let angle = p.opt_text("electric_angle")?;
    let given = MotionInput {
        field: p.opt_text("field")?,
        ..Default::default()
    };
    let motion = match p.opt_text("electric")? {
        Some(e) => given.with_electric(&e, angle.as_deref().unwrap_or("0")),
        None => MotionInput {
            electric_angle: angle,
            ..given
        },
    };
    let request = ShadowConfig {
        collisions_per_segment: p.count_usize("collisions_per_segment")?,
        segments: p.count_u32("segments")?,
        reference_bits: p.count_u32("reference_bits")?,
        seed: p.count_u64("seed")?,
        motion,
    };
    let threads = p.threads()?;
    Ok(work(move |py, progress| {
        // The triangular scene's gap as the command line's `shadow --w` takes it: 0 < w < w_inf.
        if let (Some(w), "triangular", None) = (&place.w, place.name.as_str(), &place.table) {
            inputs::diffusive_gap(w)?;
        }
        let choice = place.resolve()?;
        request.validate().map_err(crate::py_err)?;
        json(&compute(py, progress, |ctl| {
            let opts = options(ctl, threads, Engine::Auto);
            with_scene!(&choice, |s| shadowing::run(s, &request, &opts))
        })?)
    }))
}

/// `certify(params, progress)`: a segment certified to its digits.
pub fn certify(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let place = Where::read(p)?;
    let cfg = CertifyConfig {
        collisions: p.count_usize("collisions")?,
        digits: p.count_u32("digits")?,
        seed: p.count_u64("seed")?,
    };
    Ok(work(move |py, progress| {
        let choice = place.resolve()?;
        json(&compute(py, progress, |ctl| {
            let opts = options(ctl, 1, Engine::Auto);
            with_scene!(&choice, |s| certify::run(s, &cfg, &opts))
        })?)
    }))
}

/// One exact number of a trajectory's input, named for its message.
fn exact_q(name: &str, text: &str) -> PyResult<rug::Rational> {
    parse_exact(text).map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
}

/// `trajectory(params, progress)`: one orbit from exact initial conditions.
pub fn trajectory(p: &Params<'_, '_>) -> PyResult<Work<(String, String)>> {
    let place = Where::read_without_table(p)?;
    let (start, direction) = (p.text_pair("start")?, p.text_pair("direction")?);
    let time = p.text("time")?;
    let digits = p.count_u32("digits")?;
    let events = p.flag("events")?;
    let field = p.opt_text("field")?;
    let (electric, electric_angle) = (p.opt_text("electric")?, p.opt_text("electric_angle")?);
    Ok(work(move |py, progress| {
        crate::analyses::motion_shape(&field, &electric, &electric_angle)?;
        let electric = match (electric, electric_angle) {
            (Some(e), a) => Some((
                exact_q("electric", &e)?,
                exact_q("electric_angle", a.as_deref().unwrap_or("0"))?,
            )),
            (None, _) => None,
        };
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
            time: exact_q("time", &time)?,
            digits,
            record_events: events,
            field: field.map(|b| exact_q("field", &b)).transpose()?,
            electric,
        };
        let choice = orbit_scene(&place)?;
        let r = compute(py, progress, |ctl| {
            let opts = options(ctl, 1, Engine::Auto);
            with_scene!(&choice, |s| trajectory::run(s, &input, &opts))
        })?;
        Ok((
            json(&r)?,
            lorentz_gas::report::text::trajectory::trajectory(&r, &time),
        ))
    }))
}

/// The scene of one orbit: on the triangular lattice any gap w > 0 (no diffusive range is
/// needed).
fn orbit_scene(place: &Where) -> PyResult<SceneChoice> {
    match (place.name.as_str(), &place.w) {
        ("triangular", Some(w)) => {
            let q = exact("w", w)?.rational("w").map_err(crate::py_err)?;
            if q <= 0 {
                return Err(PyValueError::new_err(format!(
                    "w = {} is out of range: use w > 0 (at w <= 0 the disks touch)",
                    lorentz_gas::numbers::exact::nearest_f64(&q)
                )));
            }
            Ok(SceneChoice::Triangular(Box::new(
                lorentz_gas::scenes::triangular::TriangularScene::exact(q)
                    .map_err(crate::py_err)?,
            )))
        }
        _ => place.resolve(),
    }
}
