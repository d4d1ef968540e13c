//! The result-file reader of the audit: a bounded read, the kind recognised from the file's
//! keys, and every key checked against the schema of that kind.
//!
//! Nothing in the file decides what runs or where anything is written: the kind is one of
//! [`Kind`] (recognised by a key only that kind writes), the file is read into the kind's result
//! struct, a key the struct does not hold refuses the file (so an audited file carries no
//! unaudited fields), and the recorded configuration is validated as command-line input is.

use std::path::Path;

use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::Value;

use crate::Error;

/// Largest result file the audit reads: 64 MiB, checked from the file's metadata before reading
/// (and again while reading). The largest results lorentz writes at realistic settings are far
/// below it: a default diffusion result is 8 kB (32 batches × 25 MSD lags), a 10⁴-point sweep of
/// 10 runs about 6 MB; at 25 lags the bound allows about 10⁵ diffusion batches. Reading parses
/// into a JSON tree and the result struct, about 4 times the file's size at most.
pub const MAX_RESULT_BYTES: u64 = crate::files::Cap::RESULT.bytes;

/// The kinds of result the audit knows, each recognised by a key that only it writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `lorentz diffusion --json`.
    Diffusion,
    /// `lorentz sweep` (`sweep.json`, `--json`) and `lorentz merge` (the same result).
    Sweep,
    /// `lorentz hops --json`.
    Hops,
    /// `lorentz theory --json`.
    Theory,
    /// `lorentz lattice-walk --json`.
    LatticeWalk,
    /// `lorentz backscatter --json`.
    Backscatter,
    /// `lorentz escape --json` (open strips of the triangular gas).
    Escape,
    /// `lorentz escape --repeller` or `--open FILE` with `--json` (survival on an open table).
    Survival,
    /// `lorentz diffusion --field B --json`.
    Field,
    /// `lorentz diffusion --electric E --json` (the driven gas's steady state).
    Current,
    /// `lorentz sweep --electric E1,E2,…` (`driven-sweep.json`, `--json`) and its merge.
    DrivenSweep,
    /// `lorentz sweep --fields …` or `--field B` (`field-sweep.json`, `--json`).
    FieldSweep,
    /// `lorentz diffusion --table FILE --json` (D on a table given as data).
    TableDiffusion,
}

