//! Event counters along a trajectory: collisions, crossings, total time (compensated
//! summation), longest free path.

use serde::{Deserialize, Serialize};

use super::{lanes, EventLanes, Observer};
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
    /// Fixes `time` from the compensated sum.
    pub fn finish(&mut self) {
        self.time = self.time_sum.value();
    }
}

/// The counters of L trajectories, updated lane by lane with selects (no branches), so that the
/// update vectorises.
#[derive(Debug, Clone)]
pub struct CounterLanes {
    sum: Vec<f64>,
    comp: Vec<f64>,
    current: Vec<f64>,
    longest: Vec<f64>,
    collisions: Vec<u64>,
    crossings: Vec<u64>,
}

impl CounterLanes {
    /// Counters for `lanes` trajectories, all zero.
    pub fn new(lanes: usize) -> Self {
        CounterLanes {
            sum: vec![0.0; lanes],
            comp: vec![0.0; lanes],
            current: vec![0.0; lanes],
            longest: vec![0.0; lanes],
            collisions: vec![0; lanes],
            crossings: vec![0; lanes],
        }
    }

    /// The totals of lane `l` (with `time` filled in).
    pub fn lane(&self, l: usize) -> Counters {
        let mut c = Counters {
            collisions: self.collisions[l],
            crossings: self.crossings[l],
            time_sum: CompensatedSum::from_parts(self.sum[l], self.comp[l]),
            time: 0.0,
            longest_free_path: self.longest[l],
            current_free_path: self.current[l],
        };
        c.finish();
        c
    }
}

impl<const L: usize> Observer<L> for CounterLanes {
    #[inline(always)]
    fn observe(&mut self, e: &EventLanes<L>) {
        let sum = lanes::<f64, L>(&mut self.sum);
        let comp = lanes::<f64, L>(&mut self.comp);
        let cur = lanes::<f64, L>(&mut self.current);
        let longest = lanes::<f64, L>(&mut self.longest);
        let ncoll = lanes::<u64, L>(&mut self.collisions);
        let ncross = lanes::<u64, L>(&mut self.crossings);
        for l in 0..L {
            let live = e.live[l];
            let x = e.time[l];
            let coll = e.is_collision(l);
            // CompensatedSum::add, written with selects (the same operations).
            let s = sum[l];
            let t = s + x;
            let c = if s.abs() >= x.abs() {
                (s - t) + x
            } else {
                (x - t) + s
            };
            let c = comp[l] + c;
            let path = cur[l] + x;
            let long = if coll && path > longest[l] {
                path
            } else {
                longest[l]
            };
            let path = if coll { 0.0 } else { path };
            sum[l] = if live { t } else { s };
            comp[l] = if live { c } else { comp[l] };
            cur[l] = if live { path } else { cur[l] };
            longest[l] = if live { long } else { longest[l] };
            ncoll[l] += (live & coll) as u64;
            ncross[l] += (live & !coll) as u64;
        }
    }
}
