//! Long flights on the triangular lattice beyond w∞ (`proofs-notes/long-flights.md`, "The
//! triangular lattice"): disks of radius 1 at the points k·e₁ + l·e₂, e₁ = (a, 0),
//! e₂ = (a/2, h), of the canonical trap's frame (the same `f64` numbers a and h the trap kernel
//! uses).
//!
//! The lattice lines parallel to one of e₁, e₂, e₂ − e₁ make up the trap edges. Take the family
//! most nearly perpendicular to the flight (at an angle ψ ≥ 60° to it): a basis f₁, f₂ of the
//! lattice with f₂ along the family puts its lines at the columns c of c·f₁ + r·f₂, h apart, and
//! the disk at (c, r) is within W of the line iff |D(c, r)| < W with
//! D(c, r) = c·(f₁ × v) + r·(f₂ × v) − p × v. Every product is exact in integers after scaling
//! by a power of two, so the first column c₀ with a candidate is the first entry of a rotation
//! ([`first_entry`]), exactly.
//!
//! The flight then goes to where it crosses column c₀ − 1 and walks from there. That crossing
//! holds no disk (column c₀ − 1 has none within W, and other columns' disks stay h − 1 > 0 away
//! from its line), and no disk of a column ≥ c₀ can be met before it: such a disk's centre lies
//! at least h/sin ψ − |cot ψ| ≥ h − 1/√3 along the flight beyond it, and its surface at most 1
//! before its centre, and h − 1/√3 − 1 > 0 wherever h > 2, i.e. w > w∞. A candidate the kernel
//! misses (a near miss within the window's margin) is left through the next trap edge of the
//! family, and the search goes on from there.

use rug::Integer;

use super::{Landing, Scale};
use crate::kernel::flight::Flight;
use crate::kernel::vec2::Vec2;
use crate::numbers::rotation::{first_entry, first_entry_u64};
use crate::scenes::lattice::CellIndex;

/// The farthest column searched: beyond it a flight's position would lose its last digits.
const MAX_COLUMN: u64 = 1 << 52;

/// The largest spacing a = 2 + w with long flights, 2²⁰: the window's absolute margin 2⁻⁴⁰a then
/// stays below 2⁻²⁰ of the disks' radius (beyond it the trap kernel itself cannot resolve a
/// disk of radius 1 to better than 2⁻³³).
pub const MAX_SPACING: f64 = 1_048_576.0;

/// The triangular lattice of disks of radius 1 in the canonical trap's frame, beyond w∞.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangularFlights {
    /// The spacing a = 2 + w, as the trap kernel has it.
    pub a: f64,
    /// The row spacing h = √3a/2, as the trap kernel has it (> 2: beyond w∞).
    pub h: f64,
}

/// What the search found.
#[derive(Debug, Clone, PartialEq)]
pub enum Search {
    /// The flight lands at the crossing of the column before its first candidate's.
    Land(Landing),
    /// The first candidate is in the column crossed now or the next one: walk on.
    Walk,
    /// No disk is ever within the window: a line through a corridor.
    Corridor,
}

/// The edge Eₖ (opposite the trap's vertex Pₖ) of the lattice-line family most nearly
/// perpendicular to `vel` (smallest |d·v| over the edges' directions d; the lowest label on a
/// tie): the crossing a jump takes over.
pub fn trigger(vel: &Vec2<f64>) -> u8 {
    // E₀ runs along e₂ − e₁ ∝ (−1/2, √3/2), E₁ along e₂ ∝ (1/2, √3/2), E₂ along e₁ = (1, 0).
    let s = 3f64.sqrt() / 2.0;
    let dots = [
        (-0.5 * vel.x + s * vel.y).abs(),
        (0.5 * vel.x + s * vel.y).abs(),
        vel.x.abs(),
    ];
    let mut best = 0;
    for k in 1..3 {
        if dots[k] < dots[best] {
            best = k;
        }
    }
    best as u8
}

/// The columns of the edge Eₖ's family, oriented out of the trap: the basis (f₁, f₂) in units
/// of (e₁, e₂), the column of Eₖ's line, and the lattice point (m, n) of column c, row r.
struct Columns {
    f1: (i64, i64),
    f2: (i64, i64),
    edge: i64,
}

