//! Long flights on decoded lines (`fuzz/fuzz_targets/long_flight.rs`): flights aimed at near
//! misses of far disks and along rational directions, each jump judged against the exact column
//! walk of its line ([`crate::verification::jump_audit::check_jump`]).
//!
//! The first byte picks the radius, 2⁻³² ≤ r ≤ 1/4 (log-uniform over 2⁻¹⁷ … 2⁻², the extremes
//! exactly), the second the family:
//! * **near miss**: the line from a point of the cell passes a disk (k, l) at distance
//!   r(1 + ε), ε = ±2^−e (e from 10 to 60, or 0), the disk up to 2¹⁶ columns away: the window's
//!   margin and the kernel's band are where a skip would hide;
//! * **rational**: the direction (q, p) of a small rational slope p/q (q ≤ 64), turned by
//!   ±2^−e: lines along or near a corridor, the Euclid recursion's deepest and its degenerate
//!   (slope 0, 1, exactly rational) cases;
//! * **any**: a direction of the full circle.
//!
//! The flight is stepped by the cell kernel until it leaves through the edge it faces along its
//! major axis (at most 8 events), where the engine would jump; a jump longer than
//! [`MAX_COLUMNS`] columns is counted, not walked (the oracle stays fast).

use super::bytes::Bytes;
use super::*;
use crate::kernel::vec2::Vec2;
use crate::scenes::long_flight::{jump, major_edge};
use crate::verification::jump_audit::{JumpCheck, check_jump};

/// The longest jump the oracle walks, in columns (about 0.3 ms of the exact walk; the near-miss
/// family aims at disks up to 2¹⁶ columns away).
pub const MAX_COLUMNS: u64 = 1 << 17;

/// What one decoded line gave.
#[derive(Debug, Clone, Default)]
pub struct LongFlightReport {
    /// The jump was checked against the exact walk.
    pub checked: bool,
    /// The line met no disk (a corridor) or its jump was too long to walk.
    pub skipped: bool,
    /// The verdict, where checked.
    pub check: Option<JumpCheck>,
}

/// Decodes `data` into a radius and a flight, steps it to the edge where the engine jumps, and
/// judges the jump.
///
/// # Errors
/// The jump outside its model ([`JumpCheck::in_model`] false), with the pre-jump state.
pub fn long_flight(data: &[u8]) -> Result<LongFlightReport, OracleFailure> {
    let mut b = Bytes::new(data);
    let r = decode_radius(b.u8());
    let family = b.u8() % 3;
    let (pos, vel) = match family {
        0 => near_miss(&mut b, r),
        1 => rational(&mut b, r),
        _ => any(&mut b, r),
    };
    let scene = SquareScene::new(r).map_err(|e| failure(r, e.to_string(), ""))?;
    let lat = scene
        .lattice::<f64>(())
        .map_err(|e| failure(r, e.to_string(), ""))?;
    let mut s = LatticeState {
        cell: CellIndex::default(),
        flight: Flight::new(pos, vel),
    };
    for _ in 0..8 {
        let Some(ev) = lat.next_event(&s) else {
            return Ok(LongFlightReport::default());
        };
        if ev.kind == EventKind::Crossing(major_edge(&s.flight.vel)) {
            return judge(&s.flight, r);
        }
        lat.apply(&mut s, &ev);
    }
    Ok(LongFlightReport::default())
}

fn judge(f: &Flight<f64>, r: f64) -> Result<LongFlightReport, OracleFailure> {
    let skipped = LongFlightReport {
        skipped: true,
        ..LongFlightReport::default()
    };
    let Some(j) = jump(&f.pos, &f.vel, r) else {
        return Ok(skipped);
    };
    if j.cells[0].unsigned_abs().max(j.cells[1].unsigned_abs()) > MAX_COLUMNS {
        return Ok(skipped);
    }
    let c = check_jump(f, r, ORACLE_BITS).expect("the jump just found");
    if !c.in_model {
        return Err(failure(
            r,
            format!("a jump outside its model: {c:?}"),
            &format!("{f:?}"),
        ));
    }
    Ok(LongFlightReport {
        checked: true,
        skipped: false,
        check: Some(c),
    })
}

