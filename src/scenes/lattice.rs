//! The periodic triangular lattice, as a walk over its traps.
//!
//! State: the current trap as exact integers — the anchor lattice point (i, j) and an
//! orientation s = ±1 — plus the flight in the canonical frame, so that
//!
//! world position = i·e₁ + j·e₂ + s·p,  e₁ = (a, 0), e₂ = (a/2, h).
//!
//! Up traps have s = +1 (vertices L(i,j), L(i+1,j), L(i,j+1)); down traps s = −1 (vertices
//! L(i,j), L(i−1,j), L(i,j−1)). Crossing edge Eₖ moves the anchor by s·dₖ with
//! d₀ = (1,1), d₁ = (0,1), d₂ = (1,0) (the lattice vector of cₖ) and flips s. The offset p
//! stays bounded for ever, so precision does not decay with the distance travelled, and the
//! unwrapped displacement is exact integers plus a bounded offset.

use crate::error::Error;
use crate::kernel::trap::{Event, EventKind, Flight, Trap};
use crate::kernel::vec2::Vec2;
use crate::real::Real;

/// A trap of the lattice: anchor lattice point and orientation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Cell {
    /// Anchor index along e₁.
    pub i: i64,
    /// Anchor index along e₂.
    pub j: i64,
    /// `true` for s = −1 (a "down" trap).
    pub down: bool,
}

impl Cell {
    /// The orientation s = ±1.
    pub fn sign(&self) -> f64 {
        if self.down {
            -1.0
        } else {
            1.0
        }
    }
    /// The neighbouring trap across edge `k`.
    #[inline(always)]
    pub fn across(&self, k: u8) -> Cell {
        let (di, dj) = match k {
            0 => (1, 1),
            1 => (0, 1),
            _ => (1, 0),
        };
        if self.down {
            Cell {
                i: self.i - di,
                j: self.j - dj,
                down: false,
            }
        } else {
            Cell {
                i: self.i + di,
                j: self.j + dj,
                down: true,
            }
        }
    }
}

/// A particle in the lattice.
#[derive(Debug, Clone, PartialEq)]
pub struct LatticeState<T> {
    /// The trap it is in.
    pub cell: Cell,
    /// Its flight in the trap's canonical frame.
    pub flight: Flight<T>,
}

impl<T: Real> LatticeState<T> {
    /// Lifts an `f64` state exactly to precision `ctx`.
    pub fn convert_from_f64(ctx: T::Ctx, s: &LatticeState<f64>) -> Self {
        LatticeState {
            cell: s.cell,
            flight: Flight::convert_from_f64(ctx, &s.flight),
        }
    }
    /// Nearest `f64` state.
    pub fn to_f64(&self) -> LatticeState<f64> {
        LatticeState {
            cell: self.cell,
            flight: self.flight.to_f64(),
        }
    }
}

/// An unwrapped world position: exact lattice integers plus a bounded `f64` offset.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Unwrapped {
    /// Lattice index along e₁.
    pub i: i64,
    /// Lattice index along e₂.
    pub j: i64,
    /// Offset s·p from the lattice point, |offset| < a.
    pub off: [f64; 2],
}

impl Unwrapped {
    /// Displacement `self − from` in world coordinates, with the integer parts differenced
    /// exactly before conversion.
    #[inline(always)]
    pub fn displacement_from(&self, from: &Unwrapped, a: f64, h: f64) -> [f64; 2] {
        let di = (self.i - from.i) as f64;
        let dj = (self.j - from.j) as f64;
        [
            a * (di + 0.5 * dj) + (self.off[0] - from.off[0]),
            h * dj + (self.off[1] - from.off[1]),
        ]
    }
}

/// The periodic lattice scene.
#[derive(Debug, Clone)]
pub struct PeriodicLattice<T: Real> {
    /// The canonical trap.
    pub trap: Trap<T>,
    a64: f64,
    h64: f64,
}

impl<T: Real> PeriodicLattice<T> {
    /// The lattice at gap `w > 0`.
    pub fn new(w: T) -> Result<Self, Error> {
        let trap = Trap::new(w)?;
        let (a64, h64) = (trap.a.to_f64(), trap.h.to_f64());
        Ok(PeriodicLattice { trap, a64, h64 })
    }

