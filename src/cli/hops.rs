//! `lorentz hops`: trap-hopping statistics along lattice trajectories.

use lorentz_gas::Error;
use lorentz_gas::estimators::hops::{self, HopsReport};

use super::args::{EngineArg, HopCommand};

/// `lorentz hops` takes the shared hop-analysis options and the engine.
#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub(super) hop: HopCommand,
    #[command(flatten)]
    engine: EngineArg,
}

pub fn run(a: Args) -> Result<(), Error> {
    a.hop.run(a.engine.engine, hops::run, print)
}

fn print(r: &HopsReport) {
    print!("{}", lorentz_gas::report::text::hops::hops(r));
}
