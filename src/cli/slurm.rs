//! `lorentz slurm`: batch scripts that run a campaign on a Slurm cluster (job array + dependent
//! merge job). The scripts are written, not submitted: `sh OUT/slurm/submit.sh` submits them.

use std::path::PathBuf;

use lorentz_gas::Error;
use lorentz_gas::campaigns::slurm::SweepCampaign;

use super::args::{EngineArg, OutputArgs, SeedArg, parse_count_u32};
use super::output::emit;
use super::sweep::{FieldArgs, GridArgs};

#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    what: What,
}

#[derive(clap::Subcommand)]
enum What {
    /// A sweep as a job array of N parts and a merge job that runs when all have succeeded: over
    /// w (--w-from, --w-to), in a field (--fields at --w, --scene square --radius or --table;
    /// or --field over w), or driven (--electric at --w), as `lorentz sweep` takes them.
    Sweep(SweepArgs),
}

#[derive(clap::Args)]
struct SweepArgs {
    #[command(flatten)]
    grid: GridArgs,
    #[command(flatten)]
    in_field: FieldArgs,
    #[command(flatten)]
    driven: super::sweep::driven::DrivenArgs,
    /// Parts of the sweep: array tasks 0 .. N-1 (1 to the number of points).
    #[arg(long, value_parser = parse_count_u32, allow_negative_numbers = true)]
    array: u32,
    /// CPUs of each array task (the --threads of its `lorentz sweep`).
    #[arg(long, default_value = "1", value_parser = parse_count_u32, allow_negative_numbers = true)]
    cpus_per_task: u32,
    /// Slurm partition (default: the cluster's default partition).
    #[arg(long)]
    partition: Option<String>,
    /// Wall-time limit of each task, in Slurm's forms (90, 2:00:00, 1-12:00:00).
    #[arg(long)]
    time: Option<String>,
    /// The Slurm account the jobs are charged to (default: the user's default account).
    #[arg(long)]
    account: Option<String>,
    /// Memory of each job (per node), in Slurm's form: 4G, 500M (megabytes without a unit).
    #[arg(long)]
    mem: Option<String>,
    /// A further #SBATCH directive of both jobs in option syntax, --key=value or a flag --key
    /// (e.g. --sbatch=--qos=long); repeatable. Checked: no spaces, quotes or shell characters.
    #[arg(long, value_name = "--KEY=VALUE", allow_hyphen_values = true)]
    sbatch: Vec<String>,
    /// The lorentz binary the jobs run (default: this one), as seen from the compute nodes.
    #[arg(long)]
    lorentz: Option<PathBuf>,
    #[command(flatten)]
    seed: SeedArg,
    #[command(flatten)]
    engine: EngineArg,
    /// Output directory of the campaign: parts in OUT/shard-I, the merged sweep in OUT, scripts
    /// and job logs in OUT/slurm.
    #[arg(long, default_value = "results/sweep")]
    out: PathBuf,
    #[command(flatten)]
    output: OutputArgs,
}

/// What `lorentz slurm sweep` wrote.
#[derive(serde::Serialize)]
struct Written {
    files: Vec<PathBuf>,
    submit: String,
    meta: lorentz_gas::engine::metadata::RunMeta,
}

pub fn run(a: Args) -> Result<(), Error> {
    let What::Sweep(a) = a.what;
    let sweep = if a.driven.driven() {
        let w = a.in_field.w.as_deref();
        super::sweep::driven::config(&a.grid, w, &a.driven, a.seed.seed)?
    } else if a.in_field.in_field() {
        super::sweep::config_in_field(&a.grid, &a.in_field, a.seed.seed)?
    } else {
        a.grid.config(a.seed.seed)?
    };
    let absolute = |p: PathBuf| -> Result<PathBuf, Error> {
        if p.is_absolute() {
            Ok(p)
        } else {
            Ok(std::env::current_dir()
                .map_err(Error::io("read", "the current directory"))?
                .join(p))
        }
    };
    let binary = match a.lorentz {
        Some(p) => absolute(p)?,
        None => std::env::current_exe().map_err(Error::io("locate", "this program"))?,
    };
    let c = SweepCampaign {
        sweep,
        parts: a.array,
        out: absolute(a.out)?,
        binary,
        engine: a.engine.engine,
        cpus_per_task: a.cpus_per_task,
        partition: a.partition,
        time: a.time,
        account: a.account,
        mem: a.mem,
        extra: a.sbatch,
    };
    let w = Written {
        files: c.write()?,
        submit: format!("sh {}", c.out.join("slurm").join("submit.sh").display()),
        meta: lorentz_gas::engine::metadata::RunMeta::new(
            Some(c.sweep.seed),
            Some(c.sweep.trajectories()),
            lorentz_gas::numbers::precision::Precision::F64,
            Some(c.cpus_per_task as usize),
        ),
    };
    emit(a.output.json, &w, |w| {
        for p in &w.files {
            println!("written: {}", p.display());
        }
        println!("submit with: {}", w.submit);
    })
}
