//! Midpoint–radius enclosures in `f64` of values computed at any precision of at least 53 bits.
//!
//! A [`Ball`] (m, r) stands for every value within r of m. Its operations are built so that if
//! the operands' balls contain numbers x and y, the result's ball contains the exact x ∘ y *and*
//! that value correctly rounded to any precision p ≥ 53. A sequence of ball operations that
//! mirrors a sequence of correctly rounded operations on `rug::Float` (or `f64`) therefore
//! encloses every intermediate value that sequence computes, at whatever precision it ran, and
//! a sign or an order that the balls decide is the one the rounded computation finds. This is
//! what lets the MPFR kernel decide its next event in `f64` and compute only the chosen time at
//! its working precision (`crate::kernel::certified`, `proofs-notes/certified-filter.md`).
//!
//! Rounding of the balls themselves: the midpoint is rounded to nearest (error ≤ 2⁻⁵³|m|); the
//! other rounding, that of the enclosed computation at p ≥ 53 bits, is at most 2⁻⁵³ of its
//! magnitude. Both are covered by a term 2⁻⁵¹|m| in every radius (twice what they need), and
//! the radius itself, a few rounded operations on non-negative terms, is enlarged by the factor
//! 1 + 2⁻⁴⁹ (sixteen times the rounding of up to eight of them). A non-finite operand gives a
//! non-finite or NaN ball, which decides nothing.

/// 2⁻⁵¹: the per-operation rounding term (both roundings of a result, with a factor 2 to spare).
const ROUND: f64 = 1.0 / 2_251_799_813_685_248.0;
/// 1 + 2⁻⁴⁹: covers the rounding of a radius computed in round-to-nearest.
const UP: f64 = 1.0 + 1.0 / 562_949_953_421_312.0;
/// An absolute floor for conversions, below every normal `f64` the kernel meets (a subnormal
/// rounds with an absolute error of at most 2⁻¹⁰⁷⁵).
const FLOOR: f64 = f64::MIN_POSITIVE;

/// The values within `r` of `m` (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Ball {
    /// Midpoint.
    pub m: f64,
    /// Radius (≥ 0).
    pub r: f64,
}

impl Ball {
    /// Exactly the value `m` (a constant every precision represents exactly: 0, 1, ½).
    #[inline(always)]
    pub const fn exact(m: f64) -> Ball {
        Ball { m, r: 0.0 }
    }

    /// A ball around `x`, the nearest `f64` of a number of any precision: a correctly rounded
    /// conversion is within 2⁻⁵³|x| of it (or 2⁻¹⁰⁷⁵ below the normal range).
    #[inline(always)]
    pub fn around(x: f64) -> Ball {
        Ball {
            m: x,
            r: (2.0 * ROUND * x.abs() + FLOOR) * UP,
        }
    }

    /// `true` if every value in the ball is negative.
    #[inline(always)]
    pub fn negative(self) -> bool {
        // Rounding is monotone and 0 is representable: m + r < 0 rounded only if exactly.
        self.m + self.r < 0.0
    }

    /// `true` if every value in the ball is positive.
    #[inline(always)]
    pub fn positive(self) -> bool {
        self.m - self.r > 0.0
    }

    /// `true` if no value in the ball is positive.
    #[inline(always)]
    pub fn non_positive(self) -> bool {
        self.m + self.r <= 0.0
    }

    /// `true` if no value in the ball is negative.
    #[inline(always)]
    pub fn non_negative(self) -> bool {
        self.m - self.r >= 0.0
    }

    /// `true` if every value in `self` is smaller than every value in `o`.
    #[inline(always)]
    pub fn before(self, o: Ball) -> bool {
        // The rounded gap is within 2⁻⁵³ of the exact one, the rounded radius sum likewise.
        o.m - self.m > (self.r + o.r) * UP
    }

    /// x², correctly rounded at any p ≥ 53 (one rounding, as MPFR's and IEEE's squares).
    #[inline(always)]
    pub fn sqr(self) -> Ball {
        self * self
    }

    /// √x, correctly rounded at any p ≥ 53; NaN (deciding nothing) unless the ball is positive.
    #[inline(always)]
    pub fn sqrt(self) -> Ball {
        if !self.positive() {
            return Ball::nan();
        }
        let s = self.m.sqrt();
        // |√x − √m| = |x − m|/(√x + √m) ≤ r/√m, and √m ≥ s(1 − 2⁻⁵³).
        Ball {
            m: s,
            r: (self.r / s + ROUND * s) * UP,
        }
    }

    /// The ball that decides nothing.
    #[inline(always)]
    fn nan() -> Ball {
        Ball {
            m: f64::NAN,
            r: f64::NAN,
        }
    }
}

impl std::ops::Neg for Ball {
    type Output = Ball;
    /// −x (exact).
    #[inline(always)]
    fn neg(self) -> Ball {
        Ball {
            m: -self.m,
            r: self.r,
        }
    }
}

