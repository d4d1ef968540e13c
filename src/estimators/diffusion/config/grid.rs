//! Where the MSD is kept ([`MsdGrid`]): the fit windows' lags, the logarithmic multiple-τ grid,
//! or times the user gives (from t = 0 on), validated.

use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::observers::msd_times::MAX_TIMES;

/// A batch's trajectory must cover the MSD curve's longest time this many times.
pub const CURVE_WINDOWS: f64 = 100.0;

/// The most times per octave of a `log:FROM,TO,PER_OCTAVE` grid.
pub const MAX_PER_OCTAVE: u32 = 64;

/// The lags at which the MSD is kept: those of the fit windows only (what D is fitted from), or
/// those and a curve of the MSD, the velocity autocorrelation and its running Green–Kubo
/// integral at more times: the logarithmic grid from inside the first flight
/// ([`crate::observers::msd_curve`]), or the user's times from t = 0 on
/// ([`crate::observers::msd_times`]: with the autocorrelation per component). D has the same
/// bits on every grid.
///
/// As text (command line, Python, JSON): `fit`, `log`, `log:FROM,TO,PER_OCTAVE` (t = 0, then
/// FROM·2^(k/PER_OCTAVE) up to TO) or the times `T1,T2,…` (in JSON also an array of numbers).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(try_from = "GridText", into = "GridText")]
pub enum MsdGrid {
    /// The lags of the fit windows only.
    #[default]
    Fit,
    /// The fit windows' lags and the logarithmic grid of the MSD curve: ⟨ℓ⟩/8 … 7⟨ℓ⟩/8, then
    /// four per octave, up to a hundredth of a batch's trajectory.
    Log,
    /// t = 0, then `from`·2^(k/`per_octave`) for k = 0, 1, … up to `to` (times, not τ).
    LogFrom {
        /// The first time after 0.
        from: f64,
        /// The last time (at most).
        to: f64,
        /// Times per factor 2.
        per_octave: u32,
    },
    /// These times (from 0 on, increasing).
    Times(Vec<f64>),
}

/// The grid as JSON has it: its text, or an array of times.
#[derive(Serialize, Deserialize)]
#[serde(untagged)]
enum GridText {
    Text(String),
    Times(Vec<f64>),
}

impl TryFrom<GridText> for MsdGrid {
    type Error = Error;
    fn try_from(g: GridText) -> Result<Self, Error> {
        match g {
            GridText::Text(s) => s.parse(),
            GridText::Times(t) => checked_times(t).map(MsdGrid::Times),
        }
    }
}

impl From<MsdGrid> for GridText {
    fn from(g: MsdGrid) -> Self {
        match g {
            MsdGrid::Times(t) => GridText::Times(t),
            g => GridText::Text(g.to_string()),
        }
    }
}

/// The valid forms, for the errors.
const FORMS: &str = "use fit (the fit windows' lags), log (also a logarithmic grid from an \
     eighth of the mean free time on, four per octave), log:FROM,TO,PER_OCTAVE (t = 0, then \
     FROM*2^(k/PER_OCTAVE) up to TO; 0 < FROM < TO, 1 <= PER_OCTAVE <= 64) or the times \
     T1,T2,... (from 0 on, increasing, finite, at most 1000)";

fn bad(text: impl std::fmt::Display, why: &str) -> Error {
    Error::parameter("msd_grid", format!("{text}"), format!("{why}: {FORMS}"))
}

/// `times` if they are a grid: 1 to [`MAX_TIMES`] finite times ≥ 0, strictly increasing.
fn checked_times(times: Vec<f64>) -> Result<Vec<f64>, Error> {
    let text = || join(&times);
    if times.is_empty() || times.len() > MAX_TIMES {
        return Err(bad(text(), &format!("{} times", times.len())));
    }
    if let Some(t) = times.iter().find(|t| !(t.is_finite() && **t >= 0.0)) {
        return Err(bad(text(), &format!("the time {t} is not finite and >= 0")));
    }
    if let Some(p) = times.windows(2).find(|p| p[1] <= p[0]) {
        return Err(bad(
            text(),
            &format!("{} <= {} is not increasing", p[1], p[0]),
        ));
    }
    Ok(times)
}

