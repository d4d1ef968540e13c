//! One reader per analysis: the values of its dict (`Params`), the library's configuration
//! (checked by its `validate`), `run(&config, &options)` on a worker thread, the result as the
//! command line's JSON.

use std::path::PathBuf;
use std::time::Duration;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use lorentz_gas::engine::Engine;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::escape::{self, EscapeConfig};
use lorentz_gas::estimators::free_paths::{self, FreePathConfig};
use lorentz_gas::estimators::hops::backscatter::{self, BackscatterConfig};
use lorentz_gas::estimators::hops::{self, HopsConfig};
use lorentz_gas::estimators::superdiffusion::{self, SuperdiffusionConfig};
use lorentz_gas::estimators::sweep::{GapGrid, Grid};
use lorentz_gas::report::publication::{self, AuditConfig as PublicationConfig};
use lorentz_gas::scenes::motion::MotionInput;
use lorentz_gas::scenes::spec::{Motion, Table};
use lorentz_gas::theory::constants::{self, ConstantsConfig};

use crate::inputs::{self, exact};
use crate::params::{Params, Work, work};
use crate::scenes::Where;
use crate::watch::{Ctl, compute, json};

/// The motion the keywords `field`, `electric` and `electric_angle` give
/// ([`MotionInput::resolve`]: at most one field, an angle only with `electric`), each as typed.
pub(crate) fn motion_shape(
    field: &Option<String>,
    electric: &Option<String>,
    electric_angle: &Option<String>,
) -> PyResult<Motion> {
    let input = MotionInput {
        field: field.clone(),
        electric: electric.clone(),
        electric_angle: electric_angle.clone(),
    };
    input.resolve().map_err(crate::py_err)
}

/// The run options of a computation watched by `ctl`.
pub(crate) fn options<'a>(ctl: &'a Ctl<'a>, threads: usize, engine: Engine) -> RunOptions<'a> {
    RunOptions {
        engine,
        threads,
        progress: ctl.progress,
        stop: Some(ctl.stop.clone()),
        ..RunOptions::default()
    }
}

/// `w`: the triangular gas at a gap at which D exists (0 < w < w_inf), exactly as given.
pub(crate) fn diffusive_gap(p: &Params<'_, '_>) -> PyResult<Table> {
    p.parsed("w", Table::triangular_at(0.1), |t| {
        let w = inputs::diffusive_gap(t)?;
        Table::triangular(&w.text).map_err(crate::py_err)
    })
}

/// The configuration of a hop analysis (hops, theory, lattice walks).
fn hop_config(p: &Params<'_, '_>) -> PyResult<HopsConfig> {
    Ok(HopsConfig {
        table: diffusive_gap(p)?,
        collisions: p.count_u64("collisions")?,
        batches: p.count_u32("batches")?,
        order: p.count_usize("order")?,
        seed: p.count_u64("seed")?,
        run: 0,
    })
}

/// The threads and the checkpoint of a resumable analysis, checked before any work.
struct Kept {
    threads: usize,
    checkpoint: Option<PathBuf>,
    every: Duration,
}

impl Kept {
    /// `threads`, `checkpoint` and `checkpoint_every`.
    fn read(p: &Params<'_, '_>) -> PyResult<Self> {
        Ok(Kept {
            threads: p.threads()?,
            checkpoint: p.opt_path("checkpoint")?,
            every: p.checkpoint_every()?,
        })
    }

    fn options<'a>(&self, ctl: &'a Ctl<'a>, engine: Engine) -> RunOptions<'a> {
        RunOptions {
            resume: self.checkpoint.clone(),
            checkpoint_every: self.every,
            ..options(ctl, self.threads, engine)
        }
    }
}

/// `hops(params, progress)`.
pub fn hops(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let cfg = hop_config(p)?;
    let engine = p.engine()?;
    let kept = Kept::read(p)?;
    Ok(work(move |py, progress| {
        json(&compute(py, progress, |ctl| {
            hops::run(&cfg, &kept.options(ctl, engine))
        })?)
    }))
}

