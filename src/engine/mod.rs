//! Engines: what advances trajectories event by event and shows the events to observers.
//!
//! * The **scalar** engine runs one trajectory at a time on the scene's kernel at any precision
//!   (`f64` or MPFR): [`drive`].
//! * The **SIMD** engine runs [`BLOCK`] trajectories in `f64` vector lanes, every lane
//!   bit-identical to the scalar kernel: [`run_block`]. One lane skeleton
//!   (`simd::run_steps`) steps a block for any kernel that supplies its step
//!   ([`BlockKernel`]): the triangular trap's fused one ([`simd`]) or any convex cell's generic
//!   one ([`cells`]: a table given as data). In a field the arc engine ([`arcs`]) runs the same
//!   cells on arcs. The vector instructions are chosen at run time ([`SimdPath`]): AVX-512,
//!   AVX2, or a portable path.
//!
//! Both feed the same [`Observer`]s, so an observable is written once and has the same bits on
//! every engine, at any thread count (each trajectory's bits depend only on its start).

pub mod arcs;
pub mod bound;
pub mod cells;
pub mod checkpoint;
pub mod json;
pub mod long_flight;
pub mod metadata;
pub mod observe;
pub mod options;
pub mod parallel;
pub mod progress_lines;
pub mod resume;
pub mod simd;
pub mod work;

use simd::BLOCK;

use crate::numbers::lanes;

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::observe::{EventLanes, Observer};
use crate::kernel::cell::CellKernel;
use crate::kernel::trap::Trap;
use crate::numbers::real::Real;
use crate::scenes::lattice::{Lattice, LatticeState};

/// Longest trajectory the engines accept, in collisions: 2⁵⁰ ≈ 1.1·10¹⁵ (months of one core).
/// Cell indices and collision counts are held as exact integers in `f64` lanes; an event changes
/// an index by at most 1 and a free flight crosses at most a handful of cells, so they stay far
/// below 2⁵³, where `f64` integers stop being exact.
pub const MAX_COLLISIONS_PER_TRAJECTORY: u64 = 1 << 50;

/// Which engine runs a production computation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Engine {
    /// SIMD for `f64` runs of the triangular lattice and of tables given as data (in a field
    /// too) on a CPU with AVX2 or AVX-512, scalar otherwise.
    #[default]
    Auto,
    /// One trajectory at a time on the generic kernel (any precision).
    Scalar,
    /// Many trajectories per core in vector lanes (`f64` only).
    Simd,
}

impl Engine {
    /// The name on the command line (`--engine auto|scalar|simd`).
    pub fn name(self) -> &'static str {
        match self {
            Engine::Auto => "auto",
            Engine::Scalar => "scalar",
            Engine::Simd => "simd",
        }
    }

    /// The engine that runs at number type `precision_is_f64`: `Auto` is SIMD for `f64` (on a
    /// CPU with AVX2 or AVX-512, or with [`SIMD_ENV`] naming a path) and scalar for MPFR; an
    /// explicit `Simd` at MPFR precision is refused.
    pub fn resolve(self, precision_is_f64: bool) -> Result<Resolved, Error> {
        match (self, precision_is_f64) {
            (Engine::Scalar, _) | (Engine::Auto, false) => Ok(Resolved::Scalar),
            (Engine::Auto, true) => {
                // The portable path only pays off where the compiler can vectorise it well; on
                // a CPU with neither AVX2 nor AVX-512 `auto` keeps the scalar engine unless the
                // path is asked for by name.
                let p = SimdPath::select()?;
                if p == SimdPath::Portable && !SimdPath::forced() {
                    Ok(Resolved::Scalar)
                } else {
                    Ok(Resolved::Simd(p))
                }
            }
            (Engine::Simd, true) => Ok(Resolved::Simd(SimdPath::select()?)),
            (Engine::Simd, false) => Err(Error::parameter(
                "engine",
                "simd",
                "the SIMD engine runs f64 only: use the scalar engine (or auto) with an MPFR \
                 precision",
            )),
        }
    }
}

