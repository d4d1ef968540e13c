//! The audit of a `backscatter` result: the record against its configuration, Kac's identities,
//! and the configuration re-run through the library.

use std::path::Path;

use super::diffusion::refused_config;
use super::file::ResultFile;
use super::same_bits::rerun_check;
use super::{Checks, Ctx, SIGMAS};
use crate::Error;
use crate::estimators::hops::backscatter::{self, BackscatterConfig, BackscatterReport};
use crate::scenes::triangular::geometry::Geometry;
use crate::statistics::normal_sigma_equivalent_t;

/// The file as a backscatter result whose configuration the command line would accept.
pub(super) fn parse(file: &ResultFile, path: &Path) -> Result<BackscatterReport, Error> {
    let r: BackscatterReport = file.parse(path)?;
    r.config.validate().map_err(|e| refused_config(path, e))?;
    Ok(r)
}

/// Expected collisions of the injections: π/(3w) per visit (Kac), rounded up.
pub(super) fn collisions(cfg: &BackscatterConfig) -> Result<u64, Error> {
    let per = Geometry::new(cfg.gap()?)?.collisions_per_hop();
    Ok((cfg.particles as f64 * per.max(1.0)).ceil() as u64)
}

/// The checks: the record, Kac's identities, the re-run.
pub(super) fn checks(
    r: &BackscatterReport,
    ctx: &Ctx<'_>,
    checks: &mut Checks,
) -> Result<(), Error> {
    let cfg = &r.config;
    let gap = cfg.gap()?;
    let g = Geometry::new(gap)?;
    let mut bad = super::meta_problems(
        &r.meta,
        Some(cfg.seed),
        Some(u64::from(cfg.batches)),
        &cfg.precision.to_string(),
    );
    if r.w.to_bits() != gap.to_bits() || r.particles != cfg.particles {
        bad.push("w or particles differ from the configuration's".into());
    }
    super::record_check(bad, checks);
    identity_checks(r, &g, checks);
    let what = format!(
        "{} particles in {} batches (seed {}, {})",
        cfg.particles, cfg.batches, cfg.seed, cfg.precision
    );
    // Progress in collisions: the injections report visits.
    rerun_check(r, cfg.particles, &what, ctx, checks, |o| {
        backscatter::run(cfg, o)
    })
}

/// Kac's identities: mean visit time and collisions per visit against their closed forms.
fn identity_checks(r: &BackscatterReport, g: &Geometry<f64>, checks: &mut Checks) {
    let bound = normal_sigma_equivalent_t(f64::from(r.config.batches) - 1.0, SIGMAS);
    for (name, v, e, x, exact) in [
        (
            "mean visit time = τ (Kac)",
            r.mean_visit_time,
            r.mean_visit_time_err,
            r.mean_visit_time_exact,
            g.hop_time(),
        ),
        (
            "collisions per visit = π/(3w) (Kac)",
            r.mean_collisions_per_visit,
            r.mean_collisions_per_visit_err,
            r.mean_collisions_per_visit_exact,
            g.collisions_per_hop(),
        ),
    ] {
        let closed = exact.to_bits() == x.to_bits();
        let z = (v - exact) / e;
        // A recorded closed form that is not the closed form FAILs however few the batches.
        let dof = if closed {
            f64::from(r.config.batches) - 1.0
        } else {
            f64::INFINITY
        };
        checks.judge(
            dof,
            z.abs() <= bound && closed,
            ("identities", name),
            format!(
                "{v} ± {e:.1e} against exact {exact} ({z:+.2}σ; bound {bound:.2}σ){}",
                if closed {
                    ""
                } else {
                    "; the recorded exact value is not the closed form"
                }
            ),
            &[("value", v), ("err", e), ("exact", exact)],
        );
    }
}
