//! Trap-hopping analyses (paper Sec. III): backscattering by injection into a single trap, and
//! symbol statistics, collisionless flights and the hop-level Green–Kubo D along long lattice
//! trajectories. Every number has a standard error over independent batches.
//!
//! * [`run`]: symbol statistics, p_bs, p_cf and the hop-level Green–Kubo D ([`HopsConfig`]).
//! * [`backscatter`]: injection into a single trap.
//! * [`theory`]: the corrected hierarchy on the measured tables.
//! * [`lattice_walks`]: Fig. 6b by simulated correlated walks.

pub mod backscatter;
mod jackknife;
pub mod lattice_walks;
pub mod theory;

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::Resolved;
use crate::engine::checkpoint::{Keeper, Quota, drive_kept, run_block_kept};
use crate::engine::metadata::RunMeta;
use crate::engine::options::{RunOption, RunOptions};
use crate::engine::parallel::{par_batches, par_chunks, share};
use crate::engine::simd::BLOCK;
use crate::estimators::diffusion::Estimate;
use crate::numbers::precision::Precision;
use crate::observers::hop_correlations::{HopCorrelations, MAX_LAG};
use crate::observers::hops::{HopLanes, Hops};
use crate::scenes::lattice::TriangularLattice;
use crate::scenes::sampling::{Purpose, StreamKey};
use crate::scenes::spec::Table;
use crate::scenes::symbols::{
    check_order, mirror_index, parse_sequence_index, reverse_index, sequence_name,
};
use crate::scenes::triangular::equilibrium_state;
use crate::scenes::triangular::geometry::Geometry;
use crate::statistics::mean_se;
use crate::theory::green_kubo;

fn est(v: &[f64]) -> Estimate {
    let (value, err) = mean_se(v);
    Estimate { value, err }
}

/// Everything that defines a measurement of hop statistics along lattice trajectories (also the
/// input of [`theory::run`] and [`lattice_walks::run`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HopsConfig {
    /// The triangular gas at a gap 0 < w < w∞, without a field (in JSON its keys `w`, the
    /// double, and `w_exact`, the gap as typed; a record of before with `w` alone reads as that
    /// double).
    #[serde(flatten)]
    pub table: Table,
    /// Lorentz-gas collisions in all, shared over the batches
    /// ([`crate::engine::parallel::share`]).
    pub collisions: u64,
    /// Independent batches (trajectories, at least 2); every error bar is over them.
    pub batches: u32,
    /// Longest symbol sequence counted, 1 to [`crate::scenes::symbols::MAX_ORDER`].
    pub order: usize,
    /// Seed of the random streams.
    pub seed: u64,
    /// Which run of this seed: batch b follows the trajectory stream `(seed, run, b)`, so that
    /// the points of a grid never share streams.
    #[serde(default)]
    pub run: u64,
}

impl HopsConfig {
    /// The command line's defaults on `table`: 2·10⁸ collisions in 16 batches, order 4, seed 1.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::estimators::hops::HopsConfig;
    /// use lorentz_gas::scenes::spec::Table;
    /// let cfg = HopsConfig::new(Table::triangular("1/10").unwrap());
    /// assert_eq!(cfg.gap().unwrap(), 0.1);
    /// assert!(cfg.validate().is_ok());
    /// // The square scene has no trap symbols.
    /// let square = lorentz_gas::scenes::spec::SceneSpec::parse("square", None, Some("1/4")).unwrap();
    /// let cfg = HopsConfig::new(Table { scene: square, motion: Default::default() });
    /// assert!(matches!(cfg.validate(), Err(lorentz_gas::Error::Lacks { .. })));
    /// ```
    pub fn new(table: Table) -> Self {
        HopsConfig {
            table,
            collisions: 200_000_000,
            batches: 16,
            order: 4,
            seed: 1,
            run: 0,
        }
    }

    /// The gap as its nearest double (what the `f64` trajectories run at).
    ///
    /// # Errors
    /// A table other than the triangular gas without a field.
    pub fn gap(&self) -> Result<f64, Error> {
        crate::estimators::straight_gap(&self.table, "hops")
    }

