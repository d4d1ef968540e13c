//! The one resume mechanism: how finished work is kept so that an interrupted run continues
//! where it stopped, for every long analysis (a diffusion run's batches, a sweep point's packed
//! runs, a sweep's points and parts, a reproduction's steps).
//!
//! * [`Journal`]: finished records appended as they come, one JSON line each, after a versioned
//!   header that names the kind of work and its configuration. Opening a journal of another
//!   kind, format or configuration is refused with the first field that differs; a line torn by
//!   an interruption is ignored (that record is simply computed again).
//! * [`write_atomically`]: whole files (a sweep point, a part's manifest, a step's record) are
//!   written to a temporary file in the same directory, synced, and renamed over the target, so
//!   a reader sees the old file or the new one, never a mixture.
//! * [`difference`]: the first field in which two configurations differ, for those refusals.

use std::fs::{File, OpenOptions};
use std::io::{BufRead, BufReader, Write};
use std::marker::PhantomData;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

use super::metadata::RunMeta;
use crate::Error;

/// Version of the journal layout (header fields, one record per line). A journal of another
/// version is refused: its records may mean something else (version 3 and earlier wrote no
/// `kind`; earlier stream schemes drew other trajectories).
pub const FORMAT: u32 = 4;

/// The first line of a journal.
#[derive(Serialize, Deserialize)]
struct Header<C> {
    /// [`FORMAT`].
    format: u32,
    /// What the records are (`diffusion batches`, `packed runs`, …).
    kind: String,
    /// The configuration the records belong to.
    config: C,
    /// How the journal was started (informational).
    #[serde(default)]
    meta: Option<RunMeta>,
}

/// An append-only record of finished work of one configuration (see the module documentation).
/// Records are appended from any worker thread.
#[derive(Debug)]
pub struct Journal<R> {
    path: PathBuf,
    file: Mutex<File>,
    records: PhantomData<fn(R)>,
}

impl<R: Serialize + DeserializeOwned> Journal<R> {
    /// Opens the journal at `path` for work of `kind` at `config` (created with its header if
    /// missing or empty) and returns it with the records already in it, in file order.
    ///
    /// # Errors
    /// A file that is not a journal, or one of another format, kind or configuration (naming
    /// the first field that differs); an I/O error (naming the path).
    pub fn open<C: Serialize>(
        path: &Path,
        kind: &str,
        config: &C,
        meta: Option<RunMeta>,
    ) -> Result<(Self, Vec<R>), Error> {
        let records = read_records(path, kind, config)?;
        let fresh = std::fs::metadata(path).map_or(true, |m| m.len() == 0);
        let mut f = OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(|e| io_error("open", path, e))?;
        if fresh {
            let header = Header {
                format: FORMAT,
                kind: kind.to_string(),
                config,
                meta,
            };
            writeln!(f, "{}", to_line(&header)?).map_err(|e| io_error("write", path, e))?;
        } else {
            // A line cut short by an interruption must not swallow the next record.
            writeln!(f).map_err(|e| io_error("write", path, e))?;
        }
        f.sync_data().map_err(|e| io_error("sync", path, e))?;
        let journal = Journal {
            path: path.to_path_buf(),
            file: Mutex::new(f),
            records: PhantomData,
        };
        Ok((journal, records))
    }

    /// Appends `record` as one line and syncs it to disk, so that it survives an interruption.
    ///
    /// # Errors
    /// An I/O error, naming the path.
    pub fn append(&self, record: &R) -> Result<(), Error> {
        let line = to_line(record)?;
        let mut f = self.file.lock().map_err(|_| {
            Error::Failed(format!("{}: journal lock poisoned", self.path.display()))
        })?;
        writeln!(f, "{line}").map_err(|e| io_error("write", &self.path, e))?;
        f.sync_data().map_err(|e| io_error("sync", &self.path, e))
    }

