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

use crate::Error;
use crate::engine::SimdPath;
use crate::engine::observe::{CROSSING_CODE, EventLanes, NO_LABEL};
use crate::engine::simd::BLOCK;
use crate::kernel::cell::{ConvexCell, EdgeMap};
use crate::numbers::lanes::{self, Lanes};
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

/// A disk's constants: centre, radius, radius² (the cell's own rounded r²).
struct DiskC<V> {
    cx: V,
    cy: V,
    r: V,
    r2: V,
}

/// An edge's constants: inward normal, offset, its map (a translation by t or the point
/// reflection about c, with `flips`), the label entered by, the disk exclusions carried across
/// (as codes, one per disk), and the cell step.
struct EdgeC<V> {
    nx: V,
    ny: V,
    off: V,
    map: [V; 2],
    flips: bool,
    entered: V,
    disks_after: Vec<V>,
    step: [V; 2],
}

/// The block's constants, splatted.
struct Consts<V> {
    disks: Vec<DiskC<V>>,
    edges: Vec<EdgeC<V>>,
    w: V,
    aw: V,
    left: bool,
    unit_disks: bool,
}

impl<V: Lanes> Consts<V> {
    #[inline(always)]
    fn new(cell: &ConvexCell<f64>, w: f64) -> Self {
        let disks = cell
            .disks
            .iter()
            .map(|d| DiskC {
                cx: V::splat(d.centre.x),
                cy: V::splat(d.centre.y),
                r: V::splat(*d.radius()),
                r2: V::splat(*d.radius2()),
            })
            .collect();
        let edges = cell
            .edges
            .iter()
            .map(|e| {
                let (m, flips) = match &e.map {
                    EdgeMap::Translation(t) => (t, false),
                    EdgeMap::PointReflection(c) => (c, true),
                };
                EdgeC {
                    nx: V::splat(e.normal.x),
                    ny: V::splat(e.normal.y),
                    off: V::splat(e.offset),
                    map: [V::splat(m.x), V::splat(m.y)],
                    flips,
                    entered: V::splat(f64::from(e.entered)),
                    disks_after: e
                        .disks_after
                        .iter()
                        .map(|a| V::splat(a.map_or(NO_LABEL, f64::from)))
                        .collect(),
                    step: [V::splat(e.step[0] as f64), V::splat(e.step[1] as f64)],
                }
            })
            .collect();
        Consts {
            disks,
            edges,
            w: V::splat(w),
            aw: V::splat(w.abs()),
            left: w > 0.0,
            unit_disks: cell.disks.iter().all(|d| *d.radius2() == 1.0),
        }
    }
}

/// The arc of every lane: velocity, |v|², |v|, and the all-true mask.
#[derive(Clone, Copy)]
struct ArcL<V: Lanes> {
    vx: V,
    vy: V,
    vv: V,
    speed: V,
    all: V::Mask,
}

/// A candidate per lane: chord, found in the disk's frame, present, and the chord's place on the
/// way round for [`earlier`] (computed once per candidate).
#[derive(Clone, Copy)]
struct Cand<V: Lanes> {
    x: V,
    y: V,
    frame: V::Mask,
    has: V::Mask,
    turning: V::Mask,
    half: V::Mask,
    near: V::Mask,
    len: V,
}

impl<V: Lanes> Cand<V> {
    #[inline(always)]
    fn new(a: &ArcL<V>, left: bool, (x, y): (V, V), frame: V::Mask, has: V::Mask) -> Self {
        let (turning, half, near) = stage(a, left, x, y);
        Cand {
            x,
            y,
            frame,
            has,
            turning,
            half,
            near,
            len: x.mul(x).add(y.mul(y)),
        }
    }
}

#[inline(always)]
fn not<V: Lanes>(m: V::Mask, all: V::Mask) -> V::Mask {
    V::and_not(all, m)
}

/// `true` where both components are zero ([`crate::kernel::arc::is_zero`]: neither > 0 nor < 0).
#[inline(always)]
fn is_zero<V: Lanes>(x: V, y: V, all: V::Mask) -> V::Mask {
    let z = V::splat(0.0);
    let any = V::or(V::or(x.gt(z), x.lt(z)), V::or(y.gt(z), y.lt(z)));
    not::<V>(any, all)
}

