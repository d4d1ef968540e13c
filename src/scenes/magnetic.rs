//! A scene in a uniform magnetic field: the lattice walked along arcs, and the description of the
//! disk array that the field's exact geometry needs ([`DiskLattice`], supplied by a scene through
//! [`super::Scene::disk_lattice`]).
//!
//! The field is a number ω = B (speed 1: the velocity turns at the angular velocity B,
//! counter-clockwise for B > 0, on a cyclotron circle of radius 1/|B|). Every cell map of a
//! scene is a translation or a point reflection — both keep the sense of rotation — so the same ω
//! holds in every cell's frame. B = 0 is the straight kernel, never an arc.

use super::lattice::{Lattice, LatticeState};
use crate::Error;
use crate::kernel::arc::{arc_area, arc_time};
use crate::kernel::cell::CellKernel;
use crate::kernel::field::ArcEvent;
use crate::kernel::flight::EventKind;
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;

/// A periodic array of equal disks of radius `radius` at the points i·e₁ + j·e₂,
/// e₁ = (a, 0), e₂ = (βa, h), as `f64` (the exact geometry of the field's localized orbits is
/// evaluated in `f64`: `crate::theory::magnetic`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiskLattice {
    /// |e₁|.
    pub a: f64,
    /// The shear β of e₂.
    pub beta: f64,
    /// The height of e₂.
    pub h: f64,
    /// The disk radius.
    pub radius: f64,
}

impl DiskLattice {
    /// The area of one lattice cell, a·h.
    pub fn cell_area(&self) -> f64 {
        self.a * self.h
    }

    /// The free area |Q| of one cell (its disk removed), a·h − πr².
    pub fn free_area(&self) -> f64 {
        self.cell_area() - std::f64::consts::PI * self.radius * self.radius
    }

    /// The distance between nearest lattice points (the shortest of ±e₁ ± e₂ combinations
    /// with small coefficients: enough for the reduced bases of the scenes).
    pub fn nearest_distance(&self) -> f64 {
        let mut best = f64::INFINITY;
        for i in -2i32..=2 {
            for j in -2i32..=2 {
                if (i, j) != (0, 0) {
                    let x = self.a * (i as f64 + self.beta * j as f64);
                    let y = self.h * j as f64;
                    best = best.min(x.hypot(y));
                }
            }
        }
        best
    }

    /// The lattice point nearest to (x, y) (up to rounding ties), as world coordinates.
    pub fn nearest_point(&self, x: f64, y: f64) -> (f64, f64) {
        let mut best = (f64::INFINITY, 0.0, 0.0);
        let j0 = (y / self.h).round();
        for dj in -1..=1 {
            let j = j0 + dj as f64;
            let i = ((x - self.beta * self.a * j) / self.a).round();
            for di in -1..=1 {
                let cx = self.a * (i + di as f64 + self.beta * j);
                let cy = self.h * j;
                // The squared distance orders the nine points as the distance does (up to
                // the rounding ties the documentation allows), without nine `hypot` calls.
                let d = (x - cx) * (x - cx) + (y - cy) * (y - cy);
                if d < best.0 {
                    best = (d, cx, cy);
                }
            }
        }
        (best.1, best.2)
    }
}

/// One event of an arc flight, as the observers of a field run see it: what ended it, the flight
/// time, the world displacement of the flight (the chord) and its part of the Lévy area
/// ∫ x × dx taken from the flight's start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcStep {
    /// Collision or crossing.
    pub kind: EventKind,
    /// Flight time to the event (2α/|ω|, see [`crate::kernel::arc::arc_time`]).
    pub time: f64,
    /// The chord in world coordinates.
    pub chord: [f64; 2],
    /// ∫ x × dx over the flight, x measured from the flight's start: (φ − sin φ)/ω².
    pub area: f64,
}

impl ArcStep {
    /// The event `kind` at the end of the chord `chord` of the arc of velocity `vel` in the field
    /// `w` (both in the frame of a cell of orientation `sign`), described in world coordinates:
    /// the one description of an event whichever engine found it.
    pub fn new<T: Real>(kind: EventKind, vel: &Vec2<T>, chord: &Vec2<T>, sign: f64, w: &T) -> Self {
        let time = arc_time(vel, chord, w).to_f64();
        ArcStep {
            kind,
            time,
            chord: [sign * chord.x.to_f64(), sign * chord.y.to_f64()],
            area: arc_area(time, w.to_f64()),
        }
    }
}

impl<T: Real, K: CellKernel<T>> Lattice<T, K> {
    /// The next event of the state's arc in the field `w` (≠ 0), or `None` for a pinned orbit
    /// (its cyclotron circle inside the cell meets nothing) or a non-finite state.
    #[inline]
    pub fn next_event_in_field(&self, s: &LatticeState<T>, w: &T) -> Option<ArcEvent<T>> {
        self.cell().next_event_in_field(&s.flight, w)
    }

    /// Carries out `ev`, moving to the neighbouring cell on a crossing.
    #[inline]
    pub fn apply_in_field(&self, s: &mut LatticeState<T>, ev: &ArcEvent<T>) {
        self.cell().apply_in_field(&mut s.flight, ev);
        if let EventKind::Crossing(k) = ev.kind {
            s.cell = s.cell.across(&self.cell().edges[k as usize]);
        }
    }

    /// One event in the field `w` (≠ 0): found, carried out, and described for observers in
    /// world coordinates (`f64`).
    ///
    /// # Errors
    /// [`Error::Failed`] if the orbit has no next event (a pinned orbit: callers start only
    /// orbits that collide, `crate::theory::magnetic::classify`).
    pub fn step_in_field(&self, s: &mut LatticeState<T>, w: &T) -> Result<ArcStep, Error> {
        let ev = self
            .next_event_in_field(s, w)
            .ok_or_else(|| no_next_event(s.flight.vel.to_f64()))?;
        let step = ArcStep::new(ev.kind, &s.flight.vel, &ev.chord, s.cell.sign(), w);
        self.apply_in_field(s, &ev);
        Ok(step)
    }
}

/// The error of an orbit in a field that has no next event, with its velocity `vel`: the one
/// message whichever engine flew it.
pub fn no_next_event(vel: [f64; 2]) -> Error {
    Error::Failed(format!(
        "an orbit in the field has no next event (a pinned orbit, or velocity {vel:?})"
    ))
}
