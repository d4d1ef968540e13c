//! `lorentz constants`: every closed form of a scene, at any precision, with the corridors and
//! the superdiffusion constants of an infinite horizon.

use lorentz_gas::Error;
use lorentz_gas::theory::constants::{self, ConstantsConfig, ConstantsReport};

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
        print(&r);
    }
    Ok(())
}

/// Text shows the digits the working precision guarantees; JSON carries every digit.
fn print(r: &ConstantsReport) {
    if let Some(q) = &r.w_exact {
        println!("{:<20} {:<45} gap as typed, exactly", "w_exact", q);
    }
    if let Some(q) = &r.radius_exact {
        println!("{:<20} {:<45} radius as typed, exactly", "radius_exact", q);
    }
    for c in &r.rows {
        println!("{:<20} {:<45} {}", c.name, c.shown, c.formula);
    }
    match (&r.max_free_path_bound, &r.superdiffusion) {
        (Some(c), _) => println!("{:<20} {:<45} {}", c.name, c.shown, c.formula),
        (None, Some(sd)) => {
            println!(
                "infinite horizon: free paths are unbounded, D does not exist; {} corridors and the superdiffusion constants (proofs-notes/corridors.md):",
                sd.corridors.len()
            );
            for c in &sd.rows {
                println!("{:<20} {:<45} {}", c.name, c.shown, c.formula);
            }
            println!("corridor (m, n)      angle (deg)     period          width");
            for c in &sd.corridors {
                println!(
                    "({:>4}, {:>4})         {:>10.4}      {:<15.10} {:.10}",
                    c.direction[0], c.direction[1], c.angle_degrees, c.period, c.width
                );
            }
        }
        (None, None) => {}
    }
}
