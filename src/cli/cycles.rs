//! `lorentz cycles`: the three-disk repeller by certified periodic orbits and their cycle
//! expansions (escape rate, Lyapunov exponent, KS entropy, partial dimension against N).

use std::path::PathBuf;

use lorentz_gas::Error;
use lorentz_gas::files::Output;
use lorentz_gas::verification::cycles::repeller::{
    self, DEFAULT_CYCLE_BITS, DEFAULT_MAX_LENGTH, RepellerConfig,
};
use lorentz_gas::verification::cycles::symbols::prime_words;

use super::args::{OutputArgs, ThreadsArg, parse_count_u32, parse_count_usize};
use super::output::{emit, to_json};
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    /// Side R of the equilateral triangle whose corners are the disk centres, a decimal or a
    /// fraction (exact): R > 2a.
    #[arg(long, default_value = "6", allow_hyphen_values = true)]
    side: String,
    /// Disk radius a, a decimal or a fraction (exact): a > 0.
    #[arg(long, default_value = "1", allow_hyphen_values = true)]
    radius: String,
    /// Longest fundamental-domain prime cycle N of the expansions, 1 to 16 (the table has one
    /// row per N).
    #[arg(long, default_value_t = DEFAULT_MAX_LENGTH, value_parser = parse_count_usize, allow_negative_numbers = true)]
    max_length: usize,
    /// MPFR working precision of the cycles and their certificates, 128 to 4096 bits.
    #[arg(long, default_value_t = DEFAULT_CYCLE_BITS, value_parser = parse_count_u32, allow_negative_numbers = true)]
    bits: u32,
    #[command(flatten)]
    threads: ThreadsArg,
    /// Also write the result's JSON (as --json prints it) to this file.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    #[command(flatten)]
    output: OutputArgs,
}

/// The configuration these options give (validated).
pub fn config(a: &Args) -> Result<RepellerConfig, Error> {
    let cfg = RepellerConfig {
        max_length: a.max_length,
        bits: a.bits,
        ..RepellerConfig::new(&a.side, &a.radius)
    };
    cfg.validate()?;
    Ok(cfg)
}

pub fn run(a: Args) -> Result<(), Error> {
    let cfg = config(&a)?;
    if let Some(out) = &a.out {
        lorentz_gas::files::check_outputs(&[], &[Output::File(out.clone())])?;
    }
    let pb = Progress::new(
        prime_words(cfg.max_length).len() as u64,
        "cycles",
        a.output.quiet,
    );
    let r = repeller::run(&cfg, &pb.options(a.threads.threads()))?;
    drop(pb);
    if let Some(out) = &a.out {
        lorentz_gas::files::write(out, format!("{}\n", to_json(&r)?))?;
    }
    emit(a.output.json, &r, |r| {
        print!("{}", lorentz_gas::report::text::cycles::cycles(r));
    })
}
