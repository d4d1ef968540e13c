//! The audit of a result file before publication (`lorentz report`): why a number from a run
//! can be trusted, check by check, each PASS, FAIL, SKIP or N/A (with the reason) and its
//! numbers; the whole report PASS, FAIL or INCOMPLETE.
//!
//! **The audit trusts nothing in the file.** It reads the file ([`mod@file`]: at most
//! [`file::MAX_RESULT_BYTES`], every key checked against the schema of its kind), takes the
//! recorded *configuration* (the `config` object), validates it exactly as the command line
//! validates its input, and re-runs it through the library (`estimators::<kind>::run`). It never
//! runs the recorded command line and never starts a process: a front end that owns a
//! command-line parser ([`run_with`]) has `meta.command_line` parsed, and provenance FAILs when
//! it does not give the recorded configuration ([`command_line`]); the work of every re-run is computed from the validated configuration, and the
//! report writes only inside [`AuditConfig::out`].
//!
//! For a `diffusion` result:
//! - **reproducibility of the record** — D, D_err, D_check and MSD/(4t) recomputed from the
//!   per-batch values in the file give the recorded bits (an edited summary number fails here, an
//!   edited batch value in the re-run below);
//! - **statistics** — the batches' between-group F (one-way analysis of variance of four groups
//!   of consecutive batches), the
//!   most extreme batch against a Bonferroni Student-t bound, the batch error against the errors of
//!   blocks of 2 and 4 batches (F bounds), and the fit window: D against D_check (paired over
//!   batches) with the local slope D(t) plotted with its error band;
//! - **exact identities** from the same run: mean free path (Santaló), τ = πA/(3w), π/(3w)
//!   collisions per hop, each within 4σ;
//! - **shadow audit** — batches re-run from their seeds with a fraction of their events replayed in
//!   MPFR (≥ 128 bits) from the exact pre-event state: none outside the error model;
//! - **precision independence** — short runs from the same starts in f64 and in MPFR at 128 bits
//!   agree with each other and with the recorded D within errors;
//! - **shadowing** — for the first 1000 collisions of some of the run's own trajectories, a true
//!   orbit within δ of every f64 collision point ([`crate::verification::shadowing`]);
//! - **reproducibility** — re-run batches give the recorded bits (one batch, drawn from
//!   operating-system entropy as the audit runs, with `quick` — its strength stated in the verdict,
//!   [`Sampled`]; every batch otherwise).
//!
//! For a `sweep` result (also one written by `lorentz merge`: the same result): the record (the
//! rows, the F tests of the runs, the fits and the crossing recomputed by the sweep's own analysis
//! from each run's D and error in the file, to the bit), the runs' F tests over the points, and
//! runs re-run from their seeds (one run of one point, drawn at random, with `quick`; the
//! whole sweep otherwise). For the driven gas (`diffusion --electric`): the record recomputed
//! from its batches and exact field, their statistics, the Lyapunov sum rule on average and per
//! trajectory, J⊥ = 0 on a mirror line, a shadow audit of thermostatted events at the recorded
//! table and field, and a re-run (one batch with `quick`); a driven sweep row by row the same
//! way, with its ±E checks and the sum rule at every point recomputed. For survival on an open
//! table (`escape --repeller` or `--open`): the
//! record recomputed from its batches to the bit, their statistics, the window check, γ, λ and
//! h_KS against the certified cycle expansion of the three-disk repeller (N/A on a table given
//! as data), and the run re-run (one batch with `quick`). For `hops`, `theory`, `lattice-walk`,
//! `backscatter` and `escape` on strips: the
//! record against its configuration, the exact identities they carry (Kac's lemma for
//! injection), and the configuration re-run, every field identical but timing and metadata.
//!
//! **Work.** Each re-run's collisions follow from the configuration (a batch, a run, the whole
//! computation; expected collisions for injections and escape, from the closed forms). They are
//! taken in order from one budget, the auditor's and never the file's: [`QUICK_RERUN_COLLISIONS`]
//! with `quick`, [`AuditConfig::max_rerun_collisions`] when set, else
//! [`DEFAULT_RERUN_COLLISIONS`]. A re-run that does not fit is a SKIP saying how many collisions
//! it needs and how many remain — never a silent pass.
//!
//! **Verdict.** FAIL if any check fails; else INCOMPLETE if any was skipped (the result is not
//! verified, and the report says what was not checked and why); else PASS. A check that does
//! not apply to the result (N/A: the command line of another program, the events of an MPFR
//! run) is neither.
//!
//! Every result's provenance: this build (version, git commit, rustc), the CPU, the date, the
//! recorded `meta` (version, seed, engine, SIMD path, threads, command line) and the SHA-256 of the
//! file — so the report is bound to exactly the bytes it audited.

