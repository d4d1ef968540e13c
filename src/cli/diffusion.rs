//! `lorentz diffusion`: D(w) by the Einstein formula.

use lorentz_gas::Error;
use lorentz_gas::engine::options::{AuditSpec, RunOptions};
use lorentz_gas::estimators::diffusion::{self, DiffusionConfig, DiffusionReport, MsdGrid, Window};
use lorentz_gas::statistics::comparison;

use super::args::{
    CheckpointArgs, EngineArg, OutputArgs, PrecisionArg, ReferenceBitsArg, RunArgs, SceneArgs,
    SceneChoice, parse_count, parse_count_u32,
};
use super::output::{emit, sigmas};
use super::progress::Progress;

/// The gap diffusion needs (the shared help of `--w` gives the whole range w > 0).
const GAP_HELP: &str = "Gap w of the triangular scene, a decimal or a fraction such as 1/10: \
    0 < w < w_inf = 4/sqrt(3) - 2 = 0.3094... (a finite horizon, where D exists)";

#[derive(clap::Args)]
#[command(mut_arg("w", |a| a.help(GAP_HELP)))]
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
    #[arg(long, allow_hyphen_values = true)]
    field: Option<String>,
    /// With --field: phase points classified for the sampled share of localized orbits.
    #[arg(long, default_value = "1e6", value_parser = parse_count, requires = "field")]
    localization_samples: u64,
    #[command(flatten)]
    output: OutputArgs,
}

/// The configuration these options give (validated).
pub fn config(a: &Args) -> Result<DiffusionConfig, Error> {
    let w_exact = a.scene.w.as_ref().and_then(|w| w.exact_text());
    let w = match a.scene.resolve()? {
        SceneChoice::Triangular(s) => s.w(),
        SceneChoice::Square(s) => {
            diffusion::require_finite_horizon(&s)?;
            unreachable!("the square scene has an infinite horizon")
        }
    };
    let cfg = DiffusionConfig {
        w,
        w_exact,
        collisions: a
            .collisions
            .unwrap_or_else(|| diffusion::plan::default_collisions(a.rel_err)),
        batches: a.batches,
        seed: a.run.seed(),
        run: 0,
        precision: a.precision.precision,
        window: a.window,
        check_window: a.check_window,
        rel_err: a.rel_err,
        msd_grid: a.msd_grid,
    };
    cfg.validate()?;
    Ok(cfg)
}

/// The field run the arguments ask for (validated), unless the field is absent or exactly zero.
pub fn field_config(
    a: &Args,
) -> Result<Option<lorentz_gas::estimators::field::FieldConfig>, Error> {
    match nonzero_field(a)? {
        Some(b) => super::field::config(config(a)?, &b, a.localization_samples).map(Some),
        None => Ok(None),
    }
}

pub fn run(a: Args) -> Result<(), Error> {
    let cfg = config(&a)?;
    if let Some(fc) = field_config(&a)? {
        let audit = a
            .audit
            .map(|rate| AuditSpec::new(rate, a.reference.reference_bits))
            .transpose()?;
        let opts = a.checkpoint.apply(RunOptions {
            engine: a.engine.engine,
            threads: a.run.threads(),
            audit,
            ..super::signals::options()
        });
        return super::field::run(&fc, opts, a.output.quiet, a.output.json);
    }
    let audit = a
        .audit
        .map(|rate| AuditSpec::new(rate, a.reference.reference_bits))
        .transpose()?;
    let opts = a.checkpoint.apply(RunOptions {
        engine: a.engine.engine,
        threads: a.run.threads(),
        audit,
        ..super::signals::options()
    });
    let r = if cfg.rel_err.is_some() {
        run_planned(&cfg, &opts, a.output.quiet)?
    } else {
        with_progress(cfg.collisions, "collisions", a.output.quiet, &opts, |o| {
            diffusion::run(&cfg, o)
        })?
    };
    emit(a.output.json, &r, print)
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
    let (first, pilot) = with_progress(cfg.collisions, "collisions (pilot)", quiet, opts, |o| {
        diffusion::plan::pilot(cfg, o)
    })?;
    let full = diffusion::plan::planned_config(cfg, &pilot);
    if !quiet {
        let rate = first.collisions_per_second.max(f64::MIN_POSITIVE);
        eprintln!(
            "pilot: {:.3e} collisions gave a relative error of {:.3} %; {} % needs {:.2e} \
             collisions, about {} here{}",
            pilot.collisions as f64,
            100.0 * pilot.rel_err,
            100.0 * pilot.rel_err_target,
            pilot.planned_collisions as f64,
            lorentz_gas::engine::progress_lines::clock(pilot.planned_collisions as f64 / rate),
            if full.is_none() {
                ": the pilot is the run"
            } else {
                ""
            }
        );
    }
    let total = full.as_ref().map_or(0, |f| f.collisions);
    with_progress(total, "collisions", quiet || full.is_none(), opts, |o| {
        diffusion::plan::finish(cfg, first, pilot, o)
    })
}

/// The field, unless absent or exactly zero (the run without a field, with its own bits).
fn nonzero_field(a: &Args) -> Result<Option<String>, Error> {
    match &a.field {
        Some(b)
            if lorentz_gas::numbers::exact::parse_exact(b)
                .map_err(|e| Error::Invalid(format!("field = {b}: {e}")))?
                != 0 =>
        {
            Ok(Some(b.clone()))
        }
        _ => Ok(None),
    }
}

