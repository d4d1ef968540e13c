//! `lorentz reproduce`: every figure and table of the user guide into one folder with an index.html.

use std::path::PathBuf;
use std::sync::Mutex;

use lorentz_gas::Error;
use lorentz_gas::report::reproduce::{Budget, Reporter, reproduce};

use super::args::{OutputArgs, RunArgs};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    /// quick (minutes on 2 cores) or paper (the user guide's statistics, Fig. 8 at 2e9 collisions per
    /// run: about an hour on 2 cores).
    #[arg(long, value_enum, default_value = "quick")]
    budget: Budget,
    #[command(flatten)]
    run: RunArgs,
    /// Output directory; finished steps are kept and not redone.
    #[arg(long, default_value = "results/reproduce")]
    out: PathBuf,
    #[command(flatten)]
    output: OutputArgs,
}

/// One progress bar per step, titled "[k/n] step (unit)".
struct Bars {
    quiet: bool,
    bar: Mutex<Option<Progress>>,
}

impl Reporter for Bars {
    fn stage(&self, index: usize, count: usize, name: &str, total: u64, unit: &str) {
        if let Ok(mut b) = self.bar.lock() {
            *b = None;
            *b = Some(Progress::new(
                total,
                &format!("[{}/{count}] {name} ({unit})", index + 1),
                self.quiet,
            ));
        }
    }
    fn stop(&self) -> Option<lorentz_gas::engine::options::StopFlag> {
        Some(super::signals::stop_flag())
    }
    fn advance(&self, n: u64) {
        if let Ok(b) = self.bar.lock()
            && let Some(b) = b.as_ref()
        {
            b.callback()(n);
        }
    }
}

pub fn run(a: Args) -> Result<(), Error> {
    let out = a.out.clone();
    // Finished steps are kept in --out: a signal stops the run and the same command continues.
    super::signals::keeping(&out);
    let bars = Bars {
        quiet: a.output.quiet,
        bar: Mutex::new(None),
    };
    let r = reproduce(a.budget, &out, a.run.seed(), a.run.threads(), &bars)?;
    drop(bars);
    emit(a.output.json, &r, |r| {
        print!(
            "{}",
            lorentz_gas::report::text::reproduce::reproduce(r, &out)
        );
    })
}