mod backscatter;
mod checks;
pub mod command_line;
mod ctx;
mod current;
mod diffusion;
mod driven_sweep;
mod escape;
mod field;
mod field_sweep;
pub mod file;
pub mod headline;
mod histogram;
mod hops;
mod provenance;
mod render;
mod same_bits;
mod sampled;
mod statistics;
mod survival;
mod sweep;
mod table;

use std::cell::Cell;
use std::collections::BTreeMap;
use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::{MAX_AUDIT_BITS, MIN_AUDIT_BITS, RunOptions};
use crate::numbers::precision::Precision;
use checks::{Checks, entropy_draw, meta_problems, pick, record_check};
use ctx::Ctx;
use file::{Kind, ResultFile};
pub use sampled::Sampled;

/// A check's outcome.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "UPPERCASE")]
pub enum Verdict {
    /// The property holds, with the numbers shown.
    Pass,
    /// The property fails: the result should not be published as it is.
    Fail,
    /// Not checked, for the reason given (not a pass: the report is then INCOMPLETE).
    Skip,
    /// The property does not apply to this result, for the reason given (a command line of
    /// another program, the events of an MPFR run): neither a pass nor a gap.
    #[serde(rename = "N/A")]
    NotApplicable,
    /// The whole report only: no check failed, but at least one was skipped, so the result is
    /// not verified; the report names each skipped check and why.
    Incomplete,
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Verdict::Pass => "PASS",
            Verdict::Fail => "FAIL",
            Verdict::Skip => "SKIP",
            Verdict::NotApplicable => "N/A",
            Verdict::Incomplete => "INCOMPLETE",
        })
    }
}

/// One check of the report.
#[derive(Debug, Clone, Serialize)]
pub struct Check {
    /// Group (provenance, record, statistics, identities, verification, reproducibility).
    pub group: String,
    /// What is checked.
    pub name: String,
    /// The outcome.
    pub verdict: Verdict,
    /// The numbers and the criterion, in words.
    pub detail: String,
    /// The numbers, by name.
    pub numbers: BTreeMap<String, f64>,
}

/// Where the result and this report come from.
#[derive(Debug, Clone, Serialize)]
pub struct Provenance {
    /// The audited file.
    pub result_file: String,
    /// SHA-256 of its bytes (hex).
    pub sha256: String,
    /// Which kind of result it is (`diffusion`, `sweep`, …), recognised from its keys.
    pub kind: String,
    /// The `meta` block recorded in the file (shown; its command line is never run).
    pub recorded: Option<RunMeta>,
    /// Version of the crate that writes this report.
    pub version: String,
    /// Git commit this binary was built from (`unknown` outside a checkout).
    pub git_commit: String,
    /// The compiler that built it.
    pub rustc: String,
    /// CPU model of this machine.
    pub cpu: String,
    /// Date and time of the report (UTC, ISO 8601).
    pub date_utc: String,
}

