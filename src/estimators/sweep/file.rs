//! A sweep's configuration file, the one description that the parts of a Slurm job array read
//! (`lorentz sweep --config FILE`), so that every part runs exactly the validated sweep — over w
//! without a field, or in a field over B or over w on any table, a table given as data included.
//!
//! A configuration file is untrusted input: JSON of at most [`MAX_CONFIG_BYTES`], with only the
//! keys of a sweep, validated as the command line validates its flags.

use std::path::Path;

use serde_json::Value;

use super::{Grid, SweepConfig};
use crate::Error;

/// The largest configuration file read: a sweep's parameters and at most a table of disks.
pub const MAX_CONFIG_BYTES: u64 = crate::files::Cap::CONFIG.bytes;

impl SweepConfig {
    /// Its trajectories: runs × batches over all points, for a result's metadata.
    pub fn trajectories(&self) -> u64 {
        u64::from(self.steps()) * u64::from(self.runs()) * u64::from(self.batches)
    }

    /// One line saying what it computes (for a batch script's comment).
    pub fn describe(&self) -> String {
        match &self.grid {
            Grid::Gaps(g) => format!(
                "the sweep w = {} .. {} ({} points x {} runs x {} collisions per run)",
                g.w_from, g.w_to, g.steps, g.runs, self.collisions
            ),
            Grid::InField(f) => format!(
                "the sweep in a field over {} (fields {}; {} points x {} collisions)",
                f.place(),
                f.fields.join(", "),
                self.steps(),
                self.collisions
            ),
            Grid::Driven(d) => format!(
                "the driven sweep at w = {} (fields E {} at {} degrees; {} points x {} collisions)",
                d.gaps.join(", "),
                d.electric.join(", "),
                d.electric_angle,
                self.steps(),
                self.collisions
            ),
        }
    }

    /// The configuration file's text (pretty JSON; [`Self::read`] reads it back).
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
    /// An unreadable or oversized file, JSON that is not a sweep's configuration, or an invalid
    /// parameter.
    pub fn read(path: &Path) -> Result<Self, Error> {
        let text = crate::files::read_to_string(path, crate::files::Cap::CONFIG)?;
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
        let sweep: SweepConfig = serde_json::from_value(value.clone()).map_err(|e| {
            format!("{e}: a sweep over w has w_from, w_to, steps and runs, one in a field gaps (or radius or table), fields and localization_samples, a driven one gaps, electric and electric_angle")
        })?;
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

#[cfg(test)]
mod tests {
    use super::*;

    fn field_sweep() -> SweepConfig {
        SweepConfig {
            grid: Grid::InField(crate::estimators::sweep::field::FieldGrid {
                gaps: vec!["1/10".into()],
                radius: None,
                fields: vec!["-1".into(), "1".into()],
                localization_samples: 1000,
                table: None,
            }),
            collisions: 100_000,
            batches: 4,
            seed: 9,
        }
    }

    #[test]
    fn a_configuration_reads_back_as_the_same_sweep_and_an_unknown_key_is_refused() {
        let s = field_sweep();
        let v: Value = serde_json::from_str(&s.to_json().unwrap()).unwrap();
        assert_eq!(SweepConfig::from_value(&v).unwrap(), s);
        let mut typo = v.clone();
        typo.as_object_mut()
            .unwrap()
            .insert("feilds".into(), Value::from(1));
        let e = SweepConfig::from_value(&typo).unwrap_err();
        assert!(e.contains("unknown key `feilds`"), "{e}");
        assert!(SweepConfig::from_value(&Value::from(3)).is_err());
        let over_w = SweepConfig {
            grid: Grid::Gaps(crate::estimators::sweep::GapGrid {
                w_from: "0.2".into(),
                w_to: "0.3".into(),
                steps: 3,
                runs: 2,
            }),
            collisions: 1000,
            batches: 2,
            seed: 1,
        };
        let v = serde_json::to_value(&over_w).unwrap();
        assert_eq!(SweepConfig::from_value(&v).unwrap(), over_w);
        assert_eq!((over_w.steps(), s.steps()), (3, 2));
    }
}
