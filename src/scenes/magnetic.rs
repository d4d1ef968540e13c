//! A scene in a uniform magnetic field: the lattice walked along arcs, and the description of the
//! disk array that the field's exact geometry needs ([`DiskLattice`], supplied by a scene through
//! [`super::Scene::disk_lattice`]).
//!
//! The field is a number ω = B (speed 1: the velocity turns at the angular velocity B,
//! counter-clockwise for B > 0, on a cyclotron circle of radius 1/|B|). Every cell map of a
//! scene is a translation or a point reflection — both keep the sense of rotation — so the same ω
//! holds in every cell's frame. B = 0 is the straight kernel, never an arc.

use rug::Rational;

use super::lattice::{Lattice, LatticeState};
use crate::Error;
use crate::kernel::arc::excess_series;
use crate::kernel::cell::CellKernel;
use crate::kernel::field::ArcEvent;
use crate::kernel::flight::EventKind;
use crate::kernel::vec2::Vec2;
use crate::numbers::atan::atan2;
use crate::numbers::lanes::Lanes;
use crate::numbers::real::Real;

/// One disk of a [`DiskLattice`]'s cell: its centre (world coordinates, relative to the lattice
/// point i·e₁ + j·e₂ of its cell) and radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LatticeDisk {
    /// The centre's offset from the lattice point.
    pub centre: [f64; 2],
    /// The radius.
    pub radius: f64,
}

/// A periodic array of disks: each disk of one cell repeated at the points i·e₁ + j·e₂,
/// e₁ = (a, 0), e₂ = (βa, h), as `f64` (the exact geometry of the field's localized orbits is
/// evaluated in `f64`: `crate::theory::magnetic`), and exactly where the scene knows it
/// ([`ExactDisks`]: for the decisions that rounding could turn, such as whether every orbit is
/// localized). The presets have one disk at the lattice points ([`DiskLattice::equal`]); a
/// table given as data has any disks.
#[derive(Debug, Clone, PartialEq)]
pub struct DiskLattice {
    /// |e₁|.
    pub a: f64,
    /// The shear β of e₂.
    pub beta: f64,
    /// The height of e₂.
    pub h: f64,
    /// The disks of one cell (none overlapping, each other's images included).
    pub disks: Vec<LatticeDisk>,
    /// The same array exactly, if the scene knows it.
    pub exact: Option<ExactDisks>,
}

/// A disk array exactly: e₁ = (a, 0), e₂ = (b, h) with h² rational (h itself where it is
/// rational), and the disks' centre offsets and radii. Every squared distance between two disks'
/// centres is rational when h is, or when the two centres are at one height (the triangular
/// lattice, h = a√3/2, has one disk per cell).
#[derive(Debug, Clone, PartialEq)]
pub struct ExactDisks {
    /// |e₁|.
    pub a: Rational,
    /// The x part of e₂.
    pub b: Rational,
    /// h², the square of e₂'s height.
    pub h2: Rational,
    /// h, where it is rational.
    pub h: Option<Rational>,
    /// Each disk's centre offset from its lattice point, and its radius.
    pub disks: Vec<([Rational; 2], Rational)>,
}

impl ExactDisks {
    /// |c_k + i·e₁ + j·e₂ − c_m|², if it is rational here.
    fn distance2(&self, m: usize, k: usize, i: i64, j: i64) -> Option<Rational> {
        let (cm, ck) = (&self.disks[m].0, &self.disks[k].0);
        let dx = Rational::from(&ck[0] - &cm[0])
            + Rational::from(i) * &self.a
            + Rational::from(j) * &self.b;
        let dy = Rational::from(&ck[1] - &cm[1]);
        let dy2 = if dy == 0 {
            Rational::from(j * j) * &self.h2
        } else {
            let y = dy + Rational::from(j) * self.h.as_ref()?;
            Rational::from(&y * &y)
        };
        Some(Rational::from(&dx * &dx) + dy2)
    }
}

