//! A table given as data timed beside the triangular gas (`lorentz bench --w W --table FILE`):
//! repetition i of the table's straight flights runs right after repetition i of the triangular
//! gas, on the same threads and engine (the table's generic cell on the SIMD lanes,
//! [`crate::engine::cells`], or its scalar kernel), so that both see the same machine.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::CrossingCount;
use crate::Error;
use crate::engine::{Resolved, drive, run_block};
use crate::kernel::cell::ConvexCell;
use crate::scenes::Scene;
use crate::scenes::lattice::{Lattice, LatticeState};
use crate::scenes::sampling::stream;
use crate::scenes::table::PeriodicTable;
use crate::scenes::table::spec::TableSpec;

/// The table's speed beside the triangular gas's, in one run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TableBench {
    /// The table ([`Scene::label`]).
    pub table: String,
    /// Every repetition's collisions per second (all threads), in order.
    pub samples: Vec<f64>,
    /// Their median per thread.
    pub collisions_per_second_per_thread: f64,
    /// The table's median over the triangular gas's.
    pub over_triangular: f64,
    /// The median over repetitions of each pair's ratio (table over triangular).
    pub paired_ratio: f64,
    /// Crossings per collision seen on the table.
    pub crossings_per_collision: f64,
}

/// The table's trajectories between repetitions: thread k's `lanes` starts from the invariant
/// measure (streams k·lanes … of the seed), continued repetition after repetition.
pub(super) struct TableRuns {
    table: PeriodicTable,
    lat: Lattice<f64, ConvexCell<f64>>,
    engine: Resolved,
    states: Vec<Vec<LatticeState<f64>>>,
}

impl TableRuns {
    /// The runs of `spec` on `engine` (the SIMD path runs the cell's lanes, which it must fit).
    ///
    /// # Errors
    /// A table refused, or a cell too large for the lanes on the SIMD engine.
    pub(super) fn new(
        spec: &TableSpec,
        engine: Resolved,
        seed: u64,
        (threads, lanes): (usize, usize),
    ) -> Result<Self, Error> {
        let table = PeriodicTable::new(spec)?;
        let lat = table.lattice::<f64>(())?;
        if engine.simd().is_some() {
            crate::engine::BlockKernel::check_lanes(lat.cell())?;
        }
        let states = (0..threads)
            .map(|k| {
                (0..lanes)
                    .map(|l| {
                        let mut s = table.sample(&mut stream(seed, (k * lanes + l) as u64));
                        s.flight.normalise_speed();
                        s
                    })
                    .collect()
            })
            .collect();
        Ok(TableRuns {
            table,
            lat,
            engine,
            states,
        })
    }

    /// Every thread's trajectories continued by `n` collisions (shared out over its lanes) on
    /// `pool`; returns the crossings made.
    pub(super) fn advance(&mut self, pool: &rayon::ThreadPool, n: u64) -> Result<u64, Error> {
        let (lat, engine) = (&self.lat, self.engine);
        pool.install(|| {
            self.states
                .par_iter_mut()
                .map(|block| {
                    let mut count = CrossingCount(0);
                    let each = n / block.len() as u64;
                    match engine {
                        Resolved::Scalar => {
                            for s in block.iter_mut() {
                                drive(lat, s, each, &mut count, &|_| {})?;
                            }
                        }
                        Resolved::Simd(path) => {
                            let quotas = vec![each; block.len()];
                            run_block(path, lat.cell(), block, &quotas, &mut count, &|_| {})?;
                        }
                    }
                    Ok(count.0)
                })
                .collect::<Result<Vec<u64>, Error>>()
                .map(|v| v.iter().sum())
        })
    }

    /// The report of the table's repetition rates `samples` beside the triangular gas's
    /// `triangular` (the same number, in the same order).
    pub(super) fn report(
        &self,
        samples: Vec<f64>,
        triangular: &[f64],
        threads: usize,
        crossings_per_collision: f64,
    ) -> TableBench {
        let ratios: Vec<f64> = samples.iter().zip(triangular).map(|(t, r)| t / r).collect();
        let m = super::median(&samples);
        TableBench {
            table: self.table.label(),
            collisions_per_second_per_thread: m / threads as f64,
            over_triangular: m / super::median(triangular),
            paired_ratio: super::median(&ratios),
            crossings_per_collision,
            samples,
        }
    }
}
