//! The state of a free flight inside one cell, and the events that end it.
//!
//! Exclusions are obstacle *identities* (`Option<u8>`: a disk or edge label of the current cell,
//! or nothing), never a tolerance and never a sentinel value that could collide with a label.

use super::vec2::Vec2;
use crate::numbers::real::Real;

/// What ends a free flight inside a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EventKind {
    /// Specular collision with disk `k` of the cell.
    Collision(u8),
    /// Crossing of edge `k` of the cell into the neighbouring cell.
    Crossing(u8),
}

/// The next event: its kind and the flight time to it.
#[derive(Debug, Clone, PartialEq)]
pub struct Event<T> {
    /// Collision or crossing, with the disk/edge label.
    pub kind: EventKind,
    /// Flight time from the current position (speed ≈ 1, so also the flight length).
    pub time: T,
}

/// Position and velocity in the cell's own frame, plus the obstacles the current straight flight
/// cannot meet again (the disk it left, the edge it entered by).
#[derive(Debug, Clone, PartialEq)]
pub struct Flight<T> {
    /// Position in the cell frame (bounded: within the cell, up to rounding).
    pub pos: Vec2<T>,
    /// Velocity (|v| = 1 up to rounding).
    pub vel: Vec2<T>,
    /// Disk left by the last collision on this straight flight.
    pub excluded_disk: Option<u8>,
    /// Edge entered by on this straight flight.
    pub excluded_edge: Option<u8>,
}

impl<T: Real> Flight<T> {
    /// A flight from `pos` with velocity `vel`, nothing excluded.
    pub fn new(pos: Vec2<T>, vel: Vec2<T>) -> Self {
        Flight {
            pos,
            vel,
            excluded_disk: None,
            excluded_edge: None,
        }
    }
    /// Lifts an `f64` state exactly to the context `ctx` (conversion through `f64` of anything
    /// else is deliberately not offered).
    pub fn convert_from_f64(ctx: T::Ctx, f: &Flight<f64>) -> Self {
        Flight {
            pos: Vec2::from_f64(ctx, f.pos.x, f.pos.y),
            vel: Vec2::from_f64(ctx, f.vel.x, f.vel.y),
            excluded_disk: f.excluded_disk,
            excluded_edge: f.excluded_edge,
        }
    }
    /// Rescales the velocity to |v| = 1 at the working precision (for starts lifted from f64,
    /// whose |v|² − 1 is of order 2⁻⁵³ rather than the working unit roundoff).
    pub fn normalise_speed(&mut self) {
        let n = self.vel.norm2().sqrt();
        self.vel.x /= &n;
        self.vel.y /= &n;
    }
    /// Nearest `f64` state.
    pub fn to_f64(&self) -> Flight<f64> {
        Flight {
            pos: Vec2::new(self.pos.x.to_f64(), self.pos.y.to_f64()),
            vel: Vec2::new(self.vel.x.to_f64(), self.vel.y.to_f64()),
            excluded_disk: self.excluded_disk,
            excluded_edge: self.excluded_edge,
        }
    }
    /// Reverses the velocity. The reversed particle has not left any disk and has not entered
    /// by any edge: exclusions are cleared (a reversal right after a collision re-collides with
    /// the same disk at time 0, undoing the reflection).
    pub fn reverse(&mut self) {
        self.vel = -self.vel.clone();
        self.excluded_disk = None;
        self.excluded_edge = None;
    }
}
