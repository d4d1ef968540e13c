//! `lorentz lattice-walk`: Fig. 6b by simulation — correlated walks on the measured symbol tables.

use lorentz_gas::Error;
use lorentz_gas::engine::Engine;
use lorentz_gas::estimators::hops::lattice_walks::{self, LatticeWalkReport};

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
    print!(
        "{}",
        lorentz_gas::report::text::lattice_walk::lattice_walk(r)
    );
}
