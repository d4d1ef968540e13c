//! A field sweep in parts (`lorentz sweep --fields … --shard I/N`, `lorentz merge`): point i
//! belongs to part i mod N ([`Shard`]); a part runs its points into its directory's
//! `field-points/` as the whole sweep would (a point depends only on the configuration and its
//! index, so a part's points are the whole sweep's bits), and the merge gathers every part's
//! points — each checked, all of one sweep, none missing or twice — into the output directory,
//! where the sweep then finds every point finished and analyses them: the same report as the
//! sweep run in one piece, apart from `meta` and `resumed_points`.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::SweepConfig;
use super::field::{self, FieldSweepReport, point_path, reuse};
use crate::Error;
use crate::campaigns::shard::Shard;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::resume::{difference, seal, unseal};

/// What one part of a field sweep leaves beside its points (`field-shard.json`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FieldSweepPart {
    /// The whole sweep.
    pub config: SweepConfig,
    /// Which part.
    pub shard: Shard,
    /// Indices of the part's points, all finished.
    pub points: Vec<u32>,
    /// Of them, reused from an earlier, interrupted run of the part.
    pub resumed_points: u32,
    /// This part's process.
    pub meta: RunMeta,
}

/// Runs part `shard` of the sweep `cfg` into `options.resume` (required).
///
/// # Errors
/// An invalid sweep or part (every part needs a point), no directory, a directory of another
/// sweep, an I/O error, or an interruption.
pub fn run_part(
    cfg: &SweepConfig,
    shard: Shard,
    options: &RunOptions,
) -> Result<FieldSweepPart, Error> {
    cfg.validate()?;
    shard.fits(cfg.field_grid()?.points())?;
    let dir = crate::campaigns::shard::part_directory(options)?;
    let (rows, resumed) = field::run_points(cfg, options, &|i| shard.owns(i as u32))?;
    let part = FieldSweepPart {
        config: cfg.clone(),
        shard,
        points: (0..rows.len() as u32).filter(|&i| shard.owns(i)).collect(),
        resumed_points: resumed,
        meta: RunMeta::new(
            Some(cfg.seed),
            None,
            crate::numbers::precision::Precision::F64,
            Some(options.threads),
        ),
    };
    crate::files::write(dir.join("field-shard.json"), seal(&part)?.as_bytes())?;
    Ok(part)
}

/// `true` if `dir` holds the points of a field sweep (its `field-points/`).
pub fn is_field_part(dir: &Path) -> bool {
    dir.join("field-points").is_dir()
}

/// Gathers the points of the part directories `parts` into `out` and analyses the whole sweep
/// there (nothing is run: every point must be in a part).
///
/// # Errors
/// A part without `field-shard.json`, parts of different sweeps, a point file of another sweep
/// or edited, a point missing (named with the part that owns it), an output directory that is
/// or lies in a part, or an I/O error — before anything is written.
pub fn merge(
    parts: &[PathBuf],
    out: &Path,
    options: &RunOptions,
) -> Result<FieldSweepReport, Error> {
    crate::campaigns::merge::refuse_input_as_output(parts, out)?;
    let cfg = sweep_of(parts)?;
    let n = cfg.field_grid()?.points();
    let mut found: Vec<Option<(PathBuf, String)>> = vec![None; n];
    for dir in parts {
        for (i, slot) in found.iter_mut().enumerate() {
            let path = point_path(dir, i);
            if reuse(&cfg, &path, i)?.is_some() {
                if let Some((first, _)) = slot {
                    return Err(Error::malformed(
                        &path,
                        format!(
                            "point {i} is in two parts ({} and this one): merge each part once",
                            first.display()
                        ),
                    ));
                }
                let text = crate::files::read_to_string(&path, crate::files::Cap::FIELD_POINT)?;
                *slot = Some((path, text));
            }
        }
    }
    let missing: Vec<usize> = (0..n).filter(|&i| found[i].is_none()).collect();
    if let Some(&i) = missing.first() {
        let count = sweep_part_count(parts)?;
        return Err(Error::Invalid(format!(
            "{} of {n} points missing (the first, point {i}, belongs to part {}/{count}): merge every part once it has finished",
            missing.len(),
            i % count as usize
        )));
    }
    crate::files::create_dir_all(out)?;
    crate::files::create_subdir(out.join("field-points"))?;
    for (i, (_, text)) in found.into_iter().flatten().enumerate() {
        crate::files::write(point_path(out, i), text.as_bytes())?;
    }
    let opts = RunOptions {
        resume: Some(out.to_path_buf()),
        ..options.clone()
    };
    field::run(&cfg, &opts)
}

/// The part record of `dir`.
fn part_of(dir: &Path) -> Result<FieldSweepPart, Error> {
    let path = dir.join("field-shard.json");
    let text = crate::files::read_to_string(&path, crate::files::Cap::FIELD_POINT)?;
    unseal(&path, &text, "field sweep part")
}

/// The one sweep of the parts `parts` (every part's configuration the same).
fn sweep_of(parts: &[PathBuf]) -> Result<SweepConfig, Error> {
    let Some(first) = parts.first() else {
        return Err(Error::Zero { what: "parts" });
    };
    let cfg = part_of(first)?.config;
    for dir in &parts[1..] {
        let other = part_of(dir)?.config;
        if other != cfg {
            return Err(Error::malformed(
                dir,
                format!(
                    "a part of another sweep than {} ({}): merge the parts of one sweep",
                    first.display(),
                    difference(&other, &cfg).unwrap_or_else(|| "another configuration".into())
                ),
            ));
        }
    }
    Ok(cfg)
}

/// The number of parts the sweep was dealt into (the first part's).
fn sweep_part_count(parts: &[PathBuf]) -> Result<u32, Error> {
    Ok(part_of(&parts[0])?.shard.count)
}