    /// Checks before any work: the triangular gas without a field at 0 < w < w∞ (as typed),
    /// 1 ≤ `order` ≤ [`crate::scenes::symbols::MAX_ORDER`], `batches` ≥ 2, at least
    /// [`min_collisions_per_batch`] collisions per batch.
    ///
    /// # Errors
    /// Another scene ([`Error::Lacks`] trap symbols), a field, and each parameter out of range.
    pub fn validate(&self) -> Result<(), Error> {
        self.table.motion_taken_by("hops")?;
        let w = crate::estimators::diffusive_gap(&self.table, "hops")?;
        let (collisions, batches, order) = (self.collisions, self.batches, self.order);
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
            return Err(Error::parameter(
                "collisions",
                collisions,
                format!(
                    "too few for {batches} batches at w = {w}: the hop-level Green–Kubo \
                     estimator needs at least {min} collisions per batch ({} hops of pi/(3w) \
                     collisions each), i.e. collisions >= {}",
                    8 * MAX_LAG,
                    min.saturating_mul(batches as u64)
                ),
            ));
        }
        crate::engine::check_trajectory_length(
            collisions.div_ceil(batches as u64),
            "batches",
            batches,
        )?;
        crate::engine::parallel::check_batches("batches", batches)
    }
}

/// Hop statistics along lattice trajectories (the CLI's `hops --json`).
#[allow(non_snake_case)]
#[derive(Debug, Clone, Serialize, Deserialize)]
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
    /// The nine two-symbol probabilities, by sequence (`"zl"`: z then l; empty below order 2).
    pub pairs: BTreeMap<String, f64>,
    /// Their standard errors, by sequence.
    pub pairs_err: BTreeMap<String, f64>,
    /// Sequence probabilities of every length 1 … order, by sequence (the length of the name is
    /// the length of the sequence; the probabilities of one length sum to 1).
    pub sequences: BTreeMap<String, f64>,
    /// Their standard errors, by sequence.
    pub sequences_err: BTreeMap<String, f64>,
    /// Largest |z-score| of the symmetries p(s) = p(mirror s) and p(s) = p(reverse(mirror s)),
    /// each paired over the batches (the per-batch differences of the two frequencies).
    pub symmetry_max_z: f64,
    /// How many distinct symmetry pairs were compared (those whose frequencies differ in some
    /// batch).
    #[serde(default)]
    pub symmetry_comparisons: usize,
    /// The bound on `symmetry_max_z`: the Student-t (batches − 1 dof) quantile at the 4σ tail
    /// probability over `symmetry_comparisons` (Bonferroni), so a run whose symmetries hold
    /// exceeds it with probability below 6.3·10⁻⁵.
    #[serde(default)]
    pub symmetry_bound: f64,
    /// Hop-level Green–Kubo D = D_MZ (1 + 2 Σ_{j≤J} C_j) ([`green_kubo::HOP_TRUNCATION`]).
    pub D_GK: f64,
    /// Its standard error over the independent batches.
    pub D_GK_err: f64,
    /// The Green–Kubo window J (number of lags summed).
    pub gk_window: usize,
    /// Machta–Zwanzig D.
    pub D_MZ: f64,
    /// Hop-direction correlations C_1 … C_J (J = `gk_window`; element j − 1 is lag j), batch means.
    pub correlations: Vec<f64>,
    /// Their standard errors, lag by lag.
    pub correlations_err: Vec<f64>,
    /// Complete trap visits observed.
    pub visits: u64,
    /// Collisions simulated.
    pub collisions: u64,
    /// The configuration that produced the result (what `lorentz report` re-runs).
    pub config: HopsConfig,
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
        let m: Vec<(&String, &f64)> = self
            .sequences
            .iter()
            .filter(|(name, _)| name.chars().count() == k)
            .collect();
        if k == 0 || m.is_empty() {
            return Err(Error::Failed(format!(
                "no sequences of length {k} were counted"
            )));
        }
        let mut p = vec![0.0; 3usize.pow(k as u32)];
        for (name, v) in m {
            p[parse_sequence_index(name, k)?] = *v;
        }
        crate::theory::sequences::SequenceProbabilities::from_weights(k, p)
    }
}

/// Fewest collisions per batch [`run`] accepts: on average 8·[`MAX_LAG`] hops
/// (π/(3w) collisions each), twice the 4·J_max hops the Green–Kubo estimator needs per
/// sequence, so that a batch falls short of them with negligible probability.
pub fn min_collisions_per_batch(w: f64) -> Result<u64, Error> {
    let g = Geometry::new(w)?;
    Ok((8.0 * MAX_LAG as f64 * g.collisions_per_hop()).ceil() as u64)
}

/// Runs `cfg.batches` lattice trajectories of `cfg.collisions` collisions in all and collects
/// the hop statistics up to sequences of length `cfg.order` and the hop-level Green–Kubo D. The
/// same bits on every engine and at every thread count.
///
/// `options.progress` receives the collisions done, in increments of up to 2²⁰ per batch,
/// summing to the report's `collisions`.
///
/// # Errors
/// An invalid configuration or options ([`HopsConfig::validate`]), before any work.
pub fn run(cfg: &HopsConfig, options: &RunOptions) -> Result<HopsReport, Error> {
    run_with_batches(cfg, options).map(|(report, _)| report)
}

