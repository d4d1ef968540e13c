//! The AVX-512 and AVX2 lanes (x86_64): each operation one instruction, every lane the
//! correctly rounded IEEE operation of the scalar code. See the safety model of [`super`].

use super::Lanes;
use std::arch::x86_64::*;

/// Four lanes in an AVX2 `ymm` register. Only constructed inside functions compiled with
/// `avx2` enabled, entered after run-time detection.
#[derive(Debug, Clone, Copy)]
pub struct Avx2(__m256d);

// SAFETY (every `unsafe` block of this impl): the intrinsics need AVX (a subset of AVX2); a
// value of this type exists only inside `#[target_feature(enable = "avx2")]` functions that
// the dispatcher calls after `is_x86_feature_detected!("avx2")`, and the methods are
// inlined into them. Loads and stores are unaligned and bounds-checked by the slice index.
impl Lanes for Avx2 {
    const WIDTH: usize = 4;
    type Mask = __m256d;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Avx2(unsafe { _mm256_set1_pd(x) })
    }
    #[inline(always)]
    fn load(a: &[f64]) -> Self {
        let a = &a[..4];
        Avx2(unsafe { _mm256_loadu_pd(a.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, a: &mut [f64]) {
        let a = &mut a[..4];
        unsafe { _mm256_storeu_pd(a.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Avx2(unsafe { _mm256_add_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Avx2(unsafe { _mm256_sub_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Avx2(unsafe { _mm256_mul_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        Avx2(unsafe { _mm256_div_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Avx2(unsafe { _mm256_sqrt_pd(self.0) })
    }
    #[inline(always)]
    fn neg(self) -> Self {
        Avx2(unsafe { _mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Avx2(unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0) })
    }
    #[inline(always)]
    fn ge(self, o: Self) -> __m256d {
        unsafe { _mm256_cmp_pd::<_CMP_GE_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn lt(self, o: Self) -> __m256d {
        unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn gt(self, o: Self) -> __m256d {
        unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn eq(self, o: Self) -> __m256d {
        unsafe { _mm256_cmp_pd::<_CMP_EQ_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn select(m: __m256d, a: Self, b: Self) -> Self {
        Avx2(unsafe { _mm256_blendv_pd(b.0, a.0, m) })
    }
    #[inline(always)]
    fn and(a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_and_pd(a, b) }
    }
    #[inline(always)]
    fn or(a: __m256d, b: __m256d) -> __m256d {
        unsafe { _mm256_or_pd(a, b) }
    }
    #[inline(always)]
    fn and_not(a: __m256d, b: __m256d) -> __m256d {
        // _mm256_andnot_pd(x, y) = ¬x ∧ y.
        unsafe { _mm256_andnot_pd(b, a) }
    }
    #[inline(always)]
    fn bits(m: __m256d) -> u64 {
        (unsafe { _mm256_movemask_pd(m) }) as u64
    }
    #[inline(always)]
    fn from_bits(b: u64) -> __m256d {
        // Lane l is all ones where bit l of b is set: (b & 2ˡ) == 2ˡ, compared as integers.
        unsafe {
            let sel = _mm256_set_epi64x(8, 4, 2, 1);
            let v = _mm256_and_si256(_mm256_set1_epi64x(b as i64), sel);
            _mm256_castsi256_pd(_mm256_cmpeq_epi64(v, sel))
        }
    }
}

/// Eight lanes in an AVX-512 `zmm` register, masks in `k` registers. Only constructed inside
/// functions compiled with `avx512f` enabled, entered after run-time detection.
#[derive(Debug, Clone, Copy)]
pub struct Avx512(__m512d);

// SAFETY (every `unsafe` block of this impl): as for `Avx2`, with `avx512f`.
impl Lanes for Avx512 {
    const WIDTH: usize = 8;
    type Mask = __mmask8;
    #[inline(always)]
    fn splat(x: f64) -> Self {
        Avx512(unsafe { _mm512_set1_pd(x) })
    }
    #[inline(always)]
    fn load(a: &[f64]) -> Self {
        let a = &a[..8];
        Avx512(unsafe { _mm512_loadu_pd(a.as_ptr()) })
    }
    #[inline(always)]
    fn store(self, a: &mut [f64]) {
        let a = &mut a[..8];
        unsafe { _mm512_storeu_pd(a.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        Avx512(unsafe { _mm512_add_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        Avx512(unsafe { _mm512_sub_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Avx512(unsafe { _mm512_mul_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        Avx512(unsafe { _mm512_div_pd(self.0, o.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Avx512(unsafe { _mm512_sqrt_pd(self.0) })
    }
    #[inline(always)]
    fn neg(self) -> Self {
        // Exact sign flip: 0 − x would turn +0 into +0 rather than −0.
        Avx512(unsafe {
            _mm512_castsi512_pd(_mm512_xor_si512(
                _mm512_castpd_si512(self.0),
                _mm512_set1_epi64(i64::MIN),
            ))
        })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Avx512(unsafe {
            _mm512_castsi512_pd(_mm512_and_si512(
                _mm512_castpd_si512(self.0),
                _mm512_set1_epi64(i64::MAX),
            ))
        })
    }
    #[inline(always)]
    fn ge(self, o: Self) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_GE_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn lt(self, o: Self) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn gt(self, o: Self) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_GT_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn eq(self, o: Self) -> __mmask8 {
        unsafe { _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(self.0, o.0) }
    }
    #[inline(always)]
    fn select(m: __mmask8, a: Self, b: Self) -> Self {
        // _mm512_mask_blend_pd(k, x, y) takes y where k is set.
        Avx512(unsafe { _mm512_mask_blend_pd(m, b.0, a.0) })
    }
    #[inline(always)]
    fn and(a: __mmask8, b: __mmask8) -> __mmask8 {
        a & b
    }
    #[inline(always)]
    fn or(a: __mmask8, b: __mmask8) -> __mmask8 {
        a | b
    }
    #[inline(always)]
    fn and_not(a: __mmask8, b: __mmask8) -> __mmask8 {
        a & !b
    }
    #[inline(always)]
    fn bits(m: __mmask8) -> u64 {
        m as u64
    }
    #[inline(always)]
    fn from_bits(b: u64) -> __mmask8 {
        b as __mmask8
    }
}
