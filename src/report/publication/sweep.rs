//! The audit of a `sweep` result — also one written by `lorentz merge`, which is the same result:
//! the record recomputed by the sweep's own analysis from each run's D and error, the runs' F
//! tests, and runs re-run from their seeds.

use std::path::Path;

use super::diffusion::refused_config;
use super::file::ResultFile;
use super::same_bits::{differing, rerun_check};
use super::{ALPHA, Checks, Ctx, Sampled, pick};
use crate::Error;
use crate::estimators::sweep::analysis::analyse;
use crate::estimators::sweep::{self, RunValue, SweepConfig, SweepPoint, SweepReport};

/// The file as a sweep result whose configuration the command line would accept.
pub(super) fn parse(file: &ResultFile, path: &Path) -> Result<SweepReport, Error> {
    let r: SweepReport = file.parse(path)?;
    r.config.validate().map_err(|e| refused_config(path, e))?;
    Ok(r)
}

/// The re-runs: one run (quick) or every run of every point.
pub(super) fn reruns(r: &SweepReport, quick: bool) -> Vec<u64> {
    let c = &r.config;
    if quick {
        vec![c.collisions]
    } else {
        vec![
            c.collisions
                .saturating_mul(u64::from(c.runs()))
                .saturating_mul(u64::from(c.steps())),
        ]
    }
}

/// The checks of a sweep result, in order.
pub(super) fn checks(r: &SweepReport, ctx: &Ctx<'_>, checks: &mut Checks) -> Result<(), Error> {
    let cfg = &r.config;
    let grid = cfg.points()?;
    let points = match points_of(r, &grid) {
        Ok(p) => p,
        Err(bad) => {
            checks.pass_if(
                false,
                "reproducibility",
                "the record has the shape of its configuration",
                format!("{bad}; nothing else is checked"),
                &[],
            );
            return Ok(());
        }
    };
    let again = match analyse(cfg, &points, r.resumed_points, ctx.threads) {
        Ok(a) => a,
        Err(e) => {
            checks.pass_if(
                false,
                "reproducibility",
                "the rows, F tests, fits and crossing follow from the recorded runs",
                format!("the recorded runs cannot be analysed: {e}"),
                &[],
            );
            return Ok(());
        }
    };
    record_check(r, &again, checks)?;
    runs_check(&again, checks);
    if ctx.quick {
        one_run_check(r, &grid, ctx, checks)
    } else {
        whole_sweep_check(r, ctx, checks)
    }
}

/// The sweep's points as the file records them (each run's D and error), if the rows have the
/// shape of the configuration: one per grid point, on it, with one value per run.
fn points_of(r: &SweepReport, grid: &[f64]) -> Result<Vec<SweepPoint>, String> {
    let cfg = &r.config;
    if r.rows.len() != grid.len() {
        return Err(format!("{} rows for {} points", r.rows.len(), grid.len()));
    }
    let mut points = Vec::with_capacity(grid.len());
    for (i, (row, &w)) in r.rows.iter().zip(grid).enumerate() {
        if row.w.to_bits() != w.to_bits() {
            return Err(format!("row {i}: w = {} is not the grid's {w}", row.w));
        }
        let n = cfg.runs() as usize;
        if row.run_D.len() != n || row.run_D_err.len() != n {
            return Err(format!(
                "row {i}: {} run values and {} run errors for {n} runs",
                row.run_D.len(),
                row.run_D_err.len()
            ));
        }
        points.push(SweepPoint {
            config: cfg.clone(),
            index: i as u32,
            w,
            runs: row
                .run_D
                .iter()
                .zip(&row.run_D_err)
                .map(|(&d, &e)| RunValue { D: d, D_err: e })
                .collect(),
        });
    }
    Ok(points)
}

