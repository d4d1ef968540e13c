//! Long flights on the square lattice: the first disk a straight flight can meet, found by lattice
//! arithmetic in time independent of the flight's length (`proofs-notes/long-flights.md`).
//!
//! In the frame turned so that the flight moves along +x with 0 ≤ v_y ≤ v_x (an exact swap and
//! sign change of coordinates), the disk at the integer point (k, l) is within R of the line iff
//! |D(k, l)| < R|v|-scaled, D(k, l) = (k − x)v_y − (l − y)v_x the cross product of the centre's
//! offset with v. Scaled by a power of two that makes x, y, v_x, v_y and the window R⁺ integers,
//! "some row l of column k is in the window" is (A·k + B) mod M < 2R⁺ with A = v_y, M = v_x:
//! the first entry of a rotation, [`first_entry`], exact and O(log M). For r < 1/3 at most one row
//! of a column is in the window and columns are met in order, so the first column that enters
//! holds the first disk met.
//!
//! The window R⁺ exceeds r|v| by a relative 2⁻⁴⁰ and an absolute 2⁻⁴⁸: a disk whose centre is
//! that close to the line is a *candidate*; the flight is moved to the edge by which it enters the
//! candidate's cell, and the cell's own kernel decides the collision. No disk the kernel could hit
//! lies outside the window, so none is skipped; a candidate the kernel misses (a near miss within
//! the margin) is left through an edge, and the search goes on from there.

use rug::Integer;
use rug::ops::DivRounding;

use crate::kernel::vec2::Vec2;
use crate::numbers::rotation::{Overflow, first_entry, first_entry_u64};

/// The largest radius the long-flight search applies to: at most one row of a column within the
/// window (2R⁺ < v_x, v_x ≥ 1/√2) and columns met in order (3r < 1).
pub const MAX_RADIUS: f64 = 0.25;

/// The smallest radius the long-flight search applies to, 2⁻³²: a mean free path of 2³¹ columns,
/// far below the 2⁵² a column index may reach, and a window whose absolute margin (2⁻⁴⁸) is
/// 2⁻¹⁶ of the radius. Below it flights walk, and a run's work estimate refuses what could never
/// finish.
pub const MIN_RADIUS: f64 = 1.0 / 4_294_967_296.0;

/// Where a long flight enters the cell of its first candidate disk.
#[derive(Debug, Clone, PartialEq)]
pub struct Jump {
    /// The candidate's cell, relative to the flight's cell.
    pub cells: [i64; 2],
    /// The entry point in the candidate cell's frame (on its entered edge), to a few u.
    pub pos: Vec2<f64>,
    /// The square cell's edge entered (0 right, 1 top, 2 left, 3 bottom).
    pub entered: u8,
    /// The flight time to the entry point (|v| ≈ 1: its length), to a few u of itself.
    pub time: f64,
}

/// The first candidate disk beyond the flight's column along its major axis, for a flight at
/// `pos` (in its cell, the disk at the origin) with velocity `vel` leaving the cell through the
/// edge it faces along that axis (|v_x| ≥ |v_y| and the right or left edge, or the same with x
/// and y exchanged), in the lattice of disks of radius `r` ≤ [`MAX_RADIUS`] at the integer points.
/// `None` if no disk is ever within the window: a line of rational slope through a corridor.
pub fn jump(pos: &Vec2<f64>, vel: &Vec2<f64>, r: f64) -> Option<Jump> {
    let frame = Frame::of(vel);
    let (x, y) = frame.to(pos.x, pos.y);
    let (vx, vy) = frame.to(vel.x, vel.y);
    let window = window(vx, vy, r);
    let line = Line { x, y, vx, vy };
    let (k, l, d) = match line.fast(window) {
        Ok(found) => found?,
        Err(Overflow) => line.exact(window)?,
    };
    // The line crosses the left edge x = k − ½ of the candidate's cell at height (D − v_y/2)/v_x
    // above its centre, so it enters by that edge iff 2D − v_y + v_x ≥ 0, else by the bottom edge
    // at abscissa −(D + v_x/2)/v_y (`proofs-notes/long-flights.md`).
    let left = 2.0 * d - vy + vx >= 0.0;
    let (kf, lf) = (k as f64, l as f64);
    let (ex, ey, time) = if left {
        (-0.5, (d - 0.5 * vy) / vx, (kf - 0.5 - x) / vx)
    } else {
        (-(d + 0.5 * vx) / vy, -0.5, (lf - 0.5 - y) / vy)
    };
    let (px, py) = frame.from(ex, ey);
    let (ci, cj) = frame.cells(k, l);
    Some(Jump {
        cells: [ci, cj],
        pos: Vec2::new(px, py),
        entered: frame.edge(left),
        time,
    })
}

