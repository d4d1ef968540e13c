//! The tangent map of an arc event (`proofs-notes/tangent-map.md`, "In a magnetic field"): the
//! linearised flow of a particle turning at the angular velocity ω between collisions, carried
//! through crossings and specular collisions with the field's acceleration ωJv on both sides.

use nalgebra::{Vector2, Vector4};

use crate::kernel::cell::ConvexCell;
use crate::kernel::field::ArcEvent;
use crate::kernel::flight::{EventKind, Flight};

/// J(x, y) = (−y, x): the quarter turn in the sense of a positive field.
fn quarter(v: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-v[1], v[0])
}

/// The free flight of the tangent vector (δq, δv) for the time `t` in the field `w`:
/// δv ← R(ωt)δv, δq ← δq + (sin ωt/ω)δv + ((1 − cos ωt)/ω)Jδv, with 1 − cos φ = 2 sin²(φ/2)
/// (no cancellation for small φ).
pub fn arc_flight(t: &mut Vector4<f64>, time: f64, w: f64) {
    let phi = w * time;
    let (s, c) = phi.sin_cos();
    let half = (0.5 * phi).sin();
    let dv = Vector2::new(t[2], t[3]);
    let jdv = quarter(&dv);
    // sin(φ)/ω and (1 − cos φ)/ω, both → t as ω → 0 (their ratios are taken in the limit).
    let (a, b) = if phi == 0.0 {
        (time, 0.0)
    } else {
        (s / w, 2.0 * half * half / w)
    };
    let dq = Vector2::new(t[0], t[1]) + dv * a + jdv * b;
    let dv = dv * c + jdv * s;
    *t = Vector4::new(dq[0], dq[1], dv[0], dv[1]);
}

/// Applies the linearisation of the arc event `ev` of the flight `f` (flight time `time`, field
/// `w`) in `cell` to the tangent vector (δq, δv): the free flight ([`arc_flight`]), then a
/// crossing (a point reflection negates the vector, a translation leaves it) or a collision with
/// the disk of radius r: with n the outward normal at the contact, v⁻ the arrival velocity and
/// v⁺ = Rv⁻ its reflection, δt = −(n·δq)/(n·v⁻), δn = (δq + v⁻δt)/r, and
/// δq ← δq − 2(n·δq)n, δv ← Rδv − 2ωδt·Jv⁺ − 2(v⁻·δn)n − 2(v⁻·n)δn (the field's acceleration
/// before and after the bounce, RJv⁻ − Jv⁺ = −2Jv⁺).
pub fn arc_tangent_step(
    t: &mut Vector4<f64>,
    f: &Flight<f64>,
    ev: &ArcEvent<f64>,
    time: f64,
    cell: &ConvexCell<f64>,
    w: f64,
) {
    arc_flight(t, time, w);
    match ev.kind {
        EventKind::Crossing(k) => {
            if cell.edges[k as usize].flips() {
                *t = -*t;
            }
        }
        EventKind::Collision(m) => {
            let disk = &cell.disks[m as usize];
            let x = Vector2::new(f.pos.x + ev.chord.x, f.pos.y + ev.chord.y);
            let c = Vector2::new(disk.centre.x, disk.centre.y);
            let n = (x - c).normalize();
            let v = Vector2::new(ev.velocity.x, ev.velocity.y);
            let (dq, dv) = (Vector2::new(t[0], t[1]), Vector2::new(t[2], t[3]));
            let vn = v.dot(&n);
            let dt = -n.dot(&dq) / vn;
            let dn = (dq + v * dt) / *disk.radius();
            let vplus = v - n * (2.0 * vn);
            let dq2 = dq - n * (2.0 * n.dot(&dq));
            let dv2 = dv
                - n * (2.0 * dv.dot(&n))
                - quarter(&vplus) * (2.0 * w * dt)
                - n * (2.0 * v.dot(&dn))
                - dn * (2.0 * vn);
            *t = Vector4::new(dq2[0], dq2[1], dv2[0], dv2[1]);
        }
    }
}
