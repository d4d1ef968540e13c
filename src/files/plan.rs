//! Every path a command will write, checked before any work: what is there may be replaced, and
//! no output is one of the command's inputs.

use std::path::{Path, PathBuf};

use super::{CHOOSE_ANOTHER, found_at, kind_of, refused, writable};
use crate::Error;

/// A path a command will write, for [`check_outputs`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Output {
    /// A file written or replaced (by [`super::write()`] or a [`super::Stream`]): absent or a
    /// regular file, never a link, directory, device or FIFO.
    File(PathBuf),
    /// A directory the tool names inside an output directory (`points/`): absent or a
    /// directory, never a link (see [`super::create_subdir`]).
    Subdir(PathBuf),
    /// The output directory the user named: absent or a directory (a link to one is the
    /// user's choice and is followed).
    Dir(PathBuf),
}

impl Output {
    /// The files `names` in `dir`.
    pub fn files_in(dir: &Path, names: &[&str]) -> Vec<Output> {
        names.iter().map(|n| Output::File(dir.join(n))).collect()
    }

    fn path(&self) -> &Path {
        match self {
            Output::File(p) | Output::Subdir(p) | Output::Dir(p) => p,
        }
    }
}

/// Why an output that is an input is refused.
const NOT_AN_INPUT: &str = "an output never replaces an input of the same command: choose \
     another output path";

/// The device and inode of what `path` names, following links (`None`: nothing there, or not
/// inspectable — then it cannot be the same as an input that is).
#[cfg(unix)]
fn identity(path: &Path, follow: bool) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    let m = if follow {
        std::fs::metadata(path)
    } else {
        std::fs::symlink_metadata(path)
    };
    m.ok().map(|m| (m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn identity(path: &Path, _follow: bool) -> Option<std::path::PathBuf> {
    std::fs::canonicalize(path).ok()
}

/// Checks, before any work, every path a command will write: each [`Output`] must be what its
/// kind allows, and none may be (by device and inode, after resolving links) one of `inputs`,
/// the files and directories the command reads. A refusal names the path (and the input).
///
/// # Errors
/// [`Error::UnsafePath`] naming the first output refused; an I/O error naming a path that
/// could not be inspected.
pub fn check_outputs(inputs: &[&Path], outputs: &[Output]) -> Result<(), Error> {
    let read: Vec<_> = inputs
        .iter()
        .filter_map(|p| identity(p, true).map(|id| (*p, id)))
        .collect();
    for o in outputs {
        let path = o.path();
        match o {
            Output::File(p) => {
                writable(p, "create")?;
                if let Some(parent) = p.parent().filter(|d| !d.as_os_str().is_empty())
                    && let Ok(m) = std::fs::metadata(parent)
                    && !m.is_dir()
                {
                    return Err(refused(parent, kind_of(&m), CHOOSE_ANOTHER));
                }
            }
            Output::Subdir(p) => match found_at(p, "create directory")? {
                Some(m) if !m.file_type().is_dir() => {
                    return Err(refused(p, kind_of(&m), CHOOSE_ANOTHER));
                }
                _ => {}
            },
            Output::Dir(p) => match std::fs::metadata(p) {
                Ok(m) if !m.is_dir() => {
                    return Err(refused(p, "not a directory", CHOOSE_ANOTHER));
                }
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                    return Err(Error::io("create directory", p)(e));
                }
                _ => {}
            },
        }
        let Some(id) = identity(path, matches!(o, Output::Dir(_))) else {
            continue;
        };
        if let Some((input, _)) = read.iter().find(|(_, i)| *i == id) {
            return Err(refused(
                path,
                format!("the same file as the input {}", input.display()),
                NOT_AN_INPUT,
            ));
        }
    }
    Ok(())
}

/// `p` as the file system resolves it, so that `./a`, `a/`, a link to `a` and `a/new` (not yet
/// made) compare as `a` and `a/new`: the longest existing ancestor canonicalised, the rest
/// appended.
pub fn resolved(p: &Path) -> PathBuf {
    let mut rest = Vec::new();
    let mut at = p;
    loop {
        if let Ok(c) = std::fs::canonicalize(if at.as_os_str().is_empty() {
            Path::new(".")
        } else {
            at
        }) {
            return rest.iter().rev().fold(c, |acc, name| acc.join(name));
        }
        match (at.parent(), at.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                at = parent;
            }
            _ => return p.to_path_buf(),
        }
    }
}
