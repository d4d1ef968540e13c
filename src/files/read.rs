//! Reads: regular files only (never blocking on a FIFO), and never more than their kind can be.

use std::fs::{File, OpenOptions};
use std::io::Read;
use std::path::Path;

use super::{READ_REGULAR, careful, regular};
use crate::Error;

/// The most bytes a file of one kind may have, and the kind's name for the refusal. Every read
/// names one: a file over it is refused from its size before it is read, and a file that grows
/// past it while it is read is refused too, so no file makes the process hold more than its cap.
///
/// The caps are margins over the largest files real runs write (each constant says how large
/// those are).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cap {
    /// The most bytes.
    pub bytes: u64,
    /// What the file is, as the refusal names it ("a checkpoint").
    pub what: &'static str,
}

impl Cap {
    /// At most `bytes` bytes of a file that is `what`.
    pub const fn new(bytes: u64, what: &'static str) -> Cap {
        Cap { bytes, what }
    }

    /// A journal: a checkpoint (`--checkpoint`, a sweep's `points/*.partial`). It holds a line
    /// per finished batch (a diffusion's, with its MSD grid: 551 bytes) and one per trajectory
    /// in flight (its exact state and its observers' accumulators: about 2 kB, 16 per thread):
    /// a default diffusion's is 20 to 300 kB, and one at the most batches a run takes
    /// ([`MAX_BATCHES`](crate::engine::parallel::MAX_BATCHES)) at
    /// most about 0.6 GB, under this cap.
    pub const CHECKPOINT: Cap = Cap::new(1 << 30, "a checkpoint");
    /// A result the audit reads (`lorentz report`): a sweep of hundreds of points with every
    /// run is under 1 MiB.
    pub const RESULT: Cap = Cap::new(64 << 20, "a result file");
    /// A configuration file (`sweep --config`): a few KiB.
    pub const CONFIG: Cap = Cap::new(1 << 20, "a configuration file");
    /// A table given as data (`--table`, TOML): a few KiB.
    pub const TABLE: Cap = Cap::new(1 << 20, "a table file");
    /// A finished point of a sweep over w (`points/*.json`), with every run's batches.
    pub const POINT: Cap = Cap::new(16 << 20, "a sweep point");
    /// A finished point of a sweep in a field (`field-points/*.json`), or a part's manifest.
    pub const FIELD_POINT: Cap = Cap::new(1 << 20, "a field sweep's point or manifest");
    /// A part's manifest (`shard.json`): the part's configuration and point list.
    pub const MANIFEST: Cap = Cap::new(16 << 20, "a part's manifest");
    /// A file this tool wrote and reads back into a document: a figure's SVG, a step's table
    /// or marker (`lorentz reproduce`, `lorentz report`).
    pub const DOCUMENT: Cap = Cap::new(64 << 20, "a figure or table of this tool");
}

/// `n` bytes for a person: `6.0 GiB (6442450944 bytes)`, `300 bytes`.
fn size(n: u64) -> String {
    for (unit, name) in [(1u64 << 30, "GiB"), (1 << 20, "MiB"), (1 << 10, "KiB")] {
        if n >= unit {
            return format!("{:.1} {name} ({n} bytes)", n as f64 / unit as f64);
        }
    }
    format!("{n} bytes")
}

/// A cap for a person: `1 GiB`.
fn cap_size(n: u64) -> String {
    for (unit, name) in [(1u64 << 30, "GiB"), (1 << 20, "MiB"), (1 << 10, "KiB")] {
        if n >= unit && n.is_multiple_of(unit) {
            return format!("{} {name}", n / unit);
        }
    }
    format!("{n} bytes")
}

/// The refusal of `path`, found to hold `n` bytes (`while` it was read), against `cap`.
fn too_big(path: &Path, n: u64, cap: Cap, reading: bool) -> Error {
    Error::malformed(
        path,
        format!(
            "{}{}, beyond the {} {} can be",
            if reading { "grew to " } else { "" },
            size(n),
            cap_size(cap.bytes),
            cap.what
        ),
    )
}

/// Opens the regular file `path` for reading (following links: the user's own files may be
/// links), refusing a FIFO, device or directory before any read could block. The caller reads
/// it within a [`Cap`] of its own ([`read_capped`]).
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

/// The bytes of the open file `file` at `path`, refused if its size (from the metadata, before
/// reading) or what it gave while read is over `cap`.
///
/// # Errors
/// [`Error::Malformed`] naming the size and the cap; an I/O error naming the path.
pub fn read_capped(path: &Path, file: File, cap: Cap) -> Result<Vec<u8>, Error> {
    let len = file.metadata().map_err(Error::io("read", path))?.len();
    if len > cap.bytes {
        return Err(too_big(path, len, cap, false));
    }
    let mut v = Vec::with_capacity(len as usize);
    file.take(cap.bytes + 1)
        .read_to_end(&mut v)
        .map_err(Error::io("read", path))?;
    if v.len() as u64 > cap.bytes {
        return Err(too_big(path, v.len() as u64, cap, true));
    }
    Ok(v)
}

/// The bytes of the regular file `path` (see [`open`]), at most `cap`.
///
/// # Errors
/// As [`open`], or a file over its cap (naming the path, its size and the cap).
pub fn read(path: impl AsRef<Path>, cap: Cap) -> Result<Vec<u8>, Error> {
    let path = path.as_ref();
    read_capped(path, open(path)?, cap)
}

/// The text of the regular file `path` (see [`open`]), at most `cap`.
///
/// # Errors
/// As [`read`]; text that is not UTF-8 is an I/O error of kind `InvalidData`.
pub fn read_to_string(path: impl AsRef<Path>, cap: Cap) -> Result<String, Error> {
    let path = path.as_ref();
    String::from_utf8(read(path, cap)?).map_err(|e| {
        Error::io("read", path)(std::io::Error::new(std::io::ErrorKind::InvalidData, e))
    })
}
