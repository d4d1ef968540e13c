//! The arc kernel's throughput (`lorentz bench --field B`): the generic cell kernel on arcs, one
//! trajectory per thread, events only.

use rayon::prelude::*;

use crate::Error;
use crate::engine::Engine;
use crate::engine::Resolved;
use crate::engine::SimdPath;
use crate::engine::arcs::{ArcBlock, WinnerTape, run_arc_block};
use crate::engine::simd::BLOCK;
use crate::kernel::flight::EventKind;
use crate::kernel::trap::Trap;
use crate::numbers::precision::Precision;
use crate::numbers::real::Real;
use crate::scenes::lattice::{Lattice, LatticeState, TriangularLattice};
use crate::scenes::magnetic::DiskLattice;
use crate::scenes::sampling::stream;
use crate::scenes::triangular::equilibrium_state;
use crate::theory::magnetic::{FieldGeometry, Orbit};

use super::{FloorTimes, Observe};

/// The longest tape of `--oracle-floor`, in steps (a step is one event of each of the [`BLOCK`]
/// lanes; the tape holds 8 bytes per lane and step: 32 MiB at most).
pub const MAX_TAPE_STEPS: usize = 1 << 18;

/// The SIMD arc engine against its winner-only floor ([`WinnerTape`]): one block of thread 0's
/// starts, one tape of its events, both engines run over it in turns, one thread.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct OracleFloor {
    /// Steps on the tape (one event of every lane each).
    pub steps: usize,
    /// Collisions over the tape (all lanes).
    pub collisions: f64,
    /// Events (collisions and crossings) over the tape (all lanes).
    pub events: f64,
    /// The full engine's time and that of the engine fed each event's winner.
    #[serde(flatten)]
    pub times: FloorTimes,
}

/// [`OracleFloor`] at gap `w` in the field `b` on `path`: a tape of ⌊`collisions`/[`BLOCK`]⌋
/// steps (1 to [`MAX_TAPE_STEPS`]) timed `reps` times; the fed engine's events are checked to
/// be the full engine's, bit for bit, on every repetition.
pub(super) fn oracle_floor(
    path: SimdPath,
    w: f64,
    b: f64,
    seed: u64,
    collisions: u64,
    reps: usize,
) -> Result<OracleFloor, Error> {
    let trap = Trap::<f64>::new(w)?;
    let states = starts::<f64>((), &trap, seed, 1, BLOCK, b)?.remove(0);
    let steps = (collisions / BLOCK as u64).clamp(1, MAX_TAPE_STEPS as u64) as usize;
    let tape = WinnerTape::record(&ArcBlock::new(path, trap.cell(), b, &states)?, steps)?;
    let (mut full, mut floor) = (Vec::new(), Vec::new());
    for _ in 0..reps {
        let t = tape.time()?;
        full.push(1e9 * t.full / tape.collisions());
        floor.push(1e9 * t.oracle / tape.collisions());
    }
    Ok(OracleFloor {
        steps,
        collisions: tape.collisions(),
        events: tape.events(),
        times: FloorTimes::of(&full, &floor),
    })
}

/// Refuses what an arc benchmark cannot do yet: MPFR, observers. The engine that runs: the
/// SIMD arc engine ([`crate::engine::arcs`]) where `engine` resolves to it, else the scalar one.
pub(super) fn check(
    b: f64,
    precision: Precision,
    observe: Observe,
    engine: Engine,
) -> Result<Resolved, Error> {
    if !b.is_finite() {
        return Err(Error::NotFinite { what: "field" });
    }
    if precision != Precision::F64 {
        return Err(Error::parameter(
            "precision",
            precision,
            "a bench in a field times the f64 arc kernel: leave it out",
        ));
    }
    if observe != Observe::None {
        return Err(Error::parameter(
            "observe",
            format!("{observe:?}").to_lowercase(),
            "a bench in a field times the bare arc kernel: leave it out",
        ));
    }
    engine.resolve(true)
}

