//! The finished points of a sweep of any kind — over w without a field (`points/`), in a
//! magnetic field (`field-points/`) or under the thermostat (`driven-points/`) — as sealed texts
//! by index: what a part of a campaign computes,
//! carries and leaves, and what a merge checks and analyses. One mechanism for every sweep
//! ([`crate::campaigns`]): only running a point, checking one and analysing the whole are the
//! kind's, here.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::driven::{self, DrivenGrid, DrivenSweepReport};
use super::field::{self, FieldGrid, FieldSweepReport};
use super::point_grid::{self, PointGrid};
use super::points;
use super::{Grid, SweepConfig, SweepPoint, SweepReport};
use crate::Error;
use crate::engine::options::RunOptions;
use crate::engine::resume::{seal, unseal};

/// A finished point: its index in the grid and its sealed text (the file's bytes).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SealedPoint {
    /// Index in the grid.
    pub index: u32,
    /// The point as its file holds it (digest included).
    pub text: String,
}

/// A finished sweep's report, by kind.
#[derive(Debug, Clone)]
pub enum Finished {
    /// D(w) without a field.
    OverW(Box<SweepReport>),
    /// The tensor in a field.
    InField(Box<FieldSweepReport>),
    /// The driven gas's steady state.
    Driven(Box<DrivenSweepReport>),
}

/// The folders of points a sweep directory can hold: over w, in a field, driven.
pub const FOLDERS: [&str; 3] = ["points", FieldGrid::FOLDER, DrivenGrid::FOLDER];

/// The names of a part's manifest: over w, in a field, driven.
pub const MANIFESTS: [&str; 3] = ["shard.json", "field-shard.json", "driven-shard.json"];

impl SweepConfig {
    /// Its kind, as the index of its [`FOLDERS`] and [`MANIFESTS`]: 0 over w, 1 in a magnetic
    /// field, 2 driven.
    pub fn kind(&self) -> usize {
        match self.grid {
            Grid::Gaps(_) => 0,
            Grid::InField(_) => 1,
            Grid::Driven(_) => 2,
        }
    }

    /// The folder of this sweep's points in its directory.
    pub fn points_folder(&self) -> &'static str {
        FOLDERS[self.kind()]
    }

    /// The file a part of this sweep leaves beside its points.
    pub fn part_manifest(&self) -> &'static str {
        MANIFESTS[self.kind()]
    }
}

/// The file of point `i` of `cfg` in the sweep directory `dir`.
pub fn point_path(cfg: &SweepConfig, dir: &Path, i: u32) -> PathBuf {
    match cfg.grid {
        Grid::Gaps(_) => points::point_path(dir, i as usize),
        Grid::InField(_) => point_grid::point_path::<FieldGrid>(dir, i as usize),
        Grid::Driven(_) => point_grid::point_path::<DrivenGrid>(dir, i as usize),
    }
}

/// Runs (or reuses, from `options.resume`) the points `owns` selects, each written there as it
/// finishes: their sealed texts in index order and how many were reused.
///
/// # Errors
/// As the kind's sweep.
pub fn run_points(
    cfg: &SweepConfig,
    options: &RunOptions,
    owns: &dyn Fn(u32) -> bool,
) -> Result<(Vec<SealedPoint>, u32), Error> {
    let sealed = |index: u32, text: Result<String, Error>| Ok(SealedPoint { index, text: text? });
    match cfg.grid {
        Grid::Gaps(_) => {
            let (found, resumed) = points::run_points(cfg, options, owns)?;
            let texts = found.iter().map(|p| sealed(p.index, seal(p)));
            Ok((texts.collect::<Result<_, Error>>()?, resumed))
        }
        Grid::InField(_) => run_grid_points::<FieldGrid>(cfg, options, owns),
        Grid::Driven(_) => run_grid_points::<DrivenGrid>(cfg, options, owns),
    }
}

