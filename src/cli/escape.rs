//! `lorentz escape`: D(w) from the escape rate out of open strips of several widths
//! (Gaspard–Baras), extrapolated in 1/L; or, on an open table (`--repeller`, `--open FILE`),
//! its escape rate, Lyapunov exponent and KS entropy by survival.

use std::path::PathBuf;

use lorentz_gas::Error;
use lorentz_gas::engine::Engine;
use lorentz_gas::estimators::escape::survival::{
    self, DEFAULT_WINDOW, SurvivalConfig, SurvivalReport,
};
use lorentz_gas::estimators::escape::{self, EscapeConfig, EscapeReport};
use lorentz_gas::scenes::open::OpenSpec;

use super::args::{
    Exact, ResumableArgs, parse_count, parse_count_u32, parse_diffusive_gap, table_at,
};

/// What a checkpoint of `escape` keeps: finished particles, not trajectories in flight (the
/// shared help of `--checkpoint` and `--checkpoint-every` describes the latter).
const CHECKPOINT_HELP: &str = "Keep the run's work in this file: each batch's finished particles, \
    saved every --checkpoint-every and when the batch ends; a rerun with the same parameters \
    resumes to the same bits (open strips only)";
const CHECKPOINT_EVERY_HELP: &str = "With --checkpoint: save each batch's finished particles \
    every SECONDS of wall time (0 to 86400; a kill loses about this much work and the particles \
    in flight, each at most t_max long)";

#[derive(clap::Args)]
#[command(
    mut_arg("checkpoint", |a| a.help(CHECKPOINT_HELP)),
    mut_arg("checkpoint_every", |a| a.help(CHECKPOINT_EVERY_HELP))
)]
pub struct Args {
    /// Gap w between neighbouring disks (radius 1) of the triangular gas whose open strips are
    /// measured, a decimal or a fraction such as 1/10: 0 < w < w_inf = 4/sqrt(3) - 2 =
    /// 0.3094... (not with --repeller or --open)
    #[arg(long = "w", value_name = "W", value_parser = parse_diffusive_gap, allow_hyphen_values = true,
          required_unless_present_any = ["repeller", "open"], conflicts_with_all = ["repeller", "open"])]
    gap: Option<Exact>,
    /// Strip widths L, comma separated, at least 3 distinct (default 8a, 12a, 16a, 24a with
    /// a = 2 + w); each at least max(4a, 10 mean free paths) and at most 2000.
    #[arg(
        long,
        value_delimiter = ',',
        allow_negative_numbers = true,
        requires = "gap"
    )]
    widths: Option<Vec<f64>>,
    /// Particles injected into each strip width (2e5, 200_000 and 200000 all work); they are
    /// split into the batches the error bars are over.
    #[arg(long, default_value = "2e5", value_parser = parse_count, allow_negative_numbers = true)]
    particles_per_width: u64,
    /// The open table: the three-disk repeller (disks of radius --radius at the corners of the
    /// equilateral triangle of side --side); its escape rate, Lyapunov exponent and KS entropy
    /// by survival.
    #[arg(long, conflicts_with = "open")]
    repeller: bool,
    /// Side R of the repeller's triangle (distance between centres), a decimal or a fraction
    /// (exact): R > 2a.
    #[arg(
        long,
        default_value = "6",
        allow_hyphen_values = true,
        requires = "repeller"
    )]
    side: String,
    /// Disk radius a of the repeller, a decimal or a fraction (exact): a > 0.
    #[arg(
        long,
        default_value = "1",
        allow_hyphen_values = true,
        requires = "repeller"
    )]
    radius: String,
    /// The open table in this JSON file: {"name": ..., "disks": [{"centre": ["x", "y"],
    /// "radius": "r"}, ...]}, 2 to 64 disjoint disks, numbers quoted (exact) or integers.
    #[arg(long, value_name = "FILE")]
    open: Option<PathBuf>,
    /// Particles started on the open table (1e7, 10_000_000 and 10000000 all work), 32000 to
    /// 1e12; split into 32 batches, the error bars are over them.
    #[arg(long, default_value = "1e7", value_parser = parse_count, allow_negative_numbers = true)]
    particles: u64,
    /// The collision n0 at which the survival window starts (1 to 20); the window one collision
    /// later is the check.
    #[arg(long, default_value_t = DEFAULT_WINDOW, value_parser = parse_count_u32, allow_negative_numbers = true)]
    window: u32,
    #[command(flatten)]
    resumable: ResumableArgs,
}

/// The open table these options name, `None` for the strips.
fn open_table(a: &Args) -> Result<Option<OpenSpec>, Error> {
    if a.repeller {
        let spec = OpenSpec::repeller(&a.side, &a.radius)?;
        spec.validate()?;
        return Ok(Some(spec));
    }
    let Some(path) = &a.open else {
        return Ok(None);
    };
    let text = lorentz_gas::files::read_to_string(path, lorentz_gas::files::Cap::TABLE)?;
    OpenSpec::from_json(&text)
        .map(Some)
        .map_err(|e| Error::malformed(path, e))
}

/// The strips' configuration these options give (validated).
pub fn config(a: &Args) -> Result<EscapeConfig, Error> {
    let gap = (a.gap.as_ref())
        .ok_or_else(|| Error::missing("w", "give --w, --repeller or --open FILE"))?;
    let cfg = EscapeConfig {
        table: table_at(gap),
        widths: a
            .widths
            .clone()
            .unwrap_or_else(|| escape::default_widths(gap.value)),
        particles_per_width: a.particles_per_width,
        seed: a.resumable.run.seed(),
    };
    cfg.validate()?;
    Ok(cfg)
}

/// The open table's configuration these options give (validated).
fn survival_config(a: &Args, open: OpenSpec) -> Result<SurvivalConfig, Error> {
    let cfg = SurvivalConfig {
        particles: a.particles,
        window: a.window,
        seed: a.resumable.run.seed(),
        ..SurvivalConfig::new(open)
    };
    cfg.validate()?;
    Ok(cfg)
}

/// The configuration these options give, as a result records it: the survival run's on an open
/// table, the strips' otherwise (for the audit's provenance check).
pub fn recorded_config(a: &Args) -> Result<serde_json::Value, Error> {
    let value = match open_table(a)? {
        Some(open) => serde_json::to_value(survival_config(a, open)?),
        None => serde_json::to_value(config(a)?),
    };
    value.map_err(Error::encode)
}

pub fn run(a: Args) -> Result<(), Error> {
    if let Some(open) = open_table(&a)? {
        let cfg = survival_config(&a, open)?;
        return a.resumable.run(
            cfg.particles,
            "particles",
            Engine::Auto,
            |opts| survival::run(&cfg, opts),
            print_survival,
        );
    }
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

fn print_survival(r: &SurvivalReport) {
    print!("{}", lorentz_gas::report::text::survival::survival(r));
}
