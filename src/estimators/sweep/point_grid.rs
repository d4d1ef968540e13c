//! The points of a sweep whose every point is one transport run of its own — in a magnetic field
//! ([`super::field`]) or under the thermostatted electric one ([`super::driven`]): one mechanism
//! for running, sealing, reusing and re-checking them, the kind's grid saying only how point i
//! runs and what row it leaves.
//!
//! Point i is run i of the sweep's seed (its own streams), so points are independent and each
//! error bar is its own batches'. With `options.resume` (a directory) each finished point is
//! sealed into `DIR/FOLDER/point-NNNN.json` as it finishes and reused (its configuration and
//! digest checked, one reused point drawn at random and computed again) when the sweep runs
//! again, so an interrupted sweep loses at most the point in progress.

use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::SweepConfig;
use super::points::{recheck_one_point, renamed_point, same_sweep};
use crate::Error;
use crate::engine::options::{RunOption, RunOptions};
use crate::engine::resume::{seal, unseal};
use crate::engine::work::Work;
use crate::estimators::diffusion::DiffusionConfig;

/// A grid whose points are transport runs, each leaving one row.
pub trait PointGrid {
    /// What a point leaves.
    type Row: Clone + Serialize + DeserializeOwned;
    /// The folder of the points in a sweep directory.
    const FOLDER: &'static str;
    /// A point, in messages ("field sweep point").
    const WHAT: &'static str;
    /// The sweep, in messages ("a field sweep").
    const SWEEP: &'static str;
    /// The configuration's parameters to lower when the work is too much.
    const LOWER: &'static [&'static str];

    /// The grid of `cfg`, if it is of this kind.
    ///
    /// # Errors
    /// A sweep of another kind.
    fn of(cfg: &SweepConfig) -> Result<&Self, Error>;
    /// The number of points.
    fn points(&self) -> usize;
    /// The transport run of point `i` of `sweep`.
    ///
    /// # Errors
    /// A parameter that is not an exact decimal or fraction.
    fn point(&self, sweep: &SweepConfig, i: usize) -> Result<DiffusionConfig, Error>;
    /// Point `i` in words, for a refusal ("w = 0.1, B = 2").
    fn label(&self, i: usize) -> String;
    /// The row of a point's run.
    ///
    /// # Errors
    /// What the run refuses, or an interruption.
    fn row(point: &DiffusionConfig, opts: &RunOptions) -> Result<Self::Row, Error>;
    /// The work of a point's run on the scalar engine or (`simd`) the SIMD one.
    ///
    /// # Errors
    /// A scene that does not resolve.
    fn work(point: &DiffusionConfig, simd: bool) -> Result<Work<'static>, Error>;
}

/// Every point's row (`None`: a point not run here) and how many were reused.
pub type Rows<R> = (Vec<Option<R>>, u32);

/// One finished point on disk (the unit of resumption).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct GridPoint<R> {
    /// The sweep it belongs to.
    pub config: SweepConfig,
    /// Its index in the grid.
    pub index: u32,
    /// Its row.
    pub row: R,
}

/// The file of point `i` of a grid of kind `G` in the sweep directory `dir`.
pub fn point_path<G: PointGrid>(dir: &Path, i: usize) -> PathBuf {
    dir.join(G::FOLDER).join(format!("point-{i:04}.json"))
}

/// The points `owns` selects, each reused from `options.resume` (a directory) or run and sealed
/// there: every point's row (`None` for a point not selected) and how many were reused.
///
/// # Errors
/// An invalid configuration or options (before any work or file), a directory holding another
/// sweep's points or an edited one, an I/O error, or an interruption.
pub(crate) fn run_points<G: PointGrid>(
    cfg: &SweepConfig,
    opts: &RunOptions,
    owns: &dyn Fn(usize) -> bool,
) -> Result<Rows<G::Row>, Error> {
    cfg.validate()?;
    opts.validate()?;
    let grid = G::of(cfg)?;
    let dir = opts.resume.as_deref();
    // The points' runs take no checkpoint of their own: the point is the unit of resumption.
    let point_opts = RunOptions {
        resume: None,
        ..opts.clone()
    };
    point_opts.refuse_unused(G::SWEEP, &[RunOption::Engine])?;
    if let Some(d) = dir {
        crate::files::create_dir_all(d)?;
        crate::files::create_subdir(d.join(G::FOLDER))?;
    }
    // Every point already on disk is checked before any work.
    let mut found = Vec::with_capacity(grid.points());
    for i in 0..grid.points() {
        found.push(match dir {
            Some(d) if owns(i) => reuse::<G>(cfg, &point_path::<G>(d, i), i)?,
            _ => None,
        });
    }
    check_work(cfg, grid, &found, owns, &point_opts)?;
    recheck::<G>(cfg, &point_opts, dir, &found)?;
    let mut rows = Vec::with_capacity(grid.points());
    let mut resumed = 0;
    for (i, old) in found.into_iter().enumerate() {
        rows.push(match old {
            _ if !owns(i) => None,
            Some(row) => {
                (opts.progress)(cfg.collisions);
                resumed += 1;
                Some(row)
            }
            None => Some(run_point(cfg, grid, (i, dir), &point_opts)?),
        });
    }
    Ok((rows, resumed))
}

