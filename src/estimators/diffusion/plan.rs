//! Precision planning: how many collisions a relative error of D needs and how long they take
//! here, and the run that stops at a chosen relative error (`proofs-notes/precision-planning.md`).
//!
//! At a fixed number of batches B, D_err is the standard error of B batch slopes, each the mean of
//! a trajectory N/B collisions long whose variance falls as B/N once the trajectory is much
//! longer than the correlation time (the fit window, a few hundred collisions): the relative
//! error goes as 1/√N, so a run of N collisions with relative error r gives the constant r²N, and
//! a target ρ needs N·(r/ρ)². That constant is itself estimated from B batches: its relative
//! standard error is about √(2/(B − 1)) (25 % at B = 32), so a planned run lands within about
//! 1/√(2(B − 1)) (13 %) of the target relative error, not exactly on it.
//!
//! A planned run ([`DiffusionConfig::rel_err`]) is two plain runs of the same seed and batches: a
//! pilot of `collisions` (no checkpoint of its own), then, if the pilot's error is above the
//! target, the planned size, which continues the pilot's trajectories instead of computing them
//! again and records the pilot in its checkpoint's header, so that a resumed planned run does not
//! run the pilot again. The result is the second run, bit for bit the plain run of that size,
//! with the pilot recorded beside it.

use serde::{Deserialize, Serialize};

use super::plain::{PilotCarry, Planned};
use super::{BatchResult, DiffusionConfig, DiffusionReport};
use crate::Error;
use crate::engine::options::RunOptions;

/// The pilot's size when a planned run's collisions are not given: at w = 0.1 it measures D to
/// about 0.15 % in about 1.5 s on 2 cores.
pub const DEFAULT_PILOT: u64 = 200_000_000;

/// The collisions of a run whose collisions were not given: the pilot's ([`DEFAULT_PILOT`]) when
/// it is planned for a relative error, else the plain run's default
/// ([`DiffusionConfig::new`]'s 2·10⁹).
pub fn default_collisions(rel_err: Option<f64>) -> u64 {
    match rel_err {
        Some(_) => DEFAULT_PILOT,
        None => DiffusionConfig::new(1.0).collisions,
    }
}

/// The relative errors a run can be planned for: below 10⁻⁷ no run finishes (10¹⁸ collisions
/// and more at any gap); above 1/2 the error bar is as large as D.
pub const REL_ERR_RANGE: (f64, f64) = (1e-7, 0.5);

/// How many collisions a relative error needs and how long they take at a run's speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Plan {
    /// The relative error D_err/D planned for.
    pub rel_err: f64,
    /// The collisions that give it, in the run's number of batches (two significant digits).
    pub collisions: u64,
    /// How long they take at the run's own speed (seconds, on its threads).
    pub seconds: f64,
}

/// The pilot of a planned run (`--rel-err`), recorded in its result.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Pilot {
    /// The relative error asked for.
    pub rel_err_target: f64,
    /// The pilot's collisions (same seed and batches as the result).
    pub collisions: u64,
    /// The pilot's relative error D_err/D.
    pub rel_err: f64,
    /// The pilot's seconds.
    pub seconds: f64,
    /// The collisions planned from it (the result's, unless the pilot already met the target).
    pub planned_collisions: u64,
    /// Whether the planned run continued the pilot's trajectories (their first
    /// `collisions` / batches collisions each) instead of computing them again: with the MSD on
    /// the fit grid and no per-event audit, and not when the pilot was taken from the planned
    /// run's checkpoint. Either way the result has the same bits.
    #[serde(default)]
    pub continued: bool,
}

/// Refuses a target outside [`REL_ERR_RANGE`] (or not a number).
///
/// # Errors
/// The target, with the valid range.
pub fn check_rel_err(target: f64) -> Result<(), Error> {
    let (lo, hi) = REL_ERR_RANGE;
    if target.is_finite() && (lo..=hi).contains(&target) {
        return Ok(());
    }
    Err(Error::out_of_range(
        "rel_err",
        target,
        format!("the relative error of D to plan for must lie in [{lo:e}, {hi}] (1e-4 is 0.01 %)"),
    ))
}

/// The collisions a run of `collisions` in `batches` batches that gave the relative error
/// `achieved` needs for the relative error `target`: N·(achieved/target)², rounded up to two
/// significant digits and to a multiple of the batches. `None` beyond 2⁶⁴ − 1 or when `achieved`
/// is not a positive number.
pub fn collisions_for(collisions: u64, batches: u32, achieved: f64, target: f64) -> Option<u64> {
    if !(achieved > 0.0 && achieved.is_finite() && target > 0.0) {
        return None;
    }
    let n = collisions as f64 * (achieved / target).powi(2);
    let unit = 10f64.powi(n.log10().floor() as i32 - 1).max(1.0);
    let n = (n / unit).ceil() * unit;
    let b = batches.max(1) as f64;
    let n = (n / b).ceil() * b;
    (n < u64::MAX as f64).then_some(n as u64)
}

