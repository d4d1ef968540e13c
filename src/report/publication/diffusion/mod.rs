//! The audit of a `diffusion` result (see the module documentation of
//! [`super`]): the record, batch statistics, exact identities, and batches re-run from the
//! recorded configuration with a shadow audit, precision independence and shadowing.

use std::path::Path;

use super::file::ResultFile;
use super::statistics::batch_statistics;
use super::{Checks, Ctx, SIGMAS, Sampled, Verdict, pick};
use crate::Error;
use crate::engine::Engine;
use crate::engine::options::AuditSpec;
use crate::engine::parallel::share;
use crate::estimators::diffusion::{
    BatchResult, DiffusionConfig, DiffusionReport, batch_d, rerun_batches,
};
use crate::numbers::precision::Precision;
use crate::report::figures::{Band, PlotSpec, Series, plot};
use crate::scenes::triangular::geometry::Geometry;
use crate::statistics::{comparison, mean_se, normal_sigma_equivalent_t};

mod figures;
mod verification;

use figures::*;
use verification::*;

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

/// The file as a diffusion result whose recorded configuration the command line would accept.
pub(super) fn parse(file: &ResultFile, path: &Path) -> Result<DiffusionReport, Error> {
    let r: DiffusionReport = file.parse(path)?;
    let Some(cfg) = &r.config else {
        return Err(Error::malformed(
            path,
            "no `config`: a diffusion result written before results carried their configuration \
             cannot be audited; run the diffusion again",
        ));
    };
    cfg.validate().map_err(|e| refused_config(path, e))?;
    Ok(r)
}

/// A recorded configuration that command-line input with the same values would be refused for.
pub(super) fn refused_config(path: &Path, e: Error) -> Error {
    Error::malformed(
        path,
        format!(
            "the recorded configuration is refused, as the same command-line input would be: {e}"
        ),
    )
}

/// The recorded configuration (present: [`parse`] checked it).
fn config(r: &DiffusionReport) -> Result<&DiffusionConfig, Error> {
    r.config
        .as_ref()
        .ok_or_else(|| Error::Failed("a diffusion result without a configuration".into()))
}

/// The re-runs, in the order [`checks`] takes them: the batches, the two precision runs, the
/// shadowed segments.
pub(super) fn reruns(r: &DiffusionReport, quick: bool, draw: u64) -> Result<Vec<u64>, Error> {
    let cfg = config(r)?;
    let plan = RerunPlan::new(cfg, quick, draw)?;
    Ok(vec![
        plan.collisions,
        2 * plan.short,
        (shadowed_batches(cfg, &plan.batches, quick).len() * SHADOW_COLLISIONS) as u64,
    ])
}

/// The checks of a `diffusion` result (see the module documentation), in order.
pub(super) fn checks(
    r: &DiffusionReport,
    ctx: &Ctx<'_>,
    checks: &mut Checks,
    figures: &mut Vec<String>,
) -> Result<(), Error> {
    let cfg = config(r)?;
    let g = Geometry::new(cfg.gap()?)?;
    let shape = shape_problems(r, cfg, g.hop_time());
    if !shape.is_empty() {
        checks.pass_if(
            false,
            "reproducibility",
            "the record has the shape of its configuration",
            format!("{}; nothing else is checked", shape.join("; ")),
            &[],
        );
        return Ok(());
    }
    record_check(r, cfg, checks);
    batch_statistics(&r.batch_D, checks);
    fit_window_check(r, checks);
    green_kubo_check(r, checks);
    diffusion_figures(r, ctx.out, figures)?;
    identity_checks(r, &g, checks);
    reruns_checks(r, cfg, &g, ctx, checks)
}

