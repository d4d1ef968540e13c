//! atan2 in the lanes: one function for the scalar observers (`f64`, one lane) and the SIMD
//! ones, written with the correctly rounded operations of [`Lanes`] only (no FMA, no table), so
//! every path and every platform gives the same bits, where the C library's `atan2` differs
//! between versions and vectorises nowhere.
//!
//! With a = |y|, b = |x|, the angle θ₀ = atan(a/b) ∈ [0, π/2] is reduced to atan(u) with
//! |u| ≤ tan(π/8):
//!
//! * a ≤ b·tan(π/8): θ₀ = atan(a/b);
//! * b ≤ a·tan(π/8): θ₀ = π/2 − atan(b/a);
//! * otherwise: θ₀ = π/4 + atan((a − b)/(a + b));
//!
//! then θ = π − θ₀ where x < 0 and −θ where y < 0. atan(u) = u + u·v·P(v), v = u², P of
//! degree 10 (Chebyshev interpolation of (atan√v/√v − 1)/v on [0, tan²(π/8)·1.0002], relative
//! error 7·10⁻¹⁸), and the constant is added last as a head and tail, so that
//! θ = B + (σu + (σu·v·P + B_tail)). The error bound (at most 3 units in the last place; the
//! test drawing 10⁶ arguments against MPFR finds at most 1.86) is derived in
//! `proofs-notes/observable-angles.md`.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

use super::lanes::Lanes;

/// tan(π/8) rounded: the reduction's thresholds (a boundary off by rounding only widens |u|
/// by a few units in its last place, inside the interval P was fitted on).
const TAN_PI_8: f64 = 0.414_213_562_373_095_03;

/// P(v) = (atan(√v)/√v − 1)/v = −1/3 + v/5 − …, lowest degree first.
const P: [f64; 11] = [
    -0.333_333_333_333_333_3,
    0.199_999_999_999_955_13,
    -0.142_857_142_846_648_2,
    0.111_111_110_151_176_26,
    -0.090_909_045_724_873_47,
    0.076_921_830_598_941_14,
    -0.066_645_096_032_553_86,
    0.058_581_328_944_279_22,
    -0.050_853_659_223_442_48,
    0.039_229_237_138_359_43,
    -0.019_173_922_285_547_93,
];

/// π/4, π/2, 3π/4 and π as the double nearest and the double nearest the remainder.
const PI_4: [f64; 2] = [FRAC_PI_4, 3.061_616_997_868_383e-17];
const PI_2: [f64; 2] = [FRAC_PI_2, 6.123_233_995_736_766e-17];
const PI_3_4: [f64; 2] = [2.356_194_490_192_345, 9.184_850_993_605_148e-17];
const PI: [f64; 2] = [std::f64::consts::PI, 1.224_646_799_147_353_2e-16];

/// atan2(y, x) ∈ [−π, π] in every lane, for finite arguments, within 3 units in the last place;
/// except that both arguments zero give 0 (of either sign: an arc of no length turns by no
/// angle), and y = −0 counts as +0.
#[inline(always)]
pub fn atan2<V: Lanes>(y: V, x: V) -> V {
    let (a, b) = (y.abs(), x.abs());
    let t8 = V::splat(TAN_PI_8);
    let low = V::ge(b.mul(t8), a);
    let high = V::and_not(V::ge(a.mul(t8), b), low);
    let num = V::select(low, a, V::select(high, b, a.sub(b)));
    let den = V::select(low, b, V::select(high, a, a.add(b)));
    let u = num.div(den);
    let v = u.mul(u);
    let p = P[..10]
        .iter()
        .rev()
        .fold(V::splat(P[10]), |acc, &c| acc.mul(v).add(V::splat(c)));
    let q = u.mul(v.mul(p));
    // θ = B + σ·atan(u): B and σ by region, turned to π − B and −σ where x < 0.
    let left = x.lt(V::splat(0.0));
    let pick = |lo: [f64; 2], hi: [f64; 2], mid: [f64; 2], k: usize| {
        V::select(
            low,
            V::splat(lo[k]),
            V::select(high, V::splat(hi[k]), V::splat(mid[k])),
        )
    };
    let base = |k: usize| {
        V::select(
            left,
            pick(PI, PI_2, PI_3_4, k),
            pick([0.0; 2], PI_2, PI_4, k),
        )
    };
    // σ < 0: in the high region on the right, elsewhere on the left.
    let minus = V::or(V::and_not(high, left), V::and_not(left, high));
    let (su, sq) = (V::select(minus, u.neg(), u), V::select(minus, q.neg(), q));
    let theta = base(0).add(su.add(sq.add(base(1))));
    let theta = V::select(den.eq(V::splat(0.0)), V::splat(0.0), theta);
    V::select(y.lt(V::splat(0.0)), theta.neg(), theta)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::numbers::lanes::Portable;
    use rand::{Rng, SeedableRng};

    /// |θ − atan2(y, x)| in units in the last place of the exact value (MPFR at 256 bits).
    fn ulps(y: f64, x: f64) -> f64 {
        let exact = rug::Float::with_val(256, y).atan2(&rug::Float::with_val(256, x));
        let e = exact.to_f64();
        let err = (rug::Float::with_val(256, atan2(y, x)) - &exact)
            .abs()
            .to_f64();
        let ulp = if e == 0.0 {
            f64::MIN_POSITIVE
        } else {
            let exp = e.abs().log2().floor() as i32;
            2f64.powi(exp - 52)
        };
        err / ulp
    }

    /// Arguments from every region: random angles and magnitudes, the reduction's boundaries
    /// and the axes.
    fn arguments(n: usize) -> Vec<(f64, f64)> {
        let mut rng = rand::rngs::StdRng::seed_from_u64(58);
        let mut args = Vec::with_capacity(n + 64);
        for _ in 0..n {
            let r = 10f64.powf(rng.random_range(-8.0..8.0));
            let t = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
            args.push((r * t.sin(), r * t.cos()));
        }
        for k in [TAN_PI_8, 1.0 / TAN_PI_8, 1.0] {
            for d in -8..=8 {
                let s = k * (1.0 + f64::from(d) * f64::EPSILON);
                for (sy, sx) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                    args.push((sy * s, sx * 1.0));
                }
            }
        }
        args.extend([
            (0.0, 1.0),
            (0.0, -1.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (2.5, -0.0),
        ]);
        args
    }

    #[test]
    fn atan2_is_within_three_ulps_of_mpfr() {
        let worst = arguments(1_000_000)
            .into_iter()
            .map(|(y, x)| ulps(y, x))
            .fold(0.0, f64::max);
        // The bound of proofs-notes/observable-angles.md (1.86 is the worst found here).
        assert!(worst <= 3.0, "worst error {worst} ulp");
    }

    #[test]
    fn atan2_of_no_arc_is_zero() {
        for (y, x) in [(0.0, 0.0), (0.0, -0.0), (-0.0, -0.0), (-0.0, 0.0)] {
            assert_eq!(atan2(y, x), 0.0);
        }
    }

    #[test]
    fn atan2_has_the_same_bits_on_portable_lanes() {
        let args = arguments(4_000);
        for c in args.chunks_exact(4) {
            let y = Portable([c[0].0, c[1].0, c[2].0, c[3].0]);
            let x = Portable([c[0].1, c[1].1, c[2].1, c[3].1]);
            let lanes = atan2(y, x);
            for (l, &(y, x)) in c.iter().enumerate() {
                assert_eq!(lanes.0[l].to_bits(), atan2(y, x).to_bits());
            }
        }
    }
}
