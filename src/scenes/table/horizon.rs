//! The horizon of a periodic table decided exactly, and its widest corridor
//! (`proofs-notes/table-horizon.md`).
//!
//! A free line of irrational slope comes arbitrarily close to every lattice point, so a corridor
//! runs along a primitive lattice vector v = m e₁ + n e₂. Measured across v and scaled by |v|, a
//! disk of centre c sits at U = v × c, the lattice repeats it with period A = e₁ × e₂ (the cell's
//! area: v × w over the lattice vectors w takes every multiple of A because v is primitive), and
//! the disk covers [U − r|v|, U + r|v|]. A corridor along v is a gap of positive width in the
//! union of these intervals modulo A; its width is the gap divided by |v|. Every endpoint is
//! p + q·√N with p, q rational and N = |v|², so each comparison is decided exactly (the sign of
//! a quadratic surd). A direction with 2 r_max |v| ≥ A is closed by its largest disk alone, so
//! only the finitely many vectors with |v| < A/(2 r_max) are candidates; they are visited by shells of
//! growing |v|, and the search stops once no longer vector can hold a corridor wider than the
//! widest found (a gap is at most A/|v| wide).

use std::cmp::Ordering;

use rug::Rational;

use crate::Error;

/// A corridor: the primitive lattice vector it runs along and its width.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Corridor {
    /// (m, n): the corridor runs along m e₁ + n e₂.
    pub direction: [i64; 2],
    /// m e₁ + n e₂ in world coordinates (nearest doubles).
    pub vector: [f64; 2],
    /// The width of the free strip (nearest double of the exact width).
    pub width: f64,
}

impl std::fmt::Display for Corridor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the corridor along {} e1 + {} e2 = ({}, {}), {:.6} wide",
            self.direction[0], self.direction[1], self.vector[0], self.vector[1], self.width
        )
    }
}

/// The largest number of candidate directions visited (times disks): a table finer than this is
/// refused rather than decided slowly.
pub const MAX_WORK: u64 = 2_000_000;

/// The value p + q·√N (N > 0 the shared radicand).
#[derive(Debug, Clone)]
struct Surd {
    p: Rational,
    q: Rational,
}

impl Surd {
    fn new(p: Rational, q: Rational) -> Self {
        Surd { p, q }
    }

    /// The sign of p + q√N, exactly.
    fn sign(p: &Rational, q: &Rational, n: &Rational) -> Ordering {
        let (sp, sq) = (p.cmp0(), q.cmp0());
        if sp == Ordering::Equal || sp == sq {
            return if sp == Ordering::Equal { sq } else { sp };
        }
        if sq == Ordering::Equal {
            return sp;
        }
        // Opposite signs: the larger of p² and q²N wins.
        match p.clone().square().cmp(&(q.clone().square() * n)) {
            Ordering::Greater => sp,
            Ordering::Less => sq,
            Ordering::Equal => Ordering::Equal,
        }
    }

    /// self − other compared with zero, exactly.
    fn cmp(&self, other: &Surd, n: &Rational) -> Ordering {
        Surd::sign(
            &(self.p.clone() - &other.p),
            &(self.q.clone() - &other.q),
            n,
        )
    }

    fn to_f64(&self, root: f64) -> f64 {
        self.p.to_f64() + self.q.to_f64() * root
    }
}

/// What the horizon needs of a table: its lattice (e₁ = (a, 0), e₂ = (b, h)) and its disks.
pub struct Geometry<'a> {
    /// |e₁|.
    pub a: &'a Rational,
    /// e₂'s x component.
    pub b: &'a Rational,
    /// e₂'s y component.
    pub h: &'a Rational,
    /// (centre, radius) of each disk of a cell.
    pub disks: &'a [([Rational; 2], Rational)],
}