/// The plan for the next decade below a run's own relative error (0.046 % plans for 0.01 %),
/// at the run's speed — or, where this invocation ran nothing (a finished run reopened), at the
/// speed its batches recorded ([`recorded_speed`]); `None` without a positive error or speed.
pub fn next_decade(rep: &DiffusionReport, done: &[BatchResult]) -> Option<Plan> {
    let achieved = rep.D_err / rep.D.abs();
    if !(achieved > 0.0 && achieved.is_finite()) {
        return None;
    }
    let decade = 10f64.powi(achieved.log10().ceil() as i32 - 1);
    let batches = rep.meta.batches.unwrap_or(2) as u32;
    let collisions = collisions_for(rep.collisions, batches, achieved, decade)?;
    let speed = match rep.collisions_per_second {
        s if s > 0.0 => s,
        _ => recorded_speed(done, rep.meta.threads.unwrap_or(1)),
    };
    (speed > 0.0 && speed.is_finite()).then(|| Plan {
        rel_err: decade,
        collisions,
        seconds: collisions as f64 / speed,
    })
}

/// The speed the `batches` recorded, on `threads` threads: their collisions over their seconds
/// (each batch's seconds are its thread's time, or its share of its SIMD block's) times the
/// threads. A batch resumed from a state in flight recorded only its last invocation's time, so
/// this overstates the speed by at most the share of such batches.
pub fn recorded_speed(batches: &[BatchResult], threads: usize) -> f64 {
    let collisions: u64 = batches.iter().map(|b| b.counters.collisions).sum();
    let seconds: f64 = batches.iter().map(|b| b.seconds).sum();
    collisions as f64 / seconds * threads as f64
}

/// A planned run's pilot: its record, its result (`None` when a resumed planned run found the
/// pilot in its checkpoint's header instead of running it), and its trajectories for the planned
/// run to continue.
pub struct PilotRun {
    /// The pilot's record.
    pub pilot: Pilot,
    /// The pilot's own result.
    pub report: Option<DiffusionReport>,
    /// The pilot's trajectories.
    carry: Option<PilotCarry>,
}

/// Runs the pilot of the planned run `cfg` (its `collisions`, without checkpoint or audit) and
/// plans the target `cfg.rel_err` from it — or takes the pilot from the header of the planned
/// run's checkpoint (`options.resume`) if that run was started, so that a resumed planned run
/// does not run its pilot again.
///
/// # Errors
/// As [`super::run`]; a configuration without `rel_err` is refused.
pub fn pilot(cfg: &DiffusionConfig, options: &RunOptions) -> Result<PilotRun, Error> {
    let target = cfg
        .rel_err
        .ok_or_else(|| Error::missing("rel_err", "a pilot needs the relative error to plan for"))?;
    check_rel_err(target)?;
    cfg.validate()?;
    if let Some(pilot) = kept_pilot(cfg, options) {
        return Ok(PilotRun {
            pilot,
            report: None,
            carry: None,
        });
    }
    let plain = DiffusionConfig {
        rel_err: None,
        ..cfg.clone()
    };
    let quiet = RunOptions {
        resume: None,
        audit: None,
        ..options.clone()
    };
    let (rep, carry) = super::plain::run(&plain, &quiet, Planned::Pilot)?;
    let achieved = rep.D_err / rep.D.abs();
    let planned = collisions_for(cfg.collisions, cfg.batches, achieved, target).ok_or_else(|| {
        Error::parameter(
            "rel_err",
            target,
            format!(
                "the pilot's relative error {achieved:.3e} cannot be planned down to it: it would \
                 need more than 2^64 collisions"
            ),
        )
    })?;
    let pilot = Pilot {
        rel_err_target: target,
        collisions: cfg.collisions,
        rel_err: achieved,
        seconds: rep.seconds,
        planned_collisions: planned.max(cfg.collisions),
        continued: false,
    };
    Ok(PilotRun {
        pilot,
        report: Some(rep),
        carry,
    })
}

/// The pilot recorded in the header of the checkpoint at `options.resume`, if it is this planned
/// run's: the same target and pilot size, and a planned size the pilot's error gives. The
/// journal's own open then checks that the checkpoint is the planned run's.
fn kept_pilot(cfg: &DiffusionConfig, options: &RunOptions) -> Option<Pilot> {
    let meta = crate::engine::resume::header_meta(options.resume.as_deref()?)?;
    let p: Pilot = serde_json::from_value(meta.pilot?).ok()?;
    let again = collisions_for(p.collisions, cfg.batches, p.rel_err, p.rel_err_target)?;
    let ours = p.rel_err_target == cfg.rel_err? && p.collisions == cfg.collisions;
    (ours && p.planned_collisions == again.max(p.collisions) && p.seconds >= 0.0).then_some(p)
}

