//! The multi-trajectory engine of the triangular lattice: [`BLOCK`] independent trajectories
//! advance one event per step in vector lanes, branch-free but for one rare branch (an undecided
//! edge choice). The loop that steps a block and shows its events to the observers
//! (`run_steps`) is the lane skeleton every straight-flight kernel shares: a kernel supplies
//! its step ([`LaneStep`]), the trap's fused one here, any convex cell's in [`super::cells`].
//!
//! No closures in this file's hot code: a closure does not inherit the target features of the
//! function it is written in, so its vector operations would be calls rather than instructions.
//!
//! Every lane executes exactly the correctly rounded operations of the trap's kernel
//! ([`crate::kernel::trap::Trap::next_event`] and [`crate::kernel::trap::Trap::apply`]), in the
//! same order, on the same constants (taken from the `Trap<f64>` itself):
//!
//! * the next event is chosen by the rules of [`crate::kernel::choice`], lane by lane: the
//!   three disks' β = d·v and Δ = |v|² − (d×v)² (no square root), the earliest valid disk by the
//!   largest β (or, below the gap 2⁻²⁰, by all three roots), the earliest edge by certified cross
//!   products (a rare branch computes both quotients where some lane is undecided), then one
//!   root γ/(√Δ − β) and one quotient σ/(−n·v) per lane, the edge taken only where strictly
//!   earlier; a candidate the scalar code would not offer (excluded by identity, moving away,
//!   missing, or not leaving through the edge) is masked out rather than skipped;
//! * the reflection (with its Newton speed factor) and the point reflection into the
//!   neighbouring trap are both computed and blended by the event mask; the exclusion labels
//!   and the cell index (i, j, s) are updated by masks as exact small integers.
//!
//! The trap's fused path skips operations that are exact in its coordinates (d = p − P₀ = p,
//! p_y − 0); a lane skips exactly the same ones, and where the scalar code branches between two
//! exact forms (n = x for P₀, n = x − Pₘ otherwise) the lane computes x − 0, which is the same
//! value bit for bit. `tests/numerics/engine.rs` checks every event of every lane against the scalar
//! kernel, on every code path the machine has.

use crate::engine::observe::{CROSSING_CODE, EventLanes, NO_EVENT, NO_LABEL, Observer};
use crate::kernel::trap::Trap;
use crate::numbers::lanes::Lanes;

/// Trajectories per block: 16 = two AVX-512 vectors, four AVX2 or portable vectors — enough
/// independent work to hide the latency of the divide/square-root chain of one step.
pub const BLOCK: usize = 16;

/// The block's collision counts and quotas (exact integers below 2⁵³). The lanes' positions,
/// velocities, exclusions and cells live in the [`EventLanes`] buffers the observers read: the
/// state before step k is buffer k's, and the step writes the state after it into buffer k + 1
/// (so nothing is copied for the observers).
#[derive(Debug, Clone)]
pub struct BlockCounts {
    /// Collisions so far.
    pub collisions: [f64; BLOCK],
    /// Collisions to do.
    pub quota: [f64; BLOCK],
}

/// The trap's constants, splatted.
struct Consts<V> {
    p1x: V,
    p2x: V,
    p2y: V,
    k: V,
    h: V,
    c: [[V; 2]; 3],
    certain: V,
}

impl<V: Lanes> Consts<V> {
    #[inline(always)]
    fn new(t: &Trap<f64>) -> Self {
        Consts {
            p1x: V::splat(t.vertices[1].x),
            p2x: V::splat(t.vertices[2].x),
            p2y: V::splat(t.vertices[2].y),
            k: V::splat(t.normals[1].x),
            h: V::splat(t.h),
            c: [
                [V::splat(t.centres[0].x), V::splat(t.centres[0].y)],
                [V::splat(t.centres[1].x), V::splat(t.centres[1].y)],
                [V::splat(t.centres[2].x), V::splat(t.centres[2].y)],
            ],
            certain: V::splat(t.choice().certain),
        }
    }
}

