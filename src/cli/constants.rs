//! `lorentz constants`: every closed form at gap w, at any precision.

use lorentz_gas::theory::constants::{self, ConstantsConfig, ConstantsReport};
use lorentz_gas::Error;

use super::args::{GapArg, PrecisionArg};

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    gap: GapArg,
    #[command(flatten)]
    precision: PrecisionArg,
    /// Machine-readable output.
    #[arg(long)]
    json: bool,
}

pub fn run(a: Args) -> Result<(), Error> {
    let r = constants::run(&ConstantsConfig {
        w: a.gap.w(),
        w_exact: a.gap.exact_text(),
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
    for c in &r.rows {
        println!("{:<20} {:<45} {}", c.name, c.shown, c.formula);
    }
    match &r.max_free_path_bound {
        Some(c) => println!("{:<20} {:<45} {}", c.name, c.shown, c.formula),
        None => {
            println!("w >= w_inf: infinite horizon, free paths are unbounded and D does not exist")
        }
    }
}
