//! `lorentz backscatter`: injection into one trap from the invariant flux.

use lorentz_gas::Error;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::hops::backscatter::{self, BackscatterConfig, BackscatterReport};

use super::args::{GapArg, OutputArgs, PrecisionArg, RunArgs, parse_count, parse_count_u32};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    gap: GapArg,
    /// Particles injected in all, over every batch (1e7, 10_000_000, ...).
    #[arg(long, default_value = "1e7", value_parser = parse_count, allow_negative_numbers = true)]
    particles: u64,
    #[command(flatten)]
    precision: PrecisionArg,
    /// Independent batches, at least 2; every error bar is over them.
    #[arg(long, default_value = "32", value_parser = parse_count_u32, allow_negative_numbers = true)]
    batches: u32,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    output: OutputArgs,
}

/// The configuration these options give.
pub fn config(a: &Args) -> BackscatterConfig {
    BackscatterConfig {
        table: a.gap.table(),
        particles: a.particles,
        batches: a.batches,
        seed: a.run.seed(),
        run: 0,
        precision: a.precision.precision,
    }
}

pub fn run(a: Args) -> Result<(), Error> {
    let pb = Progress::new(a.particles, "injections", a.output.quiet);
    let cfg = config(&a);
    let progress = pb.callback();
    let opts = RunOptions {
        threads: a.run.threads(),
        progress: &progress,
        ..super::signals::options()
    };
    let r = backscatter::run(&cfg, &opts)?;
    drop(progress);
    drop(pb);
    emit(a.output.json, &r, print)
}

fn print(r: &BackscatterReport) {
    print!("{}", lorentz_gas::report::text::backscatter::backscatter(r));
}
