//! The arc kernel on decoded states: the lattice stepper's degenerate starts (grazing,
//! near-surface, tangents, rim crossings, corners) flown on arcs in a field decoded from the
//! last two bytes, |B| from 2⁻²⁰ to 2²⁰ (cyclotron radii about 10⁻⁶ to 10⁶), either sign.
//!
//! After every event: MPFR at 53 bits took the same event to the same bits (the kernel decides
//! and moves with correctly rounded operations only, `proofs-notes/magnetic-arcs.md`); the `f64`
//! state is finite, its speed within the energy band after *every* event (an arc changes the
//! velocity on crossings too), outside every disk and inside every edge up to the post-event
//! bound; the cell moved across the edge on a crossing and the obstacle met is the one excluded;
//! and the state is still in the arc kernel's domain.
//! A pinned orbit (no event) ends the run.
//!
//! **Domain.** The arc kernel orders contacts by cross products of chords and reflects in them,
//! products of two coordinates: it is exact (and MPFR-53 ≡ `f64`, `proofs-notes/bit-for-bit.md`)
//! for states whose coordinates are 0 or at least [`NORMAL_FLOOR`] = 2⁻⁵⁰⁰ in magnitude, far from
//! the subnormals, where `f64` and MPFR round differently and a chord such as 2a/ω·Jn with
//! a = 5·10⁻³²⁴ loses its direction. Sampled states are never closer (probability 2⁻⁵⁰⁰); the
//! decoder's ulp-nudged axis velocities (5·10⁻³²⁴) are set to the axis exactly, itself a
//! degenerate case (motion along an edge). Events keep states in the domain: a coordinate is a
//! sum or difference of O(1) numbers, 0 or above 2⁻⁶⁰ — checked after every event.

use super::curved_walk::{Judge, cell_and_exclusions_after, unit_speed_after, walk};
use super::stepper::EventBounds;
use super::*;
use crate::kernel::field::ArcEvent;
use crate::verification::curved::{Curved, CurvedEvent};

/// The smallest nonzero magnitude of a state coordinate at which MPFR-53 and `f64` must agree
/// bit for bit: products with fields down to 2⁻²⁰ and with other coordinates stay far above the
/// subnormal range (2⁻¹⁰²²), where MPFR, which has none, rounds differently.
pub const NORMAL_FLOOR: f64 = f64::from_bits((1023 - 500) << 52); // 2⁻⁵⁰⁰

/// `true` if every coordinate of the state is 0 or at least [`NORMAL_FLOOR`] in magnitude.
pub fn in_domain(s: &LatticeState<f64>) -> bool {
    let f = &s.flight;
    [f.pos.x, f.pos.y, f.vel.x, f.vel.y]
        .iter()
        .all(|x| *x == 0.0 || x.abs() >= NORMAL_FLOOR)
}

/// The state with every coordinate below [`NORMAL_FLOOR`] set to 0 (a velocity then lies along
/// an axis exactly), and its exclusions made the arc kernel's: on an arc an excluded disk or edge
/// is the one the particle is *on* (`proofs-notes/magnetic-arcs.md`), while the decoder, written
/// for straight flights, also excludes the disk a particle moves away from at a distance; such an
/// exclusion is dropped (one within the post-event bound of its obstacle is kept).
pub(super) fn into_domain(cell: &ConvexCell<f64>, mut s: LatticeState<f64>) -> LatticeState<f64> {
    let f = &mut s.flight;
    for x in [&mut f.pos.x, &mut f.pos.y, &mut f.vel.x, &mut f.vel.y] {
        if x.abs() < NORMAL_FLOOR {
            *x = 0.0;
        }
    }
    if let Some(m) = f.excluded_disk {
        // On the disk: |p − c|² − r² within the rounding of a contact computed to u·extent,
        // 2r·u·extent, with a wide factor — relative to r (an absolute bound would keep the
        // exclusion of a particle half a radius off a disk of radius 10⁻⁷).
        let d = &cell.disks[m as usize];
        let near = POST_EVENT_U * U * d.radius() * (d.radius() + cell.extent());
        if (f.pos.sub(&d.centre).norm2() - d.radius2()).abs() > near {
            f.excluded_disk = None;
        }
    }
    let near = POST_EVENT_U * U * (1.0 + cell.extent());
    if let Some(k) = f.excluded_edge
        && cell.edge_distance(k as usize, &f.pos).abs() > near
    {
        f.excluded_edge = None;
    }
    s
}

/// Most events one input flies (the stepper's count, capped: an arc input costs more).
pub const MAX_ARC_STEPS: u32 = 256;

/// The field of an input: its last two bytes, k and m, give
/// B = ±(1 + m/256)·2^(k mod 41 − 20) (sign: the low bit of m).
pub fn decode_field(data: &[u8]) -> f64 {
    let n = data.len();
    let (k, m) = match n {
        0 => (20, 0),
        1 => (data[0], 0),
        _ => (data[n - 2], data[n - 1]),
    };
    let sign = if m & 1 == 1 { -1.0 } else { 1.0 };
    sign * (1.0 + f64::from(m) / 256.0) * 2f64.powi(i32::from(k % 41) - 20)
}