/// The half-width W of the search's window for a flight of velocity (v_x, v_y) among disks of
/// radius `r`: r|v|(1 + 2⁻⁴⁰) + 2⁻⁴⁸, so every disk the exact line or the cell kernel can meet
/// is within W of the line (`proofs-notes/long-flights.md`).
pub(crate) fn window(vx: f64, vy: f64, r: f64) -> f64 {
    let nv = (vx * vx + vy * vy).sqrt();
    r * nv * (1.0 + f64::powi(2.0, -40)) + f64::powi(2.0, -48)
}

/// The machine search's bound g on the rounding of its offset, in units of 2^−s (scale = 2^s):
/// the rounding of p − q + W and of the scaled window, and two for floor and ceiling.
fn rounding_units(p: f64, q: f64, window: f64, scale: f64) -> f64 {
    (8.0 * f64::EPSILON * (p.abs() + q.abs() + window) * scale).ceil() + 2.0
}

/// The machine search's scale exponent s: 2^s makes v_x and v_y (binary exponents `ex`, `ey`)
/// integers.
fn slope_bits(ex: i32, ey: i32, vy: f64) -> i32 {
    -(if vy == 0.0 { ex } else { ex.min(ey) })
}

/// How far beyond the window W the machine search may take a candidate, 2g·2^−s, for a flight at
/// (x, y) with velocity (v_x, v_y) in the turned frame: its window [0, 2W + 2g) is raised by up
/// to 2g against the exact one (`proofs-notes/long-flights.md`). An upper bound wherever the
/// search answers (it declines where the slope needs more than 63 bits).
pub(crate) fn widening(x: f64, y: f64, vx: f64, vy: f64, window: f64) -> f64 {
    let bits = slope_bits(decode(vx).1, decode(vy).1, vy);
    let scale = f64::powi(2.0, bits);
    2.0 * rounding_units(y * vx, x * vy, window, scale) / scale
}

/// The flight in the turned frame: position and velocity.
struct Line {
    x: f64,
    y: f64,
    vx: f64,
    vy: f64,
}

/// The largest column searched: k must stay exact as a double.
const MAX_COLUMN: u64 = 1 << 52;

impl Line {
    /// The first candidate (k, l, D(k, l) to a few u) with the slope exact in 64-bit integers
    /// (A = v_y·2^s, M = v_x·2^s, s ≤ 63: v_y ≥ 2⁻¹¹ v_x or so) and the offset B₀ rounded to an
    /// integer with its rounding bound g added to both sides of the window, so the candidates
    /// are a superset of the exact search's; `Err` where the slope needs more bits or the
    /// answer overflows ([`Overflow`]: then [`Line::exact`]).
    fn fast(&self, window: f64) -> Result<Option<(i64, i64, f64)>, Overflow> {
        let Line { x, y, vx, vy } = *self;
        let ((mx, ex), (my, ey)) = (decode(vx), decode(vy));
        let bits = slope_bits(ex, ey, vy);
        if !(0..=63).contains(&bits) || mx <= 0 || my < 0 {
            return Err(Overflow);
        }
        let m = (mx as u64) << (ex + bits);
        let a = if vy == 0.0 {
            0
        } else {
            (my as u64) << (ey + bits)
        } % m;
        let scale = f64::powi(2.0, bits);
        let (p, q) = (y * vx, x * vy);
        let offset = (p - q + window) * scale;
        let g = rounding_units(p, q, window, scale);
        // Raised by g: B₀ + g ≥ the exact B₀, so the window [0, c) with c = 2W + 2g holds every
        // exact candidate (raised by −g, the first version lost candidates at D ≈ −W: the
        // long-flight fuzz oracle's first finding).
        let b0 = offset.floor() as i128 + g as i128;
        let c = (2.0 * window * scale).ceil() + 2.0 * g;
        if !(offset.abs() < 2f64.powi(120) && c < 2f64.powi(63)) {
            return Err(Overflow);
        }
        let b = (i128::from(a) + b0).rem_euclid(i128::from(m)) as u64;
        let Some(k) = first_entry_u64(a, b, m, c as u64)? else {
            return Ok(None);
        };
        let k = k
            .checked_add(1)
            .filter(|k| *k <= MAX_COLUMN)
            .ok_or(Overflow)?;
        let ka = i128::from(k) * i128::from(a);
        let l = (ka + b0).div_euclid(i128::from(m));
        // D = (k·A − l·M)/2^s + y·v_x − x·v_y.
        let d = (ka - l * i128::from(m)) as f64 / scale + (p - q);
        Ok(Some((k as i64, i64::try_from(l).map_err(|_| Overflow)?, d)))
    }