/// [`run`], and each batch's statistics (in batch order) for the errors of quantities derived
/// from the tables ([`jackknife`]).
fn run_with_batches(
    cfg: &HopsConfig,
    options: &RunOptions,
) -> Result<(HopsReport, Vec<Hops>), Error> {
    cfg.validate()?;
    options.validate()?;
    crate::engine::work::Work::new("hops", &["collisions"], cfg.collisions as f64)
        .simd()
        .check(options.threads)?;
    let uses = [
        RunOption::Engine,
        RunOption::Resume,
        RunOption::CheckpointEvery,
    ];
    options.refuse_unused("hops", &uses)?;
    let (w, collisions, batches) = (cfg.gap()?, cfg.collisions, cfg.batches);
    let (order, seed) = (cfg.order, cfg.seed);
    let threads = options.threads;
    let (res, resolved) = measure(cfg, options)?;
    let g = Geometry::new(w)?;
    let d_mz = g.d_mz();
    let (tables, zmax, comparisons) = sequence_tables(&res, order);
    let symmetry_bound =
        crate::statistics::comparison::largest_of_bound((res.len().max(2) - 1) as f64, comparisons);
    let p_bs = tables[0]["z"];
    let none = BTreeMap::new();
    let pairs = tables.get(1).unwrap_or(&none);
    let all: BTreeMap<String, Estimate> = tables
        .iter()
        .flatten()
        .map(|(k, e)| (k.clone(), *e))
        .collect();
    let p_cf = est(&res
        .iter()
        .map(|h| h.collisionless as f64 / h.visits.max(1) as f64)
        .collect::<Vec<_>>());
    let dirs: Vec<HopCorrelations> = res.iter().map(|h| h.directions.clone()).collect();
    let gk = green_kubo::estimate(&dirs, green_kubo::HOP_TRUNCATION)?;
    let correlations: Vec<Estimate> = (1..=gk.truncation)
        .map(|j| est(&dirs.iter().map(|d| d.correlation(j)).collect::<Vec<_>>()))
        .collect();
    let report = HopsReport {
        w,
        p_bs: p_bs.value,
        p_bs_err: p_bs.err,
        p_cf: p_cf.value,
        p_cf_err: p_cf.err,
        pairs: values(pairs),
        pairs_err: errors(pairs),
        sequences: values(&all),
        sequences_err: errors(&all),
        symmetry_max_z: zmax,
        symmetry_comparisons: comparisons,
        symmetry_bound,
        D_GK: d_mz * gk.d_over_d_mz,
        D_GK_err: d_mz * gk.se,
        gk_window: gk.truncation,
        D_MZ: d_mz,
        correlations: correlations.iter().map(|e| e.value).collect(),
        correlations_err: correlations.iter().map(|e| e.err).collect(),
        visits: res.iter().map(|h| h.visits).sum(),
        collisions,
        config: cfg.clone(),
        meta: RunMeta::new(
            Some(seed),
            Some(batches as u64),
            Precision::F64,
            Some(threads),
        )
        .with_engine(resolved),
    };
    Ok((report, res))
}

/// The values of a table of estimates.
fn values(m: &BTreeMap<String, Estimate>) -> BTreeMap<String, f64> {
    m.iter().map(|(k, e)| (k.clone(), e.value)).collect()
}

/// The standard errors of a table of estimates.
fn errors(m: &BTreeMap<String, Estimate>) -> BTreeMap<String, f64> {
    m.iter().map(|(k, e)| (k.clone(), e.err)).collect()
}

/// Kind of the records of a hops checkpoint.
const CHECKPOINT_KIND: &str = "hop trajectories";

