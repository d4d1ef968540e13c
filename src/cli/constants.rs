//! `lorentz constants`: every closed form of a scene, at any precision, with the corridors and
//! the superdiffusion constants of an infinite horizon.

use lorentz_gas::Error;
use lorentz_gas::scenes::spec::SceneSpec;
use lorentz_gas::theory::constants::{self, ConstantsConfig, ConstantsReport};

use super::args::{Exact, PrecisionArg, SceneName, parse_exact_arg};

#[derive(clap::Args)]
pub struct Args {
    /// The scene: `triangular` (disks of radius 1 at spacing 2 + w, needs --w; any w > 0, the
    /// corridors listed beyond w_inf) or `square` (disks of radius r at unit spacing, needs
    /// --radius).
    #[arg(long, default_value = "triangular")]
    scene: SceneName,
    /// Gap w of the triangular scene, a decimal or a fraction such as 1/10: w > 0.
    #[arg(long, value_parser = parse_exact_arg, allow_hyphen_values = true)]
    w: Option<Exact>,
    /// Disk radius of the square scene, a decimal or a fraction such as 1/3: 0 < r < 1/2.
    #[arg(long, value_parser = parse_exact_arg, allow_hyphen_values = true)]
    radius: Option<Exact>,
    #[command(flatten)]
    precision: PrecisionArg,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> Result<(), Error> {
    let name = match a.scene {
        SceneName::Triangular => "triangular",
        SceneName::Square => "square",
    };
    let text = |e: &Option<Exact>| e.as_ref().map(|e| e.text.clone());
    let scene = SceneSpec::parse(name, text(&a.w).as_deref(), text(&a.radius).as_deref())?;
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
