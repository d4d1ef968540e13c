//! `lorentz lyapunov`: the largest Lyapunov exponent and the divergence of finite-precision orbits.

use lorentz_gas::Error;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::current::lyapunov as driven_lyapunov;
use lorentz_gas::estimators::field::lyapunov as field_lyapunov;
use lorentz_gas::report::text::lyapunov::{self as text, LyapunovResult};
use lorentz_gas::scenes::spec::Motion;
use lorentz_gas::statistics::comparison;
use lorentz_gas::verification::divergence::{self, DivergenceConfig};
use lorentz_gas::verification::lyapunov::{self, LyapunovConfig, TANGENT_TRANSIENT};

use super::args::{
    ElectricArgs, EngineArg, FlightsArg, OutputArgs, RunArgs, SceneArgs, parse_count,
    parse_count_u32, with_scene,
};
use super::output::emit;
use super::progress::Progress;

/// What `--electric` measures here.
const ELECTRIC_HELP: &str = "A Gaussian-thermostatted electric field E in the plane (speed stays 1: dv/dt = E - \
    (E.v)v), its strength an exact decimal or fraction, 0 < |E| <= 10: the Lyapunov pair \
    lambda_+ and lambda_- of the driven gas, their sum against minus the mean contraction rate \
    alpha (the sum rule) and the Kaplan-Yorke dimension; 0 is the run without a field.";

#[derive(clap::Args)]
#[command(mut_arg("electric", |a| a.help(ELECTRIC_HELP)))]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    /// Collisions of each batch (one tangent-space orbit each), after a transient.
    #[arg(long, default_value = "2e6", value_parser = parse_count, allow_negative_numbers = true)]
    collisions_per_batch: u64,
    /// Independent batches (tangent-space orbits), at least 2; the error bar is over them.
    #[arg(long, default_value = "16", value_parser = parse_count_u32, allow_negative_numbers = true)]
    batches: u32,
    /// Initial conditions of the divergence measurement (0 to skip it); its error bars are over
    /// them [default: 8; none in a field or under --electric, nor where long flights jump: it
    /// replays the straight cell walk at up to 4096 bits]
    #[arg(long, value_parser = parse_count_u32, allow_negative_numbers = true)]
    starts: Option<u32>,
    /// A magnetic field B (exact, 1e-3 <= |B| <= 1e3; either scene): the tangent dynamics of
    /// arcs, on orbits started in the diffusing part of phase space; 0 is the run without a field.
    #[arg(long, allow_negative_numbers = true, conflicts_with = "electric")]
    field: Option<String>,
    #[command(flatten)]
    electric: ElectricArgs,
    #[command(flatten)]
    flights: FlightsArg,
    #[command(flatten)]
    engine: EngineArg,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    output: OutputArgs,
}

/// Refuses `--starts` above 0 under a motion whose divergence of finite-precision orbits is not
/// measured (`within`: "in a field", "under the thermostat").
fn no_divergence(a: &Args, within: &str) -> Result<(), Error> {
    match a.starts.filter(|&s| s > 0) {
        Some(starts) => Err(Error::parameter(
            "starts",
            starts,
            format!(
                "the divergence of finite-precision orbits is not measured {within}: leave it \
                 out or give 0"
            ),
        )),
        None => Ok(()),
    }
}

/// The progress bar of the tangent orbits, with `transient` collisions before each.
fn orbit_progress(a: &Args, transient: u64) -> Progress {
    let total = (a.collisions_per_batch.saturating_add(transient)).saturating_mul(a.batches as u64);
    Progress::new(total, "collisions", a.output.quiet)
}

/// `lorentz lyapunov --electric E`: the pair of the thermostatted flow.
fn driven(a: &Args, cfg: &LyapunovConfig) -> Result<(), Error> {
    no_divergence(a, "under the thermostat")?;
    let scene = a.scene.resolve()?;
    let pb = orbit_progress(a, driven_lyapunov::warm_up(a.collisions_per_batch));
    let opts = pb.options(a.run.threads());
    let r = with_scene!(&scene, |s| driven_lyapunov::run(s, cfg, &opts))?;
    drop(opts);
    drop(pb);
    emit(a.output.json, &r, |r| print!("{}", text::driven(r)))
}

