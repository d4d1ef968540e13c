//! The audit of a result file before publication (`lorentz report`): why a number from a run
//! can be trusted, check by check, each PASS, FAIL or SKIP (with the reason) and its numbers.
//!
//! For a `diffusion` result:
//! - **reproducibility of the record** — D, D_err, D_check and MSD/(4t) recomputed from the
//!   per-batch values in the file give the recorded bits (an edited summary number fails here, an
//!   edited batch value in the re-run below);
//! - **statistics** — the batches' between-group χ² (four groups of consecutive batches), the
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
//! - **reproducibility** — re-run batches give the recorded bits (one batch, chosen by the file's
//!   digest, with `quick`; every batch otherwise).
//!
//! For a `sweep` result: the record (each D is the mean of its runs, D_MZ and D_Bo are the closed
//! forms, the residuals are from the weighted line through the points), the runs' F tests over
//! the points, and one run of one point re-run from its seed. For `hops`, `backscatter` and
//! `escape` results: the exact identities they carry (Kac's lemma for injection) and the recorded
//! command re-run, every field identical but timing and metadata.
//!
//! Every result's provenance: this build (version, git commit, rustc), the CPU, the date, the
//! recorded `meta` (version, seed, engine, SIMD path, threads, command line) and the SHA-256 of the
//! file — so the report is bound to exactly the bytes it audited.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;
use sha2::{Digest, Sha256};

use crate::engine::metadata::RunMeta;
use crate::engine::options::{AuditSpec, RunOptions};
use crate::engine::Engine;
use crate::estimators::diffusion::{
    batch_d, rerun_batches, BatchResult, DiffusionConfig, DiffusionReport,
};
use crate::estimators::sweep::SweepConfig;
use crate::numbers::precision::Precision;
use crate::report::figures::{plot, PlotSpec, Series};
use crate::scenes::triangular::geometry::Geometry;
use crate::statistics::{
    mean_se, normal_sigma_equivalent_t, student_t_quantile, weighted_line_fit,
};
use crate::Error;

/// A check's outcome.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "UPPERCASE")]
pub enum Verdict {
    /// The property holds, with the numbers shown.
    Pass,
    /// The property fails: the result should not be published as it is.
    Fail,
    /// Not checked, for the reason given (not a pass).
    Skip,
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Verdict::Pass => "PASS",
            Verdict::Fail => "FAIL",
            Verdict::Skip => "SKIP",
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
    /// Which command produced it (`diffusion`, `sweep`, …).
    pub kind: String,
    /// The `meta` block recorded in the file.
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
    /// FAIL if any check failed, else PASS (skipped checks are listed, not counted).
    pub verdict: Verdict,
    /// Provenance of the result and of the report.
    pub provenance: Provenance,
    /// The checks, in order.
    pub checks: Vec<Check>,
    /// Figures written next to the report (file stems).
    pub figures: Vec<String>,
    /// Whether the quick settings were used.
    pub quick: bool,
    /// Wall-clock seconds the report took.
    pub seconds: f64,
    /// This process's metadata.
    pub meta: RunMeta,
}

/// How thorough the report is.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// Quick: one batch re-run, fewer events replayed, shorter precision runs (under a minute on
    /// 2 cores for a default diffusion result).
    pub quick: bool,
    /// Worker threads.
    pub threads: usize,
    /// MPFR precision of the shadow audit and of the precision-independence run (≥ 128).
    pub bits: u32,
}

/// Events replayed in MPFR by the shadow audit: enough to see the error model's tail (the
/// per-event bound is exceeded by none of the ~10⁷ events of `tests/numerics/verification.rs`).
const AUDIT_EVENTS_QUICK: f64 = 2e4;
/// As [`AUDIT_EVENTS_QUICK`], for the full report.
const AUDIT_EVENTS_FULL: f64 = 2e5;
/// Batches of the precision-independence runs (enough for a standard error).
const PRECISION_BATCHES: u32 = 8;
/// Collisions per batch of the MPFR precision run, as a multiple of the least the fit windows need:
/// about 5·10⁵ collisions at w = 0.1 for the quick report (a few seconds at 128 bits).
const PRECISION_LENGTH_QUICK: f64 = 4.0;
/// As [`PRECISION_LENGTH_QUICK`], for the full report.
const PRECISION_LENGTH_FULL: f64 = 32.0;
/// Agreement bound of exact identities and independent estimates: the normal 4σ tail probability
/// (6·10⁻⁵), as a Student-t quantile for errors from a few batches (the crate's convention).
const SIGMAS: f64 = 4.0;
/// Significance of the statistical consistency checks (Bonferroni-corrected where several values
/// are tested at once): a correct run fails one of them about once in a thousand reports.
const ALPHA: f64 = 1e-3;

/// The SHA-256 of `bytes` in hex.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Days since 1970-01-01 to (year, month, day) in the proleptic Gregorian calendar (H. Hinnant's
/// `civil_from_days`; written out because a date is all the report needs from a calendar crate).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

fn now_utc() -> String {
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let (y, m, d) = civil_from_days(t.div_euclid(86_400));
    let s = t.rem_euclid(86_400);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        s / 3600,
        s / 60 % 60,
        s % 60
    )
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

struct Checks(Vec<Check>);

impl Checks {
    fn add(
        &mut self,
        group: &str,
        name: &str,
        verdict: Verdict,
        detail: String,
        numbers: &[(&str, f64)],
    ) {
        self.0.push(Check {
            group: group.into(),
            name: name.into(),
            verdict,
            detail,
            numbers: numbers.iter().map(|(k, v)| (k.to_string(), *v)).collect(),
        });
    }
    fn pass_if(
        &mut self,
        ok: bool,
        group: &str,
        name: &str,
        detail: String,
        numbers: &[(&str, f64)],
    ) {
        let v = if ok { Verdict::Pass } else { Verdict::Fail };
        self.add(group, name, v, detail, numbers);
    }
}

/// Runs a recorded command line (the arguments after the program name) again and returns its
/// `--json` result: how the report re-runs results it has no library re-run for (`hops`,
/// `backscatter`, `escape`). The command-line layer provides it; the library only compares.
pub type Rerun<'a> = &'a dyn Fn(&[String]) -> Result<serde_json::Value, Error>;

