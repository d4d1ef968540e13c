//! Long flights: a straight flight goes to the first disk it can meet by lattice arithmetic, in
//! time independent of its length (`proofs-notes/long-flights.md`), on the square lattice
//! ([`square`]) and on the triangular one beyond w∞ ([`triangular`]). The cell walk stays the
//! reference; a scene supplies the search it admits through [`crate::scenes::Scene::long_flights`].

pub mod square;
pub mod triangular;

pub(crate) use square::{Frame, Scale, widening, window};
pub use square::{Jump, MAX_RADIUS, MIN_RADIUS, jump, major_edge};

use crate::Error;
use crate::kernel::flight::{EventKind, Flight};
use crate::scenes::lattice::{CellIndex, LatticeState};

/// The long flights a scene admits: the lattice arithmetic of its search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LongFlights {
    /// Disks of radius `radius` at the integer points ([`square::jump`]).
    Square {
        /// The disks' radius, 2⁻³² ≤ r ≤ 1/4.
        radius: f64,
    },
    /// Disks of radius 1 on the triangular lattice of spacing a beyond w∞ ([`triangular::TriangularFlights::jump`]).
    Triangular(triangular::TriangularFlights),
}

/// Where a jump leaves a flight: its cell, its flight (on the entered edge, nothing but that edge
/// excluded) and the flight time to get there.
#[derive(Debug, Clone, PartialEq)]
pub struct Landing {
    /// The cell entered.
    pub cell: CellIndex,
    /// The flight in that cell's frame.
    pub flight: Flight<f64>,
    /// The flight time from the pre-jump position.
    pub time: f64,
}

impl LongFlights {
    /// The edge whose crossing a flight with velocity `vel` hands to the search: the edge it faces
    /// along its major axis (square), or the trap edge of the family of lattice lines most nearly
    /// perpendicular to it (triangular).
    pub fn trigger(&self, vel: &crate::kernel::vec2::Vec2<f64>) -> u8 {
        match self {
            LongFlights::Square { .. } => major_edge(vel),
            LongFlights::Triangular(_) => triangular::trigger(vel),
        }
    }

    /// The landing of the state `s` whose next event is `kind`, if that event hands the flight to
    /// the search (the crossing of its [`LongFlights::trigger`] edge) and the search lands
    /// ([`LongFlights::land`]): the one rule of every engine that jumps.
    ///
    /// # Errors
    /// As [`LongFlights::land`].
    pub fn landing_at(
        &self,
        s: &LatticeState<f64>,
        kind: EventKind,
    ) -> Result<Option<Landing>, Error> {
        match kind {
            EventKind::Crossing(k) if k == self.trigger(&s.flight.vel) => self.land(s),
            _ => Ok(None),
        }
    }

    /// The landing of the state `s`, about to cross its [`LongFlights::trigger`] edge: `None`
    /// where the first candidate disk is within a cell or two and the walk goes on.
    ///
    /// # Errors
    /// A flight along a corridor that meets no disk.
    pub fn land(&self, s: &LatticeState<f64>) -> Result<Option<Landing>, Error> {
        let corridor = || Error::Failed("a free flight along a corridor meets no disk".into());
        match self {
            LongFlights::Square { radius } => {
                let j = jump(&s.flight.pos, &s.flight.vel, *radius).ok_or_else(corridor)?;
                Ok(Some(Landing {
                    cell: CellIndex {
                        i: s.cell.i + j.cells[0],
                        j: s.cell.j + j.cells[1],
                        down: s.cell.down,
                    },
                    flight: Flight {
                        pos: j.pos,
                        vel: s.flight.vel.clone(),
                        excluded_disk: None,
                        excluded_edge: Some(j.entered),
                    },
                    time: j.time,
                }))
            }
            LongFlights::Triangular(t) => match t.jump(s.cell, &s.flight) {
                triangular::Search::Land(l) => Ok(Some(l)),
                triangular::Search::Walk => Ok(None),
                triangular::Search::Corridor => Err(corridor()),
            },
        }
    }
}
