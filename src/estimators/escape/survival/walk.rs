//! One particle on an open table: its start, drawn from the billiard map's invariant measure
//! restricted to the directions that hit another disk, and its flights to escape, with the
//! time and the unstable expansion at each collision.
//!
//! The start: a boundary point uniform in arc length over all disks and an outgoing direction
//! with sin φ (φ from the outward normal) uniform on the set that hits another disk — the
//! Liouville measure ds d(sin φ) restricted to that set, drawn exactly by rejection: the set is
//! the union of one cone per other disk (its two tangent directions give the ends of an
//! interval of sin φ, clipped to the outgoing half-plane, without trigonometry). The boundary
//! is cut into arcs, each with a bound of the set's length at its points; an arc is drawn by
//! its length times its bound, a point on it uniformly, and the point kept with probability
//! (Σ interval lengths)/bound; a sin φ is drawn from the intervals by length and kept with
//! probability 1/(number of intervals holding it).
//!
//! The expansion: the unstable wavefront's curvature B (zero at the start: a plane front)
//! maps over a flight of length τ to B/(1 + τB), and at a collision on a disk of radius r at
//! incidence φ to B + 2/(r cos φ); the front's length grows by the factor 1 + τB over the
//! flight, so ln Λ is the sum of ln(1 + τB) over the flights.

use rand::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::kernel::flight::Flight;
use crate::kernel::open::OpenDisks;
use crate::kernel::vec2::Vec2;

/// Arcs per disk of the sampler's envelope.
const BINS_PER_DISK: usize = 1024;

/// One arc of a disk's boundary with a bound on the total length of the sin φ intervals at
/// any of its points.
#[derive(Debug, Clone, Copy)]
struct Arc {
    disk: usize,
    /// cos and sin of the arc's first angle.
    start: (f64, f64),
    width: f64,
    bound: f64,
}

/// The start sampler of one open table (f64): the boundary cut into arcs, each with an upper
/// bound of the hitting set's length in sin φ, drawn by arc length times bound and kept with
/// probability (length at the point)/bound — uniform on the hitting set, with few refusals.
pub struct Starts {
    arcs: Vec<Arc>,
    /// Walker's alias table of the arcs' weights r·width·bound: arc k is kept with probability
    /// `keep[k]`, else its alias is taken.
    keep: Vec<f64>,
    alias: Vec<usize>,
}

impl Starts {
    /// The sampler of `table`.
    pub fn new(table: &OpenDisks<f64>) -> Self {
        let d = &table.disks;
        let width = std::f64::consts::TAU / BINS_PER_DISK as f64;
        let mut arcs = Vec::with_capacity(d.len() * BINS_PER_DISK);
        for i in 0..d.len() {
            for b in 0..BINS_PER_DISK {
                let from = b as f64 * width;
                let bound = (0..d.len())
                    .filter(|&j| j != i)
                    .map(|j| arc_bound(table, i, j, (from, from + width)))
                    .sum();
                let (sin, cos) = from.sin_cos();
                arcs.push(Arc {
                    disk: i,
                    start: (cos, sin),
                    width,
                    bound,
                });
            }
        }
        let weights: Vec<f64> = (arcs.iter())
            .map(|a| d[a.disk].radius() * a.width * a.bound)
            .collect();
        let (keep, alias) = alias_table(&weights);
        Starts { arcs, keep, alias }
    }

    /// One start on `table`: a flight leaving a disk's boundary (that disk excluded) in a
    /// direction that hits another disk.
    pub fn draw(&self, table: &OpenDisks<f64>, rng: &mut Xoshiro256PlusPlus) -> Flight<f64> {
        let mut cones = Vec::with_capacity(table.disks.len());
        loop {
            let u = rng.random::<f64>() * self.keep.len() as f64;
            let k = (u as usize).min(self.keep.len() - 1);
            let k = if u - k as f64 <= self.keep[k] {
                k
            } else {
                self.alias[k]
            };
            let arc = self.arcs[k];
            let (c, s) = turn(arc.width * rng.random::<f64>());
            let (cos, sin) = (
                arc.start.0 * c - arc.start.1 * s,
                arc.start.1 * c + arc.start.0 * s,
            );
            let n = Vec2::new(cos, sin);
            let i = arc.disk;
            let disk = &table.disks[i];
            let x = Vec2::new(
                disk.centre.x + disk.radius() * cos,
                disk.centre.y + disk.radius() * sin,
            );
            cones.clear();
            for (j, other) in table.disks.iter().enumerate() {
                if j != i
                    && let Some(c) = cone(&x, &n, &other.centre, *other.radius())
                {
                    cones.push(c);
                }
            }
            let total: f64 = cones.iter().map(|c| c.1 - c.0).sum();
            let mut pick = rng.random::<f64>() * arc.bound;
            if pick >= total {
                continue;
            }
            let mut p = f64::NAN;
            for c in &cones {
                if pick < c.1 - c.0 {
                    p = c.0 + pick;
                    break;
                }
                pick -= c.1 - c.0;
            }
            let holding = cones.iter().filter(|c| c.0 <= p && p < c.1).count().max(1);
            if holding > 1 && rng.random::<f64>() * holding as f64 >= 1.0 {
                continue;
            }
            let t = Vec2::new(-sin, cos);
            let c = (1.0 - p * p).sqrt();
            let mut f = Flight::new(x, Vec2::new(c * n.x + p * t.x, c * n.y + p * t.y));
            f.excluded_disk = Some(i as u8);
            return f;
        }
    }
}

