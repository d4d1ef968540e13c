//! `lorentz theory`: the corrected Machta–Zwanzig hierarchy and exact correlated lattice walks.

use lorentz_gas::error::Error;
use lorentz_gas::hopping::{theory, TheoryReport};

use super::args::{parse_count, parse_count_u32, parse_count_usize, GapArg, OutputArgs, RunArgs};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    gap: GapArg,
    /// Collisions in all.
    #[arg(long, default_value = "2e8", value_parser = parse_count, allow_negative_numbers = true)]
    collisions: u64,
    /// Independent batches (at least 2).
    #[arg(long, default_value = "16", value_parser = parse_count_u32, allow_negative_numbers = true)]
    batches: u32,
    /// Highest order k of the hierarchy and of the lattice walk.
    #[arg(long, default_value = "4", value_parser = parse_count_usize, allow_negative_numbers = true)]
    order: usize,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    output: OutputArgs,
}

pub fn run(a: Args) -> Result<(), Error> {
    let pb = Progress::new(a.collisions, "collisions", a.output.quiet);
    let r = theory(
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

fn print(r: &TheoryReport) {
    println!(
        "w = {}: p_bs = {:.5} ± {:.5}, p_cf = {:.6} ± {:.6} (App. A: {:.6} corrected, {:.6} as printed)",
        r.w, r.p_bs.value, r.p_bs.err, r.p_cf.value, r.p_cf.err, r.p_cf_appendix_a.0, r.p_cf_appendix_a.1
    );
    println!(
        "D_GK (the Lorentz gas) = {:.6} ± {:.6}   D_MZ = {:.6}",
        r.D_GK.value, r.D_GK.err, r.D_MZ
    );
    println!("D_cf = {:.6}  D_bs = {:.6}  D_1 = {:.6}", r.D_cf, r.D_bs, r.D_1);
    for ((k, dk, dc), (_, ex)) in r.D_k.iter().zip(&r.lattice_gas_exact) {
        println!(
            "k = {k}: D_k = {dk:.6}  with collisionless flights {dc:.6}   exact order-{k} lattice walk {ex:.6}"
        );
    }
    println!(
        "paper's (B2), (B3) as printed: {:.6}, {:.6}",
        r.D_2_D_3_as_printed.0, r.D_2_D_3_as_printed.1
    );
}
