//! Vectors of `f64` lanes: the few IEEE operations the multi-trajectory engine and its
//! observers need, on AVX-512, AVX2, plain arrays, or a single `f64` (the scalar engine's one
//! lane).
//!
//! Why by hand rather than a SIMD crate: the engine must reproduce the generic kernel bit for bit,
//! so every lane has to execute *exactly* the correctly rounded operations of the scalar code in
//! the same order — add, sub, mul, div, sqrt (all IEEE-754 correctly rounded in every
//! implementation here), never a fused multiply–add, never an approximate reciprocal — plus
//! ordered comparisons and blends. That is a dozen operations. `wide` chooses its backend at
//! compile time (without `-C target-cpu` it would never use AVX-512 in a portable binary), and
//! `pulp`'s dispatch tokens would hide which instruction runs behind a larger API; a thin trait
//! over `std::arch` keeps each operation visibly one instruction, and the kernel
//! ([`crate::engine::simd`]) and the observers ([`crate::observers`]) are written once,
//! generic over [`Lanes`]; on one lane (`f64`) they are exactly the scalar code.
//!
//! Safety model: the AVX-512 and AVX2 types may only be *created* inside functions compiled
//! with those target features, which the dispatcher ([`crate::engine::SimdPath`]) enters only after
//! run-time detection. Their methods are `#[inline(always)]`, so they are compiled into those
//! functions with the features enabled. The types are private to the crate, so that rule holds
//! for every caller: safe code outside the crate reaches them only through the detected dispatch
//! and cannot name them, let alone construct one on a CPU without the feature:
//!
//! ```compile_fail
//! use lorentz_gas::numbers::lanes::{Avx512, Lanes};
//! let v = Avx512::splat(1.0); // would execute AVX-512 instructions on any CPU
//! ```
//!
//! The portable and one-lane types are public: they execute no special instructions.
//!
//! ```
//! use lorentz_gas::numbers::lanes::Lanes;
//! let v = <f64 as Lanes>::splat(2.0);
//! assert_eq!(v.sqrt(), 2f64.sqrt());
//! ```