/// `theory(params, progress)`.
pub fn theory(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let (cfg, kept) = (hop_config(p)?, Kept::read(p)?);
    Ok(work(move |py, progress| {
        json(&compute(py, progress, |ctl| {
            hops::theory::run(&cfg, &kept.options(ctl, Engine::Auto))
        })?)
    }))
}

/// `lattice_walk(params, progress)`.
pub fn lattice_walk(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let (cfg, kept) = (hop_config(p)?, Kept::read(p)?);
    Ok(work(move |py, progress| {
        json(&compute(py, progress, |ctl| {
            hops::lattice_walks::run(&cfg, &kept.options(ctl, Engine::Auto))
        })?)
    }))
}

/// `backscatter(params, progress)`.
pub fn backscatter(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let w = p.text("w")?;
    let particles = p.count_u64("particles")?;
    let batches = p.count_u32("batches")?;
    let seed = p.count_u64("seed")?;
    let threads = p.threads()?;
    let precision = p.precision()?;
    Ok(work(move |py, progress| {
        let w = exact("w", &w)?;
        let cfg = BackscatterConfig {
            table: Table::triangular(&w.text).map_err(crate::py_err)?,
            particles,
            batches,
            seed,
            run: 0,
            precision,
        };
        json(&compute(py, progress, |ctl| {
            backscatter::run(&cfg, &options(ctl, threads, Engine::Auto))
        })?)
    }))
}

/// `sweep(params, progress)`: D over gaps without a field.
pub fn sweep(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let grid = Grid::Gaps(GapGrid {
        w_from: p.text("w_from")?.trim().to_string(),
        w_to: p.text("w_to")?.trim().to_string(),
        steps: p.count_u32("steps")?,
        runs: p.count_u32("runs")?,
    });
    let sizes = crate::campaigns::sizes(p)?;
    let how = crate::campaigns::SweepRun {
        every: Some(p.checkpoint_every()?),
        ..crate::campaigns::SweepRun::read(p)?
    };
    Ok(work(move |py, progress| {
        crate::campaigns::run_grid(py, progress, grid, sizes, how)
    }))
}

/// `escape(params, progress)`.
pub fn escape(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let defaults = EscapeConfig::new(diffusive_gap(p)?);
    let widths = p.opt_numbers("widths")?;
    let cfg = EscapeConfig {
        widths: widths.unwrap_or(defaults.widths),
        particles_per_width: p.count_u64("particles_per_width")?,
        seed: p.count_u64("seed")?,
        table: defaults.table,
    };
    let kept = Kept::read(p)?;
    Ok(work(move |py, progress| {
        cfg.validate().map_err(crate::py_err)?;
        json(&compute(py, progress, |ctl| {
            escape::run(&cfg, &kept.options(ctl, Engine::Auto))
        })?)
    }))
}

/// `superdiffusion(params, progress)`.
pub fn superdiffusion(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let place = Where::read_without_table(p)?;
    let collisions = p.count_u64("collisions")?;
    let batches = p.count_u32("batches")?;
    let octaves = p.count_u32("octaves")?;
    let points_per_octave = p.count_u32("points_per_octave")?;
    let tail_fit_from = p.number("tail_fit_from")?;
    let (vacf_fit, msd_fit) = (p.opt_pair("vacf_fit")?, p.opt_pair("msd_fit")?);
    let (seed, flights) = (p.count_u64("seed")?, p.flights()?);
    let kept = Kept::read(p)?;
    Ok(work(move |py, progress| {
        // The scene and its parameter checked as every analysis checks them, kept as typed.
        let windows = SuperdiffusionConfig::new(place.spec()?).with_octaves(octaves);
        let cfg = SuperdiffusionConfig {
            collisions,
            batches,
            points_per_octave,
            tail_fit_from,
            vacf_fit: vacf_fit.unwrap_or(windows.vacf_fit),
            msd_fit: msd_fit.unwrap_or(windows.msd_fit),
            seed,
            flights,
            ..windows
        };
        json(&compute(py, progress, |ctl| {
            superdiffusion::run(&cfg, &kept.options(ctl, Engine::Auto))
        })?)
    }))
}

