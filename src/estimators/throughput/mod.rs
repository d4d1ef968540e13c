//! Engine throughput (the CLI's `bench`): events only, no observables. Each thread runs one
//! trajectory (scalar engine) or one block of [`BLOCK`] trajectories (SIMD engine); in a
//! magnetic field (`lorentz bench --field`) one trajectory on arcs; under the thermostatted
//! electric field (`lorentz bench --electric`, [`thermostat`]) beside straight flights.

mod arcs;
mod check;
pub mod costs;
pub mod end_to_end;
pub mod long_flights;
mod tables;
pub mod thermostat;

pub use arcs::OracleFloor;
pub use tables::TableBench;

use std::time::Instant;

use check::{Checked, check};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::bound::{self, DividerBound};
use crate::engine::metadata::RunMeta;
use crate::engine::observe::{CROSSING_CODE, EventLanes, Nothing, Observer};
use crate::engine::options::RunOptions;
use crate::engine::parallel::thread_pool;
use crate::engine::simd::BLOCK;
use crate::engine::{Resolved, drive, run_block};
use crate::estimators::diffusion::DiffusionConfig;
use crate::kernel::trap::Trap;
use crate::numbers::lanes::Lanes;
use crate::numbers::precision::{AtPrecision, Precision};
use crate::numbers::real::Real;
use crate::observers::counters::CounterLanes;
use crate::observers::hops::HopLanes;
use crate::observers::msd::Msd;
use crate::scenes::lattice::{LatticeState, TriangularLattice};
use crate::scenes::sampling::stream;
use crate::scenes::spec::Table;
use crate::scenes::triangular::equilibrium_state;
use crate::scenes::triangular::geometry::Geometry;

/// Throughput measurement: the median of several timed repetitions.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Throughput {
    /// Gap w.
    pub w: f64,
    /// Collisions of each thread in each repetition (shared out over the thread's trajectories).
    pub collisions_per_thread: u64,
    /// Number of repetitions.
    pub repetitions: usize,
    /// Threads, each running one trajectory (scalar) or one block of trajectories (SIMD).
    pub threads: usize,
    /// Trajectories per thread (1 for the scalar engine, [`BLOCK`] for the SIMD engine).
    pub trajectories_per_thread: usize,
    /// What was observed besides the crossing count.
    pub observe: Observe,
    /// Median collisions per wall-clock second over the repetitions (all threads together).
    pub collisions_per_second: f64,
    /// Median collisions per second per thread.
    pub collisions_per_second_per_thread: f64,
    /// Median nanoseconds per collision on one thread.
    pub ns_per_collision: f64,
    /// Every repetition's collisions per second (all threads), in order.
    pub samples: Vec<f64>,
    /// Crossings per collision seen (to compare event counts across implementations).
    pub crossings_per_collision: f64,
    /// The SIMD engine's floor on this machine, from its divide/square-root unit (null for the
    /// scalar engine and the portable path).
    pub divider_bound: Option<BoundReport>,
    /// The field of an arc benchmark (absent for straight flights).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub field: Option<f64>,
    /// With `straight_beside`: the straight engine timed in alternation with the arcs, in the
    /// same run (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub straight: Option<Beside>,
    /// With `oracle_floor`: the SIMD arc engine against its winner-only floor (absent
    /// otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub oracle: Option<OracleFloor>,
    /// With a table given as data: its straight flights timed beside the triangular gas's, in
    /// the same run (absent otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub table: Option<TableBench>,
    /// With `diffusion_beside`: `lorentz diffusion` in the field end to end, timed in alternation
    /// with the arcs in the same run (absent otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub diffusion: Option<end_to_end::EndToEnd>,
    /// Version, seed, precision, engine, threads, command line.
    pub meta: RunMeta,
}

/// The straight engine timed beside an arc benchmark: repetition i of the straight flights runs
/// right after repetition i of the arcs, on the same threads and engine, so that both see the
/// same machine.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Beside {
    /// Every straight repetition's collisions per second (all threads), in order.
    pub samples: Vec<f64>,
    /// Their median per thread.
    pub collisions_per_second_per_thread: f64,
    /// The arcs' median over the straight flights' (per thread).
    pub arcs_over_straight: f64,
    /// The median over repetitions of each pair's ratio (arcs over straight), less sensitive to
    /// a machine whose speed drifts during the run.
    pub paired_ratio: f64,
}

