//! `lorentz backscatter`: injection into one trap from the invariant flux.

use lorentz_gas::Error;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::hops::backscatter::{self, BackscatterConfig, BackscatterReport};
use lorentz_gas::statistics::comparison;

use super::args::{GapArg, OutputArgs, PrecisionArg, RunArgs, parse_count, parse_count_u32};
use super::output::{emit, sigmas};
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
        w: a.gap.w(),
        w_exact: a.gap.exact_text(),
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
    let n = r.meta.batches.unwrap_or_default() as usize;
    println!(
        "injection into one trap, w = {} ({} particles, {} batches, seed {}){}",
        r.w,
        r.particles,
        r.meta.batches.unwrap_or_default(),
        r.meta.seed.unwrap_or_default(),
        comparison::few_samples_note(n, "batches")
    );
    println!(
        "p_bs = {:.5} ± {:.5}   p_l = {:.5} ± {:.5}   p_r = {:.5} ± {:.5}   p_cf = {:.5} ± {:.5}",
        r.p_bs, r.p_bs_err, r.p_l, r.p_l_err, r.p_r, r.p_r_err, r.p_cf, r.p_cf_err
    );
    println!(
        "mean visit time      = {:.5} ± {:.5}   Kac tau = {:.5}  ({})",
        r.mean_visit_time,
        r.mean_visit_time_err,
        r.mean_visit_time_exact,
        sigmas(
            r.mean_visit_time,
            r.mean_visit_time_err,
            r.mean_visit_time_exact,
            n
        )
    );
    println!(
        "collisions per visit = {:.4} ± {:.4}   Kac pi/(3w) = {:.4}  ({})",
        r.mean_collisions_per_visit,
        r.mean_collisions_per_visit_err,
        r.mean_collisions_per_visit_exact,
        sigmas(
            r.mean_collisions_per_visit,
            r.mean_collisions_per_visit_err,
            r.mean_collisions_per_visit_exact,
            n
        )
    );
}
