//! Superdiffusion in an infinite horizon, measured against the exact corridor constants
//! ([`crate::theory::corridors`]): `lorentz superdiffusion`.
//!
//! Each batch is one long trajectory from the flow's invariant measure (stream (seed, b)) on the
//! scalar `f64` kernel. Along it, two observers:
//! * [`FlightTails`]: the map's tail s²·μ(τ > s) (complete collision-to-collision flights) and
//!   the flow's s·P(τ⁺ > s) (Σ (τ − s)⁺ over the total time) at the lag grid's times;
//! * [`LagMoments`]: sampled every mean free time ℓ, at lags t = mℓ on a logarithmic grid
//!   (`points_per_octave` per octave up to 2^`octaves` ℓ), the time-averaged ⟨|Δr|²⟩ and
//!   ⟨v(0)·v(t)⟩ over every window, and at each octave the histogram of Δx/√(D_sup t ln t).
//!
//! Both lattices are isotropic (their 3- and 4-fold rotations make every second-rank tensor a
//! multiple of the identity), so per-component quantities are half the vector ones:
//! ⟨Δx²⟩ = ⟨|Δr|²⟩/2 and C_xx(t) = ⟨v(0)·v(t)⟩/2 — the average of the x and y estimators, with
//! half the variance of either.
//!
//! Every number is a mean over batches with its batch standard error; fits are made batch by
//! batch with common weights (the batch variance of each point), so the batch spread of the
//! fitted values carries every correlation between points and lags. Why batch errors are
//! honest here although ⟨Δx⁴⟩ grows like t³, and what they need: `proofs-notes/
//! superdiffusion-estimators.md` and the test
//! `superdiffusion::msd_slope_errors_match_the_spread_of_independent_runs`.

use serde::{Deserialize, Serialize};

mod summary;

pub use summary::{LagRow, LawRow};

use crate::Error;
use crate::engine::checkpoint::{Keeper, LaneCheckpoint, Quota, drive_kept_with};
use crate::engine::drive;
use crate::engine::long_flight::{Flights, drive_jumps};
use crate::engine::metadata::RunMeta;
use crate::engine::observe::{EventLanes, Observer};
use crate::engine::options::{RunOption, RunOptions};
use crate::engine::parallel::{check_batches, par_batches, share};
use crate::engine::work::{Work, crossings_per_collision};
use crate::numbers::lanes::Lanes;
use crate::observers::flight_tails::{FlightTails, TailCounts, TailLane};
use crate::observers::lag_moments::{LagMoments, LagSums, MomentLane};
use crate::scenes::Scene;
use crate::scenes::lattice::LatticeState;
use crate::scenes::sampling::stream;
use crate::scenes::spec::SceneSpec;
use crate::scenes::square::SquareScene;
use crate::scenes::triangular::TriangularScene;
use crate::theory::corridors::{self, CorridorJson, LatticeGas, Superdiffusion};

/// Longest lag grid: 2²⁰ mean free times (the ring of past samples holds 2²⁰ + 1 of 48 bytes).
pub const MAX_OCTAVES: u32 = 20;

/// What a superdiffusion measurement runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuperdiffusionConfig {
    /// The lattice (an infinite horizon: the triangular gas beyond w_inf, or the square one).
    pub scene: SceneSpec,
    /// Collisions in all, shared between the batches.
    pub collisions: u64,
    /// Independent batches (one trajectory each), at least 16: the errors are over them.
    pub batches: u32,
    /// The longest lag is 2^octaves mean free times.
    pub octaves: u32,
    /// Lags per octave.
    pub points_per_octave: u32,
    /// The tail fits use the grid times s ≥ `tail_fit_from` mean free times (and only those at
    /// which every batch saw at least 100 longer flights).
    pub tail_fit_from: f64,
    /// The lags of the VACF's plateau, [from, to] in mean free times.
    pub vacf_fit: [f64; 2],
    /// The lags of the fit of ⟨Δx²⟩/t = a ln t + b, [from, to] in mean free times.
    pub msd_fit: [f64; 2],
    /// Seed: batch b starts from stream (seed, b).
    pub seed: u64,
    /// How flights cross the lattice ([`Flights`]): `auto` jumps long flights where the scene
    /// supplies them (the square lattice, 2⁻³² ≤ r ≤ 1/4).
    #[serde(default)]
    pub flights: Flights,
}

