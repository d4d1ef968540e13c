//! Backscattering by injection into a single trap from the invariant flux (paper Sec. III),
//! with Kac's lemma checked on the visit times and collision counts.

use serde::{Deserialize, Serialize};

use super::est;
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::{RunOptions, StopFlag};
use crate::engine::parallel::{par_batches_watched, share};
use crate::numbers::precision::{AtPrecision, Precision};
use crate::numbers::real::Real;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::single_trap::SingleTrap;
use crate::scenes::spec::Table;
use crate::scenes::triangular::geometry::Geometry;

/// Injected visits between two calls of a progress callback: 2¹⁶, about 10⁶ collisions at w = 0.1
/// (π/(3w) ≈ 10 collisions per visit).
const VISIT_CHUNK: u64 = 1 << 16;

/// Everything that defines an injection experiment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BackscatterConfig {
    /// The triangular gas at a gap 0 < w < w∞, without a field: `f64` runs use the double
    /// nearest the gap, runs at an MPFR precision the gap as typed rounded once (in JSON `w`
    /// and `w_exact`; a record of before with `w` alone reads as that double).
    #[serde(flatten)]
    pub table: Table,
    /// Particles injected in all (at least one per batch).
    pub particles: u64,
    /// Independent batches (at least 2); every error bar is over them.
    pub batches: u32,
    /// Seed of the random streams.
    pub seed: u64,
    /// Which run of this seed: batch b injects from the stream `(seed, Injection, run, b)`, so
    /// the points of a figure's grid never share streams.
    #[serde(default)]
    pub run: u64,
    /// Number type (statistics must not depend on it).
    pub precision: Precision,
}

impl BackscatterConfig {
    /// The command line's defaults on `table`: 10⁷ visits in 32 batches, seed 1, `f64`.
    pub fn new(table: Table) -> Self {
        BackscatterConfig {
            table,
            particles: 10_000_000,
            batches: 32,
            seed: 1,
            run: 0,
            precision: Precision::F64,
        }
    }

    /// The gap as its nearest double (what `f64` runs and the closed forms use).
    ///
    /// # Errors
    /// A table other than the triangular gas without a field.
    pub fn gap(&self) -> Result<f64, Error> {
        crate::estimators::straight_gap(&self.table, "backscatter")
    }

    /// Checks every field before any work; errors name the valid range.
    ///
    /// # Errors
    /// Another scene ([`Error::Lacks`] trap symbols), a field, a gap outside (0, w∞) as typed,
    /// fewer than 2 batches or than one particle per batch.
    pub fn validate(&self) -> Result<(), Error> {
        self.table.motion_taken_by("backscatter")?;
        crate::estimators::diffusive_gap(&self.table, "backscatter")?;
        if self.batches < 2 {
            return Err(Error::TooFew {
                what: "batches",
                min: 2,
                got: self.batches as u64,
            });
        }
        if self.particles < self.batches as u64 {
            return Err(Error::TooFew {
                what: "particles (one per batch at least)",
                min: self.batches as u64,
                got: self.particles,
            });
        }
        crate::engine::parallel::check_batches("batches", self.batches)
    }
}

/// Backscattering by injection (the CLI's `backscatter --json`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BackscatterReport {
    /// Gap.
    pub w: f64,
    /// P(leave through the entrance).
    pub p_bs: f64,
    /// Its standard error.
    pub p_bs_err: f64,
    /// P(leave to the left) (equal to `p_r` by symmetry).
    pub p_l: f64,
    /// Its standard error.
    pub p_l_err: f64,
    /// P(leave to the right).
    pub p_r: f64,
    /// Its standard error.
    pub p_r_err: f64,
    /// P(no collision in the trap).
    pub p_cf: f64,
    /// Its standard error.
    pub p_cf_err: f64,
    /// Mean time in the trap.
    pub mean_visit_time: f64,
    /// Its standard error.
    pub mean_visit_time_err: f64,
    /// Kac: τ = πA/(3w).
    pub mean_visit_time_exact: f64,
    /// Mean collisions per visit.
    pub mean_collisions_per_visit: f64,
    /// Its standard error.
    pub mean_collisions_per_visit_err: f64,
    /// Kac: π/(3w).
    pub mean_collisions_per_visit_exact: f64,
    /// Particles injected (one visit each).
    pub particles: u64,
    /// The configuration that produced the result (what `lorentz report` re-runs).
    pub config: BackscatterConfig,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// The injection batches on number type `T`.
