//! The audit of a survival result on an open table (`lorentz escape --repeller` or `--open`):
//! the record recomputed from its batches, the batches' statistics and the window check, the
//! escape rate, Lyapunov exponent and KS entropy against the certified cycle expansion (the
//! three-disk repeller: an independent estimator), and the configuration re-run (one batch,
//! drawn at random, with `quick`).

use std::path::Path;

use super::diffusion::refused_config;
use super::file::ResultFile;
use super::same_bits::rerun_check;
use super::statistics::batch_statistics;
use super::{Checks, Ctx, SIGMAS, Verdict};
use crate::Error;
use crate::engine::options::RunOptions;
use crate::engine::parallel::share;
use crate::estimators::escape::survival::{self, BATCHES, START_DENSITY, SurvivalReport};
use crate::statistics::{mean_se, normal_sigma_equivalent_t};
use crate::verification::cycles::repeller::{self, RepellerConfig};

/// The file as a survival result whose configuration the command line would accept.
pub(super) fn parse(file: &ResultFile, path: &Path) -> Result<SurvivalReport, Error> {
    let r: SurvivalReport = file.parse(path)?;
    r.config.validate().map_err(|e| refused_config(path, e))?;
    Ok(r)
}

/// The re-run's collisions, expected from the configuration's own pilot (never the file's
/// count): the whole run, or one batch of [`BATCHES`] with `quick`.
pub(super) fn reruns(r: &SurvivalReport, quick: bool) -> Result<Vec<u64>, Error> {
    let all = survival::expected_collisions(&r.config, &RunOptions::default())?;
    Ok(vec![if quick {
        all.div_ceil(u64::from(BATCHES))
    } else {
        all
    }])
}

/// The checks: the record, the batches, the window, the cycles, the re-run.
pub(super) fn checks(r: &SurvivalReport, ctx: &Ctx<'_>, checks: &mut Checks) -> Result<(), Error> {
    let cfg = &r.config;
    let mut bad = super::meta_problems(&r.meta, Some(cfg.seed), Some(u64::from(BATCHES)), "f64");
    bad.extend(record_problems(r)?);
    super::record_check(bad, checks);
    batch_statistics(&r.batch_gamma, checks);
    window_check(r, checks);
    cycle_checks(r, checks)?;
    if ctx.quick {
        let recorded = [("γ", &r.batch_gamma[..]), ("λ", &r.batch_lyapunov[..])];
        let particles = share(cfg.particles, BATCHES, 0);
        return ctx.one_batch_rerun(checks, (BATCHES, Some(particles)), &recorded, |b, o| {
            let e = survival::rerun_batch(cfg, b, o)?;
            Ok(vec![e.gamma, e.lyapunov])
        });
    }
    let what = format!(
        "{} particles in {BATCHES} batches (seed {})",
        cfg.particles, cfg.seed
    );
    rerun_check(r, cfg.particles, &what, ctx, checks, |o| {
        survival::run(cfg, o)
    })
}

/// What of the record differs from what its configuration and its own batch values give: the
/// table's name, the batch count, every error (the batches' spread), h_KS = λ − γ, the window
/// check and the rows of the windows at n₀ and n₀ + 1, all to the bit.
fn record_problems(r: &SurvivalReport) -> Result<Vec<String>, Error> {
    let mut bad = Vec::new();
    let n0 = r.config.window as usize;
    if r.table != r.config.open()?.title() || r.start_density != START_DENSITY {
        bad.push("the table's name or the start density is not the configuration's".into());
    }
    let b = BATCHES as usize;
    if r.batches != BATCHES || r.batch_gamma.len() != b || r.batch_lyapunov.len() != b {
        bad.push(format!("not {BATCHES} batches with one γ and one λ each"));
        return Ok(bad);
    }
    let h: Vec<f64> = (r.batch_gamma.iter().zip(&r.batch_lyapunov))
        .map(|(g, l)| l - g)
        .collect();
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
    let errors = [
        ("gamma_err", r.gamma_err, mean_se(&r.batch_gamma).1),
        ("lyapunov_err", r.lyapunov_err, mean_se(&r.batch_lyapunov).1),
        ("entropy_err", r.entropy_err, mean_se(&h).1),
        ("entropy", r.entropy, r.lyapunov - r.gamma),
        (
            "window_check_sigma",
            r.window_check_sigma,
            (r.gamma_late - r.gamma) / r.gamma_err.hypot(r.gamma_late_err),
        ),
    ];
    for (name, recorded, again) in errors {
        if !same(recorded, again) {
            bad.push(format!(
                "{name} {recorded:e} is not {again:e} from the batches"
            ));
        }
    }
    let rows = (r.windows.get(n0.wrapping_sub(1)), r.windows.get(n0));
    let rows_agree = match rows {
        (Some(a), Some(l)) => {
            r.windows.len() == n0 + 1
                && same(a.gamma, r.gamma)
                && same(a.gamma_err, r.gamma_err)
                && same(a.lyapunov, r.lyapunov)
                && same(a.lyapunov_err, r.lyapunov_err)
                && same(l.gamma, r.gamma_late)
                && same(l.gamma_err, r.gamma_late_err)
        }
        _ => false,
    };
    if !rows_agree {
        bad.push(format!(
            "the windows are not n = 1 … {} with the summary's rows",
            n0 + 1
        ));
    }
    let falls = r.survival.windows(2).all(|w| w[1] <= w[0]);
    if r.survival.len() != n0 + 3 || r.survival.first() != Some(&1.0) || !falls {
        bad.push("the survival is not 1 falling over collisions 0 … n₀ + 2".into());
    }
    Ok(bad)
}

