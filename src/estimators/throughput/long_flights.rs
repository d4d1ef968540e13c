//! What a collision costs against the length of its flight (`lorentz bench --long-flights`): the
//! square lattice at several radii, its long flights jumped ([`drive_jumps`]) and, beside them,
//! walked cell by cell ([`drive`]), timed in turns on one thread in one run, so that a drift of
//! the machine's speed moves every radius alike. Each radius and engine continues its own
//! trajectory from an invariant-measure start from one repetition to the next.
//!
//! A repetition times every radius once with jumps (and then walking, where asked), in an order
//! rotated by one radius per repetition; a radius's cost relative to the first is the median over
//! repetitions of the paired ratio of their times per collision.

use std::time::Instant;

use rug::Rational;
use serde::{Deserialize, Serialize};

use super::{MAX_REPETITIONS, median};
use crate::Error;
use crate::engine::drive;
use crate::engine::long_flight::drive_jumps;
use crate::engine::metadata::RunMeta;
use crate::engine::observe::Nothing;
use crate::engine::options::RunOptions;
use crate::numbers::exact::parse_exact;
use crate::scenes::Scene;
use crate::scenes::lattice::{Lattice, LatticeState};
use crate::scenes::sampling::stream;
use crate::scenes::square::SquareScene;

/// What a long-flight benchmark times.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LongFlightBenchConfig {
    /// Radii of the square scene, exact as typed (`"1/4"`), each where flights jump
    /// (2⁻³² ≤ r ≤ 1/4); the first is the reference of the ratios. 1 to 16 of them.
    pub radii: Vec<String>,
    /// Collisions of each timed run with jumps.
    pub collisions: u64,
    /// Collisions of each timed run walking cell by cell (0: the walk is not timed). A walked
    /// collision at r crosses about 1/(2r) cells, so this is usually far below `collisions`.
    pub walk_collisions: u64,
    /// Repetitions, 1 to [`MAX_REPETITIONS`].
    pub repetitions: usize,
    /// Seed of the invariant-measure starts.
    pub seed: u64,
}

/// The most radii one benchmark takes.
pub const MAX_RADII: usize = 16;

impl LongFlightBenchConfig {
    /// The command line's defaults: r = 1/4, 1/1000 and 1/10000, 10⁶ collisions jumping and 10⁴
    /// walking per run, 7 repetitions, seed 1.
    pub fn new() -> Self {
        LongFlightBenchConfig {
            radii: ["1/4", "1/1000", "1/10000"].map(String::from).to_vec(),
            collisions: 1_000_000,
            walk_collisions: 10_000,
            repetitions: 7,
            seed: 1,
        }
    }

    /// The scenes, each checked.
    ///
    /// # Errors
    /// No radius or too many, a radius that is not an exact decimal or fraction, or one where
    /// flights do not jump; no collisions; repetitions out of range.
    pub fn scenes(&self) -> Result<Vec<SquareScene>, Error> {
        if self.radii.is_empty() || self.radii.len() > MAX_RADII {
            return Err(Error::Invalid(format!(
                "long_flights: {} radii; give 1 to {MAX_RADII}",
                self.radii.len()
            )));
        }
        if self.collisions == 0 {
            return Err(Error::Zero { what: "collisions" });
        }
        if !(1..=MAX_REPETITIONS).contains(&self.repetitions) {
            return Err(Error::Invalid(format!(
                "repetitions = {}: use 1 to {MAX_REPETITIONS}",
                self.repetitions
            )));
        }
        self.radii.iter().map(|t| jumping_scene(t)).collect()
    }
}

impl Default for LongFlightBenchConfig {
    fn default() -> Self {
        Self::new()
    }
}

/// The square scene of radius `text`, where its flights jump.
fn jumping_scene(text: &str) -> Result<SquareScene, Error> {
    let r: Rational =
        parse_exact(text).map_err(|e| Error::Invalid(format!("radius = {text}: {e}")))?;
    let s = SquareScene::exact(r)?;
    if s.long_flight_radius().is_none() {
        return Err(Error::OutOfRange {
            parameter: "radius",
            value: text.to_string(),
            range: "use 2^-32 <= radius <= 1/4, where long flights jump".into(),
        });
    }
    Ok(s)
}

/// One radius's times.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LongFlightRow {
    /// The radius as typed.
    pub radius: String,
    /// Santaló's mean free path (1 − πr²)/(2r).
    pub mean_free_path: f64,
    /// Median nanoseconds per collision with jumps.
    pub ns_per_collision: f64,
    /// Each repetition's nanoseconds per collision with jumps.
    pub samples: Vec<f64>,
    /// Median over repetitions of this radius's time per collision over the first radius's.
    pub over_first: f64,
    /// Median nanoseconds per collision walking (absent where the walk was not timed).
    pub walk_ns_per_collision: Option<f64>,
    /// Each repetition's nanoseconds per collision walking.
    pub walk_samples: Vec<f64>,
    /// Median over repetitions of the walk's time per collision over the jumps'.
    pub walk_over_jump: Option<f64>,
}