/// `free_paths(params, progress)`.
pub fn free_paths(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let place = Where::read(p)?;
    let collisions = p.count_u64("collisions")?;
    let batches = p.count_u32("batches")?;
    let seed = p.count_u64("seed")?;
    let flights = p.flights()?;
    let threads = p.threads()?;
    let bins = match p.opt_text("bins")? {
        Some(t) => Some(free_paths::parse_edges(&t).map_err(crate::py_err)?),
        None => None,
    };
    let keep_samples = p.count_u64("keep_samples")?;
    Ok(work(move |py, progress| {
        let cfg = FreePathConfig {
            collisions,
            batches,
            seed,
            flights,
            bins,
            keep_samples,
            ..FreePathConfig::new(place.spec()?)
        };
        cfg.validate().map_err(crate::py_err)?;
        json(&compute(py, progress, |ctl| {
            free_paths::run(&cfg, &options(ctl, threads, Engine::Auto))
        })?)
    }))
}

/// `report(params, progress)`: the publication audit of the result file `path`.
pub fn report(p: &Params<'_, '_>) -> PyResult<Work<(String, String)>> {
    let result = p.path("path")?;
    let out = p.opt_path("out")?;
    let quick = p.flag("quick")?;
    let reference_bits = p.count_u32("reference_bits")?;
    let max_rerun_collisions = p.opt_count_u64("max_rerun_collisions")?;
    let threads = p.threads()?;
    Ok(work(move |py, progress| {
        let out = out.unwrap_or_else(|| {
            let stem = result
                .file_stem()
                .map_or("result".into(), |s| s.to_string_lossy().to_string());
            result.with_file_name(format!("{stem}-report"))
        });
        let cfg = PublicationConfig {
            result,
            out: out.clone(),
            quick,
            reference_bits,
            max_rerun_collisions,
        };
        let r = compute(py, progress, |ctl| {
            publication::run(&cfg, &options(ctl, threads, Engine::Auto))
        })?;
        Ok((
            json(&r)?,
            lorentz_gas::report::text::publication::publication(&r, &out),
        ))
    }))
}

/// `constants(params)`: every closed form of a scene.
pub fn constants(
    p: &Params<'_, '_>,
) -> PyResult<impl FnOnce() -> PyResult<(String, String)> + use<>> {
    let (w, radius) = (p.opt_text("w")?, p.opt_text("radius")?);
    let precision = p.precision()?;
    Ok(move || {
        // Either parameter names the scene; both, or neither, is refused by the scene's own check.
        let name = if radius.is_some() && w.is_none() {
            "square"
        } else {
            "triangular"
        };
        let place = Where {
            name: name.into(),
            table: None,
            w,
            radius,
        };
        let r = constants::run(&ConstantsConfig {
            scene: place.spec()?,
            precision,
        })
        .map_err(crate::py_err)?;
        Ok((
            r.to_json().map_err(crate::py_err)?,
            lorentz_gas::report::text::constants::constants(&r),
        ))
    })
}

/// The crate's agreement bound: the Student-t quantile with `dof` degrees of freedom whose
/// two-sided tail equals that of 4 normal σ (6.3·10⁻⁵), for comparing a value with an error
/// from `dof + 1` batches (`statistics::comparison::agreement_bound`).
#[pyfunction]
#[pyo3(name = "agreement_bound", signature = (dof))]
fn py_agreement_bound(dof: f64) -> PyResult<f64> {
    if dof.is_nan() || dof < 1.0 {
        return Err(PyValueError::new_err(format!(
            "dof = {dof} is out of range: use 1 or more (inf for the normal 4σ)"
        )));
    }
    Ok(lorentz_gas::statistics::comparison::agreement_bound(dof))
}

#[pyfunction]
#[pyo3(name = "constants", signature = (params))]
fn py_constants(params: &Bound<'_, PyDict>) -> PyResult<(String, String)> {
    Params::read(params, constants)?()
}

/// Registers the analyses of this file in the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(py_constants, m)?)?;
    m.add_function(wrap_pyfunction!(py_agreement_bound, m)?)?;
    Ok(())
}
