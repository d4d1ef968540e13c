//! Pruning decided by the kernel: each flight of a cycle meets its recorded disk first, at the
//! flight time Newton's map found, and no other disk before it.

use super::*;
use crate::kernel::ray_disk::ray_circle_centred;
use crate::verification::shadowing::segment_gap;

/// What the kernel says about the flights of a cycle.
pub(super) struct Contacts {
    /// Smallest distance − a of a flight from a disk other than its two ends.
    pub(super) min_clearance: f64,
    /// `Some`: the first flight the kernel refuses, and why.
    pub(super) blocked: Option<String>,
}

/// Runs every flight x_k + t v_k of the cycle `y` (flight times `tau` from the map) through the
/// kernel's ray–disk contact [`ray_circle_centred`] against each of the `count` disks but its
/// own: the recorded next disk must be met, at τ_k to 2^(40−P)(1 + τ_k)/cos φ, and no other disk
/// may be met at t ≤ τ_k.
pub(super) fn kernel_check(
    table: &Table,
    count: usize,
    y: &[OrbitPoint],
    tau: &[Float],
) -> Contacts {
    let n = y.len();
    let bits = table.bits();
    let r2 = table.radius().clone().square();
    let mut out = Contacts {
        min_clearance: f64::INFINITY,
        blocked: None,
    };
    for k in 0..n {
        let Ok((x0, v)) = table.phase(&y[k]) else {
            out.blocked = Some(format!("collision {k} is grazing"));
            return out;
        };
        let vv = v.norm2();
        let (here, next) = (y[k].disk[0] as usize, y[(k + 1) % n].disk[0] as usize);
        for j in (0..count).filter(|&j| j != here) {
            let c = table.centre([j as i64, 0]);
            let d = x0.sub(&c);
            let hit = ray_circle_centred(d.x, d.y, &v, &vv, &r2);
            if j == next {
                // The arrival's cos φ is the next departure's (a reflection keeps |sin φ|).
                let p1 = y[(k + 1) % n].p.to_f64();
                let cos_in = (1.0 - p1 * p1).max(0.0).sqrt();
                let tol = (40.0 - f64::from(bits)).exp2() * (1.0 + tau[k].to_f64()) / cos_in;
                match hit {
                    None => {
                        out.blocked =
                            Some(format!("the flight from collision {k} misses disk {j}"));
                        return out;
                    }
                    Some(t) if (t.clone() - &tau[k]).to_f64().abs() > tol => {
                        out.blocked = Some(format!(
                            "the flight from collision {k} meets disk {j} at t = {:.6e}, not at the map's {:.6e}",
                            t.to_f64(),
                            tau[k].to_f64()
                        ));
                        return out;
                    }
                    Some(_) => {}
                }
                continue;
            }
            if let Some(t) = hit.filter(|t| *t <= tau[k]) {
                out.blocked = Some(format!(
                    "the flight from collision {k} (disk {here} to disk {next}) passes through disk {j} at t = {:.6e} < {:.6e}",
                    t.to_f64(),
                    tau[k].to_f64()
                ));
                return out;
            }
            let gap = segment_gap(table, &x0, &v, &tau[k], &c).to_f64();
            out.min_clearance = out.min_clearance.min(gap);
        }
    }
    out
}
