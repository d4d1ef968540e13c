//! `lorentz cycles`: certified periodic orbits and their cycle expansions — the three-disk
//! repeller (escape rate, Lyapunov exponent, KS entropy, partial dimension against N, with
//! `--side`/`--radius`), or the triangular Lorentz gas (D by cycle averaging against N beside
//! the MSD's, with `--w`).

use std::path::PathBuf;

use lorentz_gas::Error;
use lorentz_gas::files::Output;
use lorentz_gas::verification::cycles::lattice::letters::LETTERS;
use lorentz_gas::verification::cycles::lattice::run::{
    self as lattice, DEFAULT_LATTICE_BITS, DEFAULT_LATTICE_LENGTH, DEFAULT_MSD_COLLISIONS,
    LatticeConfig,
};
use lorentz_gas::verification::cycles::repeller::{
    self, DEFAULT_CYCLE_BITS, DEFAULT_MAX_LENGTH, RepellerConfig,
};
use lorentz_gas::verification::cycles::symbols::{prime_word_count, prime_words};

use super::args::{OutputArgs, ThreadsArg, parse_count, parse_count_u32, parse_count_usize};
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
    /// The triangular Lorentz gas at gap w instead of the repeller, a decimal or a fraction
    /// (exact): 0 < w < w_inf = 0.309402 (a finite horizon). D by cycle averaging.
    #[arg(long, allow_hyphen_values = true, conflicts_with_all = ["side", "radius"])]
    w: Option<String>,
    /// Longest prime cycle N of the expansions (the table has one row per N): the repeller's
    /// fundamental-domain cycles, 1 to 16 (default 8); the lattice's, in collisions, 1 to 7
    /// (default 5).
    #[arg(long, value_parser = parse_count_usize, allow_negative_numbers = true)]
    max_length: Option<usize>,
    /// MPFR working precision of the cycles and their certificates, 128 to 4096 bits (default
    /// 256 for the repeller, 128 for the lattice).
    #[arg(long, value_parser = parse_count_u32, allow_negative_numbers = true)]
    bits: Option<u32>,
    /// With --w: collisions of the MSD run whose D stands beside the table, 10^6 to 10^11, or 0
    /// for none (default 2e8).
    #[arg(long, requires = "w", value_parser = parse_count, allow_negative_numbers = true)]
    msd_collisions: Option<u64>,
    #[command(flatten)]
    threads: ThreadsArg,
    /// Also write the result's JSON (as --json prints it) to this file.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    #[command(flatten)]
    output: OutputArgs,
}

/// The repeller's configuration these options give (validated).
pub fn config(a: &Args) -> Result<RepellerConfig, Error> {
    let cfg = RepellerConfig {
        max_length: a.max_length.unwrap_or(DEFAULT_MAX_LENGTH),
        bits: a.bits.unwrap_or(DEFAULT_CYCLE_BITS),
        ..RepellerConfig::new(&a.side, &a.radius)
    };
    cfg.validate()?;
    Ok(cfg)
}

/// The lattice's configuration at the gap `w` (validated).
pub fn lattice_config(a: &Args, w: &str) -> Result<LatticeConfig, Error> {
    let cfg = LatticeConfig {
        max_length: a.max_length.unwrap_or(DEFAULT_LATTICE_LENGTH),
        bits: a.bits.unwrap_or(DEFAULT_LATTICE_BITS),
        msd_collisions: a.msd_collisions.unwrap_or(DEFAULT_MSD_COLLISIONS),
        ..LatticeConfig::new(w)
    };
    cfg.validate()?;
    Ok(cfg)
}

pub fn run(a: Args) -> Result<(), Error> {
    if let Some(w) = a.w.clone() {
        let cfg = lattice_config(&a, &w)?;
        let total = prime_word_count(LETTERS.len() as u64, cfg.max_length);
        return run_and_emit(
            &a,
            total,
            |o| lattice::run(&cfg, o),
            lorentz_gas::report::text::lattice_cycles::lattice_cycles,
        );
    }
    let cfg = config(&a)?;
    let total = prime_words(cfg.max_length).len() as u64;
    run_and_emit(
        &a,
        total,
        |o| repeller::run(&cfg, o),
        lorentz_gas::report::text::cycles::cycles,
    )
}

/// Runs `f` with a bar over `total` prime words, writes its result to `--out` if asked (the path
/// checked first) and prints it (`text`, or JSON).
fn run_and_emit<R: serde::Serialize>(
    a: &Args,
    total: u64,
    f: impl FnOnce(&lorentz_gas::engine::options::RunOptions) -> Result<R, Error>,
    text: impl Fn(&R) -> String,
) -> Result<(), Error> {
    if let Some(out) = &a.out {
        lorentz_gas::files::check_outputs(&[], &[Output::File(out.clone())])?;
    }
    let pb = Progress::new(total, "cycles", a.output.quiet);
    let r = f(&pb.options(a.threads.threads()))?;
    drop(pb);
    if let Some(out) = &a.out {
        lorentz_gas::files::write(out, format!("{}\n", to_json(&r)?))?;
    }
    emit(a.output.json, &r, |r| print!("{}", text(r)))
}
