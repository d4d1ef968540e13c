//! The audit of a `diffusion --table` result (D on a table given as data): the table re-validated
//! exactly from the file, the record against its batches and the table's closed forms, the exact
//! identities (Santaló's mean free path; the crossing time and collisions per crossing where the
//! table has a crossing time) within the Student-t bound of the batches, the batch statistics,
//! and the configuration re-run on the table through the library.

use std::path::Path;

use super::diffusion::refused_config;
use super::file::ResultFile;
use super::same_bits::rerun_check;
use super::statistics::batch_statistics;
use super::{Checks, Ctx};
use crate::Error;
use crate::estimators::diffusion::scene::{self, SceneDiffusionReport};
use crate::scenes::Scene;
use crate::scenes::table::PeriodicTable;
use crate::statistics::{mean_se, normal_sigma_equivalent_t};

/// The file as a table result: its table valid, its configuration one the command line would
/// accept on that table.
pub(super) fn parse(
    file: &ResultFile,
    path: &Path,
) -> Result<(SceneDiffusionReport, PeriodicTable), Error> {
    let r: SceneDiffusionReport = file.parse(path)?;
    let Some(spec) = &r.table else {
        return Err(Error::malformed(
            path,
            "D on a scene without its table: report audits D on a table given as data (its \
             `table` recorded)",
        ));
    };
    let table = PeriodicTable::new(spec).map_err(|e| refused_config(path, e))?;
    r.config
        .validate(&table)
        .map_err(|e| refused_config(path, e))?;
    Ok((r, table))
}

/// The record: provenance numbers, the label, D and its check window from the batches, the
/// closed forms of the table.
fn record(r: &SceneDiffusionReport, table: &PeriodicTable, checks: &mut Checks) {
    let cfg = &r.config;
    let mut bad = super::meta_problems(
        &r.meta,
        Some(cfg.seed),
        Some(u64::from(cfg.batches)),
        &cfg.precision.to_string(),
    );
    if r.scene != table.label() || r.batch_D.len() != cfg.batches as usize {
        bad.push("the scene label or the number of batch values is not the table's".into());
    }
    let same = |(a, b): (f64, f64), (c, d): (f64, f64)| (a, b) == (c, d);
    if !same(mean_se(&r.batch_D), (r.D, r.D_err))
        || !same(mean_se(&r.batch_D_check), (r.D_check, r.D_check_err))
    {
        bad.push("D, D_check or an error is not the one its batch values give".into());
    }
    if r.time_unit.to_bits() != crate::estimators::diffusion::time_unit(table).to_bits() {
        bad.push("the time unit is not the table's".into());
    }
    let exact = |name: &str| match name {
        "mean free path" => Some(table.mean_free_path()),
        "crossing time" => table.crossing_time(),
        "collisions per crossing" => table.crossing_time().map(|t| t / table.mean_free_path()),
        _ => None,
    };
    if r.identities
        .iter()
        .any(|i| exact(&i.name).map(f64::to_bits) != Some(i.exact.to_bits()))
    {
        bad.push("an identity's closed form is not the table's".into());
    }
    super::record_check(bad, checks);
}

/// Each exact identity: the measured value within the Student-t equivalent of 4σ of its batches.
fn identities(r: &SceneDiffusionReport, checks: &mut Checks) {
    let dof = f64::from(r.config.batches.max(2)) - 1.0;
    let bound = normal_sigma_equivalent_t(dof, super::SIGMAS);
    for i in &r.identities {
        let z = (i.measured - i.exact) / i.err;
        checks.judge(
            dof,
            z.abs() <= bound,
            ("identities", &format!("{} = its closed form", i.name)),
            format!(
                "{} ± {:.1e} against {} ({z:+.2}σ; bound {bound:.2}σ)",
                i.measured, i.err, i.exact
            ),
            &[("value", i.measured), ("err", i.err), ("exact", i.exact)],
        );
    }
}

/// The checks: the record, the identities, the batches, the re-run.
pub(super) fn checks(
    (r, table): (&SceneDiffusionReport, &PeriodicTable),
    ctx: &Ctx<'_>,
    checks: &mut Checks,
) -> Result<(), Error> {
    record(r, table, checks);
    identities(r, checks);
    batch_statistics(&r.batch_D, checks);
    let cfg = &r.config;
    let what = format!(
        "{} collisions in {} batches on {} (seed {}, {})",
        cfg.collisions,
        cfg.batches,
        table.label(),
        cfg.seed,
        cfg.precision
    );
    rerun_check(r, cfg.collisions, &what, ctx, checks, |o| {
        scene::run_on(table, cfg, o)
    })
}
