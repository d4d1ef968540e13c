//! `lorentz escape`: D(w) from the escape rate out of open strips of several widths
//! (Gaspard–Baras), extrapolated in 1/L.

use lorentz_gas::Error;
use lorentz_gas::engine::Engine;
use lorentz_gas::estimators::escape::{self, EscapeConfig, EscapeReport};

use super::args::{GapArg, ResumableArgs, parse_count};

/// What a checkpoint of `escape` keeps: finished particles, not trajectories in flight (the
/// shared help of `--checkpoint` and `--checkpoint-every` describes the latter).
const CHECKPOINT_HELP: &str = "Keep the run's work in this file: each batch's finished particles, \
    saved every --checkpoint-every and when the batch ends; a rerun with the same parameters \
    resumes to the same bits";
const CHECKPOINT_EVERY_HELP: &str = "With --checkpoint: save each batch's finished particles \
    every SECONDS of wall time (0 to 86400; a kill loses about this much work and the particles \
    in flight, each at most t_max long)";

#[derive(clap::Args)]
#[command(
    mut_arg("checkpoint", |a| a.help(CHECKPOINT_HELP)),
    mut_arg("checkpoint_every", |a| a.help(CHECKPOINT_EVERY_HELP))
)]
pub struct Args {
    #[command(flatten)]
    gap: GapArg,
    /// Strip widths L, comma separated, at least 3 distinct (default 8a, 12a, 16a, 24a with
    /// a = 2 + w); each at least max(4a, 10 mean free paths) and at most 2000.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    widths: Option<Vec<f64>>,
    /// Particles injected into each strip width (2e5, 200_000 and 200000 all work); they are
    /// split into the batches the error bars are over.
    #[arg(long, default_value = "2e5", value_parser = parse_count, allow_negative_numbers = true)]
    particles_per_width: u64,
    #[command(flatten)]
    resumable: ResumableArgs,
}

/// The configuration these options give (validated).
pub fn config(a: &Args) -> Result<EscapeConfig, Error> {
    let cfg = EscapeConfig {
        table: a.gap.table(),
        widths: a
            .widths
            .clone()
            .unwrap_or_else(|| escape::default_widths(a.gap.w())),
        particles_per_width: a.particles_per_width,
        seed: a.resumable.run.seed(),
    };
    cfg.validate()?;
    Ok(cfg)
}

pub fn run(a: Args) -> Result<(), Error> {
    let cfg = config(&a)?;
    let total = cfg.particles_per_width * cfg.widths.len() as u64;
    a.resumable.run(
        total,
        "particles",
        Engine::Auto,
        |opts| escape::run(&cfg, opts),
        print,
    )
}

fn print(r: &EscapeReport) {
    print!("{}", lorentz_gas::report::text::escape::escape(r));
}
