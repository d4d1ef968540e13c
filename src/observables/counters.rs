//! Event counters along a trajectory.

use serde::{Deserialize, Serialize};

use crate::kernel::trap::EventKind;
use crate::stats::CompensatedSum;

/// Totals along one trajectory.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Counters {
    /// Number of collisions.
    pub collisions: u64,
    /// Number of trap changes (edge crossings).
    pub crossings: u64,
    /// Total flight time (= path length at speed 1), compensated summation.
    #[serde(skip)]
    pub time_sum: CompensatedSum,
    /// Total time as a plain number (filled by [`Counters::finish`]).
    pub time: f64,
    /// Longest collision-to-collision free path seen.
    pub longest_free_path: f64,
    /// Length of the free path in progress (crossings do not end a free path).
    #[serde(skip)]
    pub current_free_path: f64,
}

impl Counters {
    /// Records an event after a flight of duration `t`.
    #[inline(always)]
    pub fn record(&mut self, kind: EventKind, t: f64) {
        self.time_sum.add(t);
        self.current_free_path += t;
        match kind {
            EventKind::Collision(_) => {
                self.collisions += 1;
                if self.current_free_path > self.longest_free_path {
                    self.longest_free_path = self.current_free_path;
                }
                self.current_free_path = 0.0;
            }
            EventKind::Crossing(_) => self.crossings += 1,
        }
    }
    /// Fixes `time` from the compensated sum.
    pub fn finish(&mut self) {
        self.time = self.time_sum.value();
    }
}
