//! `lorentz sweep`: D over a range of w, resumable, with the paper's coarse and fine analyses; or
//! in a field (`--w W --fields B1,B2,...` over the field, `--w-from .. --w-to .. --field B` over w
//! in a field, any table): the diffusion tensor at every point, resumable by point; or the driven
//! gas over E (`--w W --electric E1,E2,...`, [`driven`]).

pub mod driven;

use lorentz_gas::Error;
use lorentz_gas::campaigns::shard::{self, Shard, ShardConfig};
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::sweep::field::{self, FieldGrid};
use lorentz_gas::estimators::sweep::field_grid::{self, SweepGrid};
use lorentz_gas::estimators::sweep::stored::{FOLDERS, Finished, MANIFESTS};
use lorentz_gas::estimators::sweep::{self, GapGrid, Grid, SweepConfig, SweepReport};
use lorentz_gas::report::text::sweep as text;

use std::path::{Path, PathBuf};

use lorentz_gas::files::{self, Output};

use super::args::{
    CheckpointEveryArg, EngineArg, OutputArgs, RunArgs, parse_count, parse_count_u32,
};
use super::output::emit;
use super::progress::Progress;

/// The sweep itself: the w grid, runs, collisions and batches per run (shared with `lorentz slurm
/// sweep`).
#[derive(clap::Args, Clone)]
pub struct GridArgs {
    /// First w, a decimal (the grid is computed exactly: 0.1 .. 0.2 in 3 steps gives 0.15).
    #[arg(long, allow_negative_numbers = true)]
    pub(super) w_from: Option<String>,
    /// Last w, a decimal.
    #[arg(long, allow_negative_numbers = true)]
    pub(super) w_to: Option<String>,
    /// Number of points (at least 2).
    #[arg(long, default_value = "11", value_parser = parse_count_u32, allow_negative_numbers = true)]
    pub(super) steps: u32,
    /// Independent runs at each point w (their spread is checked against the batch errors)
    /// [default: 10; a sweep in a field runs one per point]
    #[arg(long, value_parser = parse_count_u32, allow_negative_numbers = true)]
    pub(super) runs: Option<u32>,
    /// Collisions of each run, over its batches (a point costs runs x this).
    #[arg(long, default_value = "2e8", value_parser = parse_count, allow_negative_numbers = true)]
    pub(super) collisions_per_run: u64,
    /// Independent batches of each run (at least 2): each run's error is the standard error over
    /// its batches.
    #[arg(long, default_value = "8", value_parser = parse_count_u32, allow_negative_numbers = true)]
    pub(super) batches_per_run: u32,
}

/// The refusal of a sweep over w without one of its ends.
fn missing_end(g: &GridArgs) -> Error {
    Error::missing(
        if g.w_from.is_none() { "w_from" } else { "w_to" },
        "a sweep over w needs --w-from and --w-to (a sweep over the field: --w W --fields \
         B1,B2,...)",
    )
}

impl GridArgs {
    /// The sweep's configuration with `seed`, checked.
    pub fn config(&self, seed: u64) -> Result<SweepConfig, Error> {
        let (Some(w_from), Some(w_to)) = (&self.w_from, &self.w_to) else {
            return Err(missing_end(self));
        };
        let cfg = SweepConfig {
            grid: Grid::Gaps(GapGrid {
                w_from: w_from.clone(),
                w_to: w_to.clone(),
                steps: self.steps,
                runs: self.runs.unwrap_or(DEFAULT_RUNS),
            }),
            collisions: self.collisions_per_run,
            batches: self.batches_per_run,
            seed,
        };
        cfg.validate()?;
        Ok(cfg)
    }
}

/// Runs per point of a sweep over w.
const DEFAULT_RUNS: u32 = 10;

/// A sweep of the diffusion tensor in a magnetic field.
#[derive(clap::Args)]
pub struct FieldArgs {
    /// The gap of a sweep over the field (with --fields), an exact decimal or fraction.
    #[arg(long, allow_negative_numbers = true)]
    pub(super) w: Option<String>,
    /// A fixed field B for a sweep over w (--w-from, --w-to, --steps): D_xx and the Hall D_xy at
    /// each w. An exact decimal or fraction, 1e-3 <= |B| <= 1e3.
    #[arg(long, allow_negative_numbers = true)]
    pub(super) field: Option<String>,
    /// The fields of a sweep over B, comma-separated exact decimals or fractions (with B and -B
    /// both given, Onsager-Casimir is checked), e.g. --fields=-2,-1,1,2.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub(super) fields: Vec<String>,
    /// The scene of a sweep over the field: `triangular` (at --w) or `square` (at --radius; in a
    /// field its corridors close). A sweep over w is the triangular scene's.
    #[arg(long, default_value = "triangular")]
    pub(super) scene: super::args::SceneName,
    /// With --scene square: the disk radius, an exact decimal or fraction, 0 < r < 1/2.
    #[arg(long, allow_negative_numbers = true)]
    pub(super) radius: Option<String>,
    /// A table given as data (a TOML file, as `diffusion --table` reads) for a sweep over the
    /// field (with --fields) instead of --scene.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["w", "radius"])]
    pub(super) table: Option<std::path::PathBuf>,
    /// Phase points classified at each point of a field sweep for the sampled localized share.
    #[arg(long, default_value = "1e6", value_parser = parse_count, allow_negative_numbers = true)]
    pub(super) localization_samples: u64,
}