/// Audits the result file `path`, writing figures into `out` (created). `progress` receives the
/// collisions re-run; `planned` is told their total first; `rerun` re-runs recorded command
/// lines (without it, results other than `diffusion` and `sweep` are not re-run).
pub fn audit_result_file(
    path: &Path,
    out: &Path,
    opts: Options,
    planned: &dyn Fn(u64),
    progress: &(dyn Fn(u64) + Sync),
    rerun: Option<Rerun<'_>>,
) -> Result<PublicationReport, Error> {
    check_bits(opts.bits)?;
    let start = std::time::Instant::now();
    let file = ResultFile::read(path)?;
    let sha = sha256_hex(&file.bytes);
    crate::files::create_dir_all(out)?;
    let mut checks = Checks(Vec::new());
    let mut figures = Vec::new();
    identification_check(&mut checks, &file.kind, &sha, file.recorded.as_ref());
    let ctx = Ctx {
        sha: &sha,
        out,
        opts,
        planned,
        progress,
    };
    match file.kind.as_str() {
        "diffusion" => {
            let r: DiffusionReport = serde_json::from_value(file.value).map_err(|e| {
                Error::Invalid(format!("{}: not a diffusion result ({e})", path.display()))
            })?;
            diffusion_checks(&r, ctx, &mut checks, &mut figures)?;
        }
        "sweep" => sweep_checks(&file.value, ctx, &mut checks)?,
        other => other_checks(other, &file.value, opts, &mut checks, rerun),
    }
    let verdict = if checks.0.iter().any(|c| c.verdict == Verdict::Fail) {
        Verdict::Fail
    } else {
        Verdict::Pass
    };
    Ok(PublicationReport {
        verdict,
        provenance: Provenance {
            result_file: path.display().to_string(),
            sha256: sha,
            kind: file.kind,
            recorded: file.recorded,
            version: env!("CARGO_PKG_VERSION").into(),
            git_commit: env!("LORENTZ_GIT_COMMIT").into(),
            rustc: env!("LORENTZ_RUSTC_VERSION").into(),
            cpu: cpu_model(),
            date_utc: now_utc(),
        },
        checks: checks.0,
        figures,
        quick: opts.quick,
        seconds: start.elapsed().as_secs_f64(),
        meta: RunMeta::new(None, None, Precision::Bits(opts.bits), Some(opts.threads)),
    })
}

/// What every check of one audit shares: the file's digest, where figures go, the settings, and
/// where re-runs report their planned and finished collisions.
#[derive(Clone, Copy)]
struct Ctx<'a> {
    sha: &'a str,
    out: &'a Path,
    opts: Options,
    planned: &'a dyn Fn(u64),
    progress: &'a (dyn Fn(u64) + Sync),
}

/// Refuses an MPFR precision outside what the shadow audit accepts.
fn check_bits(bits: u32) -> Result<(), Error> {
    use crate::engine::options::{MAX_AUDIT_BITS, MIN_AUDIT_BITS};
    if !(MIN_AUDIT_BITS..=MAX_AUDIT_BITS).contains(&bits) {
        return Err(Error::Invalid(format!(
            "bits = {bits}: use {MIN_AUDIT_BITS} to {MAX_AUDIT_BITS} (the shadow audit needs at least {MIN_AUDIT_BITS})"
        )));
    }
    Ok(())
}

/// A result file as read: its bytes, its JSON, its recorded `meta` and the command that wrote it.
struct ResultFile {
    bytes: Vec<u8>,
    value: serde_json::Value,
    recorded: Option<RunMeta>,
    kind: String,
}

impl ResultFile {
    /// Reads and parses `path`, refusing files that are not JSON results of lorentz.
    fn read(path: &Path) -> Result<Self, Error> {
        let bytes = crate::files::read(path)?;
        let value: serde_json::Value = serde_json::from_slice(&bytes).map_err(|e| {
            Error::Invalid(format!(
                "{}: not a JSON result of lorentz ({e}); write one with --json",
                path.display()
            ))
        })?;
        let recorded: Option<RunMeta> = value
            .get("meta")
            .and_then(|m| serde_json::from_value(m.clone()).ok());
        let kind = recorded
            .as_ref()
            .and_then(|m| m.command_line.get(1).cloned())
            .ok_or_else(|| {
                Error::Invalid(format!(
                    "{}: no meta block with a command line: not a result file of lorentz --json",
                    path.display()
                ))
            })?;
        Ok(ResultFile {
            bytes,
            value,
            recorded,
            kind,
        })
    }
}

/// The provenance check: which result this is, by whom and how it was recorded.
fn identification_check(checks: &mut Checks, kind: &str, sha: &str, recorded: Option<&RunMeta>) {
    checks.add(
        "provenance",
        "result file identified",
        Verdict::Pass,
        format!(
            "{} result, SHA-256 {sha}; recorded by lorentz {} ({} engine{}, {} threads, seed {})",
            kind,
            recorded.map_or("?", |m| m.version.as_str()),
            recorded.map_or("?", |m| m.engine.as_str()),
            recorded
                .and_then(|m| m.simd.as_ref())
                .map_or(String::new(), |s| format!(" {s}")),
            recorded
                .and_then(|m| m.threads)
                .map_or("?".into(), |t| t.to_string()),
            recorded
                .and_then(|m| m.seed)
                .map_or("-".into(), |s| s.to_string()),
        ),
        &[],
    );
}

/// Fields of a result that legitimately differ between two runs of the same command: the
/// process's metadata and its timing.
const VOLATILE_FIELDS: [&str; 5] = [
    "meta",
    "seconds",
    "collisions_per_second",
    "events_per_second",
    "resumed_batches",
];

/// Most collisions, injections or events the quick report re-runs a recorded command for (about
/// 20 s on 2 cores).
const QUICK_RERUN_WORK: f64 = 2e9;

/// `hops`, `backscatter`, `escape`: the exact identities the result carries, and the recorded
/// command re-run (through `rerun`) giving the same bits in every field but timing and metadata.
fn other_checks(
    kind: &str,
    value: &serde_json::Value,
    opts: Options,
    checks: &mut Checks,
    rerun: Option<Rerun<'_>>,
) {
    if kind == "backscatter" {
        backscatter_identity_checks(value, checks);
    }
    let work = ["collisions", "particles", "events"]
        .iter()
        .find_map(|k| value[k].as_f64())
        .unwrap_or(f64::INFINITY);
    let name = "the recorded command re-run gives the same bits";
    let Some(rerun) = rerun else {
        checks.add(
            "reproducibility",
            name,
            Verdict::Skip,
            "no way to re-run commands was given".into(),
            &[],
        );
        return;
    };
    if opts.quick && work > QUICK_RERUN_WORK {
        checks.add(
            "reproducibility",
            name,
            Verdict::Skip,
            format!("{work:e} collisions/particles/events: more than the quick report re-runs ({QUICK_RERUN_WORK:e}); run without --quick"),
            &[],
        );
        return;
    }
    let args: Vec<String> = value["meta"]["command_line"]
        .as_array()
        .map(|a| {
            a.iter()
                .skip(1)
                .filter_map(|x| x.as_str().map(String::from))
                .collect()
        })
        .unwrap_or_default();
    match rerun(&args) {
        Ok(again) => rerun_identical_check(value, &again, &args, work, checks),
        Err(e) => checks.add(
            "reproducibility",
            name,
            Verdict::Fail,
            format!("`lorentz {}` did not run again: {e}", args.join(" ")),
            &[],
        ),
    }
}

