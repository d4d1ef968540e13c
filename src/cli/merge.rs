//! `lorentz merge`: the parts of a sharded sweep combined into the whole sweep's outputs.

use std::path::PathBuf;

use lorentz_gas::Error;
use lorentz_gas::campaigns::merge::{self, MergeConfig};
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::sweep;
use lorentz_gas::estimators::sweep::field_parts;

use super::args::{OutputArgs, ThreadsArg};
use super::output::emit;

#[derive(clap::Args)]
pub struct Args {
    /// Directories written by `lorentz sweep --shard I/N` (all N parts of one sweep, over w or
    /// in a field).
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// Output directory: sweep.csv, sweep-runs.csv, sweep.json, the figures, and every point in
    /// OUT/points (so `lorentz sweep` with the same settings and --out OUT resumes them).
    #[arg(long, default_value = "results/sweep")]
    out: PathBuf,
    #[command(flatten)]
    threads: ThreadsArg,
    #[command(flatten)]
    output: OutputArgs,
}

pub fn run(a: Args) -> Result<(), Error> {
    let out = a.out.clone();
    let cfg = MergeConfig {
        parts: a.dirs.clone(),
        out: out.clone(),
    };
    let opts = RunOptions {
        threads: a.threads.threads(),
        ..super::signals::options()
    };
    let in_field = a.dirs.iter().any(|d| field_parts::is_field_part(d));
    let inputs: Vec<&std::path::Path> = a.dirs.iter().map(PathBuf::as_path).collect();
    let outputs = super::sweep::outputs(&out, in_field, false);
    merge::refuse_input_as_output(&a.dirs, &out)?;
    lorentz_gas::files::check_outputs(&inputs, &outputs)?;
    if in_field {
        let r = field_parts::merge(&a.dirs, &out, &opts)?;
        return super::sweep::finish_in_field(&r, &out, a.output.json);
    }
    let r = merge::run(&cfg, &opts)?;
    sweep::write_tables(&r, &out)?;
    lorentz_gas::report::figures::sweep::write_sweep_figures(&r, &out)?;
    emit(a.output.json, &r, |r| {
        super::sweep::print(r);
        println!(
            "merged {} parts: {}/sweep.{{csv,json}}, sweep-runs.csv, fig2-D-vs-w, fig7-boltzmann, fig8-residuals (.png, .svg)",
            a.dirs.len(),
            out.display()
        );
    })
}