/// Fewest batches: the errors of heavy-tailed batch means need a few dozen
/// (`proofs-notes/superdiffusion-estimators.md`).
pub const MIN_BATCHES: u32 = 16;

/// Where each estimator has converged, in mean free times: a fit window that starts earlier
/// measures the approach, not the constant, and is given no verdict. From the convergence study
/// at r = 1/4, the fastest scene measured (docs/guide/scenes.md, "Superdiffusion"; a scene of narrower
/// corridors converges later still, so these are necessary, not sufficient): the tails are
/// within their errors of C + B/s from s ≈ 10ℓ, t·C_xx(t) within 3 % of its plateau from ~64ℓ
/// (1.07 there), the local slope of ⟨Δx²⟩/t in ln t 1.10 at 256ℓ and 1.01 at 724ℓ.
pub const CONVERGED_FROM: Converged = Converged {
    tails: 8.0,
    vacf: 64.0,
    msd: 512.0,
};

/// The lags (mean free times) from which each estimator has converged ([`CONVERGED_FROM`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Converged {
    /// The tail fits C + B/s.
    pub tails: f64,
    /// The plateau of t·C_xx(t).
    pub vacf: f64,
    /// The slope of ⟨Δx²⟩/t in ln t.
    pub msd: f64,
}

impl SuperdiffusionConfig {
    /// The command line's defaults for `scene`: 2·10⁸ collisions in 32 batches, lags to 2¹² ℓ at 4
    /// per octave, the tail fits from 8ℓ, the VACF's plateau over [64ℓ, 256ℓ], the MSD's slope
    /// over [512ℓ, 4096ℓ], seed 1.
    pub fn new(scene: SceneSpec) -> Self {
        SuperdiffusionConfig {
            scene,
            collisions: 200_000_000,
            batches: 32,
            octaves: 12,
            points_per_octave: 4,
            tail_fit_from: 8.0,
            vacf_fit: [64.0, 256.0],
            msd_fit: [512.0, 4096.0],
            seed: 1,
            flights: Flights::Auto,
        }
    }

    /// The default fit windows for lags up to 2^`octaves` mean free times, the same place
    /// relative to the longest lag as the defaults at 12 octaves: the VACF's plateau over
    /// [2^(o−6), 2^(o−4)] and the MSD's slope over [2^(o−3), 2^o] (each end at least 1, the
    /// VACF's at least 2, so a window is never empty).
    ///
    /// ```
    /// use lorentz_gas::estimators::superdiffusion::SuperdiffusionConfig;
    /// assert_eq!(SuperdiffusionConfig::default_windows(12), ([64.0, 256.0], [512.0, 4096.0]));
    /// assert_eq!(SuperdiffusionConfig::default_windows(8), ([4.0, 16.0], [32.0, 256.0]));
    /// ```
    pub fn default_windows(octaves: u32) -> ([f64; 2], [f64; 2]) {
        let o = octaves as i32;
        let p = |k: i32| 2f64.powi(k.max(0));
        ([p(o - 6), p(o - 4).max(2.0)], [p(o - 3), p(o).max(2.0)])
    }

