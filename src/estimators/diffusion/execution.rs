//! How a diffusion run executes: its jobs (one trajectory each), the observers of a batch, the
//! scalar and SIMD paths, and the parallel execution in index order.

use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::{BatchResult, DiffusionConfig};
use crate::Error;
use crate::engine::checkpoint::{Keeper, LaneCheckpoint, Quota, drive_kept, run_block_kept};
use crate::engine::observe::{EventLanes, Observer};
use crate::engine::options::AuditSpec;
use crate::engine::simd::BLOCK;
use crate::engine::{Engine, Resolved, SimdPath};
use crate::kernel::trap::Trap;
use crate::numbers::lanes::Lanes;
use crate::numbers::precision::{AtPrecision, Precision};
use crate::numbers::real::Real;
use crate::observers::counters::{CounterLaneState, CounterLanes};
use crate::observers::msd::{Msd, MsdLaneState};
use crate::observers::msd_curve::{CurveGrid, CurveLaneState, CurveValues, MsdCurve};
use crate::observers::msd_times::{MsdAtTimes, TimesGrid, TimesLaneState};
use crate::scenes::Scene;
use crate::scenes::lattice::{Basis64, LatticeState, TriangularLattice};
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::triangular::geometry::Geometry;
use crate::scenes::triangular::{TriangularScene, equilibrium_state};
use crate::verification::shadow_audit::{AuditLanes, Auditor};

/// One trajectory of a run: which stream starts it and how many collisions it makes.
#[derive(Debug, Clone, Copy)]
pub(super) struct Job {
    pub(super) seed: u64,
    pub(super) run: u64,
    pub(super) index: u32,
    pub(super) collisions: u64,
}

impl Job {
    /// Its run, index and collisions, as the checkpoint knows it.
    pub(super) fn quota(&self) -> Quota {
        Quota {
            run: self.run,
            index: self.index,
            collisions: self.collisions,
        }
    }

    /// The start: a point of the invariant measure from the trajectory stream `(seed, run,
    /// index)`, its speed normalised at the working precision.
    pub(super) fn start<T: Real>(&self, trap64: &Trap<f64>, ctx: T::Ctx) -> LatticeState<T> {
        self.start_with(ctx, |rng| equilibrium_state(trap64, rng))
    }

    /// The start drawn from `scene`'s invariant measure by the same stream: for the triangular
    /// scene the same state as [`Job::start`].
    pub(super) fn start_in<S: Scene, T: Real>(&self, scene: &S, ctx: T::Ctx) -> LatticeState<T> {
        self.start_with(ctx, |rng| scene.sample(rng))
    }

    fn start_with<T: Real>(
        &self,
        ctx: T::Ctx,
        sample: impl FnOnce(&mut rand_xoshiro::Xoshiro256PlusPlus) -> LatticeState<f64>,
    ) -> LatticeState<T> {
        let mut rng = StreamKey::new(self.seed, Purpose::Trajectory, self.index as u64)
            .in_run(self.run)
            .rng();
        let s64 = sample(&mut rng);
        let mut s = LatticeState::<T>::convert_from_f64(ctx, &s64);
        s.flight.normalise_speed();
        s
    }

    /// The per-event auditor of this job's trajectory in `scene`, on its own audit stream.
    pub(super) fn auditor<S: Scene>(&self, scene: &S, a: AuditSpec) -> Result<Auditor<S>, Error> {
        Auditor::new(
            scene,
            a.rate,
            a.bits,
            StreamKey::new(self.seed, Purpose::Audit, self.index as u64)
                .in_run(self.run)
                .rng(),
        )
    }
}

/// What a diffusion run watches along each trajectory: counters, the MSD, optionally the MSD
/// curve on its logarithmic grid or at the user's times, and optionally the per-event shadow
/// audit of the scene `S`.
pub(super) struct BatchObservers<S: Scene = TriangularScene> {
    counters: CounterLanes,
    msd: Msd,
    curve: Option<MsdCurve>,
    times: Option<MsdAtTimes>,
    audit: Option<AuditLanes<S>>,
}

/// The grid of a run's MSD curve: the logarithmic multiple-τ grid, or the user's times.
#[derive(Debug, Clone)]
pub(super) enum Curve {
    Log(CurveGrid),
    Times(TimesGrid),
}

impl Curve {
    /// The curve's times, increasing.
    pub(super) fn times(&self) -> Vec<f64> {
        match self {
            Curve::Log(g) => g.times(),
            Curve::Times(g) => g.times().to_vec(),
        }
    }
}

