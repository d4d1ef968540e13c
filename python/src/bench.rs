//! `bench`: the engine's throughput on this machine (`lorentz bench`), bare or with the
//! observers of an analysis, straight or in a magnetic field, or a table given as data beside
//! the triangular gas.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use lorentz_gas::estimators::throughput::long_flights::{self as long, LongFlightBenchConfig};
use lorentz_gas::estimators::throughput::thermostat::{self, ElectricBenchConfig};
use lorentz_gas::estimators::throughput::{self, Observe, ThroughputConfig};
use lorentz_gas::scenes::spec::Table;
use lorentz_gas::scenes::table::PeriodicTable;
use lorentz_gas::scenes::table::spec::TableSpec;

use crate::analyses::{motion_shape, options};
use crate::inputs;
use crate::params::{Params, Work, work};
use crate::watch::{compute, json};

/// The observers, by the command line's names.
fn observe(text: &str) -> PyResult<Observe> {
    serde_json::from_value(serde_json::Value::String(text.into())).map_err(|_| {
        PyValueError::new_err(format!(
            "observe '{text}' is not one of 'none', 'counters', 'msd', 'diffusion', 'hops'"
        ))
    })
}

/// The table timed beside the triangular gas (its JSON), checked as every analysis checks a
/// table (disks that overlap are refused naming them).
fn table(json: &str) -> PyResult<TableSpec> {
    let spec = TableSpec::from_json(json).map_err(crate::py_err)?;
    PeriodicTable::new(&spec).map_err(crate::py_err)?;
    Ok(spec)
}

/// `bench(params, progress)`.
pub fn bench(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let w = p.text("w")?;
    let collisions_per_thread = p.count_u64("collisions_per_thread")?;
    let repetitions = p.count_usize("repetitions")?;
    let precision = p.precision()?;
    let engine = p.engine()?;
    let observe = p.parsed("observe", Observe::None, self::observe)?;
    let seed = p.count_u64("seed")?;
    let threads = p.parsed("threads", 1, |t| inputs::threads(Some(t)))?;
    let field = p.opt_text("field")?;
    let straight_beside = p.flag("straight_beside")?;
    let diffusion_beside = p.flag("diffusion_beside")?;
    let oracle_floor = p.flag("oracle_floor")?;
    let table = p.opt_text("table")?;
    let electric = p.opt_text("electric")?;
    let electric_angle = p.opt_text("electric_angle")?;
    Ok(work(move |py, progress| {
        motion_shape(&field, &electric, &electric_angle)?;
        let field = match field {
            Some(b) => Some(inputs::exact("field", &b)?.value).filter(|b| *b != 0.0),
            None => None,
        };
        let w = inputs::exact("w", &w)?;
        let cfg = ThroughputConfig {
            table: Table::triangular(&w.text).map_err(crate::py_err)?,
            precision,
            observe,
            collisions_per_thread,
            repetitions,
            seed,
            field,
            straight_beside,
            oracle_floor,
            diffusion_beside,
            table_beside: table.as_deref().map(self::table).transpose()?,
        };
        if let Some(e) = electric {
            let angle = electric_angle.as_deref().unwrap_or("0");
            let cfg = ElectricBenchConfig {
                straight: cfg,
                electric: inputs::exact("electric", &e)?.value,
                electric_angle: inputs::exact("electric_angle", angle)?.text,
            };
            return json(&compute(py, progress, |ctl| {
                thermostat::run(&cfg, &options(ctl, threads, engine))
            })?);
        }
        json(&compute(py, progress, |ctl| {
            throughput::run(&cfg, &options(ctl, threads, engine))
        })?)
    }))
}

/// `bench_long_flights(params, progress)`: a collision's cost against its flight's length on
/// the square scene (the command line's `--long-flights`), one thread.
pub fn long_flights(p: &Params<'_, '_>) -> PyResult<Work<String>> {
    let scene = p.text("scene")?;
    let values = p.texts("long_flights")?;
    let collisions = p.count_u64("collisions_per_radius")?;
    let walk_collisions = p.count_u64("walk_collisions")?;
    let repetitions = p.count_usize("repetitions")?;
    let seed = p.count_u64("seed")?;
    Ok(work(move |py, progress| {
        let (radii, gaps) = match scene.as_str() {
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
            collisions,
            walk_collisions,
            repetitions,
            seed,
        };
        cfg.scenes()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        json(&compute(py, progress, |ctl| {
            long::run(&cfg, &options(ctl, 1, lorentz_gas::engine::Engine::Auto))
        })?)
    }))
}
