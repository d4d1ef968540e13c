//! A certified free time for each candidate at a flight's start, without a jet: the tube about
//! the straight line (`proofs-notes/thermostat-flight.md`, "The screen").
//!
//! Along the exact flight |v̇| = ε|sin θ| ≤ ε, so |v(t) − v̂₀| ≤ εt and the flight stays in the
//! tube |X(t) − t·v̂₀| ≤ εt²/2 about the straight line of its start direction v̂₀ = v₀/|v₀|. A disk
//! whose distance from the straight segment of length T exceeds r + εT²/2, or an edge whose
//! signed distance along it stays above εT²/2, has no contact before T. On the obstacle by
//! identity the tube gives more: a flight leaving a disk of radius ρ cannot return to it before
//! (1 − ρε)/ε (F = 2d·X + |X|² ≥ t²(1 − ρε − εt) when d·v̂₀ > 0), nor to the edge it entered by
//! before 2n·v̂₀/ε.
//!
//! The march ([`super::search`]) starts each candidate with this time as its certified-free time,
//! so that a candidate the flight cannot reach before its event needs no jet and no certificate
//! at all; where the tube is too wide the time is 0 and the march certifies the candidate from
//! its jet at the start, as before. Every margin is explicit: the inputs' rounding to `f64`
//! (values of every precision are rounded to `f64` here, so the time is the same at every
//! precision down to that rounding, and bit for bit in `f64` and MPFR-53), the start's speed off
//! 1, and the rounding of the test itself. The proposed time is a free choice; the test of it is
//! the certificate.

use crate::kernel::cell::ConvexCell;
use crate::kernel::flight::{EventKind, Flight};
use crate::numbers::real::Real;

/// 2⁻⁵³: the rounding of each `f64` operation and of each input's conversion to `f64`.
const U: f64 = f64::EPSILON / 2.0;

/// The tube's half-width at the longer of the two times tried, εT²/2 = 1/16 (T ≤ the exit bound).
const WIDTH: f64 = 1.0 / 16.0;

/// The start of a flight in `f64` — position, velocity, the field's strength ε rounded up, and
/// k ≥ ||v₀| − 1| + 16u, the slope the start's speed and rounding add to the tube — and the two
/// times tried, the longer where the tube's width is [`WIDTH`] (at most the exit bound) and a
/// quarter of it.
pub(super) struct Tube {
    p: [f64; 2],
    v: [f64; 2],
    vv: f64,
    eps: f64,
    k: f64,
    times: [f64; 2],
}

impl Tube {
    /// The tube of the flight `f` under a field of strength `strength`, up to `exit`.
    pub fn new<T: Real>(f: &Flight<T>, strength: &T, exit: &T) -> Tube {
        let (p, v) = (
            [f.pos.x.to_f64(), f.pos.y.to_f64()],
            [f.vel.x.to_f64(), f.vel.y.to_f64()],
        );
        let vv = v[0] * v[0] + v[1] * v[1];
        let eps = strength.to_f64() * (1.0 + 4.0 * U);
        let long = (2.0 * WIDTH / eps).sqrt().min(exit.to_f64());
        Tube {
            p,
            v,
            vv,
            eps,
            k: (vv - 1.0).abs() + 16.0 * U,
            times: [long, long * 0.25],
        }
    }

    /// The tube's half-width at the time `t` (beyond the straight point t·v₀).
    fn width(&self, t: f64) -> f64 {
        (0.5 * self.eps * t * t + self.k * t) * (1.0 + 8.0 * U)
    }

    /// The first of the two times at which `clear` certifies the candidate free, else 0.
    fn first(&self, clear: impl Fn(f64) -> bool) -> f64 {
        let t = self.times.into_iter().find(|&t| t > 0.0 && clear(t));
        t.unwrap_or(0.0)
    }

    /// A time T ≥ 0 before which the exact flight `f` (this tube's) certainly has no contact with
    /// the candidate `kind` of `cell` (0 where the tube cannot say).
    pub fn free_time<T: Real>(&self, cell: &ConvexCell<T>, f: &Flight<T>, kind: EventKind) -> f64 {
        match kind {
            EventKind::Collision(m) => {
                let disk = &cell.disks[m as usize];
                let c = [disk.centre.x.to_f64(), disk.centre.y.to_f64()];
                let r = disk.radius().to_f64();
                if f.excluded_disk == Some(m) {
                    self.disk_left(c, r)
                } else {
                    self.disk_free(c, r)
                }
            }
            EventKind::Crossing(k) => {
                let e = &cell.edges[k as usize];
                let n = [e.normal.x.to_f64(), e.normal.y.to_f64()];
                self.edge_free(n, e.offset.to_f64(), f.excluded_edge == Some(k))
            }
        }
    }

    /// The offset d = p − c in `f64` and a bound on its error against the exact offset of the
    /// values (the conversions and the subtraction).
    fn offset(&self, c: [f64; 2], r: f64) -> ([f64; 2], f64) {
        let p = self.p;
        let d = [p[0] - c[0], p[1] - c[1]];
        let slack = 8.0 * U * (p[0].abs() + p[1].abs() + c[0].abs() + c[1].abs() + r);
        (d, slack)
    }

