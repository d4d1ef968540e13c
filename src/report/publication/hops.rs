//! The audit of `hops`, `theory` and `lattice-walk` results: the record against its
//! configuration and closed forms, and the configuration re-run through the library.

use std::path::Path;

use super::diffusion::refused_config;
use super::file::{Kind, ResultFile};
use super::same_bits::rerun_check;
use super::{Checks, Ctx};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::estimators::hops::lattice_walks::{self, LatticeWalkReport};
use crate::estimators::hops::theory::{self, TheoryReport};
use crate::estimators::hops::{self, HopsConfig, HopsReport};
use crate::scenes::triangular::geometry::Geometry;

/// A result measured along lattice trajectories from a [`HopsConfig`].
pub(super) enum HopsKind {
    /// `lorentz hops`.
    Hops(HopsReport),
    /// `lorentz theory`.
    Theory(TheoryReport),
    /// `lorentz lattice-walk`.
    LatticeWalk(LatticeWalkReport),
}

/// The file as its kind's result, whose recorded configuration the command line would accept.
pub(super) fn parse(file: &ResultFile, path: &Path) -> Result<HopsKind, Error> {
    let h = match file.kind {
        Kind::Theory => HopsKind::Theory(file.parse(path)?),
        Kind::LatticeWalk => HopsKind::LatticeWalk(file.parse(path)?),
        _ => HopsKind::Hops(file.parse(path)?),
    };
    h.config().validate().map_err(|e| refused_config(path, e))?;
    Ok(h)
}

impl HopsKind {
    /// The recorded configuration.
    pub(super) fn config(&self) -> &HopsConfig {
        match self {
            HopsKind::Hops(r) => &r.config,
            HopsKind::Theory(r) => &r.config,
            HopsKind::LatticeWalk(r) => &r.config,
        }
    }

    /// The recorded metadata.
    pub(super) fn meta(&self) -> &RunMeta {
        match self {
            HopsKind::Hops(r) => &r.meta,
            HopsKind::Theory(r) => &r.meta,
            HopsKind::LatticeWalk(r) => &r.meta,
        }
    }

    /// The recorded w, collisions (absent from `lattice-walk`) and D_MZ.
    fn record(&self) -> (f64, Option<u64>, f64) {
        match self {
            HopsKind::Hops(r) => (r.w, Some(r.collisions), r.D_MZ),
            HopsKind::Theory(r) => (r.w, Some(r.collisions), r.D_MZ),
            HopsKind::LatticeWalk(r) => (r.w, None, r.D_MZ),
        }
    }
}

/// The checks: the record against the configuration, then the re-run.
pub(super) fn checks(h: &HopsKind, ctx: &Ctx<'_>, checks: &mut Checks) -> Result<(), Error> {
    let cfg = h.config();
    let (w, collisions, d_mz) = h.record();
    let mut bad = super::meta_problems(
        h.meta(),
        Some(cfg.seed),
        Some(u64::from(cfg.batches)),
        "f64",
    );
    let gap = cfg.gap()?;
    if w.to_bits() != gap.to_bits() {
        bad.push(format!("w: recorded {w}, configured {gap}"));
    }
    if collisions.is_some_and(|c| c != cfg.collisions) {
        bad.push(format!(
            "collisions: recorded {collisions:?}, configured {}",
            cfg.collisions
        ));
    }
    if Geometry::new(gap)?.d_mz().to_bits() != d_mz.to_bits() {
        bad.push("D_MZ is not the closed form".into());
    }
    super::record_check(bad, checks);
    // The result's error bars and symmetry verdicts are its batches' (the re-run checks their
    // bits, not their meaning): from too few batches they are no verdict, and the audit no PASS.
    checks.judge(
        f64::from(cfg.batches.max(1) - 1),
        true,
        (
            "statistics",
            "the error bars and verdicts rest on enough batches",
        ),
        format!("{} batches", cfg.batches),
        &[],
    );
    let what = format!(
        "{} collisions in {} batches (seed {}, order {})",
        cfg.collisions, cfg.batches, cfg.seed, cfg.order
    );
    let n = cfg.collisions;
    match h {
        HopsKind::Hops(r) => rerun_check(r, n, &what, ctx, checks, |o| hops::run(cfg, o)),
        HopsKind::Theory(r) => rerun_check(r, n, &what, ctx, checks, |o| theory::run(cfg, o)),
        HopsKind::LatticeWalk(r) => {
            rerun_check(r, n, &what, ctx, checks, |o| lattice_walks::run(cfg, o))
        }
    }
}
