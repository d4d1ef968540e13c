//! The text `lorentz backscatter` prints (injection into one trap): the command line writes it to stdout, and Python's
//! `str()` of the result is the same text.

use super::{line, sigmas};
use crate::estimators::hops::backscatter::BackscatterReport;
use crate::statistics::comparison;

/// The text of a `backscatter` result, line by line as the command line prints it.
pub fn backscatter(r: &BackscatterReport) -> String {
    let mut out = String::new();
    let n = r.meta.batches.unwrap_or_default() as usize;
    line!(
        out,
        "injection into one trap, w = {} ({} particles, {} batches, seed {}){}",
        r.w,
        r.particles,
        r.meta.batches.unwrap_or_default(),
        r.meta.seed.unwrap_or_default(),
        comparison::few_samples_note(n, "batches")
    );
    line!(
        out,
        "p_bs = {:.5} ± {:.5}   p_l = {:.5} ± {:.5}   p_r = {:.5} ± {:.5}   p_cf = {:.5} ± {:.5}",
        r.p_bs,
        r.p_bs_err,
        r.p_l,
        r.p_l_err,
        r.p_r,
        r.p_r_err,
        r.p_cf,
        r.p_cf_err
    );
    line!(
        out,
        "mean visit time      = {:.5} ± {:.5}   Kac tau = {:.5}  ({})",
        r.mean_visit_time,
        r.mean_visit_time_err,
        r.mean_visit_time_exact,
        sigmas(
            r.mean_visit_time,
            r.mean_visit_time_err,
            r.mean_visit_time_exact,
            n
        )
    );
    line!(
        out,
        "collisions per visit = {:.4} ± {:.4}   Kac pi/(3w) = {:.4}  ({})",
        r.mean_collisions_per_visit,
        r.mean_collisions_per_visit_err,
        r.mean_collisions_per_visit_exact,
        sigmas(
            r.mean_collisions_per_visit,
            r.mean_collisions_per_visit_err,
            r.mean_collisions_per_visit_exact,
            n
        )
    );
    out
}