/// A `backscatter` result's Kac identities: mean visit time and collisions per visit against
/// their closed forms.
fn backscatter_identity_checks(value: &serde_json::Value, checks: &mut Checks) {
    let num = |k: &str| value[k].as_f64();
    let batches = value["meta"]["batches"]
        .as_f64()
        .unwrap_or(f64::INFINITY)
        .max(2.0);
    let bound = normal_sigma_equivalent_t(batches - 1.0, SIGMAS);
    for (name, k, w_exact) in [
        (
            "mean visit time = τ (Kac)",
            "mean_visit_time",
            "mean_visit_time_exact",
        ),
        (
            "collisions per visit = π/(3w) (Kac)",
            "mean_collisions_per_visit",
            "mean_collisions_per_visit_exact",
        ),
    ] {
        let (Some(v), Some(e), Some(x), Some(w)) =
            (num(k), num(&format!("{k}_err")), num(w_exact), num("w"))
        else {
            continue;
        };
        let exact = Geometry::new(w).map(|g| {
            if k == "mean_visit_time" {
                g.hop_time()
            } else {
                g.collisions_per_hop()
            }
        });
        let closed = exact.as_ref().is_ok_and(|c| c.to_bits() == x.to_bits());
        let z = (v - x) / e;
        checks.pass_if(
            z.abs() <= bound && closed,
            "identities",
            name,
            format!(
                "{v} ± {e:.1e} against exact {x} ({z:+.2}σ; bound {bound:.2}σ){}",
                if closed {
                    ""
                } else {
                    "; the recorded exact value is not the closed form"
                }
            ),
            &[("value", v), ("err", e), ("exact", x)],
        );
    }
}

/// `value` without the fields that differ between two runs of the same command.
fn strip_volatile(v: &serde_json::Value) -> serde_json::Value {
    let mut v = v.clone();
    if let Some(o) = v.as_object_mut() {
        for k in VOLATILE_FIELDS {
            o.remove(k);
        }
    }
    v
}

/// The re-run check: the recorded result `value` and the re-run's `again` identical in every
/// field but timing and metadata.
fn rerun_identical_check(
    value: &serde_json::Value,
    again: &serde_json::Value,
    args: &[String],
    work: f64,
    checks: &mut Checks,
) {
    let (a, b) = (strip_volatile(value), strip_volatile(again));
    let differ: Vec<String> = a
        .as_object()
        .map(|o| {
            o.iter()
                .filter(|(k, v)| b.get(k.as_str()) != Some(v))
                .map(|(k, _)| k.clone())
                .collect()
        })
        .unwrap_or_default();
    checks.pass_if(
        differ.is_empty() && a == b,
        "reproducibility",
        "the recorded command re-run gives the same bits",
        if differ.is_empty() && a == b {
            format!(
                "`lorentz {}` again: every field identical (timing and metadata aside)",
                args.join(" ")
            )
        } else {
            format!(
                "`lorentz {}` again: {} differ",
                args.join(" "),
                if differ.is_empty() {
                    "the fields".to_string()
                } else {
                    differ.join(", ")
                }
            )
        },
        &[("work", work)],
    );
}

/// A batch index chosen by the file's digest: not known in advance to whoever edits the file.
fn batch_from_digest(sha: &str, batches: u32) -> u32 {
    let head = u64::from_str_radix(&sha[..16], 16).unwrap_or(0);
    (head % batches as u64) as u32
}

/// F(d1, d2) quantile at lower-tail probability p.
fn f_quantile(d1: f64, d2: f64, p: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, FisherSnedecor};
    FisherSnedecor::new(d1, d2).map_or(f64::NAN, |f| f.inverse_cdf(p))
}

fn chi2_upper_p(x: f64, dof: f64) -> f64 {
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    ChiSquared::new(dof).map_or(f64::NAN, |c| c.sf(x))
}

/// The checks of a `diffusion` result (see the module documentation), in order.
fn diffusion_checks(
    r: &DiffusionReport,
    ctx: Ctx<'_>,
    checks: &mut Checks,
    figures: &mut Vec<String>,
) -> Result<(), Error> {
    let Some(cfg) = r.config.clone() else {
        checks.add(
            "reproducibility",
            "per-batch record",
            Verdict::Fail,
            "the file has no configuration and per-batch values (written before result files carried them): re-run the diffusion to audit it".into(),
            &[],
        );
        return Ok(());
    };
    let n = r.batch_D.len();
    record_check(r, &cfg, checks);
    if n < 8 {
        checks.add(
            "statistics",
            "batch statistics",
            Verdict::Skip,
            format!("{n} batches: the consistency checks need at least 8"),
            &[],
        );
    } else {
        batch_statistics(r, checks);
    }
    fit_window_check(r, checks);
    diffusion_figures(r, ctx.out, figures)?;
    let g = Geometry::new(cfg.w)?;
    identity_checks(r, &g, checks);
    // --- re-runs: reproducibility with the shadow audit, precision independence ---------------
    let plan = RerunPlan::new(&cfg, ctx)?;
    (ctx.planned)(plan.collisions + 2 * plan.short);
    let can_audit = cfg.precision == Precision::F64;
    let audit = if can_audit {
        Some(AuditSpec::new(plan.rate, ctx.opts.bits)?)
    } else {
        None
    };
    let again = rerun_batches(
        &cfg,
        &plan.batches,
        plan.engine,
        ctx.opts.threads,
        audit,
        ctx.progress,
    )?;
    rerun_batches_check(r, &cfg, g.hop_time(), &plan, &again, ctx.opts, checks);
    shadow_audit_check(&again, ctx.opts, checks);
    precision_independence(&cfg, r, plan.short, ctx.opts, checks, ctx.progress)?;
    shadowing_certificate(&cfg, &plan.batches, ctx.opts, checks)?;
    Ok(())
}