/// The divider's bound against the engine's measured time.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BoundReport {
    /// The unit's figures, measured at start-up ([`crate::engine::bound::measure`]).
    #[serde(flatten)]
    pub unit: DividerBound,
    /// The bound per collision: per lane-event × (1 + crossings per collision).
    pub ns_per_collision: f64,
    /// The bound over the engine's median time per collision (1 = at the bound).
    pub fraction: f64,
}

/// A winner-only floor's times beside the full search's on the same tape, one thread: what the
/// arc engine's and the thermostat's floors share ([`OracleFloor`], [`ThermostatFloor`]).
///
/// [`ThermostatFloor`]: thermostat::ThermostatFloor
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloorTimes {
    /// The full search's median nanoseconds per collision over the tape.
    pub full_ns_per_collision: f64,
    /// The winner-only search's.
    pub floor_ns_per_collision: f64,
    /// Its collisions per second (one thread): 10⁹ / `floor_ns_per_collision`.
    pub floor_collisions_per_second: f64,
    /// The median over repetitions of each pair's ratio, floor over full time.
    pub paired_ratio: f64,
}

impl FloorTimes {
    /// From each repetition's nanoseconds per collision of the full and the winner-only pass.
    pub fn of(full: &[f64], floor: &[f64]) -> Self {
        let ratio: Vec<f64> = floor.iter().zip(full).map(|(a, b)| a / b).collect();
        let floor_ns = median(floor);
        FloorTimes {
            full_ns_per_collision: median(full),
            floor_ns_per_collision: floor_ns,
            floor_collisions_per_second: 1e9 / floor_ns,
            paired_ratio: median(&ratio),
        }
    }
}

pub(super) fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(|a, b| a.total_cmp(b));
    let n = s.len();
    if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

/// Most repetitions: the median is settled long before.
pub const MAX_REPETITIONS: usize = 1000;

/// Timed repetitions of `threads` trajectories on number type `T`.
struct TimeRuns<'a> {
    engine: Resolved,
    observe: Observe,
    field: Option<f64>,
    beside: bool,
    w: f64,
    /// The gap as typed, rounded once at the working precision.
    w_exact: Option<&'a str>,
    seed: u64,
    collisions: u64,
    reps: usize,
    threads: usize,
    progress: &'a (dyn Fn(u64) + Sync),
    /// A table timed beside (`f64`): its runs, and its repetitions' rates and crossings.
    table: Option<&'a mut (tables::TableRuns, Vec<f64>, u64)>,
    /// The diffusion analysis in the field, timed beside.
    diffusion: Option<&'a mut end_to_end::DiffusionRuns>,
}

impl AtPrecision for TimeRuns<'_> {
    /// Each repetition's rate, crossings per collision, and the straight repetitions' rates.
    type Output = Result<(Vec<f64>, f64, Vec<f64>), Error>;
    fn at<T: Real>(mut self, ctx: T::Ctx) -> Self::Output {
        let trap64 = Trap::new(self.w)?;
        let w = crate::numbers::exact::param_at::<T>(ctx, self.w, self.w_exact)?;
        let lat = TriangularLattice::new(w)?;
        let lanes = lanes(self.engine);
        let mut states = match self.field {
            Some(b) => arcs::starts::<T>(ctx, &trap64, self.seed, self.threads, lanes, b)?,
            None => starts::<T>(ctx, &trap64, self.seed, self.threads, lanes),
        };
        let pool = thread_pool(self.threads)?;
        let n = self.collisions;
        let engine = self.engine;
        let observe = self.observe;
        let field = self.field.map(|b| T::from_f64(ctx, b));
        // Each trajectory makes ⌊n/lanes⌋ collisions per repetition.
        let per_rep = n / lanes as u64 * (lanes * self.threads) as u64;
        let go = |states: &mut Vec<Vec<LatticeState<T>>>, n: u64| match &field {
            Some(b) => arcs::advance(&pool, engine, &lat, &trap64, states, n, b),
            None => advance(&pool, engine, observe, &lat, &trap64, states, n),
        };
        let mut straight = self
            .beside
            .then(|| starts::<T>(ctx, &trap64, self.seed, self.threads, lanes));
        let plain = |states: &mut Vec<Vec<LatticeState<T>>>, n: u64| {
            advance(&pool, engine, observe, &lat, &trap64, states, n)
        };
        // One untimed warm-up of a tenth of the length.
        go(&mut states, (n / 10).max(1))?;
        if let Some(s) = straight.as_mut() {
            plain(s, (n / 10).max(1))?;
        }
        let mut table = self.table;
        if let Some(t) = table.as_mut() {
            t.0.advance(&pool, (n / 10).max(1))?;
        }
        let (mut out, mut beside) = (Vec::with_capacity(self.reps), Vec::new());
        let mut hops = 0;
        for _ in 0..self.reps {
            let t0 = Instant::now();
            hops = go(&mut states, n)?;
            out.push(per_rep as f64 / t0.elapsed().as_secs_f64());
            if let Some(s) = straight.as_mut() {
                let t0 = Instant::now();
                plain(s, n)?;
                beside.push(per_rep as f64 / t0.elapsed().as_secs_f64());
            }
            if let Some(t) = table.as_mut() {
                let t0 = Instant::now();
                t.2 = t.0.advance(&pool, n)?;
                t.1.push(per_rep as f64 / t0.elapsed().as_secs_f64());
            }
            if let Some(d) = self.diffusion.as_mut() {
                d.time()?;
            }
            (self.progress)(1);
        }
        Ok((out, hops as f64 / per_rep as f64, beside))
    }
}

