//! `lorentz hops`: trap-hopping statistics along lattice trajectories.

use lorentz_gas::error::Error;
use lorentz_gas::hopping::{hops, HopsReport};

use super::args::{parse_count, parse_count_u32, parse_count_usize, GapArg, OutputArgs, RunArgs};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    gap: GapArg,
    /// Collisions in all.
    #[arg(long, default_value = "5e8", value_parser = parse_count, allow_negative_numbers = true)]
    collisions: u64,
    /// Independent batches (at least 2).
    #[arg(long, default_value = "32", value_parser = parse_count_u32, allow_negative_numbers = true)]
    batches: u32,
    /// Longest symbol sequence counted.
    #[arg(long, default_value = "4", value_parser = parse_count_usize, allow_negative_numbers = true)]
    order: usize,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    output: OutputArgs,
}

pub fn run(a: Args) -> Result<(), Error> {
    let pb = Progress::new(a.collisions, "collisions", a.output.quiet);
    let r = hops(
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

fn print(r: &HopsReport) {
    println!(
        "trap hopping along lattice trajectories, w = {} ({} visits, {:.2e} collisions, {} batches, seed {})",
        r.w,
        r.visits,
        r.collisions as f64,
        r.meta.batches.unwrap_or_default(),
        r.meta.seed.unwrap_or_default()
    );
    println!(
        "p_bs = {:.5} ± {:.5}   p_cf = {:.6} ± {:.6}",
        r.p_bs, r.p_bs_err, r.p_cf, r.p_cf_err
    );
    let pairs: Vec<String> = r
        .pairs
        .iter()
        .map(|(k, e)| format!("p({k}) = {:.5} ± {:.5}", e.value, e.err))
        .collect();
    for c in pairs.chunks(3) {
        println!("{}", c.join("   "));
    }
    println!(
        "symmetries p(s) = p(mirror s) = p(reversed mirror s): largest |z| = {:.2}",
        r.symmetry_max_z
    );
    println!(
        "hop-level Green-Kubo D = {:.6} ± {:.6}   (D_MZ = {:.6})",
        r.D_GK, r.D_GK_err, r.D_MZ
    );
}
