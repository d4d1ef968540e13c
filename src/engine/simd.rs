//! The multi-trajectory engine of the triangular lattice: [`BLOCK`] independent trajectories
//! advance one event per step in vector lanes, branch-free.
//!
//! No closures in this file's hot code: a closure does not inherit the target features of the
//! function it is written in, so its vector operations would be calls rather than instructions.
//!
//! Every lane executes exactly the correctly rounded operations of the trap's kernel
//! ([`crate::kernel::trap::Trap::next_event`] and [`crate::kernel::trap::Trap::apply`]), in the
//! same order, on the same constants (taken from the `Trap<f64>` itself):
//!
//! * all five candidates are computed in every lane — the three vertex disks by the
//!   cancellation-free root (β = d·v, q = d×v, Δ = |v|² − q², γ = |d|² − 1,
//!   t = γ/(√Δ − β)), the three edges by σₖ/(−nₖ·v) — and a candidate the scalar code would not
//!   offer (excluded by identity, moving away, missing, or not leaving through the edge) is
//!   masked out rather than skipped;
//! * the earliest is chosen by the scalar code's rule, offered in the order disk 0, 1, 2, edge
//!   0, 1, 2 and taken only if strictly earlier (so ties go to the lower disk, then collisions
//!   before crossings, then the lower edge), with a separate "have one" mask so that not even an
//!   infinite time could change the choice;
//! * the reflection (with its Newton speed factor) and the point reflection into the
//!   neighbouring trap are both computed and blended by the event mask; the exclusion labels
//!   and the cell index (i, j, s) are updated by masks as exact small integers.
//!
//! The trap's fused path skips operations that are exact in its coordinates (d = p − P₀ = p,
//! p_y − 0); a lane skips exactly the same ones, and where the scalar code branches between two
//! exact forms (n = x for P₀, n = x − Pₘ otherwise) the lane computes x − 0, which is the same
//! value bit for bit. `tests/numerics/engine.rs` checks every event of every lane against the scalar
//! kernel, on every code path the machine has.

use crate::engine::observe::{EventLanes, Observer, CROSSING_CODE, NO_EVENT, NO_LABEL};
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
        }
    }
}

/// The cancellation-free root of [`crate::kernel::ray_disk`] in every lane: the time, and the
/// mask of lanes where the scalar code returns `Some` (β < 0 and Δ > 0); where γ ≤ 0 the time
/// is 0 (a start numerically inside, moving in).
#[inline(always)]
fn root<V: Lanes>(dx: V, dy: V, vx: V, vy: V, vv: V) -> (V, V::Mask) {
    let zero = V::splat(0.0);
    let beta = dx.mul(vx).add(dy.mul(vy));
    let q = dx.mul(vy).sub(dy.mul(vx));
    let disc = vv.sub(q.mul(q));
    let gamma = dx.mul(dx).add(dy.mul(dy)).add(V::splat(-1.0));
    let hit = V::and(beta.lt(zero), disc.gt(zero));
    let t = gamma.div(disc.sqrt().sub(beta));
    (V::select(gamma.gt(zero), t, zero), hit)
}

/// A candidate event per lane: time, code, and whether there is one.
#[derive(Clone, Copy)]
struct Cand<V: Lanes> {
    t: V,
    code: V,
    has: V::Mask,
}

impl<V: Lanes> Cand<V> {
    #[inline(always)]
    fn new(valid: V::Mask, t: V, code: f64) -> Self {
        Cand {
            t,
            code: V::splat(code),
            has: valid,
        }
    }

    /// The earlier of `self` and a candidate `later` offered after it: `later` wins only where
    /// `self` has none or `later` is strictly earlier — the scalar `offer`. Offering the
    /// candidates one by one in the scalar order picks the first of the earliest; so does this
    /// rule applied as a tree over the same order (ties keep the left, which came first), which
    /// halves the dependent chain of comparisons.
    #[inline(always)]
    fn then(self, later: Self) -> Self {
        let take = V::and(
            later.has,
            V::or(later.t.lt(self.t), V::and_not(later.has, self.has)),
        );
        Cand {
            t: V::select(take, later.t, self.t),
            code: V::select(take, later.code, self.code),
            has: V::or(self.has, later.has),
        }
    }
}

