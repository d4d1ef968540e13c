//! The one way the crate touches files: `std::fs` with errors that name their operation and
//! path ([`Error::Io`]), and with the rules that keep a run from writing where it should not.
//!
//! * **Writes never follow a link and never touch the old file.** Every output, a whole file
//!   ([`write()`]) or a stream ([`Stream`]: trajectory events), goes to a temporary file created
//!   anew (`O_EXCL`, which no symbolic link survives) beside the target, synced and renamed over
//!   the target only once complete, so a reader sees the old file or the new one: a failed run,
//!   a full disk or a refusal leaves the old file as it was and no temporary file beside it.
//!   The rename replaces the name, so a second hard link to the old file keeps the old contents;
//!   a file appended to in place (a journal, [`open_append`]) must have no other hard link. A
//!   symbolic link, a directory, a device or a FIFO found at the target is refused
//!   ([`Error::UnsafePath`]), never followed or replaced; a regular file keeps its permissions.
//!   The temporary files and held locks are recorded ([`in_flight`]), so that a process ended
//!   at once by a signal removes them first.
//! * **Outputs are checked before any work, and never replace an input.** [`check_outputs`]
//!   takes every path a command will write ([`Output`]) and the files it reads, and refuses
//!   what may not be replaced and any output that is (by device and inode) one of the inputs.
//! * **Reads never block on a FIFO and are capped.** [`open`] opens with `O_NONBLOCK` and
//!   refuses anything but a regular file before reading (a FIFO or a terminal would block
//!   `read` forever); [`read`] and [`read_to_string`] take the [`Cap`] of the file's kind and
//!   refuse a larger file from its size before reading, and one that grows past it meanwhile.
//! * **Directories the tool names are its own.** [`create_subdir`] refuses a symbolic link where
//!   the tool makes a directory inside an output directory (the directory the user names is
//!   the user's choice, and [`create_dir_all`] follows it).
//! * **One run per journal.** [`lock`] takes an advisory lock beside a file that a run
//!   appends to, so that a second run on it is refused at once.
//!
//! The proof that nothing here follows a link is in `proofs-notes/file-safety.md`.

pub mod in_flight;
mod lock;
mod plan;
mod read;
#[cfg(all(test, unix))]
mod tests;
mod write;

pub use lock::{Lock, lock};
pub use plan::{Output, check_outputs, resolved};
pub use read::{Cap, open, read, read_capped, read_to_string};
pub use write::{Stream, open_append, write};

use std::fs::{File, OpenOptions};
use std::path::Path;

use crate::Error;

/// What to do about a path that is refused.
const CHOOSE_ANOTHER: &str = "lorentz writes and replaces only regular files (never through a \
     symbolic or hard link, never a device, FIFO or directory): remove it or choose another path";

/// Why a read is refused.
const READ_REGULAR: &str = "lorentz reads only regular files (a FIFO, a device or a directory \
     would block or mislead the read): give a regular file";

/// What the file system holds at `path` without following a link (`None`: nothing); an error
/// names the operation `op` that needed to know.
fn found_at(path: &Path, op: &'static str) -> Result<Option<std::fs::Metadata>, Error> {
    match std::fs::symlink_metadata(path) {
        Ok(m) => Ok(Some(m)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(Error::io(op, path)(e)),
    }
}

/// A description of a file that is not regular, for the refusals.
fn kind_of(m: &std::fs::Metadata) -> &'static str {
    let t = m.file_type();
    if t.is_symlink() {
        return "a symbolic link";
    }
    if t.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() || t.is_block_device() {
            return "a device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

/// The refusal of `path`, found to be `found`.
fn refused(path: &Path, found: impl Into<String>, why: &'static str) -> Error {
    Error::UnsafePath {
        path: path.to_path_buf(),
        found: found.into(),
        why,
    }
}

/// Checks that `path` may be written: absent, or a regular file (returned, for its
/// permissions). A link, directory, device or FIFO is refused.
///
/// # Errors
/// [`Error::UnsafePath`] naming what is there; an I/O error naming the path.
pub fn check_writable(path: &Path) -> Result<Option<std::fs::Metadata>, Error> {
    writable(path, "write")
}

/// [`check_writable`] for the operation `op`.
fn writable(path: &Path, op: &'static str) -> Result<Option<std::fs::Metadata>, Error> {
    match found_at(path, op)? {
        Some(m) if !m.file_type().is_file() => Err(refused(path, kind_of(&m), CHOOSE_ANOTHER)),
        found => Ok(found),
    }
}

/// Open flags that make `open` refuse a final symbolic link (`O_NOFOLLOW`) and never wait for a
/// FIFO's other end (`O_NONBLOCK`).
fn careful(o: &mut OpenOptions, follow: bool) -> &mut OpenOptions {
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        let nofollow = if follow { 0 } else { libc::O_NOFOLLOW };
        o.custom_flags(libc::O_NONBLOCK | nofollow);
    }
    #[cfg(not(unix))]
    let _ = follow;
    o
}

/// An opened file checked to be regular (the check is on the open file, so nothing can be
/// swapped in between).
fn regular(path: &Path, f: File, why: &'static str) -> Result<File, Error> {
    let m = f.metadata().map_err(Error::io("inspect", path))?;
    if m.is_file() {
        Ok(f)
    } else {
        Err(refused(path, kind_of(&m), why))
    }
}

/// The error of opening `path` with `O_NOFOLLOW`: a link is named as such.
fn open_error<'a>(op: &'static str, path: &'a Path) -> impl FnOnce(std::io::Error) -> Error + 'a {
    move |e| {
        if let Ok(Some(m)) = found_at(path, op)
            && m.file_type().is_symlink()
        {
            return refused(path, "a symbolic link", CHOOSE_ANOTHER);
        }
        Error::io(op, path)(e)
    }
}

/// Creates the directory `path` the user named, and its parents (a link the user gave is the
/// user's choice and is followed).
///
/// # Errors
/// An I/O error naming the path.
pub fn create_dir_all(path: impl AsRef<Path>) -> Result<(), Error> {
    let path = path.as_ref();
    std::fs::create_dir_all(path).map_err(Error::io("create directory", path))
}

/// Creates the directory `path` that the tool names inside a directory of its own (`points/`,
/// a reproduction's steps), or checks the one there: it must be a directory, not a link to
/// one, so that nothing is written outside the output directory.
///
/// # Errors
/// [`Error::UnsafePath`] for a link or a file at `path`; an I/O error naming the path.
pub fn create_subdir(path: impl AsRef<Path>) -> Result<(), Error> {
    let path = path.as_ref();
    if found_at(path, "create directory")?.is_none() {
        match std::fs::create_dir(path) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(Error::io("create directory", path)(e)),
        }
    }
    match found_at(path, "create directory")? {
        Some(m) if m.file_type().is_dir() => Ok(()),
        Some(m) => Err(refused(path, kind_of(&m), CHOOSE_ANOTHER)),
        None => Err(refused(path, "removed while it was made", CHOOSE_ANOTHER)),
    }
}
