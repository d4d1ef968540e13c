//! A plain diffusion run — one configuration's batches, kept in its checkpoint, resumed, or
//! continued from the pilot that planned it — and how it stands to a planned run.

use std::time::Instant;

use super::execution::{DiffusionKeeper, DiffusionLane, Job, execute, setup};
use super::plan::{self, Pilot};
use super::{
    BatchResult, CHECKPOINT_KIND, DiffusionConfig, DiffusionReport, check_audit,
    check_resumed_identities, open_keeper, resumed, summarise, work_lower,
};
use crate::Error;
use crate::engine::checkpoint::{Carry, Quota};
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::engine::work::Work;

/// How a plain run stands to a planned one (`rel_err`, [`plan`]).
pub(super) enum Planned {
    /// A run on its own.
    Alone,
    /// The pilot of a planned run: nothing is kept on disk, and its trajectories are captured
    /// for the planned run to continue.
    Pilot,
    /// The run a pilot planned: its checkpoint's header records the pilot, and it continues the
    /// pilot's trajectories (where it holds no later state of them).
    After(Pilot, Option<Carry<DiffusionLane>>),
}

/// The trajectories of a pilot, for the run it plans.
pub(super) type PilotCarry = Carry<DiffusionLane>;

/// Runs `cfg` (validated, without `rel_err`) as `planned` says: the result, and a pilot's
/// trajectories.
///
/// # Errors
/// As [`super::run`].
pub(super) fn run(
    cfg: &DiffusionConfig,
    options: &RunOptions,
    planned: Planned,
) -> Result<(DiffusionReport, Option<PilotCarry>), Error> {
    // Below w_inf a flight crosses at most a few traps: the collisions are the work.
    Work::new(
        "diffusion",
        work_lower(cfg.precision),
        cfg.collisions as f64,
    )
    .simd()
    .at(cfg.precision)
    .audited(options.audit)
    .check(options.threads)?;
    check_audit(options, cfg.precision)?;
    let (spec, g) = setup(cfg, options.engine, options.threads, options.audit)?;
    let (resolved, tau) = (spec.engine, spec.watch.tau);
    let start = Instant::now();
    let jobs: Vec<Job> = cfg.jobs().collect();
    let pilot = matches!(planned, Planned::Pilot);
    let (keep, carried) = keeper(cfg, options, planned, &jobs, resolved)?;
    resumed::recheck_one_batch(
        &keep,
        &jobs,
        std::slice::from_ref(cfg),
        (options.engine, options.stop.as_ref()),
        options.resume.as_deref(),
    )?;
    let todo: Vec<Job> = (jobs.iter().copied())
        .filter(|j| !keep.is_finished(&j.quota()))
        .collect();
    let new = execute(&todo, spec, &keep, options.progress)?;
    // The trajectories resumed in flight had made part of their collisions earlier: in earlier
    // runs, or in the pilot (`carried`, whose time is not this run's).
    let in_flight = keep.in_flight_collisions(None);
    let run_now =
        (new.iter().map(|b| b.counters.collisions).sum::<u64>()).saturating_sub(in_flight);
    let mut done: Vec<BatchResult> = keep.finished().map(|(_, b)| b.clone()).collect();
    let resumed = done.len() as u32;
    let earlier = in_flight - carried.1 + done.iter().map(|b| b.counters.collisions).sum::<u64>();
    done.extend(new);
    done.sort_by_key(|b| b.index);
    let seconds = start.elapsed().as_secs_f64();
    let threads = options.threads;
    let mut rep = summarise(cfg, &g, tau, &done, threads, seconds, resumed, run_now)?;
    rep.meta = rep.meta.with_engine(resolved);
    rep.resumed_collisions = earlier;
    rep.plan = plan::next_decade(&rep, &done);
    if resumed > 0 || keep.in_flight_count() > carried.0 {
        check_resumed_identities(&rep, options.resume.as_deref())?;
    }
    Ok((rep, pilot.then(|| keep.carry())))
}

/// The keeper of a run of `jobs` as `planned` says, and the trajectories and collisions it
/// took from a pilot.
fn keeper(
    cfg: &DiffusionConfig,
    options: &RunOptions,
    planned: Planned,
    jobs: &[Job],
    resolved: crate::engine::Resolved,
) -> Result<(DiffusionKeeper, (usize, u64)), Error> {
    let quotas: Vec<Quota> = jobs.iter().map(Job::quota).collect();
    // The header records the engine that runs, not the default.
    let mut meta = RunMeta::new(
        Some(cfg.seed),
        Some(cfg.batches as u64),
        cfg.precision,
        None,
    )
    .with_engine(resolved);
    let carry = match planned {
        Planned::Pilot => {
            let k = DiffusionKeeper::capturing(&quotas).watching(options.stop.as_ref());
            return Ok((k, (0, 0)));
        }
        Planned::Alone => None,
        Planned::After(p, carry) => {
            meta.pilot = serde_json::to_value(p).ok();
            carry
        }
    };
    let mut keep = open_keeper(options, CHECKPOINT_KIND, cfg, Some(meta), jobs)?;
    let carried = match carry {
        Some(c) => keep.continue_from(c)?,
        None => (0, 0),
    };
    (options.progress)(carried.1);
    Ok((keep, carried))
}