impl DiskLattice {
    /// One disk of radius `radius` at every lattice point.
    pub fn equal(a: f64, beta: f64, h: f64, radius: f64) -> Self {
        DiskLattice {
            a,
            beta,
            h,
            disks: vec![LatticeDisk {
                centre: [0.0, 0.0],
                radius,
            }],
            exact: None,
        }
    }

    /// The same array, known exactly as `exact`.
    pub fn with_exact(self, exact: ExactDisks) -> Self {
        DiskLattice {
            exact: Some(exact),
            ..self
        }
    }

    /// Whether every other disk of the array (disk `m`'s own images included) keeps its edge at
    /// least `d` from disk m's centre, |c_m − c'| − r' ≥ d, decided exactly: `None` where the
    /// array is not known exactly (then [`DiskLattice::reach`] in `f64` is all there is).
    pub fn reaches_at_least(&self, m: usize, d: &Rational) -> Option<bool> {
        let exact = self.exact.as_ref()?;
        let widest = self.disks.iter().map(|x| x.radius).fold(0.0, f64::max);
        let me = self.disks[m].centre;
        let mut far = Some(true);
        for (k, (disk, (_, r))) in self.disks.iter().zip(&exact.disks).enumerate() {
            let offset = (disk.centre[0] - me[0], disk.centre[1] - me[1]);
            // Every image nearer than d + r' lies within d + widest (the window is widened by a
            // row and a column against the rounding of the f64 bound).
            self.points_near((-offset.0, -offset.1), d.to_f64() + widest, |i, j| {
                if k == m && i == 0.0 && j == 0.0 || far != Some(true) {
                    return;
                }
                let need = Rational::from(d + r);
                far = exact
                    .distance2(m, k, i as i64, j as i64)
                    .map(|d2| d2 >= Rational::from(&need * &need));
            });
        }
        far
    }

    /// The area of one lattice cell, a·h.
    pub fn cell_area(&self) -> f64 {
        self.a * self.h
    }

    /// The free area |Q| of one cell (its disks removed), a·h − πΣr².
    pub fn free_area(&self) -> f64 {
        let covered: f64 = self
            .disks
            .iter()
            .map(|d| std::f64::consts::PI * d.radius * d.radius)
            .sum();
        self.cell_area() - covered
    }

    /// Σr over the disks of one cell (the boundary length over 2π).
    pub fn radius_sum(&self) -> f64 {
        self.disks.iter().map(|d| d.radius).sum()
    }

    /// The lattice point i·e₁ + j·e₂ as world coordinates.
    pub fn point(&self, i: f64, j: f64) -> (f64, f64) {
        (self.a * (i + self.beta * j), self.h * j)
    }

    /// Calls `f(i, j)` for every lattice point i·e₁ + j·e₂ within `reach` of (x, y), and a few
    /// beyond (the window is widened by one row and column against rounding).
    pub fn points_near(&self, (x, y): (f64, f64), reach: f64, mut f: impl FnMut(f64, f64)) {
        let (j_lo, j_hi) = (
            ((y - reach) / self.h).ceil(),
            ((y + reach) / self.h).floor(),
        );
        let mut j = j_lo - 1.0;
        while j <= j_hi + 1.0 {
            let x0 = x - self.beta * self.a * j;
            let (i_lo, i_hi) = (
                ((x0 - reach) / self.a).ceil(),
                ((x0 + reach) / self.a).floor(),
            );
            let mut i = i_lo - 1.0;
            while i <= i_hi + 1.0 {
                f(i, j);
                i += 1.0;
            }
            j += 1.0;
        }
    }

