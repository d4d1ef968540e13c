//! The text `lorentz free-paths` prints (the free path between collisions against its
//! Boltzmann–Grad limit law): the command line writes it to stdout, and Python's `str()` of the
//! result is the same text.

use super::{line, sigmas};
use crate::estimators::free_paths::FreePathReport;

/// The text of a `free-paths` result, line by line as the command line prints it.
pub fn free_paths(r: &FreePathReport) -> String {
    let mut out = String::new();
    let n = r.batches as usize;
    line!(
        out,
        "{}: free paths xi = tau/l between collisions, l = {:.6} ({} batches, {} flights{})",
        r.scene,
        r.mean_free_path,
        n,
        r.samples,
        super::jumped(r.flights)
    );
    line!(
        out,
        "  <xi>    = {:.6} ± {:.6}  exact 1 (Santalo): {}",
        r.mean,
        r.mean_err,
        sigmas(r.mean, r.mean_err, 1.0, n)
    );
    line!(
        out,
        "  <ln xi> = {:+.6} ± {:.6}  limit r -> 0: 27 zeta(3)/(2 pi^2) - 3 ln 2 = {:+.6} ({:+.1}σ)",
        r.ln_mean,
        r.ln_mean_err,
        r.ln_mean_limit,
        (r.ln_mean - r.ln_mean_limit) / r.ln_mean_err
    );
    line!(out, "  longest flight: xi = {:.1}", r.longest);
    line!(
        out,
        "  {:>13}  {:>22}  {:>10}  {:>6}",
        "xi",
        "probability",
        "limit law",
        "z"
    );
    for b in &r.bins {
        let range = match b.hi {
            Some(hi) => format!("{:.2} - {:.2}", b.lo, hi),
            None => format!("{:.2} - inf", b.lo),
        };
        let z = b.z.map_or("-".into(), |z| format!("{z:+.1}"));
        line!(
            out,
            "  {range:>13}  {:>10.6} ± {:>9.6}  {:>10.6}  {z:>6}",
            b.probability,
            b.probability_err,
            b.limit
        );
    }
    let dof = crate::statistics::comparison::batch_dof(n);
    let verdict = if dof < crate::statistics::comparison::MIN_VERDICT_DOF {
        crate::statistics::comparison::verdict_word(r.max_z, r.max_z_bound, dof)
    } else if r.max_z <= r.max_z_bound {
        "consistent with the limit law".into()
    } else {
        "differs from the limit law (at a finite radius a difference is physics, not an error)"
            .into()
    };
    line!(
        out,
        "  largest |z| = {:.1} (bound {:.1} over {} bins): {verdict}",
        r.max_z,
        r.max_z_bound,
        r.bins.len()
    );
    out
}