/// `!(mm − noise² > 0)` with noise = (|ω|·√|d|² + V)·8u ([`crate::kernel::arc::Arc::creeps`]),
/// its square root taken only where a bound without it cannot rule the test out.
#[inline(always)]
fn coincident<V: Lanes>(c: &Consts<V>, a: &ArcL<V>, dd: V, mm: V, lanes: V::Mask) -> V::Mask {
    let eight_u = V::splat(8.0 * f64::EPSILON / 2.0);
    let hi = c.aw.mul(dd.add(V::splat(1.0))).add(a.speed).mul(eight_u);
    let maybe = V::and(lanes, V::ge(hi.mul(hi), mm));
    if V::bits(maybe) == 0 {
        return maybe;
    }
    let noise = c.aw.mul(dd.sqrt()).add(a.speed).mul(eight_u);
    V::and(
        lanes,
        not::<V>(mm.sub(noise.mul(noise)).gt(V::splat(0.0)), a.all),
    )
}

/// The disk-frame contact ([`crate::kernel::arc::Arc`]'s `disk_frame`) where it decides:
/// (no contact, a contact, chord x, chord y).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn disk_frame<V: Lanes>(
    c: &Consts<V>,
    a: &ArcL<V>,
    d: &DiskC<V>,
    (dx, dy, dd): (V, V, V),
    (mx, my, mm): (V, V, V),
    ok: V::Mask,
) -> (V::Mask, V::Mask, V, V) {
    let z = V::splat(0.0);
    let conc = coincident(c, a, dd, mm, ok);
    let sm = mm.sqrt();
    let awr = c.aw.mul(d.r);
    let g = awr.sub(a.speed).mul(awr.add(a.speed)).add(mm);
    let aa = g.div(c.w.mul(V::splat(2.0)).mul(sm));
    let rs2 = d.r.sub(aa).mul(d.r.add(aa));
    let some = V::and(V::and_not(ok, conc), rs2.gt(z));
    let rs = rs2.sqrt();
    let yx = aa.mul(mx).sub(rs.mul(my)).div(sm);
    let yy = aa.mul(my).add(rs.mul(mx)).div(sm);
    (conc, some, yx.sub(dx), yy.sub(dy))
}