/// The first half of the cancellation-free root ([`crate::kernel::ray_disk::approach`]) in every
/// lane: β = d·v, Δ = |v|² − (d×v)², and the mask where the scalar code has a root (β < 0 and
/// Δ > 0).
#[inline(always)]
fn approach<V: Lanes>(dx: V, dy: V, vx: V, vy: V, vv: V) -> (V, V, V::Mask) {
    let zero = V::splat(0.0);
    let beta = dx.mul(vx).add(dy.mul(vy));
    let q = dx.mul(vy).sub(dy.mul(vx));
    let disc = vv.sub(q.mul(q));
    (beta, disc, V::and(beta.lt(zero), disc.gt(zero)))
}

/// The second half ([`crate::kernel::ray_disk::Approach::entry`]): γ/(√Δ − β) with
/// γ = |d|² − 1, or 0 where γ ≤ 0 (a start numerically inside, moving in).
#[inline(always)]
fn entry<V: Lanes>(dx: V, dy: V, beta: V, disc: V) -> V {
    let zero = V::splat(0.0);
    let gamma = dx.mul(dx).add(dy.mul(dy)).add(V::splat(-1.0));
    let t = gamma.div(disc.sqrt().sub(beta));
    V::select(gamma.gt(zero), t, zero)
}

/// Where a candidate offered later replaces the current one: where it has one and is `better`,
/// or the current has none (the scalar `offer`'s `is_none_or`).
#[inline(always)]
fn wins<V: Lanes>(later: V::Mask, current: V::Mask, better: V::Mask) -> V::Mask {
    V::and(later, V::or(better, V::and_not(later, current)))
}

/// A candidate event per lane: time, code, and whether there is one.
#[derive(Clone, Copy)]
struct Cand<V: Lanes> {
    t: V,
    code: V,
    has: V::Mask,
}

impl<V: Lanes> Cand<V> {
    /// No candidate in any lane.
    #[inline(always)]
    fn none() -> Self {
        Cand {
            t: V::splat(0.0),
            code: V::splat(0.0),
            has: V::from_bits(0),
        }
    }

    /// The earlier of `self` and a candidate `later` offered after it: `later` wins only where
    /// `self` has none or `later` is strictly earlier — the scalar `offer`.
    #[inline(always)]
    fn then(self, later: Self) -> Self {
        let take = wins::<V>(later.has, self.has, later.t.lt(self.t));
        Cand {
            t: V::select(take, later.t, self.t),
            code: V::select(take, later.code, self.code),
            has: V::or(self.has, later.has),
        }
    }
}

/// A disk before its root: offset, β, Δ, code, and whether it is offered.
#[derive(Clone, Copy)]
struct Disk<V: Lanes> {
    dx: V,
    dy: V,
    beta: V,
    disc: V,
    code: V,
    has: V::Mask,
}

impl<V: Lanes> Disk<V> {
    #[inline(always)]
    fn new(dx: V, dy: V, (vx, vy, vv): (V, V, V), ed: V, m: f64) -> Self {
        let (beta, disc, hit) = approach(dx, dy, vx, vy, vv);
        Disk {
            dx,
            dy,
            beta,
            disc,
            code: V::splat(m),
            has: V::and_not(hit, ed.eq(V::splat(m))),
        }
    }

    /// [`crate::kernel::choice::EarliestDisk`] by β: `later` wins where `self` has none or its β
    /// is strictly larger.
    #[inline(always)]
    fn then(self, later: Self) -> Self {
        let take = wins::<V>(later.has, self.has, later.beta.gt(self.beta));
        Disk {
            dx: V::select(take, later.dx, self.dx),
            dy: V::select(take, later.dy, self.dy),
            beta: V::select(take, later.beta, self.beta),
            disc: V::select(take, later.disc, self.disc),
            code: V::select(take, later.code, self.code),
            has: V::or(self.has, later.has),
        }
    }

    /// The chosen disk's event: its root computed now.
    #[inline(always)]
    fn event(self) -> Cand<V> {
        Cand {
            t: entry(self.dx, self.dy, self.beta, self.disc),
            code: self.code,
            has: self.has,
        }
    }
}

/// An edge before its quotient: s⁺ (σ where σ > 0, else 0), m = −n·v, code, offered.
#[derive(Clone, Copy)]
struct Edge<V: Lanes> {
    s: V,
    m: V,
    code: V,
    has: V::Mask,
}

