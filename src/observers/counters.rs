//! Event counters along a trajectory: collisions, crossings, total time (compensated
//! summation), longest free path.

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::observe::{CROSSING_CODE, EventLanes, NO_EVENT, Observer, lanes};
use crate::numbers::lanes::Lanes;
use crate::statistics::CompensatedSum;

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

/// The counters of L trajectories, in lanes: the compensated sum, the free path and the
/// counts (exact integers in `f64`, below 2⁵³ by [`crate::engine::MAX_COLLISIONS_PER_TRAJECTORY`])
/// are updated with vector selects, no branches. A lane that is not live has time +0 and code
/// [`NO_EVENT`] ([`EventLanes`]), which leave every accumulator unchanged, so no mask is needed.
#[derive(Debug, Clone)]
pub struct CounterLanes {
    sum: Vec<f64>,
    comp: Vec<f64>,
    current: Vec<f64>,
    longest: Vec<f64>,
    collisions: Vec<f64>,
    events: Vec<f64>,
}

impl CounterLanes {
    /// Counters for `lanes` trajectories, all zero.
    pub fn new(lanes: usize) -> Self {
        CounterLanes {
            sum: vec![0.0; lanes],
            comp: vec![0.0; lanes],
            current: vec![0.0; lanes],
            longest: vec![0.0; lanes],
            collisions: vec![0.0; lanes],
            events: vec![0.0; lanes],
        }
    }

    /// The totals of lane `l` (with `time` filled in).
    pub fn lane(&self, l: usize) -> Counters {
        let mut c = Counters {
            collisions: self.collisions[l] as u64,
            crossings: (self.events[l] - self.collisions[l]) as u64,
            time_sum: CompensatedSum::from_parts(self.sum[l], self.comp[l]),
            time: 0.0,
            longest_free_path: self.longest[l],
            current_free_path: self.current[l],
        };
        c.finish();
        c
    }
}

/// One lane of [`CounterLanes`], exactly (what a checkpoint keeps).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CounterLaneState {
    /// Compensated sum of flight times: its value and its compensation.
    pub time: [f64; 2],
    /// The free path in progress.
    pub current: f64,
    /// The longest free path so far.
    pub longest: f64,
    /// Collisions (an exact integer).
    pub collisions: f64,
    /// Events, collisions and crossings (an exact integer).
    pub events: f64,
}

impl CounterLanes {
    /// Everything lane `l` has counted.
    pub fn lane_state(&self, l: usize) -> CounterLaneState {
        CounterLaneState {
            time: [self.sum[l], self.comp[l]],
            current: self.current[l],
            longest: self.longest[l],
            collisions: self.collisions[l],
            events: self.events[l],
        }
    }

    /// Puts back into lane `l` what [`CounterLanes::lane_state`] took.
    ///
    /// # Errors
    /// If a value is not finite, or a count is not a whole number from 0 to 2⁵³.
    pub fn set_lane_state(&mut self, l: usize, s: &CounterLaneState) -> Result<(), Error> {
        let count = |x: f64| (0.0..=9007199254740992.0).contains(&x) && x.fract() == 0.0;
        let ok = s.time.iter().all(|x| x.is_finite())
            && s.current.is_finite()
            && s.longest.is_finite()
            && count(s.collisions)
            && count(s.events)
            && s.events >= s.collisions;
        if !ok {
            return Err(Error::Invalid(format!(
                "counter state {s:?} is not one a trajectory can reach"
            )));
        }
        [self.sum[l], self.comp[l]] = s.time;
        self.current[l] = s.current;
        self.longest[l] = s.longest;
        self.collisions[l] = s.collisions;
        self.events[l] = s.events;
        Ok(())
    }
}

impl<const L: usize> Observer<L> for CounterLanes {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        let sum = lanes::<f64, L>(&mut self.sum);
        let comp = lanes::<f64, L>(&mut self.comp);
        let cur = lanes::<f64, L>(&mut self.current);
        let longest = lanes::<f64, L>(&mut self.longest);
        let ncoll = lanes::<f64, L>(&mut self.collisions);
        let nev = lanes::<f64, L>(&mut self.events);
        let (zero, one) = (V::splat(0.0), V::splat(1.0));
        let (cross, none) = (V::splat(CROSSING_CODE), V::splat(NO_EVENT));
        let mut o = 0;
        while o < L {
            // The accumulators stay in registers over the steps.
            let (mut s, mut cp, mut path) =
                (V::load(&sum[o..]), V::load(&comp[o..]), V::load(&cur[o..]));
            let (mut long, mut nc, mut ne) = (
                V::load(&longest[o..]),
                V::load(&ncoll[o..]),
                V::load(&nev[o..]),
            );
            for e in steps {
                let x = V::load(&e.time[o..]);
                let code = V::load(&e.code[o..]);
                let coll = code.lt(cross);
                // CompensatedSum::add (Neumaier), the same operations with a select.
                let t = s.add(x);
                cp = cp.add(V::select(
                    s.abs().ge(x.abs()),
                    s.sub(t).add(x),
                    x.sub(t).add(s),
                ));
                s = t;
                // The free path in progress ends at a collision.
                path = path.add(x);
                long = V::select(V::and(coll, path.gt(long)), path, long);
                path = V::select(coll, zero, path);
                nc = nc.add(V::select(coll, one, zero));
                ne = ne.add(V::select(code.lt(none), one, zero));
            }
            s.store(&mut sum[o..]);
            cp.store(&mut comp[o..]);
            path.store(&mut cur[o..]);
            long.store(&mut longest[o..]);
            nc.store(&mut ncoll[o..]);
            ne.store(&mut nev[o..]);
            o += V::WIDTH;
        }
    }
}