/// The record check: D, its errors, D_check and MSD/(4t) recomputed from the per-batch values
/// give the recorded bits.
fn record_check(r: &DiffusionReport, cfg: &DiffusionConfig, checks: &mut Checks) {
    let n = r.batch_D.len();
    let ((d, de), (dc, dce)) = r.d_from_batches();
    let mut bad = Vec::new();
    if n != cfg.batches as usize || r.batch_D_check.len() != n || r.batch_msd.len() != n {
        bad.push(format!("{n} batch values for {} batches", cfg.batches));
    }
    for (name, rec, again) in [
        ("D", r.D, d),
        ("D_err", r.D_err, de),
        ("D_check", r.D_check, dc),
        ("D_check_err", r.D_check_err, dce),
        ("w", r.w, cfg.w),
    ] {
        if rec.to_bits() != again.to_bits() {
            bad.push(format!(
                "{name}: recorded {rec:e}, from the batches {again:e}"
            ));
        }
    }
    for (k, (rec, rec_err)) in r.msd_over_4t.iter().zip(&r.msd_over_4t_err).enumerate() {
        let t = r.msd_times.get(k).copied().unwrap_or(f64::NAN);
        let v: Vec<f64> = r
            .batch_msd
            .iter()
            .map(|m| m.get(k).copied().unwrap_or(f64::NAN) / (4.0 * t))
            .collect();
        let (value, err) = mean_se(&v);
        if r.msd_over_4t.len() != r.msd_over_4t_err.len()
            || value.to_bits() != rec.to_bits()
            || err.to_bits() != rec_err.to_bits()
        {
            bad.push(format!("MSD/(4t) at t = {t}"));
        }
    }
    checks.pass_if(
        bad.is_empty(),
        "reproducibility",
        "D and its errors follow from the recorded batches",
        if bad.is_empty() {
            format!("D = {} ± {} and D_check, MSD/(4t) at {} lags recomputed from {n} batch values: the same bits", r.D, r.D_err, r.msd_times.len())
        } else {
            format!("recomputed values differ from the recorded ones: {}", bad.join("; "))
        },
        &[("batches", n as f64)],
    );
}

/// The fit window: D against D_check, paired over batches.
fn fit_window_check(r: &DiffusionReport, checks: &mut Checks) {
    let n = r.batch_D.len();
    let diffs: Vec<f64> = r
        .batch_D
        .iter()
        .zip(&r.batch_D_check)
        .map(|(a, b)| a - b)
        .collect();
    let (md, sd) = mean_se(&diffs);
    let bound_pair = normal_sigma_equivalent_t((n.max(2) - 1) as f64, SIGMAS);
    checks.pass_if(
        (md / sd).abs() <= bound_pair,
        "statistics",
        "fit window: D and D_check agree",
        format!(
            "D[{}τ, {}τ] − D[{}τ, {}τ] = {md:.3e} ± {sd:.1e} ({:+.1}σ; paired over batches; bound {bound_pair:.2}σ, t with {} dof)",
            r.window.lo, r.window.hi, r.check_window.lo, r.check_window.hi, md / sd, n.max(2) - 1
        ),
        &[("difference", md), ("difference_err", sd)],
    );
}

/// The figures of a diffusion audit: the local slope D(t) with the recorded D, and the histogram
/// of the batch values.
fn diffusion_figures(
    r: &DiffusionReport,
    out: &Path,
    figures: &mut Vec<String>,
) -> Result<(), Error> {
    let slope_series = local_slopes(r);
    let t_first = r.msd_times.first().copied().unwrap_or(0.0);
    let t_last = r.msd_times.last().copied().unwrap_or(t_first);
    let stem = out.join("local-slope");
    plot(
        &stem,
        &PlotSpec {
            title: "Local slope D(t) = d MSD / (4 dt), with the recorded D",
            x_label: "t",
            y_label: "D(t)",
            log_x: false,
            log_y: false,
        },
        &[
            Series {
                label: "local slope between lags (error: over batches)".into(),
                points: slope_series,
                notes: Vec::new(),
                line: true,
            },
            Series {
                label: "MSD/(4t)".into(),
                points: r
                    .msd_times
                    .iter()
                    .zip(r.msd_over_4t.iter().zip(&r.msd_over_4t_err))
                    .map(|(t, (v, e))| (*t, *v, *e))
                    .collect(),
                notes: Vec::new(),
                line: true,
            },
            Series {
                label: format!("D + D_err = {:.6} + {:.6}", r.D, r.D_err),
                points: vec![(t_first, r.D + r.D_err, 0.0), (t_last, r.D + r.D_err, 0.0)],
                notes: Vec::new(),
                line: true,
            },
            Series {
                label: "D - D_err".into(),
                points: vec![(t_first, r.D - r.D_err, 0.0), (t_last, r.D - r.D_err, 0.0)],
                notes: Vec::new(),
                line: true,
            },
        ],
    )?;
    figures.push("local-slope".into());
    histogram(&r.batch_D, r.D, &out.join("batch-histogram"))?;
    figures.push("batch-histogram".into());
    Ok(())
}

/// The exact identities of the same run (mean free path, hop time, collisions per hop), each
/// within the 4σ bound of its batch error.
fn identity_checks(r: &DiffusionReport, g: &Geometry<f64>, checks: &mut Checks) {
    let n = r.batch_D.len();
    // Errors from n batches: the 4σ bound is the Student-t quantile at the normal 4σ tail.
    let bound_n = normal_sigma_equivalent_t((n.max(2) - 1) as f64, SIGMAS);
    for (name, v, e, exact, recorded_exact) in [
        (
            "mean free path (Santaló π|Q|/|∂Q|)",
            r.mean_free_path,
            r.mean_free_path_err,
            g.mean_free_path(),
            r.mean_free_path_exact,
        ),
        (
            "hop time τ = πA/(3w)",
            r.tau_hop,
            r.tau_hop_err,
            g.hop_time(),
            r.tau_hop_exact,
        ),
        (
            "collisions per hop π/(3w)",
            r.collisions_per_hop,
            r.collisions_per_hop_err,
            g.collisions_per_hop(),
            r.collisions_per_hop_exact,
        ),
    ] {
        let z = (v - exact) / e;
        let same = exact.to_bits() == recorded_exact.to_bits();
        checks.pass_if(
            z.abs() <= bound_n && same,
            "identities",
            name,
            format!(
                "{v} ± {e:.1e} against exact {exact} ({z:+.2}σ; bound {bound_n:.2}σ, the {SIGMAS}σ tail of t with {} dof){}",
                n - 1,
                if same {
                    ""
                } else {
                    "; the recorded exact value is not the closed form"
                }
            ),
            &[("value", v), ("err", e), ("exact", exact)],
        );
    }
}

/// What the audit re-runs: which batches on which engine, their collisions, the shadow audit's
/// replay rate and the length of the precision-independence runs.
struct RerunPlan {
    batches: Vec<u32>,
    engine: Engine,
    collisions: u64,
    rate: f64,
    short: u64,
}

