//! A finished step's marker (`done.json`): sealed, with the budget, version and seed it was made
//! with, so that a rerun takes over only its own reproduction's steps.

use std::path::Path;

use serde::Serialize;

use crate::Error;

/// A finished step's marker, sealed ([`crate::engine::resume::seal`]): the budget, version and
/// seed it was made with, so that a reproduction with another seed never takes it as its own.
#[derive(Debug, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Done {
    pub(super) budget: String,
    pub(super) version: String,
    pub(super) seed: u64,
    pub(super) seconds: f64,
    pub(super) files: Vec<String>,
}

/// The marker of a finished step at `marker` (see `Reproduction::finished`).
pub(super) fn finished_step(marker: &Path, budget: &str, seed: u64) -> Result<Option<Done>, Error> {
    if !marker.exists() {
        return Ok(None);
    }
    let text = crate::files::read_to_string(marker, crate::files::Cap::DOCUMENT)?;
    let d: Done = crate::engine::resume::unseal(marker, &text, "step marker")?;
    if d.seed != seed {
        return Err(Error::malformed(
            marker,
            format!(
                "made with seed {} and this reproduction has seed {seed}: use another folder (or \
                 seed {})",
                d.seed, d.seed
            ),
        ));
    }
    Ok((d.budget == budget && d.version == env!("CARGO_PKG_VERSION")).then_some(d))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_step_marker_of_another_seed_or_edited_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let marker = dir.path().join("done.json");
        assert!(finished_step(&marker, "quick", 2).unwrap().is_none());
        let done = Done {
            budget: "quick".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            seed: 1,
            seconds: 1.5,
            files: vec!["d-table/table.md".into()],
        };
        let sealed = crate::engine::resume::seal(&done).unwrap();
        std::fs::write(&marker, &sealed).unwrap();
        assert_eq!(finished_step(&marker, "quick", 1).unwrap().unwrap().seed, 1);
        assert!(finished_step(&marker, "paper", 1).unwrap().is_none());
        let e = finished_step(&marker, "quick", 2).unwrap_err().to_string();
        assert!(e.contains("seed 1") && e.contains("seed 2"), "{e}");
        // The seed edited without the digest, and the unsealed layout of earlier versions.
        std::fs::write(&marker, sealed.replace("\"seed\": 1", "\"seed\": 2")).unwrap();
        assert!(finished_step(&marker, "quick", 2).is_err());
        std::fs::write(&marker, serde_json::to_string(&done).unwrap()).unwrap();
        assert!(finished_step(&marker, "quick", 1).is_err());
    }
}