/// The whole report.
#[derive(Debug, Clone, Serialize)]
pub struct PublicationReport {
    /// FAIL if any check failed, else INCOMPLETE if any was skipped, else PASS: a PASS means
    /// that every check that applies ran and passed.
    pub verdict: Verdict,
    /// What was measured and what came out, from the result file ([`headline::headline`]).
    pub headline: Vec<headline::HeadlineRow>,
    /// Provenance of the result and of the report.
    pub provenance: Provenance,
    /// The checks, in order.
    pub checks: Vec<Check>,
    /// Figures written next to the report (file stems).
    pub figures: Vec<String>,
    /// Whether the quick settings were used.
    pub quick: bool,
    /// What a quick audit re-ran of a result's batches or runs, and so how strong its PASS is
    /// (`None`: every one was re-run, or the kind is re-run whole).
    pub sampled: Option<Sampled>,
    /// Collisions re-run in all (within the budget).
    pub rerun_collisions: u64,
    /// Wall-clock seconds the report took.
    pub seconds: f64,
    /// This process's metadata.
    pub meta: RunMeta,
}

/// Most collisions the quick report re-runs in all (about 20 s on 2 cores).
pub const QUICK_RERUN_COLLISIONS: u64 = 2_000_000_000;

/// Most collisions the full report re-runs in all unless the auditor sets a bound: about an
/// hour and a half on 2 cores of the SIMD engine (Zen 4). A file that claims more work than
/// this (or than the auditor's bound) gets its re-runs skipped, and so cannot PASS.
pub const DEFAULT_RERUN_COLLISIONS: u64 = 1_000_000_000_000;

/// What to audit, where the report goes, and how thoroughly.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AuditConfig {
    /// The result file (written by `lorentz … --json`, `sweep --out`, `merge`).
    pub result: PathBuf,
    /// Directory of `report.{md,html,json}` and the figures (created): the audit writes nothing
    /// anywhere else.
    pub out: PathBuf,
    /// Quick: one batch (or run) re-run, fewer events replayed, shorter precision runs, and at
    /// most [`QUICK_RERUN_COLLISIONS`] re-run in all.
    pub quick: bool,
    /// MPFR precision of the references (shadow audit, precision independence, shadowing),
    /// [`MIN_AUDIT_BITS`] to [`MAX_AUDIT_BITS`].
    pub reference_bits: u32,
    /// Most collisions re-run in all (with `quick`, the smaller of this and
    /// [`QUICK_RERUN_COLLISIONS`]); `None`: [`QUICK_RERUN_COLLISIONS`] with `quick`, else
    /// [`DEFAULT_RERUN_COLLISIONS`]. Re-runs beyond it are SKIP, and the report INCOMPLETE.
    #[serde(default)]
    pub max_rerun_collisions: Option<u64>,
}

impl AuditConfig {
    /// The full audit of `result` into `out` at 128 bits.
    pub fn new(result: impl Into<PathBuf>, out: impl Into<PathBuf>) -> Self {
        AuditConfig {
            result: result.into(),
            out: out.into(),
            quick: false,
            reference_bits: MIN_AUDIT_BITS,
            max_rerun_collisions: None,
        }
    }

    /// Checks the settings (the file itself is checked when it is read).
    pub fn validate(&self) -> Result<(), Error> {
        let bits = self.reference_bits;
        Error::unless_in(
            "reference_bits",
            bits,
            MIN_AUDIT_BITS..=MAX_AUDIT_BITS,
            &format!(" (the shadow audit needs at least {MIN_AUDIT_BITS})"),
        )?;
        Ok(())
    }

    /// Every path the audit writes: `out` and the files in it ([`FILES`]).
    pub fn outputs(&self) -> Vec<crate::files::Output> {
        let mut v = vec![crate::files::Output::Dir(self.out.clone())];
        v.extend(crate::files::Output::files_in(&self.out, &FILES));
        v
    }

    /// Checks every output before any work ([`crate::files::check_outputs`]): none is a link,
    /// a FIFO or a directory, and none is the audited file.
    fn check_outputs(&self) -> Result<(), Error> {
        crate::files::check_outputs(&[&self.result], &self.outputs())
    }

