//! How far the flights of an orbit stay from the disks they do not hit: the straight flights'
//! clearance and the lattice's disks near a box ([`super::arc`] for arcs).

use super::*;

/// The lattice indices of the disks that may reach into the box [lo, hi] (f64 corners): every
/// (i, j) whose centre lies within r of it, with one row and column to spare.
pub(super) fn disks_near(table: &Table, lo: [f64; 2], hi: [f64; 2]) -> Vec<[i64; 2]> {
    let (a, beta, h, r) = (
        table.a.to_f64(),
        table.beta.to_f64(),
        table.h.to_f64(),
        table.r.to_f64(),
    );
    let (xmin, xmax, ymin, ymax) = (lo[0] - r, hi[0] + r, lo[1] - r, hi[1] + r);
    let (j0, j1) = ((ymin / h).floor() as i64 - 1, (ymax / h).ceil() as i64 + 1);
    let mut out = Vec::new();
    for j in j0..=j1 {
        let sh = beta * j as f64;
        let (i0, i1) = (
            (xmin / a - sh).floor() as i64 - 1,
            (xmax / a - sh).ceil() as i64 + 1,
        );
        out.extend((i0..=i1).map(|i| [i, j]));
    }
    out
}

/// Smallest clearance (distance − r) of the flights of `y` from every disk other than their
/// endpoints' disks, and the first flight that passes through one (k, disk, clearance).
pub(super) fn clearance(
    table: &Table,
    y: &[OrbitPoint],
    tau: &[Float],
) -> (f64, Option<(usize, [i64; 2], f64)>) {
    let mut min = f64::INFINITY;
    for k in 0..y.len() - 1 {
        let Ok((x0, v)) = table.phase(&y[k]) else {
            continue;
        };
        let x1 = x0.along(&tau[k], &v);
        let (p0, p1) = (x0.to_f64(), x1.to_f64());
        let lo = [p0[0].min(p1[0]), p0[1].min(p1[1])];
        let hi = [p0[0].max(p1[0]), p0[1].max(p1[1])];
        for d in disks_near(table, lo, hi) {
            if d == y[k].disk || d == y[k + 1].disk {
                continue;
            }
            let g = segment_gap(table, &x0, &v, &tau[k], &table.centre(d)).to_f64();
            if g <= 0.0 {
                return (g.min(min), Some((k, d, g)));
            }
            min = min.min(g);
        }
    }
    (min, None)
}

/// Distance − r of the flight x0 + u v, 0 ≤ u ≤ `tau` (|v| = 1), from the disk centred at `c`.
pub(crate) fn segment_gap(
    table: &Table,
    x0: &Vec2<Float>,
    v: &Vec2<Float>,
    tau: &Float,
    c: &Vec2<Float>,
) -> Float {
    let mut u = c.sub(x0).dot(v);
    if u.is_sign_negative() {
        u = Float::with_val(table.bits, 0);
    } else if u > *tau {
        u = tau.clone();
    }
    let q = x0.along(&u, v);
    c.sub(&q).norm2().sqrt() - &table.r
}