/// `lanes` starts per thread from equilibrium (thread k: the seed's stream k, in order), each
/// drawn again from the same stream while it is on a localized orbit: a pinned one never
/// collides, and a skipping one makes several crossings per collision round its disk, so that
/// its lane would hold the whole block back (the block runs until its slowest lane has its
/// quota). A field run flies diffusing starts only, too.
pub(super) fn starts<T: Real>(
    ctx: T::Ctx,
    trap64: &Trap<f64>,
    seed: u64,
    threads: usize,
    lanes: usize,
    b: f64,
) -> Result<Vec<Vec<LatticeState<T>>>, Error> {
    let a = trap64.a;
    let lattice = DiskLattice::equal(a, 0.5, trap64.h, 1.0);
    let geometry = FieldGeometry::new(lattice, b)?;
    let lat64 = Lattice::from_kernel(trap64.clone());
    (0..threads)
        .map(|k| {
            let mut rng = stream(seed, k as u64);
            (0..lanes)
                .map(|_| {
                    for _ in 0..1_000_000 {
                        let s64 = equilibrium_state(trap64, &mut rng);
                        let p = lat64.world(&s64);
                        let sg = s64.cell.sign();
                        let (vx, vy) = (sg * s64.flight.vel.x, sg * s64.flight.vel.y);
                        if geometry.classify(p.x, p.y, vx, vy) == Orbit::Diffusing {
                            let mut s = LatticeState::convert_from_f64(ctx, &s64);
                            s.flight.normalise_speed();
                            return Ok(s);
                        }
                    }
                    Err(Error::Failed(
                        "no diffusing start in 10^6 draws: almost every orbit is localized at this field"
                            .into(),
                    ))
                })
                .collect()
        })
        .collect()
}

/// Every thread's trajectories continued by `n` collisions between them (each of a thread's
/// trajectories ⌊n/trajectories⌋) on arcs in the field `b`, on the scalar kernel or the SIMD
/// arc engine; returns the crossings made.
pub(super) fn advance<T: Real>(
    pool: &rayon::ThreadPool,
    engine: Resolved,
    lat: &TriangularLattice<T>,
    trap64: &Trap<f64>,
    states: &mut [Vec<LatticeState<T>>],
    n: u64,
    b: &T,
) -> Result<u64, Error> {
    pool.install(|| {
        states
            .par_iter_mut()
            .map(|block| match engine {
                Resolved::Scalar => {
                    let each = n / block.len() as u64;
                    scalar_block(lat, block, each, b)
                }
                Resolved::Simd(path) => {
                    // The SIMD engine runs f64 only (`Engine::resolve` with precision f64), so
                    // the conversions are exact copies.
                    let mut s64: Vec<LatticeState<f64>> =
                        block.iter().map(|s| s.to_f64()).collect();
                    let quotas = vec![n / block.len() as u64; block.len()];
                    let cell = trap64.cell();
                    let crossings =
                        run_arc_block(path, cell, b.to_f64(), &mut s64, &quotas, u64::MAX)?;
                    for (s, x) in block.iter_mut().zip(&s64) {
                        *s = LatticeState::convert_from_f64(s.flight.pos.x.ctx(), x);
                    }
                    Ok(crossings.iter().sum())
                }
            })
            .collect::<Result<Vec<u64>, Error>>()
            .map(|v| v.iter().sum())
    })
}

/// The scalar arc kernel: each trajectory of `block` continued by `n` collisions.
fn scalar_block<T: Real>(
    lat: &TriangularLattice<T>,
    block: &mut [LatticeState<T>],
    n: u64,
    b: &T,
) -> Result<u64, Error> {
    let mut crossings = 0;
    for s in block.iter_mut() {
        let mut done = 0;
        while done < n {
            let ev = lat
                .next_event_in_field(s, b)
                .ok_or_else(|| Error::Failed("a benchmark orbit has no next event".into()))?;
            lat.apply_in_field(s, &ev);
            match ev.kind {
                EventKind::Collision(_) => done += 1,
                EventKind::Crossing(_) => crossings += 1,
            }
        }
    }
    Ok(crossings)
}