impl Kind {
    /// Every kind, each with the keys that identify it (all present; `bench --report` has `rows`
    /// too, but no `linear_fit`).
    pub const ALL: [(Kind, &'static [&'static str]); 13] = [
        (Kind::Diffusion, &["batch_D"]),
        (Kind::Sweep, &["rows", "linear_fit"]),
        (Kind::Hops, &["pairs"]),
        (Kind::Theory, &["orders"]),
        (Kind::LatticeWalk, &["walks"]),
        (Kind::Backscatter, &["mean_visit_time"]),
        (Kind::Escape, &["D_escape"]),
        (Kind::Survival, &["start_density", "batch_gamma"]),
        (Kind::Field, &["batch_D_xx", "localized_fraction_exact"]),
        (Kind::Current, &["J_parallel", "batch_J_parallel"]),
        (Kind::DrivenSweep, &["rows", "odd", "mobility"]),
        (Kind::FieldSweep, &["rows", "onsager"]),
        (Kind::TableDiffusion, &["batch_D", "identities", "table"]),
    ];

    /// The command that writes it.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Diffusion => "diffusion",
            Kind::Sweep => "sweep",
            Kind::Hops => "hops",
            Kind::Theory => "theory",
            Kind::LatticeWalk => "lattice-walk",
            Kind::Backscatter => "backscatter",
            Kind::Escape | Kind::Survival => "escape",
            Kind::Field | Kind::Current => "diffusion",
            Kind::FieldSweep | Kind::DrivenSweep => "sweep",
            Kind::TableDiffusion => "diffusion",
        }
    }

    /// The kinds, as a list for messages: `diffusion (batch_D), sweep (rows and linear_fit), …`.
    fn list() -> String {
        Kind::ALL
            .iter()
            .map(|(k, keys)| format!("{} ({})", k.name(), keys.join(" and ")))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A result file as read: its digest, its kind and its JSON tree.
pub struct ResultFile {
    /// SHA-256 of the file's bytes (hex).
    pub sha: String,
    /// Its kind.
    pub kind: Kind,
    /// Its JSON (an object).
    pub value: Value,
}

impl ResultFile {
    /// Reads `path` (a regular file of at most [`MAX_RESULT_BYTES`]), parses it and recognises
    /// its kind; anything else is bad input naming the file and the reason.
    pub fn read(path: &Path) -> Result<Self, Error> {
        let bytes = read_bounded(path)?;
        let sha = crate::engine::resume::sha256_hex(&bytes);
        let value: Value = crate::engine::json::parse_unique(&bytes).map_err(|e| {
            Error::malformed(
                path,
                format!(
                    "not a JSON result of lorentz ({e}); give a result an analysis wrote as JSON"
                ),
            )
        })?;
        drop(bytes);
        let Some(object) = value.as_object() else {
            return Err(Error::malformed(
                path,
                "not a JSON object: not a result of lorentz",
            ));
        };
        let mut kinds: Vec<Kind> = Kind::ALL
            .iter()
            .filter(|(_, keys)| keys.iter().all(|k| object.contains_key(*k)))
            .map(|(k, _)| *k)
            .collect();
        // D on a table has the batch values of any diffusion result, and its table besides.
        if kinds.contains(&Kind::TableDiffusion) {
            kinds.retain(|k| *k != Kind::Diffusion);
        }
        let kind = match kinds[..] {
            [k] => k,
            [] => {
                return Err(Error::malformed(
                    path,
                    format!(
                        "not a result that report audits: it has none of the keys that identify {} (results of other commands are not audited)",
                        Kind::list()
                    ),
                ));
            }
            _ => {
                return Err(Error::malformed(
                    path,
                    format!(
                        "keys of several kinds of result ({}): not a result of lorentz",
                        kinds
                            .iter()
                            .map(|k| k.name())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            }
        };
        Ok(ResultFile { sha, kind, value })
    }

    /// The file as the result struct `T` of its kind: every key of the file must be one that
    /// `T` holds (the first other one is named), and `T` must parse.
    pub fn parse<T: DeserializeOwned + Serialize>(&self, path: &Path) -> Result<T, Error> {
        let kind = self.kind.name();
        let t = T::deserialize(&self.value).map_err(|e| {
            Error::malformed(
                path,
                format!("not a {kind} result as lorentz writes it: {e}"),
            )
        })?;
        let schema = serde_json::to_value(&t).map_err(|e| Error::malformed(path, e))?;
        if let Some(key) = first_unknown_key(&self.value, &schema, "") {
            return Err(Error::malformed(
                path,
                format!(
                    "unknown key `{key}`: a {kind} result holds no such key, and the audit accepts no field it does not check"
                ),
            ));
        }
        Ok(t)
    }
}

/// Reads at most [`MAX_RESULT_BYTES`] of the regular file `path`, refusing larger ones (from the
/// metadata, before reading) and anything that is not a regular file.
fn read_bounded(path: &Path) -> Result<Vec<u8>, Error> {
    crate::files::read(path, crate::files::Cap::RESULT)
}

/// The first key (as a dotted path) of `file` that `schema` (the result struct written back)
/// does not hold, looking into objects and arrays.
fn first_unknown_key(file: &Value, schema: &Value, at: &str) -> Option<String> {
    let join = |k: &str| {
        if at.is_empty() {
            k.to_string()
        } else {
            format!("{at}.{k}")
        }
    };
    match (file, schema) {
        (Value::Object(f), Value::Object(s)) => f.iter().find_map(|(k, v)| match s.get(k) {
            None => Some(join(k)),
            Some(sv) => first_unknown_key(v, sv, &join(k)),
        }),
        (Value::Object(f), _) => f.keys().next().map(|k| join(k)),
        (Value::Array(f), Value::Array(s)) => f
            .iter()
            .zip(s)
            .enumerate()
            .find_map(|(i, (a, b))| first_unknown_key(a, b, &join(&i.to_string()))),
        _ => None,
    }
}