impl Geometry<'_> {
    fn vector(&self, m: i64, n: i64) -> [Rational; 2] {
        [
            Rational::from(m) * self.a + Rational::from(n) * self.b,
            Rational::from(n) * self.h,
        ]
    }

    fn area(&self) -> Rational {
        self.a.clone() * self.h
    }

    /// The primitive vectors (m, n), one of each ±pair, with lo < |v|² ≤ hi, by increasing |v|
    /// (then n, then m: e₁ first among equals).
    fn shell(&self, lo: &Rational, hi: &Rational) -> Vec<(i64, i64, Rational)> {
        let bound = hi.to_f64().sqrt() * (1.0 + 1e-9) + 1e-300;
        let nmax = (bound / self.h.to_f64()).floor() as i64 + 1;
        let (a, b) = (self.a.to_f64(), self.b.to_f64());
        let mut out = Vec::new();
        for n in 0..=nmax {
            let mlo = ((-bound - n as f64 * b) / a).floor() as i64 - 1;
            let mhi = ((bound - n as f64 * b) / a).ceil() as i64 + 1;
            for m in mlo..=mhi {
                if (n == 0 && m <= 0) || gcd(m.unsigned_abs(), n.unsigned_abs()) != 1 {
                    continue;
                }
                let [x, y] = self.vector(m, n);
                let norm2 = x.square() + y.square();
                if norm2 > *lo && norm2 <= *hi {
                    out.push((m, n, norm2));
                }
            }
        }
        out.sort_by(|p, q| p.2.cmp(&q.2).then((p.1, p.0).cmp(&(q.1, q.0))));
        out
    }

    /// The widest gap along (m, n) in units scaled by |v| (as p + q|v|), or `None` if closed.
    fn widest_gap(&self, m: i64, n: i64, norm2: &Rational) -> Option<Surd> {
        let area = self.area();
        let [vx, vy] = self.vector(m, n);
        let mut intervals = Vec::with_capacity(3 * self.disks.len());
        for (c, r) in self.disks {
            // Closed by this disk alone: 2r|v| ≥ A.
            if Surd::sign(&(-area.clone()), &(r.clone() * 2u32), norm2) != Ordering::Less {
                return None;
            }
            let u = vx.clone() * &c[1] - vy.clone() * &c[0];
            let u = u.clone() - (u / &area).floor() * &area;
            for k in -1i32..=1 {
                let centre = u.clone() + area.clone() * k;
                intervals.push((
                    Surd::new(centre.clone(), -r.clone()),
                    Surd::new(centre, r.clone()),
                ));
            }
        }
        intervals.sort_by(|x, y| x.0.cmp(&y.0, norm2));
        let (zero, top) = (
            Surd::new(Rational::new(), Rational::new()),
            Surd::new(area, Rational::new()),
        );
        let mut best: Option<Surd> = None;
        let mut reach = intervals[0].1.clone();
        for (left, right) in &intervals[1..] {
            let starts_here = reach.cmp(&zero, norm2) != Ordering::Less
                && reach.cmp(&top, norm2) == Ordering::Less;
            if left.cmp(&reach, norm2) == Ordering::Greater && starts_here {
                let gap = Surd::new(left.p.clone() - &reach.p, left.q.clone() - &reach.q);
                if best
                    .as_ref()
                    .is_none_or(|b| gap.cmp(b, norm2) == Ordering::Greater)
                {
                    best = Some(gap);
                }
            }
            if right.cmp(&reach, norm2) == Ordering::Greater {
                reach = right.clone();
            }
        }
        best
    }

    /// The widest corridor, or `None` for a finite horizon.
    ///
    /// # Errors
    /// A table whose candidate directions exceed [`MAX_WORK`] (disks far smaller than the cell).
    pub fn widest_corridor(&self) -> Result<Option<Corridor>, Error> {
        let area = self.area();
        let rmax = self
            .disks
            .iter()
            .map(|d| d.1.clone())
            .max()
            .expect("a table has disks");
        // Candidates: |v|² < A²/(4 r_max²).
        let cap = area.clone().square() / (rmax.square() * 4u32);
        let shortest = self
            .a
            .clone()
            .square()
            .min(self.b.clone().square() + self.h.clone().square());
        let work = (cap.to_f64() / area.to_f64() * 2.0).ceil() * self.disks.len() as f64;
        let mut lo = Rational::new();
        let mut hi = (shortest * 4u32).min(cap.clone());
        let mut best: Option<Corridor> = None;
        let mut visited = 0u64;
        loop {
            for (m, n, norm2) in self.shell(&lo, &hi) {
                if norm2 >= cap {
                    continue;
                }
                visited += self.disks.len() as u64;
                if visited > MAX_WORK {
                    return Err(too_fine(work));
                }
                if let Some(gap) = self.widest_gap(m, n, &norm2) {
                    let root = norm2.to_f64().sqrt();
                    let width = gap.to_f64(root) / root;
                    if best.as_ref().is_none_or(|b| width > b.width) {
                        let [x, y] = self.vector(m, n);
                        best = Some(Corridor {
                            direction: [m, n],
                            vector: [x.to_f64(), y.to_f64()],
                            width,
                        });
                    }
                }
            }
            // No vector beyond `hi` holds a gap wider than A/|v| < A/√hi.
            let done = hi >= cap
                || best.as_ref().is_some_and(|b| {
                    b.width * b.width * hi.to_f64() >= area.to_f64().powi(2) * (1.0 + 1e-9)
                });
            if done {
                return Ok(best);
            }
            lo = hi.clone();
            hi = (hi * 4u32).min(cap.clone());
        }
    }
}

fn too_fine(work: f64) -> Error {
    super::TableError::TooFine { work }.into()
}

fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(n: i64, d: i64) -> Rational {
        Rational::from((n, d))
    }

    fn square_lattice(disks: &[([Rational; 2], Rational)]) -> Option<Corridor> {
        let (one, zero) = (q(1, 1), q(0, 1));
        Geometry {
            a: &one,
            b: &zero,
            h: &one,
            disks,
        }
        .widest_corridor()
        .unwrap()
    }

    /// One disk of radius r on the unit square lattice: the axes leave 1 − 2r, the diagonals
    /// 1/√2 − 2r, and (2, 1) leaves 1/√5 − 2r; the horizon is never finite (r < 1/2).
    #[test]
    fn the_square_lattice_has_its_axis_corridor() {
        let c = square_lattice(&[([q(0, 1), q(0, 1)], q(2, 5))]).unwrap();
        assert_eq!(c.direction, [1, 0]);
        assert!((c.width - 0.2).abs() < 1e-15, "{c:?}");
        // Off-centre disks change nothing.
        let c = square_lattice(&[([q(1, 3), q(2, 7)], q(1, 10))]).unwrap();
        assert!((c.width - 0.8).abs() < 1e-15, "{c:?}");
    }

    /// Corners of radius rc and centres of radius rm: along the axes the two rows leave
    /// 1/2 − rc − rm each, closed iff rc + rm ≥ 1/2 (exactly at equality: a zero gap is no
    /// corridor); along (1, 1) the gap is 1/√2 − 2·max(rc, rm) (both rows on the same lines).
    #[test]
    fn two_radii_close_the_axes_exactly_at_rc_plus_rm_one_half() {
        let two = |rc: Rational, rm: Rational| {
            square_lattice(&[([q(0, 1), q(0, 1)], rc), ([q(1, 2), q(1, 2)], rm)])
        };
        // 2/5 + 1/5 > 1/2 closes the axes; (1, 1): 1/√2 − 4/5 < 0 closed; (2, 1): 1/√5 − 4/5 closed.
        assert_eq!(two(q(2, 5), q(1, 5)), None);
        // rc + rm = 1/2: the axes close exactly (tangent rows), the diagonal does too.
        assert_eq!(two(q(2, 5), q(1, 10)), None);
        // Just below: the axes open by 1/2 − 2/5 − 1/11.
        let c = two(q(2, 5), q(1, 11)).unwrap();
        assert_eq!(c.direction, [1, 0]);
        assert!((c.width - (0.5 - 0.4 - 1.0 / 11.0)).abs() < 1e-15, "{c:?}");
        // Small disks: the diagonal 1/√2 − 2·(1/5) beats the axes 1/2 − 1/5 − 1/10.
        let c = two(q(1, 5), q(1, 10)).unwrap();
        assert!(c.direction == [1, 1] || c.direction == [-1, 1], "{c:?}");
        assert!((c.width - (0.5f64.sqrt() - 0.4)).abs() < 1e-15, "{c:?}");
    }

    /// The triangular lattice of unit disks at spacing 2 + w, written with a rational height
    /// h ≈ √3 (2 + w)/2 below and above the true one: the threshold w∞ = 4/√3 − 2 of the paper
    /// lies where the (1, 0) rows' gap h − 2 opens, and the other directions stay closed.
    #[test]
    fn a_rational_near_triangular_lattice_opens_where_its_rows_part() {
        let one = q(1, 1);
        let disks = [([q(0, 1), q(0, 1)], one)];
        let (a, b) = (q(23, 10), q(23, 20));
        for (h, open) in [(q(199, 100), false), (q(2, 1), false), (q(201, 100), true)] {
            let c = Geometry {
                a: &a,
                b: &b,
                h: &h,
                disks: &disks,
            }
            .widest_corridor()
            .unwrap();
            assert_eq!(c.is_some(), open, "h = {h}: {c:?}");
            if let Some(c) = c {
                assert_eq!(c.direction, [1, 0]);
                assert!((c.width - 0.01).abs() < 1e-15, "{c:?}");
            }
        }
    }

    #[test]
    fn surds_compare_exactly() {
        let two = q(2, 1);
        // 3 − 2√2 > 0, 1 − √2 < 0, 2 − √2·√2 = 0 as p + q√N with p = 2, q = −1, N = 4.
        assert_eq!(Surd::sign(&q(3, 1), &q(-2, 1), &two), Ordering::Greater);
        assert_eq!(Surd::sign(&q(1, 1), &q(-1, 1), &two), Ordering::Less);
        assert_eq!(Surd::sign(&q(2, 1), &q(-1, 1), &q(4, 1)), Ordering::Equal);
        assert_eq!(Surd::sign(&q(-3, 1), &q(2, 1), &two), Ordering::Less);
    }
}