/// The record: the sweep's analysis of the recorded runs gives every recorded field to the bit.
fn record_check(r: &SweepReport, again: &SweepReport, checks: &mut Checks) -> Result<(), Error> {
    let differ = differing((r, &r.meta), (again, &again.meta))?;
    checks.pass_if(
        differ.is_empty(),
        "reproducibility",
        "each D is the mean of its runs; errors, F tests, fits and crossing recomputed",
        if differ.is_empty() {
            format!(
                "{} points × {} runs analysed again from each run's D and error: the same bits",
                r.rows.len(),
                r.config.runs()
            )
        } else {
            format!(
                "the analysis of the recorded runs differs from the record in: {}",
                differ.join(", ")
            )
        },
        &[("points", r.rows.len() as f64)],
    );
    Ok(())
}

/// The runs of each point agree within their errors: the F tests (recomputed), Bonferroni over
/// the points.
fn runs_check(again: &SweepReport, checks: &mut Checks) {
    let ps: Vec<f64> = again
        .rows
        .iter()
        .map(|r| r.runs_p_value)
        .filter(|p| p.is_finite())
        .collect();
    if ps.is_empty() {
        checks.skip(
            "statistics",
            "runs agree within their errors",
            "one run per point: no spread to test".into(),
        );
        return;
    }
    let pmin = ps.iter().copied().fold(1.0, f64::min);
    checks.pass_if(
        pmin * ps.len() as f64 > ALPHA,
        "statistics",
        "runs agree within their errors at every point",
        format!(
            "smallest F-test p-value {pmin:.2e} over {} points (Bonferroni: fail below {ALPHA}/{})",
            ps.len(),
            ps.len()
        ),
        &[("p_min", pmin)],
    );
}

/// One run of one point, drawn at random, re-run from its seed: its D and error.
fn one_run_check(
    r: &SweepReport,
    grid: &[f64],
    ctx: &Ctx<'_>,
    checks: &mut Checks,
) -> Result<(), Error> {
    let cfg: &SweepConfig = &r.config;
    let name = "one run re-run from its seed gives the recorded bits";
    if let Err(why) = ctx.take() {
        checks.skip("reproducibility", name, why);
        return Ok(());
    }
    // steps × runs can exceed u32 (10⁴ points × 2²⁰ runs): picked in u64.
    let runs = u64::from(cfg.runs().max(1));
    let all = u64::from(cfg.steps()) * runs;
    let drawn = pick(ctx.draw, all);
    ctx.sampled.set(Sampled::new("runs", 1, all));
    // Below steps and runs respectively, so both fit in u32.
    let (i, k) = ((drawn / runs) as u32, (drawn % runs) as u32);
    let (iu, ku) = (i as usize, k as usize);
    let c = cfg.run_config(i, grid[iu], k);
    let again = crate::estimators::diffusion::run(&c, &ctx.options())?;
    let row = &r.rows[iu];
    let (d, e) = (row.run_D[ku], row.run_D_err[ku]);
    checks.pass_if(
        d.to_bits() == again.D.to_bits() && e.to_bits() == again.D_err.to_bits(),
        "reproducibility",
        name,
        format!(
            "point {i} (w = {}), run {k}: recorded D = {d} ± {e}, re-run {} ± {}",
            grid[iu], again.D, again.D_err
        ),
        &[("point", f64::from(i)), ("run", f64::from(k))],
    );
    Ok(())
}

/// The whole sweep re-run from its configuration: every field identical.
fn whole_sweep_check(r: &SweepReport, ctx: &Ctx<'_>, checks: &mut Checks) -> Result<(), Error> {
    let cfg = &r.config;
    let what = format!(
        "{} points × {} runs of {} collisions (seed {})",
        cfg.steps(),
        cfg.runs(),
        cfg.collisions,
        cfg.seed
    );
    let n = cfg
        .collisions
        .saturating_mul(u64::from(cfg.runs()) * u64::from(cfg.steps()));
    rerun_check(r, n, &what, ctx, checks, |o| sweep::run(cfg, o))
}