impl RerunPlan {
    /// One batch chosen by the digest with `quick`, every batch otherwise.
    fn new(cfg: &DiffusionConfig, ctx: Ctx<'_>) -> Result<Self, Error> {
        let opts = ctx.opts;
        let batches: Vec<u32> = if opts.quick {
            vec![batch_from_digest(ctx.sha, cfg.batches)]
        } else {
            (0..cfg.batches).collect()
        };
        let per_batch = cfg.collisions / cfg.batches as u64;
        let collisions = per_batch * batches.len() as u64;
        let events = if opts.quick {
            AUDIT_EVENTS_QUICK
        } else {
            AUDIT_EVENTS_FULL
        };
        let rate = (events / collisions.max(1) as f64).clamp(1e-9, 1.0);
        let min = precision_min_collisions(cfg)?;
        let len = if opts.quick {
            PRECISION_LENGTH_QUICK
        } else {
            PRECISION_LENGTH_FULL
        };
        let short = ((min as f64) * len).ceil() as u64;
        // One batch alone runs fastest on the scalar engine (a SIMD block would carry 15 idle
        // lanes); all batches on the SIMD engine. Both give the same bits.
        let engine = if batches.len() == 1 {
            Engine::Scalar
        } else {
            Engine::Auto
        };
        Ok(RerunPlan {
            batches,
            engine,
            collisions,
            rate,
            short,
        })
    }
}

/// The re-run batches give the recorded D and D_check of each batch to the last bit.
fn rerun_batches_check(
    r: &DiffusionReport,
    cfg: &DiffusionConfig,
    tau: f64,
    plan: &RerunPlan,
    again: &[BatchResult],
    opts: Options,
    checks: &mut Checks,
) {
    let rerun = &plan.batches;
    let mut differ = Vec::new();
    for b in again {
        let (bd, bdc) = batch_d(b, tau, &cfg.window, &cfg.check_window);
        let i = b.index as usize;
        let rec = (r.batch_D.get(i).copied(), r.batch_D_check.get(i).copied());
        if rec.0.map(f64::to_bits) != Some(bd.to_bits())
            || rec.1.map(f64::to_bits) != Some(bdc.to_bits())
        {
            differ.push(format!(
                "batch {i}: recorded D = {:?}, re-run {bd:e}",
                rec.0
            ));
        }
    }
    checks.pass_if(
        differ.is_empty(),
        "reproducibility",
        if opts.quick { "one batch re-run from its seed gives the recorded bits" } else { "every batch re-run from its seed gives the recorded bits" },
        if differ.is_empty() {
            format!(
                "batch{} {} ({} collisions) re-run on the {} engine: D of each batch identical to the last bit",
                if rerun.len() == 1 { "" } else { "es" },
                if rerun.len() <= 4 { format!("{rerun:?}") } else { format!("0..{}", rerun.len() - 1) },
                plan.collisions,
                plan.engine.name()
            )
        } else {
            format!("{} of {} re-run batches differ: {}", differ.len(), rerun.len(), differ.iter().take(3).cloned().collect::<Vec<_>>().join("; "))
        },
        &[("batches_rerun", rerun.len() as f64)],
    );
}

/// The shadow audit of the re-run batches' events: none outside the error model.
fn shadow_audit_check(again: &[BatchResult], opts: Options, checks: &mut Checks) {
    match again.iter().filter_map(|b| b.audit.clone()).reduce(|mut a, b| {
        a.merge(&b);
        a
    }) {
        Some(a) => checks.pass_if(
            a.outside == 0 && a.audited > 0,
            "verification",
            "shadow audit of events of the same trajectories",
            format!(
                "{} events replayed at {} bits from the exact pre-event state: {} outside the error model, {} ambiguous; median time error / bound {:.2e}",
                a.audited,
                opts.bits,
                a.outside,
                a.ambiguous,
                a.time_error_over_bound.quantile(0.5)
            ),
            &[("audited", a.audited as f64), ("outside", a.outside as f64)],
        ),
        None => checks.add(
            "verification",
            "shadow audit of events of the same trajectories",
            Verdict::Skip,
            "the run is not f64: its events are MPFR already".into(),
            &[],
        ),
    }
}

/// Collisions per shadowed segment: long enough that the f64 orbit has left any orbit started
/// from its rounded start (the divergence horizon is ~35 collisions), short enough for seconds.
const SHADOW_COLLISIONS: usize = 1000;

/// The true-orbit certificate ([`crate::verification::shadowing`]) for the first
/// [`SHADOW_COLLISIONS`] collisions of some of the run's own trajectories: those of the re-run
/// batches (at most two with `quick`, eight otherwise).
fn shadowing_certificate(
    cfg: &DiffusionConfig,
    rerun: &[u32],
    opts: Options,
    checks: &mut Checks,
) -> Result<(), Error> {
    use crate::verification::shadowing::{f64_segment, shadow_pseudo_orbit};
    let scene = crate::scenes::triangular::TriangularScene::new(cfg.w)?;
    let want = if opts.quick { 2 } else { 8 };
    let mut batches: Vec<u32> = rerun.iter().copied().take(want).collect();
    let mut next = rerun.first().copied().unwrap_or(0);
    while batches.len() < want.min(cfg.batches as usize) {
        next = (next + 1) % cfg.batches;
        if !batches.contains(&next) {
            batches.push(next);
        }
    }
    let results = crate::engine::parallel::par_batches(opts.threads, batches.len() as u32, |k| {
        let start = crate::estimators::diffusion::batch_start(cfg, batches[k as usize])?;
        let orbit = f64_segment(&scene, &start, SHADOW_COLLISIONS, opts.bits)?;
        shadow_pseudo_orbit(&scene, &orbit, opts.bits)
    })?;
    let certified = results.iter().filter(|s| s.certified).count();
    let delta = results.iter().filter_map(|s| s.delta).fold(0.0, f64::max);
    let bound = results
        .iter()
        .filter_map(|s| s.correction_bound)
        .fold(0.0, f64::max);
    let failures: Vec<String> = results
        .iter()
        .zip(&batches)
        .filter(|(s, _)| !s.certified)
        .map(|(s, b)| {
            format!(
                "batch {b}: {}",
                s.failure.clone().unwrap_or_else(|| "not certified".into())
            )
        })
        .collect();
    checks.pass_if(
        failures.is_empty(),
        "verification",
        "shadowing: a true orbit within δ of the computed one",
        if failures.is_empty() {
            format!(
                "first {SHADOW_COLLISIONS} collisions of batches {batches:?}: {certified} of {} segments certified at {} bits (Newton on the whole segment; a true orbit with the same disks within 2Kε ≤ {bound:.1e} of the refined one); δ ≤ {delta:.2e} from every f64 collision point",
                results.len(),
                opts.bits
            )
        } else {
            format!("{} of {} segments not certified: {}", failures.len(), results.len(), failures.join("; "))
        },
        &[("delta_max", delta), ("certified", certified as f64), ("segments", results.len() as f64)],
    );
    Ok(())
}

