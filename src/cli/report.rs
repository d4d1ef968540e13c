//! `lorentz report`: the audit of a result file before publication.

use std::path::PathBuf;

use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::report::publication::{self, planned_rerun_collisions, AuditConfig, Verdict};
use lorentz_gas::Error;

use super::args::{OutputArgs, ThreadsArg};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    /// A result of diffusion, sweep (or merge), hops, theory, lattice-walk, backscatter or
    /// escape, written with --json (or sweep.json); at most 64 MiB.
    result: PathBuf,
    /// Quick: one batch (or run) re-run, chosen by the file's digest, fewer events replayed,
    /// short precision runs, at most 2e9 collisions re-run in all — under a minute for a default
    /// diffusion result on 2 cores.
    #[arg(long)]
    quick: bool,
    /// Most collisions re-run in all (computed from the recorded configuration); re-runs
    /// beyond it are reported as SKIP.
    #[arg(long, value_parser = super::args::parse_count, allow_negative_numbers = true)]
    max_rerun_collisions: Option<u64>,
    /// MPFR precision of the references, in bits (128 or more): the shadow audit's replay and the
    /// precision-independence run.
    #[arg(long, default_value = "128", value_parser = super::args::parse_count_u32)]
    reference_bits: u32,
    /// Output directory for report.{md,html,json} and the figures (default: beside RESULT, named
    /// RESULT's file stem + "-report", e.g. d.json -> d-report).
    #[arg(long)]
    out: Option<PathBuf>,
    #[command(flatten)]
    threads: ThreadsArg,
    #[command(flatten)]
    output: OutputArgs,
}

pub fn run(a: Args) -> Result<(), Error> {
    let default = {
        let stem = a
            .result
            .file_stem()
            .map_or("result".into(), |s| s.to_string_lossy().to_string());
        a.result.with_file_name(format!("{stem}-report"))
    };
    let cfg = AuditConfig {
        result: a.result.clone(),
        out: a.out.clone().unwrap_or(default),
        quick: a.quick,
        reference_bits: a.reference_bits,
        max_rerun_collisions: a.max_rerun_collisions,
    };
    // The file is read and checked first (bad input exits before anything is written); the
    // bar counts the collisions its configuration says the audit re-runs.
    let (_, planned) = planned_rerun_collisions(&cfg)?;
    let bar = Progress::new(planned, "collisions re-run", a.output.quiet);
    let progress = bar.callback();
    let opts = RunOptions {
        threads: a.threads.threads(),
        progress: &progress,
        ..RunOptions::default()
    };
    let r = publication::run(&cfg, &opts)?;
    drop(progress);
    drop(bar);
    let out = &cfg.out;
    emit(a.output.json, &r, |r| {
        for c in &r.checks {
            println!("{}  {:<16} {}: {}", c.verdict, c.group, c.name, c.detail);
        }
        let skipped = r
            .checks
            .iter()
            .filter(|c| c.verdict == Verdict::Skip)
            .count();
        println!(
            "{}: {} ({} checks, {skipped} skipped; {:.3e} collisions re-run, {:.1} s); written: {}/report.{{md,html,json}}",
            r.provenance.result_file,
            r.verdict,
            r.checks.len(),
            r.rerun_collisions as f64,
            r.seconds,
            out.display()
        );
    })?;
    if r.verdict == Verdict::Fail {
        return Err(Error::CheckFailed(format!(
            "{}: the audit FAILED (see {}/report.md)",
            a.result.display(),
            out.display()
        )));
    }
    Ok(())
}