/// γ from the window one collision later agrees with γ (the transient has died by n₀): the
/// recorded difference in combined σ within the Student-t bound of the batches.
fn window_check(r: &SurvivalReport, checks: &mut Checks) {
    let dof = f64::from(BATCHES) - 1.0;
    let bound = normal_sigma_equivalent_t(dof, SIGMAS);
    let z = r.window_check_sigma;
    checks.judge(
        dof,
        z.abs() <= bound,
        (
            "statistics",
            "the window is late enough: γ one collision later agrees",
        ),
        format!(
            "γ(n₀ = {}) = {} ± {:.1e}, γ(n₀ + 1) = {} ± {:.1e}: {z:+.2}σ (bound {bound:.2}σ; \
             a larger difference is the transient: start the window later)",
            r.config.window, r.gamma, r.gamma_err, r.gamma_late, r.gamma_late_err
        ),
        &[("sigma", z), ("bound", bound)],
    );
}

/// γ, λ and h_KS against the cycle expansion of the same repeller (certified cycles up to the
/// default length, its truncation error added in quadrature), each within the Student-t bound;
/// N/A on an open table given as data (no cycle expansion is computed for it).
fn cycle_checks(r: &SurvivalReport, checks: &mut Checks) -> Result<(), Error> {
    let name = "γ, λ and h_KS agree with the certified cycle expansion";
    let Some(spec) = &r.config.open()?.repeller else {
        checks.add(
            "identities",
            name,
            Verdict::NotApplicable,
            "an open table given as data: cycle expansions are computed for the three-disk \
             repeller only"
                .into(),
            &[],
        );
        return Ok(());
    };
    let cfg = RepellerConfig::new(spec.side.text(), spec.radius.text());
    if let Err(e) = cfg.validate() {
        checks.skip("identities", name, format!("no cycle expansion here: {e}"));
        return Ok(());
    }
    let cycles = repeller::run(&cfg, &RunOptions::default())?;
    let Some(t) = cycles.spectral_determinant.last() else {
        checks.skip("identities", name, "the cycle expansion has no row".into());
        return Ok(());
    };
    let dof = f64::from(BATCHES) - 1.0;
    let cases = [
        (
            "γ",
            r.gamma,
            r.gamma_err,
            t.escape_rate,
            t.escape_rate_error,
        ),
        (
            "λ",
            r.lyapunov,
            r.lyapunov_err,
            t.lyapunov,
            t.lyapunov_error,
        ),
        ("h_KS", r.entropy, r.entropy_err, t.entropy, t.entropy_error),
    ];
    for (what, v, e, c, ce) in cases {
        let err = e.hypot(if ce.is_finite() { ce } else { 0.0 });
        checks.within_t(
            dof,
            (
                "identities",
                &format!("{what} by survival = {what} by cycles"),
            ),
            ((v, err), c),
            format!(
                "cycles to N = {} (truncation error {ce:.1e}); the error combines both: ",
                t.max_length
            ),
        );
    }
    Ok(())
}