impl<V: Lanes> Edge<V> {
    /// Edge `e` from (nᵉ·v, σₑ): offered where nᵉ·v < 0 and it is not the edge entered by.
    #[inline(always)]
    fn new((nv, sigma): (V, V), ee: V, e: f64) -> Self {
        let zero = V::splat(0.0);
        Edge {
            s: V::select(sigma.gt(zero), sigma, zero),
            m: nv.neg(),
            code: V::splat(CROSSING_CODE + e),
            has: V::and_not(nv.lt(zero), ee.eq(V::splat(e))),
        }
    }

    /// s⁺/m, or 0 where s⁺ = 0: the scalar σ/(−n·v) (or 0 where σ ≤ 0).
    #[inline(always)]
    fn time(&self) -> V {
        let zero = V::splat(0.0);
        V::select(self.s.gt(zero), self.s.div(self.m), zero)
    }

    /// [`crate::kernel::choice::EarliestEdge`]: `later` wins where `self` has none or its cross
    /// product is certainly smaller; where neither is certain, the quotients decide (a rare
    /// branch: only near a corner, or on zero, infinite or NaN products).
    #[inline(always)]
    fn then(self, later: Self, certain: V) -> Self {
        let late = later.s.mul(self.m);
        let soon = self.s.mul(later.m);
        let sure_later = late.lt(soon.mul(certain));
        let sure_self = soon.lt(late.mul(certain));
        let both = V::and(self.has, later.has);
        let unsure = V::and_not(V::and_not(both, sure_later), sure_self);
        let mut take = wins::<V>(later.has, self.has, sure_later);
        if V::bits(unsure) != 0 {
            take = V::or(take, V::and(unsure, later.time().lt(self.time())));
        }
        Edge {
            s: V::select(take, later.s, self.s),
            m: V::select(take, later.m, self.m),
            code: V::select(take, later.code, self.code),
            has: V::or(self.has, later.has),
        }
    }

    /// The chosen edge's event: its quotient computed now.
    #[inline(always)]
    fn event(self) -> Cand<V> {
        Cand {
            t: self.time(),
            code: self.code,
            has: self.has,
        }
    }
}

/// A step of `V::WIDTH` lanes up to its square root and divisions: the state loaded, the
/// earliest disk and edge chosen, their operands ready.
#[derive(Clone, Copy)]
struct Front<V: Lanes> {
    o: usize,
    px: V,
    py: V,
    vx: V,
    vy: V,
    vv: V,
    ed: V,
    ee: V,
    count: V,
    live: V::Mask,
    /// The chosen disk (by β), its root not yet taken.
    disk: Disk<V>,
    /// The earliest disk by every root (below the gap where β decides).
    timed: Cand<V>,
    edge: Edge<V>,
}

/// Loads the lanes starting at `o` and chooses their next disk and edge by the rules of
/// [`crate::kernel::choice`] (by β when `BY_BETA`, else by every root).
#[inline(always)]
fn front<V: Lanes, const L: usize, const BY_BETA: bool>(
    c: &Consts<V>,
    counts: &BlockCounts,
    out: &EventLanes<L>,
    o: usize,
) -> Front<V> {
    let px = V::load(&out.pos[0][o..]);
    let py = V::load(&out.pos[1][o..]);
    let vx = V::load(&out.vel[0][o..]);
    let vy = V::load(&out.vel[1][o..]);
    let ed = V::load(&out.excluded[0][o..]);
    let ee = V::load(&out.excluded[1][o..]);
    let count = V::load(&counts.collisions[o..]);
    let live = count.lt(V::load(&counts.quota[o..]));
    let vv = vx.mul(vx).add(vy.mul(vy));
    let v = (vx, vy, vv);
    let d0 = Disk::new(px, py, v, ed, 0.0);
    let d1 = Disk::new(px.sub(c.p1x), py, v, ed, 1.0);
    let d2 = Disk::new(px.sub(c.p2x), py.sub(c.p2y), v, ed, 2.0);
    let (disk, timed) = if BY_BETA {
        (d0.then(d1).then(d2), Cand::none())
    } else {
        (d0, d0.event().then(d1.event()).then(d2.event()))
    };
    let kvx = c.k.mul(vx);
    let hvy = vy.mul(V::splat(0.5));
    let kpx = c.k.mul(px);
    let hpy = py.mul(V::splat(0.5));
    let e0 = Edge::new((kvx.add(hvy).neg(), kpx.add(hpy).neg().add(c.h)), ee, 0.0);
    let e1 = Edge::new((kvx.sub(hvy), kpx.sub(hpy)), ee, 1.0);
    let e2 = Edge::new((vy, py), ee, 2.0);
    let edge = e0.then(e1, c.certain).then(e2, c.certain);
    Front {
        o,
        px,
        py,
        vx,
        vy,
        vv,
        ed,
        ee,
        count,
        live,
        disk,
        timed,
        edge,
    }
}

