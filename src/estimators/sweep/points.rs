//! A sweep's finished points on disk: one JSON file per point in `DIR/points/`, written
//! atomically as each point finishes (the unit of resumption, and what a campaign's parts leave
//! for the merge).

use std::path::{Path, PathBuf};

use serde::Serialize;

use super::{RunValue, SweepConfig, SweepPoint};
use crate::engine::options::RunOptions;
use crate::engine::resume::{difference, write_atomically};
use crate::estimators::diffusion::{run_many, DiffusionConfig};
use crate::Error;

/// The file of point `i` in the sweep directory `dir`.
pub fn point_path(dir: &Path, i: usize) -> PathBuf {
    dir.join("points").join(format!("point-{i:04}.json"))
}

/// Runs (or reuses) the points i of `cfg` with `owns(i)`, in index order; with a directory
/// (`options.resume`), each is written to `DIR/points/` as it finishes and points already there
/// are reused. Returns the points and how many were reused.
pub(crate) fn run_points(
    cfg: &SweepConfig,
    options: &RunOptions,
    owns: impl Fn(u32) -> bool,
) -> Result<(Vec<SweepPoint>, u32), Error> {
    let dir = options.resume.as_deref();
    if let Some(d) = dir {
        crate::files::create_dir_all(d.join("points"))?;
    }
    let mut points = Vec::new();
    let mut resumed = 0;
    for (i, w) in cfg.points()?.into_iter().enumerate() {
        if !owns(i as u32) {
            continue;
        }
        if let Some(d) = dir {
            if let Some(p) = reuse(cfg, &point_path(d, i), i, w)? {
                (options.progress)(cfg.collisions.saturating_mul(cfg.runs as u64));
                points.push(p);
                resumed += 1;
                continue;
            }
        }
        let p = run_point(cfg, options, dir, i, w)?;
        points.push(p);
    }
    Ok((points, resumed))
}

/// The finished point `i` at `path`, if there is one of this sweep; a file of another sweep is an
/// error.
fn reuse(cfg: &SweepConfig, path: &Path, i: usize, w: f64) -> Result<Option<SweepPoint>, Error> {
    let Ok(text) = crate::files::read_to_string(path) else {
        return Ok(None);
    };
    let p = serde_json::from_str::<SweepPoint>(&text).map_err(|e| {
        Error::Invalid(format!(
            "{} is not a sweep point ({e}): use another --out",
            path.display()
        ))
    })?;
    if p.config != *cfg {
        return Err(Error::Invalid(format!(
            "{} belongs to another sweep ({}): use another --out",
            path.display(),
            difference(&p.config, cfg).unwrap_or_else(|| "another configuration".into())
        )));
    }
    if p.w != w || p.index as usize != i {
        return Err(Error::Invalid(format!(
            "{} is point {} at w = {}, not point {i} at w = {w}: a damaged point file",
            path.display(),
            p.index,
            p.w
        )));
    }
    Ok(Some(p))
}

/// Runs point `i` (its runs packed together), written to `dir` if given.
fn run_point(
    cfg: &SweepConfig,
    options: &RunOptions,
    dir: Option<&Path>,
    i: usize,
    w: f64,
) -> Result<SweepPoint, Error> {
    let cfgs: Vec<DiffusionConfig> = (0..cfg.runs)
        .map(|r| cfg.run_config(i as u32, w, r))
        .collect();
    // Finished batches of this point are journalled as they come, so that an interruption
    // loses at most the blocks in flight, not the point's finished runs.
    let path = dir.map(|d| point_path(d, i));
    let journal = path.as_ref().map(|p| p.with_extension("partial"));
    let opts = RunOptions {
        resume: journal.clone(),
        audit: None,
        ..options.clone()
    };
    let runs = run_many(&cfgs, &opts)?
        .into_iter()
        .map(|rep| RunValue {
            D: rep.D,
            D_err: rep.D_err,
        })
        .collect();
    let p = SweepPoint {
        config: cfg.clone(),
        index: i as u32,
        w,
        runs,
    };
    if let (Some(path), Some(journal)) = (path, journal) {
        write_atomically(
            &path,
            serde_json::to_string(&p).map_err(Error::encode)?.as_bytes(),
        )?;
        let _ = std::fs::remove_file(&journal);
    }
    Ok(p)
}

/// Pretty JSON of `x`.
pub(crate) fn to_json<T: Serialize>(x: &T) -> Result<String, Error> {
    serde_json::to_string_pretty(x).map_err(Error::encode)
}