    /// This configuration at `octaves`, with the fit windows that follow it
    /// ([`SuperdiffusionConfig::default_windows`]).
    pub fn with_octaves(self, octaves: u32) -> Self {
        let (vacf_fit, msd_fit) = Self::default_windows(octaves);
        SuperdiffusionConfig {
            octaves,
            vacf_fit,
            msd_fit,
            ..self
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// A value out of range, naming the range.
    pub fn validate(&self) -> Result<(), Error> {
        self.lattice().map(drop)
    }

    /// The exact lattice of `scene`, every field checked ([`SuperdiffusionConfig::validate`]).
    fn lattice(&self) -> Result<LatticeGas, Error> {
        let gas = LatticeGas::of(&self.scene)?;
        check_batches("batches", self.batches)?;
        if self.batches < MIN_BATCHES {
            return Err(Error::out_of_range(
                "batches",
                self.batches,
                format!(
                    "use at least {MIN_BATCHES} (the errors of heavy-tailed means need a few dozen batches)"
                ),
            ));
        }
        Error::unless_in(
            "octaves",
            self.octaves,
            1..=MAX_OCTAVES,
            " (the longest lag is 2^octaves mean free times)",
        )?;
        if !(1..=16).contains(&self.points_per_octave) {
            return Err(Error::out_of_range(
                "points_per_octave",
                self.points_per_octave,
                "use 1 to 16",
            ));
        }
        let longest = (self.octaves as f64).exp2();
        if !(self.tail_fit_from >= 1.0 && self.tail_fit_from < longest) {
            return Err(Error::out_of_range(
                "tail_fit_from",
                self.tail_fit_from,
                format!("use at least 1 and below 2^octaves = {longest} (mean free times)"),
            ));
        }
        for (what, w) in [("vacf_fit", self.vacf_fit), ("msd_fit", self.msd_fit)] {
            let on_grid = self
                .lag_steps()
                .iter()
                .filter(|&&m| (w[0]..=w[1]).contains(&(m as f64)))
                .count();
            if !(w[0] >= 1.0 && w[0] < w[1] && w[1] <= longest) || on_grid < 2 {
                return Err(Error::parameter(
                    what,
                    format!("{}:{}", w[0], w[1]),
                    format!(
                        "use 1 <= from < to <= 2^octaves = {longest} mean free times with at \
                         least two lags inside"
                    ),
                ));
            }
        }
        let per_batch = self.collisions / self.batches as u64;
        let needed = 4u64 << self.octaves;
        if per_batch < needed {
            return Err(Error::parameter(
                "collisions",
                self.collisions,
                format!(
                    "too few for {} batches: use at least {needed} per batch (4 times the \
                     longest lag, 2^{} mean free times)",
                    self.batches, self.octaves
                ),
            ));
        }
        crate::engine::check_trajectory_length(per_batch + 1, "batches", self.batches)?;
        Ok(gas)
    }

    /// The lags in mean free times: round(2^(k/points_per_octave)) for k = 0 … octaves·points,
    /// duplicates dropped (ascending).
    pub fn lag_steps(&self) -> Vec<usize> {
        let q = self.points_per_octave as f64;
        let mut steps: Vec<usize> = (0..=self.octaves * self.points_per_octave)
            .map(|k| (k as f64 / q).exp2().round() as usize)
            .collect();
        steps.dedup();
        steps
    }
}

/// A superdiffusion measurement against the exact constants.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SuperdiffusionReport {
    /// The scene ([`Scene::label`]).
    pub scene: String,
    /// Santaló's mean free path ℓ (the lag unit).
    pub mean_free_path: f64,
    /// Every corridor.
    pub corridors: Vec<CorridorJson>,
    /// Σ_xx: the limit law's variance and lim t·C_xx(t).
    #[serde(rename = "D_sup_exact")]
    pub d_sup_exact: f64,
    /// The flow's tail constant: P(τ > s) ≈ C_flow/s.
    #[serde(rename = "C_flow_exact")]
    pub c_flow_exact: f64,
    /// The map's tail constant: μ(τ > s) ≈ C_map/s².
    #[serde(rename = "C_map_exact")]
    pub c_map_exact: f64,
    /// The coefficient of t ln t in ⟨Δx²⟩: 2 D_sup.
    pub msd_log_slope_exact: f64,
    /// C_flow from s·P(τ > s) = C + B/s fitted over `tail_fit` (`None` when fewer than two
    /// grid times qualify: too few long flights).
    #[serde(rename = "C_flow_tail")]
    pub c_flow_tail: Option<f64>,
    /// Its batch error.
    #[serde(rename = "C_flow_tail_err")]
    pub c_flow_tail_err: Option<f64>,
    /// C_map from s²·μ(τ > s) = C + B/s fitted over `tail_fit`.
    #[serde(rename = "C_map_tail")]
    pub c_map_tail: Option<f64>,
    /// Its batch error.
    #[serde(rename = "C_map_tail_err")]
    pub c_map_tail_err: Option<f64>,
    /// The tail fits' range of s: the grid times from `tail_fit_from`·ℓ on at which every batch
    /// saw at least 100 longer flights.
    pub tail_fit: Option<[f64; 2]>,
    /// D_sup from t·C_xx(t): its weighted mean over `vacf_fit`.
    #[serde(rename = "D_sup_vacf")]
    pub d_sup_vacf: f64,
    /// Its error: the batch error and the unsampled-flight term in quadrature.
    #[serde(rename = "D_sup_vacf_err")]
    pub d_sup_vacf_err: f64,
    /// The batch error alone.
    #[serde(rename = "D_sup_vacf_err_batch")]
    pub d_sup_vacf_err_batch: f64,
    /// The unsampled-flight term: |D_sup_vacf|·t/L at the window's last lag t, L the longest
    /// flight seen (`proofs-notes/superdiffusion-estimators.md`).
    #[serde(rename = "D_sup_vacf_err_unsampled")]
    pub d_sup_vacf_err_unsampled: f64,
    /// The lags of the VACF's plateau [from, to] (time units).
    pub vacf_fit: [f64; 2],
    /// The slope a of ⟨Δx²⟩/t = a ln t + b fitted over `msd_fit` (→ 2 D_sup).
    pub msd_log_slope: f64,
    /// Its error: batch and unsampled-flight terms in quadrature.
    pub msd_log_slope_err: f64,
    /// The batch error alone.
    pub msd_log_slope_err_batch: f64,
    /// The unsampled-flight term, |a|·t/L at the window's last lag.
    pub msd_log_slope_err_unsampled: f64,
    /// The intercept b.
    pub msd_log_intercept: f64,
    /// Its batch error.
    pub msd_log_intercept_err: f64,
    /// The lags of the MSD fit [from, to] (time units).
    pub msd_fit: [f64; 2],
    /// The longest free flight seen in all batches.
    pub longest_flight: f64,
    /// Per lag t: the tails at s = t, t·C_xx(t), ⟨Δx²⟩ and the local slope of ⟨Δx²⟩/t in ln t.
    pub lags: Vec<LagRow>,
    /// Per octave: the distribution of Δx/√(D_sup t ln t) against N(0, 1).
    pub limit_law: Vec<LawRow>,
    /// Collisions in all.
    pub collisions: u64,
    /// Collisions of each batch (the first batches take one more when they do not divide).
    pub collisions_per_batch: u64,
    /// How the flights crossed the lattice: `walk` or `jump` (files written before jumps
    /// existed: `walk`).
    #[serde(default = "walked")]
    pub flights: Flights,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// What one batch's trajectory showed (a checkpoint's finished batch).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Batch {
    tails: TailCounts,
    lags: LagSums,
}

/// The kind of a superdiffusion checkpoint.
pub const CHECKPOINT_KIND: &str = "lorentz-gas superdiffusion";

/// Both observers of one trajectory, saved and put back together.
struct Watch {
    tails: FlightTails,
    moments: LagMoments,
}

impl Observer<1> for Watch {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<1>]) {
        self.tails.observe::<V>(steps);
        self.moments.observe::<V>(steps);
    }
}

