//! The crate-local real-number trait: one kernel, two kinds of number.
//!
//! [`Real`] is implemented for `f64` (production speed) and for [`rug::Float`] at any
//! precision of at least 53 bits (the MPFR shadow). It is deliberately minimal and `Clone`,
//! not `Copy` (as nalgebra's `Scalar`): a `rug::Float` owns heap limbs and carries its own
//! precision. The precision is never global or thread-local: it travels with the data as the
//! context value [`Real::Ctx`] (`()` for `f64`, the number of bits for `rug::Float`) and every
//! constant is computed *at the working precision* from that context.
//!
//! Operators follow rug's convention: the left operand is taken by value and its allocation
//! reused (`a.clone() * &b`), in-place forms (`a *= &b`) are preferred on hot paths. For `f64`
//! all of this compiles to plain machine arithmetic.
//!
//! Only correctly rounded operations (`+ − × ÷ √`) are used by the kernel. MPFR rounds each of
//! them correctly at the target precision, exactly as IEEE 754 does for `f64`, so the generic
//! kernel instantiated with `rug::Float` at 53 bits reproduces the `f64` kernel bit for bit
//! (see `proofs-notes/bit-for-bit.md` and `tests/numerics/bit_for_bit.rs`).

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

use rug::Float;
use rug::float::Constant;

use crate::Error;

/// Smallest precision accepted for `rug::Float` runs: below 53 bits the shadow would be *less*
/// precise than the `f64` run it audits.
pub const MIN_BITS: u32 = 53;

/// Most bits a run may ask for: at 2²⁰ bits (128 KiB per number) one collision already costs
/// about a millisecond, and MPFR would accept up to 2³¹ bits — 256 MiB per number, far more than a
/// machine holds for the few hundred numbers a lattice, a trajectory and its observers keep.
pub const MAX_RUN_BITS: u32 = 1 << 20;