/// The crossing candidate of edge `e` from (nᵉ·v, σₑ): offered where nᵉ·v < 0 and the edge is
/// not the one entered by; time σₑ/(−nᵉ·v), or 0 where σₑ ≤ 0.
#[inline(always)]
fn crossing<V: Lanes>((nv, sigma): (V, V), ee: V, e: f64) -> Cand<V> {
    let zero = V::splat(0.0);
    let valid = V::and_not(nv.lt(zero), ee.eq(V::splat(e)));
    let t = V::select(sigma.gt(zero), sigma.div(nv.neg()), zero);
    Cand::new(valid, t, CROSSING_CODE + e)
}

/// One event for the `V::WIDTH` lanes starting at `o`: records each live lane's event and prior
/// state in `out`, applies it, and returns the bits (at their block positions) of the live lanes
/// that had no next event (a zero or non-finite velocity; the scalar kernel's `None`) and of the
/// live lanes. Finished lanes are left unchanged.
#[inline(always)]
fn advance<V: Lanes, const L: usize>(
    c: &Consts<V>,
    counts: &mut BlockCounts,
    out: &mut EventLanes<L>,
    next: &mut EventLanes<L>,
    o: usize,
) -> (u64, u64) {
    let zero = V::splat(0.0);
    let px = V::load(&out.pos[0][o..]);
    let py = V::load(&out.pos[1][o..]);
    let vx = V::load(&out.vel[0][o..]);
    let vy = V::load(&out.vel[1][o..]);
    let ed = V::load(&out.excluded[0][o..]);
    let ee = V::load(&out.excluded[1][o..]);
    let count = V::load(&counts.collisions[o..]);
    let live = count.lt(V::load(&counts.quota[o..]));

    // Candidates, in the scalar code's order of offers.
    let vv = vx.mul(vx).add(vy.mul(vy));
    let (t0, h0) = root(px, py, vx, vy, vv);
    let d0 = Cand::new(V::and_not(h0, ed.eq(V::splat(0.0))), t0, 0.0);
    let (t1, h1) = root(px.sub(c.p1x), py, vx, vy, vv);
    let d1 = Cand::new(V::and_not(h1, ed.eq(V::splat(1.0))), t1, 1.0);
    let (t2, h2) = root(px.sub(c.p2x), py.sub(c.p2y), vx, vy, vv);
    let d2 = Cand::new(V::and_not(h2, ed.eq(V::splat(2.0))), t2, 2.0);
    let kvx = c.k.mul(vx);
    let hvy = vy.mul(V::splat(0.5));
    let kpx = c.k.mul(px);
    let hpy = py.mul(V::splat(0.5));
    let edges = [
        (kvx.add(hvy).neg(), kpx.add(hpy).neg().add(c.h)),
        (kvx.sub(hvy), kpx.sub(hpy)),
        (vy, py),
    ];
    let c0 = crossing(edges[0], ee, 0.0);
    let c1 = crossing(edges[1], ee, 1.0);
    let c2 = crossing(edges[2], ee, 2.0);
    // The scalar order d0, d1, d2, e0, e1, e2 as a tree: ((d0 d1)(d2 e0))(e1 e2).
    let best = d0.then(d1).then(d2.then(c0)).then(c1.then(c2));
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
    // Exclusions: after a collision (m, none); after crossing k the endpoints of Eₖ swap
    // (m ↦ 3 − k − m), Pₖ and "none" become none, and Eₖ is the edge entered by.
    let k = code.sub(V::splat(CROSSING_CODE));
    let none = V::splat(NO_LABEL);
    let keeps = V::and_not(ed.gt(none), ed.eq(k));
    let relabelled = V::select(keeps, V::splat(3.0).sub(k).sub(ed), none);
    let ned = V::select(coll, code, relabelled);
    let nee = V::select(coll, none, k);
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

/// Steps between two calls of the progress callback: 2¹⁴ steps of a block, ≈ 2.4·10⁵ collisions.
const PROGRESS_STEPS: u64 = 1 << 14;

/// Steps the engine runs before the observers see them. An observer's rare work (an MSD
/// sample, a hop) is a branch on the event time, which is known only at the end of a step's long
/// divide/square-root chain; taken inside the engine loop, each misprediction would discard the
/// next step's work already in flight. Buffering a few steps and observing them afterwards
/// keeps the engine's loop free of unpredictable branches (8 steps of 16 lanes: 14 KiB, in L1).
pub const OBSERVE_EVERY: usize = 8;

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
    debug_assert_eq!(ring.len(), OBSERVE_EVERY + 1);
    let c = Consts::<V>::new(trap);
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
                let (lo, li) = advance::<V, BLOCK>(&c, counts, out, next, o);
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
