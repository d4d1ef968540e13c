//! `lorentz figure`: the paper's Figs. 5, 4a and 3/4b/6 from this crate's numbers.

use std::path::PathBuf;

use lorentz_gas::Error;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::report::figures::paper;

use super::args::{Exact, OutputArgs, RunArgs, parse_count, parse_exact_arg};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    /// Which figure (Figs. 2, 7, 8: `lorentz sweep`).
    #[command(subcommand)]
    kind: Kind,
}

#[derive(clap::Subcommand)]
enum Kind {
    /// Fig. 5: where injected particles backscatter, at one w.
    BackscatterMap(MapArgs),
    /// Fig. 4a and its inset: p_bs(w) by injection on the paper's grid.
    Backscatter(CurveArgs),
    /// Figs. 3, 4b, 6: p_cf against App. A, D_cf, D_bs, the hierarchy and the exact lattice walks.
    Hierarchy(HierarchyArgs),
}

/// Seed, threads, output folder and output format of every figure.
#[derive(clap::Args)]
struct Common {
    #[command(flatten)]
    run: RunArgs,
    /// Output directory.
    #[arg(long, default_value = "results/figures")]
    out: PathBuf,
    #[command(flatten)]
    output: OutputArgs,
}

#[derive(clap::Args)]
struct MapArgs {
    /// Gap w of the map, a decimal or a fraction such as 1/10: 0 < w < w_inf = 4/sqrt(3) - 2 = 0.3094...
    #[arg(long, default_value = "0.1", value_parser = parse_exact_arg, allow_hyphen_values = true)]
    w: Exact,
    /// Particles injected in all.
    #[arg(long, default_value_t = paper::MAP_SAMPLES, value_parser = parse_count, allow_negative_numbers = true)]
    particles: u64,
    #[command(flatten)]
    common: Common,
}

#[derive(clap::Args)]
struct CurveArgs {
    /// Particles injected at each gap w of the grid.
    #[arg(long, default_value_t = paper::CURVE_SAMPLES, value_parser = parse_count, allow_negative_numbers = true)]
    particles_per_gap: u64,
    #[command(flatten)]
    common: Common,
}

#[derive(clap::Args)]
struct HierarchyArgs {
    /// Collisions at each gap w of the grid, for the hop statistics and again for the Einstein D.
    #[arg(long, default_value_t = paper::HIERARCHY_COLLISIONS, value_parser = parse_count, allow_negative_numbers = true)]
    collisions_per_gap: u64,
    #[command(flatten)]
    common: Common,
}

/// The run options of a figure: its threads, `progress`, and Ctrl-C as a clean stop.
fn options<'a>(run: &RunArgs, progress: &'a (dyn Fn(u64) + Sync)) -> RunOptions<'a> {
    RunOptions {
        threads: run.threads(),
        progress,
        ..super::signals::options()
    }
}

pub fn run(a: Args) -> Result<(), Error> {
    let (r, c) = match &a.kind {
        Kind::BackscatterMap(m) => {
            let c = &m.common;
            let pb = Progress::new(m.particles, "injections", c.output.quiet);
            let cb = pb.callback();
            let r = paper::backscatter_map(
                m.w.value,
                m.particles,
                c.run.seed(),
                &c.out,
                &options(&c.run, &cb),
            )?;
            (r, c)
        }
        Kind::Backscatter(b) => {
            let c = &b.common;
            let n = b.particles_per_gap;
            let points = paper::backscatter_grids()?
                .iter()
                .map(|g| g.len() as u64)
                .sum::<u64>();
            let pb = Progress::new(n.saturating_mul(points), "injections", c.output.quiet);
            let cb = pb.callback();
            let r = paper::backscatter_curve(n, c.run.seed(), &c.out, &options(&c.run, &cb))?;
            (r, c)
        }
        Kind::Hierarchy(h) => {
            let c = &h.common;
            let n = h.collisions_per_gap;
            let points = paper::hierarchy_grid()?.len() as u64;
            // The hop statistics and the Einstein run each use n collisions per gap.
            let pb = Progress::new(n.saturating_mul(2 * points), "collisions", c.output.quiet);
            let cb = pb.callback();
            let r = paper::hierarchy(n, c.run.seed(), &c.out, &options(&c.run, &cb))?;
            (r, c)
        }
    };
    emit(c.output.json, &r, |r| {
        print!("{}", lorentz_gas::report::text::figure::figure(r, &c.out));
    })
}
