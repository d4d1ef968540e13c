//! The audit of a `diffusion --field` result: the record against its configuration and the exact
//! geometry of the localized orbits, the sampled localized share and Kac's mean free time against
//! their closed forms, the symmetries of the tensor, and the configuration re-run through the
//! library.

use std::path::Path;

use super::diffusion::refused_config;
use super::file::ResultFile;
use super::same_bits::rerun_check;
use super::statistics::batch_statistics;
use super::{Checks, Ctx, SIGMAS};
use crate::Error;
use crate::estimators::diffusion::DiffusionConfig;
use crate::estimators::field::{self, FieldReport};
use crate::theory::magnetic::{FieldGeometry, sampled_share_err};

/// The file as a field result whose configuration the command line would accept.
pub(super) fn parse(file: &ResultFile, path: &Path) -> Result<FieldReport, Error> {
    let r: FieldReport = file.parse(path)?;
    r.config.validate().map_err(|e| refused_config(path, e))?;
    Ok(r)
}

/// The exact geometry of the recorded configuration.
fn geometry(r: &FieldReport) -> Result<FieldGeometry, Error> {
    geometry_of(&r.config)
}

/// The exact geometry of a field run's configuration.
pub(super) fn geometry_of(cfg: &DiffusionConfig) -> Result<FieldGeometry, Error> {
    field::geometry(cfg)
}

/// The checks: the record, the localized share, Kac, the symmetries, the batches, the re-run.
pub(super) fn checks(
    r: &FieldReport,
    ctx: &Ctx<'_>,
    checks: &mut Checks,
    figures: &mut Vec<String>,
) -> Result<(), Error> {
    let cfg = &r.config;
    let d = cfg;
    let g = geometry(r)?;
    let mut bad = super::meta_problems(
        &r.meta,
        Some(d.seed),
        Some(u64::from(d.batches)),
        &d.precision.to_string(),
    );
    let exact = [
        (r.point.field, field::field_of(cfg)?),
        (r.point.pinned_fraction_exact, g.pinned_fraction()),
        (r.point.skipping_fraction_exact, g.skipping_fraction()),
        (r.point.localized_fraction_exact, g.localized_fraction()),
        (r.point.mean_free_time_exact, g.diffusing_mean_free_time()),
    ];
    let (w, radius) = field::scene_parameters(&cfg.table)?;
    let same = |a: Option<f64>, b: Option<f64>| a.map(f64::to_bits) == b.map(f64::to_bits);
    if !same(r.point.w, w)
        || !same(r.point.radius, radius)
        || exact.iter().any(|(a, b)| a.to_bits() != b.to_bits())
    {
        bad.push(
            "w, the radius, the field or a closed form differs from the configuration's".into(),
        );
    }
    if r.point.all_localized != g.all_localized() {
        bad.push("all_localized is not the exact geometry's".into());
    }
    super::record_check(bad, checks);
    localized_share(r, checks);
    if r.point.all_localized {
        let zero = r.point.D_xx == 0.0 && r.point.D_xy == 0.0 && r.point.batch_D_xx.is_empty();
        checks.pass_if(
            zero,
            "identities",
            "every orbit localized: D = 0 exactly",
            format!(
                "D_xx = {}, D_xy = {}, {} batches run",
                r.point.D_xx,
                r.point.D_xy,
                r.point.batch_D_xx.len()
            ),
            &[("D_xx", r.point.D_xx), ("D_xy", r.point.D_xy)],
        );
    } else {
        let scene = cfg.table.scene.resolve()?;
        let isotropic = crate::with_scene!(&scene, |s| crate::scenes::Scene::isotropic(s));
        diffusing_checks(r, isotropic, checks);
        component_checks(r, &g, checks);
        let kept: Vec<f64> = (r.point.batch_D_xx.iter().enumerate())
            .filter(|(i, _)| r.point.components.diffusing(*i))
            .map(|(_, v)| *v)
            .collect();
        batch_statistics(&kept, checks);
        batch_histogram(r, &kept, ctx.out, figures)?;
    }
    let what = format!(
        "{} collisions in {} batches at field {} (seed {}, {})",
        d.collisions,
        d.batches,
        cfg.table.field().unwrap_or("0"),
        d.seed,
        d.precision
    );
    rerun_check(r, d.collisions, &what, ctx, checks, |o| field::run(cfg, o))
}

/// The sampled localized share against the exact share p: binomial, with the error
/// √(p(1 − p)/n) of n samples under p (4σ normal bound); a share of 0 or 1 must be sampled
/// exactly.
fn localized_share(r: &FieldReport, checks: &mut Checks) {
    let (v, x) = (r.point.localized_fraction, r.point.localized_fraction_exact);
    let n = r.config.localization_samples.unwrap_or(0) as f64;
    let e = sampled_share_err(x, n);
    let z = (v - x) / e;
    let ok = z.abs() <= SIGMAS;
    checks.pass_if(
        ok,
        "identities",
        "sampled localized share = the exact share of pinned and skipping orbits",
        format!("{v} of {n} samples against exact {x} ({z:+.2}σ of {e:.1e}; bound {SIGMAS:.2}σ)"),
        &[("value", v), ("err", e), ("exact", x)],
    );
}

