//! The open strip: the triangular Lorentz gas between two vertical absorbing lines x = 0 and
//! x = L (infinite in y), the geometry of the escape-rate estimator ([`crate::estimators::escape`]).
//!
//! A particle is absorbed the first time its world x-coordinate leaves [0, L]. Between two events
//! the flight is a straight segment, so x is linear in time along it: comparing the world x at
//! the two ends of every segment catches every exit, and the absorption time is the exact
//! crossing time inside the segment, t_start + (boundary − x_start)/v_x (world orientation:
//! v_x = s·vₓ in a cell of orientation s). Positions are the lattice's exact integers plus a
//! bounded offset ([`Unwrapped`](super::lattice::Unwrapped)), so x keeps full relative accuracy
//! across the strip.
//!
//! Initial conditions ([`Strip::sample`]) come from the invariant measure restricted to the
//! strip: uniform position in the free region with 0 ≤ x ≤ L, uniform direction. The strip is
//! invariant under the vertical lattice translation 2e₂ − e₁ = (0, 2h), and absorption depends
//! on x only, so one vertical period y ∈ [0, 2h) is a faithful sample of the whole strip. That
//! period is tiled by the up traps of rows j ∈ {0, 1} and the down traps j ∈ {1, 2} (row
//! y ∈ [0, h] is up (i, 0) and down (i, 1); row y ∈ [h, 2h] is up (i, 1) and down (i, 2)). Every
//! trap is congruent to the canonical one with the same free area, so picking one of the traps
//! that meet [0, L] uniformly and a point uniform in its free part (the canonical sampler, point
//! reflected for a down trap — a reflection preserves area and maps uniform to uniform) gives a
//! point uniform over the union of those traps; rejecting the points with x outside [0, L]
//! leaves it uniform over the free part of the strip's period, because that union covers it.
//! The direction is uniform and stays uniform under the reflection v ↦ −v of a down trap.
//! (`proofs-notes/escape-rate.md`; enforced by `tests/analyses/escape.rs`.)

use rand::Rng;

use super::Scene;
use super::lattice::{Basis64, CellIndex, LatticeState, TriangularLattice};
use super::triangular::TriangularScene;
use crate::Error;

/// How a particle's life in the strip ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// Absorption time, or the cut-off time if the particle survived (censored).
    pub time: f64,
    /// Which line absorbed it, or `None` if it was still inside at the cut-off.
    pub exit: Option<Side>,
    /// Events (collisions and trap crossings) carried out.
    pub events: u64,
}

/// One of the two absorbing lines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// The line x = 0.
    Left,
    /// The line x = L.
    Right,
}

/// The triangular Lorentz gas restricted to the strip 0 ≤ x ≤ L with absorbing sides.
#[derive(Debug, Clone)]
pub struct Strip {
    scene: TriangularScene,
    lattice: TriangularLattice<f64>,
    basis: Basis64,
    width: f64,
    traps: Vec<CellIndex>,
}

impl Strip {
    /// The strip of width `width` (any positive finite width; the estimator imposes its own
    /// lower bound for the diffusive regime) in the scene `scene`.
    ///
    /// # Errors
    /// If `width` is not positive and finite.
    pub fn new(scene: &TriangularScene, width: f64) -> Result<Self, Error> {
        if !(width.is_finite() && width > 0.0) {
            return Err(Error::out_of_range(
                "widths",
                width,
                "use strip widths L that are positive finite lengths",
            ));
        }
        let lattice: TriangularLattice<f64> = scene.lattice(())?;
        let basis = lattice.basis_f64();
        let a = basis.a;
        // Traps of one vertical period whose x-extent meets (0, L): an up trap anchored at
        // x_A = a(i + j/2) spans [x_A, x_A + a], a down trap [x_A − a, x_A].
        let mut traps = Vec::new();
        let i_max = (width / a).ceil() as i64 + 2;
        for (j, down) in [(0, false), (1, true), (1, false), (2, true)] {
            for i in -3..=i_max {
                let anchor = a * (i as f64 + basis.beta * j as f64);
                let lo = if down { anchor - a } else { anchor };
                if lo < width && lo + a > 0.0 {
                    traps.push(CellIndex { i, j, down });
                }
            }
        }
        Ok(Strip {
            scene: scene.clone(),
            lattice,
            basis,
            width,
            traps,
        })
    }

    /// The width L.
    pub fn width(&self) -> f64 {
        self.width
    }

    /// The lattice the particles move in.
    pub fn lattice(&self) -> &TriangularLattice<f64> {
        &self.lattice
    }

    /// The traps initial conditions are drawn from (one vertical period, every trap meeting
    /// [0, L]).
    pub fn sampling_traps(&self) -> &[CellIndex] {
        &self.traps
    }

    /// World x-coordinate of a state (exact integers plus the bounded offset).
    pub fn world_x(&self, s: &LatticeState<f64>) -> f64 {
        self.lattice.unwrapped(s, 0.0).world_x(&self.basis)
    }

    /// `true` if `x` lies in the closed strip [0, L].
    pub fn contains(&self, x: f64) -> bool {
        (0.0..=self.width).contains(&x)
    }

    /// A state from the invariant measure restricted to the strip (see the module docs): a trap
    /// of one period picked uniformly, a point uniform in its free part, rejected unless
    /// 0 ≤ x ≤ L.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> LatticeState<f64> {
        loop {
            let k = rng.random_range(0..self.traps.len());
            let mut s = self.scene.sample(rng);
            s.cell = self.traps[k];
            s.flight.normalise_speed();
            if self.contains(self.world_x(&s)) {
                return s;
            }
        }
    }

    /// Follows `state` (inside the strip) until it is absorbed or the time reaches `t_max`.
    ///
    /// # Errors
    /// If the state starts outside [0, L], `t_max` is not positive and finite, or the flight
    /// loses its next event.
    pub fn follow(&self, mut state: LatticeState<f64>, t_max: f64) -> Result<Outcome, Error> {
        if !(t_max.is_finite() && t_max > 0.0) {
            return Err(Error::Failed(format!(
                "cut-off time t_max = {t_max} must be positive and finite"
            )));
        }
        let x_start = self.world_x(&state);
        if !self.contains(x_start) {
            return Err(Error::Failed(format!(
                "a particle must start inside the strip [0, {}], not at x = {x_start}",
                self.width
            )));
        }
        let lat = &self.lattice;
        let mut t = 0.0;
        let mut events = 0u64;
        loop {
            let ev = lat
                .next_event(&state)
                .ok_or_else(|| Error::Failed("trajectory lost its next event".into()))?;
            let dt = ev.time;
            let x0 = lat.unwrapped(&state, 0.0).world_x(&self.basis);
            let x1 = lat.unwrapped(&state, dt).world_x(&self.basis);
            if !self.contains(x1) {
                let (boundary, side) = if x1 < 0.0 {
                    (0.0, Side::Left)
                } else {
                    (self.width, Side::Right)
                };
                // x is linear along the segment; clamp only against rounding at its ends.
                let vx = state.cell.sign() * state.flight.vel.x;
                let tau = ((boundary - x0) / vx).clamp(0.0, dt);
                let time = t + tau;
                if time > t_max {
                    break;
                }
                return Ok(Outcome {
                    time,
                    exit: Some(side),
                    events,
                });
            }
            if t + dt > t_max {
                break;
            }
            lat.apply(&mut state, &ev);
            t += dt;
            events += 1;
        }
        Ok(Outcome {
            time: t_max,
            exit: None,
            events,
        })
    }
}
