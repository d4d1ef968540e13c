//! `lorentz lattice-walk`: Fig. 6b by simulation — correlated walks on the measured symbol tables.

use lorentz_gas::engine::Engine;
use lorentz_gas::estimators::hops::lattice_walks::{self, LatticeWalkReport};
use lorentz_gas::Error;

use super::args::HopCommand;

/// `lorentz lattice-walk` takes the shared hop-analysis options.
pub type Args = HopCommand;

pub fn run(a: Args) -> Result<(), Error> {
    a.run(Engine::Auto, lattice_walks::run, print)
}

fn print(r: &LatticeWalkReport) {
    println!(
        "w = {}: D_MZ = {:.6}, hop-level Green-Kubo D of the Lorentz gas = {:.6} ± {:.6}",
        r.w, r.D_MZ, r.D_GK, r.D_GK_err
    );
    for x in &r.walks {
        println!(
            "order {}: simulated D = {:.6} ± {:.6}   exact D = {:.6}",
            x.order, x.D_simulated, x.D_simulated_err, x.D_exact
        );
    }
}
