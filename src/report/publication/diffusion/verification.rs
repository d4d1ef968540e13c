//! The verification checks of a diffusion audit: the shadow audit of the re-run events, true shadowing of the run's own trajectories, and precision independence (f64 against MPFR from the same starts, compared paired).

use super::*;

/// The shadow audit of the re-run batches' events: none outside the error model.
pub(super) fn shadow_audit_check(again: &[BatchResult], ctx: &Ctx<'_>, checks: &mut Checks) {
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
                ctx.bits,
                a.outside,
                a.ambiguous,
                a.time_error_over_bound.quantile(0.5)
            ),
            &[("audited", a.audited as f64), ("outside", a.outside as f64)],
        ),
        None => checks.add(
            "verification",
            "shadow audit of events of the same trajectories",
            Verdict::NotApplicable,
            "the run is not f64: its events are MPFR already".into(),
            &[],
        ),
    }
}

/// Collisions per shadowed segment: long enough that the f64 orbit has left any orbit started
/// from its rounded start (the divergence horizon is ~35 collisions), short enough for seconds.
pub(super) const SHADOW_COLLISIONS: usize = 1000;

/// The true-orbit certificate ([`crate::verification::shadowing`]) for the first
/// [`SHADOW_COLLISIONS`] collisions of some of the run's own trajectories: those of the re-run
/// batches (at most two with `quick`, eight otherwise).
pub(super) fn shadowing_certificate(
    cfg: &DiffusionConfig,
    rerun: &[u32],
    ctx: &Ctx<'_>,
    checks: &mut Checks,
) -> Result<(), Error> {
    use crate::verification::shadowing::{f64_segment, shadow_pseudo_orbit};
    let scene = crate::scenes::triangular::TriangularScene::new(cfg.gap()?)?;
    let batches = shadowed_batches(cfg, rerun, ctx.quick);
    let bits = ctx.bits;
    let results = crate::engine::parallel::par_batches(ctx.threads, batches.len() as u32, |k| {
        let start = crate::estimators::diffusion::batch_start(cfg, batches[k as usize])?;
        let orbit = f64_segment(&scene, &start, SHADOW_COLLISIONS, bits)?;
        shadow_pseudo_orbit(&scene, &orbit, bits)
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
                ctx.bits
            )
        } else {
            format!("{} of {} segments not certified: {}", failures.len(), results.len(), failures.join("; "))
        },
        &[("delta_max", delta), ("certified", certified as f64), ("segments", results.len() as f64)],
    );
    Ok(())
}

/// Least collisions of a [`PRECISION_BATCHES`]-batch run at `cfg`'s w and windows.
pub(super) fn precision_min_collisions(cfg: &DiffusionConfig) -> Result<u64, Error> {
    let g = Geometry::new(cfg.gap()?)?;
    let hops = (crate::estimators::diffusion::MIN_HOPS_PER_LAG
        * cfg.window.hi.max(cfg.check_window.hi)) as f64;
    Ok((hops * g.collisions_per_hop() * PRECISION_BATCHES as f64).ceil() as u64)
}

pub(super) fn precision_independence(
    cfg: &DiffusionConfig,
    r: &DiffusionReport,
    collisions: u64,
    ctx: &Ctx<'_>,
    checks: &mut Checks,
) -> Result<(), Error> {
    let short = |precision| {
        let mut c = cfg.clone();
        c.collisions = collisions;
        c.batches = PRECISION_BATCHES;
        c.precision = precision;
        crate::estimators::diffusion::run(&c, &ctx.options())
    };
    let lo = short(Precision::F64)?;
    let hi = short(Precision::Bits(ctx.bits))?;
    // The two runs start from the same states: compared paired, batch by batch (their errors
    // must not be added in quadrature).
    let pair = comparison::paired(&hi.batch_D, &lo.batch_D)?;
    let z_pair = pair.z;
    let z_rec = (hi.D - r.D) / (hi.D_err.hypot(r.D_err));
    // Errors from PRECISION_BATCHES batches: the t quantile at the normal 4σ tail.
    let bound = normal_sigma_equivalent_t((PRECISION_BATCHES - 1) as f64, SIGMAS);
    checks.pass_if(
        z_pair.abs() <= pair.bound && z_rec.abs() <= bound,
        "verification",
        "precision independence",
        format!(
            "{PRECISION_BATCHES} batches of {} collisions from the run's first starts: MPFR {} bits D = {:.5} ± {:.5}, f64 D = {:.5} ± {:.5} (paired over the batches: {z_pair:+.1}σ, bound {:.2}σ); against the recorded D {z_rec:+.1}σ (bound {bound:.2}σ, t with {} dof)",
            collisions / PRECISION_BATCHES as u64,
            ctx.bits,
            hi.D,
            hi.D_err,
            lo.D,
            lo.D_err,
            pair.bound,
            PRECISION_BATCHES - 1
        ),
        &[("D_mpfr", hi.D), ("D_mpfr_err", hi.D_err), ("D_f64", lo.D), ("D_f64_err", lo.D_err)],
    );
    Ok(())
}
