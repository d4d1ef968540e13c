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
    /// The histogram's bin edges in xi = tau/l (l the mean free path), as E0,E1,...: 2 to 1001
    /// finite numbers >= 0, increasing (flights outside [E0, last) fall in no bin; default:
    /// quarters to 2, then wider bins to an open last one).
    #[arg(long, value_name = "EDGES", value_parser = edges)]
    bins: Option<Edges>,
    /// Keep the xi of this many flights (0 to 1e6), spread evenly over each batch's trajectory,
    /// as `free_path_samples` in the JSON.
    #[arg(long, default_value = "0", value_parser = parse_count, allow_negative_numbers = true)]
    keep_samples: u64,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    output: OutputArgs,
}

/// The edges of `--bins` (one value, not a list of them to clap).
#[derive(Clone)]
struct Edges(Vec<f64>);

fn edges(text: &str) -> Result<Edges, Error> {
    free_paths::parse_edges(text).map(Edges)
}

pub fn run(a: Args) -> Result<(), Error> {
    let cfg = FreePathConfig {
        collisions: a.collisions,
        batches: a.batches,
        seed: a.run.seed(),
        flights: a.flights.flights,
        bins: a.bins.map(|e| e.0),
        keep_samples: a.keep_samples,
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
