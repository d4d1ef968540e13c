//! A value computed at high precision together with a bound on how far the same computation
//! in `f64` can be from it: the running error analysis of the `f64` kernel, carried out by the
//! kernel itself.
//!
//! A [`Tracked`] number is a pair (v, e): v the value at P bits (P ≥ 128, far beyond `f64`), e
//! an upper bound on |x₆₄ − v|, where x₆₄ is what the same sequence of operations gives in
//! `f64` from the same inputs. Each operation propagates the bounds of its operands exactly
//! (second-order terms included) and adds the rounding of its own result, u|x| with
//! u = 2⁻⁵³ (Higham, *Accuracy and Stability of Numerical Algorithms*, §3.3, running error
//! analysis, without dropping the products of errors):
//!
//! * a ± b: e_a + e_b, plus u(|a ± b| + e_a + e_b);
//! * a·b: |a|e_b + |b|e_a + e_a·e_b, plus u times the magnitude;
//! * a/b: (e_a|b| + |a|e_b)/(|b|(|b| − e_b)) (unbounded if e_b ≥ |b|), plus rounding;
//! * √a: min(e_a/√a, √e_a) (√ is ½-Hölder), plus rounding;
//! * exact operations (negation, |·|, scaling by a power of two) move no bound but scale it.
//!
//! The bound itself is computed in `f64` and enlarged by 1 + 2⁻⁴⁸ per operation (more than the
//! rounding of its few terms). The value v is within 2⁻ᴾ of the exact result, far below e.
//! Inputs: an `f64` state lifted exactly has e = 0; an exact constant (a rational such as the
//! gap 0.1) has e = |fl₆₄(q) − q|; π and √3 the rounding of the `f64` constants.
//!
//! This holds while the `f64` computation takes the same branches as the reference. Every sign
//! test and comparison therefore checks whether the operands' bounds could reverse it
//! (|v| ≤ e, or |a − b| ≤ e_a + e_b): such a decision is *ambiguous* at `f64` resolution, and a
//! thread-local count records it ([`take_ambiguous`]). An audited event with an ambiguous
//! decision may legitimately differ from the reference (`crate::verification::arc_audit`).
//!
//! An iterative algorithm's free choices — a certified march's points and trial steps, whether to
//! march on or take the last Taylor step — are not the `f64` run's to match: any serves, and
//! what follows from the point reached is judged. [`Real::anchored`] takes such a value with
//! bound 0, and [`Real::freely`] counts the decisions made in it apart ([`take_free_ambiguous`]),
//! `proofs-notes/thermostat-audit.md`.
//!
//! The sine, cosine and arctangents of `f64` are not correctly rounded: their bound adds 2u of
//! the result plus the propagated error (used for the flight time, an observable only).

use std::cell::Cell;
use std::cmp::Ordering;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use rug::Float;
use rug::float::Constant;

use super::real::Real;
use crate::Error;

/// u = 2⁻⁵³, the unit roundoff of `f64`.
const U: f64 = f64::EPSILON / 2.0;
/// 1 + 2⁻⁴⁸: the rounding of a bound's own few terms, generously.
const UP: f64 = 1.0 + 1.0 / 281_474_976_710_656.0;
/// The smallest precision of the reference: far enough beyond `f64` that its own rounding is
/// negligible against every bound.
pub const MIN_TRACKED_BITS: u32 = 128;

thread_local! {
    static AMBIGUOUS: Cell<u64> = const { Cell::new(0) };
    static FREE_AMBIGUOUS: Cell<u64> = const { Cell::new(0) };
    static FREE_DEPTH: Cell<u32> = const { Cell::new(0) };
}

/// The number of ambiguous decisions since the last call on this thread, and reset it.
pub fn take_ambiguous() -> u64 {
    AMBIGUOUS.with(|c| c.replace(0))
}

