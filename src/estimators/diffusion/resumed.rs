//! What a resumed run checks before it trusts its checkpoint beyond the digests, which anyone can
//! recompute: one finished batch, drawn at random when the run starts, is computed again from its
//! seed and must give the recorded values to the bit (`proofs-notes/checkpoints.md`, claim 3).

use std::path::Path;

use super::execution::{DiffusionKeeper, Job, execute, setup};
use super::{BatchResult, DiffusionConfig};
use crate::Error;
use crate::engine::Engine;
use crate::engine::checkpoint::recomputed_differs;

/// Re-runs one finished batch of `keep`, drawn at random (operating-system entropy, so that no
/// one editing the file can know which), and compares it with the record: the batch's event
/// counters, lags and MSD must be the same bits. Nothing to do without finished batches.
///
/// # Errors
/// [`Error::Failed`] naming the checkpoint and the batch when they differ.
pub(super) fn recheck_one_batch(
    keep: &DiffusionKeeper,
    jobs: &[Job],
    cfgs: &[DiffusionConfig],
    engine: Engine,
    path: Option<&Path>,
) -> Result<(), Error> {
    let Some(((run, _), recorded)) = keep.random_finished() else {
        return Ok(());
    };
    let job = jobs
        .iter()
        .find(|j| j.run == run && j.index == recorded.index);
    let cfg = cfgs.iter().find(|c| c.run == run);
    let (Some(job), Some(cfg)) = (job, cfg) else {
        return Err(Error::Failed(format!(
            "{}: a finished batch (run {run}, batch {}) that this configuration does not have",
            shown(path),
            recorded.index
        )));
    };
    let (spec, _) = setup(cfg, engine, 1, None)?;
    let fresh = execute(
        std::slice::from_ref(job),
        spec,
        &DiffusionKeeper::none(),
        &|_| {},
    )?;
    let values = |b: &BatchResult| serde_json::to_value((&b.counters, &b.lags, &b.msd)).ok();
    if fresh.first().and_then(values) != values(recorded) || values(recorded).is_none() {
        let batch = format!("batch {} of run {run}", recorded.index);
        return Err(recomputed_differs(path, &batch, "values"));
    }
    Ok(())
}

/// The checkpoint's path for messages.
fn shown(path: Option<&Path>) -> String {
    path.map_or_else(|| "the checkpoint".into(), |p| p.display().to_string())
}