impl std::ops::Add for Ball {
    type Output = Ball;
    /// x + y, correctly rounded at any p ≥ 53.
    #[inline(always)]
    fn add(self, o: Ball) -> Ball {
        let m = self.m + o.m;
        Ball {
            m,
            r: (self.r + o.r + ROUND * m.abs()) * UP,
        }
    }
}

impl std::ops::Sub for Ball {
    type Output = Ball;
    /// x − y, correctly rounded at any p ≥ 53.
    #[inline(always)]
    fn sub(self, o: Ball) -> Ball {
        self + -o
    }
}

impl std::ops::Mul for Ball {
    type Output = Ball;
    /// x·y, correctly rounded at any p ≥ 53.
    #[inline(always)]
    fn mul(self, o: Ball) -> Ball {
        let m = self.m * o.m;
        let spread = self.m.abs() * o.r + o.m.abs() * self.r + self.r * o.r;
        Ball {
            m,
            r: (spread + ROUND * m.abs()) * UP,
        }
    }
}

impl std::ops::Div for Ball {
    type Output = Ball;
    /// x/y, correctly rounded at any p ≥ 53; NaN (deciding nothing) if the ball of y holds 0.
    #[inline(always)]
    fn div(self, o: Ball) -> Ball {
        // |y| ≥ |m_y| − r_y = low > 0 for every y in the ball, rounded down by the factor.
        let low = (o.m.abs() - o.r) / UP;
        if low.is_nan() || low <= 0.0 {
            return Ball::nan();
        }
        let q = self.m / o.m;
        // |x/y − m_x/m_y| ≤ (r_x + |m_x/m_y|·r_y)/low.
        Ball {
            m: q,
            r: ((self.r + q.abs() * o.r) / low + ROUND * q.abs()) * UP,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rug::Float;

    /// Every operation's ball holds the exact result of operands anywhere in the operands' balls
    /// (their midpoints, their edges, between) rounded at 53 and at 256 bits: balls of radius 0
    /// (exact constants), of one conversion (`around`) and wide ones, over 24 binades and both
    /// signs.
    #[test]
    fn balls_enclose_the_rounded_results_at_53_and_256_bits() {
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let mut unit = || (next() >> 11) as f64 / (1u64 << 53) as f64;
        let mut checked = 0;
        for _ in 0..4_000 {
            let pick = |u: f64, s: f64| s * (u + 0.5) * (u * 24.0 - 12.0).round().exp2();
            let ma = pick(unit(), if unit() < 0.5 { 1.0 } else { -1.0 });
            let mb = pick(unit(), 1.0);
            for kind in 0..3 {
                let ball = |m: f64| match kind {
                    0 => Ball::exact(m),
                    1 => Ball::around(m),
                    _ => Ball {
                        m,
                        r: m.abs() * 1e-3,
                    },
                };
                let (ba, bb) = (ball(ma), ball(mb));
                for (ta, tb) in [
                    (0.0, 0.0),
                    (1.0, 1.0),
                    (1.0, -1.0),
                    (-1.0, 1.0),
                    (0.5, 0.25),
                    (-1.0, -1.0),
                ] {
                    for bits in [53u32, 256] {
                        // Operands inside the balls, at the working precision.
                        let at = |b: Ball, t: f64| {
                            let v =
                                Float::with_val(1024, b.r) * (t * (1.0 - 1.0 / 1_048_576.0)) + b.m;
                            let v = Float::with_val(bits, &v);
                            let inside = (v.clone() - b.m).abs() <= b.r;
                            inside.then_some(v)
                        };
                        let (Some(a), Some(b)) = (at(ba, ta), at(bb, tb)) else {
                            continue;
                        };
                        let holds = |what: &str, ball: Ball, v: Float| {
                            let d = (v - Float::with_val(1024, ball.m)).abs();
                            assert!(d <= ball.r, "{what} at {bits} bits: {ball:?} misses by {d}");
                        };
                        holds("+", ba + bb, Float::with_val(bits, &a + &b));
                        holds("-", ba - bb, Float::with_val(bits, &a - &b));
                        holds("×", ba * bb, Float::with_val(bits, &a * &b));
                        holds("²", ba.sqr(), Float::with_val(bits, a.square_ref()));
                        holds("÷", ba / bb, Float::with_val(bits, &a / &b));
                        holds("√", bb.sqrt(), Float::with_val(bits, b.sqrt_ref()));
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 50_000, "{checked}");
    }

    #[test]
    fn a_ball_holding_zero_decides_nothing() {
        let z = Ball { m: 1e-20, r: 1e-19 };
        assert!(!z.positive() && !z.negative() && !z.non_negative() && !z.non_positive());
        assert!((Ball::exact(1.0) / z).m.is_nan());
        assert!(z.sqrt().m.is_nan());
        let nan = Ball::exact(1.0) / z;
        assert!(!nan.positive() && !nan.negative() && !nan.before(z) && !z.before(nan));
        assert!(Ball::exact(1.0).before(Ball::around(1.0 + 1e-10)));
        assert!(!Ball::exact(1.0).before(Ball::around(1.0 + 1e-16)));
    }
}