/// `lorentz lyapunov --field B`: the tangent-space exponent on arcs.
fn in_field(a: &Args, cfg: &LyapunovConfig) -> Result<(), Error> {
    no_divergence(a, "in a field")?;
    let scene = a.scene.resolve()?;
    let pb = orbit_progress(a, TANGENT_TRANSIENT);
    let opts = RunOptions {
        engine: a.engine.engine,
        ..pb.options(a.run.threads())
    };
    let r = with_scene!(&scene, |s| field_lyapunov::run(s, cfg, &opts))?;
    drop(opts);
    drop(pb);
    emit(a.output.json, &r, |r| {
        let l = &r.tangent;
        println!(
            "{} (cyclotron radius {:.6}): largest Lyapunov exponent (tangent space of arcs, {} batches x {} collisions, diffusing starts; {:.6} of phase space is pinned or skipping, with exponent 0)\n  {:.5} ± {:.5} per collision, {:.5} ± {:.5} per unit time{}",
            l.scene,
            r.cyclotron_radius,
            l.batches,
            l.collisions_per_batch,
            r.localized_fraction_exact,
            l.per_collision,
            l.per_collision_err,
            l.per_time,
            l.per_time_err,
            comparison::few_samples_note(l.batches as usize, "batches")
        );
    })
}

/// Most divergence starts: each costs about a second of MPFR work at 4096 bits.
const MAX_STARTS: u32 = 10_000;

/// The measurement the options ask for, without a field.
fn config(a: &Args) -> LyapunovConfig {
    LyapunovConfig {
        collisions_per_batch: a.collisions_per_batch,
        batches: a.batches,
        seed: a.run.seed(),
        flights: a.flights.flights,
        ..LyapunovConfig::new()
    }
}

pub fn run(a: Args) -> Result<(), Error> {
    let moving = config(&a).in_field(a.field.as_deref().unwrap_or("0"));
    let moving = match a.electric.given() {
        Some((e, angle)) => moving.under_electric(e, angle),
        None => moving,
    };
    match moving.motion.resolve()? {
        Motion::Field(_) => return in_field(&a, &moving),
        Motion::Thermostat { .. } => return driven(&a, &moving),
        _ => {}
    }
    let choice = a.scene.resolve()?;
    let starts = match a.starts {
        Some(s) => s,
        None => with_scene!(&choice, |s| divergence::default_starts(
            s,
            a.flights.flights
        ))?,
    };
    if starts == 1 || starts > MAX_STARTS {
        return Err(Error::out_of_range(
            "starts",
            starts,
            format!(
                "use 0 (no divergence measurement) or 2 to {MAX_STARTS} (the error bars are over \
                 the starts, reliable from 4; each costs about a second)"
            ),
        ));
    }
    let pb = orbit_progress(&a, TANGENT_TRANSIENT);
    let cfg = config(&a);
    let opts = RunOptions {
        engine: a.engine.engine,
        ..pb.options(a.run.threads())
    };
    let tangent = with_scene!(&choice, |s| lyapunov::run(s, &cfg, &opts))?;
    drop(opts);
    drop(pb);
    let divergence = if starts > 0 {
        let pb = Progress::new(starts as u64, "initial conditions", a.output.quiet);
        let cfg = DivergenceConfig {
            starts,
            seed: a.run.seed(),
            ..DivergenceConfig::new()
        };
        let opts = pb.options(1);
        let d = with_scene!(&choice, |s| divergence::run(s, &cfg, &opts))?;
        drop(opts);
        drop(pb);
        d
    } else {
        Vec::new()
    };
    emit(
        a.output.json,
        &LyapunovResult {
            tangent,
            divergence,
        },
        |r| print!("{}", text::lyapunov(r)),
    )
}
