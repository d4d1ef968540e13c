//! The audit of a sweep in a field (`lorentz sweep --fields` / `--field`): every row against the
//! exact geometry of its point, the Onsager–Casimir checks recomputed from the rows, each sampled
//! localized share and each Kac mean free time against its closed form (Bonferroni over the
//! rows), and the whole sweep re-run through the library.

use std::path::Path;

use super::diffusion::refused_config;
use super::field::geometry_of;
use super::file::ResultFile;
use super::same_bits::sweep_rerun_check;
use super::{Checks, Ctx};
use crate::Error;
use crate::estimators::sweep::field::{FieldSweepReport, FieldSweepRow, onsager};
use crate::statistics::comparison::largest_of_bound;
use crate::theory::magnetic::sampled_share_err;

/// The file as a field sweep whose configuration the command line would accept.
pub(super) fn parse(file: &ResultFile, path: &Path) -> Result<FieldSweepReport, Error> {
    let r: FieldSweepReport = file.parse(path)?;
    r.config.validate().map_err(|e| refused_config(path, e))?;
    Ok(r)
}

/// Collisions the re-run takes.
pub(super) fn collisions(r: &FieldSweepReport) -> u64 {
    let points = u64::from(r.config.steps());
    r.config.collisions.saturating_mul(points)
}

/// The checks: the record, the Onsager–Casimir verdicts, the localized shares and Kac's mean
/// free times, the re-run.
pub(super) fn checks(
    r: &FieldSweepReport,
    ctx: &Ctx<'_>,
    checks: &mut Checks,
) -> Result<(), Error> {
    let cfg = &r.config;
    let mut bad =
        super::meta_problems(&r.meta, Some(cfg.seed), Some(u64::from(cfg.batches)), "f64");
    bad.extend(row_problems(r)?);
    let again = onsager(&r.rows, cfg.batches);
    let agrees = again
        .iter()
        .all(|c| c.d_xx_even.agrees() && c.d_xy_odd.agrees());
    if again != r.onsager || agrees != r.onsager_agrees {
        bad.push("the Onsager-Casimir checks are not those of the rows".into());
    }
    super::record_check(bad, checks);
    for o in &again {
        for (name, c) in [
            ("D_xx(B) - D_xx(-B) = 0", &o.d_xx_even),
            ("D_xy(B) + D_xy(-B) = 0", &o.d_xy_odd),
        ] {
            checks.judge(
                c.dof,
                c.agrees(),
                (
                    "identities",
                    &format!(
                        "Onsager-Casimir at {}|B| = {}: {name}",
                        match (o.w, o.radius) {
                            (Some(w), _) => format!("w = {w}, "),
                            (None, Some(r)) => format!("r = {r}, "),
                            (None, None) => String::new(),
                        },
                        o.field
                    ),
                ),
                c.describe("Welch, Bonferroni over the pairs"),
                &[("value", c.difference), ("err", c.err), ("exact", 0.0)],
            );
        }
    }
    shares_and_kac(r, checks);
    components(r, checks);
    let points = (cfg, r.rows.len(), collisions(r));
    sweep_rerun_check(r, points, ctx, checks, |o| {
        // Which points an earlier run left to resume is bookkeeping, not the result.
        crate::estimators::sweep::field::run(cfg, o).map(|mut again| {
            again.resumed_points = r.resumed_points;
            again
        })
    })
}

/// Rows that are not their points' exact geometry (gap, field, radius, shares, Kac's time).
fn row_problems(r: &FieldSweepReport) -> Result<Vec<String>, Error> {
    let cfg = &r.config;
    let fg = cfg.field_grid()?;
    let grid = fg.grid();
    if r.rows.len() != grid.len() {
        return Ok(vec![format!(
            "{} rows for a grid of {} points",
            r.rows.len(),
            grid.len()
        )]);
    }
    let mut bad = Vec::new();
    for (i, ((g, f), row)) in grid.into_iter().zip(&r.rows).enumerate() {
        let at = format!("{g:?}");
        let pc = fg.point_config(cfg, i, (g, f))?;
        let geo = geometry_of(&pc)?;
        let (w, radius) = crate::estimators::field::scene_parameters(&pc.table)?;
        let same = |a: Option<f64>, b: Option<f64>| a.map(f64::to_bits) == b.map(f64::to_bits);
        let exact = [
            (row.field, crate::estimators::field::field_of(&pc)?),
            (row.cyclotron_radius, geo.cyclotron_radius()),
            (row.pinned_fraction_exact, geo.pinned_fraction()),
            (row.skipping_fraction_exact, geo.skipping_fraction()),
            (row.localized_fraction_exact, geo.localized_fraction()),
            (row.mean_free_time_exact, geo.diffusing_mean_free_time()),
        ];
        let zero = !geo.all_localized() || (row.D_xx == 0.0 && row.D_xy == 0.0);
        if !components_recomputed(row, &geo) {
            bad.push(format!(
                "row {i} ({at}, B = {f}): its components are not its batches' at the point's limit"
            ));
        }
        if exact.iter().any(|(a, b)| a.to_bits() != b.to_bits())
            || !same(row.w, w)
            || !same(row.radius, radius)
            || row.all_localized != geo.all_localized()
            || !zero
        {
            bad.push(format!(
                "row {i} ({at}, B = {f}) is not its point's exact geometry"
            ));
        }
    }
    Ok(bad)
}