/// Disk `m`'s contact in every lane ([`crate::kernel::arc::Arc::contact`]), and where the
/// particle, on it, slides ([`crate::kernel::arc::Arc::creeps`]: the scalar kernel then has no
/// event at all).
#[inline(always)]
fn disk<V: Lanes>(
    c: &Consts<V>,
    a: &ArcL<V>,
    d: &DiskC<V>,
    (px, py): (V, V),
    on: V::Mask,
) -> (Cand<V>, V::Mask) {
    let (z, w, all) = (V::splat(0.0), c.w, a.all);
    let (dx, dy) = (px.sub(d.cx), py.sub(d.cy));
    let beta = dx.mul(a.vx).add(dy.mul(a.vy));
    let q = dx.mul(a.vy).sub(dy.mul(a.vx));
    let vv_wq = a.vv.sub(w.mul(q));
    let wb = w.mul(beta);
    let inv = a.vv.div(vv_wq.mul(vv_wq).add(wb.mul(wb)));
    let (ex, ey) = (a.vx.add(w.mul(dy)), a.vy.sub(w.mul(dx)));
    let dd = dx.mul(dx).add(dy.mul(dy));
    let gamma = V::select(on, z, dd.sub(d.r2));
    let onc = not::<V>(gamma.gt(z), all);
    let (bpos, bneg) = (beta.gt(z), beta.lt(z));
    let (mx, my) = (w.mul(dx).sub(a.vy), w.mul(dy).add(a.vx));
    let mm = mx.mul(mx).add(my.mul(my));
    let turn_in = w.mul(a.vy.neg().mul(dx).add(a.vx.mul(dy))).lt(z);
    // Creeping: on the disk, moving along it (β = 0) turning in, or on its own circle.
    let along = V::and(not::<V>(V::or(bpos, bneg), all), turn_in);
    let stuck = V::or(V::and(on, along), coincident(c, a, dd, mm, on));
    // The disk frame, where 4M < V² in a lane that consults it.
    let ok = V::and(
        a.vv.sub(mm.mul(V::splat(4.0))).gt(z),
        V::or(not::<V>(onc, all), V::and(onc, bpos)),
    );
    let (none, some, fx, fy) = if V::bits(ok) == 0 {
        (ok, ok, z, z)
    } else {
        disk_frame(c, a, d, (dx, dy, dd), (mx, my, mm), ok)
    };
    // Off the circle moving in, a disk-frame entry within its rounding of the particle is now.
    let near = entry_now(
        c,
        a,
        d,
        (dd, mm),
        (fx, fy),
        V::and(V::and_not(some, onc), bneg),
    );
    let (fx, fy) = (V::select(near, z, fx), V::select(near, z, fy));
    let frame = V::and_not(some, near);
    // On the circle, moving out: the return s = −2β/M.
    let s_ret = beta.mul(V::splat(-2.0)).mul(inv);
    // Off it: the entry.
    let vr = a.speed.mul(d.r);
    let shift = q.sub(w.mul(gamma).mul(V::splat(0.5)));
    let k = vv_wq.add(w.mul(w).mul(gamma).mul(V::splat(0.25)));
    let product = vr.add(shift).mul(vr.sub(shift));
    // Off the circle with K < 0, β² − γK where the product rounded to ≤ 0.
    let sum = beta.mul(beta).sub(gamma.mul(k));
    let cancelled = V::and_not(V::and(gamma.gt(z), k.lt(z)), product.gt(z));
    let disc = V::select(cancelled, sum, product);
    let root = disc.sqrt();
    let s_in = V::select(
        bneg,
        gamma.mul(k).div(root.sub(beta)).mul(inv),
        beta.add(root).neg().mul(inv),
    );
    let f = w.mul(gamma).mul(V::splat(0.5)).neg().mul(inv);
    let (nx, ny) = (f.mul(mx).add(s_in.mul(ex)), f.mul(my).add(s_in.mul(ey)));
    let ret = V::and(onc, bpos);
    let now = V::and(V::and_not(onc, bpos), V::or(bneg, turn_in));
    let decided = V::or(none, some);
    let off = V::and(
        not::<V>(onc, all),
        V::or(some, V::and_not(disc.gt(z), decided)),
    );
    let has = V::or(V::or(V::and_not(ret, none), now), off);
    let x = V::select(
        some,
        fx,
        V::select(ret, ex.mul(s_ret), V::select(now, z, nx)),
    );
    let y = V::select(
        some,
        fy,
        V::select(ret, ey.mul(s_ret), V::select(now, z, ny)),
    );
    (Cand::new(a, c.left, (x, y), frame, has), stuck)
}

/// Where a disk-frame entry (chord `f`) of a particle off the circle moving in (`lanes`) lies
/// within its own rounding of the particle ([`crate::kernel::arc::Arc`]'s `entry_now`): there
/// the contact is now.
#[inline(always)]
fn entry_now<V: Lanes>(
    c: &Consts<V>,
    a: &ArcL<V>,
    d: &DiskC<V>,
    (dd, mm): (V, V),
    (fx, fy): (V, V),
    lanes: V::Mask,
) -> V::Mask {
    if V::bits(lanes) == 0 {
        return lanes;
    }
    let dn = dd.sqrt();
    let turn = d.r.mul(c.aw.mul(dn).add(a.speed)).div(mm.sqrt());
    let four_u = V::splat(4.0 * f64::EPSILON / 2.0);
    let bound = turn.add(d.r.add(dn).mul(V::splat(2.0))).mul(four_u);
    let chord2 = fx.mul(fx).add(fy.mul(fy));
    V::and(
        lanes,
        not::<V>(chord2.sub(bound.mul(bound)).gt(V::splat(0.0)), a.all),
    )
}