/// Least collisions of a [`PRECISION_BATCHES`]-batch run at `cfg`'s w and windows.
fn precision_min_collisions(cfg: &DiffusionConfig) -> Result<u64, Error> {
    let g = Geometry::new(cfg.w)?;
    let hops = (crate::estimators::diffusion::MIN_HOPS_PER_LAG
        * cfg.window.hi.max(cfg.check_window.hi)) as f64;
    Ok((hops * g.collisions_per_hop() * PRECISION_BATCHES as f64).ceil() as u64)
}

fn precision_independence(
    cfg: &DiffusionConfig,
    r: &DiffusionReport,
    collisions: u64,
    opts: Options,
    checks: &mut Checks,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<(), Error> {
    let short = |precision| {
        let mut c = cfg.clone();
        c.collisions = collisions;
        c.batches = PRECISION_BATCHES;
        c.precision = precision;
        crate::estimators::diffusion::run(&c, &rerun_options(opts.threads, progress))
    };
    let lo = short(Precision::F64)?;
    let hi = short(Precision::Bits(opts.bits))?;
    let z_pair = (hi.D - lo.D) / (hi.D_err.hypot(lo.D_err));
    let z_rec = (hi.D - r.D) / (hi.D_err.hypot(r.D_err));
    // Errors from PRECISION_BATCHES batches: the t quantile at the normal 4σ tail.
    let bound = normal_sigma_equivalent_t((PRECISION_BATCHES - 1) as f64, SIGMAS);
    checks.pass_if(
        z_pair.abs() <= bound && z_rec.abs() <= bound,
        "verification",
        "precision independence",
        format!(
            "{PRECISION_BATCHES} batches of {} collisions from the run's first starts: MPFR {} bits D = {:.5} ± {:.5}, f64 D = {:.5} ± {:.5} ({z_pair:+.1}σ); against the recorded D {z_rec:+.1}σ (bound {bound:.2}σ, t with {} dof)",
            collisions / PRECISION_BATCHES as u64,
            opts.bits,
            hi.D,
            hi.D_err,
            lo.D,
            lo.D_err,
            PRECISION_BATCHES - 1
        ),
        &[("D_mpfr", hi.D), ("D_mpfr_err", hi.D_err), ("D_f64", lo.D), ("D_f64_err", lo.D_err)],
    );
    Ok(())
}

/// The between-group χ², the most extreme batch, and batch against block errors.
fn batch_statistics(r: &DiffusionReport, checks: &mut Checks) {
    let x = &r.batch_D;
    between_groups_check(x, checks);
    outlier_check(x, checks);
    block_error_checks(x, checks);
}

/// The between-group χ² of four groups of consecutive batches.
fn between_groups_check(x: &[f64], checks: &mut Checks) {
    let n = x.len();
    // Four groups of consecutive batches (the last takes the remainder).
    let groups = 4;
    let size = n / groups;
    let parts: Vec<(f64, f64)> = (0..groups)
        .map(|k| {
            let hi = if k + 1 == groups { n } else { (k + 1) * size };
            mean_se(&x[k * size..hi])
        })
        .collect();
    let wsum: f64 = parts.iter().map(|(_, e)| 1.0 / (e * e)).sum();
    let m = parts.iter().map(|(v, e)| v / (e * e)).sum::<f64>() / wsum;
    let chi2: f64 = parts.iter().map(|(v, e)| ((v - m) / e).powi(2)).sum();
    let p = chi2_upper_p(chi2, (groups - 1) as f64);
    checks.pass_if(
        p > ALPHA,
        "statistics",
        "between-batch χ²: four groups of consecutive batches agree",
        format!(
            "χ² = {chi2:.2} for {} dof, p = {p:.3} (fail below {ALPHA})",
            groups - 1
        ),
        &[("chi2", chi2), ("dof", (groups - 1) as f64), ("p", p)],
    );
}

/// The most extreme batch against a Bonferroni Student-t bound.
fn outlier_check(x: &[f64], checks: &mut Checks) {
    let n = x.len();
    // Externally studentised batch values, t_{n-2}; Bonferroni over n.
    let mut worst = (0usize, 0.0f64);
    for b in 0..n {
        let rest: Vec<f64> = x
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != b)
            .map(|(_, v)| *v)
            .collect();
        let (mr, se_r) = mean_se(&rest);
        let sd = se_r * ((n - 1) as f64).sqrt();
        let t = (x[b] - mr) / (sd * (1.0 + 1.0 / (n - 1) as f64).sqrt());
        if t.abs() > worst.1.abs() {
            worst = (b, t);
        }
    }
    let bound = student_t_quantile((n - 2) as f64, ALPHA / (2.0 * n as f64));
    checks.pass_if(
        worst.1.abs() <= bound,
        "statistics",
        "no outlying batch",
        format!(
            "most extreme batch {}: t = {:+.2} against the Bonferroni bound {bound:.2} (t with {} dof, {ALPHA} over {n} batches)",
            worst.0,
            worst.1,
            n - 2
        ),
        &[("t", worst.1), ("bound", bound)],
    );
}

/// The batch error against the errors of blocks of 2 and 4 batches (F bounds).
fn block_error_checks(x: &[f64], checks: &mut Checks) {
    let n = x.len();
    // Blocks of k consecutive batches: (SE_k / SE_1)² ~ F(n/k − 1, n − 1) for independent batches.
    let se1 = mean_se(x).1;
    for k in [2usize, 4] {
        let nb = n / k;
        if nb < 3 {
            continue;
        }
        let blocks: Vec<f64> = (0..nb)
            .map(|i| x[i * k..(i + 1) * k].iter().sum::<f64>() / k as f64)
            .collect();
        let sek = mean_se(&blocks).1;
        let ratio2 = (sek / se1).powi(2);
        let (lo, hi) = (
            f_quantile((nb - 1) as f64, (n - 1) as f64, ALPHA / 2.0),
            f_quantile((nb - 1) as f64, (n - 1) as f64, 1.0 - ALPHA / 2.0),
        );
        checks.pass_if(
            ratio2 >= lo && ratio2 <= hi,
            "statistics",
            &format!("batch error against blocks of {k} batches"),
            format!(
                "error from {nb} blocks of {k} / error from {n} batches = {:.3} (independent batches: its square within [{lo:.3}, {hi:.3}], F({}, {}) at {ALPHA})",
                ratio2.sqrt(),
                nb - 1,
                n - 1
            ),
            &[("ratio", ratio2.sqrt())],
        );
    }
}