/// The chosen disk's root and edge's quotient, and the event: the edge only where strictly
/// earlier.
#[inline(always)]
fn divide<V: Lanes, const BY_BETA: bool>(f: &Front<V>) -> Cand<V> {
    let disk = if BY_BETA { f.disk.event() } else { f.timed };
    disk.then(f.edge.event())
}

/// The exclusions (disk, edge) after the event `code` (`coll` where it is a collision) of lanes
/// that excluded disk `ed`: after a collision (m, none); after crossing k the endpoints of Eₖ
/// swap (m ↦ 3 − k − m), Pₖ and "none" become none, and Eₖ is the edge entered by.
#[inline(always)]
fn exclusions_after<V: Lanes>(code: V, coll: V::Mask, ed: V) -> (V, V) {
    let k = code.sub(V::splat(CROSSING_CODE));
    let none = V::splat(NO_LABEL);
    let keeps = V::and_not(ed.gt(none), ed.eq(k));
    let relabelled = V::select(keeps, V::splat(3.0).sub(k).sub(ed), none);
    (V::select(coll, code, relabelled), V::select(coll, none, k))
}

/// Records the event of the lanes of `f` in `out`, applies it into `next`, and returns the bits
/// (at their block positions) of the live lanes that had no next event (a zero or non-finite
/// velocity; the scalar kernel's `None`) and of the live lanes. Finished lanes are left
/// unchanged.
#[inline(always)]
fn back<V: Lanes, const L: usize>(
    c: &Consts<V>,
    f: &Front<V>,
    best: Cand<V>,
    counts: &mut BlockCounts,
    out: &mut EventLanes<L>,
    next: &mut EventLanes<L>,
) -> (u64, u64) {
    let zero = V::splat(0.0);
    let Front {
        o,
        px,
        py,
        vx,
        vy,
        vv,
        ed,
        ee,
        count,
        live,
        ..
    } = *f;
    let lost = V::bits(V::and_not(live, best.has));
    let go = V::and(live, best.has);

    // Record the event for the observers (the state before it is already in `out`).
    V::select(live, best.t, zero).store(&mut out.time[o..]);
    V::select(live, best.code, V::splat(NO_EVENT)).store(&mut out.code[o..]);
    let ci = V::load(&out.cell[0][o..]);
    let cj = V::load(&out.cell[1][o..]);
    let sg = V::load(&out.cell[2][o..]);

    // Carry it out: x = p + v t, then both outcomes, blended.
    let t = best.t;
    let code = best.code;
    let xx = px.add(vx.mul(t));
    let xy = py.add(vy.mul(t));
    let coll = code.lt(V::splat(CROSSING_CODE));
    let is1 = code.eq(V::splat(1.0));
    let is2 = code.eq(V::splat(2.0));
    // Collision with disk m: n = x − Pₘ (x − 0 = x for P₀ and for P₁'s y, exactly).
    let nx = xx.sub(V::select(is1, c.p1x, V::select(is2, c.p2x, zero)));
    let ny = xy.sub(V::select(is2, c.p2y, zero));
    let kf = vv.neg().add(V::splat(3.0)).mul(V::splat(0.5));
    let s = vx.mul(nx).add(vy.mul(ny)).mul(V::splat(2.0));
    let rvx = vx.sub(nx.mul(s)).mul(kf);
    let rvy = vy.sub(ny.mul(s)).mul(kf);
    // Crossing of edge k: p ↦ cₖ − x, v ↦ −v.
    let e0 = code.eq(V::splat(CROSSING_CODE));
    let e1 = code.eq(V::splat(CROSSING_CODE + 1.0));
    let cx = V::select(e0, c.c[0][0], V::select(e1, c.c[1][0], c.c[2][0]));
    let cy = V::select(e0, c.c[0][1], V::select(e1, c.c[1][1], c.c[2][1]));
    let npx = V::select(coll, xx, cx.sub(xx));
    let npy = V::select(coll, xy, cy.sub(xy));
    let nvx = V::select(coll, rvx, vx.neg());
    let nvy = V::select(coll, rvy, vy.neg());
    let (ned, nee) = exclusions_after(code, coll, ed);
    // Cell: steps (1, 1), (0, 1), (1, 0) across E₀, E₁, E₂, times s; s flips on a crossing.
    let e2 = code.eq(V::splat(CROSSING_CODE + 2.0));
    let nci = ci.add(V::select(V::or(e0, e2), sg, zero));
    let ncj = cj.add(V::select(V::or(e0, e1), sg, zero));
    let nsg = V::select(coll, sg, sg.neg());
    let ncount = count.add(V::select(coll, V::splat(1.0), zero));

    V::select(go, npx, px).store(&mut next.pos[0][o..]);
    V::select(go, npy, py).store(&mut next.pos[1][o..]);
    V::select(go, nvx, vx).store(&mut next.vel[0][o..]);
    V::select(go, nvy, vy).store(&mut next.vel[1][o..]);
    V::select(go, ned, ed).store(&mut next.excluded[0][o..]);
    V::select(go, nee, ee).store(&mut next.excluded[1][o..]);
    V::select(go, nci, ci).store(&mut next.cell[0][o..]);
    V::select(go, ncj, cj).store(&mut next.cell[1][o..]);
    V::select(go, nsg, sg).store(&mut next.cell[2][o..]);
    V::select(go, ncount, count).store(&mut counts.collisions[o..]);
    (lost << o, V::bits(live) << o)
}

