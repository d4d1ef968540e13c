//! The parts of a sharded sweep — over w, or in a field on any table — combined into the whole
//! sweep: the same bits as the sweep run in one piece, apart from `meta` (this process) and
//! `resumed_points` (the points the parts reused from earlier runs). The parts come from directories ([`read_part`]) or
//! from memory (a process pool's, [`super::shard::SweepPart::sealed_points`]); one merge for both.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::shard::{Shard, SweepPart};
use crate::Error;
use crate::engine::options::RunOptions;
use crate::engine::resume::{difference, unseal};
use crate::estimators::sweep::SweepConfig;
use crate::estimators::sweep::points::recorded_differs;
use crate::estimators::sweep::stored::{self, Checker, FOLDERS, Finished, MANIFESTS, SealedPoint};

/// What to merge, and where.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MergeConfig {
    /// The directories of the parts (each from [`super::shard::run`], or any directory of
    /// finished points of the same sweep), in any order.
    pub parts: Vec<PathBuf>,
    /// Where the merged points go (`OUT/points/`, in a field `OUT/field-points/`, so that a sweep
    /// of the same configuration with this directory resumes all of them).
    pub out: PathBuf,
}

/// One part as the merge reads it: where it came from, its manifest if it has one, and its
/// points (each with the file or place it was read from).
#[derive(Debug, Clone)]
pub struct PartData {
    /// The part's directory, or a name for a part held in memory.
    pub origin: PathBuf,
    /// Its manifest, if any.
    pub manifest: Option<SweepPart>,
    /// Its points, with where each was read.
    pub points: Vec<(PathBuf, SealedPoint)>,
}

impl PartData {
    /// A part held in memory (with its points, [`SweepPart::sealed_points`]).
    pub fn in_memory(mut part: SweepPart) -> PartData {
        let origin = PathBuf::from(format!("part {}", part.shard));
        let points = std::mem::take(&mut part.sealed_points)
            .into_iter()
            .map(|p| (origin.join(format!("point {}", p.index)), p))
            .collect();
        PartData {
            origin,
            manifest: Some(part),
            points,
        }
    }
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

/// Reads the part in `dir`: its manifest (`shard.json` or `field-shard.json`), if any, and the
/// point files of its `points/` or `field-points/`, each sealed (checked against the sweep by
/// [`merge`]).
///
/// # Errors
/// A directory without points, an unreadable, edited or misnamed file (named).
pub fn read_part(dir: &Path) -> Result<PartData, Error> {
    let mut manifest = None;
    for name in MANIFESTS {
        let path = dir.join(name);
        if path.exists() {
            let text = crate::files::read_to_string(&path, crate::files::Cap::MANIFEST)?;
            manifest = Some(unseal::<SweepPart>(&path, &text, "part manifest")?);
        }
    }
    let folders: Vec<PathBuf> = (FOLDERS.iter())
        .map(|f| dir.join(f))
        .filter(|f| f.is_dir())
        .collect();
    if folders.is_empty() {
        return Err(Error::malformed(
            dir,
            "no sweep points here; give the directories the sweep's parts were written to",
        ));
    }
    let mut points = Vec::new();
    for folder in folders {
        let entries =
            std::fs::read_dir(&folder).map_err(Error::io("read", folder.display().to_string()))?;
        let mut names: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "json"))
            .collect();
        names.sort();
        for path in names {
            let text = crate::files::read_to_string(&path, crate::files::Cap::POINT)?;
            let named = (path.file_name().and_then(|n| n.to_str())).and_then(|n| {
                n.strip_prefix("point-")?
                    .strip_suffix(".json")?
                    .parse()
                    .ok()
            });
            let Some(index) = named else {
                return Err(Error::malformed(
                    &path,
                    "not a point file (point i lives in point-iiii.json)",
                ));
            };
            points.push((path, SealedPoint { index, text }));
        }
    }
    Ok(PartData {
        origin: dir.to_path_buf(),
        manifest,
        points,
    })
}

