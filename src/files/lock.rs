//! One run per journal: an advisory lock beside the file a run appends to.

use std::fs::{File, OpenOptions};
use std::path::{Path, PathBuf};

use super::{CHOOSE_ANOTHER, careful, check_writable, open_error, refused, regular};
use crate::Error;

/// An advisory lock held on `.name.lock` beside a file, released (and the lock file removed)
/// when dropped: see [`lock`].
#[derive(Debug)]
pub struct Lock {
    path: PathBuf,
    file: Option<File>,
}

impl Drop for Lock {
    fn drop(&mut self) {
        // Removed while still held, so a run waiting on this file finds it gone and starts
        // afresh (see `lock`); closing the file releases the lock.
        let _ = std::fs::remove_file(&self.path);
        super::in_flight::settled(&self.path);
        self.file.take();
    }
}

/// Locks `path` against a second run: an exclusive advisory lock on `.name.lock` beside it.
/// A lock file removed by its holder between our open and our lock is opened again, so two
/// runs never both hold the lock of one path.
///
/// # Errors
/// [`Error::UnsafePath`] when another run holds the lock (or the lock path is not a regular
/// file); an I/O error naming the path.
pub fn lock(path: &Path) -> Result<Lock, Error> {
    let name = path
        .file_name()
        .ok_or_else(|| refused(path, "not a file name", CHOOSE_ANOTHER))?;
    let mut lock_name = std::ffi::OsString::from(".");
    lock_name.push(name);
    lock_name.push(".lock");
    let lock_path = path.with_file_name(lock_name);
    // The file itself first: a link or a device there, or a path through a file, is named as
    // the path the caller gave.
    check_writable(path)?;
    for _ in 0..16 {
        check_writable(&lock_path)?;
        let f = careful(OpenOptions::new().write(true).create(true), false)
            .open(&lock_path)
            .map_err(open_error("create", &lock_path))?;
        let f = regular(&lock_path, f, CHOOSE_ANOTHER)?;
        match f.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                return Err(refused(
                    path,
                    format!(
                        "in use by another run (its lock is {})",
                        lock_path.display()
                    ),
                    "wait for that run to finish, or use another file",
                ));
            }
            Err(std::fs::TryLockError::Error(e)) => return Err(Error::io("lock", &lock_path)(e)),
        }
        if same_file(&f, &lock_path) {
            super::in_flight::record(&lock_path);
            return Ok(Lock {
                path: lock_path,
                file: Some(f),
            });
        }
    }
    Err(refused(
        path,
        "its lock file keeps being replaced",
        "make sure one run at a time uses it",
    ))
}

/// Whether the open file `f` is still the one at `path`.
fn same_file(f: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (f.metadata(), std::fs::symlink_metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (f, path);
        true
    }
}