/// The plan alone (`--plan-only`): the pilot of the planned run `cfg`, whose result it returns
/// with the pilot recorded and `plan` the plan for the target — its collisions, and how long they
/// take at the pilot's speed (a loaded machine runs the planned run slower; the progress of the
/// planned run estimates its end from its own speed). Nothing is kept on disk.
///
/// # Errors
/// As [`pilot`]; a checkpoint or per-event audit in `options` (a pilot keeps and audits nothing).
pub fn plan_only(cfg: &DiffusionConfig, options: &RunOptions) -> Result<DiffusionReport, Error> {
    if options.resume.is_some() || options.audit.is_some() {
        return Err(Error::parameter(
            "plan_only",
            "true",
            "the plan alone runs the pilot only, which keeps no checkpoint and has no audit: \
             drop checkpoint and audit, or plan_only",
        ));
    }
    let first = pilot(cfg, options)?;
    let mut rep = first
        .report
        .ok_or_else(|| Error::Failed("a pilot without a checkpoint gave no result".into()))?;
    let p = first.pilot;
    rep.plan = Some(Plan {
        rel_err: p.rel_err_target,
        collisions: p.planned_collisions,
        seconds: p.planned_collisions as f64 / rep.collisions_per_second,
    });
    rep.pilot = Some(p);
    Ok(rep)
}

/// The plain run a pilot plans: `cfg` at the planned size, without `rel_err`; `None` when the
/// pilot itself met the target (it is then the result).
pub fn planned_config(cfg: &DiffusionConfig, pilot: &Pilot) -> Option<DiffusionConfig> {
    (pilot.rel_err > pilot.rel_err_target).then(|| DiffusionConfig {
        collisions: pilot.planned_collisions,
        rel_err: None,
        ..cfg.clone()
    })
}

/// A planned run: the pilot, then the planned plain run (with `options`' checkpoint and audit),
/// whose result records the pilot.
///
/// # Errors
/// As [`super::run`].
pub fn run(cfg: &DiffusionConfig, options: &RunOptions) -> Result<DiffusionReport, Error> {
    finish(cfg, pilot(cfg, options)?, options)
}

/// After the pilot `first` of `cfg`: the run it plans, continuing the pilot's trajectories where
/// their observers are the planned run's (the fit grid; no per-event audit, which replays a
/// trajectory from its start), or the pilot itself where it met the target (run again with
/// `options`' audit if one is asked for), with the pilot recorded.
///
/// # Errors
/// As [`super::run`].
pub fn finish(
    cfg: &DiffusionConfig,
    first: PilotRun,
    options: &RunOptions,
) -> Result<DiffusionReport, Error> {
    let mut pilot = first.pilot;
    let ran_now = first.report.is_some();
    let mut rep = match (planned_config(cfg, &pilot), first.report) {
        (Some(full), _) => {
            let same_observers = full.msd_grid == super::MsdGrid::Fit && options.audit.is_none();
            let carry = first.carry.filter(|_| same_observers);
            // A pilot taken from the checkpoint's header keeps what it recorded.
            if ran_now {
                pilot.continued = carry.is_some();
            }
            super::plain::run(&full, options, Planned::After(pilot, carry))?.0
        }
        (None, Some(rep)) if options.audit.is_none() => rep,
        (None, _) => super::run(
            &DiffusionConfig {
                rel_err: None,
                ..cfg.clone()
            },
            options,
        )?,
    };
    rep.pilot = Some(pilot);
    Ok(rep)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// N·(r/ρ)² rounded up to two significant digits, then to a multiple of the batches.
    #[test]
    fn collisions_round_up_to_two_digits_and_whole_batches() {
        // 2e8 · (0.156/0.05)² = 1.947e9 → 2.0e9.
        assert_eq!(
            collisions_for(200_000_000, 32, 0.00156, 0.0005),
            Some(2_000_000_000)
        );
        // 1000 · 1.3² = 1690 → 1700 → a multiple of 32: 1728.
        assert_eq!(collisions_for(1000, 32, 1.3, 1.0), Some(1728));
        // Small counts: the unit is one collision.
        assert_eq!(collisions_for(7, 2, 1.0, 1.0), Some(8));
        assert_eq!(collisions_for(u64::MAX / 2, 2, 1.0, 1e-3), None);
        assert_eq!(collisions_for(10, 2, 0.0, 1e-3), None);
        assert_eq!(collisions_for(10, 2, f64::NAN, 1e-3), None);
    }

    #[test]
    fn targets_outside_the_range_are_refused_naming_it() {
        for bad in [0.0, -1e-3, 0.51, 1e-8, f64::NAN, f64::INFINITY] {
            let e = check_rel_err(bad).unwrap_err().to_string();
            assert!(e.contains("[1e-7, 0.5]"), "{e}");
        }
        for good in [1e-7, 1e-4, 0.5] {
            check_rel_err(good).unwrap();
        }
    }
}
