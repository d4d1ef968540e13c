//! What observation costs (`lorentz bench --observer-costs`): the engine bare and with each set
//! of observers, timed in turns on the same machine in one run, so that a drift of the machine's
//! speed moves every set alike. Each set continues its own copy of the same equilibrium starts,
//! so every set makes the same collisions and crossings (checked: the crossing counts must
//! agree).
//!
//! A round times every set once, in an order rotated by one set per round (so no set always
//! follows the same one); the cost of a set is the median over rounds of its time over the bare
//! engine's time in the same round, less 1.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::throughput::{MAX_REPETITIONS, Observe, advance, lanes, median, starts};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::{RunOption, RunOptions};
use crate::engine::parallel::thread_pool;
use crate::kernel::trap::Trap;
use crate::numbers::precision::Precision;
use crate::scenes::lattice::{LatticeState, TriangularLattice};
use crate::scenes::spec::Table;
use crate::scenes::triangular::geometry::Geometry;

/// The observer sets timed, the bare engine first.
pub const SETS: [Observe; 5] = [
    Observe::None,
    Observe::Counters,
    Observe::Msd,
    Observe::Diffusion,
    Observe::Hops,
];

/// What an observer-cost measurement times (in `f64`, on the engine of the run options).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObserverCostsConfig {
    /// The triangular gas at a gap w > 0, without a field (in JSON `w` and `w_exact`).
    #[serde(flatten)]
    pub table: Table,
    /// Collisions of each thread in each timed run.
    pub collisions_per_thread: u64,
    /// Repetitions (rounds), 1 to [`MAX_REPETITIONS`]; each times every set once.
    pub repetitions: usize,
    /// Seed of the equilibrium starts.
    pub seed: u64,
}

impl ObserverCostsConfig {
    /// The command line's defaults on `table`: 2·10⁷ collisions, 7 rounds, seed 1.
    pub fn new(table: Table) -> Self {
        ObserverCostsConfig {
            table,
            collisions_per_thread: 20_000_000,
            repetitions: 7,
            seed: 1,
        }
    }

    /// The gap as its nearest double (the runs are `f64`).
    ///
    /// # Errors
    /// A table other than the triangular gas without a field.
    pub fn gap(&self) -> Result<f64, Error> {
        crate::estimators::straight_gap(&self.table, "observer costs")
    }

    /// Checks the table, the gap, the collisions and the repetitions.
    ///
    /// # Errors
    /// Another scene ([`Error::Lacks`] trap symbols), a field, a gap that is not positive, no
    /// collisions, repetitions out of range.
    pub fn validate(&self) -> Result<(), Error> {
        self.table.motion_taken_by("observer costs")?;
        Geometry::new(self.gap()?)?;
        if self.collisions_per_thread == 0 {
            return Err(Error::Zero {
                what: "collisions_per_thread",
            });
        }
        if self.repetitions == 0 || self.repetitions > MAX_REPETITIONS {
            return Err(Error::out_of_range(
                "repetitions",
                self.repetitions,
                format!("use 1 to {MAX_REPETITIONS}"),
            ));
        }
        Ok(())
    }
}

/// One observer set's times.
#[derive(Debug, Clone, Serialize)]
pub struct ObserverCost {
    /// The set.
    pub observe: Observe,
    /// Median nanoseconds per collision on one thread.
    pub ns_per_collision: f64,
    /// Median over rounds of (this set's time / the bare engine's time in the same round) − 1
    /// (0 for the bare engine).
    pub over_bare: f64,
    /// Nanoseconds per collision of every round, in order.
    pub samples: Vec<f64>,
}

/// Every set's cost.
#[derive(Debug, Clone, Serialize)]
pub struct ObserverCosts {
    /// Gap w.
    pub w: f64,
    /// Collisions of each thread in each timed run.
    pub collisions_per_thread: u64,
    /// Rounds.
    pub rounds: usize,
    /// Threads, each running one trajectory (scalar) or one block of trajectories (SIMD).
    pub threads: usize,
    /// Crossings per collision (the same for every set).
    pub crossings_per_collision: f64,
    /// The sets, bare engine first ([`SETS`]).
    pub costs: Vec<ObserverCost>,
    /// Version, seed, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// Times every set of [`SETS`] in `cfg.repetitions` rounds (module documentation) on
/// `options.threads` threads and `options.engine`. `options.progress` receives finished rounds.
///
/// # Errors
/// An invalid configuration or options; a set whose crossings differ from the bare engine's
/// (the observers changed the dynamics: a bug).
pub fn run(cfg: &ObserverCostsConfig, options: &RunOptions) -> Result<ObserverCosts, Error> {
    options.accept("observer costs", &[RunOption::Engine])?;
    cfg.validate()?;
    let threads = options.threads;
    let engine = options.engine.resolve(true)?;
    let lanes = lanes(engine);
    let w = cfg.gap()?;
    let trap64 = Trap::new(w)?;
    let lat = TriangularLattice::new(w)?;
    let pool = thread_pool(threads)?;
    let n = cfg.collisions_per_thread;
    let per_run = n / lanes as u64 * (lanes * threads) as u64;
    let go = |observe: Observe, states: &mut Vec<Vec<LatticeState<f64>>>, n: u64| {
        advance(&pool, engine, observe, &lat, &trap64, states, n)
    };
    let mut states: Vec<_> = SETS
        .iter()
        .map(|_| starts::<f64>((), &trap64, cfg.seed, threads, lanes))
        .collect();
    let mut ns = vec![Vec::with_capacity(cfg.repetitions); SETS.len()];
    let mut crossings = vec![0u64; SETS.len()];
    for (k, s) in SETS.iter().zip(&mut states) {
        go(*k, s, (n / 10).max(1))?; // untimed warm-up
    }
    for r in 0..cfg.repetitions {
        for i in (0..SETS.len()).map(|i| (i + r) % SETS.len()) {
            let t0 = Instant::now();
            crossings[i] += go(SETS[i], &mut states[i], n)?;
            ns[i].push(1e9 * t0.elapsed().as_secs_f64() * threads as f64 / per_run as f64);
        }
        (options.progress)(1);
    }
    if let Some(i) = crossings.iter().position(|&c| c != crossings[0]) {
        return Err(Error::Failed(format!(
            "observing {:?} changed the crossings ({} against {} bare): the observers must not \
             change the dynamics",
            SETS[i], crossings[i], crossings[0]
        )));
    }
    let costs = SETS
        .iter()
        .zip(&ns)
        .map(|(&observe, t)| {
            let ratios: Vec<f64> = t.iter().zip(&ns[0]).map(|(a, b)| a / b - 1.0).collect();
            ObserverCost {
                observe,
                ns_per_collision: median(t),
                over_bare: median(&ratios),
                samples: t.clone(),
            }
        })
        .collect();
    Ok(ObserverCosts {
        w,
        collisions_per_thread: n,
        rounds: cfg.repetitions,
        threads,
        crossings_per_collision: crossings[0] as f64 / (per_run * cfg.repetitions as u64) as f64,
        costs,
        meta: RunMeta::new(Some(cfg.seed), None, Precision::F64, Some(threads)).with_engine(engine),
    })
}
