//! The `lorentz` command line: one module per subcommand, shared options in [`args`], progress
//! bars in [`progress`], printing in [`output`]. Every analysis lives in the library; a
//! subcommand parses, calls the library, and prints.

/// `println!` for the command line: a closed standard output (the reader of a pipe has gone, as
/// in `lorentz … --json | head -1`) ends the program quietly with status 0 instead of a panic;
/// any other failure to write is reported on stderr with its cause.
macro_rules! println {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let mut out = std::io::stdout().lock();
        if let Err(e) = writeln!(out, $($arg)*) {
            crate::cli::output::stdout_failed(e);
        }
    }};
}

/// `eprintln!` for the command line: a closed standard error is not reported anywhere (there is
/// nowhere to report it) and never panics.
macro_rules! eprintln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr().lock(), $($arg)*);
    }};
}

pub mod args;
pub mod output;
pub mod progress;

mod audit;
mod backscatter;
mod bench;
mod certify;
mod constants;
mod cycles;
mod diffusion;
mod escape;
mod field;
mod figure;
mod free_paths;
mod hops;
mod lattice_walk;
mod lyapunov;
mod merge;
mod report;
mod reproduce;
mod section;
mod shadow;
mod signals;
mod slurm;
mod superdiffusion;
mod sweep;
mod theory;
mod trajectory;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use lorentz_gas::{Error, ErrorKind};

/// Exit status of a verification whose verdict is INCOMPLETE: no check failed, some were
/// skipped (`lorentz report`).
const EXIT_INCOMPLETE: u8 = 5;
/// Exit status of every refused input (clap's convention for usage errors).
const EXIT_BAD_INPUT: u8 = 2;
/// Exit status of a verification whose verdict is FAIL (`lorentz report`).
const EXIT_CHECK_FAILED: u8 = 1;
/// Exit status when a file, a directory or standard output cannot be read or written (other
/// than a closed pipe, which exits 0).
const EXIT_IO: u8 = 3;
/// Exit status of a computation that started and could not finish correctly (a re-run that
/// fails, an identity violated during a run, a resumed run that fails its checks).
const EXIT_FAILED: u8 = 4;
/// Exit status of a run stopped before it finished (the shell's status for SIGINT; a run
/// stopped by SIGTERM or SIGHUP exits 143 or 129, [`signals::stopped`]).
const EXIT_INTERRUPTED: u8 = 130;

/// The exit status of each kind of error: the one table of the command line's statuses (the
/// "Exit status" paragraph of docs/reference/command-line.md lists the same).
fn exit_status(kind: ErrorKind) -> u8 {
    match kind {
        ErrorKind::CheckFailed => EXIT_CHECK_FAILED,
        ErrorKind::Incomplete => EXIT_INCOMPLETE,
        ErrorKind::BadInput => EXIT_BAD_INPUT,
        ErrorKind::Io => EXIT_IO,
        ErrorKind::Failed => EXIT_FAILED,
        ErrorKind::Interrupted => EXIT_INTERRUPTED,
    }
}

#[derive(Parser)]
#[command(
    name = "lorentz",
    version,
    about = "Deterministic diffusion in the periodic Lorentz gas (Klages & Dellago 2000), with error bars and MPFR shadows"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Diffusion coefficient D(w) by the Einstein formula, with standard errors from independent batches.
    Diffusion(diffusion::Args),
    /// Diffusion coefficient from the escape rate out of open strips of several widths (Gaspard-Baras), extrapolated in 1/L.
    Escape(escape::Args),
    /// Per-event shadow audit: replay f64 events in MPFR from the exact pre-event state and judge them against the error model.
    Audit(audit::Args),
    /// Largest Lyapunov exponent (tangent space) and the divergence of f64/64..1024-bit orbits from a 4096-bit reference.
    Lyapunov(lyapunov::Args),
    /// Certify a segment of N collisions to D digits by precision doubling (runs at P and 2P bits agree).
    Certify(certify::Args),
    /// True shadowing: a true orbit (MPFR, Newton on the whole segment) within delta of each f64 segment, with a Newton-Kantorovich bound.
    Shadow(shadow::Args),
    /// Superdiffusion beyond a finite horizon: flight tails, t*C(t), <dx^2>/t against ln t and the limit law, against the exact corridor constants.
    Superdiffusion(superdiffusion::Args),
    /// Free paths between collisions, tau over the mean free path, against the Boltzmann-Grad limit law of small disks.
    FreePaths(free_paths::Args),
    /// Backscattering by injection into a single trap from the invariant flux (Kac's lemma checks included).
    Backscatter(backscatter::Args),
    /// Trap-hopping statistics along lattice trajectories: p_bs, p_cf, symbol sequences, hop-level Green-Kubo D.
    Hops(hops::Args),
    /// D over a range of w with independent runs per point (resumable); residuals, Boltzmann fit, MZ crossing, figures.
    Sweep(sweep::Args),
    /// Audit a result file before publication: provenance, record, statistics, exact identities, shadow audit, precision independence, reproducibility (PASS/FAIL; Markdown, HTML, JSON).
    Report(report::Args),
    /// Regenerate every figure (2-8) and table of the user guide, the paper's claims and speed against error into one folder with an index.html (resumable).
    Reproduce(reproduce::Args),
    /// Combine the parts of a sweep run with --shard I/N into the whole sweep's CSV, JSON and figures (bit-identical).
    Merge(merge::Args),
    /// Write Slurm batch scripts for a campaign: a job array of sweep parts and a merge job that depends on it.
    Slurm(slurm::Args),
    /// Regenerate one of the paper's figures from this crate's numbers (PNG, SVG, CSV, JSON into --out).
    Figure(figure::Args),
    /// The corrected Machta-Zwanzig hierarchy (D_cf, D_bs, D_1, D_k), App. A p_cf, and the exact D of correlated lattice walks, on measured hop statistics.
    #[command(mut_arg("order", |a| a.help(theory::ORDER_HELP)))]
    Theory(theory::Args),
    /// Fig. 6b by simulation: correlated lattice walks of order 1..K driven by the measured symbol tables, next to their exact D.
    #[command(mut_arg("order", |a| a.help(lattice_walk::ORDER_HELP)))]
    LatticeWalk(lattice_walk::Args),
    /// Certified periodic orbits and cycle expansions: the three-disk repeller (escape rate, Lyapunov exponent, KS entropy, partial dimension) or, with --w, the triangular Lorentz gas (D by cycle averaging beside the MSD), against the longest cycle N.
    Cycles(cycles::Args),
    /// Every closed-form quantity at gap w (geometry, Santalo, Machta-Zwanzig, Boltzmann).
    Constants(constants::Args),
    /// Poincare section in Birkhoff coordinates (theta, p = sin of the outgoing angle) at collisions, each orbit coloured by its component: pinned, skipping, bounded (regular islands), diffusing.
    Section(section::Args),
    /// One trajectory from exact initial conditions (start, direction, time) to certified digits by precision doubling.
    Trajectory(trajectory::Args),
    /// Kernel throughput (median of repetitions); with --report, speed against error.
    Bench(bench::Args),
}

