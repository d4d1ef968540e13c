//! Trap-hopping analyses (paper Sec. III): backscattering by injection into a single trap, and
//! symbol statistics, collisionless flights and the hop-level Green–Kubo D along long lattice
//! trajectories. Every number has a standard error over independent batches.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::engine::metadata::RunMeta;
use crate::engine::parallel::{par_batches, par_chunks, share};
use crate::engine::simd::BLOCK;
use crate::engine::{drive, run_block, Engine, Resolved};
use crate::estimators::diffusion::Estimate;
use crate::numbers::precision::{AtPrecision, Precision};
use crate::numbers::real::Real;
use crate::observers::hop_correlations::{HopCorrelations, MAX_LAG};
use crate::observers::hops::{HopLanes, Hops};
use crate::scenes::lattice::TriangularLattice;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::single_trap::SingleTrap;
use crate::scenes::symbols::{
    check_order, mirror_index, parse_sequence_index, reverse_index, sequence_name,
};
use crate::scenes::triangular::equilibrium_state;
use crate::scenes::triangular::geometry::{check_diffusive_gap, Geometry};
use crate::statistics::mean_se;
use crate::theory::green_kubo;
use crate::Error;

/// Injected visits between two calls of a progress callback: 2¹⁶, about 10⁶ collisions at w = 0.1
/// (π/(3w) ≈ 10 collisions per visit).
const VISIT_CHUNK: u64 = 1 << 16;

fn est(v: &[f64]) -> Estimate {
    let (value, err) = mean_se(v);
    Estimate { value, err }
}

/// Backscattering by injection (the CLI's `backscatter --json`).
#[derive(Debug, Clone, Serialize)]
pub struct BackscatterReport {
    /// Gap.
    pub w: f64,
    /// P(leave through the entrance).
    pub p_bs: f64,
    /// Its standard error.
    pub p_bs_err: f64,
    /// P(leave to the left), P(leave to the right) (equal by symmetry).
    pub p_l: Estimate,
    /// See `p_l`.
    pub p_r: Estimate,
    /// P(no collision in the trap).
    pub p_cf: Estimate,
    /// Mean time in the trap.
    pub mean_visit_time: f64,
    /// Its standard error.
    pub mean_visit_time_err: f64,
    /// Kac: τ = πA/(3w).
    pub mean_visit_time_exact: f64,
    /// Mean collisions per visit.
    pub mean_collisions_per_visit: f64,
    /// Its standard error.
    pub mean_collisions_per_visit_err: f64,
    /// Kac: π/(3w).
    pub mean_collisions_per_visit_exact: f64,
    /// Visits simulated.
    pub visits: u64,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// Injects `visits` particles (in `batches` batches) through one gap from the invariant flux, in f64.
pub fn backscatter(
    w: f64,
    visits: u64,
    batches: u32,
    seed: u64,
    threads: usize,
) -> Result<BackscatterReport, Error> {
    backscatter_at(w, visits, batches, seed, threads, Precision::F64, &|_| {})
}

/// The injection batches on number type `T`.
struct Inject<'a> {
    w: f64,
    visits: u64,
    batches: u32,
    seed: u64,
    run: u64,
    threads: usize,
    progress: &'a (dyn Fn(u64) + Sync),
}

impl AtPrecision for Inject<'_> {
    type Output = Result<Vec<[f64; 6]>, Error>;
    fn at<T: Real>(self, ctx: T::Ctx) -> Self::Output {
        let scene = SingleTrap::new(T::from_f64(ctx, self.w))?;
        let progress = self.progress;
        par_batches(self.threads, self.batches, |b| {
            let n_b = share(self.visits, self.batches, b);
            let mut rng = StreamKey::new(self.seed, Purpose::Injection, b as u64)
                .in_run(self.run)
                .rng();
            let (mut exits, mut cf, mut t, mut c) = ([0u64; 3], 0u64, 0.0, 0u64);
            for i in 1..=n_b {
                let v = scene.random_visit(&mut rng)?;
                exits[v.exit.index()] += 1;
                cf += u64::from(v.collisions == 0);
                t += v.time;
                c += v.collisions;
                if i % VISIT_CHUNK == 0 {
                    progress(VISIT_CHUNK);
                }
            }
            progress(n_b % VISIT_CHUNK);
            let n = n_b as f64;
            Ok([
                exits[0] as f64 / n,
                exits[1] as f64 / n,
                exits[2] as f64 / n,
                cf as f64 / n,
                t / n,
                c as f64 / n,
            ])
        })
    }
}

