//! The multi-trajectory engine on arcs: [`BLOCK`] trajectories of the triangular lattice in a
//! uniform field advance one event per step in vector lanes, every lane executing exactly the
//! correctly rounded operations of the generic arc kernel
//! ([`crate::kernel::field`], [`crate::kernel::arc`]) in the same order on the same constants
//! (taken from the `f64` cell itself), so each lane is the scalar kernel bit for bit.
//!
//! Where the scalar code branches, a lane computes every branch and blends the results by masks:
//! the on-circle and off-circle contacts of each disk, the return to the line just crossed and
//! the exit through it, the order of candidates ([`crate::kernel::arc::earlier`]: its stages and
//! classes as masks; the sense of rotation is one for the block), the two velocities at a
//! contact, and a collision's reflection against a crossing's map. Two computations are rare
//! and run only where some lane needs them (a branch on the block, never a different result):
//! the disk-frame contact of nearly concentric circles (4M < V²), and the test for a cyclotron
//! circle that is a disk's to rounding, screened by a bound that needs no square root
//! (√|d|² ≤ |d|² + 1, and rounding is monotone). Two quotients the scalar code takes in
//! different branches with one divisor each (the exit through a line, the return to it) become
//! one quotient of selected operands, which is the same operation on the same numbers.
//!
//! A lane that would have no next event (a pinned orbit, a creeping slide, a lost velocity) stops
//! the block, and the lane is reported, as the scalar engine reports it.
//! `tests/numerics/arc_engine.rs` checks every path against the scalar kernel.

mod block;
mod contacts;
mod oracle;
mod order;

pub use block::{ArcBlock, ArcRecord};
pub use oracle::{OracleTiming, WinnerTape};

use contacts::{disk, edge};
use order::{Cand, offer};

use crate::Error;
use crate::engine::observe::{CROSSING_CODE, EventLanes, NO_EVENT, NO_LABEL};
use crate::engine::simd::BLOCK;
use crate::engine::{LaneWork, SimdPath, on_path};
use crate::kernel::cell::ConvexCell;
use crate::numbers::lanes::Lanes;
use crate::scenes::lattice::LatticeState;

/// The lane states of one block: position and velocity in the cell's frame, exclusions and
/// cell index in `lanes` (its event fields unused), and the collisions made, quota and crossings.
#[derive(Debug, Clone)]
pub struct ArcLanes {
    /// The states.
    pub lanes: EventLanes<BLOCK>,
    /// Collisions so far.
    pub collisions: [f64; BLOCK],
    /// Collisions to make.
    pub quota: [f64; BLOCK],
    /// Crossings so far.
    pub crossings: [f64; BLOCK],
}

pub(super) use super::cells::{CellC, DiskC, Line, cross};

/// The block's constants, splatted.
pub(super) struct Consts<V> {
    cell: CellC<V>,
    w: V,
    aw: V,
    left: bool,
    unit_disks: bool,
}

impl<V: Lanes> Consts<V> {
    #[inline(always)]
    fn new(cell: &ConvexCell<f64>, w: f64) -> Self {
        Consts {
            cell: CellC::new(cell),
            w: V::splat(w),
            aw: V::splat(w.abs()),
            left: w > 0.0,
            unit_disks: cell.disks.iter().all(|d| *d.radius2() == 1.0),
        }
    }
}

/// The arc of every lane: velocity, |v|², |v|, and the all-true mask.
#[derive(Clone, Copy)]
pub(super) struct ArcL<V: Lanes> {
    vx: V,
    vy: V,
    vv: V,
    speed: V,
    all: V::Mask,
}

#[inline(always)]
pub(super) fn not<V: Lanes>(m: V::Mask, all: V::Mask) -> V::Mask {
    V::and_not(all, m)
}

/// `true` where both components are zero ([`crate::kernel::arc::is_zero`]: neither > 0 nor < 0).
#[inline(always)]
pub(super) fn is_zero<V: Lanes>(x: V, y: V, all: V::Mask) -> V::Mask {
    let z = V::splat(0.0);
    let any = V::or(V::or(x.gt(z), x.lt(z)), V::or(y.gt(z), y.lt(z)));
    not::<V>(any, all)
}

/// A lane's loaded state.
pub(super) use super::cells::LaneState as Loaded;

