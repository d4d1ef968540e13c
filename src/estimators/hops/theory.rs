//! The corrected Machta–Zwanzig hierarchy (paper Sec. III and App. B) evaluated on hop
//! statistics measured along lattice trajectories, beside the exact D of the correlated walks
//! their tables define.

use serde::{Deserialize, Serialize};

use super::HopsConfig;
use super::jackknife::{self, Pool};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::scenes::triangular::geometry::Geometry;
use crate::theory::sequences::SequenceProbabilities;

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
    /// Its standard error (jackknife over the batches, as every `_err` of a derived number here).
    pub D_cf_err: f64,
    /// Eq. (5) with the measured p_bs.
    pub D_bs: f64,
    /// Its standard error.
    pub D_bs_err: f64,
    /// Eq. (6).
    pub D_1: f64,
    /// Its standard error.
    pub D_1_err: f64,
    /// The hierarchy by order k = 1 … max(order, 3).
    pub orders: Vec<TheoryOrder>,
    /// The paper's printed (B2) evaluated literally (for comparison; see
    /// proofs-notes/paper-appendix-b.md).
    pub D_2_as_printed: f64,
    /// Its standard error.
    pub D_2_as_printed_err: f64,
    /// The paper's printed (B3) evaluated literally.
    pub D_3_as_printed: f64,
    /// Its standard error.
    pub D_3_as_printed_err: f64,
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
    /// Its standard error (jackknife over the batches).
    pub D_k_err: f64,
    /// D_k combined with collisionless flights as eq. (6).
    pub D_k_combined: f64,
    /// Its standard error.
    pub D_k_combined_err: f64,
    /// D_k_combined − D_GK, both from the same trajectories (jackknifed together, so paired):
    /// how far order k of the hierarchy is from the Lorentz gas's own D.
    pub D_k_combined_minus_D_GK: f64,
    /// Its standard error (batches − 1 dof).
    pub D_k_combined_minus_D_GK_err: f64,
    /// Exact D of the order-k correlated lattice walk with the measured sequence table.
    pub D_lattice_walk: f64,
    /// Its standard error as an estimate of the walk of the exact table (jackknife).
    pub D_lattice_walk_err: f64,
}

/// Measures sequence tables up to max(`cfg.order`, 3) (at least 3, for the printed (B2), (B3))
/// along lattice trajectories ([`super::run`]) and evaluates the theory for k = 1 … max(order, 3).
///
/// # Errors
/// As [`super::run`], checked before any work.
pub fn run(cfg: &HopsConfig, options: &RunOptions) -> Result<TheoryReport, Error> {
    use crate::theory::{appendix_a, hierarchy};
    cfg.validate()?;
    let top = cfg.order.max(3);
    let w = cfg.gap()?;
    let deeper = HopsConfig {
        order: top,
        ..cfg.clone()
    };
    let (h, batches) = super::run_with_batches(&deeper, options)?;
    let pools = jackknife::leave_one_out(&batches, top)?;
    let g = Geometry::new(w)?;
    let table = |k: usize| h.table(k);
    let (p_cf, p_bs) = (h.p_cf, h.p_bs);
    let orders = (1..=top)
        .map(|k| order_row(k, &g, &table(k)?, p_cf, h.D_GK, &pools))
        .collect::<Result<Vec<_>, Error>>()?;
    let se = |f: &dyn Fn(&Pool) -> Result<f64, Error>| jackknife::se(&pools, f);
    Ok(TheoryReport {
        w,
        p_bs,
        p_bs_err: h.p_bs_err,
        p_cf,
        p_cf_err: h.p_cf_err,
        p_cf_appendix_a: appendix_a::p_cf(&g),
        p_cf_appendix_a_as_printed: appendix_a::p_cf_as_printed(&g),
        D_MZ: g.d_mz(),
        D_cf: hierarchy::d_cf(&g, &p_cf),
        D_cf_err: se(&|p| Ok(hierarchy::d_cf(&g, &p.p_cf)))?,
        D_bs: hierarchy::d_bs(&g, &p_bs),
        D_bs_err: se(&|p| Ok(hierarchy::d_bs(&g, &p.p_bs)))?,
        D_1: hierarchy::d_1(&g, &p_bs, &p_cf),
        D_1_err: se(&|p| Ok(hierarchy::d_1(&g, &p.p_bs, &p.p_cf)))?,
        orders,
        D_2_as_printed: hierarchy::d2_as_printed(&g, &table(2)?),
        D_2_as_printed_err: se(&|p| Ok(hierarchy::d2_as_printed(&g, &p.tables[1])))?,
        D_3_as_printed: hierarchy::d3_as_printed(&g, &table(3)?),
        D_3_as_printed_err: se(&|p| Ok(hierarchy::d3_as_printed(&g, &p.tables[2])))?,
        D_GK: h.D_GK,
        D_GK_err: h.D_GK_err,
        collisions: h.collisions,
        config: cfg.clone(),
        meta: h.meta,
    })
}

/// Order k of the hierarchy and of the exact walk, from the full table `t`, with jackknife
/// errors from the leave-one-out `pools`.
fn order_row(
    k: usize,
    g: &Geometry<f64>,
    t: &SequenceProbabilities,
    p_cf: f64,
    d_gk: f64,
    pools: &[Pool],
) -> Result<TheoryOrder, Error> {
    use crate::theory::{hierarchy, markov::CorrelatedWalk};
    let se = |f: &dyn Fn(&Pool) -> Result<f64, Error>| jackknife::se(pools, f);
    let combined = |p: &Pool| hierarchy::d_k_combined(g, &p.tables[k - 1], &p.p_cf);
    let d_k_combined = hierarchy::d_k_combined(g, t, &p_cf);
    Ok(TheoryOrder {
        k,
        D_k: hierarchy::d_k(g, t),
        D_k_err: se(&|p| Ok(hierarchy::d_k(g, &p.tables[k - 1])))?,
        D_k_combined: d_k_combined,
        D_k_combined_err: se(&|p| Ok(combined(p)))?,
        D_k_combined_minus_D_GK: d_k_combined - d_gk,
        D_k_combined_minus_D_GK_err: se(&|p| Ok(combined(p) - g.d_mz() * p.d_gk_over_d_mz))?,
        D_lattice_walk: CorrelatedWalk::new(t)?.d(g)?,
        D_lattice_walk_err: se(&|p| CorrelatedWalk::new(&p.tables[k - 1])?.d(g))?,
    })
}
