//! The parts of a sharded sweep combined into the whole sweep: the same bits as the sweep run in
//! one piece, apart from `meta` (this process) and `resumed_points` (every point merged).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::shard::{Shard, ShardReport};
use crate::Error;
use crate::engine::options::RunOptions;
use crate::engine::resume::{difference, seal, unseal};
use crate::estimators::sweep::analysis::analyse;
use crate::estimators::sweep::points::{point_path, read_point};
use crate::estimators::sweep::{SweepConfig, SweepPoint, SweepReport};

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

/// Refuses an output directory that is one of the parts or lies in one: merging into it would
/// mix the merged points with a part's and break the next merge. (Parts inside the output
/// directory, `OUT/shard-i`, are the Slurm campaign's layout.)
pub fn refuse_input_as_output(dirs: &[PathBuf], out: &Path) -> Result<(), Error> {
    let resolved = crate::files::resolved;
    let o = resolved(out);
    for d in dirs {
        let d = resolved(d);
        if o.starts_with(&d) {
            return Err(Error::parameter(
                "out",
                out.display(),
                format!(
                    "the merge's output directory {} the part {}: merging into a part would mix \
                     its points with the merged ones; choose a directory apart from every part",
                    if o == d { "is" } else { "lies in" },
                    d.display()
                ),
            ));
        }
    }
    Ok(())
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
    options.refuse_unused("merge", &[])?;
    let (dirs, out) = (&cfg.parts, cfg.out.as_path());
    if dirs.is_empty() {
        return Err(Error::Zero { what: "parts" });
    }
    refuse_input_as_output(dirs, out)?;
    let mut parts = Parts::default();
    for d in dirs {
        parts.read_manifest(d)?;
        parts.read_points(d)?;
    }
    let Some((sweep, _)) = parts.config.clone() else {
        let others = match dirs.len() - 1 {
            0 => String::new(),
            1 => " nor in the other directory given".into(),
            n => format!(" nor in the {n} other directories given"),
        };
        return Err(Error::malformed(
            &dirs[0],
            format!("no sweep points here{others}"),
        ));
    };
    sweep.validate()?;
    let points = parts.complete(&sweep)?;
    crate::files::create_dir_all(out)?;
    crate::files::create_subdir(out.join("points"))?;
    for p in &points {
        crate::files::write(point_path(out, p.index as usize), seal(p)?.as_bytes())?;
    }
    let n = points.len() as u32;
    let mut report = analyse(&sweep, &points, n, options.threads)?;
    parts.name_engines(&mut report);
    Ok(report)
}

/// What the part directories hold, gathered and checked as they are read.
#[derive(Default)]
struct Parts {
    /// The sweep, and the directory it was first seen in.
    config: Option<(SweepConfig, PathBuf)>,
    /// The parts with a manifest, by index.
    shards: BTreeMap<u32, (Shard, PathBuf)>,
    /// The points, by index, with their directory.
    found: BTreeMap<u32, (SweepPoint, PathBuf)>,
    /// The engines that ran the parts (informational: every engine gives the same bits).
    engines: Vec<(String, Option<String>)>,
}

impl Parts {
    /// Checks that `c` (read in `d`) is the sweep seen so far.
    fn same(&mut self, c: &SweepConfig, d: &Path) -> Result<(), Error> {
        match &self.config {
            None => {
                self.config = Some((c.clone(), d.to_path_buf()));
                Ok(())
            }
            Some((c0, d0)) if c0 != c => Err(Error::malformed(
                d,
                format!(
                    "{} and this directory hold different sweeps ({}): merge only parts of one \
                     sweep",
                    d0.display(),
                    difference(c0, c).unwrap_or_else(|| "their configurations differ".into())
                ),
            )),
            Some(_) => Ok(()),
        }
    }

    /// Reads `d/shard.json`, if there is one: the part's identity, checked against the others.
    fn read_manifest(&mut self, d: &Path) -> Result<(), Error> {
        let manifest = d.join("shard.json");
        if !manifest.exists() {
            return Ok(());
        }
        let text = crate::files::read_to_string(&manifest, crate::files::Cap::MANIFEST)?;
        let m: ShardReport = unseal(&manifest, &text, "shard manifest")?;
        self.same(&m.config, d)?;
        if let Some((s0, d0)) = self.shards.values().next()
            && s0.count != m.shard.count
        {
            return Err(Error::malformed(
                d,
                format!(
                    "is part {} but {} is part {s0}: merge parts of one split",
                    m.shard,
                    d0.display()
                ),
            ));
        }
        if let Some((_, d0)) = self.shards.get(&m.shard.index) {
            return Err(Error::malformed(
                d,
                format!("part {} is in both {} and here", m.shard, d0.display()),
            ));
        }
        self.shards
            .insert(m.shard.index, (m.shard, d.to_path_buf()));
        let e = (m.meta.engine, m.meta.simd);
        if !self.engines.contains(&e) {
            self.engines.push(e);
        }
        Ok(())
    }

    /// Reads the points in `d/points/`, each of the same sweep and present once.
    fn read_points(&mut self, d: &Path) -> Result<(), Error> {
        let pdir = d.join("points");
        let entries = std::fs::read_dir(&pdir).map_err(|e| {
            Error::malformed(
                d,
                format!(
                    "no sweep points here ({e}); give the directories the sweep's parts were \
                     written to"
                ),
            )
        })?;
        let mut names: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .collect();
        names.sort();
        for path in names {
            let p = read_point(&path)?;
            self.same(&p.config, d)?;
            if let Some((_, d0)) = self.found.get(&p.index) {
                return Err(Error::malformed(
                    d,
                    format!(
                        "point {} (w = {}) is in both {} and here",
                        p.index,
                        p.w,
                        d0.display()
                    ),
                ));
            }
            self.found.insert(p.index, (p, d.to_path_buf()));
        }
        Ok(())
    }

    /// Every point of `sweep`, in index order, each on its grid point; missing points are named
    /// with the part that owns each.
    fn complete(&self, sweep: &SweepConfig) -> Result<Vec<SweepPoint>, Error> {
        let grid = sweep.points()?;
        let missing: Vec<u32> = (0..sweep.steps())
            .filter(|i| !self.found.contains_key(i))
            .collect();
        if !missing.is_empty() {
            let count = self.shards.values().next().map(|(s, _)| s.count);
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
                sweep.steps()
            )));
        }
        let mut points = Vec::with_capacity(self.found.len());
        for (&i, (p, d)) in &self.found {
            if p.w != grid[i as usize] {
                return Err(Error::malformed(
                    d,
                    format!(
                        "point {i} has w = {} but the grid has {}: a damaged point file",
                        p.w, grid[i as usize]
                    ),
                ));
            }
            points.push(p.clone());
        }
        Ok(points)
    }

    /// The engines of the parts into the report's metadata (one, or all of them joined).
    fn name_engines(&self, report: &mut SweepReport) {
        if let [(engine, simd)] = &self.engines[..] {
            report.meta.engine = engine.clone();
            report.meta.simd = simd.clone();
        } else if !self.engines.is_empty() {
            report.meta.engine = self
                .engines
                .iter()
                .map(|(e, s)| s.as_ref().map_or(e.clone(), |s| format!("{e} ({s})")))
                .collect::<Vec<_>>()
                .join(" + ");
        }
    }
}