impl Columns {
    fn of(k: u8) -> Columns {
        match k {
            // E₀ on k + l = 1, the trap on k + l ≤ 1: c = k + l, r = l.
            0 => Columns {
                f1: (1, 0),
                f2: (-1, 1),
                edge: 1,
            },
            // E₁ on k = 0, the trap on k ≥ 0: c = −k, r = l.
            1 => Columns {
                f1: (-1, 0),
                f2: (0, 1),
                edge: 0,
            },
            // E₂ on l = 0, the trap on l ≥ 0: c = −l, r = k.
            _ => Columns {
                f1: (0, -1),
                f2: (1, 0),
                edge: 0,
            },
        }
    }

    /// The lattice point c·f₁ + r·f₂ in units of (e₁, e₂).
    fn point(&self, c: i64, r: i64) -> (i64, i64) {
        (c * self.f1.0 + r * self.f2.0, c * self.f1.1 + r * self.f2.1)
    }
}

impl TriangularFlights {
    /// m·e₁ + n·e₂ (m, n small integers), in `f64`.
    fn vector(&self, (m, n): (i64, i64)) -> (f64, f64) {
        let (m, n) = (m as f64, n as f64);
        (m * self.a + n * (0.5 * self.a), n * self.h)
    }

    /// The half-width W of the window: 1·|v|(1 + 2⁻⁴⁰) + 2⁻⁴⁰a, so every disk the exact line or
    /// the cell kernel can meet is within W of the line.
    pub fn window(&self, vel: &Vec2<f64>) -> f64 {
        let nv = vel.x.hypot(vel.y);
        nv * (1.0 + f64::powi(2.0, -40)) + f64::powi(2.0, -40) * self.a
    }

    /// The search from the flight `f` in the cell `cell`, about to cross its [`trigger`] edge.
    pub fn jump(&self, cell: CellIndex, f: &Flight<f64>) -> Search {
        let cols = Columns::of(trigger(&f.vel));
        let Some(red) = Reduced::of(self, &cols, f) else {
            return Search::Walk;
        };
        let k = match red.first(&cols) {
            Some(k) => k,
            None => match self.exact(&cols, f) {
                Some(k) => k,
                None => return Search::Corridor,
            },
        };
        if k <= 1 {
            return Search::Walk;
        }
        if k > MAX_COLUMN {
            return Search::Corridor;
        }
        self.land(cell, f, &cols, &red, cols.edge + k as i64 - 1)
    }

    /// The first column (counted from the edge's) with a candidate, in GMP integers: every
    /// product of two doubles exactly. `None`: no disk is ever within the window.
    fn exact(&self, cols: &Columns, f: &Flight<f64>) -> Option<u64> {
        let (p, v) = (&f.pos, &f.vel);
        let (f1, f2) = (self.vector(cols.f1), self.vector(cols.f2));
        let w = self.window(v);
        let products = [
            (f1.0, v.y),
            (f1.1, v.x),
            (f2.0, v.y),
            (f2.1, v.x),
            (p.x, v.y),
            (p.y, v.x),
        ];
        let s = Scale::of(&[w], &products);
        let cross = |x: (f64, f64), y: (f64, f64)| s.prod(x.0, y.1) - s.prod(x.1, y.0);
        let alpha = cross(f1, (v.x, v.y));
        let beta = cross(f2, (v.x, v.y));
        let gamma = cross((p.x, p.y), (v.x, v.y));
        if beta == 0 {
            return None;
        }
        let wi = s.int(w);
        // 0 ≤ c·α + r·β − γ + W < 2W: with M = |β| and r = ∓r″, (c·α + B₀) mod M < 2W.
        let m = Integer::from(beta.abs_ref());
        let b = Integer::from(cols.edge * &alpha) + &wi - &gamma;
        let width = Integer::from(&wi * 2u32);
        let k = first_entry(&alpha, &b, &m, &width)?;
        Some(k.to_u64().unwrap_or(u64::MAX))
    }