/// A real number type the generic kernel can run on.
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::real::Real;
/// use rug::Float;
///
/// // √3 at 53 bits is the correctly rounded double, as in f64.
/// let s64 = <f64 as Real>::sqrt3(());
/// let s53 = <Float as Real>::sqrt3(53);
/// assert_eq!(s64, s53.to_f64());
/// // At 256 bits it carries 256 bits.
/// assert_eq!(<Float as Real>::sqrt3(256).prec(), 256);
/// ```
pub trait Real:
    Clone
    + Debug
    + PartialOrd
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + for<'a> Add<&'a Self, Output = Self>
    + for<'a> Sub<&'a Self, Output = Self>
    + for<'a> Mul<&'a Self, Output = Self>
    + for<'a> Div<&'a Self, Output = Self>
    + for<'a> AddAssign<&'a Self>
    + for<'a> SubAssign<&'a Self>
    + for<'a> MulAssign<&'a Self>
    + for<'a> DivAssign<&'a Self>
{
    /// `true` where this type's arithmetic is so much dearer than `f64`'s that the kernel decides
    /// each event in `f64` balls first and computes only the chosen candidate's time
    /// (`crate::kernel::certified`): MPFR. The event and its bits are the same either way.
    const DECIDE_IN_BALLS: bool = false;

    /// What is needed to create a number of this type: `()` for `f64`, bits for `rug::Float`.
    type Ctx: Copy + Debug + PartialEq + Send + Sync + 'static;

    /// The context this number was created with.
    fn ctx(&self) -> Self::Ctx;

    /// Number of significand bits of numbers created with `ctx`.
    fn bits(ctx: Self::Ctx) -> u32;

    /// Unit roundoff `u = 2^(1−bits)/2 = 2^−bits` as an `f64` (for error models).
    fn unit_roundoff(ctx: Self::Ctx) -> f64 {
        (-(Self::bits(ctx) as f64)).exp2()
    }

    /// Checks that `ctx` is usable (for `rug::Float`: at least [`MIN_BITS`]).
    fn check_ctx(ctx: Self::Ctx) -> Result<(), Error>;

    /// The `f64` value `x`, converted exactly (every `f64` is representable at ≥ 53 bits).
    fn from_f64(ctx: Self::Ctx, x: f64) -> Self;

    /// The integer `n`, exactly for |n| < 2⁵³.
    fn from_i32(ctx: Self::Ctx, n: i32) -> Self {
        Self::from_f64(ctx, n as f64)
    }

    /// An exact rational (a user input such as 1/3 or 0.1), correctly rounded to the context.
    fn from_rational(ctx: Self::Ctx, q: &rug::Rational) -> Self;

    /// Nearest `f64`.
    fn to_f64(&self) -> f64;

    /// Correctly rounded square root.
    fn sqrt(self) -> Self;

    /// Absolute value (exact).
    fn abs(self) -> Self;

    /// `true` unless NaN or infinite.
    fn is_finite(&self) -> bool;

    /// π at the working precision.
    fn pi(ctx: Self::Ctx) -> Self;

    /// sin (not correctly rounded for `f64`; used by theory formulas only, never by the kernel).
    fn sin(self) -> Self;

    /// cos (theory only, see [`Real::sin`]).
    fn cos(self) -> Self;

    /// arctan, correctly rounded for `f64` too (CORE-MATH): the thermostatted flight's angle, and
    /// theory.
    fn atan(self) -> Self;

    /// The angle of the vector (x, y) = (`x`, `self`) in (−π, π] (not correctly rounded for
    /// `f64`: the flight time of an arc, for observables, never an event's choice).
    fn atan2(self, x: &Self) -> Self;

    /// arctan(`self`/`x`) for x > 0, correctly rounded from the exact quotient for `f64` too
    /// (CORE-MATH's atan2, MPFR's atan2): the thermostatted flight's angle, one rounding fewer
    /// than `atan` of the rounded quotient and, in `f64`, without the slow path CORE-MATH's atan
    /// takes for most arguments between 2⁻⁸ and 1. Other types: `atan` of the quotient.
    fn atan_ratio(self, x: &Self) -> Self {
        (self / x).atan()
    }

    /// eˣ, correctly rounded for `f64` too (CORE-MATH), so that the thermostatted flight in `f64`
    /// is its MPFR-53 flight to the bit (`proofs-notes/thermostat-flight.md`), and theory.
    fn exp(self) -> Self;

    /// eˣ − 1 without cancellation at small x (see [`Real::exp`]).
    fn exp_m1(self) -> Self;

    /// ln(1 + x) without cancellation at small x (see [`Real::exp`]).
    fn ln_1p(self) -> Self;

    /// The natural logarithm (see [`Real::exp`]).
    fn ln(self) -> Self;

    /// Zero.
    fn zero(ctx: Self::Ctx) -> Self {
        Self::from_f64(ctx, 0.0)
    }

    /// One.
    fn one(ctx: Self::Ctx) -> Self {
        Self::from_f64(ctx, 1.0)
    }

    /// √3 at the working precision.
    fn sqrt3(ctx: Self::Ctx) -> Self {
        Self::from_f64(ctx, 3.0).sqrt()
    }

    /// `self²` (by reference, no clone for `f64`).
    fn square(&self) -> Self {
        self.clone() * self
    }

    /// `self ← −self` in place (exact).
    fn neg_mut(&mut self);

    /// `self ← self²` in place (correctly rounded; no allocation for `rug::Float`).
    fn square_mut(&mut self);

    /// `self ← a·b` into existing storage (correctly rounded at `self`'s precision).
    fn set_mul(&mut self, a: &Self, b: &Self);

    /// `self > 0` (no allocation for `rug::Float`).
    fn gt0(&self) -> bool;

    /// `self < 0` (no allocation for `rug::Float`).
    fn lt0(&self) -> bool;

    /// Correctly rounded `self + k` for an exactly representable constant `k` (e.g. `−1`).
    fn add_f64(self, k: f64) -> Self {
        let c = Self::from_f64(self.ctx(), k);
        self + &c
    }

    /// Multiplication by an exactly representable small constant (`0.5`, `2`, `3`, …).
    fn scale(self, k: f64) -> Self {
        let c = Self::from_f64(self.ctx(), k);
        self * &c
    }

    /// Human-readable decimal with as many digits as the precision carries.
    fn to_decimal(&self) -> String;

    /// The value as an MPFR number of `bits` bits (exact when `bits` ≥ this number's precision).
    fn to_mpfr(&self, bits: u32) -> Float;

    /// The same value, marked as a free choice of an algorithm (a certified march's point or
    /// step, any value of which serves): the identity for every type but the running error
    /// analysis ([`super::tracked::Tracked`]), which starts its bound afresh from it
    /// (`proofs-notes/thermostat-audit.md`). No arithmetic: `f64` and MPFR keep their bits.
    #[inline(always)]
    fn anchored(self) -> Self {
        self
    }

    /// The same value, carrying a truncation of at most `e` besides its rounding (a Taylor
    /// step's remainder): the identity for every type but the running error analysis
    /// ([`super::tracked::Tracked`]), which adds `e` to its bound. No arithmetic.
    #[inline(always)]
    fn truncated(self, e: f64) -> Self {
        let _ = e;
        self
    }

    /// Runs `f`, whose decisions are free choices of an algorithm (a trial step's size, whether
    /// to march on or take the Taylor step to the root): `f()` for every type; the running error
    /// analysis counts an ambiguous decision in it apart, as one that changes the path and not,
    /// unless the event itself differs, the result (`proofs-notes/thermostat-audit.md`).
    #[inline(always)]
    fn freely<R>(f: impl FnOnce() -> R) -> R {
        f()
    }
}

