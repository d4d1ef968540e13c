//! The audit of a driven sweep (`lorentz sweep --electric`): every row recomputed from its batches
//! and its point's exact field, the mobility's analysis and the J(−E) = −J(E) checks recomputed
//! from the rows, the sum rule at every point (Bonferroni over the points), and the sweep re-run
//! (one batch of one point, drawn at random, with `quick`).

use std::path::Path;

use super::current::steady_problems;
use super::diffusion::refused_config;
use super::file::ResultFile;
use super::same_bits::sweep_rerun_check;
use super::{Checks, Ctx};
use crate::Error;
use crate::engine::options::RunOptions;
use crate::estimators::current::{self, WARM_UP_SHARE};
use crate::estimators::diffusion::DiffusionConfig;
use crate::estimators::sweep::driven::{self, DrivenGrid, DrivenSweepReport};
use crate::estimators::sweep::point_grid::PointGrid;
use crate::statistics::comparison::largest_of_bound;

/// The file as a driven sweep whose configuration the command line would accept.
pub(super) fn parse(file: &ResultFile, path: &Path) -> Result<DrivenSweepReport, Error> {
    let r: DrivenSweepReport = file.parse(path)?;
    r.config.validate().map_err(|e| refused_config(path, e))?;
    DrivenGrid::of(&r.config).map_err(|e| refused_config(path, e))?;
    Ok(r)
}

/// The re-run's collisions with their warm-ups: one batch of one point with `quick`, else every
/// point.
pub(super) fn reruns(r: &DrivenSweepReport, quick: bool) -> Vec<u64> {
    let cfg = &r.config;
    let point = cfg.collisions as f64 * (1.0 + 1.0 / WARM_UP_SHARE);
    let n = if quick {
        point / f64::from(cfg.batches)
    } else {
        point * r.rows.len() as f64
    };
    vec![n.ceil() as u64]
}

/// Point `i`'s run.
fn point(r: &DrivenSweepReport, i: usize) -> Result<DiffusionConfig, Error> {
    DrivenGrid::of(&r.config)?.point(&r.config, i)
}

/// The checks: the record, ±E, the sum rules, the re-run.
pub(super) fn checks(
    r: &DrivenSweepReport,
    ctx: &Ctx<'_>,
    checks: &mut Checks,
) -> Result<(), Error> {
    let cfg = &r.config;
    for o in &record(r, checks)?.odd {
        let c = &o.mobility_even;
        let name = format!("J(−E) = −J(E) at w = {}, |E| = {}", o.w, o.electric);
        checks.judge(
            c.dof,
            c.agrees(),
            ("identities", &name),
            c.describe("Welch, Bonferroni over the pairs"),
            &[("value", c.difference), ("err", c.err), ("exact", 0.0)],
        );
    }
    sum_rules(r, checks);
    if ctx.quick {
        let b = cfg.batches;
        let all: Vec<f64> = r
            .rows
            .iter()
            .flat_map(|x| x.batch_J_parallel.clone())
            .collect();
        let count = (r.rows.len() as u32).saturating_mul(b);
        return ctx.one_batch_rerun(checks, (count, None), &[("J∥", &all)], |k, o| {
            let pc = point(r, (k / b) as usize)?;
            Ok(vec![current::rerun_batch(&pc, k % b, o)?[0]])
        });
    }
    let units = cfg.collisions.saturating_mul(r.rows.len() as u64);
    sweep_rerun_check(r, (cfg, r.rows.len(), units), ctx, checks, |o| {
        driven::run(cfg, o).map(|mut again| {
            again.resumed_points = r.resumed_points;
            again
        })
    })
}

/// The record check (the metadata, every row against its point, the mobility's analysis and
/// the ±E checks recomputed from the rows); returns the sweep's report recomputed from its rows.
fn record(r: &DrivenSweepReport, checks: &mut Checks) -> Result<DrivenSweepReport, Error> {
    let cfg = &r.config;
    let mut bad = row_problems(r)?;
    let batches = Some(u64::from(cfg.batches));
    bad.extend(super::meta_problems(
        &r.meta,
        Some(cfg.seed),
        batches,
        "f64",
    ));
    let opts = RunOptions::default();
    let again = driven::report(cfg, r.rows.clone(), r.resumed_points, &opts)?;
    let same = serde_json::to_value(&again.mobility).ok() == serde_json::to_value(&r.mobility).ok()
        && serde_json::to_value(&again.odd).ok() == serde_json::to_value(&r.odd).ok();
    if !same || again.odd_agrees != r.odd_agrees {
        bad.push("the mobility's analysis or the ±E checks are not those of the rows".into());
    }
    super::record_check(bad, checks);
    Ok(again)
}

/// The rows against their points: the gap, the field and its angle as the exact point gives
/// them, and each row's steady state from its batches.
fn row_problems(r: &DrivenSweepReport) -> Result<Vec<String>, Error> {
    let grid = DrivenGrid::of(&r.config)?;
    if r.rows.len() != grid.points() {
        return Ok(vec![format!(
            "{} rows for a grid of {} points",
            r.rows.len(),
            grid.points()
        )]);
    }
    let mut bad = Vec::new();
    for (i, row) in r.rows.iter().enumerate() {
        let pc = point(r, i)?;
        let world = current::field_at::<f64>(&pc, ())?;
        let at = grid.label(i);
        let w = pc.table.gap_for("a driven sweep")?;
        if row.w.to_bits() != w.to_bits()
            || row.electric.abs().to_bits() != world.strength.to_bits()
        {
            bad.push(format!("row {i} ({at}) is not its point's gap and field"));
        }
        if row.batch_J_parallel.len() != r.config.batches as usize {
            bad.push(format!("row {i} ({at}) has not one J∥ per batch"));
            continue;
        }
        let eps = world.strength;
        for p in steady_problems(&row.steady, (&row.batch_J_parallel, None), eps) {
            bad.push(format!("row {i} ({at}): {p}"));
        }
    }
    Ok(bad)
}

/// λ₊ + λ₋ + ⟨α⟩ = 0 at every point (the largest |z| against the Bonferroni bound over the
/// points) and per trajectory at every point (each worst residual within its rounding bound).
fn sum_rules(r: &DrivenSweepReport, checks: &mut Checks) {
    let m = r.rows.len();
    let dof = f64::from(r.config.batches) - 1.0;
    let worst = (r.rows.iter())
        .map(|x| (x.steady.sum_rule / x.steady.sum_rule_err).abs())
        .fold(0.0, f64::max);
    let bound = largest_of_bound(dof, m);
    checks.judge(
        dof,
        worst <= bound,
        ("identities", "sum rule at every point: λ₊ + λ₋ + ⟨α⟩ = 0"),
        format!("largest |z| = {worst:.2} over {m} points (bound {bound:.2}, Bonferroni)"),
        &[("value", worst), ("exact", 0.0)],
    );
    let over = (r.rows.iter())
        .filter(|x| x.steady.sum_rule_residual.abs() > x.steady.sum_rule_residual_bound)
        .count();
    checks.pass_if(
        over == 0,
        "identities",
        "sum rule per trajectory at every point",
        format!("{over} of {m} points with a residual beyond its rounding bound"),
        &[("points_over", over as f64)],
    );
}
