//! `lorentz section`: a Poincaré section in Birkhoff coordinates, each orbit's collisions
//! coloured by its component (pinned, skipping, bounded in a regular island, diffusing).

use std::path::PathBuf;

use lorentz_gas::Error;
use lorentz_gas::estimators::section::{
    self, DEFAULT_CLASSIFY_COLLISIONS, DEFAULT_COLLISIONS, DEFAULT_TRAJECTORIES, SectionConfig,
};
use lorentz_gas::files::Output;
use lorentz_gas::report::figures::section::{write_section_csv, write_section_figure};
use lorentz_gas::scenes::spec::{Motion, Table};

use super::args::{OutputArgs, RunArgs, SceneArgs, parse_count, parse_count_u32};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    /// A uniform magnetic field B, an exact decimal or fraction such as 5/2: the velocity turns
    /// counter-clockwise for B > 0 on a cyclotron circle of radius 1/|B|. Without it (or 0)
    /// flights are straight and every orbit diffuses.
    #[arg(long, allow_hyphen_values = true)]
    field: Option<String>,
    /// Trajectories, each started from the invariant measure on its own stream: 1 to 100000.
    #[arg(long, default_value_t = DEFAULT_TRAJECTORIES, value_parser = parse_count_u32, allow_negative_numbers = true)]
    trajectories: u32,
    /// Collisions recorded per trajectory (one point each): 1 to 1e7, trajectories × collisions at most 2e7.
    #[arg(long, default_value_t = DEFAULT_COLLISIONS, value_parser = parse_count, allow_negative_numbers = true)]
    collisions: u64,
    /// Collisions flown per orbit in a field to tell a regular island (bounded) from the
    /// chaotic sea (diffusing): at least --collisions, at most 1e10.
    #[arg(long, default_value_t = DEFAULT_CLASSIFY_COLLISIONS, value_parser = parse_count, allow_negative_numbers = true)]
    classify_collisions: u64,
    #[command(flatten)]
    run: RunArgs,
    /// Write the figure (PNG: theta across, p up, one dot per collision coloured by component).
    #[arg(long, value_name = "FILE.png")]
    out: Option<PathBuf>,
    /// Write the points as CSV: trajectory, component, disk, theta, p.
    #[arg(long, value_name = "FILE")]
    csv: Option<PathBuf>,
    #[command(flatten)]
    output: OutputArgs,
}

/// The configuration these options give (validated).
pub fn config(a: &Args) -> Result<SectionConfig, Error> {
    let cfg = SectionConfig {
        table: Table {
            scene: a.scene.spec()?,
            motion: Motion::in_field(a.field.as_deref().unwrap_or("0")),
        },
        trajectories: a.trajectories,
        collisions: a.collisions,
        classify_collisions: a.classify_collisions,
        seed: a.run.seed(),
    };
    cfg.validate()?;
    Ok(cfg)
}

pub fn run(a: Args) -> Result<(), Error> {
    let cfg = config(&a)?;
    if let Some(out) = &a.out
        && !out
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        return Err(Error::parameter(
            "out",
            out.display(),
            "the figure is a PNG: name a file ending in .png",
        ));
    }
    let outputs: Vec<Output> = [&a.out, &a.csv]
        .into_iter()
        .flatten()
        .map(|p| Output::File(p.clone()))
        .collect();
    let inputs: Vec<&std::path::Path> = a.scene.table.as_deref().into_iter().collect();
    lorentz_gas::files::check_outputs(&inputs, &outputs)?;
    section::work(&cfg)?.check(a.run.threads())?;
    let per_orbit = if cfg.table.field().is_some() {
        cfg.classify_collisions
    } else {
        cfg.collisions
    };
    let pb = Progress::new(
        u64::from(cfg.trajectories).saturating_mul(per_orbit),
        "collisions",
        a.output.quiet,
    );
    let r = section::run(&cfg, &pb.options(a.run.threads()))?;
    drop(pb);
    if let Some(path) = &a.out {
        write_section_figure(&r, path)?;
    }
    if let Some(path) = &a.csv {
        write_section_csv(&r, path)?;
    }
    emit(a.output.json, &r, |r| {
        print!("{}", lorentz_gas::report::text::section::section(r));
    })
}