/// The number of ambiguous decisions among an algorithm's free choices
/// ([`Real::freely`]) since the last call on this thread, and reset
/// it.
pub fn take_free_ambiguous() -> u64 {
    FREE_AMBIGUOUS.with(|c| c.replace(0))
}

fn flag() {
    let free = FREE_DEPTH.with(Cell::get) > 0;
    let counter = if free { &FREE_AMBIGUOUS } else { &AMBIGUOUS };
    counter.with(|c| c.set(c.get() + 1));
}

/// A high-precision value and a bound on the `f64` computation's distance from it (see the
/// module documentation).
#[derive(Debug, Clone)]
pub struct Tracked {
    /// The value at the reference precision.
    pub v: Float,
    /// The bound on |x₆₄ − v|.
    pub e: f64,
}

impl Tracked {
    fn mag(&self) -> f64 {
        self.v.to_f64().abs() * UP
    }

    fn with(v: Float, propagated: f64) -> Tracked {
        let m = v.to_f64().abs();
        let e = (propagated * (1.0 + U) + U * m) * UP;
        Tracked { v, e }
    }

    fn add_to(self, b: &Tracked, negate: bool) -> Tracked {
        let e = self.e + b.e;
        let v = if negate { self.v - &b.v } else { self.v + &b.v };
        Tracked::with(v, e)
    }

    fn mul_by(self, b: &Tracked) -> Tracked {
        let e = self.mag() * b.e + b.mag() * self.e + self.e * b.e;
        Tracked::with(self.v * &b.v, e)
    }

    fn div_by(self, b: &Tracked) -> Tracked {
        let (ma, mb) = (self.mag(), b.v.to_f64().abs());
        let e = if b.e < mb {
            (self.e * mb + ma * b.e) / (mb * (mb - b.e))
        } else {
            f64::INFINITY
        };
        Tracked::with(self.v / &b.v, e)
    }

    /// A sign test: ambiguous if the bound reaches zero.
    fn sign(&self) -> Option<Ordering> {
        let s = self.v.cmp0();
        if self.e > 0.0 && self.v.to_f64().abs() <= self.e {
            flag();
        }
        s
    }
}

impl PartialEq for Tracked {
    fn eq(&self, o: &Tracked) -> bool {
        self.v == o.v
    }
}

impl PartialOrd for Tracked {
    fn partial_cmp(&self, o: &Tracked) -> Option<Ordering> {
        let gap = Float::with_val(self.v.prec(), &self.v - &o.v)
            .to_f64()
            .abs();
        if self.e + o.e > 0.0 && gap <= self.e + o.e {
            flag();
        }
        self.v.partial_cmp(&o.v)
    }
}

macro_rules! binary {
    ($tr:ident, $f:ident, $atr:ident, $af:ident, $body:expr) => {
        impl $tr<Tracked> for Tracked {
            type Output = Tracked;
            fn $f(self, b: Tracked) -> Tracked {
                $body(self, &b)
            }
        }
        impl<'a> $tr<&'a Tracked> for Tracked {
            type Output = Tracked;
            fn $f(self, b: &'a Tracked) -> Tracked {
                $body(self, b)
            }
        }
        impl<'a> $atr<&'a Tracked> for Tracked {
            fn $af(&mut self, b: &'a Tracked) {
                let a = std::mem::replace(
                    self,
                    Tracked {
                        v: Float::new(53),
                        e: 0.0,
                    },
                );
                *self = $body(a, b);
            }
        }
    };
}

binary!(
    Add,
    add,
    AddAssign,
    add_assign,
    |a: Tracked, b: &Tracked| a.add_to(b, false)
);
binary!(
    Sub,
    sub,
    SubAssign,
    sub_assign,
    |a: Tracked, b: &Tracked| a.add_to(b, true)
);
binary!(
    Mul,
    mul,
    MulAssign,
    mul_assign,
    |a: Tracked, b: &Tracked| a.mul_by(b)
);
binary!(
    Div,
    div,
    DivAssign,
    div_assign,
    |a: Tracked, b: &Tracked| a.div_by(b)
);

