//! The interface between the engines and the observers: what one step of L trajectories shows
//! ([`EventLanes`]) and what an observer implements ([`Observer`]). The engines call it; the
//! observers (`crate::observers`) implement it.

use crate::kernel::{flight::Event, flight::EventKind, flight::Flight};
use crate::numbers::lanes::Lanes;
use crate::numbers::real::Real;
use crate::scenes::lattice::{CellIndex, LatticeState, Unwrapped};

/// The label code of "no disk" / "no edge" in [`EventLanes::excluded`] (labels are 0, 1, 2).
pub const NO_LABEL: f64 = -1.0;

/// Event codes: m < [`CROSSING_CODE`] a collision with disk m; this plus k a crossing of edge k.
/// A cell may have up to 16 disks and 48 edges (the triangular trap has 3 and 3, the square
/// cell 1 and 4): every code stays below [`NO_EVENT`].
pub const CROSSING_CODE: f64 = 16.0;

/// The event code of a lane that is not live (no event: its time is 0), above every event's
/// code (an edge k < 48 has code 16 + k < 64).
pub const NO_EVENT: f64 = 64.0;

/// One step of L trajectories: the event of each lane and the lane's state just before it.
///
/// Observers read it with the engine's vector type ([`Lanes`]): `V::load(&e.time[o..])` for the
/// lanes o … o + `V::WIDTH` − 1 and `V::from_bits(e.live_bits >> o)` for their live mask.
///
/// Lanes whose trajectory has finished (or that pad a block) are not live (bit l of `live_bits`
/// clear); observers must leave their accumulators unchanged for them. Such a lane's time is
/// +0 and its code [`NO_EVENT`], so that an accumulator that adds times or counts codes is left
/// unchanged without a mask (adding +0 to a sum that is not −0 returns it bit for bit). Small integers (labels, event codes, cell
/// indices, orientation ±1) are held as exact `f64` values so that the engine can keep them in
/// vector lanes; a cell index is exact while it is below 2⁵³ in magnitude, which
/// [`crate::engine::MAX_COLLISIONS_PER_TRAJECTORY`] guarantees (an event changes it by at most 1).
#[derive(Debug, Clone)]
pub struct EventLanes<const L: usize> {
    /// Bit l set iff lane l's trajectory is still running.
    pub live_bits: u64,
    /// Flight time to the event.
    pub time: [f64; L],
    /// What ended the flight: disk m (below [`CROSSING_CODE`]), [`CROSSING_CODE`] + edge k, or
    /// [`NO_EVENT`].
    pub code: [f64; L],
    /// Position before the event, in the cell frame (x, y).
    pub pos: [[f64; L]; 2],
    /// Velocity before the event (x, y).
    pub vel: [[f64; L]; 2],
    /// Excluded disk and edge before the event ([`NO_LABEL`] for none).
    pub excluded: [[f64; L]; 2],
    /// Cell index i, j and orientation s = ±1 (−1: a down trap) before the event.
    pub cell: [[f64; L]; 3],
}

impl<const L: usize> EventLanes<L> {
    /// Calls `f(l)` for each live lane `l` below `lanes`, in increasing order.
    #[inline(always)]
    pub fn each_live(&self, lanes: usize, mut f: impl FnMut(usize)) {
        let mut live = self.live_bits;
        while live != 0 {
            let l = live.trailing_zeros() as usize;
            live &= live - 1;
            if l < lanes {
                f(l);
            }
        }
    }
}

impl<const L: usize> Default for EventLanes<L> {
    fn default() -> Self {
        EventLanes {
            live_bits: 0,
            time: [0.0; L],
            code: [NO_EVENT; L],
            pos: [[0.0; L]; 2],
            vel: [[0.0; L]; 2],
            excluded: [[NO_LABEL; L]; 2],
            cell: [[0.0; L], [0.0; L], [1.0; L]],
        }
    }
}

fn code_of(kind: EventKind) -> f64 {
    match kind {
        EventKind::Collision(m) => m as f64,
        EventKind::Crossing(k) => CROSSING_CODE + k as f64,
    }
}

fn label_code(l: Option<u8>) -> f64 {
    l.map_or(NO_LABEL, |m| m as f64)
}

fn label_of(c: f64) -> Option<u8> {
    (c >= 0.0).then_some(c as u8)
}

impl<const L: usize> EventLanes<L> {
    /// `true` if lane `l`'s trajectory is still running.
    #[inline(always)]
    pub fn is_live(&self, l: usize) -> bool {
        (self.live_bits >> l) & 1 == 1
    }

    /// `true` if lane `l`'s event is a collision.
    #[inline(always)]
    pub fn is_collision(&self, l: usize) -> bool {
        self.code[l] < CROSSING_CODE
    }

    /// Lane `l`'s event.
    pub fn event(&self, l: usize) -> Event<f64> {
        let c = self.code[l];
        let kind = if c < CROSSING_CODE {
            EventKind::Collision(c as u8)
        } else {
            EventKind::Crossing((c - CROSSING_CODE) as u8)
        };
        Event {
            kind,
            time: self.time[l],
        }
    }

    /// Lane `l`'s cell before the event.
    #[inline(always)]
    pub fn cell_index(&self, l: usize) -> CellIndex {
        CellIndex {
            i: self.cell[0][l] as i64,
            j: self.cell[1][l] as i64,
            down: self.cell[2][l] < 0.0,
        }
    }