/// One event for the `V::WIDTH` lanes starting at `o` (see [`back`] for what it returns).
#[inline(always)]
fn advance<V: Lanes, const L: usize, const BY_BETA: bool>(
    c: &Consts<V>,
    counts: &mut BlockCounts,
    out: &mut EventLanes<L>,
    next: &mut EventLanes<L>,
    o: usize,
) -> (u64, u64) {
    let f = front::<V, L, BY_BETA>(c, counts, out, o);
    let best = divide::<V, BY_BETA>(&f);
    back(c, &f, best, counts, out, next)
}

/// Steps between two calls of the progress callback: 2¹⁴ steps of a block, ≈ 2.4·10⁵ collisions.
const PROGRESS_STEPS: u64 = 1 << 14;

/// Steps the engine runs before the observers see them. An observer's rare work (an MSD
/// sample, a hop) is a branch on the event time, which is known only at the end of a step's long
/// divide/square-root chain; taken inside the engine loop, each misprediction would discard the
/// next step's work already in flight. Buffering a few steps and observing them afterwards
/// keeps the engine's loop free of unpredictable branches (8 steps of 16 lanes: 14 KiB, in L1).
pub const OBSERVE_EVERY: usize = 8;

/// One step of the `V::WIDTH` lanes at `o` of a block: the event of each live lane recorded in
/// `out` (whose state is the one before it) and carried out into `next`; returns the bits (at
/// their block positions) of the live lanes that had no next event and of the live lanes. The
/// one thing a kernel supplies to the lane skeleton (`run_steps`): the trap's fused step here,
/// any convex cell's in [`super::cells`].
pub trait LaneStep<V: Lanes> {
    /// The step (see the trait documentation).
    fn advance<const L: usize>(&self, buffers: StepBuffers<'_, L>, o: usize) -> (u64, u64);
}

/// What a step works on: the block's counts, the event buffer whose state is the one before the
/// step (its event recorded there), and the buffer of the state after it.
pub type StepBuffers<'a, const L: usize> = (
    &'a mut BlockCounts,
    &'a mut EventLanes<L>,
    &'a mut EventLanes<L>,
);

/// The trap's step, its disk rule fixed at compile time: by β (`BY_BETA`), or by every root.
struct TrapStep<V, const BY_BETA: bool>(Consts<V>);

impl<V: Lanes, const BY_BETA: bool> LaneStep<V> for TrapStep<V, BY_BETA> {
    #[inline(always)]
    fn advance<const L: usize>(&self, (c, out, next): StepBuffers<'_, L>, o: usize) -> (u64, u64) {
        advance::<V, L, BY_BETA>(&self.0, c, out, next, o)
    }
}

