//! Free-flight tails along a trajectory, at a grid of times s: the number of collision-to-
//! collision flights longer than s (the billiard map's tail μ(τ > s)) and Σ (τ − s)⁺ over every
//! flight (the flow's tail: the fraction of time whose flight still runs s later,
//! P(τ⁺ > s) = Σ (τ − s)⁺ / T).
//!
//! A trajectory that starts from the flow's invariant measure starts inside a flight: that first
//! flight (from the start to the first collision) is a flow sample, not a map sample, so it
//! counts in the flow's sums and the total time but not in the map's counts
//! (`proofs-notes/superdiffusion-estimators.md`). A trajectory ends at a collision, so there is
//! no partial last flight. Crossings of cell edges do not end a flight.

use serde::{Deserialize, Serialize};

use crate::Error;
use crate::engine::checkpoint::LaneCheckpoint;
use crate::engine::observe::{EventLanes, Observer};
use crate::numbers::lanes::Lanes;

/// What one trajectory's flights showed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TailCounts {
    /// Flights counted for the map (every complete collision-to-collision flight).
    pub flights: u64,
    /// Total time, the first (partial) flight included.
    pub time: f64,
    /// The longest flight, the first included.
    pub longest: f64,
    /// Per grid time s: flights longer than s.
    pub longer: Vec<u64>,
    /// Per grid time s: Σ (τ − s)⁺ over every flight, the first included.
    pub excess: Vec<f64>,
}

/// One lane exactly (what a checkpoint keeps): the flight in progress, whether the first
/// (partial) flight has ended, and the counts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TailLane {
    flight: f64,
    started: bool,
    counts: TailCounts,
}

/// The tails of L trajectories at the grid times `grid` (ascending).
#[derive(Debug, Clone)]
pub struct FlightTails {
    grid: Vec<f64>,
    lanes: Vec<TailLane>,
}

impl FlightTails {
    /// Tails at the ascending times `grid` for `lanes` trajectories.
    pub fn new(grid: &[f64], lanes: usize) -> Self {
        let counts = TailCounts {
            flights: 0,
            time: 0.0,
            longest: 0.0,
            longer: vec![0; grid.len()],
            excess: vec![0.0; grid.len()],
        };
        FlightTails {
            grid: grid.to_vec(),
            lanes: vec![
                TailLane {
                    flight: 0.0,
                    started: false,
                    counts,
                };
                lanes
            ],
        }
    }

    /// Lane `l`'s counts so far.
    pub fn counts(&self, l: usize) -> &TailCounts {
        &self.lanes[l].counts
    }

    /// Ends lane `l`'s flight in progress at a collision.
    #[inline(always)]
    fn close(&mut self, l: usize) {
        let lane = &mut self.lanes[l];
        let tau = lane.flight;
        lane.flight = 0.0;
        let c = &mut lane.counts;
        c.time += tau;
        c.longest = c.longest.max(tau);
        for (k, &s) in self.grid.iter().enumerate() {
            if tau <= s {
                break;
            }
            c.excess[k] += tau - s;
            if lane.started {
                c.longer[k] += 1;
            }
        }
        if lane.started {
            c.flights += 1;
        }
        lane.started = true;
    }
}

impl LaneCheckpoint for FlightTails {
    type Lane = TailLane;
    fn save_lane(&self, l: usize) -> TailLane {
        self.lanes[l].clone()
    }
    fn restore_lane(&mut self, l: usize, saved: &TailLane) -> Result<(), Error> {
        let c = &saved.counts;
        let n = self.grid.len();
        let finite = [saved.flight, c.time, c.longest]
            .iter()
            .chain(&c.excess)
            .all(|x| x.is_finite() && *x >= 0.0);
        if c.longer.len() != n || c.excess.len() != n || !finite {
            return Err(Error::Invalid(format!(
                "a flight-tail lane with {} and {} counts does not fit this run ({n} grid times, all finite and >= 0)",
                c.longer.len(),
                c.excess.len()
            )));
        }
        self.lanes[l] = saved.clone();
        Ok(())
    }
}

impl<const L: usize> Observer<L> for FlightTails {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        for e in steps {
            for l in 0..L {
                if e.is_live(l) {
                    self.lanes[l].flight += e.time[l];
                    if e.is_collision(l) {
                        self.close(l);
                    }
                }
            }
        }
    }
}
