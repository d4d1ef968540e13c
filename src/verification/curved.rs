//! The curved motions the tracked audit replays ([`super::arc_audit`]): arcs of a magnetic field
//! and the flights of the Gaussian-thermostatted electric field, each one variant of [`Curved`]
//! over the same lattice, so that one auditor, one batch loop and one verdict serve both.

use rug::Rational;

use crate::kernel::arc::arc_time;
use crate::kernel::cell::CellKernel;
use crate::kernel::field::ArcEvent;
use crate::kernel::flight::EventKind;
use crate::kernel::thermostat::Thermostat;
use crate::kernel::thermostat::cell::ThermoEvent;
use crate::numbers::real::Real;
use crate::numbers::tracked::Tracked;
use crate::scenes::lattice::{Lattice, LatticeState};
use crate::scenes::motion::{Motion, MotionInput};
use crate::scenes::thermostat::CellFields;

/// A curved motion exactly as given: the magnetic field B, or the thermostatted field's signed
/// strength E and its angle in degrees.
#[derive(Debug, Clone, PartialEq)]
pub enum ExactMotion {
    /// A magnetic field B ≠ 0.
    Field(Rational),
    /// A thermostatted electric field E ≠ 0 along `angle` degrees from the x axis.
    Thermostat {
        /// The signed strength.
        field: Rational,
        /// The angle in degrees.
        angle: Rational,
    },
}

/// A curved motion at one precision, in the form the lattice's kernels take it.
#[derive(Debug, Clone)]
pub enum Curved<T> {
    /// Arcs in the field B.
    Arc(T),
    /// Thermostatted flights, the field in the frame of each cell.
    Thermostat(CellFields<T>),
}

/// The next event of a [`Curved`] motion.
#[derive(Debug, Clone)]
pub enum CurvedEvent<T> {
    /// An arc's.
    Arc(ArcEvent<T>),
    /// A thermostatted flight's.
    Thermostat(ThermoEvent<T>),
}

impl<T> CurvedEvent<T> {
    /// What ends the flight.
    pub fn kind(&self) -> EventKind {
        match self {
            CurvedEvent::Arc(e) => e.kind,
            CurvedEvent::Thermostat(e) => e.kind,
        }
    }
}

impl ExactMotion {
    /// The motion a configuration gives ([`MotionInput::resolve`]), exact: the magnetic field B
    /// with |B| in `field_range`, or the thermostatted field of strength E along its angle;
    /// `None`: straight flights (no field, or a zero one).
    ///
    /// # Errors
    /// Both fields, an angle without a strength, or a field that is not exact or out of its
    /// range ([`super::exact_field`],
    /// [`check_electric`](crate::estimators::diffusion::check_electric)).
    pub fn of(input: &MotionInput, field_range: (f64, f64)) -> Result<Option<Self>, crate::Error> {
        use crate::numbers::exact::parse_exact;
        let motion = input.resolve()?;
        match &motion {
            Motion::Field(b) => {
                Ok(super::exact_field(Some(b), field_range)?.map(ExactMotion::Field))
            }
            Motion::Thermostat { field, angle } => {
                crate::estimators::diffusion::check_electric(&motion)?;
                Ok(Some(ExactMotion::Thermostat {
                    field: parse_exact(field).map_err(|e| e.named("electric"))?,
                    angle: parse_exact(angle).map_err(|e| e.named("electric_angle"))?,
                }))
            }
            _ => Ok(None),
        }
    }

    /// The motion on tracked numbers at `bits`: every parameter rounded once from its exact value,
    /// with the bound of its `f64` rounding.
    pub fn tracked(&self, bits: u32) -> Curved<Tracked> {
        match self {
            ExactMotion::Field(b) => Curved::Arc(Tracked::from_rational(bits, b)),
            ExactMotion::Thermostat { field, angle } => Curved::Thermostat(CellFields::new(
                Thermostat::exact(field, angle, bits).expect("a nonzero field"),
            )),
        }
    }

    /// The motion as an `f64` run flies it: the field B the tracked one at `bits` rounded to
    /// `f64` (as the arc audit always took it), the thermostat as [`Thermostat::exact`] gives it
    /// in `f64` (the diffusion run's own construction).
    pub fn in_f64(&self, bits: u32) -> Curved<f64> {
        match self {
            ExactMotion::Field(b) => Curved::Arc(Tracked::from_rational(bits, b).v.to_f64()),
            ExactMotion::Thermostat { field, angle } => Curved::Thermostat(CellFields::new(
                Thermostat::exact(field, angle, ()).expect("a nonzero field"),
            )),
        }
    }
}

impl<T: Real> Curved<T> {
    /// The next event of the state `s` on the lattice `lat`, or `None` (a pinned circle, a
    /// creeping slide).
    pub fn next<K: CellKernel<T>>(
        &self,
        lat: &Lattice<T, K>,
        s: &LatticeState<T>,
    ) -> Option<CurvedEvent<T>> {
        match self {
            Curved::Arc(b) => lat.next_event_in_field(s, b).map(CurvedEvent::Arc),
            Curved::Thermostat(f) => lat.next_event_thermostat(s, f).map(CurvedEvent::Thermostat),
        }
    }

    /// The flight time of `ev` from the pre-event state `s` (an arc's from its chord, an
    /// observable; a thermostatted flight's is the kernel's own).
    pub fn time(&self, s: &LatticeState<T>, ev: &CurvedEvent<T>) -> T {
        match (self, ev) {
            (Curved::Arc(b), CurvedEvent::Arc(e)) => arc_time(&s.flight.vel, &e.chord, b),
            (_, CurvedEvent::Thermostat(e)) => e.time.clone(),
            (Curved::Thermostat(_), CurvedEvent::Arc(_)) => unreachable!("an arc event"),
        }
    }

    /// Carries out `ev` on `s`.
    pub fn apply<K: CellKernel<T>>(
        &self,
        lat: &Lattice<T, K>,
        s: &mut LatticeState<T>,
        ev: &CurvedEvent<T>,
    ) {
        match ev {
            CurvedEvent::Arc(e) => lat.apply_in_field(s, e),
            CurvedEvent::Thermostat(e) => lat.apply_thermostat(s, e),
        }
    }
}

impl Curved<Tracked> {
    /// The reference precision of the motion's parameters, in bits.
    pub fn bits(&self) -> u32 {
        match self {
            Curved::Arc(b) => b.v.prec(),
            Curved::Thermostat(f) => f.world().strength.v.prec(),
        }
    }
}
