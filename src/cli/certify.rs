//! `lorentz certify`: certify a segment by precision doubling.

use lorentz_gas::Error;
use lorentz_gas::verification::certify::{self, CertifyConfig};

use super::args::{
    OutputArgs, SceneArgs, parse_count, parse_count_u32, parse_count_usize, with_scene,
};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    /// Collisions in the segment.
    #[arg(long, default_value = "1000", value_parser = parse_count_usize, allow_negative_numbers = true)]
    collisions: usize,
    /// Digits to certify (1 or more).
    #[arg(long, default_value = "30", value_parser = parse_count_u32, allow_negative_numbers = true)]
    digits: u32,
    /// Seed of the equilibrium start (the start of batch 0 of `diffusion --seed SEED`).
    #[arg(long, default_value = "1", value_parser = parse_count, allow_negative_numbers = true)]
    seed: u64,
    #[command(flatten)]
    output: OutputArgs,
}

pub fn run(a: Args) -> Result<(), Error> {
    // Two MPFR runs and one f64 run of the segment when the first precision suffices.
    let pb = Progress::new(3 * a.collisions as u64, "collisions", a.output.quiet);
    let choice = a.scene.resolve()?;
    let cfg = CertifyConfig {
        collisions: a.collisions,
        digits: a.digits,
        seed: a.seed,
    };
    let opts = pb.options(1);
    let c = with_scene!(&choice, |s| certify::run(s, &cfg, &opts))?;
    drop(opts);
    drop(pb);
    emit(a.output.json, &c, |c| {
        print!("{}", lorentz_gas::report::text::certify::certify(c));
    })
}
