//! `lorentz audit`: replay f64 events in MPFR and judge them against the one-step error model.

use lorentz_gas::Error;
use lorentz_gas::engine::long_flight::Flights;
use lorentz_gas::scenes::motion::MotionInput;
use lorentz_gas::verification::shadow_audit::{self, AuditConfig, AuditReport};

use lorentz_gas::scenes::Scene;

use super::args::{OutputArgs, RunArgs, SceneArgs, parse_count, parse_count_u32, with_scene};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    /// Collisions in all, over every batch.
    #[arg(long, default_value = "1e6", value_parser = parse_count, allow_negative_numbers = true)]
    collisions: u64,
    /// Independent batches (trajectories), at least 1; not tied to --threads (the result is the
    /// same on any thread count).
    #[arg(long, default_value = "4", value_parser = parse_count_u32, allow_negative_numbers = true)]
    batches: u32,
    /// Fraction of events replayed, in (0, 1].
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    sample: f64,
    /// A uniform magnetic field B perpendicular to the plane, an exact decimal or fraction like
    /// --w (1e-6 <= |B| <= 1e6; 0 or absent: no field): the replayed events are arcs, judged by
    /// the arc kernel's running error bound.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "electric")]
    field: Option<String>,
    /// A Gaussian-thermostatted electric field E in the plane (speed stays 1: dv/dt = E -
    /// (E.v)v), its strength an exact decimal or fraction, 0 < |E| <= 10 (0 is the audit without
    /// a field): the replayed events are thermostatted flights, judged by their kernel's running
    /// error bound and checked against independent closed forms.
    #[arg(long, allow_hyphen_values = true)]
    electric: Option<String>,
    /// With --electric: the field's angle from the x axis in degrees, an exact decimal or
    /// fraction.
    #[arg(long, allow_hyphen_values = true, requires = "electric")]
    electric_angle: Option<String>,
    /// How straight flights cross the lattice: jump (straight to the cell of the first disk they
    /// can meet, each jump replayed as a whole: against the exact column walk on the square
    /// scene with 2^-32 <= radius <= 1/4, by the MPFR trap walk on the triangular one with
    /// w_inf < w <= 2^20 - 2), walk (cell by cell, every crossing replayed), or auto (jump with
    /// 2^-32 <= radius <= 1/8 and w >= 6, where jumps are faster; walk in a field). Recorded in
    /// the result as `flights`.
    #[arg(long, default_value = "auto")]
    flights: Flights,
    /// MPFR precision of the replay, in bits (128 to 65536).
    #[arg(long, default_value = "128", value_parser = parse_count_u32, allow_negative_numbers = true)]
    reference_bits: u32,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    output: OutputArgs,
}

pub fn run(a: Args) -> Result<(), Error> {
    let choice = a.scene.resolve()?;
    let label = with_scene!(&choice, |s| s.label());
    let cfg = AuditConfig {
        scene: label,
        collisions: a.collisions,
        batches: a.batches,
        sample: a.sample,
        reference_bits: a.reference_bits,
        seed: a.run.seed(),
        motion: MotionInput {
            field: a.field.clone(),
            electric: a.electric.clone(),
            electric_angle: a.electric_angle.clone(),
        },
        flights: a.flights,
    };
    let pb = Progress::new(cfg.collisions, "collisions", a.output.quiet);
    let opts = pb.options(a.run.threads());
    let r = with_scene!(&choice, |s| shadow_audit::run(s, &cfg, &opts))?;
    drop(opts);
    drop(pb);
    emit(a.output.json, &r, print)
}

fn print(r: &AuditReport) {
    print!("{}", lorentz_gas::report::text::audit::audit(r));
}
