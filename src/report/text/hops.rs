//! The text `lorentz hops` prints (trap-hopping statistics): the command line writes it to stdout, and Python's
//! `str()` of the result is the same text.

use super::line;
use crate::estimators::hops::HopsReport;
use crate::statistics::comparison;

/// The text of a `hops` result, line by line as the command line prints it.
pub fn hops(r: &HopsReport) -> String {
    let mut out = String::new();
    line!(
        out,
        "trap hopping along lattice trajectories, w = {} ({} visits, {:.2e} collisions, {} batches, seed {}, {} engine){}",
        r.w,
        r.visits,
        r.collisions as f64,
        r.meta.batches.unwrap_or_default(),
        r.meta.seed.unwrap_or_default(),
        r.meta.engine,
        comparison::few_samples_note(r.meta.batches.unwrap_or_default() as usize, "batches")
    );
    line!(
        out,
        "p_bs = {:.5} ± {:.5}   p_cf = {:.6} ± {:.6}",
        r.p_bs,
        r.p_bs_err,
        r.p_cf,
        r.p_cf_err
    );
    let pairs: Vec<String> = r
        .pairs
        .iter()
        .map(|(k, v)| format!("p({k}) = {v:.5} ± {:.5}", r.pairs_err[k]))
        .collect();
    for c in pairs.chunks(3) {
        line!(out, "{}", c.join("   "));
    }
    let verdict = if r.symmetry_max_z <= r.symmetry_bound {
        "hold"
    } else {
        "VIOLATED"
    };
    line!(
        out,
        "symmetries p(s) = p(mirror s) = p(reversed mirror s): largest |z| = {:.2} of {} paired comparisons (bound {:.2}: the 4σ-equivalent t with {} dof over {} comparisons): {verdict}",
        r.symmetry_max_z,
        r.symmetry_comparisons,
        r.symmetry_bound,
        r.meta.batches.unwrap_or(1).saturating_sub(1),
        r.symmetry_comparisons
    );
    line!(
        out,
        "hop-level Green-Kubo D = {:.6} ± {:.6}   (D_MZ = {:.6})",
        r.D_GK,
        r.D_GK_err,
        r.D_MZ
    );
    out
}