/// Combines the directories `cfg.parts` of a sharded sweep into `cfg.out` ([`merge`]).
///
/// # Errors
/// As [`read_part`] and [`merge`].
pub fn run(cfg: &MergeConfig, options: &RunOptions) -> Result<Finished, Error> {
    if cfg.parts.is_empty() {
        return Err(Error::Zero { what: "parts" });
    }
    refuse_input_as_output(&cfg.parts, &cfg.out)?;
    let parts = (cfg.parts.iter())
        .map(|d| read_part(d))
        .collect::<Result<Vec<_>, Error>>()?;
    merge(parts, Some(&cfg.out), options)
}

/// The points already finished in `out` (where a sweep or a merge wrote them) as one part,
/// for a sweep whose other points were computed elsewhere (`parts`, a process pool's): a point
/// also in `parts` — one the caller drew at random and computed again — must be its file's text
/// to the bit, or the file is moved aside and the sweep refused; the others are taken as they
/// are, and the merge checks each (sealed, of this sweep, on its grid). `None` where `out`
/// holds no points.
///
/// # Errors
/// A point computed again that differs from its file, or a part that cannot be read.
pub fn reused_in(out: &Path, parts: &[PartData]) -> Result<Option<PartData>, Error> {
    if !FOLDERS.iter().any(|f| out.join(f).is_dir()) {
        return Ok(None);
    }
    let mut part = read_part(out)?;
    part.manifest = None;
    let fresh: BTreeMap<u32, &SealedPoint> = (parts.iter())
        .flat_map(|p| p.points.iter().map(|(_, s)| (s.index, s)))
        .collect();
    let mut kept = Vec::with_capacity(part.points.len());
    for (path, p) in std::mem::take(&mut part.points) {
        match fresh.get(&p.index) {
            None => kept.push((path, p)),
            Some(f) if f.text == p.text => {}
            Some(_) => return Err(recorded_differs(&format!("point {}", p.index), Some(&path))),
        }
    }
    part.points = kept;
    Ok(Some(part))
}

/// Combines `parts` of one sweep (of either kind): every point checked (sealed, of this sweep,
/// on its grid), present once, none missing; with `out`, the points are written to its points'
/// folder; the whole is analysed as the sweep in one piece analyses it.
///
/// # Errors
/// No parts, parts or points of different sweeps or splits, a point or part present twice, or
/// missing points (named, with the part that owns them) — before anything is written.
pub fn merge(
    parts: Vec<PartData>,
    out: Option<&Path>,
    options: &RunOptions,
) -> Result<Finished, Error> {
    options.accept("merge", &[])?;
    let mut gathered = Gathered::default();
    for p in &parts {
        gathered.add(p)?;
    }
    let Some((sweep, _)) = gathered.config.clone() else {
        return Err(Error::Zero { what: "parts" });
    };
    sweep.validate()?;
    let points = gathered.complete(&sweep)?;
    if let Some(out) = out {
        // A point already there must be this sweep's (a merge or sweep run there before): the
        // merge never writes over another sweep's points.
        if let Some(c) = &gathered.checker {
            for p in &points {
                let path = stored::point_path(&sweep, out, p.index);
                if path.exists() {
                    let text = crate::files::read_to_string(&path, crate::files::Cap::POINT)?;
                    c.check(&path, p.index, &text)?;
                }
            }
        }
        crate::files::create_dir_all(out)?;
        crate::files::create_subdir(out.join(sweep.points_folder()))?;
        for p in &points {
            crate::files::write(stored::point_path(&sweep, out, p.index), &p.text)?;
        }
    }
    let mut finished = stored::analyse(&sweep, &points, gathered.resumed, options)?;
    if let Finished::OverW(r) = &mut finished {
        gathered.name_engines(&mut r.meta);
    }
    Ok(finished)
}

