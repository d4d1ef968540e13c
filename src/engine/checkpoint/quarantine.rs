//! What becomes of a checkpoint or point file that a re-check refused: it is moved aside, so the
//! same command starts afresh instead of drawing again.

use std::path::{Path, PathBuf};

use crate::Error;

/// The refusal of the checkpoint at `path` whose finished `batch`, computed again from its seed,
/// did not give the recorded `values` ([`super::recheck_one_batch`]). The file is moved aside
/// first ([`quarantine`]): a refused checkpoint cannot be resumed again as it is, so retrying does
/// not draw again until an honest batch comes up — the next run starts afresh.
pub fn recomputed_differs(path: Option<&Path>, batch: &str, values: &str) -> Error {
    let shown = path.map_or_else(|| "the checkpoint".into(), |p| p.display().to_string());
    let moved = path.map(quarantine);
    Error::Failed(format!(
        "{shown}: {batch}, computed again from its seed to check the checkpoint, does not give the \
         recorded {values}: the checkpoint was edited (its digests recomputed) or belongs to \
         another configuration; {}",
        quarantined(moved)
    ))
}

/// What became of a refused file, for the refusal: moved aside, or why not.
pub(crate) fn quarantined(moved: Option<Result<PathBuf, Error>>) -> String {
    match moved {
        Some(Ok(to)) => format!(
            "it is moved to {} and cannot be resumed; the same command starts afresh",
            to.display()
        ),
        Some(Err(e)) => format!("it could not be moved aside ({e}): do not resume it"),
        None => "use another file".into(),
    }
}

/// Moves the file at `path` aside to `PATH.refused` (or `PATH.refused.N`), never over an
/// existing file: what a re-check refused cannot be resumed again as it is. The name is linked
/// first and the old one removed, so the file is never lost and nothing is replaced; where hard
/// links are not supported it is renamed to a name that does not exist.
///
/// # Errors
/// An I/O error naming the path, or 1000 names taken.
pub fn quarantine(path: &Path) -> Result<PathBuf, Error> {
    use std::io::ErrorKind;
    let name = path.file_name().unwrap_or_default().to_string_lossy();
    for n in 0..1000 {
        let to = path.with_file_name(match n {
            0 => format!("{name}.refused"),
            _ => format!("{name}.refused.{n}"),
        });
        match std::fs::hard_link(path, &to) {
            Ok(()) => {
                std::fs::remove_file(path).map_err(Error::io("remove", path))?;
                return Ok(to);
            }
            Err(e) if e.kind() == ErrorKind::AlreadyExists => continue,
            Err(_) if std::fs::symlink_metadata(&to).is_err() => {
                std::fs::rename(path, &to).map_err(Error::io("rename", path))?;
                return Ok(to);
            }
            Err(e) => return Err(Error::io("link", path)(e)),
        }
    }
    Err(Error::Failed(format!(
        "{}: 1000 refused copies of it are already beside it",
        path.display()
    )))
}