/// The checks that re-run the configuration: the batches with the shadow audit, precision
/// independence, shadowing — each within the budget.
fn reruns_checks(
    r: &DiffusionReport,
    cfg: &DiffusionConfig,
    g: &Geometry<f64>,
    ctx: &Ctx<'_>,
    checks: &mut Checks,
) -> Result<(), Error> {
    let plan = RerunPlan::new(cfg, ctx.quick, ctx.draw)?;
    let name = if ctx.quick {
        "one batch re-run from its seed gives the recorded bits"
    } else {
        "every batch re-run from its seed gives the recorded bits"
    };
    match ctx.take() {
        Ok(_) => {
            let audit = if cfg.precision == Precision::F64 {
                Some(AuditSpec::new(plan.rate, ctx.bits)?)
            } else {
                None
            };
            let again = rerun_batches(
                cfg,
                &plan.batches,
                plan.engine,
                ctx.threads,
                audit,
                ctx.progress,
            )?;
            rerun_batches_check(r, cfg, g.hop_time(), &plan, &again, ctx, checks);
            shadow_audit_check(&again, ctx, checks);
        }
        Err(why) => {
            checks.skip("reproducibility", name, why.clone());
            checks.skip(
                "verification",
                "shadow audit of events of the same trajectories",
                why,
            );
        }
    }
    match ctx.take() {
        Ok(_) => precision_independence(cfg, r, plan.short, ctx, checks)?,
        Err(why) => checks.skip("verification", "precision independence", why),
    }
    match ctx.take() {
        Ok(_) => shadowing_certificate(cfg, &plan.batches, ctx, checks)?,
        Err(why) => checks.skip(
            "verification",
            "shadowing: a true orbit within δ of the computed one",
            why,
        ),
    }
    Ok(())
}

