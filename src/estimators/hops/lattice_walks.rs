//! Fig. 6b by simulation: correlated lattice walks of order 1 … K driven by the symbol tables
//! measured along Lorentz-gas trajectories, next to their exact D.

use serde::{Deserialize, Serialize};

use super::HopsConfig;
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::RunOptions;
use crate::scenes::triangular::geometry::Geometry;
use crate::statistics::comparison;

/// Independent batches of simulated walkers per order in [`run`]: 16 give a standard
/// error whose own relative uncertainty is about 1/√(2·15) ≈ 18 %.
pub const WALK_BATCHES: usize = 16;

/// Walkers per batch in [`run`]: 16 × 4096 walkers of [`WALK_HOPS`] hops (8.4·10⁶
/// hops, a fraction of a second per order) put the error of the simulated D near 0.8 % at
/// w = 0.1 — a seventh of the 5.5 % step from order 1 to order 2 that Fig. 6b shows.
pub const WALK_WALKERS: usize = 4096;

/// Hops per walker in [`run`] (the Einstein fit runs over the second half, 64 … 128):
/// the Lorentz gas's hop correlations, which the measured walks inherit, vanish within about
/// ten hops ([`crate::theory::green_kubo`]), so the exact fit bias
/// ([`crate::theory::lattice_walk::fit_bias`]) is far below the statistical error.
pub const WALK_HOPS: usize = 128;

/// One order of [`LatticeWalkReport`].
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LatticeWalkRow {
    /// Order k of the correlated walk (memory of k − 1 symbols).
    pub order: usize,
    /// D of the simulated walk (Einstein fit, batch means).
    pub D_simulated: f64,
    /// Its standard error.
    pub D_simulated_err: f64,
    /// The exact D of the same walk (resolvent of its history chain).
    pub D_exact: f64,
    /// Its standard error as an estimate of the walk of the Lorentz gas's exact table
    /// (jackknife over the batches the table was measured from).
    pub D_exact_err: f64,
    /// D_simulated − D_exact over D_simulated_err: the simulation of this very walk against its
    /// exact value (the table is the same, so only the walk's own noise enters; Student-t with
    /// [`WALK_BATCHES`] − 1 dof).
    pub simulated_z: f64,
    /// The agreement bound of `simulated_z` (the 4σ-equivalent t).
    pub simulated_bound: f64,
}

/// Fig. 6b by simulation (the CLI's `lattice-walk --json`): correlated walks driven by the
/// measured symbol tables, simulated and exact, next to the Lorentz gas's own hop-level D.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct LatticeWalkReport {
    /// Gap.
    pub w: f64,
    /// Machta–Zwanzig D.
    pub D_MZ: f64,
    /// Hop-level Green–Kubo D of the Lorentz gas (as [`super::HopsReport::D_GK`]).
    pub D_GK: f64,
    /// Its standard error.
    pub D_GK_err: f64,
    /// Orders 1 … `order`.
    pub walks: Vec<LatticeWalkRow>,
    /// The configuration that produced the result (what `lorentz report` re-runs).
    pub config: HopsConfig,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// Measures the symbol tables up to `cfg.order` along `cfg.batches` Lorentz-gas trajectories
/// ([`super::run`]), then for each k = 1 … order simulates the order-k correlated walk with the
/// order-k table ([`WALK_BATCHES`] × [`WALK_WALKERS`] walkers of [`WALK_HOPS`] hops, Einstein
/// fit) and evaluates its exact D. `options.progress` receives the Lorentz-gas collisions done;
/// the walks, well under a second per order, are not counted.
///
/// # Errors
/// As [`super::run`], checked before any work.
pub fn run(cfg: &HopsConfig, options: &RunOptions) -> Result<LatticeWalkReport, Error> {
    use crate::theory::{lattice_walk, markov::CorrelatedWalk};
    let (h, batches) = super::run_with_batches(cfg, options)?;
    let pools = super::jackknife::leave_one_out(&batches, cfg.order)?;
    let config = cfg.clone();
    let (w, order, seed, threads) = (cfg.gap()?, cfg.order, cfg.seed, options.threads);
    let g = Geometry::new(w)?;
    let cfg = lattice_walk::LatticeWalkConfig::new(WALK_BATCHES, WALK_WALKERS, WALK_HOPS, seed);
    let pool = crate::engine::parallel::thread_pool(threads)?;
    let mut walks = Vec::new();
    for k in 1..=order {
        let walk = CorrelatedWalk::new(&h.table(k)?)?;
        let sim = pool.install(|| lattice_walk::simulate(&walk, &cfg))?;
        let (d, err) = sim.d(&g);
        let exact = walk.d(&g)?;
        let check = comparison::of(d - exact, err, (WALK_BATCHES - 1) as f64);
        walks.push(LatticeWalkRow {
            order: k,
            D_simulated: d,
            D_simulated_err: err,
            D_exact: exact,
            D_exact_err: super::jackknife::se(&pools, |p| {
                CorrelatedWalk::new(&p.tables[k - 1])?.d(&g)
            })?,
            simulated_z: check.z,
            simulated_bound: check.bound,
        });
    }
    Ok(LatticeWalkReport {
        w,
        D_MZ: g.d_mz(),
        D_GK: h.D_GK,
        D_GK_err: h.D_GK_err,
        walks,
        config,
        meta: h.meta,
    })
}