/// Where a run's trajectories are watched: τ, the fit windows' lags (in units of τ), and the
/// grid of the MSD curve if the run keeps one.
#[derive(Debug, Clone)]
pub(super) struct Watch {
    pub(super) tau: f64,
    pub(super) lags: Vec<usize>,
    pub(super) curve: Option<Curve>,
}

impl<S: Scene> BatchObservers<S> {
    /// The observers of `jobs` in `lanes` lanes; with `audit`, each job's auditor of `scene`.
    pub(super) fn new(
        jobs: &[Job],
        lanes: usize,
        basis: Basis64,
        watch: &Watch,
        audit: Option<(AuditSpec, &S)>,
    ) -> Result<Self, Error> {
        let audit = match audit {
            Some((spec, scene)) => {
                let mut v = Vec::with_capacity(lanes);
                for j in jobs {
                    v.push(Some(j.auditor(scene, spec)?));
                }
                v.resize_with(lanes, || None);
                Some(AuditLanes {
                    lanes: v,
                    error: None,
                })
            }
            None => None,
        };
        Ok(BatchObservers {
            counters: CounterLanes::new(lanes),
            msd: Msd::new(watch.tau, &watch.lags, basis, lanes),
            curve: match &watch.curve {
                Some(Curve::Log(g)) => Some(MsdCurve::new(*g, basis, lanes)),
                _ => None,
            },
            times: match &watch.curve {
                Some(Curve::Times(g)) => Some(MsdAtTimes::new(g.clone(), basis, lanes)),
                _ => None,
            },
            audit,
        })
    }

    /// The results of the jobs, lane by lane.
    pub(super) fn results(mut self, jobs: &[Job], seconds: f64) -> Result<Vec<BatchResult>, Error> {
        if let Some(e) = self.audit.as_mut().and_then(|a| a.error.take()) {
            return Err(e);
        }
        let mut audits = self.audit.take().map(|a| a.lanes);
        Ok(jobs
            .iter()
            .enumerate()
            .map(|(l, j)| BatchResult {
                index: j.index,
                counters: self.counters.lane(l),
                lags: self.msd.lags().to_vec(),
                msd: self.msd.values(l),
                curve: self.curve_values(l),
                seconds,
                audit: audits.as_mut().and_then(|a| a[l].take()).map(|a| a.summary),
            })
            .collect())
    }
}

impl<S: Scene> BatchObservers<S> {
    /// Lane `l`'s MSD curve, on whichever grid the run keeps one.
    fn curve_values(&self, l: usize) -> Option<CurveValues> {
        if let Some(c) = &self.curve {
            return Some(c.values(l));
        }
        self.times.as_ref().map(|c| {
            let v = c.values(l);
            CurveValues {
                msd: v.msd,
                vacf: v.vacf,
                green_kubo: v.green_kubo,
                vacf_x: v.vacf_x,
                vacf_y: v.vacf_y,
            }
        })
    }
}

/// What a diffusion trajectory's observers have accumulated (the per-event audit is not saved:
/// with it, only finished batches are kept).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DiffusionLane {
    counters: CounterLaneState,
    msd: MsdLaneState,
    /// The MSD curve's lane (runs that keep one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    curve: Option<CurveLaneState>,
    /// The lane of the MSD at the user's times (runs that keep them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    times: Option<TimesLaneState>,
}

/// The checkpoint of a diffusion run: finished batches and trajectories in flight.
pub(super) type DiffusionKeeper = Keeper<BatchResult, DiffusionLane>;

impl<S: Scene> LaneCheckpoint for BatchObservers<S> {
    type Lane = DiffusionLane;
    fn save_lane(&self, l: usize) -> DiffusionLane {
        DiffusionLane {
            counters: self.counters.lane_state(l),
            msd: self.msd.lane_state(l),
            curve: self.curve.as_ref().map(|c| c.lane_state(l)),
            times: self.times.as_ref().map(|c| c.lane_state(l)),
        }
    }
    fn restore_lane(&mut self, l: usize, saved: &DiffusionLane) -> Result<(), Error> {
        self.counters.set_lane_state(l, &saved.counters)?;
        self.msd.set_lane_state(l, &saved.msd)?;
        let other =
            || Error::Invalid("a saved trajectory kept another MSD grid than this run's".into());
        match (self.curve.as_mut(), &saved.curve) {
            (Some(c), Some(s)) => c.set_lane_state(l, s)?,
            (None, None) => {}
            _ => return Err(other()),
        }
        match (self.times.as_mut(), &saved.times) {
            (Some(c), Some(s)) => c.set_lane_state(l, s),
            (None, None) => Ok(()),
            _ => Err(other()),
        }
    }
}