/// Edge `e`'s exit in every lane ([`crate::kernel::arc::arc_line`]).
#[inline(always)]
fn edge<V: Lanes>(
    c: &Consts<V>,
    a: &ArcL<V>,
    e: &EdgeC<V>,
    (px, py): (V, V),
    entered: V::Mask,
) -> Cand<V> {
    let (z, w, all) = (V::splat(0.0), c.w, a.all);
    let aa = e.nx.mul(a.vx).add(e.ny.mul(a.vy));
    let (jx, jy) = (e.ny.neg(), e.nx);
    let sigma = e.nx.mul(px).add(e.ny.mul(py)).sub(e.off);
    let online = V::or(entered, not::<V>(sigma.gt(z), all));
    let apos = aa.gt(z);
    let b = e.nx.mul(a.vy.neg()).add(e.ny.mul(a.vx));
    let out = V::or(aa.lt(z), w.mul(b).lt(z));
    let ws = w.mul(sigma);
    let cc = ws.add(b.mul(V::splat(2.0)));
    let disc = aa.mul(aa).sub(ws.mul(cc));
    let root = disc.sqrt();
    // One quotient: 2a/ω (the return), (a + √Δ)/ω or −σc/(√Δ − a) (the exit).
    let num = V::select(
        online,
        aa.mul(V::splat(2.0)),
        V::select(apos, aa.add(root), sigma.mul(cc).neg()),
    );
    let den = V::select(V::or(online, apos), w, root.sub(aa));
    let s = num.div(den);
    let (ox, oy) = (
        s.mul(jx).sub(sigma.mul(e.nx)),
        s.mul(jy).sub(sigma.mul(e.ny)),
    );
    let back = V::and(online, apos);
    let now = V::and(V::and_not(online, apos), out);
    let exit = V::and(not::<V>(online, all), disc.gt(z));
    let x = V::select(back, jx.mul(s), V::select(now, z, ox));
    let y = V::select(back, jy.mul(s), V::select(now, z, oy));
    Cand::new(
        a,
        c.left,
        (x, y),
        V::from_bits(0),
        V::or(V::or(back, now), exit),
    )
}

/// A chord's stage on the way round and its class ([`crate::kernel::arc::earlier`]):
/// (turning, at the half-turn, near: at the start or turning within π/4 of v).
#[inline(always)]
fn stage<V: Lanes>(a: &ArcL<V>, left: bool, x: V, y: V) -> (V::Mask, V::Mask, V::Mask) {
    let (z, all) = (V::splat(0.0), a.all);
    let side = a.vx.mul(y).sub(a.vy.mul(x));
    let dot = a.vx.mul(x).add(a.vy.mul(y));
    let turning = if left { side.gt(z) } else { side.lt(z) };
    let start = V::and_not(V::or(is_zero::<V>(x, y, all), dot.gt(z)), turning);
    let half = V::and_not(V::and_not(all, turning), start);
    let near = V::or(start, V::and(turning, V::ge(dot, side.abs())));
    (turning, half, near)
}

/// Where candidate `c1` comes strictly before `c2` ([`crate::kernel::arc::earlier`]), lane by
/// lane.
#[inline(always)]
fn earlier<V: Lanes>(a: &ArcL<V>, left: bool, c1: &Cand<V>, c2: &Cand<V>) -> V::Mask {
    let z = V::splat(0.0);
    let both_near = V::and(c1.near, c2.near);
    let far = not::<V>(V::or(c1.near, c2.near), a.all);
    let cross = c1.x.mul(c2.y).sub(c1.y.mul(c2.x));
    let turned = if left { cross.gt(z) } else { cross.lt(z) };
    // Both far: a turning chord before a half-turn one; two half-turn chords by length
    // (longer first), two turning ones by the cross product.
    let far_rule = V::or(
        V::and(c1.turning, c2.half),
        V::or(
            V::and(V::and(c1.half, c2.half), c1.len.gt(c2.len)),
            V::and(V::and(c1.turning, c2.turning), turned),
        ),
    );
    V::or(
        V::or(
            V::and(both_near, c1.len.lt(c2.len)),
            V::and_not(c1.near, c2.near),
        ),
        V::and(far, far_rule),
    )
}

/// `m ? a : b` on masks.
#[inline(always)]
fn blend<V: Lanes>(m: V::Mask, a: V::Mask, b: V::Mask) -> V::Mask {
    V::or(V::and(m, a), V::and_not(b, m))
}

/// `later` replaces `best` where it has a chord and `best` has none or it is strictly earlier.
#[inline(always)]
fn offer<V: Lanes>(a: &ArcL<V>, left: bool, best: Cand<V>, later: Cand<V>) -> (Cand<V>, V::Mask) {
    let better = earlier(a, left, &later, &best);
    let take = V::and(later.has, V::or(better, V::and_not(a.all, best.has)));
    let c = Cand {
        x: V::select(take, later.x, best.x),
        y: V::select(take, later.y, best.y),
        frame: blend::<V>(take, later.frame, best.frame),
        has: V::or(best.has, later.has),
        turning: blend::<V>(take, later.turning, best.turning),
        half: blend::<V>(take, later.half, best.half),
        near: blend::<V>(take, later.near, best.near),
        len: V::select(take, later.len, best.len),
    };
    (c, take)
}

