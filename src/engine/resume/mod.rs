//! The one resume mechanism: how finished work is kept so that an interrupted run continues
//! where it stopped, for every long analysis (a diffusion run's batches, a sweep point's packed
//! runs, a sweep's points and parts, a reproduction's steps).
//!
//! * [`Journal`]: finished records appended as they come, one JSON line each, after a versioned
//!   header that names the kind of work and its configuration. Opening a journal of another
//!   kind, format or configuration is refused with the first field that differs. Every line
//!   carries a SHA-256 digest (a record's salted with the header's), so an edited, repeated or
//!   foreign line is refused naming the file and the line; only a last line torn by an
//!   interruption is dropped (that record is simply computed again).
//! * Whole files (a sweep point, a part's manifest, a step's record) are written by
//!   [`crate::files::write`]: to a new temporary file in the same directory, synced, and renamed
//!   over the target, so a reader sees the old file or the new one, never a mixture, and
//!   nothing is written through a link.
//! * [`seal`] / [`unseal`]: whole-file units of finished work carry a digest of their content,
//!   checked before they are reused or merged.
//! * [`difference`]: the first field in which two configurations differ, for those refusals.

use std::collections::HashMap;
use std::fs::File;
use std::io::Write;
use std::marker::PhantomData;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::metadata::RunMeta;

mod difference;
use crate::Error;
pub use difference::difference;
use difference::value_difference;

/// Version of the journal layout (header fields, one record per line). A journal of another
/// version is refused: its records may mean something else (version 4 and earlier carried no
/// digests; version 3 and earlier wrote no `kind`; earlier stream schemes drew other
/// trajectories).
pub const FORMAT: u32 = 5;

/// The SHA-256 digest of `bytes`, as 64 lower-case hex digits: the crate's one SHA-256 helper
/// (journals, sealed files, the publication audit's file digest). Feature `checkpoints`.
///
/// # Examples
///
/// ```
/// use lorentz_gas::engine::resume::sha256_hex;
/// assert_eq!(
///     sha256_hex(b"abc"),
///     "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
/// );
/// ```
#[cfg(feature = "checkpoints")]
pub fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The digest of a JSON value: SHA-256 of `salt`, a newline and the value's compact JSON (keys
/// in the order serde_json keeps them, which a parse and a re-serialisation preserve; numbers
/// round-trip exactly).
#[cfg(feature = "checkpoints")]
fn digest_of(salt: &str, v: &Value) -> Result<String, Error> {
    Ok(sha256_hex(format!("{salt}\n{v}").as_bytes()))
}

/// Without the `checkpoints` feature nothing is digested: journals and sealed files are
/// refused (and [`super::options::RunOptions::validate`] refuses `resume` before any work).
#[cfg(not(feature = "checkpoints"))]
fn digest_of(_salt: &str, _v: &Value) -> Result<String, Error> {
    Err(Error::Failed(NO_CHECKPOINTS.into()))
}

/// Why a build without the `checkpoints` feature refuses to keep or resume work.
pub const NO_CHECKPOINTS: &str = "this build of lorentz-gas keeps no checkpoints or sealed \
     files: build the library with its `checkpoints` feature (on by default)";

/// The metadata in the header of the journal at `path`, if it is a readable journal (`None`
/// otherwise: opening it decides what it is). What it says is untrusted: a caller validates what
/// it uses, and the journal's own open checks the header's digest and configuration.
pub fn header_meta(path: &Path) -> Option<RunMeta> {
    crate::files::check_writable(path).ok()??;
    let text = crate::files::read_to_string(path, crate::files::Cap::CHECKPOINT).ok()?;
    let first = text.lines().next()?;
    serde_json::from_str::<Header<Value>>(first).ok()?.meta
}

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
///
/// Every line carries a SHA-256 digest: the header's covers its format, kind, configuration and
/// metadata; a record's covers the header's digest and the record, so that a record copied from
/// a journal of another configuration is as foreign as an edited one.
#[derive(Debug)]
pub struct Journal<R> {
    path: PathBuf,
    /// The header line (with its digest), for rewrites.
    header: String,
    /// The header's digest: the salt of every record's.
    salt: String,
    /// Open for appending (`None` only while the journal is first written).
    file: Mutex<Option<File>>,
    /// Held while the journal is open: a second run on it is refused.
    _lock: crate::files::Lock,
    records: PhantomData<fn(R)>,
}

