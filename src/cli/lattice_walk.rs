//! `lorentz lattice-walk`: Fig. 6b by simulation — correlated walks on the measured symbol tables.

use lorentz_gas::error::Error;
use lorentz_gas::hopping::{lattice_walks, LatticeWalkReport};

use super::args::{parse_count, parse_count_u32, parse_count_usize, GapArg, OutputArgs, RunArgs};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    gap: GapArg,
    /// Lorentz-gas collisions used to measure the symbol tables.
    #[arg(long, default_value = "1e8", value_parser = parse_count, allow_negative_numbers = true)]
    collisions: u64,
    /// Independent batches of the Lorentz-gas measurement (at least 2).
    #[arg(long, default_value = "16", value_parser = parse_count_u32, allow_negative_numbers = true)]
    batches: u32,
    /// Highest order of the walks (1 to 7).
    #[arg(long, default_value = "4", value_parser = parse_count_usize, allow_negative_numbers = true)]
    order: usize,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    output: OutputArgs,
}

pub fn run(a: Args) -> Result<(), Error> {
    let pb = Progress::new(a.collisions, "collisions", a.output.quiet);
    let r = lattice_walks(
        a.gap.w,
        a.collisions,
        a.batches,
        a.order,
        a.run.seed,
        a.run.threads(),
        &pb.callback(),
    )?;
    drop(pb);
    emit(a.output.json, &r, print)
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
