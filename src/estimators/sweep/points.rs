//! A sweep's finished points on disk: one JSON file per point in `DIR/points/`, written
//! atomically as each point finishes (the unit of resumption, and what a campaign's parts leave
//! for the merge).

use std::path::{Path, PathBuf};

use super::{RunValue, SweepConfig, SweepPoint};
use crate::Error;
use crate::engine::checkpoint::{quarantine, quarantined};
use crate::engine::options::RunOptions;
use crate::engine::resume::{difference, seal, unseal};
use crate::estimators::diffusion::{DiffusionConfig, DiffusionReport, run_many};

/// The file of point `i` in the sweep directory `dir`.
pub fn point_path(dir: &Path, i: usize) -> PathBuf {
    dir.join("points").join(format!("point-{i:04}.json"))
}

/// The journal of point `i`'s batches in `dir` while it runs (`point-iiii.partial`).
fn journal_path(dir: &Path, i: usize) -> PathBuf {
    point_path(dir, i).with_extension("partial")
}

/// Where point `i`'s finished batches stay beside its file (`point-iiii.batches`: its journal,
/// renamed when the point is written), so that a reused point is checked from them at the cost
/// of one batch's marks, not of a run.
pub fn batches_path(dir: &Path, i: usize) -> PathBuf {
    point_path(dir, i).with_extension("batches")
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
        crate::files::create_dir_all(d)?;
        crate::files::create_subdir(d.join("points"))?;
    }
    // Every point already on disk is checked before any work: an edited or foreign file stops
    // the sweep before it computes (or writes) anything.
    let grid: Vec<(usize, f64)> = cfg
        .points()?
        .into_iter()
        .enumerate()
        .filter(|(i, _)| owns(*i as u32))
        .collect();
    let mut found = Vec::with_capacity(grid.len());
    for &(i, w) in &grid {
        found.push(match dir {
            Some(d) => reuse(cfg, &point_path(d, i), i, w)?,
            None => None,
        });
    }
    recheck_one_run(cfg, options, dir, &found)?;
    let mut points = Vec::with_capacity(grid.len());
    let mut resumed = 0;
    for (&(i, w), old) in grid.iter().zip(found) {
        match old {
            Some(p) => {
                (options.progress)(cfg.collisions.saturating_mul(cfg.runs() as u64));
                points.push(p);
                resumed += 1;
            }
            None => points.push(run_point(cfg, options, dir, i, w)?),
        }
    }
    Ok((points, resumed))
}

/// Checks one reused point, drawn at random (operating-system entropy), against its runs'
/// D and error to the bit ([`recheck_one_point`]): rebuilt from its kept batches
/// ([`batches_path`]), one of them computed again at its marks — seconds, whatever the
/// point's length — or, where the batches are not kept (a point written before they were),
/// one of its runs computed again whole.
fn recheck_one_run(
    cfg: &SweepConfig,
    options: &RunOptions,
    dir: Option<&Path>,
    found: &[Option<SweepPoint>],
) -> Result<(), Error> {
    let opts = RunOptions {
        resume: None,
        audit: None,
        progress: &|_| {},
        ..options.clone()
    };
    let same = |f: &DiffusionReport, x: &RunValue| {
        f.D.to_bits() == x.D.to_bits() && f.D_err.to_bits() == x.D_err.to_bits()
    };
    recheck_one_point(found, (dir, point_path), |_, p| {
        let i = p.index as usize;
        if let Some(kept) = dir.map(|d| batches_path(d, i)).filter(|b| is_file(b)) {
            let cfgs = point_runs(cfg, i, p.w);
            let opts = RunOptions {
                resume: Some(kept),
                ..opts.clone()
            };
            let rebuilt = run_many(&cfgs, &opts)?;
            let agree = rebuilt.len() == p.runs.len()
                && rebuilt.iter().zip(&p.runs).all(|(f, x)| same(f, x));
            return Ok((!agree).then(|| {
                format!(
                    "point {i} (w = {}), rebuilt from its batches with one of them",
                    p.w
                )
            }));
        }
        let r = rand::random_range(0..cfg.runs());
        let fresh = run_many(&[cfg.run_config(p.index, p.w, r)], &opts)?;
        let agree =
            matches!((fresh.first(), p.runs.get(r as usize)), (Some(f), Some(x)) if same(f, x));
        Ok((!agree).then(|| format!("point {i} (w = {}), run {r},", p.w)))
    })
}

/// Whether `path` is a regular file (not a link, not missing).
fn is_file(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_file())
}

/// The runs of point `i` at the gap `w`.
fn point_runs(cfg: &SweepConfig, i: usize, w: f64) -> Vec<DiffusionConfig> {
    (0..cfg.runs())
        .map(|r| cfg.run_config(i as u32, w, r))
        .collect()
}

/// Keeps a finished point's journal as its batches: linked to `kept` (which never replaces a
/// file there), then removed from its running name. Where it cannot be kept it is removed, and
/// the point is checked by a run when reused.
fn keep_batches(journal: &Path, kept: &Path) {
    let _ = std::fs::hard_link(journal, kept);
    let _ = std::fs::remove_file(journal);
}

