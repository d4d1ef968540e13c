//! `lorentz constants`: every closed form of a scene, at any precision, with the corridors and
//! the superdiffusion constants of an infinite horizon.

use lorentz_gas::Error;
use lorentz_gas::theory::constants::{self, ConstantsConfig};

use super::args::{PrecisionArg, SceneArgs};

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    #[command(flatten)]
    precision: PrecisionArg,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> Result<(), Error> {
    // Any w > 0: beyond w_inf the corridors and the superdiffusion constants are listed.
    let scene = a.scene.spec()?;
    let r = constants::run(&ConstantsConfig {
        scene,
        precision: a.precision.precision,
    })?;
    if a.json {
        println!("{}", r.to_json()?);
    } else {
        print!("{}", lorentz_gas::report::text::constants::constants(&r));
    }
    Ok(())
}