    /// The first candidate in GMP integers: every double and product of two exactly.
    fn exact(&self, window: f64) -> Option<(i64, i64, f64)> {
        let Line { x, y, vx, vy } = *self;
        let s = Scale::of(&[vx, vy, window], &[(x, vy), (y, vx)]);
        let (a, m, w) = (s.int(vy), s.int(vx), s.int(window));
        // D(k, l) + W = k·A − l·M + B₀ with B₀ = y·v_x − x·v_y + W (all scaled).
        let b0 = s.prod(y, vx) - s.prod(x, vy) + &w;
        let width = Integer::from(&w * 2u32);
        // Columns k = 1 + k′.
        let b = Integer::from(&a + &b0);
        let k = first_entry(&a, &b, &m, &width)? + 1u32;
        let l = Integer::from(&k * &a + &b0).div_floor(&m);
        let d = Integer::from(&k * &a) - Integer::from(&l * &m) + s.prod(y, vx) - s.prod(x, vy);
        if k > MAX_COLUMN {
            return None;
        }
        Some((k.to_i64()?, l.to_i64()?, s.to_f64(&d)))
    }
}

/// The turn of the plane that puts the flight along +x with 0 ≤ v_y ≤ v_x: an exchange of the
/// axes and two signs, exact on every coordinate.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    swap: bool,
    sx: f64,
    sy: f64,
}

impl Frame {
    /// The frame of a flight with velocity `v`.
    pub(crate) fn of(v: &Vec2<f64>) -> Self {
        let swap = v.y.abs() > v.x.abs();
        let (a, b) = if swap { (v.y, v.x) } else { (v.x, v.y) };
        Frame {
            swap,
            sx: if a < 0.0 { -1.0 } else { 1.0 },
            sy: if b < 0.0 { -1.0 } else { 1.0 },
        }
    }

    /// A point or vector of the cell's frame in the turned frame.
    pub(crate) fn to(&self, x: f64, y: f64) -> (f64, f64) {
        let (a, b) = if self.swap { (y, x) } else { (x, y) };
        (self.sx * a, self.sy * b)
    }

    /// A point or vector of the turned frame in the cell's frame.
    pub(crate) fn from(&self, a: f64, b: f64) -> (f64, f64) {
        let (a, b) = (self.sx * a, self.sy * b);
        if self.swap { (b, a) } else { (a, b) }
    }

    /// The cell (column k, row l) of the turned frame in the lattice's frame.
    pub(crate) fn cells(&self, k: i64, l: i64) -> (i64, i64) {
        let (a, b) = (
            if self.sx < 0.0 { -k } else { k },
            if self.sy < 0.0 { -l } else { l },
        );
        if self.swap { (b, a) } else { (a, b) }
    }

    /// The cell of the lattice's frame as (column, row) of the turned frame: the inverse of
    /// [`Frame::cells`].
    pub(crate) fn uncells(&self, i: i64, j: i64) -> (i64, i64) {
        let (a, b) = if self.swap { (j, i) } else { (i, j) };
        (
            if self.sx < 0.0 { -a } else { a },
            if self.sy < 0.0 { -b } else { b },
        )
    }

    /// The square cell's edge that is the turned frame's left edge (`left`) or bottom edge.
    pub(crate) fn edge(&self, left: bool) -> u8 {
        // In the turned frame the left edge faces −x, the bottom edge −y; back in the cell's
        // frame an axis may be exchanged and reversed. Edges: 0 +x, 1 +y, 2 −x, 3 −y.
        let (axis_is_x, negative) = if left {
            (!self.swap, self.sx > 0.0)
        } else {
            (self.swap, self.sy > 0.0)
        };
        match (axis_is_x, negative) {
            (true, true) => 2,
            (true, false) => 0,
            (false, true) => 3,
            (false, false) => 1,
        }
    }
}

/// A power of two 2^bits that makes every given double and product of two doubles an integer.
pub(crate) struct Scale {
    /// The exponent.
    pub(crate) bits: u32,
}

impl Scale {
    /// The least power covering `singles` and the products of `products`.
    pub(crate) fn of(singles: &[f64], products: &[(f64, f64)]) -> Self {
        let exp = |x: f64| -> i64 {
            if x == 0.0 {
                i64::MAX
            } else {
                i64::from(decode(x).1)
            }
        };
        let mut lo = 0i64;
        for &x in singles {
            lo = lo.min(exp(x));
        }
        for &(x, y) in products {
            let (ex, ey) = (exp(x), exp(y));
            if ex != i64::MAX && ey != i64::MAX {
                lo = lo.min(ex + ey);
            }
        }
        Scale {
            bits: u32::try_from(-lo).expect("exponents of finite doubles"),
        }
    }

    /// x·2^bits, exact.
    pub(crate) fn int(&self, x: f64) -> Integer {
        let (m, e) = decode(x);
        shift(Integer::from(m), i64::from(e) + i64::from(self.bits))
    }