/// Runs point `i` and seals it into `dir`, if any.
fn run_point<G: PointGrid>(
    cfg: &SweepConfig,
    grid: &G,
    (i, dir): (usize, Option<&Path>),
    opts: &RunOptions,
) -> Result<G::Row, Error> {
    let row = G::row(&grid.point(cfg, i)?, opts)?;
    if let Some(d) = dir {
        let p = GridPoint {
            config: cfg.clone(),
            index: i as u32,
            row: row.clone(),
        };
        crate::files::write(point_path::<G>(d, i), seal(&p)?.as_bytes())?;
    }
    Ok(row)
}

/// Refuses the points still to run when, together, even the floor costs make them longer than a
/// week of the sweep's threads: one check before the first point starts.
fn check_work<G: PointGrid>(
    cfg: &SweepConfig,
    grid: &G,
    found: &[Option<G::Row>],
    owns: &dyn Fn(usize) -> bool,
    opts: &RunOptions,
) -> Result<(), Error> {
    let simd = matches!(opts.engine.resolve(true)?, crate::engine::Resolved::Simd(_));
    let mut parts = Vec::new();
    for (i, old) in found.iter().enumerate() {
        if owns(i) && old.is_none() {
            parts.push(G::work(&grid.point(cfg, i)?, simd)?);
        }
    }
    Work::sum(G::SWEEP, G::LOWER, parts).check(opts.threads)
}

/// Computes one reused point again, drawn at random, and compares its row with the point file's
/// to the bit: the guard of every sweep ([`recheck_one_point`]).
fn recheck<G: PointGrid>(
    cfg: &SweepConfig,
    opts: &RunOptions,
    dir: Option<&Path>,
    found: &[Option<G::Row>],
) -> Result<(), Error> {
    let grid = G::of(cfg)?;
    let opts = RunOptions {
        progress: &|_| {},
        ..opts.clone()
    };
    recheck_one_point(found, (dir, point_path::<G>), |i, recorded| {
        if i >= grid.points() {
            return Ok(None);
        }
        let fresh = G::row(&grid.point(cfg, i)?, &opts)?;
        let bits = |r: &G::Row| serde_json::to_value(r).ok();
        let same = bits(&fresh).is_some() && bits(&fresh) == bits(recorded);
        Ok((!same).then(|| format!("point {i} ({}),", grid.label(i))))
    })
}

/// The finished row of point `i` at `path`, if there is one of this sweep; a file of another
/// sweep, an edited, renamed or oversized one is an error naming the path.
fn reuse<G: PointGrid>(cfg: &SweepConfig, path: &Path, i: usize) -> Result<Option<G::Row>, Error> {
    if !path.exists() {
        return Ok(None);
    }
    let text = crate::files::read_to_string(path, crate::files::Cap::FIELD_POINT)?;
    parse::<G>(cfg, path, &text, i).map(Some)
}

/// Point `i` of `cfg` from its sealed `text`, read from `path`: an edited, truncated, renamed or
/// foreign point is refused, naming the path.
///
/// # Errors
/// As above.
pub(crate) fn parse<G: PointGrid>(
    cfg: &SweepConfig,
    path: &Path,
    text: &str,
    i: usize,
) -> Result<G::Row, Error> {
    let p: GridPoint<G::Row> = unseal(path, text, G::WHAT)?;
    same_sweep(path, &p.config, cfg)?;
    if p.index as usize != i {
        return Err(renamed_point(path, p.index));
    }
    Ok(p.row)
}

/// Every point's sealed text from its row (`None`: a point not run here), in index order.
///
/// # Errors
/// A row that does not serialize.
pub(crate) fn sealed<R: Clone + Serialize>(
    cfg: &SweepConfig,
    rows: Vec<Option<R>>,
) -> Result<Vec<(u32, String)>, Error> {
    (rows.into_iter().enumerate())
        .filter_map(|(i, row)| {
            let p = GridPoint {
                config: cfg.clone(),
                index: i as u32,
                row: row?,
            };
            Some(seal(&p).map(|t| (i as u32, t)))
        })
        .collect()
}

/// The rows of sealed points (`(index, text)`), each checked as it is unsealed.
///
/// # Errors
/// A text that does not unseal.
pub(crate) fn rows_of<G: PointGrid>(points: &[(u32, &str)]) -> Result<Vec<G::Row>, Error> {
    (points.iter())
        .map(|(i, text)| {
            let at = PathBuf::from(format!("point {i}"));
            unseal::<GridPoint<G::Row>>(&at, text, G::WHAT).map(|p| p.row)
        })
        .collect()
}
