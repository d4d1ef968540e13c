//! The `f64` screen before Newton's method in MPFR: the shortest closed polygon through a
//! word's disks (a starting guess within about 10⁻¹⁵ of the cycle), refused when it is no
//! billiard orbit (a reflection through the disk, or a flight through another disk by more than
//! [`MARGIN`]). A word the screen refuses is reported as pruned by the screen, not by the
//! kernel: `proofs-notes/lattice-cycles.md` says what that does and does not prove.

use super::LatticeDisks;
use crate::verification::cycles::CycleTable;
use crate::verification::cycles::bisector_angles;
use crate::verification::cycles::minimise::{polygon_edges, shortest_polygon};

/// A polygon is refused only when it fails a condition by more than this (a near-grazing
/// candidate goes on to MPFR, whose certificate and kernel decide it).
pub const MARGIN: f64 = 1e-9;

/// Distance − 1 of the segment from `x` along the unit `u` for length `l` from the centre `c`.
fn gap(x: [f64; 2], u: [f64; 2], l: f64, c: [f64; 2]) -> f64 {
    let t = ((c[0] - x[0]) * u[0] + (c[1] - x[1]) * u[1]).clamp(0.0, l);
    (c[0] - x[0] - t * u[0]).hypot(c[1] - x[1] - t * u[1]) - 1.0
}

/// The contact angles of the shortest closed polygon through the disks `labels` (centres
/// `centres`, closing with the winding's displacement `shift`), or why it is no billiard orbit.
pub(super) fn screen(
    disks: &LatticeDisks,
    centres: &[[f64; 2]],
    shift: [f64; 2],
    labels: &[[i64; 2]],
    close: [i64; 2],
) -> Result<Vec<f64>, String> {
    let n = centres.len();
    let s0 = bisector_angles(centres, shift);
    let s = shortest_polygon(centres, shift, 1.0, s0)
        .ok_or("the length minimisation did not converge")?;
    let e = polygon_edges(centres, shift, 1.0, &s);
    for k in 0..n {
        let normal = [s[k].cos(), s[k].sin()];
        let (u_in, u_out) = (e[(k + n - 1) % n].0, e[k].0);
        let out = u_out[0] * normal[0] + u_out[1] * normal[1];
        let inward = u_in[0] * normal[0] + u_in[1] * normal[1];
        if out < -MARGIN || inward > MARGIN {
            return Err(format!(
                "the shortest polygon is not reflected at collision {k} (it passes through disk {})",
                disks.label(labels[k])
            ));
        }
    }
    for k in 0..n {
        let x = [centres[k][0] + s[k].cos(), centres[k][1] + s[k].sin()];
        let next = if k + 1 == n { close } else { labels[k + 1] };
        for j in disks.near(labels[k], e[k].1 + 1.0) {
            if j == labels[k] || j == next {
                continue;
            }
            let g = gap(x, e[k].0, e[k].1, disks.centre_f64(j));
            if g < -MARGIN {
                return Err(format!(
                    "flight {k} of the shortest polygon passes through disk {} (depth {:.1e})",
                    disks.label(j),
                    -g
                ));
            }
        }
    }
    Ok(s)
}
