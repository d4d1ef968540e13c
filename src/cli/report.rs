//! `lorentz report`: the audit of a result file before publication.

use std::path::PathBuf;
use std::sync::OnceLock;

use lorentz_gas::report::publication::{audit_result_file, Options, Verdict};
use lorentz_gas::Error;

use super::args::{OutputArgs, ThreadsArg};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    /// A result written with --json (diffusion, sweep; other kinds get provenance and digest).
    result: PathBuf,
    /// Quick: one batch re-run (chosen by the file's digest), fewer events replayed, short
    /// precision runs — under a minute for a default diffusion result on 2 cores.
    #[arg(long)]
    quick: bool,
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
    let out = a.out.clone().unwrap_or(default);
    // The amount of work is known only once the file is read: the bar starts then.
    let bar: OnceLock<Progress> = OnceLock::new();
    let quiet = a.output.quiet;
    let planned = |n: u64| {
        let _ = bar.set(Progress::new(n, "collisions re-run", quiet));
    };
    let progress = |n: u64| {
        if let Some(b) = bar.get() {
            b.callback()(n);
        }
    };
    // Re-runs a recorded command line through this binary, with its JSON on stdout.
    let rerun = |args: &[String]| -> Result<serde_json::Value, Error> {
        let exe = std::env::current_exe().map_err(Error::io("locate", "this program"))?;
        let mut cmd = std::process::Command::new(&exe);
        cmd.args(args.iter().filter(|a| *a != "--json" && *a != "--quiet"));
        cmd.args(["--json", "--quiet"]);
        let out = cmd
            .stderr(std::process::Stdio::inherit())
            .output()
            .map_err(Error::io("run", &exe))?;
        if !out.status.success() {
            return Err(Error::Failed(format!("exit status {}", out.status)));
        }
        serde_json::from_slice(&out.stdout)
            .map_err(|e| Error::Failed(format!("the re-run printed no JSON result: {e}")))
    };
    let r = audit_result_file(
        &a.result,
        &out,
        Options {
            quick: a.quick,
            threads: a.threads.threads(),
            bits: a.reference_bits,
        },
        &planned,
        &progress,
        Some(&rerun),
    )?;
    drop(bar);
    r.write(&out)?;
    emit(a.output.json, &r, |r| {
        for c in &r.checks {
            println!("{}  {:<16} {}: {}", c.verdict, c.group, c.name, c.detail);
        }
        println!(
            "{}: {} ({:.1} s); written: {}/report.{{md,html,json}}",
            r.provenance.result_file,
            r.verdict,
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
