//! A block of arc trajectories that lives across calls, for analyses that look at every event
//! (runs in a field): the engine advances the lanes a few events at a time and records each
//! lane's state before every event, with the event's code and chord, so that the caller can
//! compute the flight time, the samples on its time grid and the Lévy area exactly as it does on
//! the scalar kernel ([`crate::scenes::lattice::Lattice::step_in_field`]).

use super::{ArcLanes, Mode, check, dispatch, load};
use crate::Error;
use crate::engine::SimdPath;
use crate::engine::observe::EventLanes;
use crate::engine::simd::BLOCK;
use crate::kernel::cell::ConvexCell;
use crate::kernel::field::ArcEvent;
use crate::kernel::vec2::Vec2;
use crate::scenes::lattice::LatticeState;

/// One recorded step of a block: every lane's state before its event (`before`, whose `code` is
/// the event's, [`crate::engine::observe::NO_EVENT`] where the lane made none, and whose
/// `live_bits` are the lanes that made one), the event's chord in the cell's frame and the
/// velocity on arrival, before the event acts.
#[derive(Debug, Clone)]
pub struct ArcRecord {
    /// The states before the event and the events' codes (flight times unused: 0).
    pub before: EventLanes<BLOCK>,
    /// The chord to the event, x and y, in the cell's frame.
    pub chord: [[f64; BLOCK]; 2],
    /// The velocity on arrival, x and y ([`ArcEvent::velocity`]).
    pub arrival: [[f64; BLOCK]; 2],
}

impl Default for ArcRecord {
    fn default() -> Self {
        ArcRecord {
            before: EventLanes::default(),
            chord: [[0.0; BLOCK]; 2],
            arrival: [[0.0; BLOCK]; 2],
        }
    }
}

impl ArcRecord {
    /// Lane `l`'s event, if it made one: its state before and the event, as the scalar arc
    /// kernel's [`crate::kernel::cell::ConvexCell::next_event_in_field`] gives it.
    pub fn event(&self, l: usize) -> Option<(LatticeState<f64>, ArcEvent<f64>)> {
        let b = &self.before;
        b.is_live(l).then(|| {
            let ev = ArcEvent {
                kind: b.event(l).kind,
                chord: Vec2::new(self.chord[0][l], self.chord[1][l]),
                velocity: Vec2::new(self.arrival[0][l], self.arrival[1][l]),
            };
            (b.state(l), ev)
        })
    }
}

/// Up to [`BLOCK`] trajectories in a field on the SIMD arc engine, each lane the scalar arc
/// kernel bit for bit (`tests/numerics/arc_engine.rs`), running until the caller retires it.
#[derive(Debug, Clone)]
pub struct ArcBlock {
    pub(super) path: SimdPath,
    pub(super) cell: ConvexCell<f64>,
    pub(super) w: f64,
    pub(super) st: ArcLanes,
    n: usize,
}

impl ArcBlock {
    /// The trajectories `states` of a lattice with cell `cell` in the field `w`.
    ///
    /// # Errors
    /// More than [`BLOCK`] states, a zero or non-finite field, a path this CPU lacks.
    pub fn new(
        path: SimdPath,
        cell: &ConvexCell<f64>,
        w: f64,
        states: &[LatticeState<f64>],
    ) -> Result<Self, Error> {
        check(path, cell, w, states.len())?;
        let mut st = load(states, &vec![0; states.len()]);
        st.quota[..states.len()].fill(f64::INFINITY);
        Ok(ArcBlock {
            path,
            cell: cell.clone(),
            w,
            st,
            n: states.len(),
        })
    }

    /// One event of every running lane per entry of `ring`, each recorded there (a retired lane
    /// makes none). Returns a lane that has no next event (a pinned or creeping orbit), if any:
    /// the block then stops at that entry, the others' events there recorded, none after it.
    pub fn advance(&mut self, ring: &mut [ArcRecord]) -> Option<usize> {
        for r in ring.iter_mut() {
            r.before.live_bits = 0;
        }
        if ring.is_empty() {
            return None;
        }
        dispatch(
            self.path,
            &self.cell,
            self.w,
            &mut self.st,
            0,
            Mode::Record(ring),
        )
    }

    /// Lane `l` runs no further.
    pub fn retire(&mut self, l: usize) {
        if l < self.n {
            self.st.quota[l] = 0.0;
        }
    }

    /// The vector path the block runs on.
    pub fn path(&self) -> SimdPath {
        self.path
    }

    /// The number of trajectories.
    pub fn len(&self) -> usize {
        self.n
    }

    /// `true` for a block of no trajectories.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Lane `l`'s current state.
    pub fn state(&self, l: usize) -> LatticeState<f64> {
        self.st.lanes.state(l)
    }
}