/// The elementary functions a [`Real`] takes from its type's own inherent methods of the same
/// name (`f64`'s from the platform's libm, `Float`'s from MPFR, correctly rounded).
macro_rules! forward_unary {
    ($t:ty: $($f:ident),*) => {
        $(
            fn $f(self) -> $t {
                <$t>::$f(self)
            }
        )*
    };
}

impl Real for f64 {
    type Ctx = ();

    #[inline(always)]
    fn ctx(&self) {}
    #[inline(always)]
    fn bits(_: ()) -> u32 {
        53
    }
    fn check_ctx(_: ()) -> Result<(), Error> {
        Ok(())
    }
    #[inline(always)]
    fn from_f64(_: (), x: f64) -> f64 {
        x
    }
    fn from_rational(_: (), q: &rug::Rational) -> f64 {
        // Correctly rounded: MPFR rounds the exact quotient once to 53 bits, which is the double
        // (the normal range is all this crate uses).
        Float::with_val(53, q).to_f64()
    }
    #[inline(always)]
    fn to_f64(&self) -> f64 {
        *self
    }
    #[inline(always)]
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> f64 {
        f64::abs(self)
    }
    #[inline(always)]
    fn is_finite(&self) -> bool {
        f64::is_finite(*self)
    }
    #[inline(always)]
    fn pi(_: ()) -> f64 {
        // The correctly rounded value of π, identical to MPFR's π at 53 bits.
        std::f64::consts::PI
    }
    forward_unary!(f64: sin, cos);
    // Correctly rounded, so that a generic computation with them (the thermostatted flight) in
    // `f64` is its MPFR-53 computation to the bit.
    fn atan(self) -> f64 {
        core_math::atan(self)
    }
    fn exp(self) -> f64 {
        core_math::exp(self)
    }
    fn exp_m1(self) -> f64 {
        core_math::expm1(self)
    }
    fn ln_1p(self) -> f64 {
        core_math::log1p(self)
    }
    fn ln(self) -> f64 {
        core_math::log(self)
    }
    fn atan2(self, x: &f64) -> f64 {
        f64::atan2(self, *x)
    }
    fn atan_ratio(self, x: &f64) -> f64 {
        core_math::atan2(self, *x)
    }
    #[inline(always)]
    fn square(&self) -> f64 {
        self * self
    }
    #[inline(always)]
    fn scale(self, k: f64) -> f64 {
        self * k
    }
    #[inline(always)]
    fn neg_mut(&mut self) {
        *self = -*self;
    }
    #[inline(always)]
    fn square_mut(&mut self) {
        *self *= *self;
    }
    #[inline(always)]
    fn set_mul(&mut self, a: &f64, b: &f64) {
        *self = a * b;
    }
    #[inline(always)]
    fn gt0(&self) -> bool {
        *self > 0.0
    }
    #[inline(always)]
    fn lt0(&self) -> bool {
        *self < 0.0
    }
    #[inline(always)]
    fn add_f64(self, k: f64) -> f64 {
        self + k
    }
    fn to_decimal(&self) -> String {
        format!("{self:e}")
    }
    fn to_mpfr(&self, bits: u32) -> Float {
        Float::with_val(bits, *self)
    }
}

impl Real for Float {
    type Ctx = u32;
    const DECIDE_IN_BALLS: bool = true;

