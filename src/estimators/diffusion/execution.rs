//! How a diffusion run executes: its jobs (one trajectory each), the observers of a batch, the
//! scalar and SIMD paths, and the parallel execution in index order.

use std::time::Instant;

use rayon::prelude::*;

use super::{BatchResult, DiffusionConfig};
use crate::engine::observe::{EventLanes, Observer};
use crate::engine::options::AuditSpec;
use crate::engine::simd::BLOCK;
use crate::engine::{drive, run_block, Engine, Resolved, SimdPath};
use crate::kernel::trap::Trap;
use crate::numbers::lanes::Lanes;
use crate::numbers::precision::{AtPrecision, Precision};
use crate::numbers::real::Real;
use crate::observers::counters::CounterLanes;
use crate::observers::msd::Msd;
use crate::scenes::lattice::{Basis64, LatticeState, TriangularLattice};
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::triangular::geometry::Geometry;
use crate::scenes::triangular::{equilibrium_state, TriangularScene};
use crate::verification::shadow_audit::{AuditLanes, Auditor};
use crate::Error;

/// One trajectory of a run: which stream starts it and how many collisions it makes.
#[derive(Debug, Clone, Copy)]
pub(super) struct Job {
    pub(super) seed: u64,
    pub(super) run: u64,
    pub(super) index: u32,
    pub(super) collisions: u64,
}

impl Job {
    /// The start: a point of the invariant measure from the trajectory stream `(seed, run,
    /// index)`, its speed normalised at the working precision.
    pub(super) fn start<T: Real>(&self, trap64: &Trap<f64>, ctx: T::Ctx) -> LatticeState<T> {
        let mut rng = StreamKey::new(self.seed, Purpose::Trajectory, self.index as u64)
            .in_run(self.run)
            .rng();
        let s64 = equilibrium_state(trap64, &mut rng);
        let mut s = LatticeState::<T>::convert_from_f64(ctx, &s64);
        s.flight.normalise_speed();
        s
    }

    pub(super) fn auditor(
        &self,
        trap64: &Trap<f64>,
        audit: Option<AuditSpec>,
    ) -> Result<Option<Auditor<TriangularScene>>, Error> {
        audit
            .map(|a| {
                Auditor::new(
                    &TriangularScene::new(trap64.w)?,
                    a.rate,
                    a.bits,
                    StreamKey::new(self.seed, Purpose::Audit, self.index as u64)
                        .in_run(self.run)
                        .rng(),
                )
            })
            .transpose()
    }
}

/// What a diffusion run watches along each trajectory: counters, the MSD, and optionally the
/// per-event shadow audit.
pub(super) struct BatchObservers {
    counters: CounterLanes,
    msd: Msd,
    audit: Option<AuditLanes<TriangularScene>>,
}

impl BatchObservers {
    pub(super) fn new(
        jobs: &[Job],
        lanes: usize,
        trap64: &Trap<f64>,
        basis: Basis64,
        tau: f64,
        lags: &[usize],
        audit: Option<AuditSpec>,
    ) -> Result<Self, Error> {
        let audit = match audit {
            Some(_) => {
                let mut v = Vec::with_capacity(lanes);
                for j in jobs {
                    v.push(j.auditor(trap64, audit)?);
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
            msd: Msd::new(tau, lags, basis, lanes),
            audit,
        })
    }

    /// The results of the jobs, lane by lane.
    pub(super) fn results(mut self, jobs: &[Job], seconds: f64) -> Result<Vec<BatchResult>, Error> {
        if let Some(e) = self.audit.as_mut().and_then(|a| a.error.take()) {
            return Err(e);
        }
        let mut audits = self.audit.map(|a| a.lanes);
        Ok(jobs
            .iter()
            .enumerate()
            .map(|(l, j)| BatchResult {
                index: j.index,
                counters: self.counters.lane(l),
                lags: self.msd.lags().to_vec(),
                msd: self.msd.values(l),
                seconds,
                audit: audits.as_mut().and_then(|a| a[l].take()).map(|a| a.summary),
            })
            .collect())
    }
}

impl<const L: usize> Observer<L> for BatchObservers {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        self.counters.observe::<V>(steps);
        self.msd.observe::<V>(steps);
        if let Some(a) = self.audit.as_mut() {
            a.observe::<V>(steps);
        }
    }
}