/// The engine that actually runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Resolved {
    /// The scalar engine.
    Scalar,
    /// The SIMD engine on this instruction path.
    Simd(SimdPath),
}

impl Resolved {
    /// `"scalar"` or `"simd"` (the `engine` of a result's metadata).
    pub fn name(&self) -> &'static str {
        match self {
            Resolved::Scalar => "scalar",
            Resolved::Simd(_) => "simd",
        }
    }
    /// The instruction path of the SIMD engine (`None` for the scalar engine).
    pub fn simd(&self) -> Option<SimdPath> {
        match self {
            Resolved::Scalar => None,
            Resolved::Simd(p) => Some(*p),
        }
    }
}

/// The vector instructions of the SIMD engine. All give the same bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SimdPath {
    /// 8 lanes per `zmm` register, mask registers.
    Avx512,
    /// 4 lanes per `ymm` register.
    Avx2,
    /// Plain arrays of 4 lanes (any CPU).
    Portable,
}

/// Environment variable that forces a SIMD path (`avx512`, `avx2` or `portable`), for tests
/// and comparisons; a path the CPU lacks is refused.
pub const SIMD_ENV: &str = "LORENTZ_SIMD";

impl SimdPath {
    /// Every path, fastest first.
    pub const ALL: [SimdPath; 3] = [SimdPath::Avx512, SimdPath::Avx2, SimdPath::Portable];

    /// `true` if this CPU can run the path.
    pub fn available(self) -> bool {
        match self {
            SimdPath::Portable => true,
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx512 => std::arch::is_x86_feature_detected!("avx512f"),
            #[cfg(target_arch = "x86_64")]
            SimdPath::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The best path this CPU has.
    pub fn best() -> SimdPath {
        Self::ALL
            .into_iter()
            .find(|p| p.available())
            .unwrap_or(SimdPath::Portable)
    }

    /// Refuses a path this CPU cannot run (a caller's error: [`SimdPath::select`] picks one it
    /// can).
    pub fn check_available(self) -> Result<(), Error> {
        if self.available() {
            Ok(())
        } else {
            Err(Error::Failed(format!(
                "this CPU cannot run the {self} path"
            )))
        }
    }

    /// `true` if [`SIMD_ENV`] names a path.
    pub fn forced() -> bool {
        std::env::var(SIMD_ENV).is_ok_and(|v| !v.is_empty())
    }

    /// The path [`SIMD_ENV`] names, or the best one.
    ///
    /// # Errors
    /// If the variable names an unknown path or one this CPU lacks.
    pub fn select() -> Result<SimdPath, Error> {
        match std::env::var(SIMD_ENV) {
            Ok(v) if !v.is_empty() => {
                let p: SimdPath = v.parse()?;
                if !p.available() {
                    return Err(Error::Environment {
                        variable: SIMD_ENV,
                        why: format!(
                            "this CPU does not have {v}; available: {}",
                            Self::ALL
                                .iter()
                                .filter(|p| p.available())
                                .map(|p| p.to_string())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ),
                        value: v,
                    });
                }
                Ok(p)
            }
            _ => Ok(Self::best()),
        }
    }
}

impl fmt::Display for SimdPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            SimdPath::Avx512 => "avx512",
            SimdPath::Avx2 => "avx2",
            SimdPath::Portable => "portable",
        })
    }
}

impl FromStr for SimdPath {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s {
            "avx512" => Ok(SimdPath::Avx512),
            "avx2" => Ok(SimdPath::Avx2),
            "portable" => Ok(SimdPath::Portable),
            _ => Err(Error::Environment {
                variable: SIMD_ENV,
                value: s.into(),
                why: "use avx512, avx2 or portable".into(),
            }),
        }
    }
}