/// Where a sweep keeps point i in its directory ([`point_path`], or a field sweep's).
pub(crate) type PointPath = fn(&Path, usize) -> PathBuf;

/// Draws one of the points reused from their files (`found[i]` for point i, `None` for a point
/// not on disk) at random
/// (operating-system entropy, so that no one editing the files can know which), computes it
/// again with `again` — which names what differs, `None` if it gives the recorded bits — and
/// refuses the sweep on a difference, moving the point's file (`path` in `dir`) aside first
/// ([`quarantine`]: retrying cannot draw again until an honest point comes up). Digests stop
/// accidents, not an author who recomputes them (`proofs-notes/checkpoints.md`, claim 3). Every
/// sweep (without a field and in one) re-checks its reused points here.
///
/// # Errors
/// [`Error::Failed`] naming the point and its file, or an error of the re-run.
pub(crate) fn recheck_one_point<P>(
    found: &[Option<P>],
    (dir, path): (Option<&Path>, PointPath),
    again: impl FnOnce(usize, &P) -> Result<Option<String>, Error>,
) -> Result<(), Error> {
    let reused: Vec<(usize, &P)> = (found.iter().enumerate())
        .filter_map(|(k, p)| Some((k, p.as_ref()?)))
        .collect();
    if reused.is_empty() {
        return Ok(());
    }
    let (k, p) = reused[rand::random_range(0..reused.len())];
    let Some(what) = again(k, p)? else {
        return Ok(());
    };
    Err(recorded_differs(&what, dir.map(|d| path(d, k)).as_deref()))
}

/// The refusal of a point file (at `file`) that `what` — the point, or the part of it — computed
/// again does not reproduce; the file is moved aside first ([`quarantine`]).
pub(crate) fn recorded_differs(what: &str, file: Option<&Path>) -> Error {
    Error::Failed(format!(
        "{what} computed again from its seed to check its point file, does not give the \
         recorded values: the file was edited (its digest recomputed); {}",
        quarantined(file.map(quarantine))
    ))
}

/// Refuses the point file at `path` whose sweep `found` is not this one (`want`), naming the
/// first difference.
pub(crate) fn same_sweep<C: serde::Serialize + PartialEq>(
    path: &Path,
    found: &C,
    want: &C,
) -> Result<(), Error> {
    if found == want {
        return Ok(());
    }
    Err(Error::malformed(
        path,
        format!(
            "belongs to another sweep ({}): use another directory",
            difference(found, want).unwrap_or_else(|| "another configuration".into())
        ),
    ))
}

/// Refuses the point file at `path`, which holds point `held` under another point's name.
pub(crate) fn renamed_point(path: &Path, held: impl std::fmt::Display) -> Error {
    Error::malformed(
        path,
        format!(
            "holds point {held}: a renamed or copied point file (point i lives in point-iiii.json)"
        ),
    )
}

/// Point `i` (at the gap `w`) of `cfg` from its sealed `text`, read from `path`: an edited,
/// truncated, renamed, foreign or off-grid point is refused, naming the path.
///
/// # Errors
/// As above.
pub(crate) fn parse(
    cfg: &SweepConfig,
    path: &Path,
    text: &str,
    i: usize,
    w: f64,
) -> Result<SweepPoint, Error> {
    let p: SweepPoint = unseal(path, text, "sweep point")?;
    same_sweep(path, &p.config, cfg)?;
    if p.index as usize != i {
        return Err(renamed_point(path, p.index));
    }
    if p.w != w {
        return Err(Error::malformed(
            path,
            format!(
                "is point {i} at w = {}, not at w = {w} as the grid has it: a damaged point file",
                p.w
            ),
        ));
    }
    Ok(p)
}

/// The finished point `i` at `path`, if there is one of this sweep; a file of another sweep or an
/// edited one is an error.
fn reuse(cfg: &SweepConfig, path: &Path, i: usize, w: f64) -> Result<Option<SweepPoint>, Error> {
    if !path.exists() {
        return Ok(None);
    }
    let text = crate::files::read_to_string(path, crate::files::Cap::POINT)?;
    parse(cfg, path, &text, i, w).map(Some)
}

/// Runs point `i` (its runs packed together), written to `dir` if given.
fn run_point(
    cfg: &SweepConfig,
    options: &RunOptions,
    dir: Option<&Path>,
    i: usize,
    w: f64,
) -> Result<SweepPoint, Error> {
    let cfgs = point_runs(cfg, i, w);
    // Finished batches of this point and its trajectories in flight are journalled, so that an
    // interruption loses at most one checkpoint interval.
    let path = dir.map(|d| point_path(d, i));
    let journal = dir.map(|d| journal_path(d, i));
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
        crate::files::write(&path, seal(&p)?.as_bytes())?;
        keep_batches(&journal, &path.with_extension("batches"));
    }
    Ok(p)
}