/// The earliest candidate of every lane and its code (disk m, or [`CROSSING_CODE`] + edge k),
/// and where the scalar kernel has no event.
#[inline(always)]
fn choose<V: Lanes>(c: &Consts<V>, a: &ArcL<V>, s: &Loaded<V>) -> (Cand<V>, V, V::Mask) {
    let z = V::splat(0.0);
    // The first offer has nothing to beat (the scalar `offer`'s `is_none_or`).
    let (mut best, mut stuck) = disk(c, a, &c.cell.disks[0], s.p, s.ed.eq(z));
    let mut code = z;
    for (m, d) in c.cell.disks.iter().enumerate().skip(1) {
        let label = V::splat(m as f64);
        let (cand, slides) = disk(c, a, d, s.p, s.ed.eq(label));
        stuck = V::or(stuck, slides);
        let (b, take) = offer(a, c.left, best, cand);
        best = b;
        code = V::select(take, label, code);
    }
    for (k, e) in c.cell.edges.iter().enumerate() {
        let cand = edge(c, a, &e.line, s.p, s.ee.eq(V::splat(k as f64)));
        let (b, take) = offer(a, c.left, best, cand);
        best = b;
        code = V::select(take, V::splat(CROSSING_CODE + k as f64), code);
    }
    let lost = V::or(stuck, V::and_not(a.all, best.has));
    (best, code, lost)
}

/// The velocity on arrival at the chord ([`crate::kernel::arc::velocity_along`] for a contact
/// found in the disk's frame, else [`crate::kernel::arc::velocity_after`]).
#[inline(always)]
fn arrival<V: Lanes>(c: &Consts<V>, a: &ArcL<V>, b: &Cand<V>) -> (V, V) {
    let xx = b.x.mul(b.x).add(b.y.mul(b.y));
    let k = a.vx.mul(b.x).add(a.vy.mul(b.y)).mul(V::splat(2.0)).div(xx);
    let reflect = xx.gt(V::splat(0.0));
    let ax = V::select(reflect, k.mul(b.x).sub(a.vx), a.vx);
    let ay = V::select(reflect, k.mul(b.y).sub(a.vy), a.vy);
    (
        V::select(b.frame, a.vx.sub(c.w.mul(b.y)), ax),
        V::select(b.frame, a.vy.add(c.w.mul(b.x)), ay),
    )
}

/// The state after a collision with the disk `code` at x, arriving with velocity u.
#[inline(always)]
fn collide<V: Lanes>(c: &Consts<V>, code: V, (x, y): (V, V), (ux, uy): (V, V)) -> (V, V) {
    let DiskC { cx, cy, r2, .. } = c.cell.disk(code);
    let (nx, ny) = (x.sub(cx), y.sub(cy));
    let twice = ux.mul(nx).add(uy.mul(ny)).mul(V::splat(2.0));
    // x/1 = x exactly in IEEE arithmetic: unit disks skip the division.
    let s = if c.unit_disks { twice } else { twice.div(r2) };
    (ux.sub(nx.mul(s)), uy.sub(ny.mul(s)))
}

/// One event for the `V::WIDTH` lanes at `o`, recorded in `rec` if given, its winner read from
/// `winners` if given ([`oracle`]): returns the lanes that lost their next event and those still
/// running, as bits of the block.
#[inline(always)]
fn step<V: Lanes>(
    c: &Consts<V>,
    st: &mut ArcLanes,
    o: usize,
    rec: Option<&mut ArcRecord>,
    winners: Option<&[f64; BLOCK]>,
) -> (u64, u64) {
    let z = V::splat(0.0);
    let count = V::load(&st.collisions[o..]);
    let live = count.lt(V::load(&st.quota[o..]));
    if V::bits(live) == 0 {
        return (0, 0);
    }
    let s = Loaded::<V>::load(&st.lanes, o);
    let (vx, vy) = s.v;
    let vv = vx.mul(vx).add(vy.mul(vy));
    let a = ArcL {
        vx,
        vy,
        vv,
        speed: vv.sqrt(),
        all: V::eq(z, z),
    };
    let (best, code, lost) = match winners {
        Some(codes) => oracle::choose(c, &a, &s, V::load(&codes[o..])),
        None => choose(c, &a, &s),
    };
    let lost = V::and(live, lost);
    let go = V::and_not(live, lost);
    let u = arrival(c, &a, &best);
    let newton = vv.neg().add(V::splat(3.0)).mul(V::splat(0.5));
    let x = (s.p.0.add(best.x), s.p.1.add(best.y));
    // The disk left is carried across only by a particle that has not moved.
    let still = is_zero::<V>(best.x, best.y, a.all);
    let hit = code.lt(V::splat(CROSSING_CODE));
    let r = collide(c, code, x, u);
    let mut n = cross(&c.cell, &s, code, x, u, still);
    n.p = (V::select(hit, x.0, n.p.0), V::select(hit, x.1, n.p.1));
    n.v = (V::select(hit, r.0, n.v.0), V::select(hit, r.1, n.v.1));
    n.ed = V::select(hit, code, n.ed);
    n.ee = V::select(hit, V::splat(NO_LABEL), n.ee);
    n.v = (n.v.0.mul(newton), n.v.1.mul(newton));
    if let Some(r) = rec {
        let code = V::select(go, code, V::splat(NO_EVENT));
        record(r, o, &s, code, (best.x, best.y), u);
    }
    n.store_where(go, &s, &mut st.lanes, o);
    let one = V::splat(1.0);
    let crossings = V::load(&st.crossings[o..]);
    V::select(V::and(go, hit), count.add(one), count).store(&mut st.collisions[o..]);
    V::select(V::and_not(go, hit), crossings.add(one), crossings).store(&mut st.crossings[o..]);
    (V::bits(lost) << o, V::bits(live) << o)
}