impl<R: Serialize + DeserializeOwned> Journal<R> {
    /// Opens the journal at `path` for work of `kind` at `config` (created with its header if
    /// missing or empty) and returns it with the records already in it, in file order. A last
    /// line cut short by an interruption (no newline) is dropped from the file.
    ///
    /// # Errors
    /// A file that is not a journal, one of another format, kind or configuration (naming the
    /// first field that differs), a line edited, repeated or not a record (naming the file and
    /// the line); an I/O error (naming the path).
    pub fn open<C: Serialize>(
        path: &Path,
        kind: &str,
        config: &C,
        meta: Option<RunMeta>,
    ) -> Result<(Self, Vec<R>), Error> {
        let lock = crate::files::lock(path)?;
        let (header, salt, lines) = match read_journal(path, kind, config)? {
            Some(found) => found,
            None => {
                let mut h = serde_json::to_value(Header {
                    format: FORMAT,
                    kind: kind.to_string(),
                    config,
                    meta,
                })
                .map_err(Error::encode)?;
                let salt = digest_of("", &h)?;
                h["digest"] = Value::String(salt.clone());
                (h.to_string(), salt, Vec::new())
            }
        };
        let mut records = Vec::with_capacity(lines.len());
        for (n, line) in &lines {
            let r = serde_json::from_value::<R>(line["record"].clone()).map_err(|e| {
                Error::malformed(
                    path,
                    format!(
                        "line {n}: a record of the right digest but not a {kind} record ({e}): \
                         use another file"
                    ),
                )
            })?;
            records.push(r);
        }
        let journal = Journal {
            path: path.to_path_buf(),
            header,
            salt,
            file: Mutex::new(None),
            _lock: lock,
            records: PhantomData,
        };
        let text: String = lines.iter().map(|(_, l)| format!("{l}\n")).collect();
        journal.replace_text(&text)?;
        Ok((journal, records))
    }

    /// The line of `record`, with its digest and the newline.
    fn line(&self, record: &R) -> Result<String, Error> {
        let v = serde_json::to_value(record).map_err(Error::encode)?;
        let digest = digest_of(&self.salt, &v)?;
        let mut line = serde_json::json!({ "digest": digest, "record": v }).to_string();
        line.push('\n');
        Ok(line)
    }

    /// Appends `record` as one line (one write) and syncs it to disk, so that it survives an
    /// interruption.
    ///
    /// # Errors
    /// An I/O error, naming the path.
    pub fn append(&self, record: &R) -> Result<(), Error> {
        let line = self.line(record)?;
        let mut f = self.file.lock().map_err(|_| self.poisoned())?;
        let f = f
            .as_mut()
            .ok_or_else(|| Error::Failed(format!("{}: journal not open", self.path.display())))?;
        f.write_all(line.as_bytes())
            .map_err(|e| io_error("write", &self.path, e))?;
        f.sync_data().map_err(|e| io_error("sync", &self.path, e))
    }

    /// Replaces the records with `records`, atomically (a reader or a resumed run sees the old
    /// journal or the new one): how a journal drops records that later ones made redundant.
    ///
    /// # Errors
    /// An I/O error, naming the path.
    pub fn rewrite(&self, records: &[R]) -> Result<(), Error> {
        let mut text = String::new();
        for r in records {
            text.push_str(&self.line(r)?);
        }
        self.replace_text(&text)
    }

    /// A writer that panicked while it held the journal: a run-time failure (exit status 4), the
    /// same wherever the journal is touched.
    fn poisoned(&self) -> Error {
        Error::Failed(format!("{}: journal lock poisoned", self.path.display()))
    }

    /// Writes the header and `body` atomically and reopens the file for appending.
    fn replace_text(&self, body: &str) -> Result<(), Error> {
        let mut f = self.file.lock().map_err(|_| self.poisoned())?;
        crate::files::write(&self.path, format!("{}\n{body}", self.header))?;
        *f = Some(crate::files::open_append(&self.path)?);
        Ok(())
    }