/// Runs the configuration's trajectories on the resolved engine: the hop statistics of each
/// batch, in batch order, and the engine that ran them. With `options.resume`, finished batches
/// and (every `options.checkpoint_every`) the trajectories in flight are kept there, and work
/// already there continues, to the uninterrupted bits.
fn measure(cfg: &HopsConfig, options: &RunOptions) -> Result<(Vec<Hops>, Resolved), Error> {
    let (w, collisions, batches) = (cfg.gap()?, cfg.collisions, cfg.batches);
    let (order, seed, run) = (cfg.order, cfg.seed, cfg.run);
    let (threads, progress) = (options.threads, options.progress);
    let resolved = options.engine.resolve(true)?;
    let lat = TriangularLattice::new(w)?;
    let start = |b: u32| {
        equilibrium_state(
            lat.trap(),
            &mut StreamKey::new(seed, Purpose::Trajectory, b as u64)
                .in_run(run)
                .rng(),
        )
    };
    let jobs: Vec<Quota> = (0..batches)
        .map(|index| Quota {
            run,
            index,
            collisions: share(collisions, batches, index),
        })
        .collect();
    let meta = RunMeta::new(Some(seed), Some(batches as u64), Precision::F64, None);
    let fits = |_: &Quota, h: &Hops| h.order() == order;
    let keep = Keeper::<Hops, Hops>::open(
        options.resume.as_deref(),
        CHECKPOINT_KIND,
        cfg,
        Some(meta),
        &jobs,
        Some(options.checkpoint_every),
        &fits,
    )?
    .watching(options.stop.as_ref());
    recheck_one_batch(&keep, &jobs, &lat, &start, order, options)?;
    progress(keep.collisions_done(&jobs));
    let todo: Vec<Quota> = jobs.into_iter().filter(|j| !keep.is_finished(j)).collect();
    let new: Vec<Hops> = match resolved {
        Resolved::Scalar => par_batches(threads, todo.len() as u32, |k| {
            let j = &todo[k as usize];
            let mut h = HopLanes::new(order, 1)?;
            drive_kept(&lat, (), j, || start(j.index), &mut h, &keep, progress)?;
            let r = h.into_lanes().remove(0);
            keep.finish(j, &r)?;
            Ok(r)
        })?,
        Resolved::Simd(path) => par_chunks(threads, todo.len(), BLOCK, |r| {
            let js = &todo[r];
            let mut h = HopLanes::new(order, BLOCK)?;
            let begin = |l: usize| start(js[l].index);
            run_block_kept(path, lat.trap(), js, begin, &mut h, &keep, progress)?;
            let mut lanes = h.into_lanes();
            lanes.truncate(js.len());
            for (j, x) in js.iter().zip(&lanes) {
                keep.finish(j, x)?;
            }
            Ok(lanes)
        })?,
    };
    let mut all: Vec<(u32, Hops)> = keep.finished_by_index().collect();
    all.extend(todo.iter().map(|j| j.index).zip(new));
    all.sort_by_key(|(i, _)| *i);
    Ok((all.into_iter().map(|(_, h)| h).collect(), resolved))
}

/// Checks one finished batch of `keep`, drawn at random (operating-system entropy), on the
/// scalar engine (the same bits as the SIMD one) from its seed to its first mark and from its
/// second mark to its end, and refuses the checkpoint unless its hop statistics are the recorded
/// ones: digests stop accidents, not someone who recomputes them (`proofs-notes/checkpoints.md`,
/// claim 3).
fn recheck_one_batch(
    keep: &Keeper<Hops, Hops>,
    jobs: &[Quota],
    lat: &TriangularLattice<f64>,
    start: &dyn Fn(u32) -> crate::scenes::lattice::LatticeState<f64>,
    order: usize,
    options: &RunOptions,
) -> Result<(), Error> {
    let run = |j: &Quota, k: &Keeper<Hops, Hops>| -> Result<Hops, Error> {
        let mut h = HopLanes::new(order, 1)?;
        drive_kept(lat, (), j, || start(j.index), &mut h, k, &|_| {})?;
        Ok(h.into_lanes().remove(0))
    };
    let json = |h: &Hops| serde_json::to_value(h).ok();
    let same = |a: &Hops, b: &Hops| json(a).is_some() && json(a) == json(b);
    let stop = options.stop.as_ref();
    let at = (options.resume.as_deref(), "hop statistics");
    crate::engine::checkpoint::recheck_one_batch(keep, jobs, stop, &run, &same, at)
}

/// The sequence probabilities of every length 1 … `order` (batch means and errors by name), and
/// the largest |z-score| of the mirror and reversal symmetries.
/// The sequence tables of every length, the largest symmetry |z| and how many distinct pairs it
/// is the largest of.
fn sequence_tables(res: &[Hops], order: usize) -> (Vec<BTreeMap<String, Estimate>>, f64, usize) {
    let mut sequences = Vec::new();
    let mut zmax: f64 = 0.0;
    let mut pairs = std::collections::BTreeSet::new();
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
                    pairs.insert((k, code.min(other), code.max(other)));
                }
            }
        }
        sequences.push(m);
    }
    (sequences, zmax, pairs.len())
}