/// The local slope (MSD(t_{k+1}) − MSD(t_k)) / (4 (t_{k+1} − t_k)) per batch, mean ± error, at the
/// interval midpoints.
fn local_slopes(r: &DiffusionReport) -> Vec<(f64, f64, f64)> {
    let t = &r.msd_times;
    (0..t.len().saturating_sub(1))
        .map(|k| {
            let v: Vec<f64> = r
                .batch_msd
                .iter()
                .map(|m| (m[k + 1] - m[k]) / (4.0 * (t[k + 1] - t[k])))
                .collect();
            let (m, e) = mean_se(&v);
            (0.5 * (t[k] + t[k + 1]), m, e)
        })
        .collect()
}

/// A histogram of the batch values, as a step outline, with the mean marked.
fn histogram(x: &[f64], mean: f64, stem: &Path) -> Result<(), Error> {
    let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let bins = ((x.len() as f64).sqrt().ceil() as usize).max(4);
    let width = ((hi - lo) / bins as f64).max(f64::MIN_POSITIVE);
    let mut counts = vec![0u32; bins];
    for v in x {
        counts[(((v - lo) / width) as usize).min(bins - 1)] += 1;
    }
    let mut outline = vec![(lo, 0.0, 0.0)];
    for (i, c) in counts.iter().enumerate() {
        let a = lo + i as f64 * width;
        outline.push((a, *c as f64, 0.0));
        outline.push((a + width, *c as f64, 0.0));
    }
    outline.push((lo + bins as f64 * width, 0.0, 0.0));
    let top = *counts.iter().max().unwrap_or(&1) as f64;
    plot(
        stem,
        &PlotSpec {
            title: "D of each batch",
            x_label: "D",
            y_label: "batches",
            log_x: false,
            log_y: false,
        },
        &[
            Series {
                label: format!("{} batches", x.len()),
                points: outline,
                notes: Vec::new(),
                line: true,
            },
            Series {
                label: "mean".into(),
                points: vec![(mean, 0.0, 0.0), (mean, top, 0.0)],
                notes: Vec::new(),
                line: true,
            },
        ],
    )
}

/// The checks of a `sweep` result (see the module documentation), in order.
fn sweep_checks(value: &serde_json::Value, ctx: Ctx<'_>, checks: &mut Checks) -> Result<(), Error> {
    let bad_file = |e: String| Error::Invalid(format!("not a sweep result: {e}"));
    let cfg: SweepConfig =
        serde_json::from_value(value["config"].clone()).map_err(|e| bad_file(e.to_string()))?;
    cfg.validate()?;
    let rows = value["rows"]
        .as_array()
        .ok_or_else(|| bad_file("no rows".into()))?;
    let grid = cfg.points()?;
    sweep_record_check(&cfg, rows, &grid, checks)?;
    sweep_runs_check(rows, checks);
    sweep_rerun_check(&cfg, rows, &grid, ctx, checks)
}

/// A number of a sweep row (NaN when absent).
fn row_num(r: &serde_json::Value, k: &str) -> f64 {
    r[k].as_f64().unwrap_or(f64::NAN)
}

/// The sweep's record: the grid, each D the mean of its runs, the closed forms and the residuals
/// from the weighted line recomputed to the same bits.
fn sweep_record_check(
    cfg: &SweepConfig,
    rows: &[serde_json::Value],
    grid: &[f64],
    checks: &mut Checks,
) -> Result<(), Error> {
    let mut bad = Vec::new();
    if rows.len() != grid.len() {
        bad.push(format!("{} rows for {} points", rows.len(), grid.len()));
    }
    let (mut ws, mut ds, mut es) = (Vec::new(), Vec::new(), Vec::new());
    for (i, row) in rows.iter().enumerate() {
        let w = row_num(row, "w");
        let runs: Vec<f64> = row["run_D"]
            .as_array()
            .map(|a| a.iter().map(|v| v.as_f64().unwrap_or(f64::NAN)).collect())
            .unwrap_or_default();
        let mean = runs.iter().sum::<f64>() / runs.len() as f64;
        let g = Geometry::new(w)?;
        if grid.get(i).map(|x| x.to_bits()) != Some(w.to_bits()) {
            bad.push(format!("row {i}: w = {w} is not the grid's"));
        }
        if runs.len() != cfg.runs as usize || mean.to_bits() != row_num(row, "D").to_bits() {
            bad.push(format!(
                "row {i} (w = {w}): D = {} is not the mean of its runs ({mean})",
                row_num(row, "D")
            ));
        }
        if g.d_mz().to_bits() != row_num(row, "D_MZ").to_bits()
            || g.d_bo().to_bits() != row_num(row, "D_Bo").to_bits()
        {
            bad.push(format!("row {i}: D_MZ or D_Bo is not the closed form"));
        }
        ws.push(w);
        ds.push(row_num(row, "D"));
        es.push(row_num(row, "D_err"));
    }
    if bad.is_empty() {
        let lin = weighted_line_fit(&ws, &ds, &es)?;
        for (i, row) in rows.iter().enumerate() {
            if (ds[i] - lin.at(ws[i])).to_bits() != row_num(row, "residual").to_bits() {
                bad.push(format!(
                    "row {i}: the residual is not D minus the weighted line"
                ));
            }
        }
    }
    checks.pass_if(
        bad.is_empty(),
        "reproducibility",
        "each D is the mean of its runs; closed forms and residuals recomputed",
        if bad.is_empty() {
            format!("{} points × {} runs: the same bits", rows.len(), cfg.runs)
        } else {
            bad.iter().take(3).cloned().collect::<Vec<_>>().join("; ")
        },
        &[("points", rows.len() as f64)],
    );
    Ok(())
}

/// The runs of each point agree within their errors (the recorded F tests, Bonferroni over the
/// points).
fn sweep_runs_check(rows: &[serde_json::Value], checks: &mut Checks) {
    let ps: Vec<f64> = rows
        .iter()
        .map(|r| row_num(r, "runs_p_value"))
        .filter(|p| p.is_finite())
        .collect();
    if ps.is_empty() {
        checks.add(
            "statistics",
            "runs agree within their errors",
            Verdict::Skip,
            "one run per point: no spread to test".into(),
            &[],
        );
    } else {
        let pmin = ps.iter().copied().fold(1.0, f64::min);
        checks.pass_if(
            pmin * ps.len() as f64 > ALPHA,
            "statistics",
            "runs agree within their errors at every point",
            format!("smallest F-test p-value {pmin:.2e} over {} points (Bonferroni: fail below {ALPHA}/{})", ps.len(), ps.len()),
            &[("p_min", pmin)],
        );
    }
}