/// Runs one trajectory on the scalar engine at number type `T`.
pub(super) fn run_scalar<T: Real>(
    lat: &TriangularLattice<T>,
    trap64: &Trap<f64>,
    job: Job,
    tau: f64,
    lags: &[usize],
    audit: Option<AuditSpec>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<BatchResult, Error> {
    let start = Instant::now();
    let mut s = job.start::<T>(trap64, lat.trap().a.ctx());
    let mut obs = BatchObservers::new(&[job], 1, trap64, lat.basis_f64(), tau, lags, audit)?;
    drive(lat, &mut s, job.collisions, &mut obs, progress)?;
    let mut r = obs.results(&[job], start.elapsed().as_secs_f64())?;
    Ok(r.remove(0))
}

/// Runs up to [`BLOCK`] trajectories together on the SIMD engine (`f64`, bit-identical to
/// [`run_scalar`] lane by lane).
pub(super) fn run_simd(
    path: SimdPath,
    trap64: &Trap<f64>,
    jobs: &[Job],
    tau: f64,
    lags: &[usize],
    audit: Option<AuditSpec>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<BatchResult>, Error> {
    let start = Instant::now();
    let mut states: Vec<LatticeState<f64>> = jobs.iter().map(|j| j.start(trap64, ())).collect();
    let quotas: Vec<u64> = jobs.iter().map(|j| j.collisions).collect();
    // The basis the scalar engine's f64 lattice has (`Lattice::basis_f64`).
    let basis = TriangularLattice::from_kernel(trap64.clone()).basis_f64();
    let mut obs = BatchObservers::new(jobs, BLOCK, trap64, basis, tau, lags, audit)?;
    run_block(path, trap64, &mut states, &quotas, &mut obs, progress)?;
    // The block's wall time, shared out: each batch's `seconds` is its part of the block.
    let seconds = start.elapsed().as_secs_f64() / jobs.len() as f64;
    obs.results(jobs, seconds)
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
    let g = Geometry::new(cfg.w)?;
    let spec = ExecSpec {
        w: cfg.w,
        precision: cfg.precision,
        engine: engine.resolve(cfg.precision == Precision::F64)?,
        threads,
        tau: g.hop_time(),
        lags: cfg.lags(),
        audit,
    };
    Ok((spec, g))
}

/// How the trajectories of [`execute`] run.
pub(super) struct ExecSpec {
    pub(super) w: f64,
    pub(super) precision: Precision,
    pub(super) engine: Resolved,
    pub(super) threads: usize,
    pub(super) tau: f64,
    pub(super) lags: Vec<usize>,
    pub(super) audit: Option<AuditSpec>,
}

/// Runs `jobs` on `spec.threads` threads — one job per task on the scalar engine, blocks of
/// [`BLOCK`] jobs on the SIMD engine — handing each finished result to `record` at once.
/// Results come back in job order.
pub(super) fn execute(
    jobs: &[Job],
    spec: ExecSpec,
    record: &(dyn Fn(&Job, &BatchResult) -> Result<(), Error> + Sync),
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<BatchResult>, Error> {
    for j in jobs {
        crate::engine::check_trajectory_length(j.collisions)?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(spec.threads)
        .build()
        .map_err(|e| Error::Failed(format!("thread pool: {e}")))?;
    let trap64 = Trap::new(spec.w)?;
    match spec.engine {
        Resolved::Simd(path) => {
            let blocks: Vec<&[Job]> = jobs.chunks(BLOCK).collect();
            let out: Vec<Vec<BatchResult>> = pool.install(|| {
                blocks
                    .par_iter()
                    .map(|b| {
                        let r =
                            run_simd(path, &trap64, b, spec.tau, &spec.lags, spec.audit, progress)?;
                        for (j, x) in b.iter().zip(&r) {
                            record(j, x)?;
                        }
                        Ok(r)
                    })
                    .collect::<Result<_, Error>>()
            })?;
            Ok(out.into_iter().flatten().collect())
        }
        Resolved::Scalar => spec.precision.dispatch(RunScalar {
            jobs,
            w: spec.w,
            trap64: &trap64,
            tau: spec.tau,
            lags: &spec.lags,
            audit: spec.audit,
            pool: &pool,
            record,
            progress,
        }),
    }
}

/// The jobs on the scalar engine, at the number type of the run's precision.
pub(super) struct RunScalar<'a> {
    jobs: &'a [Job],
    w: f64,
    trap64: &'a Trap<f64>,
    tau: f64,
    lags: &'a [usize],
    audit: Option<AuditSpec>,
    pool: &'a rayon::ThreadPool,
    record: &'a (dyn Fn(&Job, &BatchResult) -> Result<(), Error> + Sync),
    progress: &'a (dyn Fn(u64) + Sync),
}

impl AtPrecision for RunScalar<'_> {
    type Output = Result<Vec<BatchResult>, Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Self::Output {
        let lat = TriangularLattice::new(T::from_f64(ctx, self.w))?;
        self.pool.install(|| {
            self.jobs
                .par_iter()
                .map(|&j| {
                    let r = run_scalar(
                        &lat,
                        self.trap64,
                        j,
                        self.tau,
                        self.lags,
                        self.audit,
                        self.progress,
                    )?;
                    (self.record)(&j, &r)?;
                    Ok(r)
                })
                .collect()
        })
    }
}