impl LaneCheckpoint for Watch {
    type Lane = (TailLane, MomentLane);
    fn save_lane(&self, l: usize) -> Self::Lane {
        (self.tails.save_lane(l), self.moments.save_lane(l))
    }
    fn restore_lane(&mut self, l: usize, saved: &Self::Lane) -> Result<(), Error> {
        self.tails.restore_lane(l, &saved.0)?;
        self.moments.restore_lane(l, &saved.1)
    }
}

/// Measures superdiffusion on `cfg.scene` (which must have an infinite horizon). Of the options,
/// `threads`, `progress`, `stop`, `resume` (a checkpoint: finished batches, and every
/// `checkpoint_every` each trajectory in flight with both observers' lanes) and
/// `checkpoint_every` apply; it runs on the scalar `f64` kernel.
///
/// # Errors
/// An invalid configuration, a finite horizon (use [`crate::estimators::diffusion`]), or a run
/// stopped on request.
pub fn run(
    cfg: &SuperdiffusionConfig,
    options: &RunOptions,
) -> Result<SuperdiffusionReport, Error> {
    let gas = cfg.lattice()?;
    options.accept(
        "superdiffusion",
        &[RunOption::Resume, RunOption::CheckpointEvery],
    )?;
    let sd = corridors::superdiffusion::<f64>((), &gas)?;
    match gas {
        LatticeGas::Square { r } => run_on(&SquareScene::exact(r)?, cfg, &sd, options),
        LatticeGas::Triangular { w } => run_on(&TriangularScene::exact(w)?, cfg, &sd, options),
    }
}