    /// Lattice spacing and row height as `f64` (for observables).
    pub fn a_h_f64(&self) -> (f64, f64) {
        (self.a64, self.h64)
    }

    /// The next event of the state's flight (see [`Trap::next_event`]).
    #[inline(always)]
    pub fn next_event(&self, s: &LatticeState<T>) -> Option<Event<T>> {
        self.trap.next_event(&s.flight)
    }

    /// Carries out `ev`, moving to the neighbouring trap on a crossing.
    #[inline(always)]
    pub fn apply(&self, s: &mut LatticeState<T>, ev: &Event<T>) {
        self.trap.apply(&mut s.flight, ev);
        if let EventKind::Crossing(k) = ev.kind {
            s.cell = s.cell.across(k);
        }
    }

    /// One event: find it and carry it out.
    ///
    /// # Errors
    /// If the state has no next event (zero or non-finite velocity).
    #[inline(always)]
    pub fn step(&self, s: &mut LatticeState<T>) -> Result<Event<T>, Error> {
        let ev = self.next_event(s).ok_or_else(|| {
            Error::Invalid(format!(
                "state has no next event (velocity {:?})",
                s.flight.vel.to_f64()
            ))
        })?;
        self.apply(s, &ev);
        Ok(ev)
    }

    /// Advances until `n` collisions have happened; returns the number of crossings on the way.
    pub fn run_collisions(&self, s: &mut LatticeState<T>, n: u64) -> Result<u64, Error> {
        let mut hops = 0;
        let mut c = 0;
        while c < n {
            match self.step(s)?.kind {
                EventKind::Collision(_) => c += 1,
                EventKind::Crossing(_) => hops += 1,
            }
        }
        Ok(hops)
    }

    /// Unwrapped world position of the state, after a further free flight of time `dt`
    /// (`dt = 0` for the current position).
    #[inline(always)]
    pub fn unwrapped(&self, s: &LatticeState<T>, dt: f64) -> Unwrapped {
        let sg = s.cell.sign();
        let p = &s.flight.pos;
        let v = &s.flight.vel;
        Unwrapped {
            i: s.cell.i,
            j: s.cell.j,
            off: [
                sg * (p.x.to_f64() + dt * v.x.to_f64()),
                sg * (p.y.to_f64() + dt * v.y.to_f64()),
            ],
        }
    }

    /// World position at the working precision: L(i, j) + s·p.
    pub fn world(&self, s: &LatticeState<T>) -> Vec2<T> {
        let ctx = self.trap.a.ctx();
        let i = T::from_f64(ctx, s.cell.i as f64);
        let j = T::from_f64(ctx, s.cell.j as f64);
        let lx = self.trap.a.clone() * &(i + &j.clone().scale(0.5));
        let ly = self.trap.h.clone() * &j;
        if s.cell.down {
            Vec2::new(lx - &s.flight.pos.x, ly - &s.flight.pos.y)
        } else {
            Vec2::new(lx + &s.flight.pos.x, ly + &s.flight.pos.y)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn across_is_an_involution_and_matches_the_geometry() {
        let t = Trap::new(0.1f64).unwrap();
        for down in [false, true] {
            let c = Cell { i: 3, j: -2, down };
            for k in 0..3u8 {
                assert_eq!(c.across(k).across(k), c);
                // The world image of a point on edge k is the same seen from both traps.
                let lat = PeriodicLattice {
                    trap: t.clone(),
                    a64: t.a,
                    h64: t.h,
                };
                let mid = Vec2::new(t.centres[k as usize].x / 2.0, t.centres[k as usize].y / 2.0);
                let s1 = LatticeState {
                    cell: c,
                    flight: Flight::new(mid.clone(), Vec2::new(1.0, 0.0)),
                };
                let other = t.centres[k as usize].sub(&mid);
                let s2 = LatticeState {
                    cell: c.across(k),
                    flight: Flight::new(other, Vec2::new(1.0, 0.0)),
                };
                let (w1, w2) = (lat.world(&s1), lat.world(&s2));
                assert!((w1.x - w2.x).abs() < 1e-14 && (w1.y - w2.y).abs() < 1e-14);
            }
        }
    }
}