struct Inject<'a> {
    w: f64,
    w_exact: Option<&'a str>,
    particles: u64,
    batches: u32,
    seed: u64,
    run: u64,
    threads: usize,
    progress: &'a (dyn Fn(u64) + Sync),
    stop: Option<&'a StopFlag>,
}

impl AtPrecision for Inject<'_> {
    type Output = Result<Vec<[f64; 6]>, Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Self::Output {
        let w = crate::numbers::exact::param_at::<T>(ctx, self.w, self.w_exact)?;
        let scene = SingleTrap::new(w)?;
        let progress = self.progress;
        par_batches_watched(self.threads, self.batches, self.stop, |b| {
            let n_b = share(self.particles, self.batches, b);
            let mut rng = StreamKey::new(self.seed, Purpose::Injection, b as u64)
                .in_run(self.run)
                .rng();
            let (mut exits, mut cf, mut t, mut c) = ([0u64; 3], 0u64, 0.0, 0u64);
            for i in 1..=n_b {
                // A visit is a few collisions: the stop flag is looked at before each one.
                if let Some(s) = self.stop {
                    s.check()?;
                }
                let v = scene.random_visit(&mut rng)?;
                exits[v.exit.index()] += 1;
                cf += u64::from(v.collisions == 0);
                t += v.time;
                c += v.collisions;
                if i % VISIT_CHUNK == 0 {
                    progress(VISIT_CHUNK);
                }
            }
            progress(n_b % VISIT_CHUNK);
            let n = n_b as f64;
            Ok([
                exits[0] as f64 / n,
                exits[1] as f64 / n,
                exits[2] as f64 / n,
                cf as f64 / n,
                t / n,
                c as f64 / n,
            ])
        })
    }
}

/// Injects `cfg.particles` particles (in `cfg.batches` batches) through one gap from the invariant
/// flux, at the configuration's precision. `options.progress` receives the visits done, in
/// increments of up to 2¹⁶ per batch, summing to `particles`. Only `threads` and `progress` of the
/// options apply (injection runs on the scalar kernel).
///
/// # Errors
/// An invalid configuration or options, before any work.
pub fn run(cfg: &BackscatterConfig, options: &RunOptions) -> Result<BackscatterReport, Error> {
    cfg.validate()?;
    options.accept("backscatter", &[])?;
    // Each injected particle stays π/(3w) collisions in its trap on average.
    let w = cfg.gap()?;
    let collisions = cfg.particles as f64 * Geometry::new(w)?.collisions_per_hop();
    crate::engine::work::Work::new("backscatter", &["particles"], collisions)
        .or_raise("w")
        .check(options.threads)?;
    let BackscatterConfig {
        particles,
        batches,
        seed,
        run,
        precision,
        ..
    } = *cfg;
    let (threads, progress) = (options.threads, options.progress);
    let res = precision.dispatch(Inject {
        w,
        w_exact: cfg.table.gap_text(),
        particles,
        batches,
        seed,
        run,
        threads,
        progress,
        stop: options.stop.as_ref(),
    })?;
    let col = |k: usize| est(&res.iter().map(|x| x[k]).collect::<Vec<_>>());
    let g = Geometry::new(w)?;
    let (pz, mt, mc) = (col(0), col(4), col(5));
    let (pl, pr, pcf) = (col(1), col(2), col(3));
    Ok(BackscatterReport {
        w,
        p_bs: pz.value,
        p_bs_err: pz.err,
        p_l: pl.value,
        p_l_err: pl.err,
        p_r: pr.value,
        p_r_err: pr.err,
        p_cf: pcf.value,
        p_cf_err: pcf.err,
        mean_visit_time: mt.value,
        mean_visit_time_err: mt.err,
        mean_visit_time_exact: g.hop_time(),
        mean_collisions_per_visit: mc.value,
        mean_collisions_per_visit_err: mc.err,
        mean_collisions_per_visit_exact: g.collisions_per_hop(),
        particles,
        config: cfg.clone(),
        meta: RunMeta::new(Some(seed), Some(batches as u64), precision, Some(threads)),
    })
}