/// One run of one point, chosen by the digest, re-run from its seed.
fn sweep_rerun_check(
    cfg: &SweepConfig,
    rows: &[serde_json::Value],
    grid: &[f64],
    ctx: Ctx<'_>,
    checks: &mut Checks,
) -> Result<(), Error> {
    let pick = batch_from_digest(ctx.sha, cfg.steps * cfg.runs);
    let (i, r) = (pick / cfg.runs, pick % cfg.runs);
    let budget = if ctx.opts.quick { 4e9 } else { f64::INFINITY };
    if cfg.collisions as f64 > budget {
        checks.add(
            "reproducibility",
            "one run re-run from its seed gives the recorded bits",
            Verdict::Skip,
            format!("a run has {} collisions, more than the quick report re-runs ({budget:e}): run without --quick", cfg.collisions),
            &[],
        );
        return Ok(());
    }
    (ctx.planned)(cfg.collisions);
    let c = cfg.run_config(i, grid[i as usize], r);
    let again =
        crate::estimators::diffusion::run(&c, &rerun_options(ctx.opts.threads, ctx.progress))?;
    let rec = rows
        .get(i as usize)
        .and_then(|row| row["run_D"].get(r as usize))
        .and_then(|v| v.as_f64());
    checks.pass_if(
        rec.map(f64::to_bits) == Some(again.D.to_bits()),
        "reproducibility",
        "one run re-run from its seed gives the recorded bits",
        format!(
            "point {i} (w = {}), run {r}: recorded D = {rec:?}, re-run {}",
            grid[i as usize], again.D
        ),
        &[("point", i as f64), ("run", r as f64)],
    );
    Ok(())
}

impl PublicationReport {
    /// The report as Markdown.
    pub fn markdown(&self) -> String {
        let p = &self.provenance;
        let mut s = format!(
            "# Audit of {}: **{}**\n\n## Provenance\n\n| | |\n|---|---|\n",
            p.result_file, self.verdict
        );
        let mut row = |k: &str, v: String| s += &format!("| {k} | {} |\n", v.replace('|', "\\|"));
        row("result file SHA-256", format!("`{}`", p.sha256));
        row("kind", p.kind.clone());
        if let Some(m) = &p.recorded {
            row("recorded by", format!("lorentz {}", m.version));
            row(
                "engine",
                format!(
                    "{}{}",
                    m.engine,
                    m.simd.as_ref().map_or(String::new(), |s| format!(" ({s})"))
                ),
            );
            row("precision", m.precision.clone());
            row("seed", m.seed.map_or("-".into(), |x| x.to_string()));
            row("threads", m.threads.map_or("-".into(), |x| x.to_string()));
            row("command line", format!("`{}`", m.command_line.join(" ")));
        }
        row(
            "report by",
            format!("lorentz {} (git {}), {}", p.version, p.git_commit, p.rustc),
        );
        row("CPU", p.cpu.clone());
        row("date (UTC)", p.date_utc.clone());
        row(
            "settings",
            format!(
                "{}, {:.1} s",
                if self.quick { "quick" } else { "full" },
                self.seconds
            ),
        );
        s += "\n## Checks\n\n| | group | check | numbers |\n|---|---|---|---|\n";
        for c in &self.checks {
            s += &format!(
                "| **{}** | {} | {} | {} |\n",
                c.verdict,
                c.group,
                c.name,
                c.detail.replace('|', "\\|")
            );
        }
        for f in &self.figures {
            s += &format!("\n![{f}]({f}.png)\n");
        }
        s
    }

    /// The report as one self-contained HTML page (figures inlined as SVG from `dir`).
    pub fn html(&self, dir: &Path) -> String {
        let esc = crate::report::figures::html_escape;
        let p = &self.provenance;
        let mut s = format!(
            "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>Audit of {}</title>\n<style>body{{font-family:sans-serif;max-width:70em;margin:2em auto}}table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:.3em .6em;vertical-align:top}}.PASS{{color:#060;font-weight:bold}}.FAIL{{color:#b00;font-weight:bold}}.SKIP{{color:#777;font-weight:bold}}</style></head><body>\n<h1>Audit of {}: <span class=\"{}\">{}</span></h1>\n<h2>Provenance</h2><table>\n",
            esc(&p.result_file), esc(&p.result_file), self.verdict, self.verdict
        );
        let mut row =
            |k: &str, v: &str| s += &format!("<tr><th>{k}</th><td>{}</td></tr>\n", esc(v));
        row("result file SHA-256", &p.sha256);
        row("kind", &p.kind);
        if let Some(m) = &p.recorded {
            row("recorded by", &format!("lorentz {}", m.version));
            row(
                "engine",
                &format!(
                    "{}{}",
                    m.engine,
                    m.simd.as_ref().map_or(String::new(), |s| format!(" ({s})"))
                ),
            );
            row("precision", &m.precision);
            row("seed", &m.seed.map_or("-".into(), |x| x.to_string()));
            row("command line", &m.command_line.join(" "));
        }
        row(
            "report by",
            &format!("lorentz {} (git {}), {}", p.version, p.git_commit, p.rustc),
        );
        row("CPU", &p.cpu);
        row("date (UTC)", &p.date_utc);
        s += "</table>\n<h2>Checks</h2><table><tr><th></th><th>group</th><th>check</th><th>numbers</th></tr>\n";
        for c in &self.checks {
            s += &format!(
                "<tr><td class=\"{}\">{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                c.verdict,
                c.verdict,
                esc(&c.group),
                esc(&c.name),
                esc(&c.detail)
            );
        }
        s += "</table>\n";
        for f in &self.figures {
            let svg = std::fs::read_to_string(dir.join(format!("{f}.svg"))).unwrap_or_default();
            let svg = svg.trim_start_matches(|c| c != '<');
            let svg = svg
                .strip_prefix("<?xml")
                .map_or(svg, |r| r.split_once("?>").map_or(r, |x| x.1));
            s += &format!("<h2>{}</h2>\n{}\n", esc(f), svg);
        }
        s += "</body></html>\n";
        s
    }

    /// Writes `report.md`, `report.html` and `report.json` into `dir`.
    pub fn write(&self, dir: &Path) -> Result<(), Error> {
        crate::files::write(dir.join("report.md"), self.markdown())?;
        crate::files::write(dir.join("report.html"), self.html(dir))?;
        crate::files::write(
            dir.join("report.json"),
            serde_json::to_string_pretty(self).map_err(Error::encode)?,
        )?;
        Ok(())
    }
}

/// How the audit re-runs a computation: the default engine on `threads` threads.
fn rerun_options<'a>(threads: usize, progress: &'a (dyn Fn(u64) + Sync)) -> RunOptions<'a> {
    RunOptions {
        threads,
        progress,
        ..RunOptions::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_from_days() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(20_780), (2026, 11, 23));
    }

    #[test]
    fn sha256_of_abc() {
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
