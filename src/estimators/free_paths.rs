//! The free path between collisions against its Boltzmann–Grad limit law: `lorentz free-paths`.
//!
//! Each batch is one trajectory from the flow's invariant measure (stream (seed, b)) on the
//! scalar `f64` kernel, jumping long flights where the scene supplies them. The
//! [`FreePaths`] observer histograms ξ = τ/⟨ℓ⟩ for every complete collision-to-collision flight
//! (Santaló's ⟨ℓ⟩, so ⟨ξ⟩ = 1 exactly at every radius). Each bin's probability, ⟨ξ⟩ and
//! ⟨ln ξ⟩ are means over batches with their batch standard errors; the bins are compared with
//! the limit law of r → 0 ([`crate::theory::free_paths`]), the mean with its exact value 1.
//! The limit law holds for every lattice; at a finite radius the differences are physics, not
//! errors, and the report says which bins differ rather than failing.

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::drive;
use crate::engine::long_flight::{Flights, drive_jumps};
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::parallel::{STOP_EVERY, check_batches, in_legs, par_batches_watched, share};
use crate::engine::work::{Work, crossings_per_collision};
use crate::observers::free_paths::{FreePathCounts, FreePaths};
use crate::scenes::Scene;
use crate::scenes::sampling::stream;
use crate::scenes::spec::{SceneChoice, SceneSpec};
use crate::statistics::comparison::{self, Comparison, batch_dof, largest_of_bound};
use crate::statistics::mean_se;
use crate::theory::free_paths as law;

/// The histogram's edges in ξ = τ/⟨ℓ⟩: quarters up to 2 (the limit density has kinks at 1 and
/// 2), then wider bins into the tail, the last open.
pub const EDGES: [f64; 15] = [
    0.0,
    0.25,
    0.5,
    0.75,
    1.0,
    1.25,
    1.5,
    1.75,
    2.0,
    2.5,
    3.0,
    4.0,
    6.0,
    10.0,
    f64::INFINITY,
];

/// Fewest complete flights a batch must have.
pub const MIN_FLIGHTS_PER_BATCH: u64 = 1000;

/// The most edges of the user's bins.
pub const MAX_EDGES: usize = 1001;

/// The most free-path samples a result keeps.
pub const MAX_KEPT_SAMPLES: u64 = 1_000_000;

/// The edges of the user's bins read from text such as `0,0.5,1,2,4` (see [`check_edges`]).
///
/// # Errors
/// A word that is not a number, or edges [`check_edges`] refuses.
pub fn parse_edges(text: &str) -> Result<Vec<f64>, Error> {
    let edges = text
        .split(',')
        .map(|x| {
            x.trim()
                .parse::<f64>()
                .map_err(|_| Error::parameter("bins", format!("{text:?}"), EDGES_RANGE))
        })
        .collect::<Result<Vec<f64>, Error>>()?;
    check_edges(&edges)?;
    Ok(edges)
}

const EDGES_RANGE: &str = "use the bin edges in xi = tau/<l> as E0,E1,...: 2 to 1001 finite numbers \
     >= 0, increasing (flights outside [E0, last) fall in no bin)";

/// Checks the user's bin edges: 2 to [`MAX_EDGES`] finite numbers ≥ 0, strictly increasing.
///
/// # Errors
/// Edges that are not such.
pub fn check_edges(edges: &[f64]) -> Result<(), Error> {
    let ok = (2..=MAX_EDGES).contains(&edges.len())
        && edges.iter().all(|e| e.is_finite() && *e >= 0.0)
        && edges.windows(2).all(|p| p[0] < p[1]);
    if ok {
        return Ok(());
    }
    let text = edges
        .iter()
        .map(|e| e.to_string())
        .collect::<Vec<_>>()
        .join(",");
    Err(Error::parameter("bins", text, EDGES_RANGE))
}

/// What a free-path measurement runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FreePathConfig {
    /// The lattice.
    pub scene: SceneSpec,
    /// Collisions in all, shared between the batches (each batch's first, partial flight is not
    /// counted).
    pub collisions: u64,
    /// Independent batches (one trajectory each), at least 2: the errors are over them.
    pub batches: u32,
    /// Seed: batch b starts from stream (seed, b).
    pub seed: u64,
    /// How flights cross the lattice ([`Flights`]): `auto` jumps long flights where the scene
    /// supplies them and they are faster.
    #[serde(default)]
    pub flights: Flights,
    /// The histogram's bin edges in ξ (see [`check_edges`]); `None` for [`EDGES`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bins: Option<Vec<f64>>,
    /// Keep the ξ of this many flights (0 to [`MAX_KEPT_SAMPLES`], at most the complete
    /// flights), spread evenly over each batch's trajectory (`free_path_samples`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub keep_samples: u64,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

