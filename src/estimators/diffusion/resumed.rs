//! What a resumed run checks before it trusts its checkpoint beyond the digests, which anyone can
//! recompute: one finished batch, drawn at random when the run starts, is run again from its seed
//! to its first mark and from its second mark to its end, and must give the recorded state and
//! values to the bit ([`crate::engine::checkpoint::recheck_one_batch`];
//! `proofs-notes/checkpoints.md`, claim 3).

use std::path::Path;

use super::execution::{DiffusionKeeper, Job, execute, setup};
use super::{BatchResult, DiffusionConfig};
use crate::Error;
use crate::engine::Engine;
use crate::engine::checkpoint::{Quota, recheck_one_batch as recheck};
use crate::engine::options::StopFlag;

/// Checks one finished batch of `keep`, drawn at random (operating-system entropy, so that no
/// one editing the file can know which): the batch's event counters, lags and MSD must be the
/// recorded bits. Nothing to do without finished batches.
///
/// # Errors
/// [`Error::Failed`] naming the checkpoint and the batch when they differ.
pub(super) fn recheck_one_batch(
    keep: &DiffusionKeeper,
    jobs: &[Job],
    cfgs: &[DiffusionConfig],
    (engine, stop): (Engine, Option<&StopFlag>),
    path: Option<&Path>,
) -> Result<(), Error> {
    let quotas: Vec<Quota> = jobs.iter().map(Job::quota).collect();
    let run = |q: &Quota, k: &DiffusionKeeper| -> Result<BatchResult, Error> {
        let job = jobs.iter().find(|j| j.run == q.run && j.index == q.index);
        let cfg = cfgs.iter().find(|c| c.run == q.run);
        let (Some(job), Some(cfg)) = (job, cfg) else {
            return Err(Error::Failed(format!(
                "run {} has no batch {}",
                q.run, q.index
            )));
        };
        let job = Job {
            collisions: q.collisions,
            ..*job
        };
        let (spec, _) = setup(cfg, engine, 1, None)?;
        let mut r = execute(std::slice::from_ref(&job), spec, k, &|_| {})?;
        r.pop()
            .ok_or_else(|| Error::Failed("a re-checked batch gave no result".into()))
    };
    let values = |b: &BatchResult| serde_json::to_value((&b.counters, &b.lags, &b.msd)).ok();
    let same = |a: &BatchResult, b: &BatchResult| values(a).is_some() && values(a) == values(b);
    recheck(keep, &quotas, stop, &run, &same, (path, "values"))
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;

    use super::*;
    use crate::engine::checkpoint::{MARK, recheck_one_batch as recheck};
    use crate::engine::options::RunOptions;

    /// The check of a resumed run costs at most 2·MARK collisions however long its batches: it
    /// runs one batch from its seed to its first mark and from its second mark to its end, and
    /// nothing else; and it passes on an honest checkpoint.
    #[test]
    fn a_resumed_run_checks_a_batch_in_two_marks_of_collisions() {
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("c.jsonl");
        let cfg = DiffusionConfig {
            collisions: 4_000_000,
            batches: 2,
            ..DiffusionConfig::new(0.2)
        };
        let opts = RunOptions {
            resume: Some(path.clone()),
            ..RunOptions::default()
        };
        crate::estimators::diffusion::run(&cfg, &opts).unwrap();
        let jobs: Vec<Job> = cfg.jobs().collect();
        let quotas: Vec<Quota> = jobs.iter().map(Job::quota).collect();
        let keep =
            super::super::open_keeper(&opts, super::super::CHECKPOINT_KIND, &cfg, None, &jobs)
                .unwrap();
        assert_eq!(keep.finished().count(), 2);
        // Each piece the check runs: (collisions asked for, collisions it starts from).
        let pieces = Mutex::new(Vec::new());
        let run = |q: &Quota, k: &DiffusionKeeper| -> Result<BatchResult, Error> {
            let from = k.resumed(q).map_or(0, |f| f.collisions);
            pieces.lock().unwrap().push((q.collisions, from));
            let job = jobs.iter().find(|j| j.index == q.index).unwrap();
            let job = Job {
                collisions: q.collisions,
                ..*job
            };
            let (spec, _) = setup(&cfg, Engine::Auto, 1, None)?;
            Ok(execute(&[job], spec, k, &|_| {})?.remove(0))
        };
        let values = |b: &BatchResult| serde_json::to_value((&b.counters, &b.msd)).unwrap();
        let same = |a: &BatchResult, b: &BatchResult| values(a) == values(b);
        recheck(&keep, &quotas, None, &run, &same, (Some(&path), "values")).unwrap();
        let pieces = pieces.into_inner().unwrap();
        let n = cfg.collisions / 2;
        assert_eq!(pieces, vec![(MARK, 0), (n, n - MARK)], "{pieces:?}");
        let work: u64 = pieces.iter().map(|(to, from)| to - from).sum();
        assert!(work <= 2 * MARK);
    }
}