    /// The budget of re-run collisions: the auditor's, never the file's.
    fn budget(&self) -> Option<u64> {
        Some(match (self.quick, self.max_rerun_collisions) {
            (true, Some(m)) => m.min(QUICK_RERUN_COLLISIONS),
            (true, None) => QUICK_RERUN_COLLISIONS,
            (false, Some(m)) => m,
            (false, None) => DEFAULT_RERUN_COLLISIONS,
        })
    }
}

/// The files an audit writes into its output directory: the report and its figures.
pub const FILES: [&str; 7] = [
    "report.md",
    "report.html",
    "report.json",
    "local-slope.png",
    "local-slope.svg",
    "batch-histogram.png",
    "batch-histogram.svg",
];

/// The audited result, parsed and validated: one per kind.
enum Audited {
    Diffusion(Box<crate::estimators::diffusion::DiffusionReport>),
    Sweep(Box<crate::estimators::sweep::SweepReport>),
    Hops(Box<hops::HopsKind>),
    Backscatter(Box<crate::estimators::hops::backscatter::BackscatterReport>),
    Escape(Box<crate::estimators::escape::EscapeReport>),
    Current(Box<crate::estimators::current::CurrentReport>),
    DrivenSweep(Box<crate::estimators::sweep::driven::DrivenSweepReport>),
    Survival(Box<crate::estimators::escape::survival::SurvivalReport>),
    Field(Box<crate::estimators::field::FieldReport>),
    FieldSweep(Box<crate::estimators::sweep::field::FieldSweepReport>),
    Table(
        Box<(
            crate::estimators::diffusion::scene::SceneDiffusionReport,
            crate::scenes::table::PeriodicTable,
        )>,
    ),
}

impl Audited {
    /// Reads `cfg.result`: the file, its kind, the result struct, its configuration validated.
    fn read(cfg: &AuditConfig) -> Result<(ResultFile, Audited), Error> {
        let path = cfg.result.as_path();
        let file = ResultFile::read(path)?;
        let a = match file.kind {
            Kind::Diffusion => Audited::Diffusion(Box::new(diffusion::parse(&file, path)?)),
            Kind::Sweep => Audited::Sweep(Box::new(sweep::parse(&file, path)?)),
            Kind::Hops | Kind::Theory | Kind::LatticeWalk => {
                Audited::Hops(Box::new(hops::parse(&file, path)?))
            }
            Kind::Backscatter => Audited::Backscatter(Box::new(backscatter::parse(&file, path)?)),
            Kind::Escape => Audited::Escape(Box::new(escape::parse(&file, path)?)),
            Kind::Survival => Audited::Survival(Box::new(survival::parse(&file, path)?)),
            Kind::Current => Audited::Current(Box::new(current::parse(&file, path)?)),
            Kind::DrivenSweep => Audited::DrivenSweep(Box::new(driven_sweep::parse(&file, path)?)),
            Kind::Field => Audited::Field(Box::new(field::parse(&file, path)?)),
            Kind::FieldSweep => Audited::FieldSweep(Box::new(field_sweep::parse(&file, path)?)),
            Kind::TableDiffusion => Audited::Table(Box::new(table::parse(&file, path)?)),
        };
        Ok((file, a))
    }

    /// The re-runs of the audit, in the order the checks take them: collisions each.
    fn reruns(&self, quick: bool, draw: u64) -> Result<Vec<u64>, Error> {
        match self {
            Audited::Diffusion(r) => diffusion::reruns(r, quick, draw),
            Audited::Sweep(r) => Ok(sweep::reruns(r, quick)),
            Audited::Hops(h) => Ok(vec![h.config().collisions]),
            Audited::Backscatter(r) => Ok(vec![backscatter::collisions(&r.config)?]),
            Audited::Escape(r) => Ok(vec![escape::collisions(&r.config)?]),
            Audited::Survival(r) => survival::reruns(r, quick),
            Audited::Current(r) => Ok(current::reruns(r, quick)),
            Audited::DrivenSweep(r) => Ok(driven_sweep::reruns(r, quick)),
            Audited::Field(r) => Ok(vec![r.config.collisions]),
            Audited::FieldSweep(r) => Ok(vec![field_sweep::collisions(r)]),
            Audited::Table(t) => Ok(vec![t.0.config.collisions]),
        }
    }

