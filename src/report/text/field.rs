//! The text `lorentz diffusion --field B` prints (the diffusion tensor in a magnetic field): the
//! command line writes it to stdout, and Python's `str()` of the result is the same text.

use super::{line, sigmas};
use crate::estimators::field::FieldReport;
use crate::statistics::comparison;
use crate::theory::magnetic::sampled_share_err;

/// The text of a diffusion result in a field, line by line as the command line prints it.
pub fn field(r: &FieldReport) -> String {
    let title = format!(
        "periodic Lorentz gas in a magnetic field, {}, B = {} (cyclotron radius {:.6})",
        scene(r),
        r.config.table.field().unwrap_or("0"),
        r.point.cyclotron_radius,
    );
    let counts = (r.collisions, r.seconds, Some(r.collisions_per_second));
    let mut out = super::first_line(title, &r.meta, counts, false);
    line!(
        out,
        "localized share = {:.6} ± {:.6}   exact {:.6} (pinned {:.6}, skipping {:.6}; {})",
        r.point.localized_fraction,
        r.point.localized_fraction_err,
        r.point.localized_fraction_exact,
        r.point.pinned_fraction_exact,
        r.point.skipping_fraction_exact,
        binomial(r)
    );
    if r.point.all_localized {
        line!(
            out,
            "every orbit is localized (2ρ ≤ A − 2r): D_xx = D_xy = 0 exactly, no trajectory run"
        );
        return out;
    }
    line!(out, "components    : {}", r.point.components.describe());
    tensor(&mut out, r, r.point.batch_D_xx.len());
    out
}

/// The scene: the triangular one by its gap, the square one by its radius.
fn scene(r: &FieldReport) -> String {
    match (r.point.w, r.point.radius) {
        (Some(w), _) => format!("w = {w}"),
        (None, Some(radius)) => format!("square lattice, r = {radius}"),
        (None, None) => r.scene.clone(),
    }
}

/// The tensor lines of a run that was not all localized: whole phase space, the diffusing
/// part, the check window and the mean free time against Kac's.
fn tensor(out: &mut String, r: &FieldReport, n: usize) {
    let kept = r.point.components.diffusing as usize;
    let bound = comparison::agreement_bound(comparison::batch_dof(kept));
    line!(
        out,
        "D_xx          = {}   (whole phase space; the diffusing part's × {:.6}){}",
        super::estimate(r.point.D_xx, r.point.D_xx_err),
        1.0 - r.point.components.bounded_fraction,
        super::negative_note(r.point.D_xx, r.point.D_xx_err, bound)
    );
    line!(
        out,
        "D_xy (Hall)   = {}   (from the Lévy area; whole phase space)",
        super::estimate(r.point.D_xy, r.point.D_xy_err)
    );
    let t = &r.diffusing;
    let c = &r.diffusing_check;
    line!(
        out,
        "diffusing part: D_xx {}, D_yy {}, Hall D_xy {}, symmetric D_xy {}   (MSD slopes over [{}τ, {}τ], τ = {:.4})",
        super::estimate(t.D_xx, t.D_xx_err),
        super::estimate(t.D_yy, t.D_yy_err),
        super::estimate(t.D_xy, t.D_xy_err),
        super::estimate(t.D_xy_symmetric, t.D_xy_symmetric_err),
        r.window.lo,
        r.window.hi,
        r.tau
    );
    line!(
        out,
        "check window  : D_xx {}, Hall D_xy {}   (over [{}τ, {}τ])",
        super::estimate(c.D_xx, c.D_xx_err),
        super::estimate(c.D_xy, c.D_xy_err),
        r.check_window.lo,
        r.check_window.hi
    );
    line!(
        out,
        "mean free time = {:.6} ± {:.6}   Kac {:.6}  ({})",
        r.point.mean_free_time,
        r.point.mean_free_time_err,
        r.point.mean_free_time_exact,
        sigmas(
            r.point.mean_free_time,
            r.point.mean_free_time_err,
            r.point.mean_free_time_exact,
            n
        )
    );
}

/// The sampled localized share against the exact one (binomial error).
fn binomial(r: &FieldReport) -> String {
    let f = r.point.localized_fraction_exact;
    let n = r.config.localization_samples.unwrap_or(0) as f64;
    let err = sampled_share_err(f, n);
    let c = comparison::of(r.point.localized_fraction - f, err, f64::INFINITY);
    format!("{:+.1}σ, bound {:.1}σ: {}", c.z, c.bound, c.verdict())
}
