//! The exact pinned and skipping shares of a [`FieldGeometry`] (`proofs-notes/magnetic-localized.md`).
//!
//! * **Skipping**, in closed form: by Fubini the centres z within X of a disk's centre c, each
//!   weighted by the share of its circle (radius ρ) inside the disk (radius r), have the measure
//!   of the intersection of the disk of radius X about c with the disk of radius r about a point
//!   ρ from c: [`lens`](X, r, ρ). So the centres in lo < |z − c| < hi weighted by the share of
//!   their circle outside the disk measure π(hi² − lo²) − lens(hi, r, ρ) + lens(lo, r, ρ).
//! * **Pinned**, by quadrature of the free length L(y) of the line at height y, the integral cut
//!   at every height where L is not smooth: where a boundary circle (radius ρ + r, and ρ − r where
//!   ρ > r, about a disk's images) is tangent to the line, and where two of them cross on the
//!   boundary of the covered set. Between two such heights L is analytic, with at most a
//!   square-root end, and [`integrate_smooth`] reaches rounding.

use std::f64::consts::PI;

use super::FieldGeometry;
use crate::theory::quadrature::integrate_smooth;

/// The relative accuracy asked of each piece of the pinned share's quadrature
/// ([`integrate_smooth`]: the test bounds the coarser rule's error, the finer sum returned is far
/// more accurate), with a floor of 10⁻³ of the cell's height on each piece's length; where the
/// circles are wider than the cell (ρ + r > a), relaxed by ((ρ + r)/a)^{3/2} above the rounding
/// of the free length's interval ends.
const PIECE_TOLERANCE: f64 = 1e-14;

/// Cut heights closer than this (relative to the cell's height) are one.
const SAME_HEIGHT: f64 = 1e-13;

/// The angle opposite the side `c` of the triangle with sides `a`, `b`, `c`, by Kahan's
/// cancellation-free formula ("Miscalculating area and angles of a needle-like triangle"): 0 or π
/// where rounding leaves no triangle.
pub(crate) fn triangle_angle(a: f64, b: f64, c: f64) -> f64 {
    let (a, b) = if a >= b { (a, b) } else { (b, a) };
    let mu = if b >= c { c - (a - b) } else { b - (a - c) };
    let num = ((a - b) + c) * mu;
    let den = (a + (b + c)) * ((a - c) + b);
    if num <= 0.0 {
        0.0
    } else if den <= 0.0 {
        PI
    } else {
        2.0 * (num / den).sqrt().atan()
    }
}

/// t − sin t without cancellation: its series below t = 1 (terms to t¹⁹/19!, the first left
/// out below 10⁻¹⁹ of the sum), directly above (where t − sin t ≥ t/6.3).
fn t_minus_sin(t: f64) -> f64 {
    if t >= 1.0 {
        return t - t.sin();
    }
    let (t2, mut term, mut sum) = (t * t, t * t * t / 6.0, 0.0);
    for k in 1..=9 {
        sum += term;
        let n = f64::from(2 * k + 2);
        term *= -t2 / (n * (n + 1.0));
    }
    sum
}

/// The area of the circular segment of a disk of radius `r` cut off by a chord seen under the
/// half-angle `alpha` (0 ≤ α ≤ π) from its centre: r²(2α − sin 2α)/2.
fn segment(r: f64, alpha: f64) -> f64 {
    r * r * t_minus_sin(2.0 * alpha) / 2.0
}

/// The area of the intersection of two disks of radii `r1`, `r2` whose centres are `d` apart:
/// 0 if they are disjoint, π min(r₁, r₂)² if one contains the other, else the sum of the two
/// circular segments, their half-angles the angles at the centres of the triangle (d, r₁, r₂)
/// from Kahan's formula (`triangle_angle`) — no cancellation near tangency (both angles
/// small: the segments by series) or near containment (one angle near π).
pub fn lens(r1: f64, r2: f64, d: f64) -> f64 {
    if d >= r1 + r2 {
        return 0.0;
    }
    if d <= (r1 - r2).abs() {
        return PI * r1.min(r2).powi(2);
    }
    segment(r1, triangle_angle(d, r1, r2)) + segment(r2, triangle_angle(d, r2, r1))
}

impl FieldGeometry {
    /// The exact share of phase space in skipping orbits, in closed form (module docs):
    /// Σ_m [(πhi² − lens(hi, r, ρ)) − (πlo² − lens(lo, r, ρ))] / |Q| over each disk's range
    /// ([`FieldGeometry::skipping_range`]). At hi = ρ + r the disk of radius hi contains the
    /// other, and the first term is π((ρ + r)² − r²) = πρ(ρ + 2r); at lo = |ρ − r| the disks are
    /// internally (ρ < r: πlo² − lens = 0) or externally (ρ ≥ r: lens = 0) tangent.
    pub fn skipping_fraction(&self) -> f64 {
        let rho = self.rho;
        let mut total = 0.0;
        for (m, d) in self.lattice.disks.iter().enumerate() {
            let (lo, hi) = self.skipping_range(m);
            if hi <= lo {
                continue;
            }
            let r = d.radius;
            let upper = if hi >= rho + r {
                PI * rho * (rho + 2.0 * r)
            } else {
                PI * hi * hi - lens(hi, r, rho)
            };
            let lower = if rho < r { 0.0 } else { PI * lo * lo };
            total += upper - lower;
        }
        total / self.lattice.free_area()
    }

    /// The exact share of phase space in pinned orbits.
    pub fn pinned_fraction(&self) -> f64 {
        *self.pinned.get_or_init(|| self.integrate_pinned())
    }

