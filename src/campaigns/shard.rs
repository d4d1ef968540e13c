//! One part of a sweep too large for one machine — any sweep: over w, or in a field on any table:
//! point i belongs to part i mod N, so a Slurm job array of N tasks (or N calls in a process pool)
//! runs the whole sweep, and [`super::merge`] combines the parts into the bits of the sweep in one
//! piece.

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::{RunOption, RunOptions};
use crate::engine::resume::seal;
use crate::estimators::sweep::stored::{self, SealedPoint};
use crate::estimators::sweep::{MAX_SWEEP_POINTS, SweepConfig};
use crate::numbers::precision::Precision;

/// Part `index` of `count` of a sweep's points: point i belongs to part i mod `count` (parts
/// 0 … count − 1, as Slurm numbers the tasks of `--array=0-(count−1)`). Round-robin, so every
/// part spans the whole w range and the parts take about equal time (the cost per collision
/// varies with w). A part's points are the same bits as those points of the whole sweep: a point
/// depends only on the configuration and its index.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which part, 0 … count − 1.
    pub index: u32,
    /// Into how many parts the points are dealt.
    pub count: u32,
}

impl Shard {
    /// Parses `I/N` (0 ≤ I < N), as in `--shard 3/8`.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::campaigns::shard::Shard;
    /// let s = Shard::parse("1/4").unwrap();
    /// assert_eq!((s.index, s.count), (1, 4));
    /// assert!(s.owns(5) && !s.owns(4));
    /// assert!(Shard::parse("4/4").is_err());
    /// ```
    pub fn parse(text: &str) -> Result<Shard, Error> {
        let bad = || {
            Error::parameter(
                "shard",
                format!("{text:?}"),
                format!(
                    "expected I/N with N from 1 to {MAX_SWEEP_POINTS} and I from 0 to N-1 (under \
                     Slurm, I is the array task id of an array 0 to N-1)"
                ),
            )
        };
        let (i, n) = text.trim().split_once('/').ok_or_else(bad)?;
        let index: u32 = i.trim().parse().map_err(|_| bad())?;
        let count: u32 = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || count > MAX_SWEEP_POINTS || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// Whether point `i` belongs to this part.
    pub fn owns(&self, i: u32) -> bool {
        i % self.count == self.index
    }

    /// Checks that every part of `cfg`'s points gets at least one point.
    pub fn validate(&self, cfg: &SweepConfig) -> Result<(), Error> {
        self.fits(cfg.steps() as usize)
    }

    /// Checks that every part of a sweep of `points` points gets at least one point.
    pub fn fits(&self, points: usize) -> Result<(), Error> {
        if self.count as usize > points || self.index >= self.count {
            return Err(Error::out_of_range(
                "shard",
                self,
                format!(
                    "a sweep of {points} points has parts 0 to N-1 with N from 1 to {points} \
                     (every part needs a point)"
                ),
            ));
        }
        Ok(())
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// What one part of a sharded sweep leaves in its directory, beside its points (`shard.json`
/// over w, `field-shard.json` in a field: [`SweepConfig::part_manifest`]): the part's identity
/// for [`super::merge::run`]. Without a directory (a part computed for a process pool), the
/// part carries its points itself (`sealed_points`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SweepPart {
    /// The whole sweep's configuration.
    pub config: SweepConfig,
    /// Which part.
    pub shard: Shard,
    /// Indices of the part's points, all finished.
    pub points: Vec<u32>,
    /// Of them, reused from an earlier, interrupted run of the part.
    pub resumed_points: u32,
    /// Version, seed, engine, threads, command line of this part's process.
    pub meta: RunMeta,
    /// The part's points as their files would hold them, when the part has no directory.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sealed_points: Vec<SealedPoint>,
}

/// One part of a sweep: the whole sweep's configuration and which part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardConfig {
    /// The whole sweep.
    pub sweep: SweepConfig,
    /// The part to run.
    pub shard: Shard,
}

impl ShardConfig {
    /// Checks the sweep and that the part has points.
    pub fn validate(&self) -> Result<(), Error> {
        self.sweep.validate()?;
        self.shard.validate(&self.sweep)
    }
}

/// Runs part `cfg.shard` of the sweep `cfg.sweep`, over w or in a field: its points only
/// (resumable, as the whole sweep), written to `DIR/points/` (in a field `DIR/field-points/`)
/// with the part's manifest, where DIR is `options.resume`; without a directory the part carries
/// its points ([`SweepPart::sealed_points`]). The analysis waits for [`super::merge`].
/// `options.progress` receives collision counts.
///
/// # Errors
/// An invalid configuration or options, a directory of another sweep, or an I/O error.
pub fn run(cfg: &ShardConfig, options: &RunOptions) -> Result<SweepPart, Error> {
    cfg.validate()?;
    options.accept(
        "sweep part",
        &[
            RunOption::Engine,
            RunOption::Resume,
            RunOption::CheckpointEvery,
        ],
    )?;
    let (sweep, shard) = (&cfg.sweep, cfg.shard);
    let resolved = options.engine.resolve(true)?;
    let (points, resumed) = stored::run_points(sweep, options, &|i| shard.owns(i))?;
    let mut part = SweepPart {
        config: sweep.clone(),
        shard,
        points: points.iter().map(|p| p.index).collect(),
        resumed_points: resumed,
        meta: RunMeta::new(
            Some(sweep.seed),
            Some(sweep.runs() as u64 * sweep.batches as u64),
            Precision::F64,
            Some(options.threads),
        )
        .with_engine(resolved),
        sealed_points: Vec::new(),
    };
    match options.resume.as_deref() {
        Some(dir) => {
            let manifest = dir.join(sweep.part_manifest());
            crate::files::write(manifest, seal(&part)?.as_bytes())?;
        }
        None => part.sealed_points = points,
    }
    Ok(part)
}
