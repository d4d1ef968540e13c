//! `lorentz bench`: kernel throughput, and with `--report` the speed-against-error table.

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::throughput::{self, Throughput, ThroughputConfig};
use lorentz_gas::report::speed_error::{self, SpeedErrorConfig, REPORT_STEPS};
use lorentz_gas::Error;

use super::args::{
    parse_count, parse_count_usize, EngineArg, GapArg, OutDirArg, OutputArgs, PrecisionArg, RunArgs,
};
use super::output::{emit, to_json};
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    gap: GapArg,
    /// Collisions per thread per repetition (the SIMD engine shares them out over the thread's
    /// 16 trajectories).
    #[arg(long, default_value = "2e7", value_parser = parse_count, allow_negative_numbers = true)]
    collisions: u64,
    /// Repetitions (the median is reported), 1 to 1000.
    #[arg(long, default_value = "7", value_parser = parse_count_usize, allow_negative_numbers = true)]
    repetitions: usize,
    #[command(flatten)]
    precision: PrecisionArg,
    #[command(flatten)]
    engine: EngineArg,
    /// Observers to run along (to measure what observation costs): none (the bare engine),
    /// counters, msd, diffusion (counters + MSD, as in `lorentz diffusion`), hops.
    #[arg(long, value_enum, default_value = "none")]
    observe: lorentz_gas::estimators::throughput::Observe,
    /// Seed of the starting points; --threads K runs K trajectories at once, one per thread
    /// (default: 1, the single-core kernel speed).
    #[command(flatten)]
    run: RunArgs,
    /// Speed against error for f64 and MPFR 53..1024 bits: Markdown, JSON, PNG and SVG into --out.
    #[arg(long)]
    report: bool,
    #[command(flatten)]
    out: OutDirArg,
    #[command(flatten)]
    output: OutputArgs,
}

pub fn run(a: Args) -> Result<(), Error> {
    let threads = a.run.threads.unwrap_or(1);
    if a.report {
        let out = a.out.dir("results");
        let pb = Progress::new(REPORT_STEPS, "steps", a.output.quiet);
        let cfg = SpeedErrorConfig {
            w: a.gap.w,
            seed: a.run.seed,
            out: out.clone(),
        };
        let opts = pb.options(a.run.threads());
        let (r, md) = speed_error::run(&cfg, &opts)?;
        drop(opts);
        drop(pb);
        if a.output.json {
            println!("{}", to_json(&r)?);
        } else {
            println!("{md}");
            println!(
                "written: {}/speed-vs-error.{{md,json,png,svg}}",
                out.display()
            );
        }
        return Ok(());
    }
    let pb = Progress::new(a.repetitions as u64, "repetitions", a.output.quiet);
    let cfg = ThroughputConfig {
        w: a.gap.w,
        precision: a.precision.precision,
        observe: a.observe,
        collisions: a.collisions,
        repetitions: a.repetitions,
        seed: a.run.seed,
    };
    let opts = RunOptions {
        engine: a.engine.engine,
        ..pb.options(threads)
    };
    let r = throughput::run(&cfg, &opts)?;
    drop(opts);
    drop(pb);
    emit(a.output.json, &r, print)
}

fn print(r: &Throughput) {
    println!(
        "w = {}  precision {}  engine {}  {} collisions x {} repetitions on {} thread(s)\nmedian {:.3e} collisions/s ({:.3e} per thread) = {:.2} ns/collision per thread  (runs: {})",
        r.w,
        r.meta.precision,
        match &r.meta.simd {
            Some(p) => format!("{} ({p})", r.meta.engine),
            None => r.meta.engine.clone(),
        },
        r.collisions,
        r.repetitions,
        r.threads,
        r.collisions_per_second,
        r.collisions_per_second_per_thread,
        r.ns_per_collision,
        r.samples
            .iter()
            .map(|s| format!("{s:.3e}"))
            .collect::<Vec<_>>()
            .join(" ")
    );
}
