//! `lorentz theory`: the corrected Machta–Zwanzig hierarchy and exact correlated lattice walks.

use lorentz_gas::Error;
use lorentz_gas::engine::Engine;
use lorentz_gas::estimators::hops::theory::{self, TheoryReport};

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
    print!("{}", lorentz_gas::report::text::theory::theory(r));
}
