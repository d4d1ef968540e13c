//! A re-run against the record: every field identical, timing and the process's metadata aside.

use serde::Serialize;
use serde_json::Value;

use super::{Checks, Ctx};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;

/// Fields of a result that legitimately differ between two runs of the same configuration: the
/// process's metadata (compared apart: seed, batches and precision must agree) and timing.
const VOLATILE_FIELDS: [&str; 7] = [
    "meta",
    "seconds",
    "collisions_per_second",
    "events_per_second",
    "resumed_batches",
    "resumed_collisions",
    "resumed_points",
];

/// `v` as JSON without the fields that differ between two runs of one configuration.
fn science<T: Serialize>(v: &T) -> Result<Value, Error> {
    let mut v = serde_json::to_value(v).map_err(Error::encode)?;
    if let Some(o) = v.as_object_mut() {
        for k in VOLATILE_FIELDS {
            o.remove(k);
        }
    }
    Ok(v)
}

/// The top-level fields in which `a` and `b` differ, timing and metadata aside.
fn differing_fields<T: Serialize>(a: &T, b: &T) -> Result<Vec<String>, Error> {
    let (a, b) = (science(a)?, science(b)?);
    Ok(match (a.as_object(), b.as_object()) {
        (Some(x), Some(y)) => x
            .iter()
            .filter(|(k, v)| y.get(k.as_str()) != Some(v))
            .map(|(k, _)| k.clone())
            .chain(y.keys().filter(|k| !x.contains_key(*k)).cloned())
            .collect(),
        _ if a != b => vec!["the whole result".into()],
        _ => Vec::new(),
    })
}

/// The fields of `recorded` that differ from `again` (timing and metadata aside), and what of the
/// recorded metadata differs from the seed, batches and precision of `again`'s.
pub(super) fn differing<T: Serialize>(
    recorded: (&T, &RunMeta),
    again: (&T, &RunMeta),
) -> Result<Vec<String>, Error> {
    let mut differ = differing_fields(recorded.0, again.0)?;
    let m = again.1;
    differ.extend(super::meta_problems(
        recorded.1,
        m.seed,
        m.batches,
        &m.precision,
    ));
    Ok(differ)
}

/// The check that the re-run `again` of the recorded configuration gives the recorded result in
/// every field but timing and metadata, and the recorded `meta` the re-run's seed, batches and
/// precision.
fn identical_check<T: Serialize>(
    recorded: (&T, &RunMeta),
    again: (&T, &RunMeta),
    what: &str,
    checks: &mut Checks,
) -> Result<(), Error> {
    let differ = differing(recorded, again)?;
    checks.pass_if(
        differ.is_empty(),
        "reproducibility",
        "the recorded configuration re-run gives the same bits",
        if differ.is_empty() {
            format!("{what} re-run through the library: every field identical (timing and metadata aside)")
        } else {
            format!("{what} re-run through the library: {} differ", differ.join(", "))
        },
        &[("fields_differing", differ.len() as f64)],
    );
    Ok(())
}

/// A result that carries the `meta` block of the process that computed it.
pub(super) trait Recorded: Serialize {
    /// Its metadata.
    fn meta(&self) -> &RunMeta;
}

macro_rules! recorded {
    ($($t:ty),*) => {
        $(impl Recorded for $t {
            fn meta(&self) -> &RunMeta {
                &self.meta
            }
        })*
    };
}

recorded!(
    crate::estimators::sweep::SweepReport,
    crate::estimators::hops::HopsReport,
    crate::estimators::hops::theory::TheoryReport,
    crate::estimators::hops::lattice_walks::LatticeWalkReport,
    crate::estimators::hops::backscatter::BackscatterReport,
    crate::estimators::escape::EscapeReport,
    crate::estimators::escape::survival::SurvivalReport,
    crate::estimators::current::CurrentReport,
    crate::estimators::sweep::driven::DrivenSweepReport,
    crate::estimators::field::FieldReport,
    crate::estimators::sweep::field::FieldSweepReport,
    crate::estimators::diffusion::scene::SceneDiffusionReport
);

/// The re-run check of a whole sweep `recorded` of `points` points (`units` collisions in all),
/// configured by `cfg`: [`rerun_check`].
pub(super) fn sweep_rerun_check<T: Recorded>(
    recorded: &T,
    (cfg, points, units): (&crate::estimators::sweep::SweepConfig, usize, u64),
    ctx: &Ctx<'_>,
    checks: &mut Checks,
    run: impl FnOnce(&RunOptions) -> Result<T, Error>,
) -> Result<(), Error> {
    let what = format!(
        "{points} points of {} collisions in {} batches (seed {})",
        cfg.collisions, cfg.batches, cfg.seed
    );
    rerun_check(recorded, units, &what, ctx, checks, run)
}

/// The re-run check of the result `recorded`, whose re-run reports progress in `units` units:
/// skipped when the budget does not admit it, else `run` re-runs the recorded configuration and
/// every field must be identical.
pub(super) fn rerun_check<T: Recorded>(
    recorded: &T,
    units: u64,
    what: &str,
    ctx: &Ctx<'_>,
    checks: &mut Checks,
    run: impl FnOnce(&RunOptions) -> Result<T, Error>,
) -> Result<(), Error> {
    let n = match ctx.take() {
        Ok(n) => n,
        Err(why) => {
            checks.skip(
                "reproducibility",
                "the recorded configuration re-run gives the same bits",
                why,
            );
            return Ok(());
        }
    };
    let again = ctx.rerun_in_units(n, units, run)?;
    identical_check(
        (recorded, recorded.meta()),
        (&again, again.meta()),
        what,
        checks,
    )
}