/// A vector of `f64` lanes with lane-wise IEEE operations and masks.
///
/// Every arithmetic method is the correctly rounded IEEE-754 operation in every lane (no
/// contraction into FMA); comparisons are ordered (false if either operand is NaN), exactly like
/// `<`, `>` and `==` on `f64`.
pub trait Lanes: Copy {
    /// Number of lanes.
    const WIDTH: usize;
    /// Lane-wise booleans.
    type Mask: Copy;
    /// All lanes `x`.
    fn splat(x: f64) -> Self;
    /// Lanes from `a[0..WIDTH]`.
    fn load(a: &[f64]) -> Self;
    /// Lanes into `a[0..WIDTH]`.
    fn store(self, a: &mut [f64]);
    /// `self + o`.
    fn add(self, o: Self) -> Self;
    /// `self − o`.
    fn sub(self, o: Self) -> Self;
    /// `self · o`.
    fn mul(self, o: Self) -> Self;
    /// `self / o`.
    fn div(self, o: Self) -> Self;
    /// `√self`.
    fn sqrt(self) -> Self;
    /// `−self` (exact: flips the sign bit).
    fn neg(self) -> Self;
    /// `|self|` (exact: clears the sign bit).
    fn abs(self) -> Self;
    /// `self < o`.
    fn lt(self, o: Self) -> Self::Mask;
    /// `self > o`.
    fn gt(self, o: Self) -> Self::Mask;
    /// `self == o`.
    fn eq(self, o: Self) -> Self::Mask;
    /// `self ≥ o`.
    fn ge(self, o: Self) -> Self::Mask;
    /// `m ? a : b` lane by lane.
    fn select(m: Self::Mask, a: Self, b: Self) -> Self;
    /// `a ∧ b`.
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// `a ∨ b`.
    fn or(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// `a ∧ ¬b`.
    fn and_not(a: Self::Mask, b: Self::Mask) -> Self::Mask;
    /// Bit `l` set for every true lane `l`.
    fn bits(m: Self::Mask) -> u64;
    /// The mask whose lane `l` is bit `l` of `b` (higher bits ignored).
    fn from_bits(b: u64) -> Self::Mask;
}

/// One lane: the scalar engine's observers run the same generic code on plain `f64`.
impl Lanes for f64 {
    const WIDTH: usize = 1;
    type Mask = bool;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn load(a: &[f64]) -> Self {
        a[0]
    }
    #[inline(always)]
    fn store(self, a: &mut [f64]) {
        a[0] = self;
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        self + o
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        self - o
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        self * o
    }
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        self / o
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn neg(self) -> Self {
        -self
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64::abs(self)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> bool {
        self < o
    }
    #[inline(always)]
    fn gt(self, o: Self) -> bool {
        self > o
    }
    #[inline(always)]
    fn eq(self, o: Self) -> bool {
        self == o
    }
    #[inline(always)]
    fn ge(self, o: Self) -> bool {
        self >= o
    }
    #[inline(always)]
    fn select(m: bool, a: Self, b: Self) -> Self {
        if m { a } else { b }
    }
    #[inline(always)]
    fn and(a: bool, b: bool) -> bool {
        a & b
    }
    #[inline(always)]
    fn or(a: bool, b: bool) -> bool {
        a | b
    }
    #[inline(always)]
    fn and_not(a: bool, b: bool) -> bool {
        a & !b
    }
    #[inline(always)]
    fn bits(m: bool) -> u64 {
        m as u64
    }
    #[inline(always)]
    fn from_bits(b: u64) -> bool {
        b & 1 == 1
    }
}

/// Plain arrays of four lanes: the portable path (any CPU; the compiler vectorises what the
/// baseline target allows).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Portable(pub [f64; 4]);

impl Portable {
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        Portable([f(self.0[0]), f(self.0[1]), f(self.0[2]), f(self.0[3])])
    }
    #[inline(always)]
    fn zip(self, o: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        Portable([
            f(self.0[0], o.0[0]),
            f(self.0[1], o.0[1]),
            f(self.0[2], o.0[2]),
            f(self.0[3], o.0[3]),
        ])
    }
    #[inline(always)]
    fn test(self, o: Self, f: impl Fn(f64, f64) -> bool) -> [bool; 4] {
        [
            f(self.0[0], o.0[0]),
            f(self.0[1], o.0[1]),
            f(self.0[2], o.0[2]),
            f(self.0[3], o.0[3]),
        ]
    }
}

impl Lanes for Portable {
    const WIDTH: usize = 4;
    type Mask = [bool; 4];
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Portable([x; 4])
    }
    #[inline(always)]
    fn load(a: &[f64]) -> Self {
        Portable([a[0], a[1], a[2], a[3]])
    }
    #[inline(always)]
    fn store(self, a: &mut [f64]) {
        a[..4].copy_from_slice(&self.0);
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        self.zip(o, |a, b| a + b)
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        self.zip(o, |a, b| a - b)
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        self.zip(o, |a, b| a * b)
    }
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        self.zip(o, |a, b| a / b)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(f64::sqrt)
    }
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        self.map(f64::abs)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> [bool; 4] {
        self.test(o, |a, b| a < b)
    }
    #[inline(always)]
    fn ge(self, o: Self) -> [bool; 4] {
        self.test(o, |a, b| a >= b)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> [bool; 4] {
        self.test(o, |a, b| a > b)
    }
    #[inline(always)]
    fn eq(self, o: Self) -> [bool; 4] {
        self.test(o, |a, b| a == b)
    }
    #[inline(always)]
    fn select(m: [bool; 4], a: Self, b: Self) -> Self {
        Portable([
            if m[0] { a.0[0] } else { b.0[0] },
            if m[1] { a.0[1] } else { b.0[1] },
            if m[2] { a.0[2] } else { b.0[2] },
            if m[3] { a.0[3] } else { b.0[3] },
        ])
    }
    #[inline(always)]
    fn and(a: [bool; 4], b: [bool; 4]) -> [bool; 4] {
        [a[0] & b[0], a[1] & b[1], a[2] & b[2], a[3] & b[3]]
    }
    #[inline(always)]
    fn or(a: [bool; 4], b: [bool; 4]) -> [bool; 4] {
        [a[0] | b[0], a[1] | b[1], a[2] | b[2], a[3] | b[3]]
    }
    #[inline(always)]
    fn and_not(a: [bool; 4], b: [bool; 4]) -> [bool; 4] {
        [a[0] & !b[0], a[1] & !b[1], a[2] & !b[2], a[3] & !b[3]]
    }
    #[inline(always)]
    fn bits(m: [bool; 4]) -> u64 {
        (m[0] as u64) | (m[1] as u64) << 1 | (m[2] as u64) << 2 | (m[3] as u64) << 3
    }
    #[inline(always)]
    fn from_bits(b: u64) -> [bool; 4] {
        [b & 1 != 0, b & 2 != 0, b & 4 != 0, b & 8 != 0]
    }
}