impl Neg for Tracked {
    type Output = Tracked;
    fn neg(self) -> Tracked {
        Tracked {
            v: -self.v,
            e: self.e,
        }
    }
}

impl Real for Tracked {
    type Ctx = u32;

    fn ctx(&self) -> u32 {
        self.v.prec()
    }
    fn bits(ctx: u32) -> u32 {
        ctx
    }
    fn unit_roundoff(_: u32) -> f64 {
        // The computation bounded is the f64 one.
        U
    }
    fn check_ctx(ctx: u32) -> Result<(), Error> {
        if !(MIN_TRACKED_BITS..=crate::numbers::precision::MAX_RUN_BITS).contains(&ctx) {
            return Err(Error::Precision { bits: ctx });
        }
        Ok(())
    }
    fn from_f64(ctx: u32, x: f64) -> Tracked {
        Tracked {
            v: Float::with_val(ctx, x),
            e: 0.0,
        }
    }
    fn from_rational(ctx: u32, q: &rug::Rational) -> Tracked {
        let v = Float::with_val(ctx, q);
        let nearest = Float::with_val(53, q);
        let e = Float::with_val(ctx, &nearest - &v).to_f64().abs() * UP;
        Tracked { v, e }
    }
    fn to_f64(&self) -> f64 {
        self.v.to_f64()
    }
    fn sqrt(self) -> Tracked {
        let a = self.v.to_f64().abs();
        let e = if a > 0.0 {
            (self.e / a.sqrt()).min(self.e.sqrt())
        } else {
            self.e.sqrt()
        };
        Tracked::with(self.v.sqrt(), e)
    }
    fn abs(self) -> Tracked {
        Tracked {
            v: self.v.abs(),
            e: self.e,
        }
    }
    fn is_finite(&self) -> bool {
        self.v.is_finite()
    }
    fn pi(ctx: u32) -> Tracked {
        let v = Float::with_val(ctx, Constant::Pi);
        let e = Float::with_val(ctx, std::f64::consts::PI - &v)
            .to_f64()
            .abs()
            * UP;
        Tracked { v, e }
    }
    fn sin(self) -> Tracked {
        // |sin′|, |cos′|, |atan′| ≤ 1.
        let v = self.v.sin();
        Tracked::with(v, self.e).widen_libm()
    }
    fn cos(self) -> Tracked {
        let v = self.v.cos();
        Tracked::with(v, self.e).widen_libm()
    }
    fn atan(self) -> Tracked {
        let v = self.v.clone().atan();
        Tracked::with(v, self.e).widen_libm()
    }
    fn atan2(self, x: &Tracked) -> Tracked {
        let (ax, ay) = (x.v.to_f64().abs(), self.v.to_f64().abs());
        let r2 = (ax * ax + ay * ay) * (1.0 - 4.0 * U);
        let e = (ax * self.e + ay * x.e) / r2;
        Tracked::with(self.v.atan2(&x.v), e).widen_libm()
    }
    fn exp(self) -> Tracked {
        // |δeˣ| ≤ eˣ(e^δ − 1) for |δ| ≤ e.
        let v = self.v.exp();
        let e = v.to_f64().abs() * self.e.exp_m1() * UP;
        Tracked::with(v, e).widen_libm()
    }
    fn exp_m1(self) -> Tracked {
        let ex = Float::with_val(self.v.prec(), self.v.exp_ref());
        let e = ex.to_f64().abs() * self.e.exp_m1() * UP;
        Tracked::with(self.v.exp_m1(), e).widen_libm()
    }
    fn ln_1p(self) -> Tracked {
        // |ln′| = 1/(1 + x) ≤ 1/(1 + x − e) over the bound.
        let room = (1.0 + self.v.to_f64()) * (1.0 - 4.0 * U) - self.e;
        let e = if room > 0.0 {
            self.e / room * UP
        } else {
            f64::INFINITY
        };
        Tracked::with(self.v.ln_1p(), e).widen_libm()
    }
    fn ln(self) -> Tracked {
        let room = self.v.to_f64().abs() * (1.0 - 4.0 * U) - self.e;
        let e = if room > 0.0 {
            self.e / room * UP
        } else {
            f64::INFINITY
        };
        Tracked::with(self.v.ln(), e).widen_libm()
    }
    fn neg_mut(&mut self) {
        rug::ops::NegAssign::neg_assign(&mut self.v);
    }
    fn square_mut(&mut self) {
        let a = std::mem::replace(
            self,
            Tracked {
                v: Float::new(53),
                e: 0.0,
            },
        );
        *self = a.clone().mul_by(&a);
    }
    fn set_mul(&mut self, a: &Tracked, b: &Tracked) {
        *self = a.clone().mul_by(b);
    }
    fn gt0(&self) -> bool {
        self.sign() == Some(Ordering::Greater)
    }
    fn lt0(&self) -> bool {
        self.sign() == Some(Ordering::Less)
    }
    fn scale(self, k: f64) -> Tracked {
        let exact = k.to_bits() & ((1 << 52) - 1) == 0;
        let v = self.v * k;
        if exact {
            return Tracked {
                v,
                e: self.e * k.abs(),
            };
        }
        Tracked::with(v, self.e * k.abs())
    }
    fn to_decimal(&self) -> String {
        format!("{} ± {:e}", self.v.to_string_radix(10, Some(40)), self.e)
    }
    fn to_mpfr(&self, bits: u32) -> Float {
        Float::with_val(bits, &self.v)
    }
    /// A free choice of the algorithm: the replay takes it as the `f64` run's own value, bound 0
    /// (the `f64` run's choice differs, and serves as well: what follows from it is judged, not
    /// how it was reached).
    fn anchored(self) -> Tracked {
        Tracked { v: self.v, e: 0.0 }
    }
    /// A truncation bounded by `e` joins the running bound.
    fn truncated(self, e: f64) -> Tracked {
        Tracked {
            v: self.v,
            e: self.e + e,
        }
    }
    /// The decisions in `f` are counted apart ([`take_free_ambiguous`]).
    fn freely<R>(f: impl FnOnce() -> R) -> R {
        FREE_DEPTH.with(|d| d.set(d.get() + 1));
        let r = f();
        FREE_DEPTH.with(|d| d.set(d.get() - 1));
        r
    }
}

