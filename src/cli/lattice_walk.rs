//! `lorentz lattice-walk`: Fig. 6b by simulation — correlated walks on the measured symbol tables.

use lorentz_gas::Error;
use lorentz_gas::engine::Engine;
use lorentz_gas::estimators::hops::lattice_walks::{self, LatticeWalkReport};
use lorentz_gas::statistics::comparison;

use super::args::HopCommand;

/// `lorentz lattice-walk` takes the shared hop-analysis options.
pub type Args = HopCommand;

/// The help of `--order` for `lorentz lattice-walk` (the shared text is `hops`'s).
pub const ORDER_HELP: &str = "Highest order K of the correlated lattice walks simulated (orders 1 \
    to K), and the longest symbol sequence counted for their tables (1 to 7)";

pub fn run(a: Args) -> Result<(), Error> {
    a.run(Engine::Auto, lattice_walks::run, print)
}

fn print(r: &LatticeWalkReport) {
    println!(
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
        println!(
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
}
