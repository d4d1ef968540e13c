//! The parts of a sharded sweep combined into the whole sweep: the same bits as the sweep run in
//! one piece, apart from `meta` (this process) and `resumed_points` (every point merged).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::shard::{Shard, ShardReport};
use crate::engine::options::RunOptions;
use crate::estimators::sweep::analysis::{analyse, config_difference};
use crate::estimators::sweep::points::{point_path, write_atomically};
use crate::estimators::sweep::{SweepConfig, SweepPoint, SweepReport};
use crate::Error;

/// What to merge, and where.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MergeConfig {
    /// The directories of the parts (each from [`super::shard::run`], or any directory of
    /// finished points of the same sweep), in any order.
    pub parts: Vec<PathBuf>,
    /// Where the merged points go (`OUT/points/`, so that a sweep of the same configuration with
    /// this directory resumes all of them).
    pub out: PathBuf,
}

/// Combines the directories `cfg.parts` of a sharded sweep into `cfg.out`: the points are copied
/// to `OUT/points/` and analysed as [`crate::estimators::sweep::run`] analyses them.
///
/// # Errors
/// A directory without points, points or parts of different configurations, a point or part
/// present twice, parts of different counts, or missing points (named, with the part that owns
/// each) — before anything is written.
pub fn run(cfg: &MergeConfig, options: &RunOptions) -> Result<SweepReport, Error> {
    options.validate()?;
    let (dirs, out, threads): (&[PathBuf], &Path, usize) = (&cfg.parts, &cfg.out, options.threads);
    if dirs.is_empty() {
        return Err(Error::Invalid(
            "merge needs at least one directory of sweep points".into(),
        ));
    }
    let mut cfg: Option<(SweepConfig, PathBuf)> = None;
    let mut shards: std::collections::BTreeMap<u32, (Shard, PathBuf)> = Default::default();
    let mut found: std::collections::BTreeMap<u32, (SweepPoint, PathBuf)> = Default::default();
    // The engines that ran the parts (informational: every engine gives the same bits).
    let mut engines: Vec<(String, Option<String>)> = Vec::new();
    let same = |c: &SweepConfig, d: &Path, cfg: &mut Option<(SweepConfig, PathBuf)>| match cfg {
        None => {
            *cfg = Some((c.clone(), d.to_path_buf()));
            Ok(())
        }
        Some((c0, d0)) if c0 != c => Err(Error::Invalid(format!(
            "{} and {} hold different sweeps ({}): merge only parts of one sweep",
            d0.display(),
            d.display(),
            config_difference(c0, c)
        ))),
        Some(_) => Ok(()),
    };
    for d in dirs {
        let manifest = d.join("shard.json");
        if manifest.exists() {
            let text = std::fs::read_to_string(&manifest)?;
            let m: ShardReport = serde_json::from_str(&text).map_err(|e| {
                Error::Invalid(format!(
                    "{} is not a shard manifest: {e}",
                    manifest.display()
                ))
            })?;
            same(&m.config, d, &mut cfg)?;
            if let Some((s0, d0)) = shards.values().next() {
                if s0.count != m.shard.count {
                    return Err(Error::Invalid(format!(
                        "{} is part {} but {} is part {}: merge parts of one split",
                        d0.display(),
                        s0,
                        d.display(),
                        m.shard
                    )));
                }
            }
            if let Some((_, d0)) = shards.get(&m.shard.index) {
                return Err(Error::Invalid(format!(
                    "part {} is in both {} and {}",
                    m.shard,
                    d0.display(),
                    d.display()
                )));
            }
            shards.insert(m.shard.index, (m.shard, d.clone()));
            let e = (m.meta.engine, m.meta.simd);
            if !engines.contains(&e) {
                engines.push(e);
            }
        }
        let pdir = d.join("points");
        let entries = std::fs::read_dir(&pdir).map_err(|e| {
            Error::Invalid(format!(
                "{}: no sweep points here ({e}); give the directories that lorentz sweep --shard wrote",
                d.display()
            ))
        })?;
        let mut names: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .collect();
        names.sort();
        for path in names {
            let text = std::fs::read_to_string(&path)?;
            let p: SweepPoint = serde_json::from_str(&text).map_err(|e| {
                Error::Invalid(format!("{} is not a sweep point: {e}", path.display()))
            })?;
            same(&p.config, d, &mut cfg)?;
            if let Some((_, d0)) = found.get(&p.index) {
                return Err(Error::Invalid(format!(
                    "point {} (w = {}) is in both {} and {}",
                    p.index,
                    p.w,
                    d0.display(),
                    d.display()
                )));
            }
            found.insert(p.index, (p, d.clone()));
        }
    }
    let Some((cfg, _)) = cfg else {
        return Err(Error::Invalid(format!(
            "no sweep points in {}",
            dirs.iter()
                .map(|d| d.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    };
    cfg.validate()?;
    let grid = cfg.points()?;
    let missing: Vec<u32> = (0..cfg.steps).filter(|i| !found.contains_key(i)).collect();
    if !missing.is_empty() {
        let count = shards.values().next().map(|(s, _)| s.count);
        let list = missing
            .iter()
            .take(10)
            .map(|&i| match count {
                Some(n) => format!("{i} (w = {}, part {}/{n})", grid[i as usize], i % n),
                None => format!("{i} (w = {})", grid[i as usize]),
            })
            .collect::<Vec<_>>()
            .join(", ");
        let more = if missing.len() > 10 { ", …" } else { "" };
        return Err(Error::Invalid(format!(
            "{} of {} points missing: {list}{more}; run (or finish) those parts first",
            missing.len(),
            cfg.steps
        )));
    }
    let mut points = Vec::with_capacity(found.len());
    for (i, (p, _)) in found {
        if p.w != grid[i as usize] {
            return Err(Error::Invalid(format!(
                "point {i} has w = {} but the grid has {}: a damaged point file",
                p.w, grid[i as usize]
            )));
        }
        points.push(p);
    }
    std::fs::create_dir_all(out.join("points"))?;
    for p in &points {
        write_atomically(
            &point_path(out, p.index as usize),
            &serde_json::to_string(p).map_err(|e| Error::Io(e.to_string()))?,
        )?;
    }
    let n = points.len() as u32;
    let mut report = analyse(&cfg, &points, n, threads)?;
    if let [(engine, simd)] = &engines[..] {
        report.meta.engine = engine.clone();
        report.meta.simd = simd.clone();
    } else if !engines.is_empty() {
        report.meta.engine = engines
            .iter()
            .map(|(e, s)| s.as_ref().map_or(e.clone(), |s| format!("{e} ({s})")))
            .collect::<Vec<_>>()
            .join(" + ");
    }
    Ok(report)
}