/// The benchmark's starts: thread k runs trajectories k·`lanes` … (k+1)·`lanes` − 1 of the
/// seed's streams, from equilibrium.
pub(super) fn starts<T: Real>(
    ctx: T::Ctx,
    trap64: &Trap<f64>,
    seed: u64,
    threads: usize,
    lanes: usize,
) -> Vec<Vec<LatticeState<T>>> {
    (0..threads)
        .map(|k| {
            (0..lanes)
                .map(|l| {
                    let s64 = equilibrium_state(trap64, &mut stream(seed, (k * lanes + l) as u64));
                    let mut s = LatticeState::convert_from_f64(ctx, &s64);
                    s.flight.normalise_speed();
                    s
                })
                .collect()
        })
        .collect()
}

/// Trajectories per thread: one on the scalar engine, a block of [`BLOCK`] on the SIMD engine.
pub(super) fn lanes(engine: Resolved) -> usize {
    match engine {
        Resolved::Scalar => 1,
        Resolved::Simd(_) => BLOCK,
    }
}

/// Every thread's trajectories (`states[k]`, on `pool`) continued by `n` collisions and watched
/// with `observe` ([`run_thread`]); returns the crossings made.
pub(super) fn advance<T: Real>(
    pool: &rayon::ThreadPool,
    engine: Resolved,
    observe: Observe,
    lat: &TriangularLattice<T>,
    trap64: &Trap<f64>,
    states: &mut [Vec<LatticeState<T>>],
    n: u64,
) -> Result<u64, Error> {
    par_blocks(pool, states, |block| {
        run_thread(engine, observe, lat, trap64, block, n)
    })
}

/// The sum of `f` over every thread's block of trajectories, one block a task on `pool`.
pub(super) fn par_blocks<T: Real>(
    pool: &rayon::ThreadPool,
    states: &mut [Vec<LatticeState<T>>],
    f: impl Fn(&mut Vec<LatticeState<T>>) -> Result<u64, Error> + Sync + Send,
) -> Result<u64, Error> {
    pool.install(|| {
        states
            .par_iter_mut()
            .map(f)
            .collect::<Result<Vec<u64>, Error>>()
            .map(|v| v.iter().sum())
    })
}

/// What the benchmark watches besides the engine's own crossing count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Observe {
    /// Nothing: the bare engine.
    #[default]
    None,
    /// The event counters (collisions, crossings, compensated time, longest flight).
    Counters,
    /// The MSD at the default fit windows' lags.
    Msd,
    /// Counters and MSD: what `lorentz diffusion` watches.
    Diffusion,
    /// The hop symbols and hop-direction correlations of `lorentz hops` (order 3).
    Hops,
}

/// One thread's share of a repetition: `n` collisions over its trajectories, continuing them
/// and watching them with `observe`; returns the crossings made.
fn run_thread<T: Real>(
    engine: Resolved,
    observe: Observe,
    lat: &TriangularLattice<T>,
    trap64: &Trap<f64>,
    block: &mut [LatticeState<T>],
    n: u64,
) -> Result<u64, Error> {
    let lanes = lanes(engine);
    let w = trap64.w;
    let msd = || -> Result<Msd, Error> {
        let tau = Geometry::new(w)?.hop_time();
        Ok(Msd::new(
            tau,
            &DiffusionConfig::new(w).lags(),
            lat.basis_f64(),
            lanes,
        ))
    };
    match observe {
        Observe::None => run_observed(engine, lat, trap64, block, n, Nothing),
        Observe::Counters => run_observed(engine, lat, trap64, block, n, CounterLanes::new(lanes)),
        Observe::Msd => run_observed(engine, lat, trap64, block, n, msd()?),
        Observe::Diffusion => run_observed(
            engine,
            lat,
            trap64,
            block,
            n,
            (CounterLanes::new(lanes), msd()?),
        ),
        Observe::Hops => run_observed(engine, lat, trap64, block, n, HopLanes::new(3, lanes)?),
    }
}