/// (cos h, sin h) for 0 ≤ h ≤ 2π/[`BINS_PER_DISK`] by their Taylor polynomials (the first
/// terms left out are below 10⁻²⁰): the turn within an arc, without a library call.
fn turn(h: f64) -> (f64, f64) {
    let h2 = h * h;
    let cos = 1.0 - h2 / 2.0 * (1.0 - h2 / 12.0 * (1.0 - h2 / 30.0));
    let sin = h * (1.0 - h2 / 6.0 * (1.0 - h2 / 20.0 * (1.0 - h2 / 42.0)));
    (cos, sin)
}

/// Walker's alias table of `weights` (Vose's construction): index k drawn uniformly is kept
/// with probability keep[k], else alias[k] is taken; the result is k with probability
/// ∝ weights[k].
fn alias_table(weights: &[f64]) -> (Vec<f64>, Vec<usize>) {
    let n = weights.len();
    let total: f64 = weights.iter().sum();
    let mut keep: Vec<f64> = weights.iter().map(|w| w * n as f64 / total).collect();
    let mut alias: Vec<usize> = (0..n).collect();
    let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&k| keep[k] < 1.0);
    while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
        alias[s] = l;
        keep[l] -= 1.0 - keep[s];
        if keep[l] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    for k in large.into_iter().chain(small) {
        keep[k] = 1.0;
    }
    (keep, alias)
}

/// A bound on the length in sin φ of the directions from the arc `(from, to)` of disk `i` that
/// hit disk `j`. Seen from a point x at distance D from c_j, under the angle ψ from the normal
/// n, the interval is 2 cos ψ sin δ long (sin δ = r_j/D), and clipped by the tangent line
/// (ψ + δ > π/2 by β < 2δ) 1 − cos β ≤ 2 sin²δ: at most 2 sin δ max(cos ψ, sin δ); with
/// d·n = D cos ψ ≤
/// max (c_j − c_i)·n(θ) − r_i on the arc and D ≥ D_min both are bounded on the whole arc (0 where
/// disk j lies behind every tangent line of the arc). A relative margin covers the rounding.
fn arc_bound(table: &OpenDisks<f64>, i: usize, j: usize, (from, to): (f64, f64)) -> f64 {
    let (a, b) = (&table.disks[i], &table.disks[j]);
    let v = b.centre.sub(&a.centre);
    let dist = v.norm2().sqrt();
    let towards = v.y.atan2(v.x).rem_euclid(std::f64::consts::TAU);
    let reach = |th: f64| v.x * th.cos() + v.y * th.sin();
    let most = if (from..=to).contains(&towards) {
        dist
    } else {
        reach(from).max(reach(to))
    };
    let (ri, rj) = (*a.radius(), *b.radius());
    let slack = 1e-9 * (dist + ri + rj);
    if most - ri < -rj - slack {
        return 0.0;
    }
    let d_min = ((dist * dist + ri * ri - 2.0 * ri * most).max(0.0).sqrt() - slack).max(0.0);
    let sin_delta = (rj / d_min).min(1.0);
    let facing = ((most - ri + slack).max(0.0) / d_min).min(1.0);
    2.0 * sin_delta * facing.max(sin_delta) * (1.0 + 1e-9)
}