    /// The landing where the flight crosses column `c1`: the row r and the fraction μ of the way
    /// along f₂ from (c1, r) to (c1, r + 1), the trap beyond, and the flight time.
    fn land(
        &self,
        cell: CellIndex,
        f: &Flight<f64>,
        cols: &Columns,
        red: &Reduced,
        c1: i64,
    ) -> Search {
        let Some((r, mu, t)) = red.crossing(c1) else {
            return Search::Walk;
        };
        let f2 = self.vector(cols.f2);
        let r0 = cols.point(c1, r);
        let r1 = cols.point(c1, r + 1);
        // The third vertex of the trap beyond: a lattice neighbour of both on column c1 + 1.
        let Some(z) = (-1..=2)
            .map(|z| cols.point(c1 + 1, r + z))
            .find(|&z| unit(diff(z, r0)) && unit(diff(z, r1)))
        else {
            return Search::Walk;
        };
        let sum = (r0.0 + r1.0 + z.0, r0.1 + r1.1 + z.1);
        // Up traps {Q, Q + e₁, Q + e₂} sum to 3Q + (1, 1), down traps {Q, Q − e₁, Q − e₂} to
        // 3Q − (1, 1).
        let up = (sum.0 - 1).rem_euclid(3) == 0 && (sum.1 - 1).rem_euclid(3) == 0;
        let sg = if up { 1 } else { -1 };
        let q = ((sum.0 - sg) / 3, (sum.1 - sg) / 3);
        let entered = match diff(z, q) {
            (0, 0) => 0,
            (_, 0) => 1,
            _ => 2,
        };
        // X − Q = (r0 − Q) + μ·f₂, negated in a down trap's frame.
        let base = self.vector(diff(r0, q));
        let x = (base.0 + mu * f2.0, base.1 + mu * f2.1);
        let sgf = sg as f64;
        let frame = if cell.down { -1 } else { 1 };
        Search::Land(Landing {
            cell: CellIndex {
                i: cell.i + frame * q.0,
                j: cell.j + frame * q.1,
                down: cell.down ^ !up,
            },
            flight: Flight {
                pos: Vec2::new(sgf * x.0, sgf * x.1),
                vel: Vec2::new(sgf * f.vel.x, sgf * f.vel.y),
                excluded_disk: None,
                excluded_edge: Some(entered),
            },
            time: t,
        })
    }
}

/// The columns the machine-integer search answers for (beyond them, the GMP search).
const FAST_COLUMNS: u64 = 1 << 24;

/// The search's quantities as integers at the scale 2^s that puts |β| in [2⁶⁰, 2⁶¹], each
/// product of two doubles rounded down to an integer there (an error below 1, so below 2 for
/// each of α, β, γ, f₂ × f₁ and f₂ × p): D(c, r)·2^s is c·α + r·β − γ to 2(|c| + |r| + 1).
struct Reduced {
    alpha: i128,
    beta: i128,
    gamma: i128,
    f2f1: i128,
    f2p: i128,
    window: i128,
}

impl Reduced {
    fn of(t: &TriangularFlights, cols: &Columns, f: &Flight<f64>) -> Option<Reduced> {
        let (p, v) = (&f.pos, &f.vel);
        let (f1, f2) = (t.vector(cols.f1), t.vector(cols.f2));
        let approx = f2.0 * v.y - f2.1 * v.x;
        if approx == 0.0 || !approx.is_finite() {
            return None;
        }
        let s = 60 - super::square::decode(approx).1 - 52;
        let prod = |x: f64, y: f64| -> Option<i128> {
            let ((mx, ex), (my, ey)) = (super::square::decode(x), super::square::decode(y));
            let m = i128::from(mx) * i128::from(my);
            let e = ex + ey + s;
            match e {
                0.. if e <= 20 => Some(m << e),
                0.. => None,
                -126..0 => Some(m >> -e),
                _ => Some(if m < 0 { -1 } else { 0 }),
            }
        };
        let cross = |x: (f64, f64), y: (f64, f64)| Some(prod(x.0, y.1)? - prod(x.1, y.0)?);
        let w = t.window(v) * f64::powi(2.0, s);
        Some(Reduced {
            alpha: cross(f1, (v.x, v.y))?,
            beta: cross(f2, (v.x, v.y))?,
            gamma: cross((p.x, p.y), (v.x, v.y))?,
            f2f1: cross(f2, f1)?,
            f2p: cross(f2, (p.x, p.y))?,
            window: (w.is_finite() && w < 2f64.powi(100)).then(|| w.ceil() as i128)?,
        })
    }

    /// The first column (from the edge's) with a candidate within [`FAST_COLUMNS`], on the
    /// window widened by the integers' error there, so that no exact candidate is missed: a
    /// rotation in 64-bit integers ([`first_entry_u64`]). `None`: ask the GMP search.
    fn first(&self, cols: &Columns) -> Option<u64> {
        let m = self.beta.unsigned_abs();
        // |r| ≤ (|γ| + |c|·|α|)/|β| + 1 ≤ 1.2 + 1.16·|c| + 1 at ψ ≥ 60°: the error
        // 2(|c| + |r| + 1) stays below 5·FAST_COLUMNS + 16 over the columns searched.
        let g = 5 * i128::from(FAST_COLUMNS) + 16;
        let wide = self.window + g;
        if m >= 1 << 63 || 2 * wide >= m as i128 {
            return None;
        }
        let mi = m as i128;
        let a = self.alpha.rem_euclid(mi) as u64;
        let b = (i128::from(cols.edge) * self.alpha + wide - self.gamma).rem_euclid(mi) as u64;
        match first_entry_u64(a, b, m as u64, (2 * wide) as u64) {
            Ok(Some(k)) if k <= FAST_COLUMNS => Some(k),
            _ => None,
        }
    }