fn run_observed<T: Real, O: Observer<1> + Observer<BLOCK>>(
    engine: Resolved,
    lat: &TriangularLattice<T>,
    trap64: &Trap<f64>,
    block: &mut [LatticeState<T>],
    n: u64,
    obs: O,
) -> Result<u64, Error> {
    let mut obs = (CrossingCount(0), obs);
    match engine {
        Resolved::Scalar => {
            let each = n / block.len() as u64;
            for s in block.iter_mut() {
                drive(lat, s, each, &mut obs, &|_| {})?;
            }
            Ok(obs.0.0)
        }
        Resolved::Simd(path) => {
            // The SIMD engine runs f64 only (`Engine::resolve` refuses otherwise), so the
            // conversions below are exact copies.
            let mut s64: Vec<LatticeState<f64>> = block.iter().map(|s| s.to_f64()).collect();
            let quotas = vec![n / block.len() as u64; block.len()];
            run_block(path, trap64, &mut s64, &quotas, &mut obs, &|_| {})?;
            for (s, x) in block.iter_mut().zip(&s64) {
                *s = LatticeState::convert_from_f64(s.flight.pos.x.ctx(), x);
            }
            Ok(obs.0.0)
        }
    }
}

/// Counts crossings only — the cheapest possible observer, so that the benchmark times the
/// engine (and the counts show that the same events were made).
struct CrossingCount(u64);

impl<const L: usize> Observer<L> for CrossingCount {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        for e in steps {
            let mut o = 0;
            let mut collided = 0u64;
            while o < L {
                let coll = V::load(&e.code[o..]).lt(V::splat(CROSSING_CODE));
                collided |= V::bits(coll) << o;
                o += V::WIDTH;
            }
            self.0 += (e.live_bits & !collided).count_ones() as u64;
        }
    }
}

/// What a throughput measurement times.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThroughputConfig {
    /// The triangular gas at a gap w > 0, without a field (the bench's own `field` flies arcs):
    /// `f64` runs use the double nearest the gap, MPFR runs the gap as typed rounded once (in
    /// JSON `w` and `w_exact`).
    #[serde(flatten)]
    pub table: Table,
    /// Number type.
    pub precision: Precision,
    /// Which observers run beside the engine.
    pub observe: Observe,
    /// Collisions of each thread in each repetition.
    pub collisions_per_thread: u64,
    /// Repetitions, 1 to [`MAX_REPETITIONS`] (the median is reported).
    pub repetitions: usize,
    /// Seed of the equilibrium starts.
    pub seed: u64,
    /// A magnetic field B: the kernel then flies arcs (`f64`, no observers, on the SIMD arc
    /// engine or the scalar kernel as the engine option resolves; starts on pinned orbits are
    /// drawn again). `None` or 0: straight flights.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub field: Option<f64>,
    /// With a field: time the straight engine too, each repetition right after the arcs' (the
    /// speed of arcs measured side by side with straight flights in one run).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub straight_beside: bool,
    /// With a field on the SIMD engine: time the arc engine fed each event's winner from a tape
    /// of its own run (computing only that disk and that edge) beside the full engine on the
    /// same tape, one thread — the speed no choice of the next event in advance can beat with
    /// this kernel's arithmetic ([`OracleFloor`]).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub oracle_floor: bool,
    /// A table given as data, timed beside the triangular gas at `w` (straight flights, `f64`,
    /// no observers; the same engine, its cell on the SIMD lanes): [`TableBench`] (in JSON
    /// `table`).
    #[serde(default, rename = "table", skip_serializing_if = "Option::is_none")]
    pub table_beside: Option<crate::scenes::table::spec::TableSpec>,
    /// With a field: time `lorentz diffusion` in the field end to end beside the engine, each
    /// repetition right after the arcs', with as many collisions on the same threads
    /// ([`end_to_end::EndToEnd`]).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub diffusion_beside: bool,
}

impl ThroughputConfig {
    /// The command line's defaults on `table`: f64, bare engine, 2·10⁷ collisions, 7
    /// repetitions, seed 1.
    pub fn new(table: Table) -> Self {
        ThroughputConfig {
            table,
            precision: Precision::F64,
            observe: Observe::None,
            collisions_per_thread: 20_000_000,
            repetitions: 7,
            seed: 1,
            field: None,
            straight_beside: false,
            oracle_floor: false,
            table_beside: None,
            diffusion_beside: false,
        }
    }
}