/// The interval [lo, hi) of sin φ (φ from the outward normal `n` at `x`, counterclockwise)
/// of the outgoing directions that hit the disk of centre `c` and radius `r`, or `None` if the
/// disk lies wholly behind the tangent line at `x`.
fn cone(x: &Vec2<f64>, n: &Vec2<f64>, c: &Vec2<f64>, r: f64) -> Option<(f64, f64)> {
    let d = c.sub(x);
    let dist = d.norm2().sqrt();
    let (s, co) = (r / dist, (1.0 - (r / dist).powi(2)).sqrt());
    let u = Vec2::new(d.x / dist, d.y / dist);
    // The tangent directions u± = cos δ û ± sin δ û⊥ (û⊥ = û turned by +90°).
    let plus = Vec2::new(co * u.x - s * u.y, co * u.y + s * u.x);
    let minus = Vec2::new(co * u.x + s * u.y, co * u.y - s * u.x);
    let t = Vec2::new(-n.y, n.x);
    let (front_plus, front_minus) = (plus.dot(n) >= 0.0, minus.dot(n) >= 0.0);
    if !front_plus && !front_minus {
        return None;
    }
    let lo = if front_minus { minus.dot(&t) } else { -1.0 };
    let hi = if front_plus { plus.dot(&t) } else { 1.0 };
    (lo < hi).then_some((lo, hi))
}

/// What a particle's flights give at each collision k = 1, 2, … up to a cap: the time τ_k of
/// the collision and ln Λ_k, the log of the unstable expansion over the flights before it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Collision {
    /// Time since the start (unit speed: the path length).
    pub time: f64,
    /// ln Λ over the flights so far.
    pub ln_expansion: f64,
}

/// Follows `flight` on `table` until it escapes or has made `cap` collisions, calling
/// `at(k, collision)` at each collision k = 1 … ; returns the number of collisions.
pub fn follow(
    table: &OpenDisks<f64>,
    mut flight: Flight<f64>,
    cap: usize,
    mut at: impl FnMut(usize, Collision),
) -> usize {
    let (mut time, mut ln, mut b) = (0.0f64, 0.0f64, 0.0f64);
    for k in 1..=cap {
        let Some((j, t)) = table.next_collision(&flight) else {
            return k - 1;
        };
        table.collide(&mut flight, j, &t);
        time += t;
        ln += (t * b).ln_1p();
        let disk = &table.disks[j as usize];
        // After the reflection v·(x − c) = r cos φ > 0.
        let cos_r = flight.vel.dot(&flight.pos.sub(&disk.centre));
        b = b / (1.0 + t * b) + 2.0 * disk.radius() / cos_r;
        at(
            k,
            Collision {
                time,
                ln_expansion: ln,
            },
        );
    }
    cap
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::open::OpenSpec;
    use rand::SeedableRng;

    /// Every start leaves its disk outwards and hits another disk (up to a rounding-thin set
    /// at the cones' edges).
    #[test]
    fn starts_hit_another_disk_and_leave_outwards() {
        let table = OpenSpec::repeller("6", "1").unwrap().at::<f64>(());
        let s = Starts::new(&table);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        let mut misses = 0;
        for _ in 0..20_000 {
            let f = s.draw(&table, &mut rng);
            let i = f.excluded_disk.unwrap() as usize;
            assert!(f.vel.dot(&f.pos.sub(&table.disks[i].centre)) > 0.0);
            misses += usize::from(table.next_collision(&f).is_none());
        }
        assert!(misses <= 2, "{misses}");
    }

    /// The two-disk orbit (R = 6, a = 1: flights of τ = 4 at normal incidence): the front's
    /// curvature tends to the fixed point B* = 1 + √6/2 of B ↦ B/(1 + 4B) + 2, and ln Λ per
    /// flight to ln(1 + 4B*) = ln(5 + 2√6), the two-disk cycle's expanding eigenvalue per
    /// flight.
    #[test]
    fn the_two_disk_orbit_expands_by_its_closed_form() {
        let table = OpenSpec::repeller("6", "1").unwrap().at::<f64>(());
        let mut f = Flight::new(Vec2::new(1.0, 0.0), Vec2::new(1.0, 0.0));
        f.excluded_disk = Some(0);
        let mut last = Vec::new();
        let n = follow(&table, f, 40, |_, c| last.push(c));
        assert_eq!(n, 40);
        let per = last[39].ln_expansion - last[38].ln_expansion;
        assert!(
            (per - (5.0 + 2.0 * 6f64.sqrt()).ln()).abs() < 1e-12,
            "{per}"
        );
        assert_eq!(last[39].time, 160.0);
    }
}