impl Tracked {
    /// Adds the 2u·|value| of a library function that is not correctly rounded in `f64`.
    fn widen_libm(mut self) -> Tracked {
        self.e += 2.0 * U * self.v.to_f64().abs();
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(x: f64) -> Tracked {
        Tracked::from_f64(128, x)
    }

    /// The bound covers the actual f64 error of a cancelling sum and of a division.
    #[test]
    fn bounds_cover_the_f64_computation() {
        let (a, b, c) = (0.1f64, 0.2f64, 0.3f64);
        let x64 = (a + b - c) / (b * c);
        let x = (t(a) + &t(b) - &t(c)) / &(t(b) * &t(c));
        let err = (Float::with_val(128, x64) - &x.v).to_f64().abs();
        assert!(err <= x.e && x.e < 1e-15, "{err} {}", x.e);
        let q = rug::Rational::from((1, 10));
        let tenth = Tracked::from_rational(128, &q);
        assert!(tenth.e > 0.0 && tenth.e <= U * 0.1);
    }

    /// A sign within its bound is ambiguous; an exact zero or a clear sign is not.
    #[test]
    fn ambiguous_decisions_are_counted() {
        take_ambiguous();
        let x = t(0.1) + &t(0.2) - &t(0.3);
        assert!(x.gt0());
        assert_eq!(take_ambiguous(), 1);
        assert!(!t(0.0).gt0() && t(1.0).gt0());
        assert!(t(1.0) > t(0.5));
        assert_eq!(take_ambiguous(), 0);
    }
}