    /// The journal's file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// The verified contents of the journal at `path` (`None` if it is missing or empty): its
/// header line, the header's digest, and the records' lines (numbered from 1 as an editor
/// numbers them) with their digests checked.
#[allow(clippy::type_complexity)]
fn read_journal<C: Serialize>(
    path: &Path,
    kind: &str,
    config: &C,
) -> Result<Option<(String, String, Vec<(usize, Value)>)>, Error> {
    // Only a regular file is read or replaced: a link, a device or a FIFO is refused as it is.
    if crate::files::check_writable(path)?.is_none() {
        return Ok(None);
    }
    let not_journal = |why: &str| Error::UnsafePath {
        path: path.to_path_buf(),
        found: format!("not a lorentz journal ({why})"),
        why: "a checkpoint file is one this tool wrote, or absent, or empty: use another file",
    };
    let text = match crate::files::read_to_string(path, crate::files::Cap::CHECKPOINT) {
        Ok(t) => t,
        Err(Error::Io { source, .. }) if source.kind() == std::io::ErrorKind::InvalidData => {
            return Err(not_journal("not UTF-8 text"));
        }
        Err(e) => return Err(e),
    };
    if text.is_empty() {
        return Ok(None);
    }
    // A last line without its newline was cut short by an interruption: it is dropped (that
    // record is computed again). Every complete line must be intact; the header is written
    // whole (atomically), so a file without one complete line is not a journal.
    let complete = &text[..text.rfind('\n').map_or(0, |i| i + 1)];
    let mut lines = complete.lines().enumerate().map(|(i, l)| (i + 1, l));
    let Some((_, first)) = lines.next() else {
        return Err(not_journal("no complete line"));
    };
    let salt = check_header(path, first, kind, config)?;
    let mut seen: HashMap<String, usize> = HashMap::new();
    let mut out = Vec::new();
    for (n, line) in lines {
        let v = check_record(path, n, line, &salt)?;
        let d = v["digest"].as_str().unwrap_or_default().to_string();
        if let Some(m) = seen.insert(d, n) {
            return Err(Error::malformed(
                path,
                format!("line {n} repeats line {m}: an edited journal (use another file)"),
            ));
        }
        out.push((n, v));
    }
    Ok(Some((first.to_string(), salt, out)))
}

/// Checks a journal's header line against `kind` and `config` and returns its digest.
fn check_header<C: Serialize>(
    path: &Path,
    line: &str,
    kind: &str,
    config: &C,
) -> Result<String, Error> {
    let not_journal = |why: String| {
        Error::malformed(
            path,
            format!("not a lorentz journal ({why}): use another file"),
        )
    };
    let mut v: Value =
        super::json::parse_unique(line.as_bytes()).map_err(|e| not_journal(e.to_string()))?;
    let digest = match v.as_object_mut().and_then(|o| o.remove("digest")) {
        Some(Value::String(d)) => Some(d),
        _ => None,
    };
    let h: Header<Value> =
        serde_json::from_value(v.clone()).map_err(|e| not_journal(e.to_string()))?;
    if h.format != FORMAT || h.kind != kind {
        return Err(Error::malformed(
            path,
            format!(
                "holds {} of format {} (this version resumes {kind} of format {FORMAT}): use \
                 another file",
                if h.kind.is_empty() { "work" } else { &h.kind },
                h.format
            ),
        ));
    }
    let salt = digest_of("", &v)?;
    if digest.as_deref() != Some(salt.as_str()) {
        return Err(Error::malformed(
            path,
            "line 1: the header does not match its digest (edited): use another file",
        ));
    }
    let want = serde_json::to_value(config).map_err(Error::encode)?;
    if !same_config(&h.config, &want) {
        return Err(Error::malformed(
            path,
            format!(
                "belongs to another configuration ({}): use another file or the same parameters",
                value_difference(&h.config, &want, "")
                    .unwrap_or_else(|| "the configurations differ".into())
            ),
        ));
    }
    Ok(salt)
}

/// Whether a journal's recorded configuration `stored` is the configuration `want` of this run:
/// equal, or recorded before a triangular gap was kept as typed — without `w_exact`, the double
/// `w` alone — where `want` names the same double and runs in `f64` (no `precision`, or `f64`)
/// or at a gap that is exactly that double: the same trajectories, bit for bit.
fn same_config(stored: &Value, want: &Value) -> bool {
    match (stored, want) {
        (Value::Array(a), Value::Array(b)) => {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same_config(x, y))
        }
        (Value::Object(a), Value::Object(b))
            if !a.contains_key("w_exact") && b.contains_key("w_exact") =>
        {
            let w = b.get("w").and_then(Value::as_f64);
            let exact = b.get("w_exact").and_then(Value::as_str);
            let of_double = w.and_then(crate::numbers::exact::exact_text_of);
            let f64_run = b.get("precision").is_none_or(|p| p == "f64");
            let mut b = b.clone();
            b.remove("w_exact");
            (f64_run || exact == of_double.as_deref()) && *a == b
        }
        _ => stored == want,
    }
}