/// What `--checkpoint-every` saves in a sweep, which has no `--checkpoint` file: its work is in
/// `--out` (the shared help describes a checkpoint file).
const CHECKPOINT_EVERY_HELP: &str = "Save the whole state of every trajectory in flight of the \
    point in progress into OUT/points/*.partial every SECONDS of wall time (0 to 86400; a kill \
    loses at most about this much work). Finished batches and points are saved as they finish";

#[derive(clap::Args)]
#[command(mut_arg("checkpoint_every", |a| a.help(CHECKPOINT_EVERY_HELP)))]
pub struct Args {
    #[command(flatten)]
    pub(super) grid: GridArgs,
    #[command(flatten)]
    pub(super) in_field: FieldArgs,
    #[command(flatten)]
    pub(super) driven: driven::DrivenArgs,
    /// The sweep's configuration as JSON (as `lorentz slurm sweep` writes it, or a result's
    /// `config`), instead of the flags that describe a sweep: over w, or in a field on any table.
    #[arg(long, value_name = "FILE", conflicts_with_all = [
        "w_from", "w_to", "steps", "runs", "collisions_per_run", "batches_per_run", "w", "field",
        "fields", "scene", "radius", "table", "localization_samples", "seed", "electric",
        "electric_angle",
    ])]
    pub(super) config: Option<PathBuf>,
    /// Compute only part I of N (I = 0 .. N-1; point i belongs to part i mod N) into --out, for
    /// `lorentz merge`; as a Slurm array task: --shard $SLURM_ARRAY_TASK_ID/N.
    #[arg(long)]
    pub(super) shard: Option<String>,
    #[command(flatten)]
    pub(super) run: RunArgs,
    #[command(flatten)]
    pub(super) engine: EngineArg,
    /// Output directory: sweep.csv, sweep-runs.csv, sweep.json and the figures; finished points
    /// are kept in OUT/points/ and reused, the point in progress in OUT/points/*.partial.
    #[arg(long, default_value = "results/sweep")]
    pub(super) out: PathBuf,
    #[command(flatten)]
    pub(super) every: CheckpointEveryArg,
    #[command(flatten)]
    pub(super) output: OutputArgs,
}

/// The configuration of the whole sweep these options give (validated): its configuration file
/// (`--config`), or its flags — a sweep in a field with `--field` or `--fields`.
pub fn config(a: &Args) -> Result<SweepConfig, Error> {
    match a.config.as_deref() {
        Some(p) => SweepConfig::read(p),
        None if a.driven.driven() => {
            let w = a.in_field.w.as_deref();
            driven::config(&a.grid, w, &a.driven, a.run.seed())
        }
        None if a.in_field.in_field() => config_in_field(&a.grid, &a.in_field, a.run.seed()),
        None => {
            refuse_field_options(a)?;
            a.grid.config(a.run.seed())
        }
    }
}

impl FieldArgs {
    /// `--field` or `--fields` given.
    pub fn in_field(&self) -> bool {
        self.field.is_some() || !self.fields.is_empty()
    }
}

/// Refuses the options of a sweep over the field in a sweep over w.
fn refuse_field_options(a: &Args) -> Result<(), Error> {
    if let Some(w) = &a.in_field.w {
        return Err(Error::parameter(
            "w",
            w,
            "the gap of a sweep over the field: give --fields B1,B2,... (a sweep over w: \
             --w-from and --w-to)",
        ));
    }
    const FIELD_ONLY: &str = "for a sweep over the field (--fields B1,B2,...): a sweep over w \
                              without a field is the triangular scene's";
    if let Some(r) = &a.in_field.radius {
        return Err(Error::parameter("radius", r, FIELD_ONLY));
    }
    if a.in_field.scene != super::args::SceneName::Triangular {
        return Err(Error::parameter("scene", "square", FIELD_ONLY));
    }
    if a.config.is_none() && (a.grid.w_from.is_none() || a.grid.w_to.is_none()) {
        return Err(missing_end(&a.grid));
    }
    Ok(())
}

/// Every path a sweep of the kind `kind` (0 over w, 1 in a field, 2 driven: the index of
/// [`FOLDERS`]; `part`: one part of it) or a merge writes into `out`, for
/// [`files::check_outputs`] before any work: `out`, its points' folder, and its tables and
/// figures (a part: its manifest).
pub fn outputs(out: &Path, kind: usize, part: bool) -> Vec<Output> {
    use lorentz_gas::estimators::sweep::driven as driven_tables;
    use lorentz_gas::report::figures::{driven_sweep, field_sweep, sweep as figures};
    let names: Vec<&str> = match (kind, part) {
        (_, true) => vec![MANIFESTS[kind]],
        (0, false) => [&sweep::TABLE_FILES[..], &figures::FILES].concat(),
        (1, false) => [&field::TABLE_FILES[..], &field_sweep::FILES].concat(),
        _ => [&driven_tables::TABLE_FILES[..], &driven_sweep::FILES].concat(),
    };
    let mut v = vec![
        Output::Dir(out.to_path_buf()),
        Output::Subdir(out.join(FOLDERS[kind])),
    ];
    v.extend(Output::files_in(out, &names));
    v
}

