//! `lorentz report`: the audit of a result file before publication.

use std::path::PathBuf;

use lorentz_gas::Error;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::report::publication::command_line::CommandLine;
use lorentz_gas::report::publication::{self, AuditConfig, Verdict, planned_rerun_collisions};

use super::args::{OutputArgs, ThreadsArg};
use super::output::emit;
use super::progress::Progress;

#[derive(clap::Args)]
pub struct Args {
    /// A result of diffusion, sweep (or merge), hops, theory, lattice-walk, backscatter or
    /// escape (strips, or survival on an open table), written with --json (or sweep.json); at
    /// most 64 MiB.
    result: PathBuf,
    /// Quick: one batch (or run) re-run, drawn at random (the verdict states how strong that is:
    /// publish with the full audit), fewer events replayed,
    /// short precision runs, at most 2e9 collisions re-run in all — under a minute for a default
    /// diffusion result on 2 cores.
    #[arg(long)]
    quick: bool,
    /// Most collisions re-run in all (computed from the recorded configuration; default 1e12,
    /// with --quick 2e9); re-runs beyond it are SKIP and the verdict INCOMPLETE (exit status 5).
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

/// A recorded command line read with this command line's own parser (never run): the command
/// and the configuration it gives, for the audit's provenance check.
fn read_command_line(line: &[String]) -> CommandLine {
    let program = line
        .first()
        .and_then(|p| std::path::Path::new(p).file_stem())
        .map(|s| s.to_string_lossy().to_string());
    if program.as_deref() != Some("lorentz") {
        return CommandLine::Foreign(format!(
            "recorded by `{}`, not by the lorentz command line: nothing to parse",
            line.first().map_or("", String::as_str)
        ));
    }
    let cli = match <super::Cli as clap::Parser>::try_parse_from(line) {
        Ok(c) => c,
        Err(e) => {
            let text = e.to_string();
            return CommandLine::Refused(text.lines().next().unwrap_or("").to_string());
        }
    };
    use super::Cmd;
    let command = line.get(1).cloned().unwrap_or_default();
    let config = match &cli.cmd {
        Cmd::Diffusion(a) => super::diffusion::recorded_config(a).map(Some),
        Cmd::Hops(a) => json(Ok(a.hop.config())),
        Cmd::Theory(a) | Cmd::LatticeWalk(a) => json(Ok(a.config())),
        Cmd::Backscatter(a) => json(Ok(super::backscatter::config(a))),
        Cmd::Escape(a) => super::escape::recorded_config(a).map(Some),
        Cmd::Sweep(a) => json(super::sweep::config(a)),
        _ => Ok(None),
    };
    // The commands whose results `lorentz report` audits write a result of their own name;
    // `merge` writes the sweep it merges.
    let writes = match &cli.cmd {
        Cmd::Merge(_) => Some("sweep".to_string()),
        Cmd::Diffusion(_)
        | Cmd::Hops(_)
        | Cmd::Theory(_)
        | Cmd::LatticeWalk(_)
        | Cmd::Backscatter(_)
        | Cmd::Escape(_)
        | Cmd::Sweep(_) => Some(command.clone()),
        _ => None,
    };
    match config {
        Ok(config) => CommandLine::Parsed {
            command,
            writes,
            config,
        },
        Err(e) => CommandLine::Refused(e.to_string()),
    }
}

/// A configuration as the result file records it.
fn json<C: serde::Serialize>(c: Result<C, Error>) -> Result<Option<serde_json::Value>, Error> {
    c.and_then(|c| serde_json::to_value(c).map_err(Error::encode))
        .map(Some)
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
        ..super::signals::options()
    };
    let r = publication::run_with(&cfg, &opts, Some(&read_command_line))?;
    drop(progress);
    drop(bar);
    let out = &cfg.out;
    emit(a.output.json, &r, |r| {
        print!(
            "{}",
            lorentz_gas::report::text::publication::publication(r, out)
        );
    })?;
    if r.verdict == Verdict::Fail {
        return Err(Error::CheckFailed(format!(
            "{}: the audit FAILED (see {}/report.md)",
            a.result.display(),
            out.display()
        )));
    }
    if r.verdict == Verdict::Incomplete {
        let skipped: Vec<&str> = r
            .checks
            .iter()
            .filter(|c| c.verdict == Verdict::Skip)
            .map(|c| c.name.as_str())
            .collect();
        return Err(Error::Incomplete(format!(
            "{}: the audit is INCOMPLETE, not a pass: {} check{} skipped ({}; the reasons are in \
             {}/report.md)",
            a.result.display(),
            skipped.len(),
            if skipped.len() == 1 { "" } else { "s" },
            skipped.join("; "),
            out.display()
        )));
    }
    Ok(())
}
