//! Long flights of the triangular lattice beyond w∞ on decoded lines
//! (`fuzz/fuzz_targets/long_flight_triangular.rs`): flights aimed at near misses of far disks and
//! along lattice directions, each jump replayed by the MPFR trap walk and judged against its model
//! ([`crate::verification::jump_audit_triangular::check_jump`]).
//!
//! The first byte picks the gap: just beyond w∞ (by 2⁻³⁰ of it), the largest spacing 2²⁰, or a
//! spacing log-uniform between 2.32 and 2²⁰. The second picks the family:
//! * **near miss**: the line from a point of the trap passes the disk at m·e₁ + n·e₂ (|m|, |n| up to
//!   1024) at distance 1 + ε, ε = ±2^−e (e from 10 to 60, or 0);
//! * **lattice**: the direction of a lattice vector p·e₁ + q·e₂ (|p|, |q| ≤ 16) turned by ±2^−e:
//!   lines along or near a corridor;
//! * **any**: a direction of the full circle.
//!
//! The flight is stepped by the trap kernel until its next event is the crossing of its trigger
//! edge (at most 8 events), where the engine would jump; a landing more than [`MAX_SPAN`] lattice
//! steps away is counted, not walked.

use super::bytes::Bytes;
use super::long_flight::{jump_failure, tiny, unit};
use super::*;
use crate::scenes::long_flight::LongFlights;
use crate::scenes::long_flight::triangular::{MAX_SPACING, Search, trigger};
use crate::verification::jump_audit_triangular::{TriangularJumpCheck, check_jump};

/// The farthest landing the oracle walks, in lattice steps |i| + |j| (a few thousand MPFR trap
/// crossings, some milliseconds).
pub const MAX_SPAN: u64 = 2048;

/// What one decoded line gave.
#[derive(Debug, Clone, Default)]
pub struct TriangularFlightReport {
    /// The jump was replayed.
    pub checked: bool,
    /// The search let the flight walk on (a candidate within a column or two), found a corridor,
    /// or landed beyond [`MAX_SPAN`].
    pub skipped: bool,
    /// The verdict, where replayed.
    pub check: Option<TriangularJumpCheck>,
}

/// Decodes `data` into a gap and a flight, steps it to the crossing where the engine jumps, and
/// judges the jump.
///
/// # Errors
/// The jump outside its model, with the pre-jump state.
pub fn long_flight_triangular(data: &[u8]) -> Result<TriangularFlightReport, OracleFailure> {
    let mut b = Bytes::new(data);
    let w = decode_gap(b.u8());
    let family = b.u8() % 3;
    let scene = TriangularScene::new(w).map_err(|e| failure(w, e.to_string(), ""))?;
    let Some(LongFlights::Triangular(t)) = scene.long_flights() else {
        return Ok(TriangularFlightReport::default());
    };
    let trap = scene.trap64();
    let p = point(&mut b, trap);
    let v = match family {
        0 => near_miss(&mut b, &p, t.a, t.h),
        1 => lattice(&mut b, t.a, t.h),
        _ => unit(b.frac32() * std::f64::consts::TAU),
    };
    let lat = scene
        .lattice::<f64>(())
        .map_err(|e| failure(w, e.to_string(), ""))?;
    let mut s = LatticeState {
        cell: CellIndex::default(),
        flight: Flight::new(p, v),
    };
    for _ in 0..8 {
        let Some(ev) = lat.next_event(&s) else {
            return Ok(TriangularFlightReport::default());
        };
        if ev.kind == EventKind::Crossing(trigger(&s.flight.vel)) {
            return judge(&scene, &t, &s);
        }
        lat.apply(&mut s, &ev);
    }
    Ok(TriangularFlightReport::default())
}

fn judge(
    scene: &TriangularScene,
    t: &crate::scenes::long_flight::triangular::TriangularFlights,
    s: &LatticeState<f64>,
) -> Result<TriangularFlightReport, OracleFailure> {
    let skipped = TriangularFlightReport {
        skipped: true,
        ..TriangularFlightReport::default()
    };
    let f = &s.flight;
    let Search::Land(landing) = t.jump(CellIndex::default(), f) else {
        return Ok(skipped);
    };
    if landing.cell.i.unsigned_abs() + landing.cell.j.unsigned_abs() > MAX_SPAN {
        return Ok(skipped);
    }
    let w = scene.w();
    let kref = scene
        .kernel::<Float>(ORACLE_BITS)
        .map_err(|e| failure(w, e.to_string(), ""))?;
    let c = check_jump(&kref, t, f, &landing).map_err(|e| failure(w, e.to_string(), ""))?;
    if !c.in_model {
        return Err(failure(
            w,
            format!("a jump outside its model: {c:?}"),
            &format!("{f:?}"),
        ));
    }
    Ok(TriangularFlightReport {
        checked: true,
        skipped: false,
        check: Some(c),
    })
}

fn failure(w: f64, reason: String, state: &str) -> OracleFailure {
    jump_failure(format!("triangular w={w}"), reason, state)
}

/// Just beyond w∞, the largest spacing, or a spacing log-uniform between 2.32 and 2²⁰.
fn decode_gap(x: u8) -> f64 {
    let w_inf = 4.0 / 3f64.sqrt() - 2.0;
    match x {
        0 => w_inf * (1.0 + f64::powi(2.0, -30)),
        255 => MAX_SPACING - 2.0,
        _ => (2.32f64.ln() + (MAX_SPACING / 2.32).ln() * f64::from(x - 1) / 253.0).exp() - 2.0,
    }
}

/// A point of the canonical trap outside its disks, from two fractions (the trap's centre where
/// they fall inside one).
fn point(b: &mut Bytes, trap: &Trap<f64>) -> Vec2<f64> {
    let (mut u1, mut u2) = (b.frac16(), b.frac16());
    if u1 + u2 > 1.0 {
        (u1, u2) = (1.0 - u1, 1.0 - u2);
    }
    let (a, h) = (*trap.a(), *trap.h());
    let p = Vec2::new(u1 * a + u2 * a * 0.5, u2 * h);
    if trap.is_free(&p) {
        p
    } else {
        Vec2::new(a * 0.5, h / 3.0)
    }
}

/// The direction from `p` that passes the disk at m·e₁ + n·e₂ at distance 1 + ε.
fn near_miss(b: &mut Bytes, p: &Vec2<f64>, a: f64, h: f64) -> Vec2<f64> {
    let sign = |b: &mut Bytes| if b.u8() & 1 == 0 { 1.0 } else { -1.0 };
    let m = f64::from(b.u16() % 1024) * sign(b);
    let n = f64::from(b.u16() % 1024) * sign(b);
    let eps = tiny(b);
    let side = sign(b);
    let (dx, dy) = (m * a + n * a * 0.5 - p.x, n * h - p.y);
    let d = dx.hypot(dy);
    if d <= 2.0 {
        return unit(dy.atan2(dx) + 0.5);
    }
    unit(dy.atan2(dx) + side * ((1.0 + eps) / d).asin())
}

/// The direction of a lattice vector p·e₁ + q·e₂ (|p|, |q| ≤ 16, not both 0), turned by ±2^−e.
fn lattice(b: &mut Bytes, a: f64, h: f64) -> Vec2<f64> {
    let p = f64::from(b.u8() % 33) - 16.0;
    let q = f64::from(b.u8() % 33) - 16.0;
    let (x, y) = if p == 0.0 && q == 0.0 {
        (1.0, 0.0)
    } else {
        (p * a + q * a * 0.5, q * h)
    };
    unit(y.atan2(x) + tiny(b))
}