/// Times `cfg.repetitions` repetitions of `cfg.collisions_per_thread` collisions on each of
/// `options.threads` threads (one trajectory each on the scalar engine, a block of [`BLOCK`] on
/// the SIMD engine, `options.engine`), continuing equilibrium starts. `options.progress`
/// receives finished repetitions.
///
/// # Errors
/// A gap that is not positive, no collisions, repetitions out of range, or invalid options.
pub fn run(cfg: &ThroughputConfig, options: &RunOptions) -> Result<Throughput, Error> {
    let Checked {
        w,
        field,
        resolved,
        oracle: oracle_path,
    } = check(cfg, options)?;
    let ThroughputConfig {
        precision,
        observe,
        collisions_per_thread: collisions,
        repetitions: reps,
        seed,
        straight_beside,
        ..
    } = *cfg;
    let mut table = cfg
        .table_beside
        .as_ref()
        .map(|spec| {
            let runs =
                tables::TableRuns::new(spec, resolved, seed, (options.threads, lanes(resolved)))?;
            Ok::<_, Error>((runs, Vec::new(), 0))
        })
        .transpose()?;
    let (threads, progress) = (options.threads, options.progress);
    let per_rep = collisions / lanes(resolved) as u64 * (lanes(resolved) * threads) as u64;
    let mut diffusion = end_to_end::DiffusionRuns::beside(cfg, field, per_rep, options)?;
    let unit = divider_unit(resolved, field);
    let (samples, cpc, beside) = precision.dispatch(TimeRuns {
        engine: resolved,
        observe,
        field,
        beside: straight_beside,
        w,
        w_exact: cfg.table.gap_text(),
        seed,
        collisions,
        reps,
        threads,
        progress,
        table: table.as_mut(),
        diffusion: diffusion.as_mut(),
    })?;
    let m = median(&samples);
    let table = table.map(|(runs, rates, crossings)| {
        runs.report(rates, &samples, threads, crossings as f64 / per_rep as f64)
    });
    let straight = straight_beside.then(|| beside_report(&samples, beside, threads));
    let diffusion = diffusion.map(|d| d.report(&samples));
    let oracle = oracle_path
        .map(|(b, path)| arcs::oracle_floor(path, w, b, seed, collisions, reps))
        .transpose()?;
    let ns_per_collision = 1e9 * threads as f64 / m;
    let divider_bound = unit.map(|unit| divider_bound(unit, cpc, ns_per_collision));
    Ok(Throughput {
        w,
        collisions_per_thread: collisions,
        repetitions: reps,
        threads,
        observe,
        trajectories_per_thread: lanes(resolved),
        collisions_per_second: m,
        collisions_per_second_per_thread: m / threads as f64,
        ns_per_collision,
        samples,
        crossings_per_collision: cpc,
        divider_bound,
        field,
        straight,
        oracle,
        table,
        diffusion,
        meta: RunMeta::new(Some(seed), None, precision, Some(threads)).with_engine(resolved),
    })
}

/// The divider's bound `unit` against the engine's `ns_per_collision`, `cpc` crossings per
/// collision.
fn divider_bound(unit: DividerBound, cpc: f64, ns_per_collision: f64) -> BoundReport {
    let per_collision = unit.ns_per_event * (1.0 + cpc);
    BoundReport {
        unit,
        ns_per_collision: per_collision,
        fraction: per_collision / ns_per_collision,
    }
}

/// The divider bound of one event on the SIMD path `resolved` runs (none on the scalar engine):
/// the arc kernel's roots and divisions in a field, one root and two divisions without.
fn divider_unit(resolved: Resolved, field: Option<f64>) -> Option<DividerBound> {
    let (roots, divisions) = match field {
        Some(_) => (bound::ARC_ROOTS, bound::ARC_DIVISIONS),
        None => (1, 2),
    };
    resolved
        .simd()
        .and_then(|p| bound::measure(p, roots, divisions))
}

/// The straight repetitions' summary against the arcs' `samples`.
fn beside_report(samples: &[f64], straight: Vec<f64>, threads: usize) -> Beside {
    let ratios: Vec<f64> = samples.iter().zip(&straight).map(|(a, s)| a / s).collect();
    let m = median(&straight);
    Beside {
        collisions_per_second_per_thread: m / threads as f64,
        arcs_over_straight: median(samples) / m,
        paired_ratio: median(&ratios),
        samples: straight,
    }
}
