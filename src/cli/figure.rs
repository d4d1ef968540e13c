//! `lorentz figure`: the paper's Figs. 5, 4a and 3/4b/6 from this crate's numbers.

use clap::ValueEnum;

use lorentz_gas::report::figures::paper;
use lorentz_gas::Error;

use super::args::{parse_count, OutDirArg, OutputArgs, RunArgs};
use super::output::emit;
use super::progress::Progress;

#[derive(Clone, Copy, Debug, ValueEnum)]
enum Kind {
    /// Fig. 5: where injected particles backscatter, at one w.
    BackscatterMap,
    /// Fig. 4a and its inset: p_bs(w) by injection on the paper's grid.
    Backscatter,
    /// Figs. 3, 4b, 6: p_cf against App. A, D_cf, D_bs, the hierarchy and the exact lattice walks.
    Hierarchy,
}

#[derive(clap::Args)]
pub struct Args {
    /// Which figure (Figs. 2, 7, 8: `lorentz sweep`).
    #[arg(value_enum)]
    kind: Kind,
    /// Gap for backscatter-map.
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    w: f64,
    /// Injections (map), injections per point (backscatter) or collisions per gap (hierarchy);
    /// default 60000, 200000 and 2e7.
    #[arg(long, value_parser = parse_count, allow_negative_numbers = true)]
    samples: Option<u64>,
    #[command(flatten)]
    run: RunArgs,
    /// Output directory (default results/figures).
    #[command(flatten)]
    out: OutDirArg,
    #[command(flatten)]
    output: OutputArgs,
}

pub fn run(a: Args) -> Result<(), Error> {
    let out = a.out.dir("results/figures");
    let (seed, threads) = (a.run.seed, a.run.threads());
    let r = match a.kind {
        Kind::BackscatterMap => {
            let n = a.samples.unwrap_or(paper::MAP_SAMPLES);
            let pb = Progress::new(n, "injections", a.output.quiet);
            let r = paper::backscatter_map(a.w, n, seed, &out, &pb.callback())?;
            r
        }
        Kind::Backscatter => {
            let n = a.samples.unwrap_or(paper::CURVE_SAMPLES);
            let points = paper::backscatter_grids()?
                .iter()
                .map(|g| g.len() as u64)
                .sum::<u64>();
            let pb = Progress::new(n.saturating_mul(points), "injections", a.output.quiet);
            let r = paper::backscatter_curve(n, seed, threads, &out, &pb.callback())?;
            r
        }
        Kind::Hierarchy => {
            let n = a.samples.unwrap_or(paper::HIERARCHY_COLLISIONS);
            let points = paper::hierarchy_grid()?.len() as u64;
            // The hop statistics and the Einstein run each use n collisions per gap.
            let pb = Progress::new(n.saturating_mul(2 * points), "collisions", a.output.quiet);
            let r = paper::hierarchy(n, seed, threads, &out, &pb.callback())?;
            r
        }
    };
    emit(a.output.json, &r, |r| {
        println!("written into {}: {}", out.display(), r.files.join(", "));
    })
}
