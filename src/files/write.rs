//! Writes: every output, whole or streamed, goes to a new temporary file beside its target and
//! is renamed over it only once it is complete and synced.

use std::fs::{File, OpenOptions, Permissions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use super::{CHOOSE_ANOTHER, careful, check_writable, open_error, refused, regular};
use crate::Error;

/// An output being written: a temporary file beside its target, renamed over the target by
/// [`Stream::commit`] and removed if dropped before (a failed or refused run leaves the target
/// as it was and nothing beside it). Until the commit the target is not touched: not truncated,
/// not removed, not written through a hard link (the rename replaces the name, so another hard
/// link to the old file keeps the old contents).
///
/// Written through [`std::io::Write`]; the errors of those writes are the caller's to name
/// (with [`Stream::path`]).
#[derive(Debug)]
pub struct Stream {
    target: PathBuf,
    tmp: PathBuf,
    out: Option<BufWriter<File>>,
    /// The permissions of the regular file found at the target, kept by its replacement.
    kept: Option<Permissions>,
}

impl Stream {
    /// Starts writing `path`: refuses a link, directory, device or FIFO there, and creates the
    /// temporary file beside it.
    ///
    /// # Errors
    /// [`Error::UnsafePath`] for what is at `path`; an I/O error naming the temporary file.
    pub fn create(path: impl AsRef<Path>) -> Result<Stream, Error> {
        let target = path.as_ref().to_path_buf();
        let kept = check_writable(&target)?.map(|m| m.permissions());
        let (tmp, f) = create_temporary(&target)?;
        Ok(Stream {
            target,
            tmp,
            out: Some(BufWriter::new(f)),
            kept,
        })
    }

    /// The target's path, for the errors of writes.
    pub fn path(&self) -> &Path {
        &self.target
    }

    /// Completes the output: flushes and syncs the temporary file, checks the target again (a
    /// link put there meanwhile is refused too) and renames the temporary file over it.
    ///
    /// # Errors
    /// An I/O error naming the target (a full disk, a file size limit); [`Error::UnsafePath`].
    /// The temporary file is removed and the target left as it was.
    pub fn commit(mut self) -> Result<(), Error> {
        let out = self
            .out
            .take()
            .ok_or_else(|| Error::Failed(format!("{}: committed twice", self.target.display())))?;
        let f = out
            .into_inner()
            .map_err(|e| Error::io("write", &self.target)(e.into_error()))?;
        if let Some(p) = &self.kept {
            f.set_permissions(p.clone())
                .map_err(Error::io("set the permissions of", &self.tmp))?;
        }
        f.sync_all().map_err(Error::io("write", &self.target))?;
        drop(f);
        check_writable(&self.target)?;
        std::fs::rename(&self.tmp, &self.target).map_err(Error::io("rename into", &self.target))?;
        super::in_flight::settled(&std::mem::take(&mut self.tmp));
        // The rename itself is durable once the directory is synced (where the platform
        // allows it).
        if let Some(dir) = self.target.parent().filter(|d| !d.as_os_str().is_empty())
            && let Ok(d) = File::open(dir)
        {
            let _ = d.sync_all();
        }
        Ok(())
    }
}

impl Write for Stream {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.out {
            Some(o) => o.write(buf),
            None => Err(std::io::Error::other("output already committed")),
        }
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out.as_mut().map_or(Ok(()), BufWriter::flush)
    }
}

impl Drop for Stream {
    fn drop(&mut self) {
        if !self.tmp.as_os_str().is_empty() {
            // Unflushed bytes are dropped with the file: nothing of an unfinished output stays.
            if let Some(o) = self.out.take() {
                let (f, _) = o.into_parts();
                drop(f);
            }
            let _ = std::fs::remove_file(&self.tmp);
            super::in_flight::settled(&self.tmp);
        }
    }
}

/// Writes `contents` to `path` atomically and without following links, through a [`Stream`]:
/// see the module documentation. A regular file already there is replaced and keeps its
/// permissions.
///
/// # Errors
/// [`Error::UnsafePath`] for a link, directory, device or FIFO at `path`; an I/O error naming
/// the path and the operation.
pub fn write(path: impl AsRef<Path>, contents: impl AsRef<[u8]>) -> Result<(), Error> {
    let mut s = Stream::create(path)?;
    s.write_all(contents.as_ref())
        .map_err(Error::io("write", &s.target))?;
    s.commit()
}

/// A new file beside `path` (`.name.PID-N.tmp`), created exclusively: a name already taken, by
/// a link or anything else, is skipped, never opened. It is recorded
/// [`in_flight`](super::in_flight) until its [`Stream`] renames or removes it.
fn create_temporary(path: &Path) -> Result<(PathBuf, File), Error> {
    let name = path
        .file_name()
        .ok_or_else(|| refused(path, "not a file name", CHOOSE_ANOTHER))?;
    for n in 0..64u32 {
        let mut tmp_name = std::ffi::OsString::from(".");
        tmp_name.push(name);
        tmp_name.push(format!(".{}-{n}.tmp", std::process::id()));
        let tmp = path.with_file_name(tmp_name);
        let opened = super::in_flight::create(&tmp, || {
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

/// Opens the regular file `path` to append to it in place (a journal, just written by
/// [`write()`]): never through a symbolic link, and never a file with another hard link, whose
/// other name would change with it.
///
/// # Errors
/// [`Error::UnsafePath`] for what is not a regular file of one link; an I/O error naming the
/// path.
pub fn open_append(path: impl AsRef<Path>) -> Result<File, Error> {
    let path = path.as_ref();
    let f = careful(OpenOptions::new().append(true), false)
        .open(path)
        .map_err(open_error("open", path))?;
    let f = regular(path, f, CHOOSE_ANOTHER)?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let links = f.metadata().map_err(Error::io("inspect", path))?.nlink();
        if links > 1 {
            return Err(refused(
                path,
                format!("a file with {links} hard links"),
                CHOOSE_ANOTHER,
            ));
        }
    }
    Ok(f)
}