fn print(r: &DiffusionReport) {
    let m = &r.meta;
    println!(
        "periodic Lorentz gas, w = {}  ({} precision, {} engine, seed {}, {} batches, {:.3e} collisions, {}, {:.1} s, {:.3e} collisions/s)",
        r.w,
        m.precision,
        match &m.simd {
            Some(p) => format!("{} ({p})", m.engine),
            None => m.engine.clone(),
        },
        m.seed.unwrap_or_default(),
        m.batches.unwrap_or_default(),
        r.collisions as f64,
        lorentz_gas::report::counted(m.threads.unwrap_or_default() as u64, "thread"),
        r.seconds,
        r.collisions_per_second
    );
    print_d(r);
    print_identities(r);
    print_curve(r);
    print_plan(r);
    if let Some(a) = &r.audit {
        println!(
            "self-audit     : {} events replayed in MPFR, {} outside the error model, worst time error / bound {:.2e}",
            a.audited, a.outside, a.time_error_over_bound.max
        );
    }
    if r.resumed_collisions > 0 {
        println!(
            "({} finished batches and {:.3e} collisions in all resumed from the checkpoint; the \
             speed counts this run's collisions only)",
            r.resumed_batches, r.resumed_collisions as f64
        );
    }
}

/// The MSD curve's extent and D by Green–Kubo against the Einstein D (runs on the log grid).
fn print_curve(r: &DiffusionReport) {
    let Some(c) = &r.msd_curve else {
        return;
    };
    let (first, last) = (c.times.first().copied(), c.times.last().copied());
    println!(
        "MSD curve      : {} times from {:.4} to {:.4e} (MSD, velocity autocorrelation and \
         Green-Kubo integral, in the --json result's msd_curve)",
        c.times.len(),
        first.unwrap_or(f64::NAN),
        last.unwrap_or(f64::NAN)
    );
    let g = &r.green_kubo;
    match (g.D_green_kubo, g.D_green_kubo_err) {
        (Some(d), Some(e)) => {
            let n = r.batch_D.len();
            let diff = comparison::of(
                g.D_minus_D_green_kubo.unwrap_or(f64::NAN),
                g.D_minus_D_green_kubo_err.unwrap_or(f64::NAN),
                comparison::batch_dof(n),
            );
            println!(
                "D (Green-Kubo) = {d:.6} ± {e:.6}   (running integral over [{}τ, {}τ]; D − D_green_kubo = \
                 {:+.6} ± {:.6}, {})",
                r.window.lo,
                r.window.hi,
                diff.difference,
                diff.err,
                diff.describe(&format!("paired over {n} batches"))
            );
        }
        _ => println!(
            "D (Green-Kubo) : no grid time inside [{}τ, {}τ] (more collisions per batch reach it)",
            r.window.lo, r.window.hi
        ),
    }
}

/// The relative error this run reached against a planned one, and what the next decade needs.
fn print_plan(r: &DiffusionReport) {
    if let Some(p) = &r.pilot {
        println!(
            "planned run    : for {} % from a pilot of {:.3e} collisions ({:.3} %); reached {:.3} %",
            100.0 * p.rel_err_target,
            p.collisions as f64,
            100.0 * p.rel_err,
            100.0 * r.D_err / r.D.abs()
        );
    }
    if let Some(p) = &r.plan {
        println!(
            "precision plan : {} % needs {:.2e} collisions, about {} here (the error falls as \
             1/sqrt(collisions); --rel-err stops at a target)",
            100.0 * p.rel_err,
            p.collisions as f64,
            lorentz_gas::engine::progress_lines::clock(p.seconds)
        );
    }
}

/// D over both windows, their paired difference (a warning on stderr when they disagree), and
/// the closed forms D_MZ and D_Bo.
fn print_d(r: &DiffusionReport) {
    println!(
        "D              = {:.6} ± {:.6}   ({:.3} %, MSD slope over [{}τ, {}τ]){}",
        r.D,
        r.D_err,
        100.0 * r.D_err / r.D,
        r.window.lo,
        r.window.hi,
        comparison::few_samples_note(r.batch_D.len(), "batches")
    );
    let n = r.batch_D.len();
    let window_check = comparison::of(
        r.D_minus_D_check,
        r.D_minus_D_check_err,
        comparison::batch_dof(n),
    );
    println!(
        "D (check)      = {:.6} ± {:.6}   (MSD slope over [{}τ, {}τ]; D − D_check = {:+.6} ± {:.6}, {})",
        r.D_check,
        r.D_check_err,
        r.check_window.lo,
        r.check_window.hi,
        r.D_minus_D_check,
        r.D_minus_D_check_err,
        window_check.describe(&format!("paired over {n} batches"))
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
    println!(
        "D_MZ           = {:.6}           D/D_MZ = {:.4}",
        r.D_MZ,
        r.D / r.D_MZ
    );
    println!("D_Bo           = {:.6}", r.D_Bo);
}

/// The measured exact identities against their closed forms, each with its bound and verdict.
fn print_identities(r: &DiffusionReport) {
    let n = r.batch_D.len();
    println!(
        "mean free path = {:.7} ± {:.7}   exact {:.7}  ({})",
        r.mean_free_path,
        r.mean_free_path_err,
        r.mean_free_path_exact,
        sigmas(
            r.mean_free_path,
            r.mean_free_path_err,
            r.mean_free_path_exact,
            n
        )
    );
    println!(
        "mean hop time  = {:.6} ± {:.6}   exact {:.6}  ({})",
        r.tau_hop,
        r.tau_hop_err,
        r.tau_hop_exact,
        sigmas(r.tau_hop, r.tau_hop_err, r.tau_hop_exact, n)
    );
    println!(
        "collisions/hop = {:.5} ± {:.5}   exact {:.5}  ({})",
        r.collisions_per_hop,
        r.collisions_per_hop_err,
        r.collisions_per_hop_exact,
        sigmas(
            r.collisions_per_hop,
            r.collisions_per_hop_err,
            r.collisions_per_hop_exact,
            n
        )
    );
}