fn failure(r: f64, reason: String, state: &str) -> OracleFailure {
    jump_failure(format!("square r={r}"), reason, state)
}

/// A long flight's failure in `scene`: at its one jump, from the pre-jump `state`.
pub(super) fn jump_failure(scene: String, reason: String, state: &str) -> OracleFailure {
    OracleFailure {
        case: None,
        scene,
        event: Some(0),
        reason,
        state: state.to_string(),
    }
}

/// 2⁻³² and 1/4 exactly at the ends of the byte's range, log-uniform between 2⁻¹⁷ and 2⁻².
fn decode_radius(x: u8) -> f64 {
    match x {
        0 => crate::scenes::long_flight::MIN_RADIUS,
        255 => crate::scenes::long_flight::MAX_RADIUS,
        _ => 2f64.powf(-2.0 - 15.0 * f64::from(x - 1) / 253.0),
    }
}

/// A point of the cell outside its disk (by at least r/2), from two fractions.
fn point(b: &mut Bytes, r: f64) -> Vec2<f64> {
    let (x, y) = (b.frac16() - 0.5, b.frac16() - 0.5);
    if x.hypot(y) > 1.5 * r {
        Vec2::new(x, y)
    } else {
        Vec2::new(0.5, y)
    }
}

/// ±2^−e for e from 10 to 60, or 0.
pub(super) fn tiny(b: &mut Bytes) -> f64 {
    let x = b.u8();
    let e = x % 64;
    if e < 10 {
        return 0.0;
    }
    let s = if x & 64 == 0 { 1.0 } else { -1.0 };
    s * 2f64.powi(-i32::from(e))
}

pub(super) fn unit(a: f64) -> Vec2<f64> {
    Vec2::new(a.cos(), a.sin())
}

/// The direction from `p` that passes the disk at (k, l) at distance r(1 + ε).
fn near_miss(b: &mut Bytes, r: f64) -> (Vec2<f64>, Vec2<f64>) {
    let p = point(b, r);
    let k = f64::from(b.u16()) + 1.0;
    let l = f64::from(b.u16() % 4096) * if b.u8() & 1 == 0 { 1.0 } else { -1.0 };
    let eps = tiny(b);
    let side = if b.u8() & 1 == 0 { 1.0 } else { -1.0 };
    let (dx, dy) = (k - p.x, l - p.y);
    let d = dx.hypot(dy);
    let a = dy.atan2(dx) + side * (r * (1.0 + eps) / d).asin();
    let turn = f64::from(b.u8() % 4) * std::f64::consts::FRAC_PI_2;
    let v = unit(a);
    let (c, s) = (turn.cos().round(), turn.sin().round());
    (p, Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y))
}

/// A small rational direction (q, p), q ≤ 64, turned by a tiny angle and into any octant.
fn rational(b: &mut Bytes, r: f64) -> (Vec2<f64>, Vec2<f64>) {
    let pos = point(b, r);
    let q = f64::from(b.u8() % 64) + 1.0;
    let p = f64::from(b.u8()) % (q + 1.0);
    let a = p.atan2(q) + tiny(b);
    let o = b.u8();
    let v = unit(a);
    let (mut x, mut y) = (v.x, v.y);
    if o & 1 != 0 {
        std::mem::swap(&mut x, &mut y);
    }
    if o & 2 != 0 {
        x = -x;
    }
    if o & 4 != 0 {
        y = -y;
    }
    (pos, Vec2::new(x, y))
}

fn any(b: &mut Bytes, r: f64) -> (Vec2<f64>, Vec2<f64>) {
    let p = point(b, r);
    (p, unit(b.frac32() * std::f64::consts::TAU))
}
