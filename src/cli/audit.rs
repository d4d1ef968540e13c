//! `lorentz audit`: replay f64 events in MPFR and judge them against the one-step error model.

use lorentz_gas::Error;
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
    #[arg(long, allow_hyphen_values = true)]
    field: Option<String>,
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
        field: a.field.clone(),
    };
    let pb = Progress::new(cfg.collisions, "collisions", a.output.quiet);
    let opts = pb.options(a.run.threads());
    let r = with_scene!(&choice, |s| shadow_audit::run(s, &cfg, &opts))?;
    drop(opts);
    drop(pb);
    emit(a.output.json, &r, print)
}

fn print(r: &AuditReport) {
    let s = &r.summary;
    let c = &r.config;
    let field = match (&c.field, c.field_exact()) {
        (Some(b), Ok(Some(_))) => {
            format!(" in the field B = {b} (arcs, against their running error bound)")
        }
        _ => String::new(),
    };
    println!(
        "shadow audit, {}{field}: {} events of {} ({} collisions, {} batches, seed {}) replayed at {} bits in {:.1} s",
        c.scene, s.audited, r.events, c.collisions, c.batches, c.seed, c.reference_bits, r.seconds
    );
    println!(
        "outside the error model: {}   ambiguous at f64 resolution: {}   f64 chose another obstacle: {}",
        s.outside, s.ambiguous, s.different_choice
    );
    let q = &r.quantiles;
    println!("one-step error            median      99%         max");
    for (name, v) in [
        ("flight time", q.time_error),
        ("contact point", q.position_error),
        ("velocity", q.velocity_error),
        ("time error / bound", q.time_error_over_bound),
    ]
    .into_iter()
    .chain(
        [
            ("position error / bound", q.position_error_over_bound),
            ("velocity error / bound", q.velocity_error_over_bound),
        ]
        .into_iter()
        .filter_map(|(n, v)| v.map(|v| (n, v))),
    ) {
        println!(
            "{name:<22} {:>10.2e} {:>10.2e} {:>10.2e}",
            v.median, v.p99, v.max
        );
    }
    for e in s.outside_events.iter().take(5) {
        println!(
            "outside: state bits {:x?} excluded {:?}: {:?}",
            e.state_bits, e.excluded, e.check
        );
    }
}