/// [`run_points`] of a sweep of transport runs ([`point_grid`]).
fn run_grid_points<G: PointGrid>(
    cfg: &SweepConfig,
    options: &RunOptions,
    owns: &dyn Fn(u32) -> bool,
) -> Result<(Vec<SealedPoint>, u32), Error> {
    let (rows, resumed) = point_grid::run_points::<G>(cfg, options, &|i| owns(i as u32))?;
    let texts = point_grid::sealed(cfg, rows)?;
    let points = (texts.into_iter()).map(|(index, text)| SealedPoint { index, text });
    Ok((points.collect(), resumed))
}

/// The sweep a sealed point (read from `path`) belongs to, its digest checked, whatever its
/// kind.
///
/// # Errors
/// An edited, truncated or foreign text, naming `path`.
pub fn sweep_of(path: &Path, text: &str) -> Result<SweepConfig, Error> {
    #[derive(Deserialize)]
    struct Head {
        config: SweepConfig,
    }
    let h: Head = unseal(path, text, "sweep point")?;
    Ok(h.config)
}

/// Checks points of one sweep (its grid computed once).
pub struct Checker {
    cfg: SweepConfig,
    gaps: Vec<f64>,
}

impl Checker {
    /// The checker of `cfg`'s points.
    ///
    /// # Errors
    /// A grid that is not exact.
    pub fn new(cfg: &SweepConfig) -> Result<Checker, Error> {
        let gaps = match cfg.grid {
            Grid::Gaps(_) => cfg.points()?,
            Grid::InField(_) | Grid::Driven(_) => Vec::new(),
        };
        Ok(Checker {
            cfg: cfg.clone(),
            gaps,
        })
    }

    /// Checks that `text` (read from `path`) is point `i` of the sweep: sealed, of this sweep,
    /// and on its grid.
    ///
    /// # Errors
    /// As above, naming `path` and what differs.
    pub fn check(&self, path: &Path, i: u32, text: &str) -> Result<(), Error> {
        let cfg = &self.cfg;
        if i >= cfg.steps() {
            return Err(Error::malformed(
                path,
                format!("point {i} is not on the grid of {} points", cfg.steps()),
            ));
        }
        match cfg.grid {
            Grid::Gaps(_) => {
                points::parse(cfg, path, text, i as usize, self.gaps[i as usize]).map(drop)
            }
            Grid::InField(_) => {
                point_grid::parse::<FieldGrid>(cfg, path, text, i as usize).map(drop)
            }
            Grid::Driven(_) => {
                point_grid::parse::<DrivenGrid>(cfg, path, text, i as usize).map(drop)
            }
        }
    }
}

/// The whole sweep's analysis from every point (`points[i]` is point i, checked by
/// [`Checker::check`]), `resumed` of them reused from earlier runs.
///
/// # Errors
/// A text that does not parse, or what the kind's analysis refuses.
pub fn analyse(
    cfg: &SweepConfig,
    points: &[SealedPoint],
    resumed: u32,
    options: &RunOptions,
) -> Result<Finished, Error> {
    let at = |p: &SealedPoint| PathBuf::from(format!("point {}", p.index));
    match cfg.grid {
        Grid::Gaps(_) => {
            let parsed = (points.iter())
                .map(|p| unseal::<SweepPoint>(&at(p), &p.text, "sweep point"))
                .collect::<Result<Vec<_>, Error>>()?;
            let r = super::analysis::analyse(cfg, &parsed, resumed, options.threads)?;
            Ok(Finished::OverW(Box::new(r)))
        }
        Grid::InField(_) => {
            let rows = point_grid::rows_of::<FieldGrid>(&texts(points))?;
            let r = field::report(cfg, rows, resumed, options)?;
            Ok(Finished::InField(Box::new(r)))
        }
        Grid::Driven(_) => {
            let rows = point_grid::rows_of::<DrivenGrid>(&texts(points))?;
            let r = driven::report(cfg, rows, resumed, options)?;
            Ok(Finished::Driven(Box::new(r)))
        }
    }
}

/// The points' indices and texts.
fn texts(points: &[SealedPoint]) -> Vec<(u32, &str)> {
    points.iter().map(|p| (p.index, p.text.as_str())).collect()
}
