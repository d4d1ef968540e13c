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

/// Runs every flight x_k + t v_k of the cycle `y` closing on the disk `close` (flight times
/// `tau` from the map) through the kernel's ray–disk contact [`ray_circle_centred`] against each
/// disk of `geometry` it can come near but its own: the recorded next disk must be met, at τ_k
/// to 2^(40−P)(1 + τ_k)/cos φ, and no other disk may be met at t ≤ τ_k.
pub(super) fn kernel_check<G: CycleTable>(
    table: &Table,
    geometry: &G,
    (y, close): (&[OrbitPoint], [i64; 2]),
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
        let here = y[k].disk;
        let next = if k + 1 == n { close } else { y[k + 1].disk };
        let reach = tau[k].to_f64() + 1.0;
        let near = geometry.near(here, reach);
        if !near.contains(&next) {
            out.blocked = Some(format!(
                "the flight from collision {k} cannot reach disk {}",
                geometry.label(next)
            ));
            return out;
        }
        for j in near.into_iter().filter(|&j| j != here) {
            let c = table.centre(j);
            let d = x0.sub(&c);
            let hit = ray_circle_centred(d.x, d.y, &v, &vv, &r2);
            if j == next {
                // The arrival's cos φ is the next departure's (a reflection keeps |sin φ|).
                let p1 = y[(k + 1) % n].p.to_f64();
                let cos_in = (1.0 - p1 * p1).max(0.0).sqrt();
                let tol = (40.0 - f64::from(bits)).exp2() * (1.0 + tau[k].to_f64()) / cos_in;
                match hit {
                    None => {
                        out.blocked = Some(format!(
                            "the flight from collision {k} misses disk {}",
                            geometry.label(j)
                        ));
                        return out;
                    }
                    Some(t) if (t.clone() - &tau[k]).to_f64().abs() > tol => {
                        out.blocked = Some(format!(
                            "the flight from collision {k} meets disk {} at t = {:.6e}, not at the map's {:.6e}",
                            geometry.label(j),
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
                    "the flight from collision {k} (disk {} to disk {}) passes through disk {} at t = {:.6e} < {:.6e}",
                    geometry.label(here),
                    geometry.label(next),
                    geometry.label(j),
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
