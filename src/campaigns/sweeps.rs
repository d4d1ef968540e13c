//! Every sweep a campaign deals into parts — over w without a field ([`SweepConfig`]), or in a
//! field over B or over w on any table ([`FieldSweepConfig`]) — and its configuration file, the
//! one description that the parts of a Slurm job array read (`lorentz sweep --config FILE`), so
//! that every part runs exactly the validated sweep, a table given as data included.
//!
//! A configuration file is untrusted input: JSON of at most [`MAX_CONFIG_BYTES`], with only the
//! keys of one of the two configurations, validated as the command line validates its flags.

use std::path::Path;

use serde::Serialize;
use serde_json::Value;

use crate::Error;
use crate::estimators::field::sweep::FieldSweepConfig;
use crate::estimators::sweep::SweepConfig;

/// A sweep, without a field or in one.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Sweep {
    /// D(w) over a range of gaps of the triangular scene, without a field.
    OverW(SweepConfig),
    /// The diffusion tensor in a field: over the fields at one scene, or over w at one field.
    InField(FieldSweepConfig),
}

/// The largest configuration file read: a sweep's parameters and at most a table of disks.
pub const MAX_CONFIG_BYTES: u64 = 1 << 20;

impl Sweep {
    /// Checks every parameter, as the sweep itself does before it runs.
    ///
    /// # Errors
    /// What [`SweepConfig::validate`] or [`FieldSweepConfig::validate`] refuses.
    pub fn validate(&self) -> Result<(), Error> {
        match self {
            Sweep::OverW(c) => c.validate(),
            Sweep::InField(c) => c.validate(),
        }
    }

    /// Its points (each belongs to one part).
    pub fn points(&self) -> u32 {
        match self {
            Sweep::OverW(c) => c.steps,
            Sweep::InField(c) => c.grid().len() as u32,
        }
    }

    /// Its seed.
    pub fn seed(&self) -> u64 {
        match self {
            Sweep::OverW(c) => c.seed,
            Sweep::InField(c) => c.seed,
        }
    }

    /// Its trajectories: runs × batches over all points, for a result's metadata.
    pub fn batches(&self) -> u64 {
        match self {
            Sweep::OverW(c) => c.runs as u64 * c.batches as u64,
            Sweep::InField(c) => c.batches as u64 * u64::from(self.points()),
        }
    }

    /// One line saying what it computes (for a batch script's comment).
    pub fn describe(&self) -> String {
        match self {
            Sweep::OverW(c) => format!(
                "the sweep w = {} .. {} ({} points x {} runs x {} collisions per run)",
                c.w_from, c.w_to, c.steps, c.runs, c.collisions
            ),
            Sweep::InField(c) => format!(
                "the sweep in a field over {} (fields {}; {} points x {} collisions)",
                scene_of(c),
                c.fields.join(", "),
                self.points(),
                c.collisions
            ),
        }
    }

    /// The configuration file's text (pretty JSON; [`Sweep::read`] reads it back).
    ///
    /// # Errors
    /// None in practice: a configuration is plain data.
    pub fn to_json(&self) -> Result<String, Error> {
        serde_json::to_string_pretty(self).map_err(Error::encode)
    }

    /// The sweep of the configuration file `path`, validated: a field sweep has `fields`, a sweep
    /// over w `w_from`; a key of neither is refused, naming it.
    ///
    /// # Errors
    /// An unreadable or oversized file, JSON that is not one of the two configurations, or an
    /// invalid parameter.
    pub fn read(path: &Path) -> Result<Self, Error> {
        let text = crate::files::read_to_string_limited(path, MAX_CONFIG_BYTES)?;
        let value: Value = serde_json::from_str(&text).map_err(|e| Error::malformed(path, e))?;
        let sweep = Self::from_value(&value).map_err(|e| Error::malformed(path, e))?;
        sweep.validate()?;
        Ok(sweep)
    }

    /// The sweep `value` describes, every key known.
    fn from_value(value: &Value) -> Result<Self, String> {
        let Some(given) = value.as_object() else {
            return Err("not a JSON object: a sweep's configuration is one".into());
        };
        let sweep = if given.contains_key("fields") {
            Sweep::InField(serde_json::from_value(value.clone()).map_err(|e| e.to_string())?)
        } else {
            Sweep::OverW(serde_json::from_value(value.clone()).map_err(|e| e.to_string())?)
        };
        let known = serde_json::to_value(&sweep).map_err(|e| e.to_string())?;
        let known = known.as_object().map(|o| o.keys().collect::<Vec<_>>());
        let optional = ["radius", "table"];
        if let Some(k) = given.keys().find(|k| {
            !known.as_ref().is_some_and(|n| n.contains(k)) && !optional.contains(&k.as_str())
        }) {
            return Err(format!("unknown key `{k}` (not a parameter of this sweep)"));
        }
        Ok(sweep)
    }
}

/// The scene of a field sweep, in words.
fn scene_of(c: &FieldSweepConfig) -> String {
    match (&c.table, &c.radius) {
        (Some(t), _) => format!("the table {}", t.title()),
        (None, Some(r)) => format!("the square lattice at radius {r}"),
        (None, None) => format!("the triangular lattice at w = {}", c.gaps.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field_sweep() -> Sweep {
        Sweep::InField(FieldSweepConfig {
            gaps: vec!["1/10".into()],
            radius: None,
            fields: vec!["-1".into(), "1".into()],
            collisions: 100_000,
            batches: 4,
            seed: 9,
            localization_samples: 1000,
            table: None,
        })
    }

    #[test]
    fn a_configuration_reads_back_as_the_same_sweep_and_an_unknown_key_is_refused() {
        let s = field_sweep();
        let v: Value = serde_json::from_str(&s.to_json().unwrap()).unwrap();
        assert_eq!(Sweep::from_value(&v).unwrap(), s);
        let mut typo = v.clone();
        typo.as_object_mut()
            .unwrap()
            .insert("feilds".into(), Value::from(1));
        let e = Sweep::from_value(&typo).unwrap_err();
        assert!(e.contains("unknown key `feilds`"), "{e}");
        assert!(Sweep::from_value(&Value::from(3)).is_err());
        let over_w = Sweep::OverW(SweepConfig {
            w_from: "0.2".into(),
            w_to: "0.3".into(),
            steps: 3,
            runs: 2,
            collisions: 1000,
            batches: 2,
            seed: 1,
        });
        let v = serde_json::to_value(&over_w).unwrap();
        assert_eq!(Sweep::from_value(&v).unwrap(), over_w);
        assert_eq!((over_w.points(), s.points()), (3, 2));
    }
}