fn run_on<S: Scene>(
    scene: &S,
    cfg: &SuperdiffusionConfig,
    sd: &Superdiffusion<f64>,
    options: &RunOptions,
) -> Result<SuperdiffusionReport, Error> {
    if scene.finite_horizon() || !sd.infinite_horizon() {
        return Err(Error::Lacks {
            scene: scene.label(),
            capability: crate::error::Capability::InfiniteHorizon,
            analysis: "superdiffusion",
        });
    }
    let flights = cfg.flights.resolve(scene)?;
    let crossings = match flights {
        Flights::Jump => 0.0,
        _ => crossings_per_collision(scene),
    };
    Work::new("superdiffusion", &["collisions"], cfg.collisions as f64)
        .walking(scene)
        .crossing(crossings)
        .check(options.threads)?;
    let ell = scene.mean_free_path();
    let steps = cfg.lag_steps();
    let times: Vec<f64> = steps.iter().map(|&m| m as f64 * ell).collect();
    let histogram_at: Vec<usize> = (0..steps.len())
        .filter(|&k| steps[k].is_power_of_two() && times[k] > std::f64::consts::E)
        .collect();
    let input = summary::Input {
        cfg,
        sd,
        ell,
        steps: &steps,
        times: &times,
        histogram_at: &histogram_at,
    };
    let meta = RunMeta::new(
        Some(cfg.seed),
        Some(cfg.batches as u64),
        "f64",
        Some(options.threads),
    );
    let radius = scene.long_flights().filter(|_| flights == Flights::Jump);
    let batches = run_batches(scene, &input, &meta, radius, options)?;
    let s = summary::summarise(&input, &batches)?;
    Ok(report(scene.label(), &input, s, flights, meta))
}