    /// Where the flight crosses column `c1`: the row r, the fraction μ to row r + 1 and the flight
    /// time, from (p + t·v) × v = p × v and f₂ × (p + t·v) = c1·(f₂ × f₁).
    fn crossing(&self, c1: i64) -> Option<(i64, f64, f64)> {
        let c = i128::from(c1);
        let (mut n, mut d) = (
            self.gamma.checked_sub(c.checked_mul(self.alpha)?)?,
            self.beta,
        );
        if d < 0 {
            (n, d) = (-n, -d);
        }
        let r = i64::try_from(n.div_euclid(d)).ok()?;
        let mu = n.rem_euclid(d) as f64 / d as f64;
        let t = (c.checked_mul(self.f2f1)? - self.f2p) as f64 / self.beta as f64;
        Some((r, mu, t))
    }
}

fn diff(x: (i64, i64), y: (i64, i64)) -> (i64, i64) {
    (x.0 - y.0, x.1 - y.1)
}

/// m·e₁ + n·e₂ has length a: m² + mn + n² = 1.
fn unit((m, n): (i64, i64)) -> bool {
    m * m + m * n + n * n == 1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::flight::EventKind;
    use crate::scenes::Scene;
    use crate::scenes::lattice::{Lattice, LatticeState};
    use crate::scenes::triangular::TriangularScene;
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// The first collision from `s`: the cell and disk met, the flight time, and the jumps taken
    /// on the way (walking every crossing where `jumps` is `None`).
    fn first_collision(
        lat: &crate::scenes::lattice::TriangularLattice<f64>,
        mut s: LatticeState<f64>,
        jumps: Option<&TriangularFlights>,
    ) -> (CellIndex, u8, f64, u32) {
        let (mut t, mut n) = (0.0, 0);
        loop {
            let ev = lat.next_event(&s).expect("a next event");
            if let EventKind::Collision(m) = ev.kind {
                return (s.cell, m, t + ev.time, n);
            }
            if let (Some(j), EventKind::Crossing(k)) = (jumps, ev.kind)
                && k == trigger(&s.flight.vel)
            {
                match j.jump(s.cell, &s.flight) {
                    Search::Land(l) => {
                        t += l.time;
                        s.cell = l.cell;
                        s.flight = l.flight;
                        n += 1;
                        continue;
                    }
                    Search::Walk => {}
                    Search::Corridor => panic!("a corridor from {s:?}"),
                }
            }
            t += ev.time;
            lat.apply(&mut s, &ev);
        }
    }

    /// Jumping and walking meet the same disk of the same trap after the same flight time (to
    /// the walk's own rounding over its crossings), at gaps from just beyond w∞ to w = 100, and
    /// the jumps are taken: at w = 100 nearly every flight jumps.
    #[test]
    fn jumps_meet_the_disk_the_walk_meets() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(34);
        for (w, flights) in [("1/3", 2000), ("1", 2000), ("10", 2000), ("100", 500)] {
            let scene = TriangularScene::exact(w.parse().unwrap()).unwrap();
            let Some(super::super::LongFlights::Triangular(t)) = scene.long_flights() else {
                panic!("w = {w} has long flights");
            };
            let lat = Lattice::new(scene.w()).unwrap();
            let mut jumped = 0;
            for _ in 0..flights {
                let s = scene.sample(&mut rng);
                let walk = first_collision(&lat, s.clone(), None);
                let jump = first_collision(&lat, s, Some(&t));
                assert_eq!((walk.0, walk.1), (jump.0, jump.1), "w = {w}");
                let scale = walk.2 + t.a;
                assert!(
                    (walk.2 - jump.2).abs() <= 1e-12 * scale,
                    "w = {w}: {} against {}",
                    walk.2,
                    jump.2
                );
                jumped += u32::from(jump.3 > 0);
            }
            if w == "100" {
                assert!(
                    jumped > flights * 9 / 10,
                    "w = {w}: {jumped} of {flights} jumped"
                );
            }
        }
    }
}