/// What the parts hold, gathered and checked as they are added.
#[derive(Default)]
struct Gathered {
    /// The sweep, and where it was first seen.
    config: Option<(SweepConfig, PathBuf)>,
    /// The checker of its points.
    checker: Option<Checker>,
    /// The parts with a manifest, by index.
    shards: BTreeMap<u32, (Shard, PathBuf)>,
    /// The points, by index, with where each was read.
    found: BTreeMap<u32, (SealedPoint, PathBuf)>,
    /// The engines that ran the parts (informational: every engine gives the same bits).
    engines: Vec<(String, Option<String>)>,
    /// Points the parts reused from earlier runs (a directory without a manifest: all of its).
    resumed: u32,
}

impl Gathered {
    /// Checks that `c` (read at `d`) is the sweep seen so far.
    fn same(&mut self, c: &SweepConfig, d: &Path) -> Result<(), Error> {
        match &self.config {
            None => {
                self.checker = Some(Checker::new(c)?);
                self.config = Some((c.clone(), d.to_path_buf()));
                Ok(())
            }
            Some((c0, d0)) if c0 != c => Err(Error::malformed(
                d,
                format!(
                    "{} and this hold different sweeps ({}): merge only parts of one sweep",
                    d0.display(),
                    difference(c0, c).unwrap_or_else(|| "their configurations differ".into())
                ),
            )),
            Some(_) => Ok(()),
        }
    }

    /// Adds one part: its manifest (checked against the other parts) and its points (each of the
    /// same sweep and present once).
    fn add(&mut self, part: &PartData) -> Result<(), Error> {
        let d = &part.origin;
        if let Some(m) = &part.manifest {
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
            self.shards.insert(m.shard.index, (m.shard, d.clone()));
            self.resumed += m.resumed_points;
            let e = (m.meta.engine.clone(), m.meta.simd.clone());
            if !self.engines.contains(&e) {
                self.engines.push(e);
            }
        }
        if part.manifest.is_none() {
            self.resumed += part.points.len() as u32;
        }
        for (path, p) in &part.points {
            self.same(&stored::sweep_of(path, &p.text)?, d)?;
            if let Some(c) = &self.checker {
                c.check(path, p.index, &p.text)?;
            }
            if let Some((_, d0)) = self.found.get(&p.index) {
                return Err(Error::malformed(
                    d,
                    format!("point {} is in both {} and here", p.index, d0.display()),
                ));
            }
            self.found.insert(p.index, (p.clone(), d.clone()));
        }
        Ok(())
    }

    /// Every point of `sweep`, in index order; missing points are named with the part that owns
    /// each.
    fn complete(&self, sweep: &SweepConfig) -> Result<Vec<SealedPoint>, Error> {
        let n = sweep.steps();
        let missing: Vec<u32> = (0..n).filter(|i| !self.found.contains_key(i)).collect();
        if let Some(&first) = missing.first() {
            let count = self.shards.values().next().map(|(s, _)| s.count);
            let owner = count.map_or(String::new(), |c| {
                format!(", belongs to part {}/{c}", first % c)
            });
            let list = (missing.iter().take(10))
                .map(|&i| match count {
                    Some(c) => format!("{i} (part {}/{c})", i % c),
                    None => i.to_string(),
                })
                .collect::<Vec<_>>()
                .join(", ");
            let more = if missing.len() > 10 { ", …" } else { "" };
            return Err(Error::Invalid(format!(
                "{} of {n} points missing (the first, point {first}{owner}): points {list}{more}; \
                 run (or finish) those parts, then merge every part",
                missing.len(),
            )));
        }
        Ok(self.found.values().map(|(p, _)| p.clone()).collect())
    }

    /// The engines of the parts into the report's metadata (one, or all of them joined).
    fn name_engines(&self, meta: &mut crate::engine::metadata::RunMeta) {
        if let [(engine, simd)] = &self.engines[..] {
            meta.engine = engine.clone();
            meta.simd = simd.clone();
        } else if !self.engines.is_empty() {
            meta.engine = self
                .engines
                .iter()
                .map(|(e, s)| s.as_ref().map_or(e.clone(), |s| format!("{e} ({s})")))
                .collect::<Vec<_>>()
                .join(" + ");
        }
    }
}
