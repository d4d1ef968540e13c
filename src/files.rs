//! The one way the crate touches files: `std::fs` with errors that name their operation and
//! path ([`Error::Io`]), and with the rules that keep a run from writing where it should not.
//!
//! * **Writes never follow a link.** [`write()`] writes a temporary file created anew (`O_EXCL`,
//!   which no symbolic link survives) beside the target, syncs it and renames it over the
//!   target, so a reader sees the old file or the new one. A symbolic link, a directory, a
//!   device or a FIFO found at the target is refused ([`Error::UnsafePath`]), never followed
//!   or replaced; a regular file keeps its permissions. [`create`] opens a file for streaming
//!   output with `O_NOFOLLOW`.
//!   The temporary files in flight are recorded ([`in_flight`]), so that a process ended at once
//!   by a signal removes them first.
//! * **Reads never block on a FIFO.** [`open`] opens with `O_NONBLOCK` and refuses anything but
//!   a regular file before reading (a FIFO or a terminal would block `read` forever).
//! * **Directories the tool names are its own.** [`create_subdir`] refuses a symbolic link where
//!   the tool makes a directory inside an output directory (the directory the user names is
//!   the user's choice, and [`create_dir_all`] follows it).
//! * **One run per journal.** [`lock`] takes an advisory lock beside a file that a run
//!   appends to, so that a second run on it is refused at once.
//!
//! The proof that nothing here follows a link is in `proofs-notes/file-safety.md`.

use std::fs::{File, OpenOptions};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use crate::Error;

pub mod in_flight;

/// What to do about a path that is refused.
const CHOOSE_ANOTHER: &str = "lorentz writes and replaces only regular files (never through a \
     symbolic link, never a device, FIFO or directory): remove it or choose another path";

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

/// Opens the regular file `path` for reading (following links: the user's own files may be
/// links), refusing a FIFO, device or directory before any read could block.
///
/// # Errors
/// [`Error::UnsafePath`] for a file that is not regular; an I/O error naming the path.
pub fn open(path: impl AsRef<Path>) -> Result<File, Error> {
    let path = path.as_ref();
    let f = careful(OpenOptions::new().read(true), true)
        .open(path)
        .map_err(Error::io("read", path))?;
    regular(path, f, READ_REGULAR)
}

/// The text of the regular file `path` (see [`open`]).
///
/// # Errors
/// As [`open`]; text that is not UTF-8 is an I/O error of kind `InvalidData`.
pub fn read_to_string(path: impl AsRef<Path>) -> Result<String, Error> {
    let path = path.as_ref();
    let mut s = String::new();
    open(path)?
        .read_to_string(&mut s)
        .map_err(Error::io("read", path))?;
    Ok(s)
}

/// The text of the regular file `path` (see [`open`]), refused if it has more than `max` bytes
/// (an untrusted file that should be small: the limit is checked before and while reading).
///
/// # Errors
/// As [`read_to_string`], or a file over `max` bytes (naming the path and the limit).
pub fn read_to_string_limited(path: impl AsRef<Path>, max: u64) -> Result<String, Error> {
    let path = path.as_ref();
    let file = open(path)?;
    let len = file.metadata().map_err(Error::io("read", path))?.len();
    let mut s = String::new();
    if len <= max {
        file.take(max + 1)
            .read_to_string(&mut s)
            .map_err(Error::io("read", path))?;
    }
    if len > max || s.len() as u64 > max {
        return Err(Error::malformed(
            path,
            format!("more than {max} bytes is too large for this file"),
        ));
    }
    Ok(s)
}

/// The bytes of the regular file `path` (see [`open`]).
///
/// # Errors
/// As [`open`].
pub fn read(path: impl AsRef<Path>) -> Result<Vec<u8>, Error> {
    let path = path.as_ref();
    let mut v = Vec::new();
    open(path)?
        .read_to_end(&mut v)
        .map_err(Error::io("read", path))?;
    Ok(v)
}

/// Writes `contents` to `path` atomically and without following links: see the module
/// documentation. A regular file already there is replaced and keeps its permissions.
///
/// # Errors
/// [`Error::UnsafePath`] for a link, directory, device or FIFO at `path`; an I/O error naming
/// the path and the operation.
pub fn write(path: impl AsRef<Path>, contents: impl AsRef<[u8]>) -> Result<(), Error> {
    let path = path.as_ref();
    let before = check_writable(path)?;
    let (tmp, mut f) = create_temporary(path)?;
    let written = (|| {
        f.write_all(contents.as_ref())
            .map_err(Error::io("write", &tmp))?;
        if let Some(m) = &before {
            f.set_permissions(m.permissions())
                .map_err(Error::io("set the permissions of", &tmp))?;
        }
        f.sync_all().map_err(Error::io("sync", &tmp))?;
        // The check again, just before the rename: a link put there meanwhile is refused too.
        check_writable(path)?;
        std::fs::rename(&tmp, path).map_err(Error::io("rename into", path))
    })();
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    in_flight::settled(&tmp);
    written?;
    // The rename itself is durable once the directory is synced (where the platform allows it).
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
        && let Ok(d) = File::open(dir)
    {
        let _ = d.sync_all();
    }
    Ok(())
}