/// Flies a decoded lattice state on arcs (see the module documentation).
///
/// # Errors
/// A decoding failure or the first violation, with the state before the failing event.
pub fn arc_kernel(data: &[u8]) -> Result<OracleReport, OracleFailure> {
    let input = decode_scene(data)?;
    let (case, start) = input.start();
    let b = decode_field(data);
    let steps = input.steps.min(MAX_ARC_STEPS);
    match input.primitive.scene {
        SceneParams::Triangular { w } => fly(&triangular(w)?, case, &start, b, steps),
        SceneParams::Square { r } => fly(&square(r)?, case, &start, b, steps),
    }
}

/// Flies `start` of `scene` in the field `b` for up to `steps` events, checking every one.
///
/// # Errors
/// The first violation.
pub fn fly<S: Scene>(
    scene: &S,
    case: Option<PrimitiveCase>,
    start: &LatticeState<f64>,
    b: f64,
    steps: u32,
) -> Result<OracleReport, OracleFailure> {
    let label = format!("{} B={b:e}", scene.label());
    let lat = scene
        .lattice::<f64>(())
        .map_err(|e| OracleFailure::new(case, &label, None, e.to_string(), String::new()))?;
    let cell = lat.cell();
    let bounds = EventBounds::new(cell.clone());
    let band = arc_energy_band(&bounds, b);
    // Consecutive returns to the disk the particle is on (see `returns_after`).
    let mut hops = 0.0;
    let judge: &mut Judge<'_> = &mut |before, ev, after, rep| {
        let CurvedEvent::Arc(ev) = ev else {
            return Err(format!("not an arc's event: {:?}", ev.kind()));
        };
        let kappa = concentricity(cell, &before.flight, ev, b);
        unit_speed_after(&after.flight, ev.kind, band * kappa, rep)?;
        cell_and_exclusions_after(cell, before, ev.kind, after, rep)?;
        hops = returns_after(hops, &before.flight, ev, &after.flight);
        bounds.check_position_within(&after.flight, ev.kind, kappa * (1.0 + hops))
    };
    let motions = (&Curved::Arc(b), &Curved::Arc(Float::with_val(53, b)));
    let run = (case, label.as_str(), steps);
    walk(scene, &lat, run, start, motions, judge)
}

/// ||v|² − 1| ≤ `ARC_ENERGY_BAND_U`·u·(1 + extent/r)²·(1 + |B|·extent) after every arc event
/// (`proofs-notes/magnetic-arcs.md`). The speed error is 4(residual of the contact)/r² through
/// the reflection, as for a straight flight. On an arc the residual is the rounding of the
/// discriminant Δ = (V²r² − q²) + ωγ(q − ωγ/4) over M, whose terms are of size q² and |ω||d|³:
/// unlike a straight flight (|q| < r at a hit) an arc may meet a small disk with |q| ≫ r. A few
/// roundings each: residual ≲ 12u|d|²(1 + |ω||d|)/M, M ≈ 1 away from concentric circles, hence
/// the square of extent/r; 4·12 = 48 ≤ 64.
pub const ARC_ENERGY_BAND_U: f64 = 64.0;

/// The arc energy band of `cell` in the field `b`, in units of u.
pub fn arc_energy_band_of(cell: &ConvexCell<f64>, b: f64) -> f64 {
    let ratio = 1.0 + cell.extent() / cell.smallest_radius();
    ARC_ENERGY_BAND_U * ratio * ratio * (1.0 + b.abs() * cell.extent())
}

fn arc_energy_band(bounds: &EventBounds, b: f64) -> f64 {
    arc_energy_band_of(&bounds.cell, b)
}

/// The conditioning of a collision's contact found on the radical line, 1/min(1, M) with
/// M = |Jv + ωd|² the squared distance between the cyclotron centre and the disk centre times
/// ω²: there a rounding δ moves the contact across both circles by up to δ/M. The kernel takes
/// that form only where 4M ≥ V² (so this is at most 4/V²); closer to concentric it finds the
/// contact in the disk's frame, on the circle to a few u, and this is 1
/// (`proofs-notes/magnetic-arcs.md`). 1 for a crossing.
fn concentricity(cell: &ConvexCell<f64>, f: &Flight<f64>, ev: &ArcEvent<f64>, b: f64) -> f64 {
    let EventKind::Collision(m) = ev.kind else {
        return 1.0;
    };
    let d = f.pos.sub(&cell.disks[m as usize].centre);
    let (mx, my) = (b * d.x - f.vel.y, b * d.y + f.vel.x);
    let mm = mx * mx + my * my;
    if f.vel.norm2() - 4.0 * mm > 0.0 {
        return 1.0;
    }
    1.0 / mm.min(1.0)
}

/// The consecutive returns to the disk the particle is on, after `ev`: a return (a collision
/// with the disk it was on by identity) is found from the position as the other intersection of
/// the cyclotron circle, s = −2β/M, so it carries that position's distance from the disk and
/// adds its own rounding: along k such hops the post-event bound is k + 1 times one event's
/// (`proofs-notes/magnetic-arcs.md`; the fifth libFuzzer campaign: 255 hops shorter than an
/// ulp in a cusp, 257u inside). A collision from off the disk is found from the disk itself
/// (the count restarts), and so is every contact once the exclusion has lapsed.
fn returns_after(hops: f64, before: &Flight<f64>, ev: &ArcEvent<f64>, after: &Flight<f64>) -> f64 {
    match ev.kind {
        EventKind::Collision(m) if before.excluded_disk == Some(m) => hops + 1.0,
        EventKind::Crossing(_) if after.excluded_disk.is_some() => hops,
        _ => 0.0,
    }
}