/// Every batch's trajectory, in batch order: those a checkpoint holds finished, the others run
/// (from their saved state when they were in flight) and kept as they finish.
fn run_batches<S: Scene>(
    scene: &S,
    inp: &summary::Input,
    meta: &RunMeta,
    jumps: Option<crate::scenes::long_flight::LongFlights>,
    options: &RunOptions,
) -> Result<Vec<Batch>, Error> {
    let cfg = inp.cfg;
    let lat = scene.lattice::<f64>(())?;
    let basis = lat.basis_f64();
    let jobs: Vec<Quota> = (0..cfg.batches)
        .map(|index| Quota {
            run: 0,
            index,
            collisions: share(cfg.collisions, cfg.batches, index),
        })
        .collect();
    let n = inp.steps.len();
    let fits = |_: &Quota, b: &Batch| b.tails.longer.len() == n && b.lags.squared.len() == n;
    let keep = Keeper::<Batch, (TailLane, MomentLane)>::open(
        options.resume.as_deref(),
        CHECKPOINT_KIND,
        cfg,
        Some(meta.clone()),
        &jobs,
        Some(options.checkpoint_every),
        &fits,
    )?
    .watching(options.stop.as_ref());
    (options.progress)(keep.collisions_done(&jobs));
    let todo: Vec<Quota> = jobs.into_iter().filter(|j| !keep.is_finished(j)).collect();
    let new = par_batches(options.threads, todo.len() as u32, |k| {
        let j = &todo[k as usize];
        let mut obs = Watch {
            tails: FlightTails::new(inp.times, 1),
            moments: LagMoments::new(
                inp.ell,
                inp.steps,
                inp.histogram_at,
                inp.sd.d_sup_xx,
                basis,
                1,
            ),
        };
        let start = || scene.sample(&mut stream(cfg.seed, j.index as u64));
        let step = |s: &mut LatticeState<f64>, q: u64, obs: &mut Watch| match jumps {
            Some(r) => drive_jumps(&lat, &r, s, q, obs, options.progress),
            None => drive(&lat, s, q, obs, options.progress),
        };
        drive_kept_with((), j, start, &mut obs, &keep, step)?;
        let b = Batch {
            tails: obs.tails.counts(0).clone(),
            lags: obs.moments.sums(0).clone(),
        };
        keep.finish(j, &b)?;
        Ok(b)
    })?;
    let mut all: Vec<(u32, Batch)> = keep.finished_by_index().collect();
    all.extend(todo.iter().map(|j| j.index).zip(new));
    all.sort_by_key(|(i, _)| *i);
    Ok(all.into_iter().map(|(_, b)| b).collect())
}

/// The report: the exact constants beside the summary's measurements.
fn report(
    scene: String,
    inp: &summary::Input,
    s: summary::Summary,
    flights: Flights,
    meta: RunMeta,
) -> SuperdiffusionReport {
    let (cfg, sd) = (inp.cfg, inp.sd);
    SuperdiffusionReport {
        scene,
        mean_free_path: inp.ell,
        corridors: sd.corridors.iter().map(|c| c.to_json()).collect(),
        d_sup_exact: sd.d_sup_xx,
        c_flow_exact: sd.c_flow,
        c_map_exact: sd.c_map,
        msd_log_slope_exact: sd.msd_x_coefficient(),
        c_flow_tail: s.c_flow.map(|c| c.0),
        c_flow_tail_err: s.c_flow.map(|c| c.1),
        c_map_tail: s.c_map.map(|c| c.0),
        c_map_tail_err: s.c_map.map(|c| c.1),
        tail_fit: s.tail_fit,
        d_sup_vacf: s.d_sup.value,
        d_sup_vacf_err: s.d_sup.err(),
        d_sup_vacf_err_batch: s.d_sup.batch,
        d_sup_vacf_err_unsampled: s.d_sup.unsampled,
        vacf_fit: s.vacf_fit,
        msd_log_slope: s.slope.value,
        msd_log_slope_err: s.slope.err(),
        msd_log_slope_err_batch: s.slope.batch,
        msd_log_slope_err_unsampled: s.slope.unsampled,
        msd_log_intercept: s.intercept.0,
        msd_log_intercept_err: s.intercept.1,
        msd_fit: s.msd_fit,
        longest_flight: s.longest,
        lags: s.lags,
        limit_law: s.law,
        collisions: cfg.collisions,
        collisions_per_batch: cfg.collisions / cfg.batches as u64,
        flights,
        meta,
    }
}

fn walked() -> Flights {
    Flights::Walk
}