    /// Lane `l`'s state before the event.
    pub fn state(&self, l: usize) -> LatticeState<f64> {
        LatticeState {
            cell: self.cell_index(l),
            flight: Flight {
                pos: crate::kernel::vec2::Vec2::new(self.pos[0][l], self.pos[1][l]),
                vel: crate::kernel::vec2::Vec2::new(self.vel[0][l], self.vel[1][l]),
                excluded_disk: label_of(self.excluded[0][l]),
                excluded_edge: label_of(self.excluded[1][l]),
            },
        }
    }

    /// Sets lane `l`'s state (position, velocity, exclusions, cell) to `s`.
    pub fn set_state(&mut self, l: usize, s: &LatticeState<f64>) {
        let f = &s.flight;
        self.pos[0][l] = f.pos.x;
        self.pos[1][l] = f.pos.y;
        self.vel[0][l] = f.vel.x;
        self.vel[1][l] = f.vel.y;
        self.excluded[0][l] = label_code(f.excluded_disk);
        self.excluded[1][l] = label_code(f.excluded_edge);
        self.cell[0][l] = s.cell.i as f64;
        self.cell[1][l] = s.cell.j as f64;
        self.cell[2][l] = s.cell.sign();
    }

    /// Lane `l`'s unwrapped world position after a further flight of `dt` from the state before
    /// the event: the same operations as [`crate::scenes::lattice::Lattice::unwrapped`].
    #[inline(always)]
    pub fn unwrapped(&self, l: usize, dt: f64) -> Unwrapped {
        let sg = self.cell[2][l];
        Unwrapped {
            i: self.cell[0][l] as i64,
            j: self.cell[1][l] as i64,
            off: [
                sg * (self.pos[0][l] + dt * self.vel[0][l]),
                sg * (self.pos[1][l] + dt * self.vel[1][l]),
            ],
        }
    }
}

impl EventLanes<1> {
    /// The one-lane step of the scalar engine: state `s` (any precision, rounded to `f64` for
    /// the observers, as they always did) and its event `ev`.
    #[inline(always)]
    pub fn single<T: Real>(s: &LatticeState<T>, ev: &Event<T>) -> Self {
        let f = &s.flight;
        EventLanes {
            live_bits: 1,
            time: [ev.time.to_f64()],
            code: [code_of(ev.kind)],
            pos: [[f.pos.x.to_f64()], [f.pos.y.to_f64()]],
            vel: [[f.vel.x.to_f64()], [f.vel.y.to_f64()]],
            excluded: [[label_code(f.excluded_disk)], [label_code(f.excluded_edge)]],
            cell: [[s.cell.i as f64], [s.cell.j as f64], [s.cell.sign()]],
        }
    }
}

/// Something that watches the events of L trajectories at a time, keeping one accumulator per
/// lane. It must update lane `l` only if it is live, and do the same `f64` operations per lane
/// whatever L and `V` are (so results do not depend on the engine): written with the
/// operations of [`Lanes`], which are exactly the scalar ones lane by lane, that is automatic.
pub trait Observer<const L: usize> {
    /// Consecutive steps, in order, read with vectors of type `V` (`f64` on the scalar engine,
    /// whose L is 1). The engine hands over a few steps at a time, so an observer can keep its
    /// accumulators in registers across them.
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]);
}

impl<const L: usize, A: Observer<L>, B: Observer<L>> Observer<L> for (A, B) {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        self.0.observe::<V>(steps);
        self.1.observe::<V>(steps);
    }
}

impl<const L: usize, A: Observer<L>, B: Observer<L>, C: Observer<L>> Observer<L> for (A, B, C) {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        self.0.observe::<V>(steps);
        self.1.observe::<V>(steps);
        self.2.observe::<V>(steps);
    }
}

/// Observes nothing (for timing the bare engine).
#[derive(Debug, Clone, Copy, Default)]
pub struct Nothing;

impl<const L: usize> Observer<L> for Nothing {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, _: &[EventLanes<L>]) {}
}

/// The lanes of up to [`StepLanes::STEPS`] consecutive steps gathered into one mask (lane l of
/// step k is bit k·L + l), visited in step order: an observer that has rare work in some lanes
/// (a sample, a hop) finds them step by step with vector compares, then does the work in one
/// loop over the group, so that the trip counts it cannot predict cost one loop exit per group
/// rather than one per step.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepLanes<const L: usize> {
    bits: u128,
}

impl<const L: usize> StepLanes<L> {
    /// Steps one mask holds (L ≤ 64).
    pub const STEPS: usize = 128 / L;

    /// Marks `lanes` (bit l: lane l) of step `k` (< [`Self::STEPS`]).
    #[inline(always)]
    pub fn set(&mut self, k: usize, lanes: u64) {
        debug_assert!(k < Self::STEPS && (L == 64 || lanes >> L == 0));
        self.bits |= u128::from(lanes) << (k * L);
    }

    /// Whether lane `l` of step `k` is marked.
    #[inline(always)]
    pub fn contains(&self, k: usize, l: usize) -> bool {
        (self.bits >> (k * L + l)) & 1 == 1
    }
}

impl<const L: usize> Iterator for StepLanes<L> {
    /// (step, lane), in step order and lane order within a step.
    type Item = (usize, usize);
    #[inline(always)]
    fn next(&mut self) -> Option<(usize, usize)> {
        if self.bits == 0 {
            return None;
        }
        let i = self.bits.trailing_zeros() as usize;
        self.bits &= self.bits - 1;
        Some((i / L, i % L))
    }
}

/// Views lane accumulators of length `n` as an array of the block's width (checked once per
/// step, so the lane loops have no bounds checks and vectorise).
#[inline(always)]
pub fn lanes<T, const L: usize>(v: &mut [T]) -> &mut [T; L] {
    v.try_into()
        .expect("an observer is called with as many lanes as it was built for")
}