/// The result of [`run`] (`lorentz bench --long-flights --json`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LongFlightBench {
    /// What was timed.
    pub config: LongFlightBenchConfig,
    /// One row per radius, in the configuration's order.
    pub rows: Vec<LongFlightRow>,
    /// Version, seed, engine, threads (1), command line.
    pub meta: RunMeta,
}

/// Times `cfg` on the calling thread. Of the options only `progress` (one unit per repetition)
/// and `stop` apply, and `threads` must be 1.
///
/// # Errors
/// An invalid configuration, other options, or a run stopped on request.
pub fn run(cfg: &LongFlightBenchConfig, options: &RunOptions) -> Result<LongFlightBench, Error> {
    options.validate()?;
    options.refuse_unused("bench --long-flights", &[])?;
    if options.threads != 1 {
        return Err(Error::Invalid(format!(
            "threads = {}: bench --long-flights times one thread; use 1",
            options.threads
        )));
    }
    let scenes = cfg.scenes()?;
    let mut runs = scenes
        .iter()
        .enumerate()
        .map(|(k, s)| Runner::new(s, cfg.seed, k as u64))
        .collect::<Result<Vec<_>, Error>>()?;
    let n = runs.len();
    let mut jump = vec![vec![0.0; cfg.repetitions]; n];
    let mut walk = vec![vec![0.0; cfg.repetitions]; n];
    for rep in 0..cfg.repetitions {
        for i in 0..n {
            let k = (i + rep) % n;
            if let Some(stop) = &options.stop {
                stop.check()?;
            }
            jump[k][rep] = runs[k].time(cfg.collisions, true)?;
            if cfg.walk_collisions > 0 {
                walk[k][rep] = runs[k].time(cfg.walk_collisions, false)?;
            }
        }
        (options.progress)(1);
    }
    let rows = scenes
        .iter()
        .zip(&cfg.radii)
        .enumerate()
        .map(|(k, (s, text))| row(text, s, &jump[k], &jump[0], &walk[k], cfg))
        .collect();
    Ok(LongFlightBench {
        config: cfg.clone(),
        rows,
        meta: RunMeta::new(Some(cfg.seed), None, "f64", Some(1)),
    })
}

fn row(
    text: &str,
    s: &SquareScene,
    jump: &[f64],
    first: &[f64],
    walk: &[f64],
    cfg: &LongFlightBenchConfig,
) -> LongFlightRow {
    let ratios =
        |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x / y).collect() };
    let walked = cfg.walk_collisions > 0;
    LongFlightRow {
        radius: text.to_string(),
        mean_free_path: s.mean_free_path(),
        ns_per_collision: median(jump),
        samples: jump.to_vec(),
        over_first: median(&ratios(jump, first)),
        walk_ns_per_collision: walked.then(|| median(walk)),
        walk_samples: if walked { walk.to_vec() } else { Vec::new() },
        walk_over_jump: walked.then(|| median(&ratios(walk, jump))),
    }
}

/// One radius's lattice and its two trajectories (jumping and walking), each continued from
/// run to run.
struct Runner {
    lat: Lattice<f64, <SquareScene as Scene>::Kernel<f64>>,
    flights: crate::scenes::long_flight::LongFlights,
    jumping: LatticeState<f64>,
    walking: LatticeState<f64>,
}

impl Runner {
    fn new(scene: &SquareScene, seed: u64, k: u64) -> Result<Self, Error> {
        let start = scene.sample(&mut stream(seed, k));
        Ok(Runner {
            lat: scene.lattice::<f64>(())?,
            flights: scene.long_flights().expect("checked where flights jump"),
            jumping: start.clone(),
            walking: start,
        })
    }

    /// Nanoseconds per collision of `collisions` more, jumping or walking.
    fn time(&mut self, collisions: u64, jumps: bool) -> Result<f64, Error> {
        let t = Instant::now();
        if jumps {
            drive_jumps(
                &self.lat,
                &self.flights,
                &mut self.jumping,
                collisions,
                &mut Nothing,
                &|_| {},
            )?;
        } else {
            drive(
                &self.lat,
                &mut self.walking,
                collisions,
                &mut Nothing,
                &|_| {},
            )?;
        }
        Ok(t.elapsed().as_secs_f64() * 1e9 / collisions as f64)
    }
}
