//! The scalar engine with long flights: in a scene that supplies them
//! ([`Scene::long_flight_radius`]), a flight leaving its cell through the edge it faces along its
//! major axis goes straight to the cell of the first disk it can meet
//! ([`crate::scenes::long_flight::jump`]), so a collision costs the same whatever the flight's
//! length (`proofs-notes/long-flights.md`). The cell walk stays the reference.

use serde::{Deserialize, Serialize};

use super::drive_with;
use super::observe::{EventLanes, Observer};
use crate::Error;
use crate::kernel::cell::CellKernel;
use crate::kernel::flight::Event;
use crate::scenes::Scene;
use crate::scenes::lattice::{Lattice, LatticeState};
use crate::scenes::long_flight::LongFlights;

/// How free flights cross the lattice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Flights {
    /// Jumps where the scene supplies them and they are the faster engine (the square lattice with
    /// 2⁻³² ≤ r ≤ [`AUTO_MAX_RADIUS`]), else the walk.
    #[default]
    Auto,
    /// Cell by cell (the reference: every edge crossing is an event).
    Walk,
    /// Jumps; refused where the scene does not supply them.
    Jump,
}

/// The largest radius at which `auto` jumps, 1/8: above it a jump replaces one or two crossings
/// and costs more than they do. `lorentz bench --long-flights 1/4,1/6,1/8,1/10,1/12,1/16
/// --collisions-per-radius 5e5 --walk-collisions 5e5 --repetitions 5` (the bare engine, one thread):
/// walk/jump = 0.74 at r = 1/4, 0.95 at 1/6, 1.11 at 1/8, 1.26 at 1/10, 1.79 at 1/16
/// (`proofs-notes/long-flights.md`, "Cost").
pub const AUTO_MAX_RADIUS: f64 = 0.125;

impl Flights {
    /// The engine that runs for `scene`: `Walk` or `Jump`.
    ///
    /// # Errors
    /// `Jump` in a scene without long flights.
    pub fn resolve<S: Scene>(self, scene: &S) -> Result<Flights, Error> {
        match (self, scene.long_flights()) {
            (Flights::Walk, _) | (Flights::Auto, None) => Ok(Flights::Walk),
            (Flights::Auto, Some(f)) if !auto_jumps(&f) => Ok(Flights::Walk),
            (_, Some(_)) => Ok(Flights::Jump),
            (Flights::Jump, None) => Err(Error::parameter(
                "flights",
                self,
                format!(
                    "{} has no long flights (the square lattice with 2^-32 <= radius <= 1/4 and \
                     the triangular one with w_inf = 4/sqrt(3) - 2 < w <= 2^20 - 2 have); use \
                     walk or auto",
                    scene.label()
                ),
            )),
        }
    }

    /// The engine that runs in a magnetic field: `Walk` (arcs cross the lattice cell by cell).
    ///
    /// # Errors
    /// `Jump`.
    pub fn in_field(self) -> Result<Flights, Error> {
        match self {
            Flights::Jump => Err(Error::parameter(
                "flights",
                self,
                "arcs in a field cross the lattice cell by cell; use walk or auto",
            )),
            _ => Ok(Flights::Walk),
        }
    }

    /// The long flights `scene` runs with: `Some` where this engine jumps there.
    ///
    /// # Errors
    /// As [`Flights::resolve`].
    pub fn of<S: Scene>(self, scene: &S) -> Result<Option<LongFlights>, Error> {
        let jump = self.resolve(scene)? == Flights::Jump;
        Ok(scene.long_flights().filter(|_| jump))
    }
}

/// Where `auto` jumps: the square lattice at r ≤ [`AUTO_MAX_RADIUS`], the triangular one at
/// spacings a ≥ [`AUTO_MIN_SPACING`].
fn auto_jumps(f: &LongFlights) -> bool {
    match f {
        LongFlights::Square { radius } => *radius <= AUTO_MAX_RADIUS,
        LongFlights::Triangular(t) => t.a >= AUTO_MIN_SPACING,
    }
}

/// The smallest spacing a = 2 + w of the triangular lattice at which `auto` jumps: below it a jump
/// replaces a few trap crossings and costs more than they do (`proofs-notes/long-flights.md`,
/// "Cost").
pub const AUTO_MIN_SPACING: f64 = 8.0;

impl std::fmt::Display for Flights {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Flights::Auto => "auto",
            Flights::Walk => "walk",
            Flights::Jump => "jump",
        })
    }
}

impl std::str::FromStr for Flights {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s {
            "auto" => Ok(Flights::Auto),
            "walk" => Ok(Flights::Walk),
            "jump" => Ok(Flights::Jump),
            _ => Err(Error::parameter("flights", s, "use auto, walk or jump")),
        }
    }
}

/// [`super::drive`] with jumps ([`LongFlights`]): the observer sees a jump as the crossing of the
/// edge it leaves by, with the jump's flight time (the free flight is one straight segment
/// whichever cells it crosses), and the state then stands on the entered edge of the cell it
/// lands in. Where the search finds its first candidate within a cell or two, the flight walks.
///
/// # Errors
/// If the state loses its next event, or flies along a corridor that meets no disk.
pub fn drive_jumps<K: CellKernel<f64>, O: Observer<1>>(
    lat: &Lattice<f64, K>,
    flights: &LongFlights,
    s: &mut LatticeState<f64>,
    collisions: u64,
    obs: &mut O,
    progress: &dyn Fn(u64),
) -> Result<(), Error> {
    drive_with(lat, s, collisions, obs, progress, |s, ev, obs| {
        let Some(landing) = flights.landing_at(s, ev.kind)? else {
            return Ok(false);
        };
        let seen = Event {
            kind: ev.kind,
            time: landing.time,
        };
        obs.observe::<f64>(std::slice::from_ref(&EventLanes::single(s, &seen)));
        s.cell = landing.cell;
        s.flight = landing.flight;
        Ok(true)
    })
}