/// Checks record line `n` against its digest (salted with the header's).
fn check_record(path: &Path, n: usize, line: &str, salt: &str) -> Result<Value, Error> {
    let bad = |why: &str| {
        Error::malformed(
            path,
            format!("line {n}: {why}: an edited, damaged or foreign journal (use another file)"),
        )
    };
    let v: Value =
        super::json::parse_unique(line.as_bytes()).map_err(|_| bad("not a journal record"))?;
    let (Some(Value::String(d)), Some(r)) = (v.get("digest"), v.get("record")) else {
        return Err(bad("not a journal record"));
    };
    if v.as_object().map_or(0, |o| o.len()) != 2 {
        return Err(bad("unknown fields beside the record"));
    }
    if *d != digest_of(salt, r)? {
        return Err(bad("the record does not match its digest"));
    }
    Ok(v)
}

/// `x` as pretty JSON with a `digest` field: the SHA-256 of its compact JSON. What a whole-file
/// unit of finished work (a sweep point, a part's manifest) is written as, so that
/// [`unseal`] can refuse an edited file.
///
/// # Errors
/// If `x` is not a JSON object.
pub fn seal<T: Serialize>(x: &T) -> Result<String, Error> {
    let mut v = serde_json::to_value(x).map_err(Error::encode)?;
    let d = digest_of("", &v)?;
    let Some(o) = v.as_object_mut() else {
        return Err(Error::Failed("only a JSON object can be sealed".into()));
    };
    o.insert("digest".into(), Value::String(d));
    serde_json::to_string_pretty(&v).map_err(Error::encode)
}

/// The value of a file written by [`seal`], its digest checked: an edited, truncated or
/// unsealed file is refused, naming `path` and what it should be (`what`).
///
/// # Errors
/// As above.
pub fn unseal<T: DeserializeOwned>(path: &Path, text: &str, what: &str) -> Result<T, Error> {
    let bad = |why: String| {
        Error::malformed(
            path,
            format!("{why}: not an intact {what} (edited, damaged or of another version)"),
        )
    };
    let mut v: Value =
        super::json::parse_unique(text.as_bytes()).map_err(|e| bad(e.to_string()))?;
    let d = match v.as_object_mut().and_then(|o| o.remove("digest")) {
        Some(Value::String(d)) => d,
        _ => return Err(bad("no digest".into())),
    };
    if d != digest_of("", &v)? {
        return Err(bad("the content does not match its digest".into()));
    }
    serde_json::from_value(v).map_err(|e| bad(e.to_string()))
}

/// An I/O error that names the operation and the path.
pub fn io_error(op: &'static str, path: &Path, e: std::io::Error) -> Error {
    Error::io(op, path)(e)
}

#[cfg(all(test, feature = "checkpoints"))]
mod tests {
    use super::*;

    #[derive(Serialize, Deserialize, PartialEq, Debug)]
    struct Cfg {
        w: f64,
        seed: u64,
    }

