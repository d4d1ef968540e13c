//! `lorentz diffusion`: D(w) by the Einstein formula.

use lorentz_gas::Error;
use lorentz_gas::engine::options::{AuditSpec, RunOptions};
use lorentz_gas::estimators::diffusion::{self, DiffusionConfig, DiffusionReport, MsdGrid, Window};
use lorentz_gas::estimators::transport::{self, Transport};
use lorentz_gas::scenes::spec::{Motion, Table};
use lorentz_gas::statistics::comparison;

use super::args::{
    CheckpointArgs, ElectricArgs, EngineArg, OutputArgs, PrecisionArg, ReferenceBitsArg, RunArgs,
    SceneArgs, parse_count, parse_count_u32,
};
use super::output::emit;
use super::progress::Progress;

/// The gap diffusion needs (the shared help of `--w` gives the whole range w > 0).
const GAP_HELP: &str = "Gap w of the triangular scene, a decimal or a fraction such as 1/10: \
    0 < w < w_inf = 4/sqrt(3) - 2 = 0.3094... (a finite horizon, where D exists); with --field \
    any w > 0 (a field bounds every flight)";

const ELECTRIC_HELP: &str = "A Gaussian-thermostatted electric field E in the plane (speed stays 1: dv/dt = E - \
    (E.v)v), its strength an exact decimal or fraction, 0 < |E| <= 10: the run measures the \
    current J, the mobility J/E (-> D as E -> 0), the entropy production E.J and the diffusion \
    tensor about the drift; 0 is the run without a field.";

#[derive(clap::Args)]
#[command(mut_arg("w", |a| a.help(GAP_HELP)))]
#[command(mut_arg("electric", |a| a.help(ELECTRIC_HELP)))]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    /// Collisions in all, over every batch (2e9, 2_000_000_000 and 2000000000 all work) [default:
    /// 2e9; with --rel-err the pilot's, 2e8].
    #[arg(long, value_parser = parse_count, allow_negative_numbers = true)]
    collisions: Option<u64>,
    /// Stop at this relative error of D (1e-4 is 0.01 %): a pilot of --collisions measures how
    /// the error falls with the collisions, then the run of the size it plans (the bits of a plain
    /// run of that size; resumable with --checkpoint). From 1e-7 to 0.5.
    #[arg(long, allow_negative_numbers = true)]
    rel_err: Option<f64>,
    /// With --rel-err: run the pilot only and print its result with the plan (the collisions the
    /// target needs and how long they take at the pilot's speed), without the planned run.
    #[arg(long, requires = "rel_err", conflicts_with_all = ["checkpoint", "audit"])]
    plan_only: bool,
    /// Independent batches (trajectories), at least 2; the error bar is their standard error.
    #[arg(long, default_value = "32", value_parser = parse_count_u32, allow_negative_numbers = true)]
    batches: u32,
    #[command(flatten)]
    run: RunArgs,
    #[command(flatten)]
    precision: PrecisionArg,
    #[command(flatten)]
    engine: EngineArg,
    /// Fit window LO:HI for the MSD slope, in units of the mean hop time tau.
    #[arg(long, default_value = "10:40")]
    window: Window,
    /// Second, later window LO:HI fitted as a check of the linear regime, in units of tau.
    #[arg(long, default_value = "20:80")]
    check_window: Window,
    /// Where the MSD is kept: fit (the fit windows' lags, which D is fitted from) or log (also a
    /// logarithmic grid from an eighth of the mean free time on, four times per octave, with the
    /// velocity autocorrelation and its running Green-Kubo integral; D keeps its bits; slower).
    #[arg(long, default_value = "fit", value_name = "GRID")]
    msd_grid: MsdGrid,
    #[command(flatten)]
    checkpoint: CheckpointArgs,
    /// Replay this fraction (0, 1] of the events in MPFR as the run goes (f64 runs).
    #[arg(long)]
    audit: Option<f64>,
    #[command(flatten)]
    reference: ReferenceBitsArg,
    /// A uniform magnetic field B perpendicular to the plane, an exact decimal or fraction like
    /// --w: the velocity turns at the angular velocity B, counter-clockwise for B > 0, on a
    /// cyclotron circle of radius 1/|B|. With a nonzero field the run measures the diffusion
    /// tensor (D_xx and the Hall D_xy) and the localized orbits; 0 is the run without a field.
    #[arg(long, allow_hyphen_values = true, conflicts_with = "electric")]
    field: Option<String>,
    #[command(flatten)]
    electric: ElectricArgs,
    /// With --field: phase points classified for the sampled share of localized orbits.
    #[arg(long, default_value = "1e6", value_parser = parse_count, requires = "field")]
    localization_samples: u64,
    #[command(flatten)]
    output: OutputArgs,
}

/// The configuration these options give (validated): the table (`--w`, `--scene`, `--table`)
/// in the field `--field` or under `--electric` (none, or exactly 0, is the run without a
/// field).
pub fn config(a: &Args) -> Result<DiffusionConfig, Error> {
    let motion = match a.electric.given() {
        Some((e, angle)) => Motion::thermostat(e, angle),
        None => Motion::in_field(a.field.as_deref().unwrap_or("0")),
    };
    let table = Table {
        scene: a.scene.spec()?,
        motion,
    };
    let cfg = DiffusionConfig {
        batches: a.batches,
        seed: a.run.seed(),
        precision: a.precision.precision,
        window: a.window,
        check_window: a.check_window,
        msd_grid: a.msd_grid.clone(),
        ..DiffusionConfig::sized(table, a.collisions, a.rel_err, a.localization_samples)
    };
    cfg.validate()?;
    Ok(cfg)
}

