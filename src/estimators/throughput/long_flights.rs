//! What a collision costs against the length of its flight (`lorentz bench --long-flights`): the
//! square lattice at several radii, or the triangular one at several gaps beyond w∞, its long
//! flights jumped ([`drive_jumps`]) and, beside them, walked cell by cell ([`drive`]), timed in
//! turns on one thread in one run, so that a drift of the machine's speed moves every scene
//! alike. Each scene and engine continues its own trajectory from an invariant-measure start from
//! one repetition to the next.
//!
//! A repetition times every scene once with jumps (and then walking, where asked), in an order
//! rotated by one scene per repetition; a scene's cost relative to the first is the median over
//! repetitions of the paired ratio of their times per collision.

use crate::engine::work::Work;
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
use crate::scenes::triangular::TriangularScene;

/// What a long-flight benchmark times.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LongFlightBenchConfig {
    /// Radii of the square scene, exact as typed (`"1/4"`), each where flights jump
    /// (2⁻³² ≤ r ≤ 1/4); the first is the reference of the ratios. 1 to 16 of them, or none
    /// with `gaps`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub radii: Vec<String>,
    /// Gaps w of the triangular scene instead, exact as typed, each where flights jump
    /// (w∞ < w ≤ 2²⁰ − 2); the first is the reference. 1 to 16 of them, or none with `radii`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub gaps: Vec<String>,
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
            gaps: Vec::new(),
            collisions: 1_000_000,
            walk_collisions: 10_000,
            repetitions: 7,
            seed: 1,
        }
    }

    /// The scenes, each checked.
    ///
    /// # Errors
    /// No radius or gap, or too many, or both radii and gaps; a value that is not an exact
    /// decimal or fraction, or one where flights do not jump; no collisions; repetitions out of
    /// range.
    pub fn scenes(&self) -> Result<BenchScenes, Error> {
        let values = if self.gaps.is_empty() {
            &self.radii
        } else {
            &self.gaps
        };
        if !self.radii.is_empty() && !self.gaps.is_empty() {
            return Err(Error::parameter(
                "long_flights",
                values.join(","),
                "radii (square) and gaps (triangular) at once; time one lattice per run",
            ));
        }
        if values.is_empty() || values.len() > MAX_RADII {
            return Err(Error::out_of_range(
                "long_flights",
                values.join(","),
                format!(
                    "give 1 to {MAX_RADII} radii or gaps ({} given)",
                    values.len()
                ),
            ));
        }
        if self.collisions == 0 {
            return Err(Error::Zero { what: "collisions" });
        }
        Error::unless_in("repetitions", self.repetitions, 1..=MAX_REPETITIONS, "")?;
        if self.gaps.is_empty() {
            let s = self.radii.iter().map(|t| jumping_square(t));
            Ok(BenchScenes::Square(s.collect::<Result<_, _>>()?))
        } else {
            let s = self.gaps.iter().map(|t| jumping_triangular(t));
            Ok(BenchScenes::Triangular(s.collect::<Result<_, _>>()?))
        }
    }

    /// The values as typed, radii or gaps.
    fn values(&self) -> &[String] {
        if self.gaps.is_empty() {
            &self.radii
        } else {
            &self.gaps
        }
    }
}

/// The scenes of one benchmark: one lattice.
#[derive(Debug, Clone)]
pub enum BenchScenes {
    /// The square lattice at its radii.
    Square(Vec<SquareScene>),
    /// The triangular lattice at its gaps.
    Triangular(Vec<TriangularScene>),
}

impl Default for LongFlightBenchConfig {
    fn default() -> Self {
        Self::new()
    }
}

/// The triangular scene of gap `text`, where its flights jump.
fn jumping_triangular(text: &str) -> Result<TriangularScene, Error> {
    let w: Rational = parse_exact(text).map_err(|e| e.named("long_flights"))?;
    let s = TriangularScene::exact(w)?;
    if s.long_flights().is_none() {
        return Err(Error::OutOfRange {
            parameter: "w",
            value: text.to_string(),
            range: "use w_inf = 4/sqrt(3) - 2 < w <= 2^20 - 2, where long flights jump".into(),
        });
    }
    Ok(s)
}

