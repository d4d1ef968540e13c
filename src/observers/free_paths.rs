//! The free paths between collisions of one trajectory, in units of a given length (the scene's
//! mean free path): their count, sum, sum of logarithms, longest and histogram on given edges,
//! and optionally some of them as raw samples (every k-th flight, so that the samples kept are
//! spread over the whole trajectory and nearly independent).
//!
//! A trajectory that starts from the flow's invariant measure starts inside a flight; that
//! first, partial flight is not a sample of the billiard map and is not counted (as in
//! [`super::flight_tails`]). Crossings of cell edges (and long-flight jumps) do not end a flight.

use crate::engine::observe::{EventLanes, Observer};
use crate::numbers::lanes::Lanes;

/// What one trajectory's complete flights showed, ξ = τ/unit.
#[derive(Debug, Clone, PartialEq)]
pub struct FreePathCounts {
    /// Complete collision-to-collision flights.
    pub flights: u64,
    /// Σ ξ.
    pub sum: f64,
    /// Σ ln ξ.
    pub ln_sum: f64,
    /// The longest ξ.
    pub longest: f64,
    /// Per bin k, `edges[k] <= ξ < edges[k + 1]`: the flights in it.
    pub bins: Vec<u64>,
    /// The raw ξ of the flights kept (flights 0, k, 2k, … up to the number asked for).
    pub kept: Vec<f64>,
}

/// The free paths of one trajectory (the scalar engine's one lane).
#[derive(Debug, Clone)]
pub struct FreePaths {
    inverse_unit: f64,
    edges: Vec<f64>,
    flight: f64,
    started: bool,
    counts: FreePathCounts,
    /// Keep this many flights' ξ, every `stride`-th.
    keep: usize,
    stride: u64,
}

impl FreePaths {
    /// Flights measured in units of `unit`, histogrammed on the ascending `edges` (a flight
    /// outside `[edges[0], edges[last])` falls in no bin).
    pub fn new(unit: f64, edges: &[f64]) -> Self {
        FreePaths {
            inverse_unit: 1.0 / unit,
            edges: edges.to_vec(),
            flight: 0.0,
            started: false,
            counts: FreePathCounts {
                flights: 0,
                sum: 0.0,
                ln_sum: 0.0,
                longest: 0.0,
                bins: vec![0; edges.len().saturating_sub(1)],
                kept: Vec::new(),
            },
            keep: 0,
            stride: 1,
        }
    }

    /// Also keeps the ξ of `keep` flights, every `stride`-th complete flight from the first.
    pub fn keeping(mut self, keep: usize, stride: u64) -> Self {
        self.keep = keep;
        self.stride = stride.max(1);
        self.counts.kept = Vec::with_capacity(keep);
        self
    }

    /// The counts so far.
    pub fn counts(&self) -> &FreePathCounts {
        &self.counts
    }

    /// Ends the flight in progress at a collision.
    fn close(&mut self) {
        let xi = self.flight * self.inverse_unit;
        self.flight = 0.0;
        if !std::mem::replace(&mut self.started, true) {
            return;
        }
        let c = &mut self.counts;
        if c.kept.len() < self.keep && c.flights.is_multiple_of(self.stride) {
            c.kept.push(xi);
        }
        c.flights += 1;
        c.sum += xi;
        c.ln_sum += xi.ln();
        c.longest = c.longest.max(xi);
        // The bin k with edges[k] <= xi < edges[k + 1] (none below the first edge).
        let k = self.edges.partition_point(|&e| e <= xi).checked_sub(1);
        if let Some(b) = k.and_then(|k| c.bins.get_mut(k)) {
            *b += 1;
        }
    }
}

impl Observer<1> for FreePaths {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<1>]) {
        for e in steps {
            if e.is_live(0) {
                self.flight += e.time[0];
                if e.is_collision(0) {
                    self.close();
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::observe::NO_EVENT;

    fn event(time: f64, collision: bool) -> EventLanes<1> {
        EventLanes {
            live_bits: 1,
            time: [time],
            code: [if collision { 0.0 } else { 16.0 }],
            ..EventLanes::default()
        }
    }

    /// The partial first flight is dropped, crossings add up, bins are [lo, hi).
    #[test]
    fn flights_are_counted_from_the_first_collision_on() {
        let mut f = FreePaths::new(2.0, &[0.0, 1.0, 2.0, f64::INFINITY]);
        let steps = [
            event(5.0, true),  // the partial first flight
            event(1.0, false), // a crossing
            event(1.0, true),  // xi = 1: bin 1
            event(1.0, true),  // xi = 0.5: bin 0
            event(9.0, true),  // xi = 4.5: bin 2
            EventLanes {
                live_bits: 0,
                code: [NO_EVENT],
                ..EventLanes::default()
            },
        ];
        f.observe::<f64>(&steps);
        let c = f.counts();
        assert_eq!(c.flights, 3);
        assert_eq!(c.bins, vec![1, 1, 1]);
        assert_eq!(c.sum, 6.0);
        assert_eq!(c.longest, 4.5);
        assert!((c.ln_sum - (0.5f64.ln() + 4.5f64.ln())).abs() < 1e-15);
        assert!(c.kept.is_empty());
        // Keeping two, every second complete flight: flights 0 and 2.
        let mut k = FreePaths::new(2.0, &[0.0, 1.0]).keeping(2, 2);
        k.observe::<f64>(&steps);
        assert_eq!(k.counts().kept, vec![1.0, 4.5]);
        // Flights beyond the last edge, or below the first, fall in no bin.
        assert_eq!(k.counts().bins, vec![1]);
        let mut above = FreePaths::new(2.0, &[0.6, 5.0]);
        above.observe::<f64>(&steps);
        assert_eq!(above.counts().bins, vec![2]);
    }
}
