//! `lorentz sweep --w W --fields B1,B2,...` (over the field) and `lorentz sweep --w-from .. --w-to ..
//! --field B` (over w in a field): the diffusion tensor at every point, resumable by point.

use lorentz_gas::Error;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::field::sweep::{self, FieldSweepConfig, FieldSweepReport};

use super::output::emit;
use super::progress::Progress;
use super::sweep::Args;

/// The field sweep these options give (validated).
pub fn config(a: &Args) -> Result<FieldSweepConfig, Error> {
    let (g, f) = (&a.grid, &a.in_field);
    if g.runs.is_some() {
        return Err(Error::Invalid(
            "--runs is not used by a sweep in a field (one run of --collisions-per-run per point; its error is over --batches-per-run)".into(),
        ));
    }
    let scene = match f.scene {
        super::args::SceneName::Triangular => "triangular",
        super::args::SceneName::Square => "square",
    };
    let sweep::SweepGrid {
        gaps,
        radius,
        fields,
    } = sweep::scene_grid(
        scene,
        (f.w.as_deref(), f.radius.as_deref()),
        (g.w_from.as_deref(), g.w_to.as_deref(), g.steps),
        f.field.as_deref(),
        &f.fields,
    )?;
    let cfg = FieldSweepConfig {
        gaps,
        radius,
        fields,
        collisions: g.collisions_per_run,
        batches: g.batches_per_run,
        seed: a.run.seed(),
        localization_samples: f.localization_samples,
    };
    cfg.validate()?;
    Ok(cfg)
}

/// Runs it, writes the tables and figures into --out, and prints the table; an Onsager–Casimir
/// disagreement is a FAIL (exit 1) after everything is written.
pub fn run(a: &Args) -> Result<(), Error> {
    let cfg = config(a)?;
    if a.shard.is_some() {
        return Err(Error::Invalid(
            "--shard splits a sweep over w without a field; a sweep in a field resumes by point from --out".into(),
        ));
    }
    let out = a.out.clone();
    let total = cfg
        .collisions
        .saturating_mul((cfg.gaps.len() * cfg.fields.len()) as u64);
    let pb = Progress::new(total, "collisions", a.output.quiet);
    let progress = pb.callback();
    super::signals::keeping(&out);
    let opts = RunOptions {
        engine: a.engine.engine,
        threads: a.run.threads(),
        progress: &progress,
        resume: Some(out.clone()),
        audit: None,
        checkpoint_every: a.every.checkpoint_every,
        stop: Some(super::signals::stop_flag()),
    };
    let r = sweep::run(&cfg, &opts)?;
    drop(progress);
    drop(pb);
    sweep::write_tables(&r, &out)?;
    lorentz_gas::report::figures::field_sweep::write_field_sweep_figures(&r, &out)?;
    emit(a.output.json, &r, |r| {
        print(r);
        println!(
            "written: {}/field-sweep.{{csv,json}}, field-D_xx, field-D_xy (.png, .svg); points in {}/field-points",
            out.display(),
            out.display()
        );
    })?;
    if r.onsager_agrees {
        Ok(())
    } else {
        Err(Error::CheckFailed(
            "Onsager-Casimir: D_xx(B) - D_xx(-B) or D_xy(B) + D_xy(-B) is not consistent with 0"
                .into(),
        ))
    }
}

/// The sweep's table and its Onsager–Casimir checks, as text.
fn print(r: &FieldSweepReport) {
    let c = &r.config;
    let (place, scenes) = match &c.radius {
        Some(r) => ("radius", format!("square lattice, r = {r}")),
        None => ("w", format!("{} gap(s)", c.gaps.len())),
    };
    println!(
        "sweep in a magnetic field: {scenes} x {} field(s), {} collisions in {} batches per point, seed {} ({} points resumed)",
        c.fields.len(),
        c.collisions,
        c.batches,
        c.seed,
        r.resumed_points
    );
    println!(
        "{place:>8}          B      D_xx         +-        D_xy (Hall)  +-        localized exact  sampled +-"
    );
    for x in &r.rows {
        println!(
            "{:>8}  {:>9}  {:.6}  {:.6}  {:+.6}  {:.6}  {:.6}         {:.6} {:.6}{}",
            x.place(),
            x.field,
            x.D_xx,
            x.D_xx_err,
            x.D_xy,
            x.D_xy_err,
            x.localized_fraction_exact,
            x.localized_fraction,
            x.localized_fraction_err,
            if x.all_localized {
                "  (every orbit localized: D = 0 exactly)"
            } else {
                ""
            }
        );
    }
    for o in &r.onsager {
        println!(
            "Onsager-Casimir at {place} = {}, |B| = {}: D_xx(B) - D_xx(-B) = {:+.6} {}; D_xy(B) + D_xy(-B) = {:+.6} {}",
            o.w.or(o.radius).unwrap_or(f64::NAN),
            o.field,
            o.d_xx_even.difference,
            o.d_xx_even.describe("Welch"),
            o.d_xy_odd.difference,
            o.d_xy_odd.describe("Welch")
        );
    }
}
