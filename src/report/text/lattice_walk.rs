//! The text `lorentz lattice-walk` prints (correlated lattice walks): the command line writes it to stdout, and Python's
//! `str()` of the result is the same text.

use super::line;
use crate::estimators::hops::lattice_walks::LatticeWalkReport;
use crate::statistics::comparison;

/// The text of a `lattice-walk` result, line by line as the command line prints it.
pub fn lattice_walk(r: &LatticeWalkReport) -> String {
    let mut out = String::new();
    line!(
        out,
        "w = {}: D_MZ = {:.6}, hop-level Green-Kubo D of the Lorentz gas = {:.6} ± {:.6}{}",
        r.w,
        r.D_MZ,
        r.D_GK,
        r.D_GK_err,
        comparison::few_samples_note(r.meta.batches.unwrap_or_default() as usize, "batches")
    );
    for x in &r.walks {
        let verdict = if x.simulated_z.abs() <= x.simulated_bound {
            "agree"
        } else {
            "DISAGREE"
        };
        line!(
            out,
            "order {}: simulated D = {:.6} ± {:.6}   exact D = {:.6} ± {:.6} (table's jackknife)   simulated − exact: {:+.1}σ of the walk's own noise, bound {:.1}σ: {verdict}",
            x.order,
            x.D_simulated,
            x.D_simulated_err,
            x.D_exact,
            x.D_exact_err,
            x.simulated_z,
            x.simulated_bound
        );
    }
    out
}
