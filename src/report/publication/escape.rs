//! The audit of an `escape` result: the record against its configuration and the configuration
//! re-run through the library.

use std::path::Path;

use super::diffusion::refused_config;
use super::file::ResultFile;
use super::same_bits::rerun_check;
use super::{Checks, Ctx};
use crate::Error;
use crate::estimators::escape::{self, BATCHES_PER_WIDTH, EscapeConfig, EscapeReport};
use crate::scenes::triangular::geometry::Geometry;

/// Smallest D/D_MZ over the diffusive range (0.89 near w = 0.055, docs/guide/diffusion.md table): the expected
/// lifetimes below are computed with D = this × D_MZ, so they do not underestimate.
const D_OVER_D_MZ_MIN: f64 = 0.85;

/// The file as an escape result whose configuration the command line would accept.
pub(super) fn parse(file: &ResultFile, path: &Path) -> Result<EscapeReport, Error> {
    let r: EscapeReport = file.parse(path)?;
    r.config.validate().map_err(|e| refused_config(path, e))?;
    Ok(r)
}

/// Expected collisions of the run: per particle, the mean time to leave [0, L] from a uniform
/// start, L²/(12D) (cut at t_max = 8L²/(π²D_MZ)), over the mean free path.
pub(super) fn collisions(cfg: &EscapeConfig) -> Result<u64, Error> {
    let g = Geometry::new(cfg.gap()?)?;
    let (d_mz, ell) = (g.d_mz(), g.mean_free_path());
    let per_particle: f64 = cfg
        .widths
        .iter()
        .map(|l| {
            let t_exit = l * l / (12.0 * D_OVER_D_MZ_MIN * d_mz);
            let t_max = escape::T_MAX_E_FOLDS * l * l / (std::f64::consts::PI.powi(2) * d_mz);
            t_exit.min(t_max) / ell
        })
        .sum();
    Ok((cfg.particles_per_width as f64 * per_particle).ceil() as u64)
}

/// The checks: the record, the re-run.
pub(super) fn checks(r: &EscapeReport, ctx: &Ctx<'_>, checks: &mut Checks) -> Result<(), Error> {
    let cfg = &r.config;
    let widths = cfg.widths.len() as u64;
    let mut bad = super::meta_problems(
        &r.meta,
        Some(cfg.seed),
        Some(widths * u64::from(BATCHES_PER_WIDTH)),
        "f64",
    );
    let recorded: Vec<f64> = r.widths.iter().map(|x| x.L).collect();
    if r.w.to_bits() != cfg.gap()?.to_bits() || recorded != cfg.widths {
        bad.push("w or the widths differ from the configuration's".into());
    }
    super::record_check(bad, checks);
    let what = format!(
        "{} widths × {} particles (seed {})",
        widths, cfg.particles_per_width, cfg.seed
    );
    // Progress in collisions: the escape run reports particles.
    let particles = cfg.particles_per_width.saturating_mul(widths);
    rerun_check(r, particles, &what, ctx, checks, |o| escape::run(cfg, o))
}