fn join(times: &[f64]) -> String {
    times
        .iter()
        .map(|t| t.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

impl MsdGrid {
    /// True for the default, the fit grid (which a configuration's JSON leaves out).
    pub fn is_fit(&self) -> bool {
        *self == MsdGrid::Fit
    }

    /// The times of a grid of the user's (`log:…` or explicit), `None` for `fit` and `log`.
    pub fn times(&self) -> Option<Vec<f64>> {
        match *self {
            MsdGrid::Fit | MsdGrid::Log => None,
            MsdGrid::LogFrom {
                from,
                to,
                per_octave,
            } => {
                let mut t = vec![0.0];
                let mut k = 0;
                loop {
                    let x = from * 2f64.powf(f64::from(k) / f64::from(per_octave));
                    if x > to * (1.0 + 1e-12) || t.len() > MAX_TIMES {
                        break;
                    }
                    t.push(x.min(to));
                    k += 1;
                }
                Some(t)
            }
            MsdGrid::Times(ref t) => Some(t.clone()),
        }
    }

    /// Checks that the grid's longest time is at most a hundredth of a batch's trajectory
    /// (`collisions` in `batches` at mean free path `ell`).
    ///
    /// # Errors
    /// A longer time, naming the longest this run allows.
    pub fn check_reach(&self, ell: f64, collisions: u64, batches: u32) -> Result<(), Error> {
        let Some(times) = self.times() else {
            return Ok(());
        };
        let longest = times.last().copied().unwrap_or(0.0);
        let per_batch = collisions as f64 / f64::from(batches.max(1));
        let reach = per_batch * ell / CURVE_WINDOWS;
        if longest > reach {
            return Err(Error::out_of_range(
                "msd_grid",
                format!("{self} (longest time {longest})"),
                format!(
                    "times from 0 to {reach:.6} (a hundredth of a batch's trajectory: \
                     {per_batch:.0} collisions of mean free path {ell:.6}): use shorter times, \
                     or more collisions per batch"
                ),
            ));
        }
        Ok(())
    }
}

fn number(text: &str, s: &str) -> Result<f64, Error> {
    s.trim()
        .parse::<f64>()
        .map_err(|_| bad(text, &format!("{:?} is not a number", s.trim())))
}

impl FromStr for MsdGrid {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s.trim() {
            "fit" => return Ok(MsdGrid::Fit),
            "log" => return Ok(MsdGrid::Log),
            _ => {}
        }
        if let Some(rest) = s.trim().strip_prefix("log:") {
            let parts: Vec<&str> = rest.split(',').collect();
            let [a, b, n] = parts[..] else {
                return Err(bad(s, "log: takes three numbers"));
            };
            let (from, to) = (number(s, a)?, number(s, b)?);
            let per_octave: u32 = n
                .trim()
                .parse()
                .map_err(|_| bad(s, "PER_OCTAVE is not a whole number"))?;
            if !(from > 0.0 && to > from && to.is_finite()) {
                return Err(bad(s, "not 0 < FROM < TO"));
            }
            if !(1..=MAX_PER_OCTAVE).contains(&per_octave) {
                return Err(bad(s, "PER_OCTAVE out of range"));
            }
            let g = MsdGrid::LogFrom {
                from,
                to,
                per_octave,
            };
            if g.times().is_some_and(|t| t.len() > MAX_TIMES) {
                return Err(bad(s, "more than 1000 times"));
            }
            return Ok(g);
        }
        if !s.contains(',') && s.trim().parse::<f64>().is_err() {
            return Err(bad(s, "not a grid"));
        }
        let times = s
            .split(',')
            .map(|x| number(s, x))
            .collect::<Result<Vec<f64>, Error>>()?;
        checked_times(times).map(MsdGrid::Times)
    }
}

impl std::fmt::Display for MsdGrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MsdGrid::Fit => f.write_str("fit"),
            MsdGrid::Log => f.write_str("log"),
            MsdGrid::LogFrom {
                from,
                to,
                per_octave,
            } => write!(f, "log:{from},{to},{per_octave}"),
            MsdGrid::Times(t) => f.write_str(&join(t)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every form reads back from its text and its JSON; bad grids are refused naming the forms.
    #[test]
    fn grids_read_back_and_bad_ones_are_refused() {
        for text in ["fit", "log", "log:0.1,100,4", "0,0.5,1,2.25", "0"] {
            let g: MsdGrid = text.parse().unwrap();
            assert_eq!(g.to_string(), text);
            let json = serde_json::to_string(&g).unwrap();
            assert_eq!(serde_json::from_str::<MsdGrid>(&json).unwrap(), g);
        }
        let g: MsdGrid = serde_json::from_str("[0, 0.5, 1]").unwrap();
        assert_eq!(g.times().unwrap(), vec![0.0, 0.5, 1.0]);
        let log: MsdGrid = "log:1,8,2".parse().unwrap();
        let t = log.times().unwrap();
        assert_eq!(t.len(), 8);
        assert_eq!((t[0], t[1], t[3], t[7]), (0.0, 1.0, 2.0, 8.0));
        for text in [
            "0,1,1",
            "1,0.5",
            "-1,2",
            "0,inf",
            "nan",
            "",
            "log:0,1,4",
            "log:1,1,4",
            "log:1,2,0",
            "log:1,2,65",
            "log:1e-9,1e9,64",
            "lin",
            "0,x",
        ] {
            let e = text.parse::<MsdGrid>().unwrap_err().to_string();
            assert!(
                e.contains("msd_grid") && e.contains("log:FROM,TO,PER_OCTAVE"),
                "{e}"
            );
        }
        let many = (0..=MAX_TIMES).map(|k| k.to_string()).collect::<Vec<_>>();
        assert!(many.join(",").parse::<MsdGrid>().is_err());
        assert!(serde_json::from_str::<MsdGrid>("[1, 0]").is_err());
    }

    /// The longest time must be at most a hundredth of a batch's trajectory.
    #[test]
    fn the_longest_time_is_bounded_by_the_run() {
        let g: MsdGrid = "0,1,10".parse().unwrap();
        assert!(g.check_reach(1.0, 2000, 2).is_ok());
        let e = g.check_reach(1.0, 1999, 2).unwrap_err().to_string();
        assert!(e.contains("from 0 to 9.995"), "{e}");
        assert!(MsdGrid::Log.check_reach(1.0, 1, 2).is_ok());
    }
}