/// Two vectors used as one of twice the width. Every operation is issued for both halves
/// back to back, so the two independent dependency chains interleave in the instruction stream
/// and the core overlaps them (one step of the engine is a long chain of divisions and square
/// roots: a single vector would leave the divider idle while it waits).
#[derive(Debug, Clone, Copy)]
pub struct Pair<V>(pub V, pub V);

impl<V: Lanes> Lanes for Pair<V> {
    const WIDTH: usize = 2 * V::WIDTH;
    type Mask = (V::Mask, V::Mask);
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Pair(V::splat(x), V::splat(x))
    }
    #[inline(always)]
    fn load(a: &[f64]) -> Self {
        Pair(V::load(a), V::load(&a[V::WIDTH..]))
    }
    #[inline(always)]
    fn store(self, a: &mut [f64]) {
        self.0.store(a);
        self.1.store(&mut a[V::WIDTH..]);
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Pair(self.0.add(o.0), self.1.add(o.1))
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Pair(self.0.sub(o.0), self.1.sub(o.1))
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Pair(self.0.mul(o.0), self.1.mul(o.1))
    }
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        Pair(self.0.div(o.0), self.1.div(o.1))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Pair(self.0.sqrt(), self.1.sqrt())
    }
    #[inline(always)]
    fn neg(self) -> Self {
        Pair(self.0.neg(), self.1.neg())
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Pair(self.0.abs(), self.1.abs())
    }
    #[inline(always)]
    fn ge(self, o: Self) -> Self::Mask {
        (self.0.ge(o.0), self.1.ge(o.1))
    }
    #[inline(always)]
    fn lt(self, o: Self) -> Self::Mask {
        (self.0.lt(o.0), self.1.lt(o.1))
    }
    #[inline(always)]
    fn gt(self, o: Self) -> Self::Mask {
        (self.0.gt(o.0), self.1.gt(o.1))
    }
    #[inline(always)]
    fn eq(self, o: Self) -> Self::Mask {
        (self.0.eq(o.0), self.1.eq(o.1))
    }
    #[inline(always)]
    fn select(m: Self::Mask, a: Self, b: Self) -> Self {
        Pair(V::select(m.0, a.0, b.0), V::select(m.1, a.1, b.1))
    }
    #[inline(always)]
    fn and(a: Self::Mask, b: Self::Mask) -> Self::Mask {
        (V::and(a.0, b.0), V::and(a.1, b.1))
    }
    #[inline(always)]
    fn or(a: Self::Mask, b: Self::Mask) -> Self::Mask {
        (V::or(a.0, b.0), V::or(a.1, b.1))
    }
    #[inline(always)]
    fn and_not(a: Self::Mask, b: Self::Mask) -> Self::Mask {
        (V::and_not(a.0, b.0), V::and_not(a.1, b.1))
    }
    #[inline(always)]
    fn bits(m: Self::Mask) -> u64 {
        V::bits(m.0) | V::bits(m.1) << V::WIDTH
    }
    #[inline(always)]
    fn from_bits(b: u64) -> Self::Mask {
        (V::from_bits(b), V::from_bits(b >> V::WIDTH))
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use x86::{Avx2, Avx512};

#[cfg(target_arch = "x86_64")]
mod x86;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn portable_lanes_are_the_scalar_operations() {
        let a = Portable([1.0, -0.0, 3.0, f64::NAN]);
        let b = Portable([3.0, 0.0, 3.0, 1.0]);
        assert_eq!(a.div(b).0[0], 1.0 / 3.0);
        assert_eq!(Portable::bits(a.lt(b)), 0b0001);
        assert_eq!(Portable::bits(a.eq(b)), 0b0110);
        assert!(a.neg().0[1].is_sign_positive());
        assert_eq!(Portable::select(a.gt(b), a, b).0, [3.0, 0.0, 3.0, 1.0]);
        assert_eq!(Portable::bits(Portable::from_bits(0b1010)), 0b1010);
        assert_eq!(a.abs().0[1].to_bits(), 0);
    }

    /// Every path computes every operation exactly as `f64` does, lane by lane, on values
    /// chosen to hit signed zeros, subnormals, infinities and NaN; masks round-trip through bits.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn vector_paths_agree_with_f64_lane_by_lane() {
        let vals = [
            1.0,
            -0.0,
            0.0,
            3.5,
            -2.25,
            1e-310,
            -1e308,
            f64::INFINITY,
            f64::NAN,
            0.1,
            7.0,
            -3.0,
            2.0,
            1e-16,
            0.5,
            -1.0,
        ];
        let other = [
            3.0, 0.0, -0.0, 3.5, 1e-300, 2.0, 1e308, 1.0, 1.0, 0.3, -7.0, 9.0, 2.0, 1.0, -0.5, -1.0,
        ];
        fn check<V: Lanes>(a: &[f64; 16], b: &[f64; 16]) {
            let mut o = 0;
            while o < 16 {
                let (x, y) = (V::load(&a[o..]), V::load(&b[o..]));
                let mut got = [0.0; 16];
                type Op<V> = (fn(V, V) -> V, fn(f64, f64) -> f64);
                let ops: [Op<V>; 6] = [
                    (V::add, |p, q| p + q),
                    (V::sub, |p, q| p - q),
                    (V::mul, |p, q| p * q),
                    (V::div, |p, q| p / q),
                    (|p, _| V::sqrt(p), |p, _| p.sqrt()),
                    (|p, _| V::abs(V::neg(p)), |p, _| (-p).abs()),
                ];
                for (vop, sop) in ops {
                    vop(x, y).store(&mut got[o..]);
                    for l in 0..V::WIDTH {
                        let want = sop(a[o + l], b[o + l]);
                        assert!(
                            got[o + l].to_bits() == want.to_bits()
                                || (want.is_nan() && got[o + l].is_nan()),
                            "lane {} {} vs {}",
                            o + l,
                            got[o + l],
                            want
                        );
                    }
                }
                let m = V::bits(x.lt(y)) | V::bits(x.ge(y)) << 16;
                for l in 0..V::WIDTH {
                    assert_eq!(m >> l & 1 == 1, a[o + l] < b[o + l]);
                    assert_eq!(m >> (16 + l) & 1 == 1, a[o + l] >= b[o + l]);
                }
                assert_eq!(
                    V::bits(V::from_bits(0b0110_1001)),
                    0b0110_1001 & ((1 << V::WIDTH) - 1)
                );
                o += V::WIDTH;
            }
        }
        check::<f64>(&vals, &other);
        check::<Portable>(&vals, &other);
        if std::arch::is_x86_feature_detected!("avx2") {
            #[target_feature(enable = "avx2")]
            unsafe fn avx2(a: &[f64; 16], b: &[f64; 16]) {
                check::<Avx2>(a, b);
                check::<Pair<Avx2>>(a, b);
            }
            // SAFETY: the feature was detected.
            unsafe { avx2(&vals, &other) }
        }
        if std::arch::is_x86_feature_detected!("avx512f") {
            #[target_feature(enable = "avx512f")]
            unsafe fn avx512(a: &[f64; 16], b: &[f64; 16]) {
                check::<Avx512>(a, b);
                check::<Pair<Avx512>>(a, b);
            }
            // SAFETY: the feature was detected.
            unsafe { avx512(&vals, &other) }
        }
    }
}
