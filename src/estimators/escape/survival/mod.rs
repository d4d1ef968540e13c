//! The escape rate of an open table by survival, with the Lyapunov exponent and the KS entropy
//! conditioned on survival: the three-disk repeller's γ, λ and h_KS measured by following
//! particles, independently of its cycles (`docs/guide/cycles.md`, "Survival").
//!
//! Particles start from the billiard map's invariant measure restricted to the directions that
//! hit another disk ([`walk`]: uniform in arc length and in sin φ on that set) and are followed
//! until they escape. Their surviving fraction is a staircase in time — on the repeller every
//! flight is nearly R − 2a long, and the steps die out only at the rate of the next resonance,
//! close to γ — so the continuous-time tail is not fitted directly; the collisions count the
//! steps instead. Z_n(s) = Σ_{alive at collision n} e^{sτ_n} (τ_n the time of collision n)
//! decays or grows geometrically in n after a transient that dies at the map's spectral gap
//! (about 1/Λ per collision), and is constant in n exactly at s = γ ([`tally`]). The estimate
//! from the window starting at collision n₀ solves Z_{n₀+1}(γ̂) = Z_{n₀}(γ̂); the window one
//! collision later gives the check that n₀ is late enough (both reported, with their
//! difference in combined σ). At γ̂ the increments of the weighted means of τ and ln Λ give
//! the natural measure's ⟨T⟩ and ⟨ln Λ⟩: λ = ⟨ln Λ⟩/⟨T⟩, h_KS = λ − γ.
//!
//! Errors: [`BATCHES`] independent batches each give their own estimates; the standard error
//! is their standard deviation over √B (Student-t with B − 1 degrees of freedom), the values
//! those of the pooled batches. The weights are kept as Taylor moments about a pilot's rate, so
//! any s is evaluated after the run.
//!
//! Streams: batch b uses `StreamKey::new(seed, Purpose::Survival, b)`, the pilot
//! `StreamKey::new(seed, Purpose::Survival, 0).in_run(1)`; every batch is a fixed set of
//! particles, so the result does not depend on the thread count.

pub mod tally;
pub mod walk;

use std::time::Instant;

use serde::{Deserialize, Serialize};

use self::tally::{Tally, WindowEstimate, estimate};
use self::walk::{Starts, follow};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::parallel::{par_batches_watched, share};
use crate::kernel::open::OpenDisks;
use crate::scenes::open::OpenSpec;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::spec::{Motion, SceneSpec, Table};
use crate::statistics::mean_se;

/// Independent batches: the errors are over them.
pub const BATCHES: u32 = 32;

/// Starts of the pilot run that fixes the point s₀ of the moments.
pub const PILOT_PARTICLES: u64 = 1 << 18;

/// Fewest particles: each batch needs survivors at the window's end.
pub const MIN_PARTICLES: u64 = 1000 * BATCHES as u64;

/// Most particles (about a day of one core at R/a = 6).
pub const MAX_PARTICLES: u64 = 1_000_000_000_000;

/// The latest window start n₀: the surviving fraction falls by a constant factor per
/// collision, so later windows need exponentially more particles.
pub const MAX_WINDOW: u32 = 20;

/// The default window start n₀ (collisions): the transient at the three-disk repeller has died
/// to below 10⁻⁵ of γ there (`docs/guide/cycles.md`).
pub const DEFAULT_WINDOW: u32 = 3;

/// The start density, in words (for the report).
pub const START_DENSITY: &str = "uniform in arc length on the disks' boundaries and in sin(phi) on the outgoing directions that hit another disk (the billiard map's invariant measure restricted to them)";

/// Everything that defines a survival run on an open table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurvivalConfig {
    /// An open table ([`SceneSpec::Open`]), without a field (in JSON `scene`).
    #[serde(flatten)]
    pub table: Table,
    /// Particles started.
    pub particles: u64,
    /// The collision n₀ at which the window starts.
    pub window: u32,
    /// Seed of the random streams.
    pub seed: u64,
}

impl SurvivalConfig {
    /// The default run on `open`: 10⁷ particles, window n₀ = [`DEFAULT_WINDOW`], seed 1.
    pub fn new(open: OpenSpec) -> Self {
        SurvivalConfig {
            table: Table {
                scene: SceneSpec::Open(open),
                motion: Motion::Straight,
            },
            particles: 10_000_000,
            window: DEFAULT_WINDOW,
            seed: 1,
        }
    }