/// The diffusing part: Kac's mean free time and, where the scene's symmetry implies it
/// ([`crate::scenes::Scene::isotropic`]), a vanishing symmetric off-diagonal part, each within
/// the Student-t bound of its batches.
fn diffusing_checks(r: &FieldReport, isotropic: bool, checks: &mut Checks) {
    let t = &r.diffusing;
    let symmetric = "symmetric off-diagonal part of the tensor = 0 (lattice symmetry)";
    if !isotropic {
        checks.add(
            "identities",
            symmetric,
            super::Verdict::NotApplicable,
            "no rotation of order above 2 maps this table onto itself: the tensor's symmetric \
             part need not be isotropic"
                .into(),
            &[],
        );
    }
    let mut cases = vec![(
        "mean free time of the diffusing part = Kac's",
        r.point.mean_free_time,
        r.point.mean_free_time_err,
        r.point.mean_free_time_exact,
    )];
    if isotropic {
        cases.push((symmetric, t.D_xy_symmetric, t.D_xy_symmetric_err, 0.0));
    }
    for (name, v, e, x) in cases {
        let dof = f64::from(r.config.batches) - 1.0;
        checks.within_t(dof, ("identities", name), ((v, e), x), String::new());
    }
}

/// The components: the record's classification is the one its reaches make at the table's limit,
/// the diffusing batches are one distribution (else FAIL: an average over components is not an
/// estimate), and every diffusing batch went clearly beyond the limit (else the split is not
/// clear: skipped, so the report is INCOMPLETE).
fn component_checks(r: &FieldReport, g: &FieldGeometry, checks: &mut Checks) {
    use crate::estimators::field::Components;
    use crate::observers::excursion::{Excursion, Reach};
    let c = &r.point.components;
    let excursion = Excursion::of(g.lattice(), g.cyclotron_radius());
    let reaches: Vec<Reach> = c.batch_reach.iter().map(|&x| Reach::at(x)).collect();
    let again = Components::of(
        excursion,
        &reaches,
        (&r.point.batch_D_xx, &r.point.batch_D_xy),
        r.point.localized_fraction_exact,
    );
    let same = serde_json::to_value(&again).ok() == serde_json::to_value(c).ok();
    checks.pass_if(
        same && reaches.len() == r.point.batch_D_xx.len(),
        "statistics",
        "components: the record's classification is its batches' reaches at the table's limit",
        c.describe(),
        &[("bounded", f64::from(c.bounded)), ("limit", c.limit)],
    );
    let one = "the diffusing batches are one component (no outlying D_xx or D_xy)";
    match (c.extreme_D_xx, c.extreme_D_xy) {
        (Some(xx), Some(xy)) => checks.pass_if(
            !c.split,
            "statistics",
            one,
            format!(
                "most extreme D_xx batch {}: t = {:+.2}, D_xy batch {}: t = {:+.2}, against the \
                 Bonferroni bound {:.2} (false alarm {} in all)",
                xx.batch,
                xx.t,
                xy.batch,
                xy.t,
                xx.bound,
                crate::estimators::field::SPLIT_ALPHA
            ),
            &[("t_D_xx", xx.t), ("t_D_xy", xy.t), ("bound", xx.bound)],
        ),
        _ => checks.skip(
            "statistics",
            one,
            format!(
                "{} diffusing batches: the test needs at least 3",
                c.diffusing
            ),
        ),
    }
    if c.ambiguous > 0 {
        checks.skip(
            "statistics",
            "the bounded and diffusing trajectories are clearly apart",
            format!(
                "{} diffusing batches stayed within {} limits ({:.3}) of their start: run longer",
                c.ambiguous,
                Excursion::AMBIGUOUS,
                Excursion::AMBIGUOUS * c.limit
            ),
        );
    }
}

/// The histogram of the batches' D_xx: the diffusing ones and the bounded ones set aside, with
/// the diffusing part's D_xx marked.
fn batch_histogram(
    r: &FieldReport,
    kept: &[f64],
    out: &Path,
    figures: &mut Vec<String>,
) -> Result<(), Error> {
    let bounded: Vec<f64> = (r.point.batch_D_xx.iter().enumerate())
        .filter(|(i, _)| !r.point.components.diffusing(*i))
        .map(|(_, v)| *v)
        .collect();
    let groups = [
        (format!("{} diffusing batches", kept.len()), kept),
        (
            format!("{} bounded batches (set aside)", bounded.len()),
            &bounded[..],
        ),
    ];
    let mean = (r.diffusing.D_xx + r.diffusing.D_yy) / 2.0;
    let names = ("D_xx of each batch (mean of xx and yy)", "D_xx");
    super::histogram::histogram(&groups, mean, names, &out.join("batch-histogram"))?;
    figures.push("batch-histogram".into());
    Ok(())
}