/// The configuration a result of these options records: the run's, or on a table given as
/// data without a field what it samples (the table recorded beside it).
pub fn recorded_config(a: &Args) -> Result<serde_json::Value, Error> {
    let cfg = config(a)?;
    let table_run = cfg.table.motion == Motion::Straight && cfg.table.gap_text().is_none();
    if table_run {
        serde_json::to_value(cfg.sampling())
    } else {
        serde_json::to_value(&cfg)
    }
    .map_err(Error::encode)
}

pub fn run(a: Args) -> Result<(), Error> {
    let cfg = config(&a)?;
    let opts = options(&a)?;
    if a.plan_only {
        let r = with_progress(
            cfg.collisions,
            "collisions (pilot)",
            a.output.quiet,
            &opts,
            |o| diffusion::plan::plan_only(&cfg, o),
        )?;
        return emit(a.output.json, &r, print);
    }
    if cfg.rel_err.is_some() {
        let r = run_planned(&cfg, &opts, a.output.quiet)?;
        return emit(a.output.json, &r, print);
    }
    let r = with_progress(cfg.collisions, "collisions", a.output.quiet, &opts, |o| {
        transport::run(&cfg, o)
    })?;
    match r {
        Transport::Trap(r) => emit(a.output.json, &*r, print),
        Transport::Field(r) => emit(a.output.json, &*r, super::field::print),
        Transport::Current(r) => emit(a.output.json, &*r, |r| {
            print!("{}", lorentz_gas::report::text::current::current(r))
        }),
        Transport::Table(r) => emit(a.output.json, &*r, |r| {
            print!(
                "{}",
                lorentz_gas::report::text::scene_diffusion::scene_diffusion(r)
            )
        }),
    }
}

/// How the run goes: engine, threads, the self-audit, the checkpoint, the stop on a signal.
fn options(a: &Args) -> Result<RunOptions<'static>, Error> {
    let audit = a
        .audit
        .map(|rate| AuditSpec::new(rate, a.reference.reference_bits))
        .transpose()?;
    a.checkpoint
        .check(&a.scene.table.as_deref().into_iter().collect::<Vec<_>>())?;
    Ok(a.checkpoint.apply(RunOptions {
        engine: a.engine.engine,
        threads: a.run.threads(),
        audit,
        ..super::signals::options()
    }))
}

/// Runs `f` with a progress report over `total` units in its options.
fn with_progress<T>(
    total: u64,
    unit: &str,
    quiet: bool,
    opts: &RunOptions,
    f: impl FnOnce(&RunOptions) -> Result<T, Error>,
) -> Result<T, Error> {
    let pb = Progress::new(total, unit, quiet);
    let progress = pb.callback();
    f(&RunOptions {
        progress: &progress,
        ..opts.clone()
    })
}

/// A run planned for a relative error: the pilot, the plan on stderr, then the planned run.
fn run_planned(
    cfg: &DiffusionConfig,
    opts: &RunOptions,
    quiet: bool,
) -> Result<DiffusionReport, Error> {
    let first = with_progress(cfg.collisions, "collisions (pilot)", quiet, opts, |o| {
        diffusion::plan::pilot(cfg, o)
    })?;
    let pilot = &first.pilot;
    let full = diffusion::plan::planned_config(cfg, pilot);
    if !quiet {
        let rate = match &first.report {
            Some(r) => r.collisions_per_second,
            None => pilot.collisions as f64 / pilot.seconds,
        };
        eprintln!(
            "pilot{}: {:.3e} collisions gave a relative error of {:.3} %; {} % needs {:.2e} \
             collisions, about {} here{}",
            if first.report.is_none() {
                " (from the checkpoint)"
            } else {
                ""
            },
            pilot.collisions as f64,
            100.0 * pilot.rel_err,
            100.0 * pilot.rel_err_target,
            pilot.planned_collisions as f64,
            lorentz_gas::engine::progress_lines::clock(
                pilot.planned_collisions as f64 / rate.max(f64::MIN_POSITIVE)
            ),
            if full.is_none() {
                ": the pilot is the run"
            } else {
                ""
            }
        );
    }
    let total = full.as_ref().map_or(0, |f| f.collisions);
    with_progress(total, "collisions", quiet || full.is_none(), opts, |o| {
        diffusion::plan::finish(cfg, first, o)
    })
}

/// The result's text (the library's, which Python's `str()` shows too), and on stderr a warning
/// when the two fit windows disagree.
fn print(r: &DiffusionReport) {
    print!("{}", lorentz_gas::report::text::diffusion::diffusion(r));
    let n = r.batch_D.len();
    let window_check = comparison::of(
        r.D_minus_D_check,
        r.D_minus_D_check_err,
        comparison::batch_dof(n),
    );
    if !window_check.agrees() {
        eprintln!(
            "warning: D over [{}τ, {}τ] and over [{}τ, {}τ] differ by {:.1} paired standard errors: \
             the MSD is not yet linear over the fit window; use a later --window",
            r.window.lo,
            r.window.hi,
            r.check_window.lo,
            r.check_window.hi,
            window_check.z.abs()
        );
    }
}
