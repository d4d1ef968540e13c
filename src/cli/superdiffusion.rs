//! `lorentz superdiffusion`: an infinite horizon's flight tails, velocity autocorrelation, t ln t
//! growth and limit law, each against the exact corridor constants.

use lorentz_gas::Error;
use lorentz_gas::engine::Engine;
use lorentz_gas::estimators::superdiffusion::{self, SuperdiffusionConfig, SuperdiffusionReport};

use super::args::{FlightsArg, ResumableArgs, SceneArgs, parse_count, parse_count_u32};

/// The gap superdiffusion needs (the shared help of `--w` gives the whole range w > 0).
const GAP_HELP: &str = "Gap w of the triangular scene, a decimal or a fraction such as 1/10: w > \
    w_inf = 4/sqrt(3) - 2 = 0.3094... (an infinite horizon)";

#[derive(clap::Args)]
#[command(mut_arg("w", |a| a.help(GAP_HELP)))]
pub struct Args {
    /// The scene (an infinite horizon: `--scene triangular --w W` with W > w_inf = 0.3094..., or
    /// `--scene square --radius R`).
    #[command(flatten)]
    scene: SceneArgs,
    /// Collisions in all, shared between the batches.
    #[arg(long, default_value = "2e8", value_parser = parse_count, allow_negative_numbers = true)]
    collisions: u64,
    /// Independent batches (one trajectory each), at least 16; the error bars are over them.
    #[arg(long, default_value = "32", value_parser = parse_count_u32, allow_negative_numbers = true)]
    batches: u32,
    /// The longest lag is 2^OCTAVES mean free times (1 to 20).
    #[arg(long, default_value = "12", value_parser = parse_count_u32, allow_negative_numbers = true)]
    octaves: u32,
    /// Lags per octave (1 to 16).
    #[arg(long, default_value = "4", value_parser = parse_count_u32, allow_negative_numbers = true)]
    points_per_octave: u32,
    /// The tail fits s P(tau > s) = C + B/s and s^2 mu(tau > s) = C + B/s use the times s from
    /// this many mean free times on (where every batch saw 100 longer flights).
    #[arg(long, default_value = "8", allow_negative_numbers = true)]
    tail_fit_from: f64,
    /// The lags of the plateau of t C(t), FROM:TO in mean free times; by default 2^(OCTAVES-6)
    /// to 2^(OCTAVES-4) (64:256 at 12 octaves).
    #[arg(long, value_parser = parse_window, allow_hyphen_values = true)]
    vacf_fit: Option<[f64; 2]>,
    /// The lags of the fit of <dx^2>/t = a ln t + b, FROM:TO in mean free times; by default
    /// 2^(OCTAVES-3) to 2^OCTAVES (512:4096 at 12 octaves).
    #[arg(long, value_parser = parse_window, allow_hyphen_values = true)]
    msd_fit: Option<[f64; 2]>,
    #[command(flatten)]
    flights: FlightsArg,
    #[command(flatten)]
    resumable: ResumableArgs,
}

/// A window FROM:TO of two positive numbers.
fn parse_window(text: &str) -> Result<[f64; 2], String> {
    let bad = || {
        format!("'{text}' is not a window FROM:TO: use two numbers such as 64:256, 1 <= FROM < TO")
    };
    let (a, b) = text.split_once(':').ok_or_else(bad)?;
    let a: f64 = a.trim().parse().map_err(|_| bad())?;
    let b: f64 = b.trim().parse().map_err(|_| bad())?;
    if !(a >= 1.0 && a < b && b.is_finite()) {
        return Err(bad());
    }
    Ok([a, b])
}

pub fn run(a: Args) -> Result<(), Error> {
    let windows = SuperdiffusionConfig::new(a.scene.spec()?).with_octaves(a.octaves);
    let cfg = SuperdiffusionConfig {
        collisions: a.collisions,
        batches: a.batches,
        points_per_octave: a.points_per_octave,
        tail_fit_from: a.tail_fit_from,
        vacf_fit: a.vacf_fit.unwrap_or(windows.vacf_fit),
        msd_fit: a.msd_fit.unwrap_or(windows.msd_fit),
        seed: a.resumable.run.seed(),
        flights: a.flights.flights,
        ..windows
    };
    cfg.validate()?;
    a.resumable.run(
        a.collisions,
        "collisions",
        Engine::Auto,
        |opts| superdiffusion::run(&cfg, opts),
        print,
    )
}

fn print(r: &SuperdiffusionReport) {
    print!(
        "{}",
        lorentz_gas::report::text::superdiffusion::superdiffusion(r)
    );
}