/// The state of the lanes at `o` before their event, the event's code ([`NO_EVENT`] in a lane
/// that made none), its chord and the velocity on arrival.
#[inline(always)]
fn record<V: Lanes>(
    r: &mut ArcRecord,
    o: usize,
    s: &Loaded<V>,
    code: V,
    (x, y): (V, V),
    (ux, uy): (V, V),
) {
    let z = V::splat(0.0);
    s.store_where(V::eq(z, z), s, &mut r.before, o);
    code.store(&mut r.before.code[o..]);
    x.store(&mut r.chord[0][o..]);
    y.store(&mut r.chord[1][o..]);
    ux.store(&mut r.arrival[0][o..]);
    uy.store(&mut r.arrival[1][o..]);
}

/// How [`run`] steps the block.
enum Mode<'a> {
    /// At most `limit` steps, until every lane has its quota of collisions.
    Free,
    /// `ring.len()` steps, each recorded in its entry.
    Record(&'a mut [ArcRecord]),
    /// One step per entry of the tape, each lane's winner read from it ([`oracle`]).
    Oracle(&'a [[f64; BLOCK]]),
}

/// Runs the block as `mode` says; returns a lane that lost its next event, if any (the block
/// stops there).
#[inline(always)]
fn run<V: Lanes>(
    cell: &ConvexCell<f64>,
    w: f64,
    st: &mut ArcLanes,
    limit: u64,
    mode: Mode<'_>,
) -> Option<usize> {
    let c = Consts::<V>::new(cell, w);
    match mode {
        Mode::Free => steps::<V, false>(&c, st, limit, &mut []),
        Mode::Record(ring) => steps::<V, true>(&c, st, ring.len() as u64, ring),
        Mode::Oracle(tape) => oracle::steps::<V>(&c, st, tape),
    }
}

/// [`run`]'s steps, recorded (`RECORD`) or not (then `ring` is unused, and the step stores
/// nothing else).
#[inline(always)]
fn steps<V: Lanes, const RECORD: bool>(
    c: &Consts<V>,
    st: &mut ArcLanes,
    limit: u64,
    ring: &mut [ArcRecord],
) -> Option<usize> {
    for k in 0..limit as usize {
        let (mut lost, mut live) = (0u64, 0u64);
        let mut o = 0;
        while o < BLOCK {
            let rec = if RECORD { ring.get_mut(k) } else { None };
            let (l, v) = step::<V>(c, st, o, rec, None);
            lost |= l;
            live |= v;
            o += V::WIDTH;
        }
        if let Some(r) = ring.get_mut(k) {
            r.before.live_bits = live & !lost;
        }
        if lost != 0 {
            return Some(lost.trailing_zeros() as usize);
        }
        if live == 0 {
            break;
        }
    }
    None
}

/// The arc engine: advances up to [`BLOCK`] trajectories `states` of a lattice with cell `cell`
/// in the field `w` (≠ 0, finite), lane l until it has made `quotas[l]` collisions or the block
/// has run `limit` events; returns the crossings of each state. The states are left where the
/// scalar arc kernel would leave them after as many events.
///
/// # Errors
/// Bad arguments (more than [`BLOCK`] states, quotas and states differing in number, a zero or
/// non-finite field, a path this CPU lacks), or a trajectory with no next event.
pub fn run_arc_block(
    path: SimdPath,
    cell: &ConvexCell<f64>,
    w: f64,
    states: &mut [LatticeState<f64>],
    quotas: &[u64],
    limit: u64,
) -> Result<Vec<u64>, Error> {
    if quotas.len() != states.len() {
        return Err(Error::Failed(format!(
            "an arc block runs its trajectories with one quota each (got {} states, {} quotas)",
            states.len(),
            quotas.len()
        )));
    }
    check(path, cell, w, states.len())?;
    super::check_quotas(quotas)?;
    let mut st = load(states, quotas);
    let lost = dispatch(path, cell, w, &mut st, limit, Mode::Free);
    unload(&st, states);
    if let Some(l) = lost {
        return Err(no_next_event(l, &states[l]));
    }
    Ok(st.crossings[..states.len()]
        .iter()
        .map(|&c| c as u64)
        .collect())
}

/// Refuses a block the engine cannot run: more than [`BLOCK`] trajectories, a zero or
/// non-finite field, a path this CPU lacks, a cell without disks.
fn check(path: SimdPath, cell: &ConvexCell<f64>, w: f64, n: usize) -> Result<(), Error> {
    if n > BLOCK {
        return Err(Error::Failed(format!(
            "an arc block runs 1 to {BLOCK} trajectories (got {n})"
        )));
    }
    if !(w.is_finite() && w != 0.0) {
        return Err(Error::Failed(format!(
            "the arc engine needs a finite nonzero field (got {w})"
        )));
    }
    path.check_available()?;
    if cell.disks.is_empty() {
        return Err(Error::Failed(
            "the arc engine needs a cell with disks".into(),
        ));
    }
    Ok(())
}

/// [`run`] on `path` (checked available by [`check`]), through [`on_path`]: one `zmm` vector at a
/// time on AVX-512 — a step of the arc engine keeps far more values live than the straight
/// engine's, and a pair of vectors spilled them (0.94 of the pair's time per collision,
/// w = 0.1, B = 1, paired runs); two vectors interleaved candidate by candidate were slower
/// still (77 against 56 ns per collision): the step is bound by the issue of its vector
/// instructions, not by their latency (`docs/guide/field.md`, "Speed").
fn dispatch(
    path: SimdPath,
    cell: &ConvexCell<f64>,
    w: f64,
    st: &mut ArcLanes,
    limit: u64,
    mode: Mode<'_>,
) -> Option<usize> {
    let mut work = ArcRun {
        cell,
        w,
        st,
        limit,
        mode: Some(mode),
        lost: None,
    };
    // `check` made sure that this CPU has the path.
    on_path(path, &mut work).ok()?;
    work.lost
}

/// One run of [`run`] as lane work for [`on_path`].
struct ArcRun<'a, 'm> {
    cell: &'a ConvexCell<f64>,
    w: f64,
    st: &'a mut ArcLanes,
    limit: u64,
    mode: Option<Mode<'m>>,
    lost: Option<usize>,
}

impl LaneWork for ArcRun<'_, '_> {
    #[inline(always)]
    fn run<V: Lanes>(&mut self) {
        if let Some(mode) = self.mode.take() {
            self.lost = run::<V>(self.cell, self.w, self.st, self.limit, mode);
        }
    }
}

/// The error of a trajectory `l` that has no next event.
fn no_next_event(l: usize, s: &LatticeState<f64>) -> Error {
    Error::Failed(format!(
        "trajectory {l} of the arc block has no next event (a pinned or creeping orbit, or velocity {:?})",
        [s.flight.vel.x, s.flight.vel.y]
    ))
}

/// The lanes of `states` (lanes beyond them have quota 0: never live).
fn load(states: &[LatticeState<f64>], quotas: &[u64]) -> ArcLanes {
    let mut st = ArcLanes {
        lanes: EventLanes::default(),
        collisions: [0.0; BLOCK],
        quota: [0.0; BLOCK],
        crossings: [0.0; BLOCK],
    };
    for (l, (s, &q)) in states.iter().zip(quotas).enumerate() {
        st.lanes.set_state(l, s);
        st.quota[l] = q as f64;
    }
    st
}

/// The lanes back into `states`.
fn unload(st: &ArcLanes, states: &mut [LatticeState<f64>]) {
    for (l, s) in states.iter_mut().enumerate() {
        *s = st.lanes.state(l);
    }
}