    /// The exact share of phase space in pinned orbits, integrated piece by piece between the
    /// heights where the free length is not smooth ([`FieldGeometry::kink_heights`]).
    fn integrate_pinned(&self) -> f64 {
        let l = &self.lattice;
        let cuts = self.kink_heights();
        let free = |y: f64| self.free_length(y);
        // The free length's rounding grows with the circles (its interval ends are ~ρ + r from
        // their rows' points) and their number (~(ρ + r)/h rows): the test stays above it.
        let widest = self.rho + l.disks.iter().map(|d| d.radius).fold(0.0, f64::max);
        let rel = PIECE_TOLERANCE * (widest / l.a).max(1.0).powf(1.5);
        let area: f64 = cuts
            .windows(2)
            .map(|p| integrate_smooth(&free, p[0], p[1], l.a, (rel, 1e-3 * l.h)))
            .sum();
        area / l.free_area()
    }

    /// The boundary circles of the covered set: (disk, radius) for the radius ρ + r of each disk
    /// and ρ − r where ρ > r.
    fn boundary_circles(&self) -> Vec<(usize, f64)> {
        let mut circles = Vec::new();
        for (m, d) in self.lattice.disks.iter().enumerate() {
            circles.push((m, self.rho + d.radius));
            if self.rho > d.radius {
                circles.push((m, self.rho - d.radius));
            }
        }
        circles
    }

    /// The heights in [0, h] (sorted, 0 and h included, those closer than [`SAME_HEIGHT`]·h
    /// merged) where the free length may not be smooth: where a boundary circle is tangent to
    /// the line, and where two boundary circles cross at a point not inside another annulus
    /// (within a margin of 10⁻⁹ of the widest circle: a point kept needlessly costs a cut, never
    /// accuracy).
    pub(super) fn kink_heights(&self) -> Vec<f64> {
        let l = &self.lattice;
        let circles = self.boundary_circles();
        let mut cuts = vec![0.0, l.h];
        let mut push = |y: f64| {
            let y = y.rem_euclid(l.h);
            if y > 0.0 && y < l.h {
                cuts.push(y);
            }
        };
        for &(m, radius) in &circles {
            let c = l.disks[m].centre;
            push(c[1] + radius);
            push(c[1] - radius);
        }
        let widest = circles.iter().map(|c| c.1).fold(0.0, f64::max);
        let margin = 1e-9 * widest;
        for (n, &(m, r1)) in circles.iter().enumerate() {
            for &(k, r2) in &circles[n..] {
                let (p, q) = (l.disks[m].centre, l.disks[k].centre);
                let offset = (p[0] - q[0], p[1] - q[1]);
                l.points_near(offset, r1 + r2, |i, j| {
                    // Each pair of one circle with its own images once.
                    if (m, r1) == (k, r2) && (j < 0.0 || j == 0.0 && i <= 0.0) {
                        return;
                    }
                    let (x, y) = l.point(i, j);
                    let (dx, dy) = (q[0] + x - p[0], q[1] + y - p[1]);
                    let dist = dx.hypot(dy);
                    if dist >= r1 + r2 || dist <= (r1 - r2).abs() {
                        return;
                    }
                    let (towards, half) = (dy.atan2(dx), triangle_angle(dist, r1, r2));
                    for angle in [towards - half, towards + half] {
                        let (zx, zy) = (p[0] + r1 * angle.cos(), p[1] + r1 * angle.sin());
                        if !self.inside_an_annulus(zx, zy, margin) {
                            push(zy);
                        }
                    }
                });
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|y, prev| *y - *prev <= SAME_HEIGHT * l.h);
        if cuts.last() != Some(&l.h) {
            // The last cut merged into one just below h: h itself ends the period.
            *cuts.last_mut().expect("0 and h are cuts") = l.h;
        }
        cuts
    }

    /// `true` if (zx, zy) is inside some disk's annulus ρ − r < |z − c| < ρ + r by more than
    /// `margin`.
    fn inside_an_annulus(&self, zx: f64, zy: f64, margin: f64) -> bool {
        self.lattice.disks.iter().any(|d| {
            let (outer, inner) = (self.rho + d.radius - margin, self.rho - d.radius + margin);
            outer > 0.0 && self.in_annuli(zx - d.centre[0], zy - d.centre[1], outer, inner)
        })
    }

    /// The free length, over one period a of x, of the line at height y left by the annuli
    /// ρ − r ≤ |z − c| ≤ ρ + r of every disk (the pinned centres on that line).
    pub(super) fn free_length(&self, y: f64) -> f64 {
        let l = &self.lattice;
        let mut covered: Vec<(f64, f64)> = Vec::new();
        for d in &l.disks {
            let (outer, inner) = (self.rho + d.radius, self.rho - d.radius);
            for (_, shift, xo, xi) in self.rows(y - d.centre[1], outer, inner) {
                let shift = d.centre[0] + shift;
                let pieces = if xi > 0.0 {
                    vec![(shift - xo, shift - xi), (shift + xi, shift + xo)]
                } else {
                    vec![(shift - xo, shift + xo)]
                };
                for (lo, hi) in pieces {
                    if hi - lo >= l.a {
                        return 0.0;
                    }
                    let start = lo.rem_euclid(l.a);
                    let end = start + (hi - lo);
                    if end > l.a {
                        covered.push((start, l.a));
                        covered.push((0.0, end - l.a));
                    } else {
                        covered.push((start, end));
                    }
                }
            }
        }
        covered.sort_by(|p, q| p.0.total_cmp(&q.0));
        let (mut total, mut reach) = (0.0, 0.0f64);
        for (lo, hi) in covered {
            let lo = lo.max(reach);
            if hi > lo {
                total += hi - lo;
            }
            reach = reach.max(hi);
        }
        (l.a - total).max(0.0)
    }
}