    /// The open table.
    ///
    /// # Errors
    /// Another scene (it lacks an escape: [`Error::Parameter`] naming `scene`).
    pub fn open(&self) -> Result<&OpenSpec, Error> {
        match &self.table.scene {
            SceneSpec::Open(o) => Ok(o),
            s => Err(Error::parameter(
                "scene",
                s.name(),
                "survival runs on an open table (the repeller or disks given as data)",
            )),
        }
    }

    /// Checks every parameter; errors name the valid range.
    ///
    /// # Errors
    /// Not an open table, a field, a table refused by [`OpenSpec::validate`], particles or
    /// window out of range.
    pub fn validate(&self) -> Result<(), Error> {
        self.open()?.validate()?;
        if self.table.motion != Motion::Straight {
            return Err(Error::Invalid(
                "escape on an open table takes no field: leave it out".into(),
            ));
        }
        Error::unless_in(
            "particles",
            self.particles,
            MIN_PARTICLES..=MAX_PARTICLES,
            "",
        )?;
        Error::unless_in("window", self.window, 1..=MAX_WINDOW, " (collisions)")?;
        Ok(())
    }
}

/// The result of a survival run (the CLI's `--json`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SurvivalReport {
    /// The table's name.
    pub table: String,
    /// How the particles start.
    pub start_density: String,
    /// Escape rate γ from the window starting at collision n₀.
    pub gamma: f64,
    /// Its batch standard error.
    pub gamma_err: f64,
    /// γ from the window one collision later (the check that n₀ is late enough).
    pub gamma_late: f64,
    /// Its batch standard error.
    pub gamma_late_err: f64,
    /// (γ_late − γ) in combined σ: near 0 when the transient has died.
    pub window_check_sigma: f64,
    /// The estimates of every window start from collision 1 to n₀ + 1: how the transient dies.
    pub windows: Vec<SurvivalWindow>,
    /// The transient's ratio per collision, (γ_{n₀} − γ_{n₀−1})/(γ_{n₀−1} − γ_{n₀−2}) (from
    /// n₀ = 3 on; `None` before).
    pub transient_ratio: Option<f64>,
    /// The bias of γ left by a transient that keeps that ratio, (γ_{n₀} − γ_{n₀−1}) r/(r − 1):
    /// γ(∞) ≈ γ − this (from n₀ = 3 on).
    pub transient_bias: Option<f64>,
    /// Lyapunov exponent λ on the repeller (natural measure), from the window at n₀.
    pub lyapunov: f64,
    /// Its batch standard error.
    pub lyapunov_err: f64,
    /// KS entropy h_KS = λ − γ.
    pub entropy: f64,
    /// Its batch standard error (of the batches' λ − γ).
    pub entropy_err: f64,
    /// Mean flight time ⟨T⟩ on the repeller.
    pub mean_flight_time: f64,
    /// Its batch standard error.
    pub mean_flight_time_err: f64,
    /// The fraction of the particles alive at collision k = 0, 1, …, n₀ + 2.
    pub survival: Vec<f64>,
    /// Each batch's γ from the window at n₀ (the errors are their spread; the audit re-runs one).
    pub batch_gamma: Vec<f64>,
    /// Each batch's λ from the window at n₀.
    pub batch_lyapunov: Vec<f64>,
    /// The pilot's γ, about which the weights are expanded.
    pub pilot_gamma: f64,
    /// Collisions over all particles.
    pub collisions: u64,
    /// Independent batches.
    pub batches: u32,
    /// Wall-clock seconds.
    pub seconds: f64,
    /// The configuration that produced the result.
    pub config: SurvivalConfig,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// The estimates of one window.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct SurvivalWindow {
    /// The collision n at which the window starts (Z_{n+1} = Z_n).
    pub start: u32,
    /// Escape rate γ.
    pub gamma: f64,
    /// Its batch standard error.
    pub gamma_err: f64,
    /// Lyapunov exponent λ.
    pub lyapunov: f64,
    /// Its batch standard error.
    pub lyapunov_err: f64,
}

/// One batch: `n` particles from `key`'s stream, moments about `s0`.
fn batch(
    table: &OpenDisks<f64>,
    starts: &Starts,
    (n, window, s0): (u64, usize, f64),
    key: StreamKey,
    options: &RunOptions,
) -> Result<Tally, Error> {
    let cap = window + 2;
    let mut tally = Tally::new(cap);
    let mut rng = key.rng();
    const EVERY: u64 = 1 << 16;
    for i in 0..n {
        if i % EVERY == 0 && i > 0 {
            (options.progress)(EVERY);
            if let Some(s) = &options.stop {
                s.check()?;
            }
        }
        let start = starts.draw(table, &mut rng);
        tally.alive[0] += 1;
        let made = follow(table, start, cap, |k, c| {
            tally.alive[k] += 1;
            tally.moments[k].add(s0, c.time, c.ln_expansion);
            tally.time_max = tally.time_max.max(c.time);
        });
        tally.collisions += made as u64;
    }
    (options.progress)(n - n.saturating_sub(1) / EVERY * EVERY);
    Ok(tally)
}