/// Each sampled localized share within the binomial bound of its exact share, and each measured
/// mean free time within the Student-t bound of Kac's, the largest of the rows' |z| judged by
/// the Bonferroni bound over the rows.
fn shares_and_kac(r: &FieldSweepReport, checks: &mut Checks) {
    let n = r.rows.len();
    let z_of = |v: f64, e: f64, x: f64| {
        if e > 0.0 {
            (v - x) / e
        } else if v == x {
            0.0
        } else {
            f64::INFINITY
        }
    };
    let samples = r.config.field_grid().map_or(0, |g| g.localization_samples);
    let share = |row: &FieldSweepRow| {
        let (x, m) = (row.localized_fraction_exact, samples as f64);
        z_of(row.localized_fraction, sampled_share_err(x, m), x)
    };
    let kac = |row: &FieldSweepRow| {
        z_of(
            row.mean_free_time,
            row.mean_free_time_err,
            row.mean_free_time_exact,
        )
    };
    let diffusing: Vec<&FieldSweepRow> = r.rows.iter().filter(|x| !x.all_localized).collect();
    for (name, zs, dof, m) in [
        (
            "every sampled localized share = its exact share (binomial)",
            r.rows.iter().map(share).collect::<Vec<_>>(),
            f64::INFINITY,
            n,
        ),
        (
            "every mean free time of the diffusing part = Kac's",
            diffusing.iter().map(|x| kac(x)).collect(),
            f64::from(r.config.batches) - 1.0,
            diffusing.len(),
        ),
    ] {
        if zs.is_empty() {
            continue;
        }
        let worst = zs.iter().fold(0.0f64, |a, z| a.max(z.abs()));
        let bound = largest_of_bound(dof, m);
        checks.judge(
            dof,
            worst <= bound,
            ("identities", name),
            format!("largest |z| = {worst:.2} over {m} points (bound {bound:.2}, Bonferroni)"),
            &[("value", worst), ("exact", 0.0)],
        );
    }
}

/// Whether a row's components are those its batch values and reaches make at its point's limit.
fn components_recomputed(
    row: &FieldSweepRow,
    geo: &crate::theory::magnetic::FieldGeometry,
) -> bool {
    use crate::estimators::field::Components;
    use crate::observers::excursion::{Excursion, Reach};
    let c = &row.components;
    let reaches: Vec<Reach> = c.batch_reach.iter().map(|&x| Reach::at(x)).collect();
    let excursion = Excursion::of(geo.lattice(), geo.cyclotron_radius());
    let batches = (&row.batch_D_xx[..], &row.batch_D_xy[..]);
    let again = Components::of(excursion, &reaches, batches, row.localized_fraction_exact);
    let lengths = reaches.len() == row.batch_D_xx.len() && reaches.len() == row.batch_D_xy.len();
    lengths && serde_json::to_value(&again).ok() == serde_json::to_value(c).ok()
}

/// Every point's diffusing batches are one component (each at the false-alarm rate
/// [`SPLIT_ALPHA`], so m points at most m times it), and every point's split is clear.
///
/// [`SPLIT_ALPHA`]: crate::estimators::field::SPLIT_ALPHA
fn components(r: &FieldSweepReport, checks: &mut Checks) {
    let at = |row: &FieldSweepRow| format!("{} at B = {}", row.place(), row.field);
    let split: Vec<String> = r
        .rows
        .iter()
        .filter(|x| x.components.split)
        .map(at)
        .collect();
    let bounded: u32 = r.rows.iter().map(|x| x.components.bounded).sum();
    checks.pass_if(
        split.is_empty(),
        "statistics",
        "every point's diffusing batches are one component",
        if split.is_empty() {
            format!(
                "no outlying batch at any of {} points ({bounded} bounded batches set aside; \
                 false alarm {} a point)",
                r.rows.len(),
                crate::estimators::field::SPLIT_ALPHA
            )
        } else {
            format!("split at {}", split.join(", "))
        },
        &[("split", split.len() as f64)],
    );
    let unclear: Vec<String> = (r.rows.iter())
        .filter(|x| x.components.ambiguous > 0)
        .map(at)
        .collect();
    if !unclear.is_empty() {
        checks.skip(
            "statistics",
            "the bounded and diffusing trajectories are clearly apart at every point",
            format!("not at {}: run longer", unclear.join(", ")),
        );
    }
}
