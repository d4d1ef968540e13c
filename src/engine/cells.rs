//! The multi-trajectory engine on straight flights in any convex cell ([`ConvexCell`]: a table
//! given as data, the square cell): [`BLOCK`] trajectories advance one event per step in vector
//! lanes on the lane skeleton of `simd::run_steps`, every lane executing exactly the
//! correctly rounded operations of the generic kernel ([`ConvexCell::next_event`] and
//! [`ConvexCell::apply`], with [`crate::kernel::ray_disk::approach`] and
//! [`crate::kernel::ray_disk::Approach::entry`] for each disk) in the same order, on the same
//! constants (taken from the `f64` cell itself).
//!
//! Where the scalar code skips a candidate (the disk it is on, a ray that misses, an edge it
//! entered by or moves away from) a lane computes it and masks it out; every disk's root and every
//! edge's quotient is taken, and the candidates are offered in the scalar order (disks by label,
//! then edges), a later one winning only where strictly earlier, as the scalar `offer`. A
//! collision's reflection (with its Newton speed factor) and a crossing's map are both computed
//! and blended by the event; exclusions and the cell index (i, j, s) are updated as exact small
//! integers. The constants of the cell (`CellC`) are shared with the arc engine
//! ([`super::arcs`]). `tests/numerics/cell_engine.rs` checks every event of every lane against
//! the scalar kernel.

use super::BlockRun;
use super::observe::Observer;
use super::observe::{CROSSING_CODE, EventLanes, NO_EVENT, NO_LABEL};
use super::simd::{BLOCK, LaneStep, StepBuffers};
use crate::kernel::cell::{ConvexCell, EdgeMap};
use crate::numbers::lanes::Lanes;

/// Most disks and edges a cell may have on the lane engines (the event codes: disk m < 16,
/// [`CROSSING_CODE`] + edge k < [`NO_EVENT`]).
pub const MAX_LANE_DISKS: usize = CROSSING_CODE as usize;

/// Most edges a cell may have on the lane engines.
pub const MAX_LANE_EDGES: usize = (NO_EVENT - CROSSING_CODE) as usize;

/// A disk's constants: centre, radius, radius² (the cell's own rounded r²).
pub(super) struct DiskC<V> {
    pub(super) cx: V,
    pub(super) cy: V,
    pub(super) r: V,
    pub(super) r2: V,
}

/// An edge's line: inward normal and offset.
pub(super) struct Line<V> {
    pub(super) nx: V,
    pub(super) ny: V,
    pub(super) off: V,
}

/// An edge's constants: its line, its map (a translation by t or the point reflection about c,
/// with `flips`), the label entered by, the disk exclusions carried across (as codes, one per
/// disk), and the cell step.
pub(super) struct EdgeC<V> {
    pub(super) line: Line<V>,
    pub(super) map: [V; 2],
    pub(super) flips: bool,
    pub(super) entered: V,
    pub(super) disks_after: Vec<V>,
    pub(super) step: [V; 2],
}

/// A cell's constants, splatted: its disks and edges.
pub(super) struct CellC<V> {
    pub(super) disks: Vec<DiskC<V>>,
    pub(super) edges: Vec<EdgeC<V>>,
}

impl<V: Lanes> CellC<V> {
    #[inline(always)]
    pub(super) fn new(cell: &ConvexCell<f64>) -> Self {
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
        let edges = cell.edges.iter().map(edge_consts).collect();
        CellC { disks, edges }
    }

    /// Disk `code`'s constants in each lane (disk 0's where the code names no disk).
    #[inline(always)]
    pub(super) fn disk(&self, code: V) -> DiskC<V> {
        let d0 = &self.disks[0];
        let mut d = DiskC {
            cx: d0.cx,
            cy: d0.cy,
            r: d0.r,
            r2: d0.r2,
        };
        for (m, dm) in self.disks.iter().enumerate().skip(1) {
            let here = code.eq(V::splat(m as f64));
            d.cx = V::select(here, dm.cx, d.cx);
            d.cy = V::select(here, dm.cy, d.cy);
            d.r = V::select(here, dm.r, d.r);
            d.r2 = V::select(here, dm.r2, d.r2);
        }
        d
    }
}