/// The pilot's γ and its collisions per particle: a small run whose moments are taken about
/// s = 0 and solved exactly by doubling the reach until the root is inside it.
fn pilot(
    table: &OpenDisks<f64>,
    starts: &Starts,
    cfg: &SurvivalConfig,
    options: &RunOptions,
) -> Result<(f64, f64), Error> {
    let key = StreamKey::new(cfg.seed, Purpose::Survival, 0).in_run(1);
    let quiet = RunOptions {
        progress: &|_| {},
        ..options.clone()
    };
    let mut s0 = 0.0;
    for _ in 0..64 {
        let n = (PILOT_PARTICLES, cfg.window as usize, s0);
        let t = batch(table, starts, n, key, &quiet)?;
        match estimate(&t, cfg.window as usize, s0) {
            Ok(e) => {
                if (e.gamma - s0).abs() * t.time_max < 0.1 * tally::MAX_SHIFT {
                    return Ok((e.gamma, t.collisions as f64 / PILOT_PARTICLES as f64));
                }
                s0 = e.gamma;
            }
            Err(_) => s0 += tally::MAX_SHIFT / t.time_max.max(1e-300),
        }
    }
    Err(Error::Failed(format!(
        "the pilot of {PILOT_PARTICLES} particles found no escape rate at window {}: use an \
         earlier window",
        cfg.window
    )))
}

/// Runs the configured survival measurement. `options.progress` receives particle counts;
/// `threads`, `progress` and `stop` apply.
///
/// # Errors
/// An invalid configuration or options, before any work; a window without survivors.
pub fn run(cfg: &SurvivalConfig, options: &RunOptions) -> Result<SurvivalReport, Error> {
    cfg.validate()?;
    options.accept("escape", &[])?;
    let start = Instant::now();
    let open = cfg.open()?;
    let p = Prepared::new(cfg, options)?;
    let tallies = par_batches_watched(options.threads, BATCHES, options.stop.as_ref(), |b| {
        p.batch(cfg, b, options)
    })?;
    let window = cfg.window as usize;
    let s0 = p.s0;
    let mut all = Tally::new(window + 2);
    for t in &tallies {
        all.merge(t);
    }
    let mut report = summarise(cfg, open, &all, &tallies, s0)?;
    report.seconds = start.elapsed().as_secs_f64();
    report.meta = RunMeta::new(
        Some(cfg.seed),
        Some(u64::from(BATCHES)),
        "f64",
        Some(options.threads),
    );
    Ok(report)
}

/// Collisions a run of `cfg` makes, expected from its pilot (run here: about 0.1 s) — the
/// audit's budget, computed from the configuration and never from a record.
///
/// # Errors
/// As [`run`].
pub fn expected_collisions(cfg: &SurvivalConfig, options: &RunOptions) -> Result<u64, Error> {
    cfg.validate()?;
    let p = Prepared::new(cfg, options)?;
    Ok((p.per_particle * cfg.particles as f64).ceil() as u64)
}

/// Batch `b` of the run of `cfg` alone, with the run's pilot: its estimates from the window at
/// n₀, the bits of the whole run's `batch_gamma[b]` and `batch_lyapunov[b]` (the audit's quick
/// re-run). `options.progress` receives particles.
///
/// # Errors
/// As [`run`], and a batch outside 0 … [`BATCHES`] − 1.
pub fn rerun_batch(
    cfg: &SurvivalConfig,
    b: u32,
    options: &RunOptions,
) -> Result<WindowEstimate, Error> {
    cfg.validate()?;
    Error::unless_in("batch", b, 0..=BATCHES - 1, "")?;
    let p = Prepared::new(cfg, options)?;
    estimate(&p.batch(cfg, b, options)?, cfg.window as usize, p.s0)
}

/// What every batch of a run shares: the table, its start sampler and the pilot's rate (with
/// the pilot's collisions per particle).
struct Prepared {
    table: OpenDisks<f64>,
    starts: Starts,
    s0: f64,
    per_particle: f64,
}

impl Prepared {
    /// The table of `cfg` (validated by the caller) and its pilot.
    fn new(cfg: &SurvivalConfig, options: &RunOptions) -> Result<Self, Error> {
        let table = cfg.open()?.at::<f64>(());
        let starts = Starts::new(&table);
        let (s0, per_particle) = pilot(&table, &starts, cfg, options)?;
        Ok(Prepared {
            table,
            starts,
            s0,
            per_particle,
        })
    }

