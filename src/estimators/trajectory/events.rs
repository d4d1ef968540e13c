//! The events of a trajectory's final run, for `--events`: where each one is, when, the world
//! velocity after it, and in a field the centre of the arc that follows it.

use rug::Float;
use serde::Serialize;

use crate::kernel::cell::CellKernel;
use crate::scenes::lattice::{Lattice, LatticeState};

/// Significant digits of an event's numbers.
const EVENT_DIGITS: usize = 20;

/// One event of the final run, for `--events`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EventRecord {
    /// `collision` or `crossing`.
    pub kind: &'static str,
    /// The disk (collision) or edge (crossing) label in the cell's frame.
    pub obstacle: u8,
    /// World x of the event, 20 significant digits.
    pub x: String,
    /// World y of the event, 20 significant digits.
    pub y: String,
    /// Time of the event since the start, 20 significant digits.
    pub time: String,
    /// World velocity after the event, x component (unit length), 20 significant digits.
    pub vx: String,
    /// Its y component.
    pub vy: String,
    /// In a field B: the centre of the arc that follows, (x, y) + (−vy, vx)/B (its radius is
    /// 1/|B|, counter-clockwise for B > 0); `None` without a field.
    pub centre: Option<(String, String)>,
}

/// The record of the event that left `s` at `elapsed` (in `field` if any).
pub(super) fn record<K: CellKernel<Float>>(
    lat: &Lattice<Float, K>,
    s: &LatticeState<Float>,
    field: Option<&Float>,
    (kind, obstacle): (&'static str, u8),
    elapsed: &Float,
) -> EventRecord {
    let text = |v: &Float| v.to_string_radix(10, Some(EVENT_DIGITS));
    let w = lat.world(s);
    // A point-reflected cell (s = −1) sees the world velocity reversed.
    let (vx, vy) = if s.cell.down {
        (-s.flight.vel.x.clone(), -s.flight.vel.y.clone())
    } else {
        (s.flight.vel.x.clone(), s.flight.vel.y.clone())
    };
    let centre = field.map(|b| {
        let cx = w.x.clone() - &(vy.clone() / b);
        let cy = w.y.clone() + &(vx.clone() / b);
        (text(&cx), text(&cy))
    });
    EventRecord {
        kind,
        obstacle,
        x: text(&w.x),
        y: text(&w.y),
        time: text(elapsed),
        vx: text(&vx),
        vy: text(&vy),
        centre,
    }
}
