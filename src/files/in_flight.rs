//! The temporary files of this process in flight (created by [`super::write`], not yet renamed
//! into place or removed, and the lock files of [`super::lock`] still held), so that a command line ending the process at once on a signal can
//! remove them first ([`abandon`]): the targets keep their old content and nothing is left
//! beside them. Nothing here installs a signal handler; only the `lorentz` binary ends the
//! process.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

static IN_FLIGHT: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn held() -> MutexGuard<'static, Vec<PathBuf>> {
    IN_FLIGHT.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Creates the temporary file `path` by `create`, recorded as in flight if it was created. The
/// record and the creation are one step for [`abandon`], which therefore never misses a file
/// this process made.
pub(super) fn create<T, E>(path: &Path, create: impl FnOnce() -> Result<T, E>) -> Result<T, E> {
    let mut files = held();
    let made = create();
    if made.is_ok() {
        files.push(path.to_path_buf());
    }
    made
}

/// Records the file `path` this process made and will remove (a lock file it holds).
pub(super) fn record(path: &Path) {
    held().push(path.to_path_buf());
}

/// Records that the temporary file `path` was renamed into place or removed.
pub(super) fn settled(path: &Path) {
    let mut files = held();
    if let Some(i) = files.iter().position(|p| p == path) {
        files.swap_remove(i);
    }
}

/// Removes every temporary file of this process in flight and keeps any other from being made:
/// for a process about to end at once (the `lorentz` binary on a signal its command does not
/// wait for). Every later attempt to write a file through [`super::write`] blocks, so call this
/// only just before the process exits.
pub fn abandon() {
    let files = held();
    for p in files.iter() {
        let _ = std::fs::remove_file(p);
    }
    // Held until the process ends: no temporary file is created after this.
    std::mem::forget(files);
}
