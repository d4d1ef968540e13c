//! What a sweep in a field checks before it runs a point: the work of the points still to run,
//! priced together, and one point reused from its file computed again — the guards of the
//! field-free sweep, shared (`engine::work`, [`points::recheck_one_point`]).

use std::path::Path;

use super::SweepConfig;
use super::field::{FieldGrid, FieldSweepRow, point_path};
use super::points;
use crate::Error;
use crate::engine::options::RunOptions;
use crate::scenes::spec::SceneSpec;

/// Refuses the points still to run when, together, even the floor costs make them longer than a
/// week of the sweep's threads: one check before the first point starts.
pub(super) fn check_work(
    cfg: &SweepConfig,
    fg: &FieldGrid,
    found: &[Option<FieldSweepRow>],
    owns: &dyn Fn(usize) -> bool,
    opts: &RunOptions,
) -> Result<(), Error> {
    let simd = matches!(opts.engine.resolve(true)?, crate::engine::Resolved::Simd(_));
    let mut parts = Vec::new();
    for (i, (point, old)) in fg.grid().into_iter().zip(found).enumerate() {
        if owns(i) && old.is_none() {
            let point = fg.point_config(cfg, i, point)?;
            parts.push(crate::estimators::field::work(&point, simd)?);
        }
    }
    let lower = &["collisions_per_run", "fields", "localization_samples"];
    crate::engine::work::Work::sum("a field sweep", lower, parts).check(opts.threads)
}

/// Computes one reused point again, drawn at random, and compares its row with the point file's
/// to the bit: the guard of every sweep ([`points::recheck_one_point`]).
pub(super) fn recheck_one_point(
    cfg: &SweepConfig,
    opts: &RunOptions,
    dir: Option<&Path>,
    found: &[Option<FieldSweepRow>],
) -> Result<(), Error> {
    let fg = cfg.field_grid()?;
    let opts = RunOptions {
        progress: &|_| {},
        ..opts.clone()
    };
    points::recheck_one_point(found, (dir, point_path), |i, recorded| {
        let grid = fg.grid();
        let Some(place) = grid.get(i) else {
            return Ok(None);
        };
        let point = fg.point_config(cfg, i, place.clone())?;
        let fresh = super::field::row_of(&crate::estimators::field::run(&point, &opts)?);
        let bits = |r: &FieldSweepRow| serde_json::to_value(r).ok();
        let same = bits(&fresh).is_some() && bits(&fresh) == bits(recorded);
        let at = match &place.0 {
            SceneSpec::Triangular { w } => format!("w = {w}"),
            SceneSpec::Square { radius } => format!("radius {radius}"),
            SceneSpec::Table(t) => t.title().to_string(),
        };
        Ok((!same).then(|| format!("point {i} ({at}, B = {}),", place.1)))
    })
}