    /// The journal's file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// The records of the journal at `path` (none if it is missing or empty), after checking its
/// header against `kind` and `config`.
fn read_records<C: Serialize, R: DeserializeOwned>(
    path: &Path,
    kind: &str,
    config: &C,
) -> Result<Vec<R>, Error> {
    let f = match File::open(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(io_error("open", path, e)),
    };
    let mut lines = BufReader::new(f).lines();
    let Some(first) = lines.next() else {
        return Ok(Vec::new());
    };
    let first = first.map_err(|e| io_error("read", path, e))?;
    let h: Header<serde_json::Value> = serde_json::from_str(&first).map_err(|e| {
        Error::Invalid(format!(
            "{} is not a lorentz journal ({e}): use another file",
            path.display()
        ))
    })?;
    if h.format != FORMAT || h.kind != kind {
        return Err(Error::Invalid(format!(
            "{} holds {} of format {} (this version resumes {kind} of format {FORMAT}): use another file",
            path.display(),
            if h.kind.is_empty() { "work" } else { &h.kind },
            h.format
        )));
    }
    let want = serde_json::to_value(config).map_err(Error::encode)?;
    if h.config != want {
        return Err(Error::Invalid(format!(
            "{} belongs to another configuration ({}): use another file or the same parameters",
            path.display(),
            value_difference(&h.config, &want, "")
                .unwrap_or_else(|| "the configurations differ".into())
        )));
    }
    let mut out = Vec::new();
    for line in lines {
        let line = line.map_err(|e| io_error("read", path, e))?;
        // A line torn by an interruption is ignored: that record is computed again.
        if let Ok(r) = serde_json::from_str::<R>(&line) {
            out.push(r);
        }
    }
    Ok(out)
}

/// Writes `bytes` to `path` atomically: a temporary file in the same directory is written,
/// synced and renamed over `path`, so a reader (or a resumed run) sees the old file or the new
/// one, never a mixture.
///
/// # Errors
/// An I/O error, naming the path and the operation.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let name = path
        .file_name()
        .ok_or_else(|| Error::Invalid(format!("{}: not a file path", path.display())))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(".tmp");
    let tmp = path.with_file_name(tmp_name);
    {
        let mut f = File::create(&tmp).map_err(|e| io_error("create", &tmp, e))?;
        f.write_all(bytes).map_err(|e| io_error("write", &tmp, e))?;
        f.sync_all().map_err(|e| io_error("sync", &tmp, e))?;
    }
    std::fs::rename(&tmp, path).map_err(|e| io_error("rename into", path, e))?;
    // The rename itself is durable once the directory is synced (where the platform allows it).
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        if let Ok(d) = File::open(dir) {
            let _ = d.sync_all();
        }
    }
    Ok(())
}

/// The first field in which two configurations differ, as `field: a vs b` (`None` if equal).
pub fn difference<C: Serialize>(a: &C, b: &C) -> Option<String> {
    let (a, b) = (serde_json::to_value(a).ok()?, serde_json::to_value(b).ok()?);
    value_difference(&a, &b, "")
}

/// The first differing leaf of two JSON values, with its path.
fn value_difference(a: &serde_json::Value, b: &serde_json::Value, at: &str) -> Option<String> {
    use serde_json::Value;
    let name = |k: &str| {
        if at.is_empty() {
            k.to_string()
        } else {
            format!("{at}.{k}")
        }
    };
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            keys.into_iter().find_map(|k| match (x.get(k), y.get(k)) {
                (Some(u), Some(v)) => value_difference(u, v, &name(k)),
                (u, v) => Some(format!("{}: {} vs {}", name(k), show(u), show(v))),
            })
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .find_map(|(i, (u, v))| value_difference(u, v, &name(&i.to_string()))),
        _ if a == b => None,
        _ => Some(format!(
            "{}: {} vs {}",
            if at.is_empty() { "value" } else { at },
            show(Some(a)),
            show(Some(b))
        )),
    }
}

fn show(v: Option<&serde_json::Value>) -> String {
    match v {
        None => "absent".into(),
        Some(serde_json::Value::String(s)) => s.clone(),
        Some(v) => v.to_string(),
    }
}

fn to_line<T: Serialize>(v: &T) -> Result<String, Error> {
    serde_json::to_string(v).map_err(Error::encode)
}

/// An I/O error that names the operation and the path.
pub fn io_error(op: &'static str, path: &Path, e: std::io::Error) -> Error {
    Error::io(op, path)(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize, Deserialize, PartialEq, Debug)]
    struct Cfg {
        w: f64,
        seed: u64,
    }

    #[test]
    fn journals_keep_records_and_refuse_foreign_work() {
        let dir = std::env::temp_dir().join(format!("lorentz-resume-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("j.jsonl");
        let _ = std::fs::remove_file(&p);
        let cfg = Cfg { w: 0.1, seed: 1 };
        let (j, old) = Journal::<u32>::open(&p, "numbers", &cfg, None).unwrap();
        assert!(old.is_empty());
        j.append(&7).unwrap();
        j.append(&9).unwrap();
        drop(j);
        // A torn last line is ignored; the records before it are kept.
        let mut text = std::fs::read_to_string(&p).unwrap();
        text.push_str("1\"x");
        std::fs::write(&p, text).unwrap();
        let (_, old) = Journal::<u32>::open(&p, "numbers", &cfg, None).unwrap();
        assert_eq!(old, vec![7, 9]);
        let e = Journal::<u32>::open(&p, "numbers", &Cfg { w: 0.1, seed: 2 }, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("seed: 1 vs 2"), "{e}");
        let e = Journal::<u32>::open(&p, "letters", &cfg, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("letters"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn atomic_writes_replace_whole_files() {
        let dir = std::env::temp_dir().join(format!("lorentz-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.json");
        write_atomically(&p, b"first").unwrap();
        write_atomically(&p, b"second").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"second");
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(names.len(), 1, "no temporary file is left behind");
        let e = write_atomically(&dir.join("missing").join("b.json"), b"x").unwrap_err();
        assert!(e.to_string().contains("missing"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn differences_name_the_first_field() {
        let a = Cfg { w: 0.1, seed: 1 };
        assert_eq!(difference(&a, &a), None);
        let b = Cfg { w: 0.2, seed: 1 };
        assert_eq!(difference(&a, &b).unwrap(), "w: 0.1 vs 0.2");
    }
}