/// A new file beside `path` (`.name.PID-N.tmp`), created exclusively: a name already taken, by
/// a link or anything else, is skipped, never opened. It is recorded [`in_flight`] until
/// [`write`] renames or removes it.
fn create_temporary(path: &Path) -> Result<(PathBuf, File), Error> {
    let name = path
        .file_name()
        .ok_or_else(|| refused(path, "not a file name", CHOOSE_ANOTHER))?;
    for n in 0..64u32 {
        let mut tmp_name = std::ffi::OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!(".{}-{n}.tmp", std::process::id()));
        let tmp = path.with_file_name(tmp_name);
        let opened = in_flight::create(&tmp, || {
            careful(OpenOptions::new().write(true).create_new(true), false).open(&tmp)
        });
        match opened {
            Ok(f) => return Ok((tmp, f)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(Error::io("create", &tmp)(e)),
        }
    }
    Err(refused(
        path,
        "64 temporary names beside it are taken",
        "remove the stale .*.tmp files beside it",
    ))
}

/// Creates (or truncates) the regular file `path` for streaming output, never through a link
/// and never a device or FIFO; an existing file keeps its permissions.
///
/// # Errors
/// [`Error::UnsafePath`] for what is not a regular file; an I/O error naming the path.
pub fn create(path: impl AsRef<Path>) -> Result<File, Error> {
    let path = path.as_ref();
    writable(path, "create")?;
    let f = careful(OpenOptions::new().write(true).create(true), false)
        .open(path)
        .map_err(open_error("create", path))?;
    let f = regular(path, f, CHOOSE_ANOTHER)?;
    f.set_len(0).map_err(Error::io("truncate", path))?;
    Ok(f)
}

/// Opens the regular file `path` to append to it (never through a link).
///
/// # Errors
/// [`Error::UnsafePath`] for what is not a regular file; an I/O error naming the path.
pub fn open_append(path: impl AsRef<Path>) -> Result<File, Error> {
    let path = path.as_ref();
    let f = careful(OpenOptions::new().append(true), false)
        .open(path)
        .map_err(open_error("open", path))?;
    regular(path, f, CHOOSE_ANOTHER)
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
        in_flight::settled(&self.path);
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
            in_flight::record(&lock_path);
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

#[cfg(all(test, unix))]
mod tests {
    use super::*;
    use std::os::unix::fs::{PermissionsExt, symlink};

    fn fifo(path: &Path) {
        let c = std::ffi::CString::new(path.as_os_str().as_encoded_bytes()).unwrap();
        // SAFETY: `c` is a NUL-terminated path that lives across the call.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    }

    #[test]
    fn write_refuses_a_link_and_leaves_its_target_alone() {
        let d = tempfile::tempdir().unwrap();
        let victim = d.path().join("victim");
        std::fs::write(&victim, "precious").unwrap();
        let link = d.path().join("sweep.json");
        symlink(&victim, &link).unwrap();
        let e = write(&link, "overwritten").unwrap_err();
        assert!(matches!(e, Error::UnsafePath { .. }), "{e}");
        assert!(e.to_string().contains("a symbolic link"), "{e}");
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        let e = create(&link).unwrap_err();
        assert!(e.to_string().contains("a symbolic link"), "{e}");
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 2);
    }

    #[test]
    fn write_replaces_a_regular_file_keeping_its_mode() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("out.csv");
        std::fs::write(&p, "old").unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o600)).unwrap();
        write(&p, "new").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
        let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o600);
        // A directory where a file goes is refused.
        std::fs::create_dir(d.path().join("dir")).unwrap();
        assert!(write(d.path().join("dir"), "x").is_err());
    }

    #[test]
    fn a_fifo_is_refused_without_blocking() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("fifo");
        fifo(&p);
        // Without O_NONBLOCK the open itself would wait forever for a writer.
        let e = read_to_string(&p).unwrap_err();
        assert!(e.to_string().contains("a FIFO"), "{e}");
        let e = write(&p, "x").unwrap_err();
        assert!(e.to_string().contains("a FIFO"), "{e}");
        let e = create(&p).unwrap_err();
        assert!(e.to_string().contains("a FIFO"), "{e}");
        use std::os::unix::fs::FileTypeExt;
        assert!(std::fs::symlink_metadata(&p).unwrap().file_type().is_fifo());
    }

    #[test]
    fn a_subdirectory_that_is_a_link_is_refused() {
        let d = tempfile::tempdir().unwrap();
        let elsewhere = tempfile::tempdir().unwrap();
        let points = d.path().join("points");
        symlink(elsewhere.path(), &points).unwrap();
        let e = create_subdir(&points).unwrap_err();
        assert!(e.to_string().contains("a symbolic link"), "{e}");
        let fresh = d.path().join("fresh");
        create_subdir(&fresh).unwrap();
        create_subdir(&fresh).unwrap();
        assert!(fresh.is_dir());
    }

    #[test]
    fn a_second_lock_is_refused_until_the_first_is_dropped() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("run.ckpt");
        let first = lock(&p).unwrap();
        let e = lock(&p).unwrap_err();
        assert!(e.to_string().contains("in use by another run"), "{e}");
        drop(first);
        assert!(!d.path().join(".run.ckpt.lock").exists());
        let _again = lock(&p).unwrap();
    }
}
