//! `lorentz sweep --w W --fields B1,B2,...` (over the field) and `lorentz sweep --w-from .. --w-to ..
//! --field B` (over w in a field): the diffusion tensor at every point, resumable by point.

use lorentz_gas::Error;
use lorentz_gas::campaigns::shard::Shard;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::sweep::field::{self as sweep, FieldGrid};
use lorentz_gas::estimators::sweep::field_grid::{self, SweepGrid};
use lorentz_gas::estimators::sweep::field_parts::{self, FieldSweepPart};
use lorentz_gas::estimators::sweep::{Grid, SweepConfig};

use super::output::emit;
use super::sweep::{Args, FieldArgs, GridArgs};

/// The field sweep of the grid `g` and field options `f` with `seed` (validated; shared with
/// `lorentz slurm sweep`).
pub fn config_of(g: &GridArgs, f: &FieldArgs, seed: u64) -> Result<SweepConfig, Error> {
    if let Some(runs) = g.runs {
        return Err(Error::parameter(
            "runs",
            runs,
            "not used by a sweep in a field (one run of --collisions-per-run per point; its \
             error is over --batches-per-run)",
        ));
    }
    let table = f
        .table
        .as_deref()
        .map(lorentz_gas::scenes::table::spec::TableSpec::read)
        .transpose()?;
    let scene = match (&table, f.scene) {
        (Some(_), _) => "table",
        (None, super::args::SceneName::Triangular) => "triangular",
        (None, super::args::SceneName::Square) => "square",
    };
    let SweepGrid {
        gaps,
        radius,
        fields,
    } = field_grid::scene_grid(
        scene,
        (f.w.as_deref(), f.radius.as_deref()),
        (g.w_from.as_deref(), g.w_to.as_deref(), g.steps),
        f.field.as_deref(),
        &f.fields,
    )?;
    let cfg = SweepConfig {
        grid: Grid::InField(FieldGrid {
            gaps,
            radius,
            fields,
            localization_samples: f.localization_samples,
            table,
        }),
        collisions: g.collisions_per_run,
        batches: g.batches_per_run,
        seed,
    };
    cfg.validate()?;
    Ok(cfg)
}

/// What a sweep in a field computed: one part of it, or the whole.
pub enum Outcome {
    /// A part (`--shard`).
    Part(FieldSweepPart),
    /// The whole sweep.
    Whole(Box<sweep::FieldSweepReport>),
}

/// Runs the sweep in a field, or the part `shard` of it, with `opts`.
pub fn compute(
    cfg: &SweepConfig,
    shard: Option<Shard>,
    opts: &RunOptions,
) -> Result<Outcome, Error> {
    Ok(match shard {
        Some(s) => Outcome::Part(field_parts::run_part(cfg, s, opts)?),
        None => Outcome::Whole(Box::new(sweep::run(cfg, opts)?)),
    })
}

/// Writes the tables and figures of a whole sweep into --out and prints it (an Onsager–Casimir
/// disagreement is a FAIL, exit 1, after everything is written), or prints what a part did.
pub fn show(a: &Args, done: Outcome) -> Result<(), Error> {
    match done {
        Outcome::Whole(r) => finish(&r, &a.out, a.output.json),
        Outcome::Part(part) => emit(a.output.json, &part, |p| {
            println!(
                "part {} of the field sweep: points {:?} in {}/field-points ({} reused); merge every part with `lorentz merge`",
                p.shard,
                p.points,
                a.out.display(),
                p.resumed_points
            )
        }),
    }
}

/// Writes the tables and figures of a finished field sweep into `out`, prints it, and judges
/// Onsager–Casimir (a FAIL, exit 1, after everything is written).
pub fn finish(r: &sweep::FieldSweepReport, out: &std::path::Path, json: bool) -> Result<(), Error> {
    sweep::write_tables(r, out)?;
    lorentz_gas::report::figures::field_sweep::write_field_sweep_figures(r, out)?;
    emit(json, r, |r| {
        print!("{}", lorentz_gas::report::text::field_sweep::field_sweep(r));
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
