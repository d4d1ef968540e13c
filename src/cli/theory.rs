//! `lorentz theory`: the corrected Machta–Zwanzig hierarchy and exact correlated lattice walks.

use lorentz_gas::engine::Engine;
use lorentz_gas::estimators::hops::theory::{self, TheoryReport};
use lorentz_gas::Error;

use super::args::HopCommand;

/// `lorentz theory` takes the shared hop-analysis options.
pub type Args = HopCommand;

pub fn run(a: Args) -> Result<(), Error> {
    a.run(Engine::Auto, theory::run, print)
}

fn print(r: &TheoryReport) {
    println!(
        "w = {}: p_bs = {:.5} ± {:.5}, p_cf = {:.6} ± {:.6} (App. A: {:.6} corrected, {:.6} as printed)",
        r.w, r.p_bs.value, r.p_bs.err, r.p_cf.value, r.p_cf.err, r.p_cf_appendix_a.0, r.p_cf_appendix_a.1
    );
    println!(
        "D_GK (the Lorentz gas) = {:.6} ± {:.6}   D_MZ = {:.6}",
        r.D_GK.value, r.D_GK.err, r.D_MZ
    );
    println!(
        "D_cf = {:.6}  D_bs = {:.6}  D_1 = {:.6}",
        r.D_cf, r.D_bs, r.D_1
    );
    for ((k, dk, dc), (_, ex)) in r.D_k.iter().zip(&r.lattice_gas_exact) {
        println!(
            "k = {k}: D_k = {dk:.6}  with collisionless flights {dc:.6}   exact order-{k} lattice walk {ex:.6}"
        );
    }
    println!(
        "paper's (B2), (B3) as printed: {:.6}, {:.6}",
        r.D_2_D_3_as_printed.0, r.D_2_D_3_as_printed.1
    );
}