/// A lane's loaded state.
struct Loaded<V: Lanes> {
    p: (V, V),
    v: (V, V),
    ed: V,
    ee: V,
    cell: [V; 3],
}

/// The earliest candidate of every lane and its code (disk m, or [`CROSSING_CODE`] + edge k),
/// and where the scalar kernel has no event.
#[inline(always)]
fn choose<V: Lanes>(c: &Consts<V>, a: &ArcL<V>, s: &Loaded<V>) -> (Cand<V>, V, V::Mask) {
    let z = V::splat(0.0);
    // The first offer has nothing to beat (the scalar `offer`'s `is_none_or`).
    let (mut best, mut stuck) = disk(c, a, &c.disks[0], s.p, s.ed.eq(z));
    let mut code = z;
    for (m, d) in c.disks.iter().enumerate().skip(1) {
        let label = V::splat(m as f64);
        let (cand, slides) = disk(c, a, d, s.p, s.ed.eq(label));
        stuck = V::or(stuck, slides);
        let (b, take) = offer(a, c.left, best, cand);
        best = b;
        code = V::select(take, label, code);
    }
    for (k, e) in c.edges.iter().enumerate() {
        let cand = edge(c, a, e, s.p, s.ee.eq(V::splat(k as f64)));
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
    let d0 = &c.disks[0];
    let (mut cx, mut cy, mut r2) = (d0.cx, d0.cy, d0.r2);
    for (m, d) in c.disks.iter().enumerate().skip(1) {
        let here = code.eq(V::splat(m as f64));
        cx = V::select(here, d.cx, cx);
        cy = V::select(here, d.cy, cy);
        r2 = V::select(here, d.r2, r2);
    }
    let (nx, ny) = (x.sub(cx), y.sub(cy));
    let twice = ux.mul(nx).add(uy.mul(ny)).mul(V::splat(2.0));
    // x/1 = x exactly in IEEE arithmetic: unit disks skip the division.
    let s = if c.unit_disks { twice } else { twice.div(r2) };
    (ux.sub(nx.mul(s)), uy.sub(ny.mul(s)))
}

/// Where each lane is after crossing the edge `code` at x with velocity u: position,
/// velocity, exclusions, cell (the carried exclusion only if the particle did not move).
#[inline(always)]
fn cross<V: Lanes>(
    c: &Consts<V>,
    s: &Loaded<V>,
    code: V,
    (x, y): (V, V),
    (ux, uy): (V, V),
    moved: V::Mask,
) -> Loaded<V> {
    let mut out = Loaded {
        p: (x, y),
        v: (ux, uy),
        ed: s.ed,
        ee: s.ee,
        cell: s.cell,
    };
    let no = V::splat(NO_LABEL);
    for (k, e) in c.edges.iter().enumerate() {
        let here = code.eq(V::splat(CROSSING_CODE + k as f64));
        let (px, py, vx, vy, sg) = if e.flips {
            let (px, py) = (e.map[0].sub(x), e.map[1].sub(y));
            (px, py, ux.neg(), uy.neg(), s.cell[2].neg())
        } else {
            (x.sub(e.map[0]), y.sub(e.map[1]), ux, uy, s.cell[2])
        };
        let mut ed = no;
        for (m, after) in e.disks_after.iter().enumerate() {
            ed = V::select(s.ed.eq(V::splat(m as f64)), *after, ed);
        }
        let ed = V::select(moved, no, ed);
        let i = s.cell[0].add(s.cell[2].mul(e.step[0]));
        let j = s.cell[1].add(s.cell[2].mul(e.step[1]));
        out.p = (V::select(here, px, out.p.0), V::select(here, py, out.p.1));
        out.v = (V::select(here, vx, out.v.0), V::select(here, vy, out.v.1));
        out.ed = V::select(here, ed, out.ed);
        out.ee = V::select(here, e.entered, out.ee);
        out.cell = [
            V::select(here, i, out.cell[0]),
            V::select(here, j, out.cell[1]),
            V::select(here, sg, out.cell[2]),
        ];
    }
    out
}

/// One event for the `V::WIDTH` lanes at `o`: returns the lanes that lost their next event and
/// those still running, as bits of the block.
#[inline(always)]
fn step<V: Lanes>(c: &Consts<V>, st: &mut ArcLanes, o: usize) -> (u64, u64) {
    let z = V::splat(0.0);
    let count = V::load(&st.collisions[o..]);
    let live = count.lt(V::load(&st.quota[o..]));
    if V::bits(live) == 0 {
        return (0, 0);
    }
    let s = Loaded {
        p: (
            V::load(&st.lanes.pos[0][o..]),
            V::load(&st.lanes.pos[1][o..]),
        ),
        v: (
            V::load(&st.lanes.vel[0][o..]),
            V::load(&st.lanes.vel[1][o..]),
        ),
        ed: V::load(&st.lanes.excluded[0][o..]),
        ee: V::load(&st.lanes.excluded[1][o..]),
        cell: [
            V::load(&st.lanes.cell[0][o..]),
            V::load(&st.lanes.cell[1][o..]),
            V::load(&st.lanes.cell[2][o..]),
        ],
    };
    let (vx, vy) = s.v;
    let vv = vx.mul(vx).add(vy.mul(vy));
    let a = ArcL {
        vx,
        vy,
        vv,
        speed: vv.sqrt(),
        all: V::eq(z, z),
    };
    let (best, code, lost) = choose(c, &a, &s);
    let lost = V::and(live, lost);
    let go = V::and_not(live, lost);
    let u = arrival(c, &a, &best);
    let newton = vv.neg().add(V::splat(3.0)).mul(V::splat(0.5));
    let x = (s.p.0.add(best.x), s.p.1.add(best.y));
    let moved = V::and_not(a.all, is_zero::<V>(best.x, best.y, a.all));
    let hit = code.lt(V::splat(CROSSING_CODE));
    let r = collide(c, code, x, u);
    let mut n = cross(c, &s, code, x, u, moved);
    n.p = (V::select(hit, x.0, n.p.0), V::select(hit, x.1, n.p.1));
    n.v = (V::select(hit, r.0, n.v.0), V::select(hit, r.1, n.v.1));
    n.ed = V::select(hit, code, n.ed);
    n.ee = V::select(hit, V::splat(NO_LABEL), n.ee);
    let (nvx, nvy) = (n.v.0.mul(newton), n.v.1.mul(newton));
    V::select(go, n.p.0, s.p.0).store(&mut st.lanes.pos[0][o..]);
    V::select(go, n.p.1, s.p.1).store(&mut st.lanes.pos[1][o..]);
    V::select(go, nvx, vx).store(&mut st.lanes.vel[0][o..]);
    V::select(go, nvy, vy).store(&mut st.lanes.vel[1][o..]);
    V::select(go, n.ed, s.ed).store(&mut st.lanes.excluded[0][o..]);
    V::select(go, n.ee, s.ee).store(&mut st.lanes.excluded[1][o..]);
    for k in 0..3 {
        V::select(go, n.cell[k], s.cell[k]).store(&mut st.lanes.cell[k][o..]);
    }
    let one = V::splat(1.0);
    let crossings = V::load(&st.crossings[o..]);
    V::select(V::and(go, hit), count.add(one), count).store(&mut st.collisions[o..]);
    V::select(V::and_not(go, hit), crossings.add(one), crossings).store(&mut st.crossings[o..]);
    (V::bits(lost) << o, V::bits(live) << o)
}

/// Runs the block for at most `limit` steps, until every lane has its quota of collisions;
/// returns a lane that lost its next event, if any (the block stops there).
#[inline(always)]
fn run<V: Lanes>(cell: &ConvexCell<f64>, w: f64, st: &mut ArcLanes, limit: u64) -> Option<usize> {
    let c = Consts::<V>::new(cell, w);
    for _ in 0..limit {
        let (mut lost, mut live) = (0u64, 0u64);
        let mut o = 0;
        while o < BLOCK {
            let (l, v) = step::<V>(&c, st, o);
            lost |= l;
            live |= v;
            o += V::WIDTH;
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

/// One `zmm` vector at a time: a step of the arc engine keeps far more values live than the
/// straight engine's, and a pair of vectors spilled them (0.94 of the pair's time per
/// collision, w = 0.1, B = 1, paired runs).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn run_avx512(
    cell: &ConvexCell<f64>,
    w: f64,
    st: &mut ArcLanes,
    limit: u64,
) -> Option<usize> {
    run::<lanes::Avx512>(cell, w, st, limit)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn run_avx2(cell: &ConvexCell<f64>, w: f64, st: &mut ArcLanes, limit: u64) -> Option<usize> {
    run::<lanes::Pair<lanes::Avx2>>(cell, w, st, limit)
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
    if states.len() > BLOCK || quotas.len() != states.len() {
        return Err(Error::Invalid(format!(
            "an arc block runs 1 to {BLOCK} trajectories with one quota each (got {} states, {} quotas)",
            states.len(),
            quotas.len()
        )));
    }
    if !(w.is_finite() && w != 0.0) {
        return Err(Error::Invalid(format!(
            "the arc engine needs a finite nonzero field (got {w})"
        )));
    }
    if !path.available() {
        return Err(Error::Invalid(format!(
            "this CPU cannot run the {path} path"
        )));
    }
    if cell.disks.is_empty() {
        return Err(Error::Invalid(
            "the arc engine needs a cell with disks".into(),
        ));
    }
    for &q in quotas {
        super::check_trajectory_length(q)?;
    }
    let mut st = load(states, quotas);
    let lost = match path {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: `path.available()` checked the CPU feature above.
        SimdPath::Avx512 => unsafe { run_avx512(cell, w, &mut st, limit) },
        #[cfg(target_arch = "x86_64")]
        // SAFETY: as above.
        SimdPath::Avx2 => unsafe { run_avx2(cell, w, &mut st, limit) },
        _ => run::<lanes::Portable>(cell, w, &mut st, limit),
    };
    unload(&st, states);
    match lost {
        Some(l) => Err(Error::Failed(format!(
            "trajectory {l} of the arc block has no next event (a pinned or creeping orbit, or velocity {:?})",
            [states[l].flight.vel.x, states[l].flight.vel.y]
        ))),
        None => Ok(st.crossings[..states.len()]
            .iter()
            .map(|&c| c as u64)
            .collect()),
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::arc::earlier as scalar_earlier;
    use crate::kernel::vec2::Vec2;
    use rand::{Rng, SeedableRng};

    /// A chord of the arc of velocity v in one of the places `earlier` tells apart: zero, just
    /// behind or ahead of v, turning within or beyond π/4, or near the half-turn (short and
    /// behind), at lengths from 10⁻¹⁸ to 2.
    fn chord(rng: &mut impl Rng, v: (f64, f64), left: bool) -> (f64, f64) {
        let side = if left { 1.0 } else { -1.0 };
        let (jx, jy) = (-v.1 * side, v.0 * side);
        let len = 10f64.powf(rng.random_range(-18.0..0.3));
        let (a, b) = match rng.random_range(0..6) {
            0 => return (0.0, 0.0),
            1 => (1.0, -1e-3 * rng.random::<f64>()),
            2 => (1.0, rng.random::<f64>()),
            3 => (rng.random::<f64>(), 1.0),
            4 => (-1.0, rng.random::<f64>() * 1e-3),
            _ => (-1.0, -1e-3 * rng.random::<f64>()),
        };
        let n = (a * a + b * b).sqrt();
        (len * (a * v.0 + b * jx) / n, len * (a * v.1 + b * jy) / n)
    }

    #[test]
    fn the_lanes_order_of_chords_is_the_scalar_order() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
        let mut taken = [0u32; 2];
        for k in 0..200_000 {
            let phi = rng.random_range(0.0..std::f64::consts::TAU);
            let v = (phi.cos(), phi.sin());
            let w: f64 = if k % 2 == 0 { 1.5 } else { -0.7 };
            let left = w > 0.0;
            let (x1, x2) = (chord(&mut rng, v, left), chord(&mut rng, v, left));
            let vv = v.0 * v.0 + v.1 * v.1;
            let a = ArcL::<f64> {
                vx: v.0,
                vy: v.1,
                vv,
                speed: vv.sqrt(),
                all: true,
            };
            let c1 = Cand::new(&a, left, x1, false, true);
            let c2 = Cand::new(&a, left, x2, false, true);
            let lanes = earlier(&a, left, &c1, &c2);
            let scalar = scalar_earlier(
                &Vec2::new(x1.0, x1.1),
                &Vec2::new(x2.0, x2.1),
                &Vec2::new(v.0, v.1),
                &w,
            );
            assert_eq!(
                lanes, scalar,
                "v = {v:?}, w = {w}, x1 = {x1:?}, x2 = {x2:?}"
            );
            taken[usize::from(lanes)] += 1;
        }
        // Both answers are common: the comparison is not vacuous.
        assert!(taken.iter().all(|&n| n > 50_000), "{taken:?}");
    }
}
