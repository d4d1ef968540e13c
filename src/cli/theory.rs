//! `lorentz theory`: the corrected Machta–Zwanzig hierarchy and exact correlated lattice walks.

use lorentz_gas::Error;
use lorentz_gas::engine::Engine;
use lorentz_gas::estimators::hops::theory::{self, TheoryReport};
use lorentz_gas::statistics::comparison;

use super::args::HopCommand;

/// `lorentz theory` takes the shared hop-analysis options.
pub type Args = HopCommand;

/// The help of `--order` for `lorentz theory` (the shared text is `hops`'s).
pub const ORDER_HELP: &str = "Highest order k of the hierarchy D_k and of the exact lattice walks, \
    and the longest symbol sequence counted for them (1 to 7)";

pub fn run(a: Args) -> Result<(), Error> {
    a.run(Engine::Auto, theory::run, print)
}

fn print(r: &TheoryReport) {
    println!(
        "w = {}: p_bs = {:.5} ± {:.5}, p_cf = {:.6} ± {:.6} (App. A: {:.6} corrected, {:.6} as printed)",
        r.w,
        r.p_bs,
        r.p_bs_err,
        r.p_cf,
        r.p_cf_err,
        r.p_cf_appendix_a,
        r.p_cf_appendix_a_as_printed
    );
    println!(
        "D_GK (the Lorentz gas) = {:.6} ± {:.6}   D_MZ = {:.6}",
        r.D_GK, r.D_GK_err, r.D_MZ
    );
    let n = r.meta.batches.unwrap_or(0) as usize;
    println!(
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
        println!(
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
    println!(
        "paper's (B2), (B3) as printed: {:.6} ± {:.6}, {:.6} ± {:.6}",
        r.D_2_as_printed, r.D_2_as_printed_err, r.D_3_as_printed, r.D_3_as_printed_err
    );
}