#[inline(always)]
fn edge_consts<V: Lanes>(e: &crate::kernel::cell::Edge<f64>) -> EdgeC<V> {
    let (m, flips) = match &e.map {
        EdgeMap::Translation(t) => (t, false),
        EdgeMap::PointReflection(c) => (c, true),
    };
    EdgeC {
        line: Line {
            nx: V::splat(e.normal.x),
            ny: V::splat(e.normal.y),
            off: V::splat(e.offset),
        },
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
}

/// `true` if the lane engines can run `cell`: at least one disk, at most [`MAX_LANE_DISKS`]
/// disks and [`MAX_LANE_EDGES`] edges.
pub fn fits(cell: &ConvexCell<f64>) -> bool {
    !cell.disks.is_empty()
        && cell.disks.len() <= MAX_LANE_DISKS
        && cell.edges.len() <= MAX_LANE_EDGES
}

/// The states of the `V::WIDTH` lanes at one offset: position and velocity in the cell's
/// frame, exclusions (disk, edge) and cell index (i, j, s), as the lane engines load them from
/// and store them into [`EventLanes`].
#[derive(Clone, Copy)]
pub(super) struct LaneState<V: Lanes> {
    pub(super) p: (V, V),
    pub(super) v: (V, V),
    pub(super) ed: V,
    pub(super) ee: V,
    pub(super) cell: [V; 3],
}

impl<V: Lanes> LaneState<V> {
    /// The lanes at `o` of `e`.
    #[inline(always)]
    pub(super) fn load<const L: usize>(e: &EventLanes<L>, o: usize) -> Self {
        LaneState {
            p: (V::load(&e.pos[0][o..]), V::load(&e.pos[1][o..])),
            v: (V::load(&e.vel[0][o..]), V::load(&e.vel[1][o..])),
            ed: V::load(&e.excluded[0][o..]),
            ee: V::load(&e.excluded[1][o..]),
            cell: [
                V::load(&e.cell[0][o..]),
                V::load(&e.cell[1][o..]),
                V::load(&e.cell[2][o..]),
            ],
        }
    }

    /// Stores `self` into the lanes at `o` of `e` where `go`, `old` elsewhere.
    #[inline(always)]
    pub(super) fn store_where<const L: usize>(
        &self,
        go: V::Mask,
        old: &Self,
        e: &mut EventLanes<L>,
        o: usize,
    ) {
        V::select(go, self.p.0, old.p.0).store(&mut e.pos[0][o..]);
        V::select(go, self.p.1, old.p.1).store(&mut e.pos[1][o..]);
        V::select(go, self.v.0, old.v.0).store(&mut e.vel[0][o..]);
        V::select(go, self.v.1, old.v.1).store(&mut e.vel[1][o..]);
        V::select(go, self.ed, old.ed).store(&mut e.excluded[0][o..]);
        V::select(go, self.ee, old.ee).store(&mut e.excluded[1][o..]);
        for k in 0..3 {
            V::select(go, self.cell[k], old.cell[k]).store(&mut e.cell[k][o..]);
        }
    }
}

/// Where each lane is after crossing the edge `code` of `c` at x with velocity u: the
/// neighbour's position and velocity (translated, or point-reflected with v ↦ −v and the
/// orientation flipped), the disk exclusion carried across where `carry` (none elsewhere), the
/// edge entered by, the neighbour's index. Lanes whose code is no edge keep x, u and `s`'s labels.
#[inline(always)]
pub(super) fn cross<V: Lanes>(
    c: &CellC<V>,
    s: &LaneState<V>,
    code: V,
    (x, y): (V, V),
    (ux, uy): (V, V),
    carry: V::Mask,
) -> LaneState<V> {
    let mut out = LaneState {
        p: (x, y),
        v: (ux, uy),
        ..*s
    };
    let no = V::splat(NO_LABEL);
    for (k, e) in c.edges.iter().enumerate() {
        let here = code.eq(V::splat(CROSSING_CODE + k as f64));
        let (px, py, vx, vy, sg) = if e.flips {
            (
                e.map[0].sub(x),
                e.map[1].sub(y),
                ux.neg(),
                uy.neg(),
                s.cell[2].neg(),
            )
        } else {
            (x.sub(e.map[0]), y.sub(e.map[1]), ux, uy, s.cell[2])
        };
        let mut ed = no;
        for (m, after) in e.disks_after.iter().enumerate() {
            ed = V::select(s.ed.eq(V::splat(m as f64)), *after, ed);
        }
        let ed = V::select(carry, ed, no);
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

/// The best candidate so far of every lane: time, code, and whether there is one.
struct Best<V: Lanes> {
    t: V,
    code: V,
    has: V::Mask,
}

impl<V: Lanes> Best<V> {
    /// The scalar `offer`: the candidate (`t`, `label`) where it is offered (`ok`) and there is
    /// none yet or it is strictly earlier. (A method, not a closure: a closure would not inherit
    /// the target features of the function it is written in.)
    #[inline(always)]
    fn offer(&mut self, t: V, label: f64, ok: V::Mask) {
        let take = V::and(ok, V::or(t.lt(self.t), V::and_not(ok, self.has)));
        self.t = V::select(take, t, self.t);
        self.code = V::select(take, V::splat(label), self.code);
        self.has = V::or(self.has, ok);
    }
}

/// The earliest candidate of every lane: time, code, and whether there is one.
#[inline(always)]
fn earliest<V: Lanes>(c: &CellC<V>, s: &LaneState<V>, vv: V) -> Best<V> {
    let zero = V::splat(0.0);
    let ((px, py), (vx, vy)) = (s.p, s.v);
    let mut best = Best {
        t: zero,
        code: zero,
        has: V::from_bits(0),
    };
    for (m, d) in c.disks.iter().enumerate() {
        let (dx, dy) = (px.sub(d.cx), py.sub(d.cy));
        let beta = dx.mul(vx).add(dy.mul(vy));
        let q = dx.mul(vy).sub(dy.mul(vx));
        let disc = vv_r2(vv, d.r2).sub(q.mul(q));
        let gamma = dx.mul(dx).add(dy.mul(dy)).sub(d.r2);
        let root = gamma.div(disc.sqrt().sub(beta));
        let ok = V::and(V::and(beta.lt(zero), disc.gt(zero)), not_label(s.ed, m));
        best.offer(V::select(gamma.gt(zero), root, zero), m as f64, ok);
    }
    for (k, e) in c.edges.iter().enumerate() {
        let l = &e.line;
        let nv = l.nx.mul(vx).add(l.ny.mul(vy));
        let sigma = l.nx.mul(px).add(l.ny.mul(py)).sub(l.off);
        let q = V::select(sigma.gt(zero), sigma.div(nv.neg()), zero);
        let ok = V::and(nv.lt(zero), not_label(s.ee, k));
        best.offer(q, CROSSING_CODE + k as f64, ok);
    }
    best
}

/// |v|²r², as the scalar root forms it.
#[inline(always)]
fn vv_r2<V: Lanes>(vv: V, r2: V) -> V {
    vv.mul(r2)
}

/// The lanes whose label is not `m` (the candidate is not the excluded one).
#[inline(always)]
fn not_label<V: Lanes>(label: V, m: usize) -> V::Mask {
    let z = V::splat(0.0);
    V::and_not(V::eq(z, z), label.eq(V::splat(m as f64)))
}

/// The state after each lane's event at time `t` with code `code`: a collision's reflection with
/// the Newton factor (|v|² = `vv`), or a crossing's map, relabelled exclusions and the
/// neighbour's index.
#[inline(always)]
fn after<V: Lanes>(c: &CellC<V>, s: &LaneState<V>, vv: V, (t, code): (V, V)) -> LaneState<V> {
    let ((px, py), (vx, vy)) = (s.p, s.v);
    let (x, y) = (px.add(vx.mul(t)), py.add(vy.mul(t)));
    let z = V::splat(0.0);
    let mut out = cross(c, s, code, (x, y), (vx, vy), V::eq(z, z));
    let d = c.disk(code);
    let (nx, ny) = (x.sub(d.cx), y.sub(d.cy));
    let k = vv.neg().add(V::splat(3.0)).mul(V::splat(0.5));
    let sc = vx.mul(nx).add(vy.mul(ny)).mul(V::splat(2.0)).div(d.r2);
    let hit = code.lt(V::splat(CROSSING_CODE));
    let (rx, ry) = (vx.sub(nx.mul(sc)).mul(k), vy.sub(ny.mul(sc)).mul(k));
    out.p = (V::select(hit, x, out.p.0), V::select(hit, y, out.p.1));
    out.v = (V::select(hit, rx, out.v.0), V::select(hit, ry, out.v.1));
    out.ed = V::select(hit, code, out.ed);
    out.ee = V::select(hit, V::splat(NO_LABEL), out.ee);
    out
}

/// The step of a convex cell: [`CellC`] for the lane skeleton.
pub(super) struct CellStep<V>(pub(super) CellC<V>);

impl<V: Lanes> LaneStep<V> for CellStep<V> {
    #[inline(always)]
    fn advance<const L: usize>(
        &self,
        (counts, out, next): StepBuffers<'_, L>,
        o: usize,
    ) -> (u64, u64) {
        let zero = V::splat(0.0);
        let count = V::load(&counts.collisions[o..]);
        let live = count.lt(V::load(&counts.quota[o..]));
        let s = LaneState::<V>::load(out, o);
        let (vx, vy) = s.v;
        let vv = vx.mul(vx).add(vy.mul(vy));
        let Best { t, code, has } = earliest(&self.0, &s, vv);
        let lost = V::bits(V::and_not(live, has));
        let go = V::and(live, has);
        V::select(live, t, zero).store(&mut out.time[o..]);
        V::select(live, code, V::splat(NO_EVENT)).store(&mut out.code[o..]);
        after(&self.0, &s, vv, (t, code)).store_where(go, &s, next, o);
        let coll = code.lt(V::splat(CROSSING_CODE));
        let counted = count.add(V::select(coll, V::splat(1.0), zero));
        V::select(go, counted, count).store(&mut counts.collisions[o..]);
        (lost << o, V::bits(live) << o)
    }
}

/// The lane engine's block of [`BLOCK`] lanes on `cell`, at vector type `V`.
#[inline(always)]
pub(super) fn run<V: Lanes, O: Observer<BLOCK>>(
    cell: &ConvexCell<f64>,
    r: BlockRun<'_, O>,
) -> Option<usize> {
    let step = CellStep::<V>(CellC::new(cell));
    super::simd::run_steps::<V, O, _>(&step, r.counts, r.ring, r.obs, r.progress)
}
