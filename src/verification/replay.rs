//! Per-event MPFR shadow: replay one `f64` event at high precision from the *same* pre-event
//! state (lifted exactly) and judge the difference against the one-step error model of
//! `proofs-notes/error-model.md`.
//!
//! This is the check that scales to production runs: a chaotic orbit cannot be compared with the
//! exact one from the same start beyond ~35 collisions, but every single event can be. A run
//! whose events are all inside the model is an ε-pseudo-orbit with the measured ε.

use rug::Float;
use serde::{Deserialize, Serialize};

use crate::Error;
use crate::kernel::{
    cell::CellKernel, cell::ConvexCell, cell::Disk, flight::Event, flight::EventKind,
    flight::Flight,
};
use crate::numbers::real::Real;

/// One candidate event computed at reference precision, with the quantities the error model
/// needs.
#[derive(Debug, Clone)]
struct Candidate {
    kind: EventKind,
    time: Float,
    /// First-order bound on |t_f64 − t_exact| (absolute, time units).
    time_bound: f64,
    /// For a disk: the discriminant Δ = |v|² − q² and its f64 error bound.
    disc: Option<(f64, f64)>,
}

/// The verdict on one replayed event.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EventCheck {
    /// Event chosen by the f64 kernel (`"collision k"` / `"crossing k"`).
    pub kind_f64: String,
    /// Event chosen at reference precision.
    pub kind_ref: String,
    /// |t_f64 − t_ref|.
    pub time_error: f64,
    /// Error-model bound on the time error.
    pub time_bound: f64,
    /// |x_f64 − x_ref| after the event (canonical frame).
    pub position_error: f64,
    /// |v_f64 − v_ref| after the event.
    pub velocity_error: f64,
    /// Error-model bound on the position error.
    pub position_bound: f64,
    /// Error-model bound on the velocity error.
    pub velocity_bound: f64,
    /// The reference says the choice is ambiguous at f64 (a near tie or a tangency within the
    /// band): f64 and reference may legitimately choose differently.
    pub ambiguous: bool,
    /// Everything within the model.
    pub in_model: bool,
    /// Thermostatted flights: the reference flight's largest residual against closed forms the
    /// kernel does not use, in units of its tolerance (above 1: the reference is not the
    /// thermostatted flight, and the event is outside the model); absent for other motions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flight_identity: Option<f64>,
}

fn label(k: EventKind) -> String {
    match k {
        EventKind::Collision(m) => format!("collision {m}"),
        EventKind::Crossing(e) => format!("crossing {e}"),
    }
}

/// Unit roundoff of f64.
const U: f64 = crate::verification::error_model::UNIT_ROUNDOFF;

/// Candidates at reference precision (same exclusions as the f64 state), each with its bound.
///
/// The bounds are written for any [`ConvexCell`]: `a` below is the cell's extent (the largest
/// |coordinate| of its corners and disk centres, the spacing a for the triangular trap), r² the
/// squared radius of the disk considered (1 there), so for the triangular trap they are the bounds of
/// `proofs-notes/error-model.md` term by term.
fn candidates(cell: &ConvexCell<Float>, a: f64, f: &Flight<Float>) -> Vec<Candidate> {
    let disks =
        (cell.disks.iter().enumerate()).filter_map(|(m, d)| disk_candidate(d, m as u8, a, f));
    let edges = (0..cell.edges.len()).filter_map(|k| edge_candidate(cell, k as u8, a, f));
    disks.chain(edges).collect()
}

/// Disk `m`'s candidate, with its time bound and discriminant error ([`candidates`]).
fn disk_candidate(disk: &Disk<Float>, m: u8, a: f64, f: &Flight<Float>) -> Option<Candidate> {
    if f.excluded_disk == Some(m) {
        return None;
    }
    let (p, v) = (&f.pos, &f.vel);
    let vv = v.norm2();
    let r2 = disk.radius2().to_f64();
    let d = p.sub(&disk.centre);
    let beta = d.dot(v);
    let q = d.cross(v);
    let disc = vv.clone() * disk.radius2() - &Real::square(&q);
    let dn = d.norm2().sqrt().to_f64();
    // Error model (first order, each term doubled): the f64 centre differs from the exact
    // one by ≤ u·a per component, each operation adds its rounding; r² is rounded once.
    let e_d = U * (dn + 2.0 * a);
    let e_beta = 2.0 * (2.0 * e_d + 2.0 * U * dn);
    let e_disc =
        2.0 * (4.0 * U * r2 + 2.0 * q.to_f64().abs() * (2.0 * e_d + 2.0 * U * dn) + U * r2);
    if !beta.lt0() {
        // Moving away: the f64 sign of β can flip only if |β| ≤ e_β; then Δ ≈ |v|²r² and the
        // root is t ≈ γ/(2|β|) ≥ …: such a start sits on the disk surface, handled by γ ≤ 0.
        if beta.to_f64().abs() > e_beta || d.norm2().to_f64() > r2 + 8.0 * U * dn * dn {
            return None;
        }
    }
    let disc64 = disc.to_f64();
    if disc64 <= -e_disc {
        return None;
    }
    let gamma = d.norm2() - disk.radius2();
    let sq = if disc.is_sign_positive() {
        disc.clone().sqrt()
    } else {
        Float::with_val(disc.prec(), 0)
    };
    let denom = sq.clone() - &beta;
    let t = if gamma.is_sign_positive() && denom.is_sign_positive() && !denom.is_zero() {
        gamma.clone() / &denom
    } else {
        Float::with_val(gamma.prec(), 0)
    };
    let (t64, den64, sq64) = (
        t.to_f64(),
        denom.to_f64().max(f64::MIN_POSITIVE),
        sq.to_f64(),
    );
    let e_gamma = 2.0 * (2.0 * dn * e_d + 3.0 * U * dn * dn + U * r2);
    let e_sq = if sq64 > 0.0 {
        e_disc / (2.0 * sq64) + U * sq64
    } else {
        f64::INFINITY
    };
    let e_den = e_sq + e_beta + U * den64;
    let time_bound = 2.0 * (e_gamma / den64 + t64 * e_den / den64 + U * t64);
    Some(Candidate {
        kind: EventKind::Collision(m),
        time: t,
        time_bound,
        disc: Some((disc64, e_disc)),
    })
}