    /// A disk the flight is not on: the straight segment [0, t]·v₀ from the offset d stays
    /// farther than r + the tube's width at t from the centre — its smallest squared distance
    /// (at its start, its end or the closest approach, |d × v₀|²/|v₀|²), less its rounding,
    /// against that radius's square rounded up. No square root, no division.
    fn disk_free(&self, c: [f64; 2], r: f64) -> f64 {
        let (d, slack) = self.offset(c, r);
        let (v, vv) = (self.v, self.vv);
        let b = d[0] * v[0] + d[1] * v[1];
        let q2 = d[0] * d[0] + d[1] * d[1];
        let cross = d[0] * v[1] - d[1] * v[0];
        self.first(|t| {
            let reach = r + slack + self.width(t);
            let reach2 = reach * reach * (1.0 + 8.0 * U);
            let rounding = 16.0 * U * (q2 + 2.0 * b.abs() * t + vv * t * t);
            if b >= 0.0 {
                q2 - rounding > reach2
            } else if -b >= vv * t {
                q2 + t * (2.0 * b + vv * t) - rounding > reach2
            } else {
                // |d × v₀|² > reach²·|v₀|², the rounding scaled by |v₀|² ≤ 2.
                cross * cross - 2.0 * rounding > reach2 * vv * (1.0 + 4.0 * U)
            }
        })
    }

    /// The disk the flight leaves (on it by identity): with d·v̂₀ > 0 for certain, no return
    /// before (1 − ρε)/ε for ρ ≥ |d|, that is while ε(t + ρ) < 1 — tested as ρ² < (1/ε − t)²
    /// with ρ² ≥ |d|² (the identity's own offset is the position on the circle).
    fn disk_left(&self, c: [f64; 2], r: f64) -> f64 {
        let (d, slack) = self.offset(c, r);
        let (v, vv) = (self.v, self.vv);
        let b = d[0] * v[0] + d[1] * v[1];
        let q2 = d[0] * d[0] + d[1] * d[1];
        // √q2 ≤ (1 + q2)/2: a bound on |d| for the margins, without a square root.
        let rho = (1.0 + q2) * 0.5 * (1.0 + 8.0 * U) + slack;
        let leaving = b - 8.0 * U * rho * (1.0 + vv) - slack * (1.0 + vv) - rho * self.k;
        if leaving.is_nan() || leaving <= 0.0 {
            return 0.0;
        }
        let rho2 = (q2 * (1.0 + 8.0 * U)).sqrt() + slack;
        let inverse = 1.0 / self.eps * (1.0 - 4.0 * U);
        self.first(|t| {
            let room = (inverse - t) * (1.0 - 4.0 * U) - rho2;
            room > 0.0
        })
    }