    /// z·2^−bits, rounded.
    pub(crate) fn to_f64(&self, z: &Integer) -> f64 {
        let (m, e) = z.to_f64_exp();
        m * f64::powi(2.0, e as i32 - self.bits as i32)
    }

    /// x·y·2^bits, exact.
    pub(crate) fn prod(&self, x: f64, y: f64) -> Integer {
        let ((mx, ex), (my, ey)) = (decode(x), decode(y));
        let p = Integer::from(mx) * Integer::from(my);
        shift(p, i64::from(ex) + i64::from(ey) + i64::from(self.bits))
    }
}

/// z·2^e for e ≥ 0 (the scale makes every exponent so).
fn shift(z: Integer, e: i64) -> Integer {
    debug_assert!(e >= 0 || z == 0);
    if z == 0 {
        return z;
    }
    z << u32::try_from(e).expect("a scale covering the exponent")
}

/// x = m·2^e exactly, m an integer (0 for x = 0).
pub(crate) fn decode(x: f64) -> (i64, i32) {
    if x == 0.0 {
        return (0, 0);
    }
    let bits = x.to_bits();
    let sign = if bits >> 63 == 0 { 1 } else { -1 };
    let exp = ((bits >> 52) & 0x7ff) as i32;
    let frac = (bits & ((1u64 << 52) - 1)) as i64;
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | (1i64 << 52), exp - 1075)
    };
    (sign * m, e)
}

/// The edge of the square cell a flight with velocity `v` faces along its major axis (the axis of
/// the larger |component|, x on a tie): the edge through which [`jump`] takes over.
pub fn major_edge(v: &Vec2<f64>) -> u8 {
    let f = Frame::of(v);
    match (f.swap, f.sx > 0.0) {
        (false, true) => 0,
        (true, true) => 1,
        (false, false) => 2,
        (true, false) => 3,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// The machine-integer search and the GMP one find the same candidate, or the machine one an
    /// earlier candidate inside its widened window (within its rounding bound of the window's
    /// edge), on random lines at radii 10⁻¹ to 10⁻⁶ and slopes down to 2⁻²⁰ (where it declines).
    #[test]
    fn the_fast_search_finds_the_exact_candidate() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(341);
        let (mut same, mut earlier, mut declined) = (0, 0, 0);
        for _ in 0..20_000 {
            let r = 10f64.powf(rng.random_range(-6.0..-1.0));
            let slope = 2f64.powf(rng.random_range(-20.0..0.0));
            let n = slope.hypot(1.0);
            let line = Line {
                x: rng.random_range(-0.5..0.5),
                y: rng.random_range(-0.5..0.5),
                vx: 1.0 / n,
                vy: slope / n,
            };
            let window = r * (1.0 + f64::powi(2.0, -40)) + f64::powi(2.0, -48);
            let exact = line.exact(window).expect("a disk ahead");
            match line.fast(window) {
                Err(Overflow) => declined += 1,
                Ok(fast) => {
                    let fast = fast.expect("a disk ahead");
                    let u = f64::EPSILON / 2.0;
                    assert!((fast.2 - exact.2).abs() <= 16.0 * u || fast.0 < exact.0);
                    if fast.0 == exact.0 {
                        assert_eq!(fast.1, exact.1);
                        same += 1;
                    } else {
                        assert!(fast.0 < exact.0 && fast.2.abs() >= window * (1.0 - 1e-9));
                        earlier += 1;
                    }
                }
            }
        }
        assert!(
            same > 10_000 && declined > 500,
            "{same} same, {earlier} earlier, {declined} declined"
        );
    }

    /// The long-flight oracle's first finding (r = 1.6657·10⁻⁵, slope 2⁻⁹): the disk of column
    /// 54 370 lies at D = −1.6656931878946·10⁻⁵, within 10⁻¹⁶ of the window's lower edge −W.
    /// The machine search had lowered its offset by its rounding bound where it must raise it,
    /// and went on to column 65 156, skipping the candidate (a near miss by 2⁻⁴⁰r + 2⁻⁴⁸, which
    /// the kernel would have missed too, but outside the model's claim). Now both searches find it.
    #[test]
    fn regression_fast_search_skipped_a_candidate_at_the_lower_edge_of_its_window() {
        let line = Line {
            x: -0.2131303883421073,
            y: 0.1428473334859236,
            vx: 0.9999981046606534,
            vy: 0.0019469656136990674,
        };
        let w = window(line.vx, line.vy, 0.00001665693187544487);
        let exact = line.exact(w).expect("a disk ahead");
        let fast = line
            .fast(w)
            .expect("a machine-integer answer")
            .expect("a disk");
        assert_eq!((exact.0, exact.1), (54_370, 106));
        assert_eq!((fast.0, fast.1), (exact.0, exact.1));
    }
}