/// As [`backscatter`], on number type `precision` (the same generic kernel at MPFR precision:
/// statistics must not depend on it). `progress` receives the visits done, in increments of up
/// to 2¹⁶ per batch, summing to `visits`.
pub fn backscatter_at(
    w: f64,
    visits: u64,
    batches: u32,
    seed: u64,
    threads: usize,
    precision: Precision,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<BackscatterReport, Error> {
    backscatter_run(w, visits, batches, (seed, 0), threads, precision, progress)
}

/// As [`backscatter_at`], in run `run` of seed `seed`: batch b injects from the stream
/// `(seed, Injection, run, b)`, so the points of a figure's grid and inset never share streams.
pub fn backscatter_run(
    w: f64,
    visits: u64,
    batches: u32,
    (seed, run): (u64, u64),
    threads: usize,
    precision: Precision,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<BackscatterReport, Error> {
    check_diffusive_gap(w)?;
    if batches < 2 {
        return Err(Error::TooFew {
            what: "batches",
            min: 2,
            got: batches as u64,
        });
    }
    if visits < batches as u64 {
        return Err(Error::TooFew {
            what: "visits (one per batch at least)",
            min: batches as u64,
            got: visits,
        });
    }
    let res = precision.dispatch(Inject {
        w,
        visits,
        batches,
        seed,
        run,
        threads,
        progress,
    })?;
    let col = |k: usize| est(&res.iter().map(|x| x[k]).collect::<Vec<_>>());
    let g = Geometry::new(w)?;
    let (pz, mt, mc) = (col(0), col(4), col(5));
    Ok(BackscatterReport {
        w,
        p_bs: pz.value,
        p_bs_err: pz.err,
        p_l: col(1),
        p_r: col(2),
        p_cf: col(3),
        mean_visit_time: mt.value,
        mean_visit_time_err: mt.err,
        mean_visit_time_exact: g.hop_time(),
        mean_collisions_per_visit: mc.value,
        mean_collisions_per_visit_err: mc.err,
        mean_collisions_per_visit_exact: g.collisions_per_hop(),
        visits,
        meta: RunMeta::new(Some(seed), Some(batches as u64), precision, Some(threads)),
    })
}

/// Hop statistics along lattice trajectories (the CLI's `hops --json`).
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize)]
pub struct HopsReport {
    /// Gap.
    pub w: f64,
    /// Backscattering probability p(z).
    pub p_bs: f64,
    /// Its standard error.
    pub p_bs_err: f64,
    /// Probability of a visit without collision.
    pub p_cf: f64,
    /// Its standard error.
    pub p_cf_err: f64,
    /// The nine two-symbol probabilities.
    pub pairs: BTreeMap<String, Estimate>,
    /// Sequence probabilities for every length 1 … order.
    pub sequences: Vec<BTreeMap<String, Estimate>>,
    /// Largest |z-score| of the symmetries p(s) = p(mirror s) and p(s) = p(reverse(mirror s)).
    pub symmetry_max_z: f64,
    /// Hop-level Green–Kubo D = D_MZ (1 + 2 Σ_{j≤J} C_j) ([`green_kubo::HOP_TRUNCATION`]).
    pub D_GK: f64,
    /// Its standard error over the independent batches.
    pub D_GK_err: f64,
    /// The Green–Kubo window J (number of lags summed).
    pub gk_window: usize,
    /// Machta–Zwanzig D.
    pub D_MZ: f64,
    /// Hop-direction correlations C_1 … C_J (J = `gk_window`), batch means and errors.
    pub correlations: Vec<Estimate>,
    /// Complete trap visits observed.
    pub visits: u64,
    /// Collisions simulated.
    pub collisions: u64,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

impl HopsReport {
    /// The measured probabilities of the sequences of length `k` as a validated table for the
    /// theory ([`crate::theory::sequences::SequenceProbabilities`]; same index order). A sequence
    /// name that is not a word of length `k` over z, l, r is an error.
    pub fn table(
        &self,
        k: usize,
    ) -> Result<crate::theory::sequences::SequenceProbabilities, Error> {
        let m = self
            .sequences
            .get(k.wrapping_sub(1))
            .ok_or_else(|| Error::Invalid(format!("no sequences of length {k} were counted")))?;
        let mut p = vec![0.0; 3usize.pow(k as u32)];
        for (name, e) in m {
            p[parse_sequence_index(name, k)?] = e.value;
        }
        crate::theory::sequences::SequenceProbabilities::from_weights(k, p)
    }
}

/// Fewest collisions per batch [`hops`] accepts: on average 8·[`MAX_LAG`] hops
/// (π/(3w) collisions each), twice the 4·J_max hops the Green–Kubo estimator needs per
/// sequence, so that a batch falls short of them with negligible probability.
pub fn min_collisions_per_batch(w: f64) -> Result<u64, Error> {
    let g = Geometry::new(w)?;
    Ok((8.0 * MAX_LAG as f64 * g.collisions_per_hop()).ceil() as u64)
}

pub(crate) fn check_hops_input(
    w: f64,
    collisions: u64,
    batches: u32,
    order: usize,
) -> Result<(), Error> {
    check_diffusive_gap(w)?;
    check_order("order", order)?;
    if batches < 2 {
        return Err(Error::TooFew {
            what: "batches",
            min: 2,
            got: batches as u64,
        });
    }
    let per = collisions / batches as u64;
    let min = min_collisions_per_batch(w)?;
    if per < min {
        return Err(Error::Invalid(format!(
            "collisions = {collisions} is too few for {batches} batches at w = {w}: the hop-level \
             Green–Kubo estimator needs at least {min} collisions per batch ({} hops of \
             pi/(3w) collisions each), i.e. collisions >= {}",
            8 * MAX_LAG,
            min.saturating_mul(batches as u64)
        )));
    }
    crate::engine::check_trajectory_length(collisions.div_ceil(batches as u64))?;
    crate::engine::parallel::check_batches("batches", batches)
}

/// Runs `batches` lattice trajectories of `collisions` collisions in all
/// ([`crate::engine::parallel::share`]) and collects the hop statistics up to sequences of length `order` and the hop-level Green–Kubo D.
///
/// Checked before any work: 0 < w < w∞, 1 ≤ `order` ≤ [`crate::scenes::symbols::MAX_ORDER`],
/// `batches` ≥ 2, at least [`min_collisions_per_batch`] collisions per batch, `threads` ≥ 1.
/// `progress` receives the collisions done, in increments of up to 2²⁰ per batch, summing to
/// the report's `collisions`.
pub fn hops(
    w: f64,
    collisions: u64,
    batches: u32,
    order: usize,
    seed: u64,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<HopsReport, Error> {
    hops_run(w, collisions, batches, order, (seed, 0), threads, progress)
}

/// As [`hops`], in run `run` of seed `seed` (batch b follows the trajectory stream
/// `(seed, run, b)`), so that the points of a grid never share streams.
pub fn hops_run(
    w: f64,
    collisions: u64,
    batches: u32,
    order: usize,
    (seed, run): (u64, u64),
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<HopsReport, Error> {
    hops_on(
        w,
        collisions,
        batches,
        order,
        (seed, run),
        Engine::Auto,
        threads,
        progress,
    )
}

/// As [`hops_run`], on the engine `engine` (the same bits on every engine).
#[allow(clippy::too_many_arguments)]
pub fn hops_on(
    w: f64,
    collisions: u64,
    batches: u32,
    order: usize,
    (seed, run): (u64, u64),
    engine: Engine,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<HopsReport, Error> {
    check_hops_input(w, collisions, batches, order)?;
    let resolved = engine.resolve(true)?;
    let lat = TriangularLattice::new(w)?;
    let start = |b: usize| {
        equilibrium_state(
            lat.trap(),
            &mut StreamKey::new(seed, Purpose::Trajectory, b as u64)
                .in_run(run)
                .rng(),
        )
    };
    let quota = |b: usize| share(collisions, batches, b as u32);
    let res: Vec<Hops> = match resolved {
        Resolved::Scalar => par_batches(threads, batches, |b| {
            let mut s = start(b as usize);
            let mut h = HopLanes::new(order, 1)?;
            drive(&lat, &mut s, quota(b as usize), &mut h, progress)?;
            Ok(h.lanes.remove(0))
        })?,
        Resolved::Simd(path) => par_chunks(threads, batches as usize, BLOCK, |r| {
            let mut states: Vec<_> = r.clone().map(start).collect();
            let quotas: Vec<u64> = r.clone().map(quota).collect();
            let mut h = HopLanes::new(order, BLOCK)?;
            run_block(path, lat.trap(), &mut states, &quotas, &mut h, progress)?;
            h.lanes.truncate(r.len());
            Ok(h.lanes)
        })?,
    };
    let g = Geometry::new(w)?;
    let d_mz = g.d_mz();
    let mut sequences = Vec::new();
    let mut zmax: f64 = 0.0;
    for k in 1..=order {
        let n = 3usize.pow(k as u32);
        let per_batch: Vec<Vec<f64>> = res
            .iter()
            .map(|h| {
                let tot: u64 = h.counts[k - 1].iter().sum();
                h.counts[k - 1]
                    .iter()
                    .map(|&c| c as f64 / tot.max(1) as f64)
                    .collect()
            })
            .collect();
        let mut m = BTreeMap::new();
        for code in 0..n {
            m.insert(
                sequence_name(k, code),
                est(&per_batch.iter().map(|p| p[code]).collect::<Vec<_>>()),
            );
            for other in [
                mirror_index(k, code),
                reverse_index(k, mirror_index(k, code)),
            ] {
                let d: Vec<f64> = per_batch.iter().map(|p| p[code] - p[other]).collect();
                let e = est(&d);
                if e.err > 0.0 {
                    zmax = zmax.max(e.value.abs() / e.err);
                }
            }
        }
        sequences.push(m);
    }
    let pairs = if order >= 2 {
        sequences[1].clone()
    } else {
        BTreeMap::new()
    };
    let p_bs = sequences[0]["z"];
    let p_cf = est(&res
        .iter()
        .map(|h| h.collisionless as f64 / h.visits.max(1) as f64)
        .collect::<Vec<_>>());
    let dirs: Vec<HopCorrelations> = res.iter().map(|h| h.directions.clone()).collect();
    let gk = green_kubo::estimate(&dirs, green_kubo::HOP_TRUNCATION)?;
    let correlations = (1..=gk.truncation)
        .map(|j| est(&dirs.iter().map(|d| d.correlation(j)).collect::<Vec<_>>()))
        .collect();
    Ok(HopsReport {
        w,
        p_bs: p_bs.value,
        p_bs_err: p_bs.err,
        p_cf: p_cf.value,
        p_cf_err: p_cf.err,
        pairs,
        sequences,
        symmetry_max_z: zmax,
        D_GK: d_mz * gk.d_over_d_mz,
        D_GK_err: d_mz * gk.se,
        gk_window: gk.truncation,
        D_MZ: d_mz,
        correlations,
        visits: res.iter().map(|h| h.visits).sum(),
        collisions,
        meta: RunMeta::new(
            Some(seed),
            Some(batches as u64),
            Precision::F64,
            Some(threads),
        )
        .with_engine(resolved),
    })
}

/// The corrected Machta–Zwanzig hierarchy evaluated on measured hop statistics (the CLI's
/// `theory --json`).
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize)]
pub struct TheoryReport {
    /// Gap.
    pub w: f64,
    /// Measured p_bs and p_cf (with errors).
    pub p_bs: Estimate,
    /// See `p_bs`.
    pub p_cf: Estimate,
    /// App. A analytic p_cf with the flux integral corrected, and as printed.
    pub p_cf_appendix_a: (f64, f64),
    /// Machta–Zwanzig.
    pub D_MZ: f64,
    /// Eq. (4) with the measured p_cf.
    pub D_cf: f64,
    /// Eq. (5) with the measured p_bs.
    pub D_bs: f64,
    /// Eq. (6).
    pub D_1: f64,
    /// (k, D_k from the walked distance classes, D_k combined with collisionless flights as eq. 6).
    pub D_k: Vec<(usize, f64, f64)>,
    /// The paper's printed (B2) and (B3) evaluated literally (for comparison; see
    /// proofs-notes/paper-appendix-b.md).
    pub D_2_D_3_as_printed: (f64, f64),
    /// (k, exact D of the order-k correlated walk with the measured sequence table).
    pub lattice_gas_exact: Vec<(usize, f64)>,
    /// Hop-level Green–Kubo D of the Lorentz gas itself (the reference).
    pub D_GK: Estimate,
    /// Collisions simulated.
    pub collisions: u64,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// Measures sequence tables up to `order` (at least 3, for the printed (B2), (B3)) along lattice
/// trajectories and evaluates the theory for k = 1 … max(`order`, 3).
///
/// Checked before any work: as [`hops`], with 1 ≤ `order` ≤ [`crate::scenes::symbols::MAX_ORDER`].
/// `progress` receives the collisions done (see [`hops`]).
pub fn theory(
    w: f64,
    collisions: u64,
    batches: u32,
    order: usize,
    seed: u64,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<TheoryReport, Error> {
    theory_run(w, collisions, batches, order, (seed, 0), threads, progress)
}

/// As [`theory`], in run `run` of seed `seed` (see [`hops_run`]).
pub fn theory_run(
    w: f64,
    collisions: u64,
    batches: u32,
    order: usize,
    seed_run: (u64, u64),
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<TheoryReport, Error> {
    use crate::theory::{appendix_a, hierarchy, markov::CorrelatedWalk};
    check_order("order", order)?;
    let top = order.max(3);
    let h = hops_run(w, collisions, batches, top, seed_run, threads, progress)?;
    let g = Geometry::new(w)?;
    let table = |k: usize| h.table(k);
    let p_cf = h.p_cf;
    let mut d_k = Vec::new();
    let mut exact = Vec::new();
    for k in 1..=top {
        let t = table(k)?;
        d_k.push((
            k,
            hierarchy::d_k(&g, &t),
            hierarchy::d_k_combined(&g, &t, &p_cf),
        ));
        exact.push((k, CorrelatedWalk::new(&t)?.d(&g)?));
    }
    Ok(TheoryReport {
        w,
        p_bs: Estimate {
            value: h.p_bs,
            err: h.p_bs_err,
        },
        p_cf: Estimate {
            value: h.p_cf,
            err: h.p_cf_err,
        },
        p_cf_appendix_a: (appendix_a::p_cf(&g), appendix_a::p_cf_as_printed(&g)),
        D_MZ: g.d_mz(),
        D_cf: hierarchy::d_cf(&g, &p_cf),
        D_bs: hierarchy::d_bs(&g, &h.p_bs),
        D_1: hierarchy::d_1(&g, &h.p_bs, &p_cf),
        D_k: d_k,
        D_2_D_3_as_printed: (
            hierarchy::d2_as_printed(&g, &table(2)?),
            hierarchy::d3_as_printed(&g, &table(3)?),
        ),
        lattice_gas_exact: exact,
        D_GK: Estimate {
            value: h.D_GK,
            err: h.D_GK_err,
        },
        collisions: h.collisions,
        meta: h.meta,
    })
}

/// Independent batches of simulated walkers per order in [`lattice_walks`]: 16 give a standard
/// error whose own relative uncertainty is about 1/√(2·15) ≈ 18 %.
pub const WALK_BATCHES: usize = 16;

/// Walkers per batch in [`lattice_walks`]: 16 × 4096 walkers of [`WALK_HOPS`] hops (8.4·10⁶
/// hops, a fraction of a second per order) put the error of the simulated D near 0.8 % at
/// w = 0.1 — a seventh of the 5.5 % step from order 1 to order 2 that Fig. 6b shows.
pub const WALK_WALKERS: usize = 4096;

/// Hops per walker in [`lattice_walks`] (the Einstein fit runs over the second half, 64 … 128):
/// the Lorentz gas's hop correlations, which the measured walks inherit, vanish within about
/// ten hops ([`crate::theory::green_kubo`]), so the exact fit bias
/// ([`crate::theory::lattice_walk::fit_bias`]) is far below the statistical error.
pub const WALK_HOPS: usize = 128;

/// One order of [`LatticeWalkReport`].
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize)]
pub struct LatticeWalkRow {
    /// Order k of the correlated walk (memory of k − 1 symbols).
    pub order: usize,
    /// D of the simulated walk (Einstein fit, batch means).
    pub D_simulated: f64,
    /// Its standard error.
    pub D_simulated_err: f64,
    /// The exact D of the same walk (resolvent of its history chain).
    pub D_exact: f64,
}

/// Fig. 6b by simulation (the CLI's `lattice-walk --json`): correlated walks driven by the
/// measured symbol tables, simulated and exact, next to the Lorentz gas's own hop-level D.
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize)]
pub struct LatticeWalkReport {
    /// Gap.
    pub w: f64,
    /// Machta–Zwanzig D.
    pub D_MZ: f64,
    /// Hop-level Green–Kubo D of the Lorentz gas (as [`HopsReport::D_GK`]).
    pub D_GK: f64,
    /// Its standard error.
    pub D_GK_err: f64,
    /// Orders 1 … `order`.
    pub walks: Vec<LatticeWalkRow>,
    /// Version, seed, batches, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// Measures the symbol tables up to `order` along `batches` Lorentz-gas trajectories
/// ([`hops`]), then for each k = 1 … `order` simulates the order-k correlated walk with the
/// order-k table ([`WALK_BATCHES`] × [`WALK_WALKERS`] walkers of [`WALK_HOPS`] hops, Einstein
/// fit) and evaluates its exact D.
///
/// Checked before any work: as [`hops`], with 1 ≤ `order` ≤ [`crate::scenes::symbols::MAX_ORDER`].
/// `progress` receives the Lorentz-gas collisions done (see [`hops`]); the walks, well under a
/// second per order, are not counted.
pub fn lattice_walks(
    w: f64,
    collisions: u64,
    batches: u32,
    order: usize,
    seed: u64,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<LatticeWalkReport, Error> {
    use crate::theory::{lattice_walk, markov::CorrelatedWalk};
    check_order("order", order)?;
    let h = hops(w, collisions, batches, order, seed, threads, progress)?;
    let g = Geometry::new(w)?;
    let cfg = lattice_walk::LatticeWalkConfig::new(WALK_BATCHES, WALK_WALKERS, WALK_HOPS, seed);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Invalid(e.to_string()))?;
    let mut walks = Vec::new();
    for k in 1..=order {
        let walk = CorrelatedWalk::new(&h.table(k)?)?;
        let sim = pool.install(|| lattice_walk::simulate(&walk, &cfg))?;
        let (d, err) = sim.d(&g);
        walks.push(LatticeWalkRow {
            order: k,
            D_simulated: d,
            D_simulated_err: err,
            D_exact: walk.d(&g)?,
        });
    }
    Ok(LatticeWalkReport {
        w,
        D_MZ: g.d_mz(),
        D_GK: h.D_GK,
        D_GK_err: h.D_GK_err,
        walks,
        meta: h.meta,
    })
}