/// Refuses a trajectory of `collisions` collisions, longer than
/// [`MAX_COLLISIONS_PER_TRAJECTORY`], naming the `parameter` (given `value`) that sets it.
pub fn check_trajectory_length(
    collisions: u64,
    parameter: &'static str,
    value: impl fmt::Display,
) -> Result<(), Error> {
    if collisions > MAX_COLLISIONS_PER_TRAJECTORY {
        return Err(Error::parameter(
            parameter,
            value,
            format!(
                "{collisions} collisions in one trajectory: use at most 2^50 = \
                 {MAX_COLLISIONS_PER_TRAJECTORY} per trajectory (more batches for more collisions)"
            ),
        ));
    }
    Ok(())
}

/// Refuses a quota beyond [`MAX_COLLISIONS_PER_TRAJECTORY`] given to an engine directly (the
/// analyses refuse such a run first, naming their parameters: here it is a caller's error).
pub(crate) fn check_quotas(quotas: &[u64]) -> Result<(), Error> {
    if let Some(q) = quotas.iter().find(|&&q| q > MAX_COLLISIONS_PER_TRAJECTORY) {
        return Err(Error::Failed(format!(
            "a quota of {q} collisions: an engine runs at most 2^50 = \
             {MAX_COLLISIONS_PER_TRAJECTORY} per trajectory"
        )));
    }
    Ok(())
}

/// The scalar engine: advances `s` on `lat` until it has made `collisions` collisions, showing
/// every event (with the state before it) to `obs`. `progress` receives collision counts in
/// chunks of 2²⁰.
///
/// # Errors
/// If the state loses its next event (zero or non-finite velocity).
#[inline]
pub fn drive<T: Real, K: CellKernel<T>, O: Observer<1>>(
    lat: &Lattice<T, K>,
    s: &mut LatticeState<T>,
    collisions: u64,
    obs: &mut O,
    progress: &dyn Fn(u64),
) -> Result<(), Error> {
    drive_with(lat, s, collisions, obs, progress, |_, _, _| Ok(false))
}

/// [`drive`] with a hook that may carry out an event itself (and show it to the observer): it
/// returns `true` if it did, and the event is then neither shown nor applied again. The long
/// flights' jumps ([`long_flight::drive_jumps`]) are such a hook.
///
/// # Errors
/// If the state loses its next event, or the hook fails.
#[inline(always)]
pub(crate) fn drive_with<T: Real, K: CellKernel<T>, O: Observer<1>>(
    lat: &Lattice<T, K>,
    s: &mut LatticeState<T>,
    collisions: u64,
    obs: &mut O,
    progress: &dyn Fn(u64),
    mut hook: impl FnMut(
        &mut LatticeState<T>,
        &crate::kernel::flight::Event<T>,
        &mut O,
    ) -> Result<bool, Error>,
) -> Result<(), Error> {
    const CHUNK: u64 = 1 << 20;
    let mut c = 0u64;
    let mut next_report = CHUNK;
    while c < collisions {
        let ev = lat
            .next_event(s)
            .ok_or_else(|| Error::Failed("trajectory lost its next event".into()))?;
        if hook(s, &ev, obs)? {
            continue;
        }
        obs.observe::<f64>(std::slice::from_ref(&EventLanes::single(s, &ev)));
        if let crate::kernel::flight::EventKind::Collision(_) = ev.kind {
            c += 1;
        }
        lat.apply(s, &ev);
        if c >= next_report {
            progress(CHUNK);
            next_report += CHUNK;
        }
    }
    progress(collisions % CHUNK);
    Ok(())
}

/// The event buffers of one SIMD block ([`simd::OBSERVE_EVERY`] steps and the state after them),
/// starting a page. Where the allocator happened to put them changed a worker's speed: with the
/// ring from a plain `Vec`, one of two threads ran 15–20 % slower than the other, for its whole
/// block (8·10⁸ collisions on 2 threads: 180 M/s; page-aligned: 192–208 M/s, with one thread
/// unchanged at ~103 M/s). Aligning the ring, not the buffers inside it, leaves the hot loop's
/// code as it was (`#[repr(align(64))]` on [`EventLanes`] balanced the threads too but made one
/// thread 8–14 % slower).
#[repr(C, align(4096))]
struct Ring([EventLanes<BLOCK>; simd::OBSERVE_EVERY + 1]);