    fn meta(&self) -> &RunMeta {
        match self {
            Audited::Diffusion(r) => &r.meta,
            Audited::Sweep(r) => &r.meta,
            Audited::Hops(h) => h.meta(),
            Audited::Backscatter(r) => &r.meta,
            Audited::Escape(r) => &r.meta,
            Audited::Survival(r) => &r.meta,
            Audited::Current(r) => &r.meta,
            Audited::DrivenSweep(r) => &r.meta,
            Audited::Field(r) => &r.meta,
            Audited::FieldSweep(r) => &r.meta,
            Audited::Table(t) => &t.0.meta,
        }
    }
}

/// The re-runs admitted by `budget`, in order: each fits in what the earlier ones left.
fn admitted(reruns: &[u64], budget: Option<u64>) -> Vec<bool> {
    let mut left = budget;
    reruns
        .iter()
        .map(|&n| match left {
            None => true,
            Some(l) if n <= l => {
                left = Some(l - n);
                true
            }
            Some(_) => false,
        })
        .collect()
}

/// The kind of `cfg.result` and the collisions the audit will re-run: what a progress bar needs
/// before [`run`]. Reads and checks the file as [`run`] does (bad input is refused here too).
pub fn planned_rerun_collisions(cfg: &AuditConfig) -> Result<(Kind, u64), Error> {
    cfg.validate()?;
    cfg.check_outputs()?;
    let (file, a) = Audited::read(cfg)?;
    let reruns = a.reruns(cfg.quick, entropy_draw())?;
    let ok = admitted(&reruns, cfg.budget());
    let total = reruns
        .iter()
        .zip(&ok)
        .filter(|(_, y)| **y)
        .map(|(n, _)| n)
        .sum();
    Ok((file.kind, total))
}

/// Audits the result file `cfg.result` and writes the report (`report.md`, `report.html`,
/// `report.json`) and its figures into `cfg.out` (created) — nowhere else. `options.threads` run
/// the re-runs; `options.progress` receives the collisions re-run (in all
/// [`planned_rerun_collisions`]); the engine is the audit's choice (the bits are the same on every
/// engine).
///
/// # Errors
/// Bad input (before anything is written): settings out of range, a file that cannot be read,
/// is larger than [`file::MAX_RESULT_BYTES`], is not JSON, is not a result of a kind the audit
/// knows, holds a key its kind does not, or records a configuration the command line would
/// refuse. A FAIL verdict is not an error: it is in the report.
pub fn run(cfg: &AuditConfig, options: &RunOptions) -> Result<PublicationReport, Error> {
    run_with(cfg, options, None)
}

