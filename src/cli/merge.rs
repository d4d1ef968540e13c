//! `lorentz merge`: the parts of a sharded sweep (over w, or in a field on any table) combined
//! into the whole sweep's outputs.

use std::path::PathBuf;

use lorentz_gas::Error;
use lorentz_gas::campaigns::merge::{self, MergeConfig};
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::sweep::stored::{FOLDERS, Finished};

use super::args::{OutputArgs, ThreadsArg};

#[derive(clap::Args)]
pub struct Args {
    /// Directories written by `lorentz sweep --shard I/N` (all N parts of one sweep, over w or
    /// in a field).
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// Output directory: the tables, JSON and figures of the whole sweep, and every point in
    /// OUT/points (in a field OUT/field-points), so `lorentz sweep` with the same settings and
    /// --out OUT resumes them.
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
    let kind = (1..FOLDERS.len())
        .rev()
        .find(|&k| a.dirs.iter().any(|d| d.join(FOLDERS[k]).is_dir()))
        .unwrap_or(0);
    let inputs: Vec<&std::path::Path> = a.dirs.iter().map(PathBuf::as_path).collect();
    let outputs = super::sweep::outputs(&out, kind, false);
    merge::refuse_input_as_output(&a.dirs, &out)?;
    lorentz_gas::files::check_outputs(&inputs, &outputs)?;
    let r = merge::run(&cfg, &opts)?;
    if !a.output.json {
        let kind = match r {
            Finished::OverW(_) => "sweep",
            Finished::InField(_) => "field sweep",
            Finished::Driven(_) => "driven sweep",
        };
        println!("merged {} parts of the {kind}", a.dirs.len());
    }
    super::sweep::finish(&r, &out, a.output.json)
}