/// Parses the command line, runs the subcommand, and maps every error to its exit status
/// ([`exit_status`]) with one line on stderr.
pub fn main() -> ExitCode {
    // Before any command runs: every command ends on SIGINT, SIGTERM and SIGHUP ([`signals`]).
    signals::install();
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) if e.use_stderr() => {
            // clap's first line names the option and the reason; the usage lines that follow
            // are left to --help.
            let text = e.to_string();
            let first = text.lines().next().unwrap_or("error: invalid arguments");
            // An invalid choice names the valid ones on the same line, a missing argument
            // itself (clap lists it on the next line).
            use clap::error::{ContextKind, ContextValue};
            let listed = |k| match e.get(k) {
                Some(ContextValue::Strings(v)) if !v.is_empty() => Some(v.join(", ")),
                _ => None,
            };
            match (
                listed(ContextKind::ValidValue),
                listed(ContextKind::InvalidArg),
            ) {
                (Some(v), _) => eprintln!("{first}: use one of {v}"),
                (None, Some(a)) if e.kind() == clap::error::ErrorKind::MissingRequiredArgument => {
                    eprintln!("{first} {a}")
                }
                _ => eprintln!("{first}"),
            }
            return ExitCode::from(EXIT_BAD_INPUT);
        }
        Err(e) => {
            // --help and --version.
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
    };
    match run(cli.cmd) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if signals::stopped().is_some() => {
            // A run asked to stop by a signal: its own error first if the stop is not what
            // ended it, then the signal's line and status.
            if e.kind() != ErrorKind::Interrupted {
                eprintln!("error: {}", one_line(&e));
            }
            let (status, message) = signals::stopped().unwrap_or_default();
            signals::say(&message);
            ExitCode::from(status)
        }
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            ExitCode::from(exit_status(e.kind()))
        }
    }
}

/// The error as the command line says it: the library's message on one line, with the typed
/// errors that name a parameter presented in the command line's terms (its flags).
fn one_line(e: &Error) -> String {
    let text = e.presented(&flag);
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The flag of a parameter the library names (`resume` is `--checkpoint` here, a Slurm
/// campaign's `binary` `--lorentz`).
fn flag(parameter: &str) -> String {
    match parameter {
        "resume" => "--checkpoint".into(),
        "binary" => "--lorentz".into(),
        p => format!("--{}", p.replace('_', "-")),
    }
}

fn run(cmd: Cmd) -> Result<(), Error> {
    match cmd {
        Cmd::Diffusion(a) => diffusion::run(a),
        Cmd::Section(a) => section::run(a),
        Cmd::Escape(a) => escape::run(a),
        Cmd::Audit(a) => audit::run(a),
        Cmd::Lyapunov(a) => lyapunov::run(a),
        Cmd::Certify(a) => certify::run(a),
        Cmd::Shadow(a) => shadow::run(a),
        Cmd::Superdiffusion(a) => superdiffusion::run(a),
        Cmd::FreePaths(a) => free_paths::run(a),
        Cmd::Backscatter(a) => backscatter::run(a),
        Cmd::Hops(a) => hops::run(a),
        Cmd::Sweep(a) => sweep::run(a),
        Cmd::Merge(a) => merge::run(a),
        Cmd::Report(a) => report::run(a),
        Cmd::Reproduce(a) => reproduce::run(a),
        Cmd::Slurm(a) => slurm::run(a),
        Cmd::Figure(a) => figure::run(a),
        Cmd::Theory(a) => theory::run(a),
        Cmd::LatticeWalk(a) => lattice_walk::run(a),
        Cmd::Constants(a) => constants::run(a),
        Cmd::Cycles(a) => cycles::run(a),
        Cmd::Trajectory(a) => trajectory::run(a),
        Cmd::Bench(a) => bench::run(a),
    }
}
