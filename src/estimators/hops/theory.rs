//! The corrected Machta–Zwanzig hierarchy (paper Sec. III and App. B) evaluated on hop
//! statistics measured along lattice trajectories, beside the exact D of the correlated walks
//! their tables define.

use serde::{Deserialize, Serialize};

use super::HopsConfig;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::scenes::triangular::geometry::Geometry;
use crate::Error;

/// The corrected Machta–Zwanzig hierarchy evaluated on measured hop statistics (the CLI's
/// `theory --json`).
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TheoryReport {
    /// Gap.
    pub w: f64,
    /// Measured p_bs (backscattering probability of a trap visit).
    pub p_bs: f64,
    /// Its standard error.
    pub p_bs_err: f64,
    /// Measured p_cf (probability of a collisionless flight through a trap).
    pub p_cf: f64,
    /// Its standard error.
    pub p_cf_err: f64,
    /// App. A analytic p_cf with the flux integral corrected.
    pub p_cf_appendix_a: f64,
    /// App. A analytic p_cf as printed in the paper.
    pub p_cf_appendix_a_as_printed: f64,
    /// Machta–Zwanzig.
    pub D_MZ: f64,
    /// Eq. (4) with the measured p_cf.
    pub D_cf: f64,
    /// Eq. (5) with the measured p_bs.
    pub D_bs: f64,
    /// Eq. (6).
    pub D_1: f64,
    /// The hierarchy by order k = 1 … max(order, 3).
    pub orders: Vec<TheoryOrder>,
    /// The paper's printed (B2) evaluated literally (for comparison; see
    /// proofs-notes/paper-appendix-b.md).
    pub D_2_as_printed: f64,
    /// The paper's printed (B3) evaluated literally.
    pub D_3_as_printed: f64,
    /// Hop-level Green–Kubo D of the Lorentz gas itself (the reference).
    pub D_GK: f64,
    /// Its standard error.
    pub D_GK_err: f64,
    /// Collisions simulated.
    pub collisions: u64,
    /// The configuration that produced the result (as given: the tables are measured up to
    /// max(order, 3)); what `lorentz report` re-runs.
    pub config: HopsConfig,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// One order of the hierarchy in a [`TheoryReport`].
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TheoryOrder {
    /// The order k (length of the symbol sequences).
    pub k: usize,
    /// D_k from the walked distance classes.
    pub D_k: f64,
    /// D_k combined with collisionless flights as eq. (6).
    pub D_k_combined: f64,
    /// Exact D of the order-k correlated lattice walk with the measured sequence table.
    pub D_lattice_walk: f64,
}

/// Measures sequence tables up to max(`cfg.order`, 3) (at least 3, for the printed (B2), (B3))
/// along lattice trajectories ([`super::run`]) and evaluates the theory for k = 1 … max(order, 3).
///
/// # Errors
/// As [`super::run`], checked before any work.
pub fn run(cfg: &HopsConfig, options: &RunOptions) -> Result<TheoryReport, Error> {
    use crate::theory::{appendix_a, hierarchy, markov::CorrelatedWalk};
    cfg.validate()?;
    let top = cfg.order.max(3);
    let w = cfg.w;
    let h = super::run(&HopsConfig { order: top, ..*cfg }, options)?;
    let g = Geometry::new(w)?;
    let table = |k: usize| h.table(k);
    let p_cf = h.p_cf;
    let mut orders = Vec::new();
    for k in 1..=top {
        let t = table(k)?;
        orders.push(TheoryOrder {
            k,
            D_k: hierarchy::d_k(&g, &t),
            D_k_combined: hierarchy::d_k_combined(&g, &t, &p_cf),
            D_lattice_walk: CorrelatedWalk::new(&t)?.d(&g)?,
        });
    }
    Ok(TheoryReport {
        w,
        p_bs: h.p_bs,
        p_bs_err: h.p_bs_err,
        p_cf: h.p_cf,
        p_cf_err: h.p_cf_err,
        p_cf_appendix_a: appendix_a::p_cf(&g),
        p_cf_appendix_a_as_printed: appendix_a::p_cf_as_printed(&g),
        D_MZ: g.d_mz(),
        D_cf: hierarchy::d_cf(&g, &p_cf),
        D_bs: hierarchy::d_bs(&g, &h.p_bs),
        D_1: hierarchy::d_1(&g, &h.p_bs, &p_cf),
        orders,
        D_2_as_printed: hierarchy::d2_as_printed(&g, &table(2)?),
        D_3_as_printed: hierarchy::d3_as_printed(&g, &table(3)?),
        D_GK: h.D_GK,
        D_GK_err: h.D_GK_err,
        collisions: h.collisions,
        config: *cfg,
        meta: h.meta,
    })
}