impl FreePathConfig {
    /// The command line's defaults on `scene`: 1.6·10⁷ collisions in 16 batches, seed 1.
    pub fn new(scene: SceneSpec) -> Self {
        FreePathConfig {
            scene,
            collisions: 16_000_000,
            batches: 16,
            seed: 1,
            flights: Flights::Auto,
            bins: None,
            keep_samples: 0,
        }
    }

    /// The histogram's edges: the user's, or [`EDGES`].
    pub fn edges(&self) -> &[f64] {
        self.bins.as_deref().unwrap_or(&EDGES)
    }

    /// Checks the counts.
    ///
    /// # Errors
    /// Fewer than 2 batches, too many, fewer than [`MIN_FLIGHTS_PER_BATCH`] collisions per batch,
    /// or more than [`crate::engine::MAX_COLLISIONS_PER_TRAJECTORY`] in one.
    pub fn validate(&self) -> Result<(), Error> {
        check_batches("batches", self.batches)?;
        // A batch is one trajectory: a count near 2^64 would wrap around its cell index.
        crate::engine::check_trajectory_length(
            share(self.collisions, self.batches.max(1), 0),
            "batches",
            self.batches,
        )?;
        if self.batches < 2 {
            return Err(Error::TooFew {
                what: "batches",
                min: 2,
                got: self.batches as u64,
            });
        }
        let min = (MIN_FLIGHTS_PER_BATCH + 1) * self.batches as u64;
        if self.collisions < min {
            return Err(Error::TooFew {
                what: "collisions (1001 per batch)",
                min,
                got: self.collisions,
            });
        }
        if let Some(e) = &self.bins {
            check_edges(e)?;
        }
        let flights = self.collisions - self.batches as u64;
        if self.keep_samples > MAX_KEPT_SAMPLES.min(flights) {
            return Err(Error::out_of_range(
                "keep_samples",
                self.keep_samples,
                format!(
                    "use 0 to {} (at most 1e6, and at most the complete flights)",
                    MAX_KEPT_SAMPLES.min(flights)
                ),
            ));
        }
        Ok(())
    }
}

/// One bin of the histogram against the limit law.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FreePathBin {
    /// Lower edge in ξ = τ/⟨ℓ⟩.
    pub lo: f64,
    /// Upper edge (`null` in JSON for the open last bin).
    pub hi: Option<f64>,
    /// The measured probability of lo ≤ ξ < hi (mean over batches).
    pub probability: f64,
    /// Its standard error.
    pub probability_err: f64,
    /// The Boltzmann–Grad limit law's probability of the bin.
    pub limit: f64,
    /// (probability − limit)/probability_err; `None` (JSON `null`) where the batches do not
    /// spread (an error of 0: every batch saw the same share, as when none saw a flight there).
    pub z: Option<f64>,
}

/// The free paths of a scene against the limit law.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FreePathReport {
    /// The scene ([`Scene::label`]).
    pub scene: String,
    /// Santaló's mean free path ⟨ℓ⟩, the unit of ξ.
    pub mean_free_path: f64,
    /// Complete flights counted, over all batches.
    pub samples: u64,
    /// Collisions in all.
    pub collisions: u64,
    /// Independent batches.
    pub batches: u32,
    /// How the flights crossed the lattice: `walk` or `jump`.
    pub flights: Flights,
    /// ⟨ξ⟩ (exactly 1 by Santaló's formula).
    pub mean: f64,
    /// Its standard error.
    pub mean_err: f64,
    /// ⟨ξ⟩ − 1 with its error and agreement bound.
    pub mean_check: Comparison,
    /// ⟨ln ξ⟩.
    pub ln_mean: f64,
    /// Its standard error.
    pub ln_mean_err: f64,
    /// The limit law's ⟨ln ξ⟩ = 27ζ(3)/(2π²) − 3 ln 2.
    pub ln_mean_limit: f64,
    /// The longest ξ seen.
    pub longest: f64,
    /// The histogram against the limit law (on the configuration's `bins`, or [`EDGES`]).
    pub bins: Vec<FreePathBin>,
    /// The ξ of the flights kept (`keep_samples`): in batch order, each batch's every k-th
    /// complete flight from its first.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub free_path_samples: Vec<f64>,
    /// The largest |z| over the bins that have one.
    pub max_z: f64,
    /// Its bound for a run that follows the limit law (Bonferroni over the bins, Student-t).
    pub max_z_bound: f64,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// Measures the free paths of `cfg.scene`. Of the options, `threads`, `progress` (collisions)