/// What the lane skeleton runs: the triangular trap's fused step ([`simd`]) or any convex cell's
/// generic one ([`cells`]). Each method runs a whole block at the vector type of its path
/// (the caller has checked that the CPU has it).
pub trait BlockKernel {
    /// Refuses a kernel the lane engines cannot run (a cell with too many disks or edges).
    ///
    /// # Errors
    /// The reason, naming the limit.
    fn check_lanes(&self) -> Result<(), Error> {
        Ok(())
    }

    /// The block on AVX-512 vectors (`#[inline(always)]`: it is inlined into the function that
    /// enables the feature).
    #[cfg(target_arch = "x86_64")]
    fn avx512<O: Observer<BLOCK>>(&self, run: BlockRun<'_, O>) -> Option<usize>;

    /// The block on AVX2 vectors (as [`BlockKernel::avx512`]).
    #[cfg(target_arch = "x86_64")]
    fn avx2<O: Observer<BLOCK>>(&self, run: BlockRun<'_, O>) -> Option<usize>;

    /// The block on the portable path.
    fn portable<O: Observer<BLOCK>>(&self, run: BlockRun<'_, O>) -> Option<usize>;
}

/// What one block runs on: its counts, its event ring (the starting states in `ring[0]`), its
/// observers and its progress callback.
pub struct BlockRun<'a, O> {
    counts: &'a mut simd::BlockCounts,
    ring: &'a mut [EventLanes<BLOCK>],
    obs: &'a mut O,
    progress: &'a dyn Fn(u64),
}

impl BlockKernel for Trap<f64> {
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn avx512<O: Observer<BLOCK>>(&self, r: BlockRun<'_, O>) -> Option<usize> {
        simd::run::<lanes::Pair<lanes::Avx512>, O>(self, r.counts, r.ring, r.obs, r.progress)
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn avx2<O: Observer<BLOCK>>(&self, r: BlockRun<'_, O>) -> Option<usize> {
        simd::run::<lanes::Pair<lanes::Avx2>, O>(self, r.counts, r.ring, r.obs, r.progress)
    }

    /// The portable path's lanes are scalar code: every root is cheaper there than the β choice.
    fn portable<O: Observer<BLOCK>>(&self, r: BlockRun<'_, O>) -> Option<usize> {
        simd::run_with::<lanes::Portable, O, false>(self, r.counts, r.ring, r.obs, r.progress)
    }
}

impl BlockKernel for crate::kernel::cell::ConvexCell<f64> {
    fn check_lanes(&self) -> Result<(), Error> {
        if cells::fits(self) {
            return Ok(());
        }
        Err(Error::Failed(format!(
            "a cell of {} disks and {} edges: the lane engines run 1 to {} disks and at most {} \
             edges (use the scalar engine)",
            self.disks.len(),
            self.edges.len(),
            cells::MAX_LANE_DISKS,
            cells::MAX_LANE_EDGES
        )))
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn avx512<O: Observer<BLOCK>>(&self, r: BlockRun<'_, O>) -> Option<usize> {
        cells::run::<lanes::Pair<lanes::Avx512>, O>(self, r)
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn avx2<O: Observer<BLOCK>>(&self, r: BlockRun<'_, O>) -> Option<usize> {
        cells::run::<lanes::Pair<lanes::Avx2>, O>(self, r)
    }

    fn portable<O: Observer<BLOCK>>(&self, r: BlockRun<'_, O>) -> Option<usize> {
        cells::run::<lanes::Portable, O>(self, r)
    }
}

/// The SIMD engine: advances up to [`BLOCK`] trajectories `states` of a lattice whose cell
/// kernel is `kernel` (the triangular trap, or any convex cell of the generic kernel), lane l
/// until it has made `quotas[l]` collisions, showing every step to `obs` (built for [`BLOCK`]
/// lanes; lanes beyond `states.len()` are never live). The states are left where the scalar
/// engine would leave them.
///
/// # Errors
/// If more than [`BLOCK`] states are given, quotas and states differ in number, a quota exceeds
/// [`MAX_COLLISIONS_PER_TRAJECTORY`], the kernel does not fit the lanes, or a trajectory loses
/// its next event.
pub fn run_block<O: Observer<BLOCK>, K: BlockKernel>(
    path: SimdPath,
    kernel: &K,
    states: &mut [LatticeState<f64>],
    quotas: &[u64],
    obs: &mut O,
    progress: &dyn Fn(u64),
) -> Result<(), Error> {
    if states.len() > BLOCK || quotas.len() != states.len() {
        return Err(Error::Failed(format!(
            "a SIMD block runs 1 to {BLOCK} trajectories with one quota each (got {} states, {} quotas)",
            states.len(),
            quotas.len()
        )));
    }
    path.check_available()?;
    kernel.check_lanes()?;
    check_quotas(quotas)?;
    let mut counts = simd::BlockCounts {
        collisions: [0.0; BLOCK],
        quota: [0.0; BLOCK],
    };
    let mut ring = Box::new(Ring(std::array::from_fn(|_| EventLanes::default())));
    let ring = &mut ring.0[..];
    let st = &mut ring[0];
    for (l, (s, &q)) in states.iter().zip(quotas).enumerate() {
        st.set_state(l, s);
        counts.quota[l] = q as f64;
    }
    let run = BlockRun {
        counts: &mut counts,
        ring: &mut *ring,
        obs,
        progress,
    };
    let lost = match path {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `path.available()` checked the CPU feature above.
        SimdPath::Avx512 => unsafe { run_avx512(kernel, run) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        SimdPath::Avx2 => unsafe { run_avx2(kernel, run) },
        _ => kernel.portable(run),
    };
    for (l, s) in states.iter_mut().enumerate() {
        *s = ring[0].state(l);
    }
    match lost {
        Some(l) => Err(Error::Failed(format!(
            "trajectory {l} of the block lost its next event (velocity {:?})",
            [states[l].flight.vel.x, states[l].flight.vel.y]
        ))),
        None => Ok(()),
    }
}

/// Work written once over the lane width ([`Lanes`](crate::numbers::lanes::Lanes)), for
/// [`on_path`]: its `run` must be `#[inline(always)]`, so that it is compiled with the path's
/// instructions.
pub trait LaneWork {
    /// The work at lane type `V`.
    fn run<V: crate::numbers::lanes::Lanes>(&mut self);
}

/// Runs `work` with the vector instructions of `path` (AVX-512, two AVX2 vectors, or the
/// portable lanes): the same operations, so the same bits, on every path.
///
/// # Errors
/// A path this CPU lacks.
pub fn on_path<W: LaneWork>(path: SimdPath, work: &mut W) -> Result<(), Error> {
    if !path.available() {
        return Err(Error::Failed(format!(
            "this CPU cannot run the {path} path"
        )));
    }
    match path {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the CPU has AVX-512F (checked above).
        SimdPath::Avx512 => unsafe { work_avx512(work) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the CPU has AVX2 (checked above).
        SimdPath::Avx2 => unsafe { work_avx2(work) },
        _ => work.run::<crate::numbers::lanes::Portable>(),
    }
    Ok(())
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn work_avx512<W: LaneWork>(work: &mut W) {
    work.run::<crate::numbers::lanes::Avx512>()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn work_avx2<W: LaneWork>(work: &mut W) {
    work.run::<crate::numbers::lanes::Pair<crate::numbers::lanes::Avx2>>()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn run_avx512<O: Observer<BLOCK>, K: BlockKernel>(
    kernel: &K,
    run: BlockRun<'_, O>,
) -> Option<usize> {
    kernel.avx512(run)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn run_avx2<O: Observer<BLOCK>, K: BlockKernel>(
    kernel: &K,
    run: BlockRun<'_, O>,
) -> Option<usize> {
    kernel.avx2(run)
}
