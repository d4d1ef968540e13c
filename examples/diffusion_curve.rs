//! D(w) at a few gaps through the library API, with standard errors, beside Machta–Zwanzig.
//!
//! ```sh
//! cargo run --release --example diffusion_curve            # 4·10⁷ collisions per gap
//! cargo run --release --example diffusion_curve -- 2e9     # the command line's default
//! ```
//!
//! Every analysis of the crate is a validated configuration and one call,
//! `run(&config, &RunOptions)`; the options (engine, threads, progress, resume) never change the
//! bits of a result.

use lorentz_gas::Error;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::diffusion::{self, DiffusionConfig};

fn main() -> Result<(), Error> {
    let collisions = match std::env::args().nth(1) {
        Some(s) => s
            .parse::<f64>()
            .ok()
            .filter(|c| c.is_finite() && *c >= 1e6 && *c <= 1e13)
            .ok_or_else(|| Error::Invalid(format!("collisions = {s}: use 1e6 to 1e13")))?
            as u64,
        None => 40_000_000,
    };
    let options = RunOptions::default();
    println!("    w      D            ± err       D_MZ       D/D_MZ   seconds");
    for w in [0.05, 0.1, 0.15, 0.2, 0.25, 0.3] {
        let cfg = DiffusionConfig {
            collisions,
            batches: 16,
            ..DiffusionConfig::new(w)
        };
        let r = diffusion::run(&cfg, &options)?;
        println!(
            "  {w:.2}   {:.6}   ± {:.6}   {:.6}   {:.4}   {:.1}",
            r.D,
            r.D_err,
            r.D_MZ,
            r.D / r.D_MZ,
            r.seconds
        );
    }
    Ok(())
}