    /// Batch `b`'s tally: its share of the particles on its own stream.
    fn batch(&self, cfg: &SurvivalConfig, b: u32, options: &RunOptions) -> Result<Tally, Error> {
        let key = StreamKey::new(cfg.seed, Purpose::Survival, u64::from(b));
        let n = share(cfg.particles, BATCHES, b);
        let window = cfg.window as usize;
        batch(
            &self.table,
            &self.starts,
            (n, window, self.s0),
            key,
            options,
        )
    }
}

/// One window: the pooled estimates, their standard errors over the batches of (γ, λ, ⟨T⟩,
/// λ − γ), and each batch's estimates.
type Window = (WindowEstimate, [f64; 4], Vec<WindowEstimate>);

/// The windows n = 1 … n₀ + 1 of `all` with the batch errors of `tallies`.
fn windows(
    cfg: &SurvivalConfig,
    all: &Tally,
    tallies: &[Tally],
    s0: f64,
) -> Result<Vec<Window>, Error> {
    (1..=cfg.window as usize + 1)
        .map(|n| {
            let pooled = estimate(all, n, s0)?;
            let each: Vec<WindowEstimate> = (tallies.iter())
                .map(|t| estimate(t, n, s0))
                .collect::<Result<_, Error>>()?;
            let errs = batch_errors(&each);
            Ok((pooled, errs, each))
        })
        .collect()
}

/// The standard errors over the batches' estimates `each` of (γ, λ, ⟨T⟩, λ − γ): the report's
/// errors.
pub fn batch_errors(each: &[WindowEstimate]) -> [f64; 4] {
    let se =
        |f: &dyn Fn(&WindowEstimate) -> f64| mean_se(&each.iter().map(f).collect::<Vec<f64>>()).1;
    [
        se(&|e| e.gamma),
        se(&|e| e.lyapunov),
        se(&|e| e.mean_flight_time),
        se(&|e| e.lyapunov - e.gamma),
    ]
}

/// The transient's ratio per collision and the bias it leaves in γ at the last of `gammas`.
fn transient(gammas: &[f64]) -> (Option<f64>, Option<f64>) {
    let [.., a, b, c] = gammas else {
        return (None, None);
    };
    let r = (c - b) / (b - a);
    (Some(r), Some((c - b) * r / (r - 1.0)))
}

/// The report of `all` with the batch errors of `tallies`.
fn summarise(
    cfg: &SurvivalConfig,
    open: &OpenSpec,
    all: &Tally,
    tallies: &[Tally],
    s0: f64,
) -> Result<SurvivalReport, Error> {
    let rows = windows(cfg, all, tallies, s0)?;
    let n0 = cfg.window as usize;
    let ((main, err, each), (late, late_err, _)) = (&rows[n0 - 1], &rows[n0]);
    let (main, err, late, late_err) = (*main, *err, *late, *late_err);
    let gammas: Vec<f64> = rows[..n0].iter().map(|r| r.0.gamma).collect();
    let (transient_ratio, transient_bias) = transient(&gammas);
    let starts = all.alive[0].max(1) as f64;
    Ok(SurvivalReport {
        table: open.title(),
        start_density: START_DENSITY.to_string(),
        gamma: main.gamma,
        gamma_err: err[0],
        gamma_late: late.gamma,
        gamma_late_err: late_err[0],
        window_check_sigma: (late.gamma - main.gamma) / err[0].hypot(late_err[0]),
        windows: (rows.iter().zip(1u32..))
            .map(|((e, s, _), start)| SurvivalWindow {
                start,
                gamma: e.gamma,
                gamma_err: s[0],
                lyapunov: e.lyapunov,
                lyapunov_err: s[1],
            })
            .collect(),
        transient_ratio,
        transient_bias,
        lyapunov: main.lyapunov,
        lyapunov_err: err[1],
        entropy: main.lyapunov - main.gamma,
        entropy_err: err[3],
        mean_flight_time: main.mean_flight_time,
        mean_flight_time_err: err[2],
        survival: all.alive.iter().map(|&a| a as f64 / starts).collect(),
        batch_gamma: each.iter().map(|e| e.gamma).collect(),
        batch_lyapunov: each.iter().map(|e| e.lyapunov).collect(),
        pilot_gamma: s0,
        collisions: all.collisions,
        batches: BATCHES,
        seconds: 0.0,
        config: cfg.clone(),
        meta: RunMeta::new(Some(cfg.seed), None, "f64", None),
    })
}
