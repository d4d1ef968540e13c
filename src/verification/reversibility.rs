//! Time reversal: N collisions forward, reverse the velocity, N collisions back.
//!
//! The reversed orbit retraces the forward one; the distance between where it ends and where
//! the forward orbit was after its first collision measures the accumulated rounding error,
//! amplified by the chaos. The bound (`proofs-notes/reversibility.md`) is
//!
//! error ≤ 2 N · K u · max_k ‖J_k‖,
//!
//! with u the unit roundoff, K u the one-event error, J_k the Jacobian of the first k events
//! (computed along the f64 orbit by [`super::birkhoff::Tangent`]).

use crate::Error;
use crate::kernel::vec2::Vec2;
use crate::kernel::{cell::CellKernel, cell::ConvexCell, flight::EventKind};
use crate::numbers::real::Real;
use crate::scenes::lattice::{Lattice, LatticeState};
use crate::verification::error_model::ONE_EVENT_U;

/// Outcome of a reversal experiment.
#[derive(Debug, Clone)]
pub struct Reversal<T> {
    /// World position right after the forward orbit's first collision.
    pub first_contact: Vec2<T>,
    /// World position where the reversed orbit made its N-th collision.
    pub returned_contact: Vec2<T>,
    /// |returned − first| (position error).
    pub position_error: T,
    /// |v_returned + v₀| (velocity error: the returned velocity is the reversed initial one).
    pub velocity_error: T,
}

/// Runs `n ≥ 1` collisions forward from `start` (a free-flight state with nothing excluded),
/// reverses, and runs `n` collisions back (the first of which re-does the last forward one at
/// zero flight time).
pub fn reverse_and_return<T: Real, K: CellKernel<T>>(
    lat: &Lattice<T, K>,
    start: &LatticeState<T>,
    n: u64,
) -> Result<Reversal<T>, Error> {
    if n == 0 {
        return Err(Error::Zero { what: "collisions" });
    }
    let mut s = start.clone();
    let v0 = world_velocity(&s);
    let mut first = None;
    let mut c = 0;
    while c < n {
        if let EventKind::Collision(_) = lat.step(&mut s)?.kind {
            c += 1;
            if c == 1 {
                first = Some(lat.world(&s));
            }
        }
    }
    s.flight.reverse();
    let mut c = 0;
    while c < n {
        if let EventKind::Collision(_) = lat.step(&mut s)?.kind {
            c += 1;
        }
    }
    let first_contact = first.expect("n ≥ 1");
    let returned_contact = lat.world(&s);
    let d = returned_contact.sub(&first_contact);
    let vb = world_velocity(&s);
    let dv = Vec2::new(vb.x + &v0.x, vb.y + &v0.y);
    Ok(Reversal {
        position_error: d.norm2().sqrt(),
        velocity_error: dv.norm2().sqrt(),
        first_contact,
        returned_contact,
    })
}

fn world_velocity<T: Real>(s: &LatticeState<T>) -> Vec2<T> {
    if s.cell.down {
        -s.flight.vel.clone()
    } else {
        s.flight.vel.clone()
    }
}

/// Largest singular value of the flow Jacobian over the first `n` collisions of the orbit from
/// `start` (computed in f64 along the `T` orbit), and the number of events on the way.
pub fn amplification<T: Real, K: CellKernel<T>>(
    lat: &Lattice<T, K>,
    start: &LatticeState<T>,
    n: u64,
) -> Result<(f64, u64), Error> {
    use super::birkhoff::Tangent;
    let cell64 = cell_to_f64(lat.cell());
    let mut s = start.clone();
    let mut tan = Tangent::default();
    let (mut c, mut events, mut max) = (0, 0u64, 1.0f64);
    while c < n {
        let ev = lat
            .next_event(&s)
            .ok_or_else(|| Error::Failed("no next event".into()))?;
        let f64s = s.flight.to_f64();
        let e64 = crate::kernel::flight::Event {
            kind: ev.kind,
            time: ev.time.to_f64(),
        };
        tan.push(&f64s, &e64, &cell64);
        lat.apply(&mut s, &ev);
        events += 1;
        if let EventKind::Collision(_) = ev.kind {
            c += 1;
            max = max.max(tan.norm());
        }
    }
    Ok((max, events))
}

/// The nearest-`f64` copy of a cell (for the f64 tangent map along an orbit of any precision).
pub fn cell_to_f64<T: Real>(c: &ConvexCell<T>) -> ConvexCell<f64> {
    c.map_values(|x| x.to_f64())
}

/// The reversal error bound 2·E·K·u·max‖J‖ with E events forward (as many back) and the
/// one-event error K·u, K = [`ONE_EVENT_U`] = 256 (`proofs-notes/reversibility.md`).
pub fn reversal_bound(unit_roundoff: f64, events: u64, max_amplification: f64) -> f64 {
    2.0 * events as f64 * ONE_EVENT_U * unit_roundoff * max_amplification
}