/// Runs the sweep (over w without a field, or in one), or the part `--shard` of it.
pub fn run(a: Args) -> Result<(), Error> {
    let cfg = config(&a)?;
    let shard = a.shard.as_deref().map(Shard::parse).transpose()?;
    if let Some(s) = shard {
        s.validate(&cfg)?;
    }
    let inputs: Vec<&Path> = [&a.config, &a.in_field.table]
        .into_iter()
        .filter_map(|p| p.as_deref())
        .collect();
    files::check_outputs(&inputs, &outputs(&a.out, cfg.kind(), shard.is_some()))?;
    let out = a.out.clone();
    let points = match shard {
        Some(s) => (0..cfg.steps()).filter(|&i| s.owns(i)).count() as u64,
        None => cfg.steps() as u64,
    };
    let total = cfg
        .collisions
        .saturating_mul(cfg.runs() as u64)
        .saturating_mul(points);
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
    if let Some(s) = shard {
        let part = ShardConfig {
            sweep: cfg.clone(),
            shard: s,
        };
        let r = shard::run(&part, &opts);
        drop(progress);
        drop(pb);
        return emit(a.output.json, &r?, |r| {
            println!(
                "part {} of {}: points {:?} ({} resumed) written to {}/{}; combine the parts with lorentz merge",
                r.shard,
                cfg.describe(),
                r.points,
                r.resumed_points,
                out.display(),
                cfg.points_folder(),
            );
        });
    }
    let r = match cfg.grid {
        Grid::Gaps(_) => sweep::run(&cfg, &opts).map(|r| Finished::OverW(Box::new(r))),
        Grid::InField(_) => field::run(&cfg, &opts).map(|r| Finished::InField(Box::new(r))),
        Grid::Driven(_) => lorentz_gas::estimators::sweep::driven::run(&cfg, &opts)
            .map(|r| Finished::Driven(Box::new(r))),
    };
    drop(progress);
    drop(pb);
    finish(&r?, &out, a.output.json)
}

/// Writes the tables and figures of a finished sweep of either kind into `out` and prints it (a
/// field sweep's Onsager–Casimir disagreement is a FAIL, exit 1, after everything is written).
pub fn finish(r: &Finished, out: &Path, json: bool) -> Result<(), Error> {
    match r {
        Finished::OverW(r) => finish_over_w(r, out, json),
        Finished::InField(r) => finish_in_field(r, out, json),
        Finished::Driven(r) => driven::finish(r, out, json),
    }
}

/// Writes the tables and figures of a finished sweep over w into `out` and prints it.
fn finish_over_w(r: &SweepReport, out: &Path, json: bool) -> Result<(), Error> {
    sweep::write_tables(r, out)?;
    lorentz_gas::report::figures::sweep::write_sweep_figures(r, out)?;
    emit(json, r, |r| {
        print(r);
        println!(
            "written: {}/sweep.{{csv,json}}, sweep-runs.csv, fig2-D-vs-w, fig7-boltzmann, fig8-residuals (.png, .svg)",
            out.display()
        );
    })
}

/// The sweep's table and fits, as text ([`text::sweep`]).
pub fn print(r: &SweepReport) {
    print!("{}", text::sweep(r));
}

/// The field sweep of the grid `g` and field options `f` with `seed` (validated; shared with
/// `lorentz slurm sweep`).
pub fn config_in_field(g: &GridArgs, f: &FieldArgs, seed: u64) -> Result<SweepConfig, Error> {
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

/// Writes the tables and figures of a finished field sweep into `out`, prints it, and judges
/// Onsager–Casimir (a FAIL, exit 1, after everything is written).
pub fn finish_in_field(
    r: &field::FieldSweepReport,
    out: &std::path::Path,
    json: bool,
) -> Result<(), Error> {
    field::write_tables(r, out)?;
    lorentz_gas::report::figures::field_sweep::write_field_sweep_figures(r, out)?;
    emit(json, r, |r| {
        print!("{}", lorentz_gas::report::text::field_sweep::field_sweep(r));
        println!(
            "written: {}/field-sweep.{{csv,json}}, field-D_xx, field-D_xy (.png, .svg); points in {}/field-points",
            out.display(),
            out.display()
        );
    })?;
    verdict(
        r.onsager_agrees,
        "Onsager-Casimir: D_xx(B) - D_xx(-B) or D_xy(B) + D_xy(-B) is not consistent with 0",
    )
}

/// A sweep's symmetry check: `Ok` where it agrees, else the FAIL `failure` (exit 1).
pub fn verdict(agrees: bool, failure: &str) -> Result<(), Error> {
    if agrees {
        Ok(())
    } else {
        Err(Error::CheckFailed(failure.into()))
    }
}