/// and `stop` apply.
///
/// # Errors
/// An invalid configuration or options, jumps asked for where the scene has none, or a run
/// stopped on request.
pub fn run(cfg: &FreePathConfig, options: &RunOptions) -> Result<FreePathReport, Error> {
    cfg.validate()?;
    options.accept("free_paths", &[])?;
    match cfg.scene.resolve()? {
        SceneChoice::Triangular(s) => run_on(&*s, cfg, options),
        SceneChoice::Square(s) => run_on(&s, cfg, options),
        SceneChoice::Table(s) => run_on(&*s, cfg, options),
    }
}

fn run_on<S: Scene>(
    scene: &S,
    cfg: &FreePathConfig,
    options: &RunOptions,
) -> Result<FreePathReport, Error> {
    let flights = cfg.flights.resolve(scene)?;
    let radius = scene.long_flights().filter(|_| flights == Flights::Jump);
    let crossings = if radius.is_some() {
        0.0
    } else {
        crossings_per_collision(scene)
    };
    Work::new("free_paths", &["collisions"], cfg.collisions as f64)
        .walking(scene)
        .crossing(crossings)
        .check(options.threads)?;
    let ell = scene.mean_free_path();
    let lat = scene.lattice::<f64>(())?;
    let progress = options.progress;
    let per: Vec<FreePathCounts> =
        par_batches_watched(options.threads, cfg.batches, options.stop.as_ref(), |b| {
            let mut rng = stream(cfg.seed, b as u64);
            let mut s = scene.sample(&mut rng);
            let n = share(cfg.collisions, cfg.batches, b);
            let keep = share(cfg.keep_samples, cfg.batches, b);
            let stride = (n - 1) / keep.max(1);
            let mut obs = FreePaths::new(ell, cfg.edges()).keeping(keep as usize, stride);
            in_legs(options.stop.as_ref(), n, STOP_EVERY, |k| match radius {
                Some(r) => drive_jumps(&lat, &r, &mut s, k, &mut obs, progress),
                None => drive(&lat, &mut s, k, &mut obs, progress),
            })?;
            Ok(obs.counts().clone())
        })?;
    Ok(summarize(
        &per,
        cfg,
        (scene.label(), ell, flights),
        options.threads,
    ))
}

/// The batch means against the limit law, on the scene `scene` of mean free path
/// `mean_free_path`.
fn summarize(
    per: &[FreePathCounts],
    cfg: &FreePathConfig,
    (scene, mean_free_path, flights): (String, f64, Flights),
    threads: usize,
) -> FreePathReport {
    let of = |f: &dyn Fn(&FreePathCounts) -> f64| mean_se(&per.iter().map(f).collect::<Vec<_>>());
    let n = |c: &FreePathCounts| c.flights.max(1) as f64;
    let (mean, mean_err) = of(&|c| c.sum / n(c));
    let (ln_mean, ln_mean_err) = of(&|c| c.ln_sum / n(c));
    let dof = batch_dof(per.len());
    let bins: Vec<FreePathBin> = cfg
        .edges()
        .windows(2)
        .enumerate()
        .map(|(k, e)| {
            let (p, err) = of(&|c| c.bins[k] as f64 / n(c));
            let limit = law::probability(e[0], e[1]);
            FreePathBin {
                lo: e[0],
                hi: e[1].is_finite().then_some(e[1]),
                probability: p,
                probability_err: err,
                limit,
                z: (err > 0.0).then(|| comparison::of(p - limit, err, dof).z),
            }
        })
        .collect();
    let max_z = bins
        .iter()
        .filter_map(|b| b.z)
        .map(f64::abs)
        .fold(0.0, f64::max);
    FreePathReport {
        scene,
        mean_free_path,
        samples: per.iter().map(|c| c.flights).sum(),
        collisions: cfg.collisions,
        batches: cfg.batches,
        flights,
        mean,
        mean_err,
        mean_check: comparison::of(mean - 1.0, mean_err, dof),
        ln_mean,
        ln_mean_err,
        ln_mean_limit: law::LN_MEAN,
        longest: per.iter().map(|c| c.longest).fold(0.0, f64::max),
        max_z_bound: largest_of_bound(dof, bins.len()),
        max_z,
        bins,
        free_path_samples: per.iter().flat_map(|c| c.kept.iter().copied()).collect(),
        meta: RunMeta::new(
            Some(cfg.seed),
            Some(cfg.batches as u64),
            "f64",
            Some(threads),
        ),
    }
}
