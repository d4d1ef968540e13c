//! The text `lorentz theory` prints (the corrected Machta–Zwanzig hierarchy): the command line writes it to stdout, and Python's
//! `str()` of the result is the same text.

use super::line;
use crate::estimators::hops::theory::TheoryReport;
use crate::statistics::comparison;

/// The text of a `theory` result, line by line as the command line prints it.
pub fn theory(r: &TheoryReport) -> String {
    let mut out = String::new();
    line!(
        out,
        "w = {}: p_bs = {:.5} ± {:.5}, p_cf = {:.6} ± {:.6} (App. A: {:.6} corrected, {:.6} as printed)",
        r.w,
        r.p_bs,
        r.p_bs_err,
        r.p_cf,
        r.p_cf_err,
        r.p_cf_appendix_a,
        r.p_cf_appendix_a_as_printed
    );
    line!(
        out,
        "D_GK (the Lorentz gas) = {:.6} ± {:.6}   D_MZ = {:.6}",
        r.D_GK,
        r.D_GK_err,
        r.D_MZ
    );
    let n = r.meta.batches.unwrap_or(0) as usize;
    line!(
        out,
        "D_cf = {:.6} ± {:.6}  D_bs = {:.6} ± {:.6}  D_1 = {:.6} ± {:.6}   (errors: jackknife over the {n} batches){}",
        r.D_cf,
        r.D_cf_err,
        r.D_bs,
        r.D_bs_err,
        r.D_1,
        r.D_1_err,
        comparison::few_samples_note(n, "batches")
    );
    for o in &r.orders {
        let against = comparison::of(
            o.D_k_combined_minus_D_GK,
            o.D_k_combined_minus_D_GK_err,
            comparison::batch_dof(n),
        );
        let verdict = if against.agrees() {
            "not resolved from D_GK"
        } else {
            "resolved from D_GK"
        };
        line!(
            out,
            "k = {}: D_k = {:.6} ± {:.6}  with collisionless flights {:.6} ± {:.6} (− D_GK = {:+.6} ± {:.6}, {:+.1}σ paired, bound {:.1}σ: {verdict})   exact order-{} lattice walk {:.6} ± {:.6}",
            o.k,
            o.D_k,
            o.D_k_err,
            o.D_k_combined,
            o.D_k_combined_err,
            o.D_k_combined_minus_D_GK,
            o.D_k_combined_minus_D_GK_err,
            against.z,
            against.bound,
            o.k,
            o.D_lattice_walk,
            o.D_lattice_walk_err
        );
    }
    line!(
        out,
        "paper's (B2), (B3) as printed: {:.6} ± {:.6}, {:.6} ± {:.6}",
        r.D_2_as_printed,
        r.D_2_as_printed_err,
        r.D_3_as_printed,
        r.D_3_as_printed_err
    );
    out
}