/// What in the record does not have the shape its configuration gives: the gap and windows, the
/// number of batch values, the lag times.
fn shape_problems(r: &DiffusionReport, cfg: &DiffusionConfig, tau: f64) -> Vec<String> {
    let mut bad = Vec::new();
    let batches = cfg.batches as usize;
    if cfg.gap().ok().map(f64::to_bits) != Some(r.w.to_bits())
        || r.window != cfg.window
        || r.check_window != cfg.check_window
    {
        bad.push("w or the fit windows differ from the configuration's".to_string());
    }
    for (name, len) in [
        ("batch_D", r.batch_D.len()),
        ("batch_D_check", r.batch_D_check.len()),
        ("batch_msd", r.batch_msd.len()),
    ] {
        if len != batches {
            bad.push(format!("{len} values of {name} for {batches} batches"));
        }
    }
    let times: Vec<f64> = cfg.lags().iter().map(|&l| l as f64 * tau).collect();
    let same = |a: &[f64]| a.len() == times.len();
    if times
        .iter()
        .map(|t| t.to_bits())
        .ne(r.msd_times.iter().map(|t| t.to_bits()))
        || !same(&r.msd_over_4t)
        || !same(&r.msd_over_4t_err)
        || !r.batch_msd.iter().all(|m| same(m))
    {
        bad.push(format!(
            "the MSD lag times or the lengths of the MSD series are not the {} lags of the fit windows",
            times.len()
        ));
    }
    bad
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
    /// One batch picked by the audit's `draw` with `quick`, every batch otherwise.
    fn new(cfg: &DiffusionConfig, quick: bool, draw: u64) -> Result<Self, Error> {
        let batches: Vec<u32> = if quick {
            // Below `batches`, so it fits.
            vec![pick(draw, u64::from(cfg.batches)) as u32]
        } else {
            (0..cfg.batches).collect()
        };
        let collisions: u64 = if quick {
            batches
                .iter()
                .map(|&b| share(cfg.collisions, cfg.batches, b))
                .sum()
        } else {
            cfg.collisions
        };
        let events = if quick {
            AUDIT_EVENTS_QUICK
        } else {
            AUDIT_EVENTS_FULL
        };
        let rate = (events / collisions.max(1) as f64).clamp(1e-9, 1.0);
        let min = precision_min_collisions(cfg)?;
        let len = if quick {
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

/// The batches whose trajectories are shadowed: the re-run ones first, at most two with `quick`
/// and eight otherwise.
fn shadowed_batches(cfg: &DiffusionConfig, rerun: &[u32], quick: bool) -> Vec<u32> {
    let want = if quick { 2 } else { 8 };
    let mut batches: Vec<u32> = rerun.iter().copied().take(want).collect();
    let mut next = rerun.first().copied().unwrap_or(0);
    while batches.len() < want.min(cfg.batches as usize) {
        next = (next + 1) % cfg.batches;
        if !batches.contains(&next) {
            batches.push(next);
        }
    }
    batches
}

/// The record check: D, its errors, D_check and MSD/(4t) recomputed from the per-batch values
/// give the recorded bits.
fn record_check(r: &DiffusionReport, cfg: &DiffusionConfig, checks: &mut Checks) {
    let n = r.batch_D.len();
    let ((d, de), (dc, dce)) = r.d_from_batches();
    let mut bad = Vec::new();
    bad.extend(super::meta_problems(
        &r.meta,
        Some(cfg.seed),
        Some(u64::from(cfg.batches)),
        &cfg.precision.to_string(),
    ));
    if r.collisions != cfg.collisions {
        bad.push(format!(
            "collisions: recorded {}, configured {}",
            r.collisions, cfg.collisions
        ));
    }
    let (diff, diff_err) = match comparison::paired(&r.batch_D, &r.batch_D_check) {
        Ok(c) => (c.difference, c.err),
        Err(e) => {
            bad.push(format!("D − D_check: {e}"));
            (f64::NAN, f64::NAN)
        }
    };
    for (name, rec, again) in [
        ("D", r.D, d),
        ("D_err", r.D_err, de),
        ("D_check", r.D_check, dc),
        ("D_check_err", r.D_check_err, dce),
        ("D_minus_D_check", r.D_minus_D_check, diff),
        ("D_minus_D_check_err", r.D_minus_D_check_err, diff_err),
        ("w", r.w, cfg.gap().unwrap_or(f64::NAN)),
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
    let Ok(c) = comparison::paired(&r.batch_D, &r.batch_D_check) else {
        return checks.pass_if(
            false,
            "statistics",
            "fit window: D and D_check agree",
            format!(
                "{n} values of D against {} of D_check: no paired comparison",
                r.batch_D_check.len()
            ),
            &[],
        );
    };
    checks.pass_if(
        c.agrees(),
        "statistics",
        "fit window: D and D_check agree",
        format!(
            "D[{}τ, {}τ] − D[{}τ, {}τ] = {:.3e} ± {:.1e} ({:+.1}σ; paired over batches; bound {:.2}σ, t with {} dof)",
            r.window.lo, r.window.hi, r.check_window.lo, r.check_window.hi, c.difference, c.err, c.z, c.bound, c.dof
        ),
        &[("difference", c.difference), ("difference_err", c.err)],
    );
}

/// A run on the logarithmic grid (`--msd-grid log`): D by the running Green–Kubo integral against
/// the Einstein D, paired over the batches (its recorded difference and error).
fn green_kubo_check(r: &DiffusionReport, checks: &mut Checks) {
    let g = &r.green_kubo;
    let (Some(d), Some(e)) = (g.D_minus_D_green_kubo, g.D_minus_D_green_kubo_err) else {
        return;
    };
    let c = comparison::of(d, e, comparison::batch_dof(r.batch_D.len()));
    checks.pass_if(
        c.agrees(),
        "statistics",
        "Green–Kubo: D by the integral of the velocity autocorrelation agrees with D",
        format!(
            "D − D_green_kubo = {:.3e} ± {:.1e} ({:+.1}σ; paired over batches; bound {:.2}σ, t with {} dof)",
            c.difference, c.err, c.z, c.bound, c.dof
        ),
        &[("difference", d), ("difference_err", e)],
    );
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
        // A recorded closed form that is not the closed form FAILs however few the batches.
        let dof = if same {
            (n.max(2) - 1) as f64
        } else {
            f64::INFINITY
        };
        checks.judge(
            dof,
            z.abs() <= bound_n && same,
            ("identities", name),
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

/// The re-run batches give the recorded D and D_check of each batch to the last bit.
fn rerun_batches_check(
    r: &DiffusionReport,
    cfg: &DiffusionConfig,
    tau: f64,
    plan: &RerunPlan,
    again: &[BatchResult],
    ctx: &Ctx<'_>,
    checks: &mut Checks,
) {
    let rerun = &plan.batches;
    ctx.sampled.set(Sampled::new(
        "batches",
        rerun.len() as u64,
        u64::from(cfg.batches),
    ));
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
        if ctx.quick { "one batch re-run from its seed gives the recorded bits" } else { "every batch re-run from its seed gives the recorded bits" },
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
        &[
            ("batches_rerun", rerun.len() as f64),
            ("first_batch_rerun", rerun.first().map_or(-1.0, |&b| f64::from(b))),
        ],
    );
}