    /// For disk `m`: the smallest distance from its centre to the edge of any other disk of the
    /// array, min |c − c'| − r' over every other disk c' (its own images included).
    pub fn reach(&self, m: usize) -> f64 {
        let me = &self.disks[m];
        let widest = self.disks.iter().map(|d| d.radius).fold(0.0, f64::max);
        // Its own image at e₁ bounds the answer; a nearer edge is within that bound + r_max.
        let mut best = self.a - me.radius;
        for (k, d) in self.disks.iter().enumerate() {
            let offset = (d.centre[0] - me.centre[0], d.centre[1] - me.centre[1]);
            self.points_near((-offset.0, -offset.1), best + widest, |i, j| {
                if k == m && i == 0.0 && j == 0.0 {
                    return;
                }
                let (px, py) = self.point(i, j);
                let (dx, dy) = (offset.0 + px, offset.1 + py);
                best = best.min(dx.hypot(dy) - d.radius);
            });
        }
        best
    }
}

/// One event of an arc flight, as the observers of a field run see it: what ended it, the flight
/// time, the world displacement of the flight (the chord) and its part of the Lévy area
/// ∫ x × dx taken from the flight's start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcStep {
    /// Collision or crossing.
    pub kind: EventKind,
    /// Flight time to the event ([`arc_observables`]).
    pub time: f64,
    /// The chord in world coordinates.
    pub chord: [f64; 2],
    /// ∫ x × dx over the flight, x measured from the flight's start: (φ − sin φ)/ω².
    pub area: f64,
}

impl ArcStep {
    /// The event `kind` at the end of the chord `chord` of the arc of velocity `vel` in the field
    /// `w` (both in the frame of a cell of orientation `sign`), described in world coordinates:
    /// the one description of an event whichever engine and precision found it (the chord,
    /// velocity and field rounded to `f64`, then [`arc_observables`]).
    pub fn new<T: Real>(kind: EventKind, vel: &Vec2<T>, chord: &Vec2<T>, sign: f64, w: &T) -> Self {
        let x = (chord.x.to_f64(), chord.y.to_f64());
        let (time, area) = arc_observables((vel.x.to_f64(), vel.y.to_f64()), x, w.to_f64());
        ArcStep {
            kind,
            time,
            chord: [sign * x.0, sign * x.1],
            area,
        }
    }
}

/// The flight time t and the arc's part of the Lévy area, (φ − sin φ)/ω², of the arc of
/// velocity `v` and chord `x` in the field `w` ≠ 0, in every lane (one `f64` for the scalar
/// driver): φ = ωt = 2·atan2(y, c), y = ω|x|²/2 and c = v·x the chord's angle from v
/// ([`crate::kernel::arc`]), and sin φ = 2yc/(y² + c²) (tan(φ/2) = y/c), the difference taken by
/// its series where |φ| < 1/4 so that nothing cancels. The lanes' operations only
/// ([`atan2`]): every engine, path and platform gives the same bits; observables only (no event
/// depends on them). A chord of no length has t = 0.
#[inline(always)]
pub fn arc_observables<V: Lanes>(v: (V, V), x: (V, V), w: V) -> (V, V) {
    let y = w.mul(x.0.mul(x.0).add(x.1.mul(x.1))).mul(V::splat(0.5));
    let c = v.0.mul(x.0).add(v.1.mul(x.1));
    let phi = atan2(y, c).mul(V::splat(2.0));
    let series = excess_series(phi);
    let sin = V::splat(2.0).mul(y).mul(c).div(y.mul(y).add(c.mul(c)));
    let excess = V::select(phi.abs().lt(V::splat(0.25)), series, phi.sub(sin));
    (phi.div(w), excess.div(w.mul(w)))
}

impl<T: Real, K: CellKernel<T>> Lattice<T, K> {
    /// The next event of the state's arc in the field `w` (≠ 0), or `None` for a pinned orbit
    /// (its cyclotron circle inside the cell meets nothing) or a non-finite state.
    #[inline]
    pub fn next_event_in_field(&self, s: &LatticeState<T>, w: &T) -> Option<ArcEvent<T>> {
        self.cell().next_event_in_field(&s.flight, w)
    }