/// Edge `k`'s candidate, with its time bound ([`candidates`]).
fn edge_candidate(cell: &ConvexCell<Float>, k: u8, a: f64, f: &Flight<Float>) -> Option<Candidate> {
    let (p, v) = (&f.pos, &f.vel);
    let e = &cell.edges[k as usize];
    if f.excluded_edge == Some(k) {
        return None;
    }
    let nv = e.normal.dot(v);
    let sigma = cell.edge_distance(k as usize, p);
    let (nv64, s64) = (nv.to_f64(), sigma.to_f64());
    let e_nv = 4.0 * U;
    let e_sigma = 4.0 * U * (p.norm2().sqrt().to_f64() + 2.0 * a);
    if nv64 >= e_nv {
        return None;
    }
    let t = if sigma.is_sign_positive() && nv.is_sign_negative() {
        sigma / &(-nv)
    } else {
        Float::with_val(v.x.prec(), 0)
    };
    let t64 = t.to_f64();
    let mag = nv64.abs().max(f64::MIN_POSITIVE);
    let time_bound = 2.0 * ((e_sigma + s64.abs().min(e_sigma)) / mag + t64 * e_nv / mag + U * t64);
    Some(Candidate {
        kind: EventKind::Crossing(k),
        time: t,
        time_bound,
        disc: None,
    })
}

/// Replays the next event of the f64 flight `f` at `bits` of precision and compares.
///
/// # Errors
/// If `bits < 53` or the f64 state has no next event.
pub fn check_event<K64: CellKernel<f64>, KRef: CellKernel<Float>>(
    t64: &K64,
    tref: &KRef,
    f: &Flight<f64>,
) -> Result<EventCheck, Error> {
    let cell = tref.cell();
    let bits = cell.lattice.a.prec();
    <Float as Real>::check_ctx(bits)?;
    let e64: Event<f64> = t64
        .next_event(f)
        .ok_or_else(|| Error::Failed("f64 state has no next event".into()))?;
    let fr = Flight::<Float>::convert_from_f64(bits, f);
    let er: Event<Float> = tref
        .next_event(&fr)
        .ok_or_else(|| Error::Failed("reference state has no next event".into()))?;
    // The cell's extent, the scale of its constants' rounding (computed once per event).
    let a = cell.extent();
    let cands = candidates(cell, a, &fr);
    let best = cands.iter().find(|c| c.kind == er.kind);
    let best_bound = best.map(|c| c.time_bound).unwrap_or(f64::INFINITY);
    // Ambiguous: another candidate within the combined bounds of the best, or a disk in the
    // tangency band |Δ| ≤ e_Δ.
    let ambiguous = cands.iter().any(|c| {
        c.kind != er.kind && {
            let gap = (c.time.clone() - &er.time).to_f64().abs();
            gap <= c.time_bound + best_bound
        }
    }) || cands
        .iter()
        .any(|c| matches!(c.disc, Some((d, e)) if d.abs() <= e));

    let mut a64 = f.clone();
    t64.apply(&mut a64, &e64);
    let mut ar = fr.clone();
    tref.apply(&mut ar, &er);
    let time_error = (Float::with_val(bits, e64.time) - &er.time).to_f64().abs();
    let lifted = Flight::<Float>::convert_from_f64(bits, &a64);
    let position_error = lifted.pos.sub(&ar.pos).norm2().sqrt().to_f64();
    let velocity_error = lifted.vel.sub(&ar.vel).norm2().sqrt().to_f64();
    // The radius of the disk met (the smallest one for a crossing, where no bound uses it).
    let r = match er.kind {
        EventKind::Collision(m) => cell.disks[m as usize].radius().to_f64(),
        EventKind::Crossing(_) => cell.smallest_radius(),
    };
    // Position: the time error along |v| ≈ 1, plus rounding of x = p + t v and of the frame map.
    let position_bound = best_bound + 4.0 * U * (2.0 * a + er.time.to_f64());
    // Velocity: v' = v − 2(v·n)n/r² with n = x − c, |n| = r; |δv'| ≤ 4|δn|/r + 8u,
    // |δn| ≤ |δx| + u(r + 2a) (r = 1 for the triangular trap).
    let velocity_bound = 4.0 * (position_bound + U * (r + 2.0 * a)) / r + 8.0 * U;
    let same = e64.kind == er.kind;
    let in_model = if same {
        time_error <= best_bound
            && position_error <= position_bound
            && velocity_error <= velocity_bound
    } else {
        ambiguous
    };
    Ok(EventCheck {
        kind_f64: label(e64.kind),
        kind_ref: label(er.kind),
        time_error,
        time_bound: best_bound,
        position_error,
        velocity_error,
        position_bound,
        velocity_bound,
        ambiguous,
        in_model,
        flight_identity: None,
    })
}