    /// An edge: the signed distance σ + t·n·v₀ less the tube's width, concave in t, is positive
    /// at both ends of [0, t] (on the edge by identity, σ = 0 and the slope n·v₀ above the
    /// width's εt/2).
    fn edge_free(&self, n: [f64; 2], o: f64, identity: bool) -> f64 {
        let (p, v) = (self.p, self.v);
        let beta = n[0] * v[0] + n[1] * v[1];
        // |n| ≤ 1 + 4u: its excess widens the tube, within the factors below.
        let slope = beta - 4.0 * U * (beta.abs() + 1.0) - self.k * (1.0 + 4.0 * U);
        let sigma = if identity {
            0.0
        } else {
            let s = n[0] * p[0] + n[1] * p[1] - o;
            s - 16.0 * U * (p[0].abs() + p[1].abs() + o.abs() + 1.0)
        };
        if !(identity || sigma > 0.0) || (identity && (slope.is_nan() || slope <= 0.0)) {
            return 0.0;
        }
        let eps = self.eps * (1.0 + 8.0 * U);
        self.first(|t| {
            let at_t = sigma + t * (slope - 0.5 * eps * t);
            let rounding = 8.0 * U * (sigma + t * (slope.abs() + 0.5 * eps * t));
            at_t - rounding > 0.0
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::isolate::{self, Found};
    use super::super::tests::Mix;
    use super::super::{Thermostat, contacts::Candidate};
    use super::*;
    use crate::kernel::cell::Disk;
    use crate::kernel::trap::Trap;
    use crate::kernel::vec2::Vec2;
    use rug::Float;

    const BITS: u32 = 200;

    fn big(x: f64) -> Float {
        Float::with_val(BITS, x)
    }

    fn lift(v: &Vec2<f64>) -> Vec2<Float> {
        Vec2::new(big(v.x), big(v.y))
    }

    /// The cell `c` at 200 bits, its values lifted exactly: the screen's claims are about the
    /// exact geometry of the values it reads.
    fn lift_cell(c: &ConvexCell<f64>) -> ConvexCell<Float> {
        c.map_values(|x| big(*x))
    }

    /// A start of `kind` in `cell`: free inside, on a disk leaving it, or on an edge entering by
    /// it; its direction is random, or (every third) grazing the straight line past a disk by a
    /// gap below the tube's width, with the field bending the flight towards it.
    fn start(cell: &ConvexCell<f64>, r: &mut Mix, n: usize) -> (Flight<f64>, Thermostat<f64>) {
        let eps = 10f64.powf(5.0 * r.unit() - 3.0);
        let phi = 6.3 * r.unit();
        let th = Thermostat::new(eps, Vec2::new(phi.cos(), phi.sin()));
        let (w, h) = cell
            .corners
            .iter()
            .fold((0f64, 0f64), |(w, h), c| (w.max(c.x), h.max(c.y)));
        let angle = 6.3 * r.unit();
        let dir = Vec2::new(angle.cos(), angle.sin());
        match n % 3 {
            0 => {
                let m = (r.unit() * cell.disks.len() as f64) as usize;
                let d = &cell.disks[m];
                let out = if dir.dot(&Vec2::new(1.0, 0.0)) >= 0.0 {
                    1.0
                } else {
                    -1.0
                };
                let a = 6.3 * r.unit();
                let normal = Vec2::new(a.cos(), a.sin());
                let p = Vec2::new(
                    d.centre.x + d.radius() * normal.x,
                    d.centre.y + d.radius() * normal.y,
                );
                // Leaving: the direction's normal component outward, sometimes nearly tangent.
                let tangent = Vec2::new(-normal.y * out, normal.x * out);
                let lean = r.unit().powi(1 + (n / 3 % 4) as i32);
                let v = Vec2::new(tangent.x + lean * normal.x, tangent.y + lean * normal.y);
                let k = v.norm2().sqrt();
                let mut f = Flight::new(p, Vec2::new(v.x / k, v.y / k));
                f.excluded_disk = Some(m as u8);
                (f, th)
            }
            1 => loop {
                let p = Vec2::new(w * r.unit(), h * r.unit());
                if cell.is_free(&p) {
                    return (Flight::new(p, dir), th);
                }
            },
            _ => {
                // Aimed past a disk by a gap g, the field across the flight towards the disk.
                let m = (r.unit() * cell.disks.len() as f64) as usize;
                let d = &cell.disks[m];
                let gap = 0.3 * r.unit().powi(2);
                let side = Vec2::new(-dir.y, dir.x);
                let miss = d.radius() + gap;
                let back = 0.5 + r.unit();
                let p = Vec2::new(
                    d.centre.x + miss * side.x - back * dir.x,
                    d.centre.y + miss * side.y - back * dir.y,
                );
                let th = Thermostat::new(eps, Vec2::new(-side.x, -side.y));
                (Flight::new(p, dir), th)
            }
        }
    }

    /// The screen's times are free (`proofs-notes/thermostat-flight.md`, "The screen"): for
    /// every candidate of 3000 starts in the trap at w = 0.1 and 0.3 and a box with a small and
    /// a large disk (free, leaving a disk — some nearly tangent — and aimed past a disk with the
    /// field bending the flight towards it, ε from 10⁻³ to 10²), the certified march at 200 bits
    /// over (0, T] of the exact flight of the same values finds no contact. Counts how many
    /// times were positive and how close the nearest contact beyond T came.
    #[test]
    fn the_screen_never_excludes_a_contact_the_certified_march_finds() {
        let mut r = Mix(31);
        let mut cells: Vec<ConvexCell<f64>> = [0.1, 0.3]
            .iter()
            .map(|&w| Trap::new(w).unwrap().cell().clone())
            .collect();
        let mut boxed = cells[0].clone();
        boxed.disks = vec![
            Disk::new(Vec2::new(0.5, 0.6), 1e-3),
            Disk::new(Vec2::new(1.5, 0.2), 0.4),
        ];
        cells.push(boxed);
        let (mut screened, mut tight) = (0usize, 0f64);
        for n in 0..3000 {
            let cell = &cells[n % cells.len()];
            let hi_cell = lift_cell(cell);
            let (f, th) = start(cell, &mut r, n / cells.len());
            let tube = Tube::new(&f, &th.strength, &100.0);
            let fh = Flight::<Float>::convert_from_f64(BITS, &f);
            let th_hi = Thermostat {
                strength: big(th.strength),
                dir: lift(&th.dir),
            };
            let start_hi = th_hi.start(&fh.vel);
            let kinds = (0..cell.edges.len() as u8)
                .map(EventKind::Crossing)
                .chain((0..cell.disks.len() as u8).map(EventKind::Collision));
            for kind in kinds {
                let t = tube.free_time(cell, &f, kind);
                if t == 0.0 {
                    continue;
                }
                screened += 1;
                let c = Candidate::new(&hi_cell, &start_hi, &fh, kind);
                let horizon = big(2.0 * t);
                if let Found::Root(at) = isolate::earliest(&c, c.identity(), &horizon) {
                    let at = at.to_f64();
                    assert!(
                        at > t,
                        "{n}: {kind:?} met at {at} within the screen's {t}: {f:?}, {th:?}"
                    );
                    tight = tight.max(t / at);
                }
            }
        }
        assert!(screened > 6000, "{screened}");
        eprintln!(
            "screened {screened} candidates; largest T over the contact after it: {tight:.3}"
        );
    }
}