    /// Carries out `ev`, moving to the neighbouring cell on a crossing.
    #[inline]
    pub fn apply_in_field(&self, s: &mut LatticeState<T>, ev: &ArcEvent<T>) {
        self.cell().apply_in_field(&mut s.flight, ev);
        if let EventKind::Crossing(k) = ev.kind {
            s.cell = s.cell.across(&self.cell().edges[k as usize]);
        }
    }

    /// One event in the field `w` (≠ 0): found, carried out, and described for observers in
    /// world coordinates (`f64`).
    ///
    /// # Errors
    /// [`Error::Failed`] if the orbit has no next event (a pinned orbit: callers start only
    /// orbits that collide, `crate::theory::magnetic::classify`).
    pub fn step_in_field(&self, s: &mut LatticeState<T>, w: &T) -> Result<ArcStep, Error> {
        let ev = self
            .next_event_in_field(s, w)
            .ok_or_else(|| no_next_event(s.flight.vel.to_f64()))?;
        let step = ArcStep::new(ev.kind, &s.flight.vel, &ev.chord, s.cell.sign(), w);
        self.apply_in_field(s, &ev);
        Ok(step)
    }
}

/// The error of an orbit in a field that has no next event, with its velocity `vel`: the one
/// message whichever engine flew it.
pub fn no_next_event(vel: [f64; 2]) -> Error {
    Error::Failed(format!(
        "an orbit in the field has no next event (a pinned orbit, or velocity {vel:?})"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::arc::chord_at;
    use rand::{Rng, SeedableRng};
    use rug::Float;

    /// The flight time and arc area of the `f64` chord, to 256 bits: MPFR's atan2 and sin on the
    /// same inputs.
    fn exact(v: (f64, f64), x: (f64, f64), w: f64) -> (f64, f64) {
        let f = |a: f64| Float::with_val(256, a);
        let (vx, vy, xx, xy, w) = (f(v.0), f(v.1), f(x.0), f(x.1), f(w));
        let y = w.clone() * (xx.clone() * &xx + xy.clone() * &xy) / 2u32;
        let c = vx * &xx + vy * &xy;
        let phi = y.atan2(&c) * 2u32;
        let excess = phi.clone() - phi.clone().sin();
        ((phi / &w).to_f64(), (excess / (w.clone() * &w)).to_f64())
    }

    #[test]
    fn arc_observables_are_within_their_error_model() {
        // proofs-notes/observable-angles.md: |δφ| ≤ 8ε|φ| (atan2 within 3 ulp, y and c within
        // 2ε and ε|x|), |δ sin φ| ≤ 8ε; the area's error over the excess φ − sin φ, whose
        // series (|φ| < 1/4) has only |δφ|'s threefold.
        let eps = f64::EPSILON / 2.0;
        let mut rng = rand::rngs::StdRng::seed_from_u64(58);
        for _ in 0..200_000 {
            let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let v = (a.cos(), a.sin());
            let w = rng.random_range(-3.0..3.0f64) * 10f64.powi(rng.random_range(-3..3));
            let phi = rng.random_range(1e-6..std::f64::consts::TAU - 1e-3);
            let x = chord_at(&Vec2::new(v.0, v.1), &(phi / w.abs()), &w);
            let (t, area) = arc_observables(v, (x.x, x.y), w);
            let (te, ae) = exact(v, (x.x, x.y), w);
            assert!((t - te).abs() <= 8.0 * eps * te, "t {t} {te}");
            let p = w * te;
            let bound = if p.abs() < 0.25 {
                40.0 * eps * ae.abs()
            } else {
                (8.0 * eps * p.abs() + 8.0 * eps) / (w * w) + 4.0 * eps * ae.abs()
            };
            assert!((area - ae).abs() <= bound, "area {area} {ae} at φ {p}");
        }
    }

    #[test]
    fn an_arc_of_no_length_takes_no_time() {
        let (t, area) = arc_observables((-0.6, -0.8), (0.0, 0.0), 2.0);
        assert_eq!((t, area), (0.0, 0.0));
    }
}
