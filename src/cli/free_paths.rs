//! `lorentz free-paths`: the free path between collisions against its Boltzmann–Grad limit law.

use lorentz_gas::Error;
use lorentz_gas::estimators::free_paths::{self, FreePathConfig, FreePathReport};

use super::args::{FlightsArg, OutputArgs, RunArgs, SceneArgs, parse_count, parse_count_u32};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    /// The scene (`--scene square --radius R` for small disks; the triangular scene runs too).
    #[command(flatten)]
    scene: SceneArgs,
    /// Collisions in all, shared between the batches.
    #[arg(long, default_value = "1.6e7", value_parser = parse_count, allow_negative_numbers = true)]
    collisions: u64,
    /// Independent batches (one trajectory each), at least 2; the error bars are over them.
    #[arg(long, default_value = "16", value_parser = parse_count_u32, allow_negative_numbers = true)]
    batches: u32,
    #[command(flatten)]
    flights: FlightsArg,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    output: OutputArgs,
}

pub fn run(a: Args) -> Result<(), Error> {
    let cfg = FreePathConfig {
        collisions: a.collisions,
        batches: a.batches,
        seed: a.run.seed(),
        flights: a.flights.flights,
        ..FreePathConfig::new(a.scene.spec()?)
    };
    cfg.validate()?;
    let pb = Progress::new(a.collisions, "collisions", a.output.quiet);
    let opts = pb.options(a.run.threads());
    let r = free_paths::run(&cfg, &opts)?;
    drop(opts);
    drop(pb);
    emit(a.output.json, &r, print)
}

fn print(r: &FreePathReport) {
    print!("{}", lorentz_gas::report::text::free_paths::free_paths(r));
}