impl<const L: usize, S: Scene> Observer<L> for BatchObservers<S> {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        self.counters.observe::<V>(steps);
        self.msd.observe::<V>(steps);
        if let Some(c) = self.curve.as_mut() {
            c.observe::<V>(steps);
        }
        if let Some(c) = self.times.as_mut() {
            c.observe::<V>(steps);
        }
        if let Some(a) = self.audit.as_mut() {
            a.observe::<V>(steps);
        }
    }
}

/// Runs one trajectory on the scalar engine at number type `T`, from its saved state if it was
/// in flight, saving it at `keep`'s interval.
pub(super) fn run_scalar<T: Real>(
    lat: &TriangularLattice<T>,
    trap64: &Trap<f64>,
    job: Job,
    x: &ExecSpec,
    keep: &DiffusionKeeper,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<BatchResult, Error> {
    let start = Instant::now();
    let ctx = lat.trap().a.ctx();
    let scene = audit_scene(trap64, x.audit)?;
    let audit = x.audit.zip(scene.as_ref());
    let mut obs = BatchObservers::new(&[job], 1, lat.basis_f64(), &x.watch, audit)?;
    let begin = || job.start::<T>(trap64, ctx);
    drive_kept(lat, ctx, &job.quota(), begin, &mut obs, keep, progress)?;
    let mut r = obs.results(&[job], start.elapsed().as_secs_f64())?;
    Ok(r.remove(0))
}

/// Runs up to [`BLOCK`] trajectories together on the SIMD engine (`f64`, bit-identical to
/// [`run_scalar`] lane by lane), each from its saved state if it was in flight, saving them at
/// `keep`'s interval.
pub(super) fn run_simd(
    path: SimdPath,
    trap64: &Trap<f64>,
    jobs: &[Job],
    x: &ExecSpec,
    keep: &DiffusionKeeper,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<BatchResult>, Error> {
    let start = Instant::now();
    // The basis the scalar engine's f64 lattice has (`Lattice::basis_f64`).
    let basis = TriangularLattice::from_kernel(trap64.clone()).basis_f64();
    let scene = audit_scene(trap64, x.audit)?;
    let audit = x.audit.zip(scene.as_ref());
    let mut obs = BatchObservers::new(jobs, BLOCK, basis, &x.watch, audit)?;
    let quotas: Vec<Quota> = jobs.iter().map(Job::quota).collect();
    let begin = |l: usize| jobs[l].start(trap64, ());
    run_block_kept(path, trap64, &quotas, begin, &mut obs, keep, progress)?;
    // The block's wall time, shared out: each batch's `seconds` is its part of the block.
    let seconds = start.elapsed().as_secs_f64() / jobs.len() as f64;
    obs.results(jobs, seconds)
}

/// The triangular scene the per-event audit replays (at the run's double w), if there is an audit.
fn audit_scene(
    trap64: &Trap<f64>,
    audit: Option<AuditSpec>,
) -> Result<Option<TriangularScene>, Error> {
    audit.map(|_| TriangularScene::new(trap64.w)).transpose()
}

/// What a run (or runs packed together) at `cfg`'s w and windows needs before its trajectories
/// start: how they execute (the engine that will run them, τ, the MSD lags, the audit) and the
/// geometry.
pub(super) fn setup(
    cfg: &DiffusionConfig,
    engine: Engine,
    threads: usize,
    audit: Option<AuditSpec>,
) -> Result<(ExecSpec, Geometry<f64>), Error> {
    if threads == 0 {
        return Err(Error::Zero { what: "threads" });
    }
    let w = cfg.gap()?;
    let g = Geometry::new(w)?;
    let spec = ExecSpec {
        w,
        w_exact: cfg.table.gap_text().map(str::to_string),
        precision: cfg.precision,
        engine: engine.resolve(cfg.precision == Precision::F64)?,
        threads,
        watch: Watch {
            tau: g.hop_time(),
            lags: cfg.lags(),
            curve: curve_grid(
                &cfg.msd_grid,
                g.mean_free_path(),
                cfg.collisions,
                cfg.batches,
            ),
        },
        audit,
    };
    Ok((spec, g))
}

/// How the trajectories of [`execute`] run.
pub(super) struct ExecSpec {
    pub(super) w: f64,
    /// The gap as given, for MPFR runs ([`crate::numbers::exact::param_at`]).
    pub(super) w_exact: Option<String>,
    pub(super) precision: Precision,
    pub(super) engine: Resolved,
    pub(super) threads: usize,
    pub(super) watch: Watch,
    pub(super) audit: Option<AuditSpec>,
}

/// The grid of the MSD curve of a run of `collisions` in `batches` at mean free path `ell`
/// (`None` on the fit grid): the logarithmic grid from ⟨ℓ⟩/8, inside the first flight, on to a
/// hundredth of a batch's trajectory, or the user's times with origins every ⟨ℓ⟩.
pub(super) fn curve_grid(
    grid: &super::MsdGrid,
    ell: f64,
    collisions: u64,
    batches: u32,
) -> Option<Curve> {
    if let Some(times) = grid.times() {
        return Some(Curve::Times(TimesGrid::new(times, ell)));
    }
    let per_batch = collisions as f64 / f64::from(batches.max(1));
    (*grid == super::MsdGrid::Log).then(|| {
        Curve::Log(CurveGrid::reaching(
            ell / 8.0,
            per_batch * ell / super::config::CURVE_WINDOWS,
        ))
    })
}

/// Runs `jobs` in blocks of [`BLOCK`] on `pool`, each block by `run` (the SIMD engine's lanes),
/// handing each finished batch to `keep` at once; results in job order.
pub(super) fn in_blocks(
    pool: &rayon::ThreadPool,
    jobs: &[Job],
    keep: &DiffusionKeeper,
    run: impl Fn(&[Job]) -> Result<Vec<BatchResult>, Error> + Sync,
) -> Result<Vec<BatchResult>, Error> {
    let blocks: Vec<&[Job]> = jobs.chunks(BLOCK).collect();
    let out: Vec<Vec<BatchResult>> = pool.install(|| {
        blocks
            .par_iter()
            .map(|b| {
                let r = run(b)?;
                for (j, x) in b.iter().zip(&r) {
                    keep.finish(&j.quota(), x)?;
                }
                Ok(r)
            })
            .collect::<Result<_, Error>>()
    })?;
    Ok(out.into_iter().flatten().collect())
}

/// Runs `jobs` on `spec.threads` threads — one job per task on the scalar engine, blocks of
/// [`BLOCK`] jobs on the SIMD engine — handing each finished result to `keep` at once (and the
/// trajectories in flight at its interval). Results come back in job order.
pub(super) fn execute(
    jobs: &[Job],
    spec: ExecSpec,
    keep: &DiffusionKeeper,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<BatchResult>, Error> {
    let quotas: Vec<u64> = jobs.iter().map(|j| j.collisions).collect();
    crate::engine::check_quotas(&quotas)?;
    let pool = crate::engine::parallel::thread_pool(spec.threads)?;
    let trap64 = Trap::new(spec.w)?;
    match spec.engine {
        Resolved::Simd(path) => in_blocks(&pool, jobs, keep, |b| {
            run_simd(path, &trap64, b, &spec, keep, progress)
        }),
        Resolved::Scalar => spec.precision.dispatch(RunScalar {
            jobs,
            spec: &spec,
            trap64: &trap64,
            pool: &pool,
            keep,
            progress,
        }),
    }
}

/// The jobs on the scalar engine, at the number type of the run's precision.
pub(super) struct RunScalar<'a> {
    jobs: &'a [Job],
    spec: &'a ExecSpec,
    trap64: &'a Trap<f64>,
    pool: &'a rayon::ThreadPool,
    keep: &'a DiffusionKeeper,
    progress: &'a (dyn Fn(u64) + Sync),
}

impl AtPrecision for RunScalar<'_> {
    type Output = Result<Vec<BatchResult>, Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Self::Output {
        let w =
            crate::numbers::exact::param_at::<T>(ctx, self.spec.w, self.spec.w_exact.as_deref())?;
        let lat = TriangularLattice::new(w)?;
        self.pool.install(|| {
            self.jobs
                .par_iter()
                .map(|&j| {
                    let r = run_scalar(&lat, self.trap64, j, self.spec, self.keep, self.progress)?;
                    self.keep.finish(&j.quota(), &r)?;
                    Ok(r)
                })
                .collect()
        })
    }
}