    #[inline]
    fn ctx(&self) -> u32 {
        self.prec()
    }
    fn bits(ctx: u32) -> u32 {
        ctx
    }
    fn check_ctx(ctx: u32) -> Result<(), Error> {
        if !(MIN_BITS..=MAX_RUN_BITS).contains(&ctx) {
            return Err(Error::Precision { bits: ctx });
        }
        Ok(())
    }
    #[inline]
    fn from_f64(ctx: u32, x: f64) -> Float {
        Float::with_val(ctx, x)
    }
    fn from_i32(ctx: u32, n: i32) -> Float {
        Float::with_val(ctx, n)
    }
    fn from_rational(ctx: u32, q: &rug::Rational) -> Float {
        Float::with_val(ctx, q)
    }
    #[inline]
    fn to_f64(&self) -> f64 {
        Float::to_f64(self)
    }
    #[inline]
    fn sqrt(self) -> Float {
        Float::sqrt(self)
    }
    #[inline]
    fn abs(self) -> Float {
        Float::abs(self)
    }
    #[inline]
    fn is_finite(&self) -> bool {
        Float::is_finite(self)
    }
    fn pi(ctx: u32) -> Float {
        Float::with_val(ctx, Constant::Pi)
    }
    forward_unary!(Float: sin, cos, atan, exp, exp_m1, ln_1p, ln);
    fn atan2(self, x: &Float) -> Float {
        Float::atan2(self, x)
    }
    fn atan_ratio(self, x: &Float) -> Float {
        Float::atan2(self, x)
    }
    #[inline]
    fn square(&self) -> Float {
        Float::with_val(self.prec(), self.square_ref())
    }
    #[inline]
    fn scale(self, k: f64) -> Float {
        // A power of two scales exactly: by the exponent (mpfr_mul_2si), the same value as the
        // correctly rounded product and without converting k.
        let bits = k.to_bits();
        let exponent = ((bits >> 52) & 0x7ff) as i32;
        if bits & ((1 << 52) - 1) == 0 && exponent != 0 && exponent != 0x7ff {
            let mut x = self;
            x <<= exponent - 1023;
            if k < 0.0 {
                x.neg_mut();
            }
            return x;
        }
        self * k
    }
    #[inline]
    fn neg_mut(&mut self) {
        rug::ops::NegAssign::neg_assign(self);
    }
    #[inline]
    fn square_mut(&mut self) {
        Float::square_mut(self);
    }
    #[inline]
    fn set_mul(&mut self, a: &Float, b: &Float) {
        rug::Assign::assign(self, a * b);
    }
    #[inline]
    fn gt0(&self) -> bool {
        self.cmp0() == Some(std::cmp::Ordering::Greater)
    }
    #[inline]
    fn lt0(&self) -> bool {
        self.cmp0() == Some(std::cmp::Ordering::Less)
    }
    #[inline]
    fn add_f64(self, k: f64) -> Float {
        self + k
    }
    fn to_decimal(&self) -> String {
        // digits ≈ bits·log10(2), plus one guard digit.
        let digits = (self.prec() as f64 * std::f64::consts::LOG10_2).ceil() as usize + 1;
        self.to_string_radix(10, Some(digits))
    }
    fn to_mpfr(&self, bits: u32) -> Float {
        Float::with_val(bits, self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pi_and_sqrt3_at_53_bits_are_the_doubles() {
        assert_eq!(<Float as Real>::pi(53).to_f64(), std::f64::consts::PI);
        assert_eq!(<Float as Real>::sqrt3(53).to_f64(), 3f64.sqrt());
    }

    #[test]
    fn precision_below_53_is_rejected() {
        assert!(<Float as Real>::check_ctx(52).is_err());
        assert!(<Float as Real>::check_ctx(53).is_ok());
    }

    #[test]
    fn unit_roundoff() {
        assert_eq!(<f64 as Real>::unit_roundoff(()), f64::EPSILON / 2.0);
        assert_eq!(<Float as Real>::unit_roundoff(128), (-128f64).exp2());
    }

    #[test]
    fn to_decimal_carries_the_precision() {
        let s = <Float as Real>::sqrt3(256).to_decimal();
        assert!(s.len() > 78, "{s}");
        // 256 bits carry 77 significant digits; compare the first 72 with √3.
        assert!(s.starts_with(
            "1.73205080756887729352744634150587236694280525381038062805580697945193301"
        ));
    }
}