/// The square scene of radius `text`, where its flights jump.
fn jumping_square(text: &str) -> Result<SquareScene, Error> {
    let r: Rational = parse_exact(text).map_err(|e| e.named("long_flights"))?;
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

/// One scene's times.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LongFlightRow {
    /// The radius as typed (square lattice).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<String>,
    /// The gap as typed (triangular lattice).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub w: Option<String>,
    /// Santaló's mean free path: (1 − πr²)/(2r) in lattice spacings (square), in disk radii
    /// (triangular).
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
    /// One row per scene, in the configuration's order.
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
    options.accept("the bench of long flights", &[])?;
    if options.threads != 1 {
        return Err(Error::parameter(
            "threads",
            options.threads,
            "the bench of long flights times one thread; use 1",
        ));
    }
    let (jump, walk, mfp) = match cfg.scenes()? {
        BenchScenes::Square(s) => time_all(&s, cfg, options)?,
        BenchScenes::Triangular(s) => time_all(&s, cfg, options)?,
    };
    let square = cfg.gaps.is_empty();
    let rows = cfg
        .values()
        .iter()
        .enumerate()
        .map(|(k, text)| {
            let mut r = row(mfp[k], &jump[k], &jump[0], &walk[k], cfg);
            if square {
                r.radius = Some(text.clone());
            } else {
                r.w = Some(text.clone());
            }
            r
        })
        .collect();
    Ok(LongFlightBench {
        config: cfg.clone(),
        rows,
        meta: RunMeta::new(Some(cfg.seed), None, "f64", Some(1)),
    })
}

/// Each scene's nanoseconds per collision jumping and walking, per repetition, and its mean
/// free path.
type Timings = (Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<f64>);

/// Times every scene of `scenes` in turns, `cfg.repetitions` times.
fn time_all<S: Scene>(
    scenes: &[S],
    cfg: &LongFlightBenchConfig,
    options: &RunOptions,
) -> Result<Timings, Error> {
    // The walk crosses ⟨ℓ⟩/τ cells a collision: at a radius of 2⁻³² billions. Priced first.
    let reps = cfg.repetitions as f64;
    let parts = scenes.iter().flat_map(|s| {
        let lower = &["collisions", "walk_collisions", "repetitions"];
        [
            Work::new(
                "the bench of long flights",
                lower,
                reps * cfg.collisions as f64,
            ),
            Work::new(
                "the bench of long flights",
                lower,
                reps * cfg.walk_collisions as f64,
            )
            .walking(s),
        ]
    });
    let lower = &["walk_collisions", "collisions", "repetitions"];
    Work::sum("the bench of long flights", lower, parts).check(1)?;
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
    Ok((
        jump,
        walk,
        scenes.iter().map(|s| s.mean_free_path()).collect(),
    ))
}

/// A row without its scene's value (the caller names it).
fn row(
    mean_free_path: f64,
    jump: &[f64],
    first: &[f64],
    walk: &[f64],
    cfg: &LongFlightBenchConfig,
) -> LongFlightRow {
    let ratios =
        |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x / y).collect() };
    let walked = cfg.walk_collisions > 0;
    LongFlightRow {
        radius: None,
        w: None,
        mean_free_path,
        ns_per_collision: median(jump),
        samples: jump.to_vec(),
        over_first: median(&ratios(jump, first)),
        walk_ns_per_collision: walked.then(|| median(walk)),
        walk_samples: if walked { walk.to_vec() } else { Vec::new() },
        walk_over_jump: walked.then(|| median(&ratios(walk, jump))),
    }
}

/// One scene's lattice and its two trajectories (jumping and walking), each continued from
/// run to run.
struct Runner<S: Scene> {
    lat: Lattice<f64, S::Kernel<f64>>,
    flights: crate::scenes::long_flight::LongFlights,
    jumping: LatticeState<f64>,
    walking: LatticeState<f64>,
}

impl<S: Scene> Runner<S> {
    fn new(scene: &S, seed: u64, k: u64) -> Result<Self, Error> {
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
