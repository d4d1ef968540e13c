//! What a throughput measurement can time: [`check`] refuses the rest before any work.

use crate::Error;
use crate::engine::options::{RunOption, RunOptions};
use crate::engine::{Resolved, SimdPath};
use crate::numbers::precision::Precision;
use crate::scenes::spec::Table;
use crate::scenes::triangular::geometry::Geometry;

use super::{MAX_REPETITIONS, Observe, ThroughputConfig, arcs};

/// What [`check`] found a measurement to be.
pub(super) struct Checked {
    /// The gap as its nearest double.
    pub(super) w: f64,
    /// The field (`None` for straight flights).
    pub(super) field: Option<f64>,
    /// The engine that runs.
    pub(super) resolved: Resolved,
    /// With `oracle_floor`: the field and SIMD path of the winner-only floor.
    pub(super) oracle: Option<(f64, SimdPath)>,
}

/// Refuses what [`run`](super::run) cannot time.
pub(super) fn check(cfg: &ThroughputConfig, options: &RunOptions) -> Result<Checked, Error> {
    options.accept("throughput", &[RunOption::Engine])?;
    cfg.table.motion_taken_by("throughput")?;
    let w = gap(&cfg.table)?;
    if cfg.collisions_per_thread == 0 {
        return Err(Error::Zero {
            what: "collisions_per_thread",
        });
    }
    let reps = cfg.repetitions;
    if reps == 0 || reps > MAX_REPETITIONS {
        return Err(Error::out_of_range(
            "repetitions",
            reps,
            format!("use 1 to {MAX_REPETITIONS}"),
        ));
    }
    if options.threads == 0 {
        return Err(Error::Zero { what: "threads" });
    }
    let field = cfg.field.filter(|b| *b != 0.0);
    if let Some(b) = field {
        // The transport analyses' range: beyond it the arc engine's starts are all pinned.
        crate::scenes::spec::field_within(b, &format!("{b:e}"), crate::scenes::spec::FIELD_RANGE)?;
    }
    if cfg.diffusion_beside && field.is_none() {
        return Err(Error::parameter(
            "diffusion_beside",
            true,
            "times a field run beside the arc engine: give a nonzero field",
        ));
    }
    if cfg.straight_beside && field.is_none() {
        return Err(Error::parameter(
            "straight_beside",
            true,
            "times straight flights beside arcs: give a nonzero field",
        ));
    }
    const TABLE_BESIDE: &str = "a table is timed by its bare straight flights beside the \
                                triangular gas: leave it out";
    if let (Some(_), Some(b)) = (&cfg.table_beside, field) {
        return Err(Error::parameter("field", b, TABLE_BESIDE));
    }
    if cfg.table_beside.is_some() && cfg.observe != Observe::None {
        let observe = format!("{:?}", cfg.observe).to_lowercase();
        return Err(Error::parameter("observe", observe, TABLE_BESIDE));
    }
    if cfg.table_beside.is_some() && cfg.precision != Precision::F64 {
        return Err(Error::out_of_range(
            "precision",
            cfg.precision.to_string(),
            "use f64 with a table timed beside the triangular gas",
        ));
    }
    let (precision, engine) = (cfg.precision, options.engine);
    let resolved = match field {
        Some(b) => arcs::check(b, precision, cfg.observe, engine)?,
        None => engine.resolve(precision == Precision::F64)?,
    };
    let oracle_path = match (cfg.oracle_floor, field, resolved.simd()) {
        (false, ..) => None,
        (true, Some(b), Some(path)) => Some((b, path)),
        _ => {
            return Err(Error::parameter(
                "oracle_floor",
                true,
                "times the SIMD arc engine against its winner-only floor: give a nonzero field \
                 and a SIMD engine",
            ));
        }
    };
    Ok(Checked {
        w,
        field,
        resolved,
        oracle: oracle_path,
    })
}

/// The gap of the triangular gas timed (w > 0) as its nearest double: another scene is refused
/// ([`Error::Lacks`] trap symbols; a table given as data is timed beside it), and so is a table
/// in a field (the bench flies arcs in its own `field`).
fn gap(table: &Table) -> Result<f64, Error> {
    let w = table.gap_for("throughput")?;
    if let Some(b) = table.field() {
        return Err(Error::parameter(
            "field",
            b,
            "the bench flies arcs in its own `field`: give the table without one",
        ));
    }
    Geometry::new(w)?;
    Ok(w)
}
