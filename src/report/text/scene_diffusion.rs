//! The text of D on any table (`lorentz diffusion --table FILE`; Python's `str()` of the result).

use super::line;
use crate::estimators::diffusion::scene::SceneDiffusionReport;
use crate::statistics::comparison;

/// The text of a diffusion result on a table, line by line as the command line prints it.
pub fn scene_diffusion(r: &SceneDiffusionReport) -> String {
    let mut out = super::first_line(&r.scene, &r.meta, (r.collisions, r.seconds, None), false);
    let unit = format!("the {}", r.time_unit_name);
    let w = &r.config.window;
    line!(
        out,
        "{:<24} = {}   (MSD slope over [{}, {}] x {unit} = {:.6}){}",
        "D",
        super::estimate(r.D, r.D_err),
        w.lo,
        w.hi,
        r.time_unit,
        super::negative_note(
            r.D,
            r.D_err,
            comparison::agreement_bound(comparison::batch_dof(r.batch_D.len()))
        )
    );
    let check = comparison::of(
        r.D_minus_D_check,
        r.D_minus_D_check_err,
        comparison::batch_dof(r.batch_D.len()),
    );
    line!(
        out,
        "{:<24} = {}   (over [{}, {}]; D − D_check = {:+.6} ± {:.6}, {:+.1}σ: {})",
        "D (check)",
        super::estimate(r.D_check, r.D_check_err),
        r.config.check_window.lo,
        r.config.check_window.hi,
        r.D_minus_D_check,
        r.D_minus_D_check_err,
        check.z,
        check.verdict()
    );
    for i in &r.identities {
        line!(
            out,
            "{:<24} = {:.7} ± {:.7}   exact {:.7}  ({:+.1}σ, bound {:.1}σ: {})",
            i.name,
            i.measured,
            i.err,
            i.exact,
            i.t,
            i.bound,
            comparison::verdict_word(i.t, i.bound, comparison::batch_dof(r.batch_D.len()))
        );
    }
    if let Some(a) = &r.audit {
        line!(
            out,
            "{:<24} : {} events replayed in MPFR, {} outside the error model",
            "self-audit",
            a.audited,
            a.outside
        );
    }
    out
}
