//! How a trajectory flies between events at its working precision: straight lines, the arcs of
//! a magnetic field B, or the flights of a Gaussian-thermostatted electric field E (the
//! thermostat's generic kernel with certified events, [`crate::kernel::thermostat`]); each input
//! exact, rounded once at the working precision.

use rug::{Float, Rational};

use super::TrajectoryInput;
use crate::Error;
use crate::estimators::diffusion::check_electric;
use crate::kernel::arc::{arc_time, chord_at};
use crate::kernel::cell::CellKernel;
use crate::kernel::flight::EventKind;
use crate::kernel::thermostat::Thermostat;
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;
use crate::scenes::lattice::{Lattice, LatticeState};
use crate::scenes::spec::Motion;
use crate::scenes::thermostat::CellFields;

/// The motion of one run at its working precision.
pub(super) enum Flow {
    Straight,
    /// Arcs in the field B.
    Arc(Float),
    /// Thermostatted flights, the field in every cell's frame.
    Driven(CellFields<Float>),
}

/// The input's magnetic field, if any and nonzero (B = 0 is the straight run, with its bits).
pub(super) fn field_of(input: &TrajectoryInput) -> Option<&Rational> {
    input.field.as_ref().filter(|b| **b != 0)
}

/// The input's electric field (strength, angle in degrees), if any and nonzero (E = 0 is the
/// straight run, with its bits).
pub(super) fn electric_of(input: &TrajectoryInput) -> Option<&(Rational, Rational)> {
    input.electric.as_ref().filter(|(e, _)| *e != 0)
}

/// Refuses a magnetic field beside an electric one, and an electric field the diffusion run
/// would refuse ([`check_electric`]: 0 < |E| ≤ 10, the angle within ±360°).
pub(super) fn check_electric_input(input: &TrajectoryInput) -> Result<(), Error> {
    let Some((e, angle)) = electric_of(input) else {
        return Ok(());
    };
    if field_of(input).is_some() {
        return Err(Error::parameter(
            "electric",
            crate::numbers::exact::nearest_f64(e),
            "both a magnetic field and an electric one: give one motion",
        ));
    }
    check_electric(&Motion::Thermostat {
        field: e.to_string(),
        angle: angle.to_string(),
    })
}

impl Flow {
    /// The motion of `input` at `bits` bits.
    pub(super) fn of(input: &TrajectoryInput, bits: u32) -> Flow {
        if let Some(b) = field_of(input) {
            return Flow::Arc(<Float as Real>::from_rational(bits, b));
        }
        match electric_of(input).and_then(|(e, a)| Thermostat::exact(e, a, bits)) {
            Some(th) => Flow::Driven(CellFields::new(th)),
            None => Flow::Straight,
        }
    }

    /// The magnetic field, for the events' arc centres.
    pub(super) fn field(&self) -> Option<&Float> {
        match self {
            Flow::Arc(b) => Some(b),
            _ => None,
        }
    }

    /// The next event of `s` if it comes by time `total` (then carried out: its kind and the
    /// time after it); else `s` is moved to time `total` and `None` returned.
    pub(super) fn next(
        &self,
        lat: &Lattice<Float, impl CellKernel<Float>>,
        s: &mut LatticeState<Float>,
        elapsed: &Float,
        total: &Float,
    ) -> Result<Option<(EventKind, Float)>, Error> {
        match self {
            Flow::Straight => next_straight(lat, s, elapsed, total),
            Flow::Arc(b) => next_arc(lat, s, b, elapsed, total),
            Flow::Driven(fields) => next_driven(lat, s, fields, elapsed, total),
        }
    }
}

/// The next straight event of `s` ([`Flow::next`]).
fn next_straight(
    lat: &Lattice<Float, impl CellKernel<Float>>,
    s: &mut LatticeState<Float>,
    elapsed: &Float,
    total: &Float,
) -> Result<Option<(EventKind, Float)>, Error> {
    let ev = lat
        .next_event(s)
        .ok_or_else(|| Error::Failed("the flight has no next event (zero velocity)".into()))?;
    let end = elapsed.clone() + &ev.time;
    if end > *total {
        let rest = total.clone() - elapsed;
        s.flight.pos = s.flight.pos.along(&rest, &s.flight.vel);
        return Ok(None);
    }
    lat.apply(s, &ev);
    Ok(Some((ev.kind, end)))
}

/// The same on arcs in the field `b`: the event's time is the arc's angle over ω
/// ([`arc_time`]), and the last part-flight the arc's chord after the remaining time
/// ([`chord_at`]). With no event at all the cyclotron circle meets no disk or edge (a pinned
/// orbit): the particle circles for the remaining time. A particle sliding along the disk it is
/// on (the kernel's creeping limit, measure zero) has no defined continuation and is refused.
fn next_arc(
    lat: &Lattice<Float, impl CellKernel<Float>>,
    s: &mut LatticeState<Float>,
    b: &Float,
    elapsed: &Float,
    total: &Float,
) -> Result<Option<(EventKind, Float)>, Error> {
    let rest = total.clone() - elapsed;
    let Some(ev) = lat.next_event_in_field(s, b) else {
        if s.flight.excluded_disk.is_some() {
            return Err(Error::Failed(
                "the particle slides along the disk it is on (a tangent start turning into the disk): choose another direction".into(),
            ));
        }
        finish_arc(s, &rest, b);
        return Ok(None);
    };
    let end = elapsed.clone() + &arc_time(&s.flight.vel, &ev.chord, b);
    if end > *total {
        finish_arc(s, &rest, b);
        return Ok(None);
    }
    lat.apply_in_field(s, &ev);
    Ok(Some((ev.kind, end)))
}

/// Moves `s` along its arc for the time `t` (no event on the way).
fn finish_arc(s: &mut LatticeState<Float>, t: &Float, b: &Float) {
    let x = chord_at(&s.flight.vel, t, b);
    s.flight.pos = Vec2::new(s.flight.pos.x.clone() + &x.x, s.flight.pos.y.clone() + &x.y);
}

/// The same under the thermostat: the event's time is the kernel's certified one, and the last
/// part-flight the closed form at the remaining time (in the cell's frame, whose field the
/// cell's orientation picks). A particle creeping along the disk it is on (measure zero) has no
/// next event and is refused.
fn next_driven(
    lat: &Lattice<Float, impl CellKernel<Float>>,
    s: &mut LatticeState<Float>,
    fields: &CellFields<Float>,
    elapsed: &Float,
    total: &Float,
) -> Result<Option<(EventKind, Float)>, Error> {
    let Some(ev) = lat.next_event_thermostat(s, fields) else {
        return Err(Error::Failed(
            "the thermostatted flight has no next event (a particle creeping along the disk it \
             is on): choose another direction"
                .into(),
        ));
    };
    let end = elapsed.clone() + &ev.time;
    if end > *total {
        let rest = total.clone() - elapsed;
        let at = fields.in_cell(&s.cell).start(&s.flight.vel).at(&rest);
        s.flight.pos = Vec2::new(
            s.flight.pos.x.clone() + &at.disp.x,
            s.flight.pos.y.clone() + &at.disp.y,
        );
        s.flight.vel = at.vel;
        return Ok(None);
    }
    lat.apply_thermostat(s, &ev);
    Ok(Some((ev.kind, end)))
}