/// Runs the block until every lane has its quota of collisions, showing each step to `obs`.
/// `ring[0]` holds the starting states (the other fields are ignored) and, on return, the final
/// ones. Returns the index of a lane that lost its next event, if any (the run stops there,
/// after the observers have seen the steps before).
#[inline(always)]
pub(super) fn run<V: Lanes, O: Observer<BLOCK>>(
    trap: &Trap<f64>,
    counts: &mut BlockCounts,
    ring: &mut [EventLanes<BLOCK>],
    obs: &mut O,
    progress: &dyn Fn(u64),
) -> Option<usize> {
    if trap.choice().disks_by_beta {
        run_with::<V, O, true>(trap, counts, ring, obs, progress)
    } else {
        run_with::<V, O, false>(trap, counts, ring, obs, progress)
    }
}

/// [`run`] with the disk rule fixed at compile time: by β (`BY_BETA`), or by every root (below the
/// gap 2⁻²⁰, and always on the portable path, whose lanes are scalar code: there the β choice's
/// selects cost more than the roots it saves — 43.7 against 32.1 ns per collision at w = 0.1).
#[inline(always)]
pub(super) fn run_with<V: Lanes, O: Observer<BLOCK>, const BY_BETA: bool>(
    trap: &Trap<f64>,
    counts: &mut BlockCounts,
    ring: &mut [EventLanes<BLOCK>],
    obs: &mut O,
    progress: &dyn Fn(u64),
) -> Option<usize> {
    let step = TrapStep::<V, BY_BETA>(Consts::<V>::new(trap));
    run_steps::<V, O, _>(&step, counts, ring, obs, progress)
}

/// The lane skeleton: steps the block with `step` until every lane has its quota of
/// collisions, [`OBSERVE_EVERY`] steps at a time shown to `obs`, with progress every
/// [`PROGRESS_STEPS`]. `ring[0]` holds the starting states and, on return, the final ones;
/// returns a lane that lost its next event, if any.
#[inline(always)]
pub(super) fn run_steps<V: Lanes, O: Observer<BLOCK>, S: LaneStep<V>>(
    step: &S,
    counts: &mut BlockCounts,
    ring: &mut [EventLanes<BLOCK>],
    obs: &mut O,
    progress: &dyn Fn(u64),
) -> Option<usize> {
    debug_assert_eq!(ring.len(), OBSERVE_EVERY + 1);
    let mut reported = counts.collisions.iter().sum::<f64>();
    let mut steps = 0u64;
    loop {
        let mut filled = 0;
        let mut stop = None;
        while filled < OBSERVE_EVERY {
            let (done, rest) = ring.split_at_mut(filled + 1);
            let (out, next) = (&mut done[filled], &mut rest[0]);
            let mut lost = 0u64;
            let mut live = 0u64;
            let mut o = 0;
            while o < BLOCK {
                let (lo, li) = step.advance::<BLOCK>((&mut *counts, &mut *out, &mut *next), o);
                lost |= lo;
                live |= li;
                o += V::WIDTH;
            }
            out.live_bits = live;
            if lost != 0 {
                stop = Some(Some(lost.trailing_zeros() as usize));
                break;
            }
            if live == 0 {
                stop = Some(None);
                break;
            }
            filled += 1;
        }
        obs.observe::<V>(&ring[..filled]);
        // The state before the first unobserved step starts the next round (and is the final
        // state when the run stops).
        if filled > 0 {
            let (head, tail) = ring.split_at_mut(filled);
            copy_state(&tail[0], &mut head[0]);
        }
        if let Some(r) = stop {
            let done = counts.collisions.iter().sum::<f64>();
            progress((done - reported) as u64);
            return r;
        }
        steps += OBSERVE_EVERY as u64;
        if steps.is_multiple_of(PROGRESS_STEPS) {
            let done = counts.collisions.iter().sum::<f64>();
            progress((done - reported) as u64);
            reported = done;
        }
    }
}

/// Copies the lane states (position, velocity, exclusions, cell) of `from` into `to`.
#[inline(always)]
fn copy_state<const L: usize>(from: &EventLanes<L>, to: &mut EventLanes<L>) {
    to.pos = from.pos;
    to.vel = from.vel;
    to.excluded = from.excluded;
    to.cell = from.cell;
}
