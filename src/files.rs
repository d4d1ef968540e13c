//! `std::fs` with errors that name their operation and path ([`Error::Io`]): every file the
//! crate reads or writes goes through these or through `map_err(Error::io(op, path))`.

use std::path::Path;

use crate::Error;

/// Writes `contents` to `path` (created or truncated).
pub fn write(path: impl AsRef<Path>, contents: impl AsRef<[u8]>) -> Result<(), Error> {
    let path = path.as_ref();
    std::fs::write(path, contents).map_err(Error::io("write", path))
}

/// The text of `path`.
pub fn read_to_string(path: impl AsRef<Path>) -> Result<String, Error> {
    let path = path.as_ref();
    std::fs::read_to_string(path).map_err(Error::io("read", path))
}

/// The bytes of `path`.
pub fn read(path: impl AsRef<Path>) -> Result<Vec<u8>, Error> {
    let path = path.as_ref();
    std::fs::read(path).map_err(Error::io("read", path))
}

/// Creates the directory `path` and its parents.
pub fn create_dir_all(path: impl AsRef<Path>) -> Result<(), Error> {
    let path = path.as_ref();
    std::fs::create_dir_all(path).map_err(Error::io("create directory", path))
}

/// Creates (or truncates) the file `path` for writing.
pub fn create(path: impl AsRef<Path>) -> Result<std::fs::File, Error> {
    let path = path.as_ref();
    std::fs::File::create(path).map_err(Error::io("create", path))
}