    #[test]
    fn journals_keep_records_and_refuse_foreign_work() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("j.jsonl");
        let cfg = Cfg { w: 0.1, seed: 1 };
        let (j, old) = Journal::<u32>::open(&p, "numbers", &cfg, None).unwrap();
        assert!(old.is_empty());
        j.append(&7).unwrap();
        j.append(&9).unwrap();
        drop(j);
        // A torn last line is dropped; the records before it are kept.
        let mut text = std::fs::read_to_string(&p).unwrap();
        text.push_str("{\"digest\":\"12");
        std::fs::write(&p, text).unwrap();
        let (_, old) = Journal::<u32>::open(&p, "numbers", &cfg, None).unwrap();
        assert_eq!(old, vec![7, 9]);
        assert!(
            std::fs::read_to_string(&p).unwrap().ends_with("}\n"),
            "the torn line is gone"
        );
        let e = Journal::<u32>::open(&p, "numbers", &Cfg { w: 0.1, seed: 2 }, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("seed: 1 vs 2"), "{e}");
        let e = Journal::<u32>::open(&p, "letters", &cfg, None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("letters"), "{e}");
    }

    /// Writes `lines` as the journal at `p` and returns the refusal of opening it.
    fn refusal(p: &Path, lines: &[String], cfg: &Cfg) -> String {
        std::fs::write(p, lines.concat()).unwrap();
        Journal::<u32>::open(p, "numbers", cfg, None)
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn edited_repeated_and_foreign_lines_are_refused_by_line() {
        let dir = tempfile::tempdir().unwrap();
        let (p, q) = (dir.path().join("a.jsonl"), dir.path().join("b.jsonl"));
        let (a, b) = (Cfg { w: 0.1, seed: 1 }, Cfg { w: 0.1, seed: 2 });
        let (j, _) = Journal::<u32>::open(&p, "numbers", &a, None).unwrap();
        j.append(&7).unwrap();
        j.append(&9).unwrap();
        let (k, _) = Journal::<u32>::open(&q, "numbers", &b, None).unwrap();
        k.append(&5).unwrap();
        // Closed (their locks released) before the files are reopened.
        drop((j, k));
        let lines: Vec<String> = std::fs::read_to_string(&p)
            .unwrap()
            .lines()
            .map(|l| format!("{l}\n"))
            .collect();
        let other: Vec<String> = std::fs::read_to_string(&q)
            .unwrap()
            .lines()
            .map(|l| format!("{l}\n"))
            .collect();
        let edited = lines[2].replace("\"record\":9", "\"record\":8");
        assert_ne!(edited, lines[2]);
        let e = refusal(&p, &[lines[0].clone(), lines[1].clone(), edited], &a);
        assert!(e.contains("a.jsonl: line 3") && e.contains("digest"), "{e}");
        let e = refusal(
            &p,
            &[lines[0].clone(), lines[1].clone(), lines[1].clone()],
            &a,
        );
        assert!(e.contains("line 3 repeats line 2"), "{e}");
        let e = refusal(&p, &[lines[0].clone(), other[1].clone()], &a);
        assert!(e.contains("line 2") && e.contains("foreign"), "{e}");
        let header = lines[0].replace("\"w\":0.1", "\"w\":0.2");
        let e = refusal(&p, &[header, lines[1].clone()], &Cfg { w: 0.2, seed: 1 });
        assert!(e.contains("line 1") && e.contains("digest"), "{e}");
        let e = refusal(&p, &[lines[0].clone(), "garbage\n".into()], &a);
        assert!(e.contains("line 2"), "{e}");
    }

    #[test]
    fn sealed_files_refuse_edits() {
        let p = Path::new("point.json");
        let text = seal(&Cfg { w: 0.1, seed: 3 }).unwrap();
        let back: Cfg = unseal(p, &text, "point").unwrap();
        assert_eq!(back, Cfg { w: 0.1, seed: 3 });
        let edited = text.replace("0.1", "0.10000000000000002");
        assert_ne!(edited, text);
        let e = unseal::<Cfg>(p, &edited, "point").unwrap_err().to_string();
        assert!(e.contains("point.json") && e.contains("digest"), "{e}");
        let e = unseal::<Cfg>(p, &text[..text.len() / 2], "point")
            .unwrap_err()
            .to_string();
        assert!(e.contains("point.json"), "{e}");
        let e = unseal::<Cfg>(p, "{\"w\":0.1,\"seed\":3}", "point")
            .unwrap_err()
            .to_string();
        assert!(e.contains("no digest"), "{e}");
    }

    #[test]
    fn atomic_writes_replace_whole_files() {
        let dir = std::env::temp_dir().join(format!("lorentz-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.json");
        crate::files::write(&p, b"first").unwrap();
        crate::files::write(&p, b"second").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"second");
        let names: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(names.len(), 1, "no temporary file is left behind");
        let e = crate::files::write(dir.join("missing").join("b.json"), b"x").unwrap_err();
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