/// [`run`] with a front end's reader of its own command lines: the recorded command line is
/// parsed by it (never run) and must give the recorded configuration
/// (the module [`command_line`]); without one that check is a SKIP.
///
/// # Errors
/// As [`run`].
pub fn run_with(
    cfg: &AuditConfig,
    options: &RunOptions,
    reader: Option<command_line::ReadCommandLine>,
) -> Result<PublicationReport, Error> {
    cfg.validate()?;
    options.accept("report", &[])?;
    cfg.check_outputs()?;
    let start = std::time::Instant::now();
    let (file, audited) = Audited::read(cfg)?;
    let draw = entropy_draw();
    let reruns = audited.reruns(cfg.quick, draw)?;
    let ctx = Ctx {
        draw,
        sampled: Cell::new(None),
        out: &cfg.out,
        quick: cfg.quick,
        bits: cfg.reference_bits,
        threads: options.threads,
        progress: options.progress,
        reruns,
        admitted: Vec::new(),
        next: Cell::new(0),
        done: Cell::new(0),
        budget: cfg.budget(),
    };
    let ctx = Ctx {
        admitted: admitted(&ctx.reruns, ctx.budget),
        ..ctx
    };
    crate::files::create_dir_all(&cfg.out)?;
    let mut checks = Checks(Vec::new());
    let mut figures = Vec::new();
    let kind = file.kind.name();
    provenance::identification_check(&mut checks, kind, &file.sha, audited.meta());
    let given = (file.value.get("config"), file.value.get("pilot"));
    command_line::check(&mut checks, kind, given, audited.meta(), reader);
    match &audited {
        Audited::Diffusion(r) => diffusion::checks(r, &ctx, &mut checks, &mut figures)?,
        Audited::Sweep(r) => sweep::checks(r, &ctx, &mut checks)?,
        Audited::Hops(h) => hops::checks(h, &ctx, &mut checks)?,
        Audited::Backscatter(r) => backscatter::checks(r, &ctx, &mut checks)?,
        Audited::Escape(r) => escape::checks(r, &ctx, &mut checks)?,
        Audited::Survival(r) => survival::checks(r, &ctx, &mut checks)?,
        Audited::Current(r) => current::checks(r, &ctx, &mut checks)?,
        Audited::DrivenSweep(r) => driven_sweep::checks(r, &ctx, &mut checks)?,
        Audited::Field(r) => field::checks(r, &ctx, &mut checks, &mut figures)?,
        Audited::FieldSweep(r) => field_sweep::checks(r, &ctx, &mut checks)?,
        Audited::Table(t) => table::checks((&t.0, &t.1), &ctx, &mut checks)?,
    }
    let verdict = overall(&checks.0);
    let report = PublicationReport {
        verdict,
        headline: headline::headline(kind, &file.value),
        provenance: provenance::provenance(
            cfg.result.display().to_string(),
            &file.sha,
            kind,
            Some(audited.meta().clone()),
        ),
        checks: checks.0,
        figures,
        quick: cfg.quick,
        sampled: ctx.sampled.get(),
        rerun_collisions: ctx.done.get(),
        seconds: start.elapsed().as_secs_f64(),
        meta: RunMeta::new(
            None,
            None,
            Precision::Bits(cfg.reference_bits),
            Some(options.threads),
        ),
    };
    report.write(&cfg.out)?;
    Ok(report)
}

/// FAIL if any check failed, else INCOMPLETE if any was skipped, else PASS.
fn overall(checks: &[Check]) -> Verdict {
    if checks.iter().any(|c| c.verdict == Verdict::Fail) {
        Verdict::Fail
    } else if checks.iter().any(|c| c.verdict == Verdict::Skip) {
        Verdict::Incomplete
    } else {
        Verdict::Pass
    }
}

/// Agreement bound of exact identities and independent estimates: the crate's one convention
/// (the normal 4σ tail probability as a Student-t quantile, [`crate::statistics::comparison`]).
use crate::statistics::comparison::SIGMAS;
/// Significance of the statistical consistency checks (Bonferroni-corrected where several values
/// are tested at once): a correct run fails one of them about once in a thousand reports.
const ALPHA: f64 = 1e-3;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_from_days() {
        assert_eq!(provenance::civil_from_days(0), (1970, 1, 1));
        assert_eq!(provenance::civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(provenance::civil_from_days(20_780), (2026, 11, 23));
    }

    #[test]
    fn sha256_of_abc() {
        assert_eq!(
            crate::engine::resume::sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }

    #[test]
    fn the_budget_admits_re_runs_in_order() {
        assert_eq!(admitted(&[5, 10, 3], Some(9)), [true, false, true]);
        assert_eq!(admitted(&[5, 10, 3], None), [true, true, true]);
        assert_eq!(admitted(&[5], Some(0)), [false]);
    }
}
