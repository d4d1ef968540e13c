//! The block-bidiagonal linear algebra of the Newton step: 2×2 blocks, the minimum-norm correction, the inverse bound.

use super::*;

/// `d` reduced to (−π, π] (differences of polar angles).
pub(crate) fn reduce_angle(d: Float) -> Float {
    let b = d.prec();
    let two_pi = Float::with_val(b, rug::float::Constant::Pi) * 2u32;
    let k = (d.clone() / &two_pi).round();
    d - &(k * &two_pi)
}

pub(crate) fn m_mul(a: &M2, b: &M2) -> M2 {
    let e = |i: usize, j: usize| a[2 * i].clone() * &b[j] + &(a[2 * i + 1].clone() * &b[2 + j]);
    [e(0, 0), e(0, 1), e(1, 0), e(1, 1)]
}

pub(crate) fn m_t(a: &M2) -> M2 {
    [a[0].clone(), a[2].clone(), a[1].clone(), a[3].clone()]
}

/// Inverse of a symmetric 2×2 matrix if it is positive definite (leading entry and determinant
/// positive), else `None`.
pub(super) fn m_inv_spd(a: &M2) -> Option<M2> {
    let det = a[0].clone() * &a[3] - &(a[1].clone() * &a[2]);
    if !a[0].is_sign_positive() || a[0].is_zero() || !det.is_sign_positive() || det.is_zero() {
        return None;
    }
    Some([
        a[3].clone() / &det,
        -(a[1].clone() / &det),
        -(a[2].clone() / &det),
        a[0].clone() / &det,
    ])
}

pub(crate) type V2 = [Float; 2];

pub(crate) fn mv(a: &M2, v: &V2) -> V2 {
    [
        a[0].clone() * &v[0] + &(a[1].clone() * &v[1]),
        a[2].clone() * &v[0] + &(a[3].clone() * &v[1]),
    ]
}

pub(super) fn mtv(a: &M2, v: &V2) -> V2 {
    mv(&m_t(a), v)
}

pub(crate) fn norm2(v: &V2) -> Float {
    (v[0].clone().square() + &v[1].clone().square()).sqrt()
}

/// Frobenius norm of a 2×2 matrix (≥ its spectral norm), in f64.
pub(crate) fn m_norm(a: &M2) -> f64 {
    a.iter().map(|x| x.to_f64().powi(2)).sum::<f64>().sqrt()
}

/// Inverses of the block LDLᵀ pivots of JJᵀ − μI, J the block-bidiagonal matrix of the rows
/// (A_k, −I): S₀ = A₀A₀ᵀ + (1 − μ)I, S_k = A_kA_kᵀ + (1 − μ)I − A_k S_{k−1}⁻¹ A_kᵀ. `None` if
/// a pivot is not positive definite — by Sylvester's law of inertia, exactly when JJᵀ − μI is not.
pub(super) fn pivot_inverses(a: &[M2], mu: &Float) -> Option<Vec<M2>> {
    let one_mu = Float::with_val(mu.prec(), 1) - mu;
    let mut inv: Vec<M2> = Vec::with_capacity(a.len());
    for (k, ak) in a.iter().enumerate() {
        let mut s = m_mul(ak, &m_t(ak));
        s[0] += &one_mu;
        s[3] += &one_mu;
        if k > 0 {
            let q = m_mul(&m_mul(ak, &inv[k - 1]), &m_t(ak));
            for (x, y) in s.iter_mut().zip(&q) {
                *x -= y;
            }
        }
        inv.push(m_inv_spd(&s)?);
    }
    Some(inv)
}

/// The minimum-norm solution e of A_k e_k − e_{k+1} = −F_k (k = 0 … m−1, m + 1 unknown
/// blocks): e = Jᵀz with (JJᵀ)z = −F solved by the block LDLᵀ sweep. `None` if JJᵀ is not
/// numerically positive definite.
pub(super) fn min_norm_correction(a: &[M2], f: &[V2]) -> Option<Vec<V2>> {
    let m = a.len();
    let bits = f[0][0].prec();
    let inv = pivot_inverses(a, &Float::with_val(bits, 0))?;
    let mut y: Vec<V2> = Vec::with_capacity(m);
    for k in 0..m {
        let mut r = [-f[k][0].clone(), -f[k][1].clone()];
        if k > 0 {
            let t = mv(&a[k], &mv(&inv[k - 1], &y[k - 1]));
            r[0] += &t[0];
            r[1] += &t[1];
        }
        y.push(r);
    }
    let mut z: Vec<V2> = vec![[Float::new(bits), Float::new(bits)]; m];
    for k in (0..m).rev() {
        let mut w = y[k].clone();
        if k + 1 < m {
            let t = mtv(&a[k + 1], &z[k + 1]);
            w[0] += &t[0];
            w[1] += &t[1];
        }
        z[k] = mv(&inv[k], &w);
    }
    let mut e: Vec<V2> = Vec::with_capacity(m + 1);
    for j in 0..=m {
        let mut ej = if j < m {
            mtv(&a[j], &z[j])
        } else {
            [Float::with_val(bits, 0), Float::with_val(bits, 0)]
        };
        if j > 0 {
            ej[0] -= &z[j - 1][0];
            ej[1] -= &z[j - 1][1];
        }
        e.push(ej);
    }
    Some(e)
}

/// Geometric bisection steps of the λ_min(JJᵀ) bracket: from [2⁻⁸⁰, ~1] the ratio of the
/// bracket falls below 2^(80/2¹⁰) < 1.06, so K is certified to within 3 %.
pub(super) const BISECTION_STEPS: usize = 10;
/// Smallest λ_min(JJᵀ) tried: K ≤ 2⁴⁰. A larger K means a near-singular linearisation (a
/// grazing collision), where the argument is worthless anyway.
pub(super) const MU_FLOOR_LOG2: i32 = -80;

/// A certified K ≥ ‖J⁺‖₂ = 1/√λ_min(JJᵀ): the largest μ of a geometric bisection for which the
/// LDLᵀ pivots of JJᵀ − μI are positive definite, lowered by an allowance for the rounding of
/// JJᵀ and of the sweep (2^(16−P)·(1 + max‖A_k‖²), Weyl's inequality with a generous backward
/// error of the block sweep). `None` if even μ = 2⁻⁸⁰ fails.
pub(super) fn inverse_bound(a: &[M2], bits: u32) -> Option<f64> {
    let ok = |mu: f64| pivot_inverses(a, &Float::with_val(bits, mu)).is_some();
    // λ_min ≤ any diagonal entry of JJᵀ (a Rayleigh quotient): 1 + the smallest row norm².
    let hi0 = a
        .iter()
        .map(|x| 1.0 + (x[0].to_f64().powi(2) + x[1].to_f64().powi(2)))
        .fold(f64::INFINITY, f64::min);
    let mut lo = (MU_FLOOR_LOG2 as f64).exp2();
    let mut hi = hi0 * 1.01;
    if !ok(lo) {
        return None;
    }
    for _ in 0..BISECTION_STEPS {
        let mid = (lo * hi).sqrt();
        if ok(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let amax = a.iter().map(m_norm).fold(0.0, f64::max);
    let mu = lo - (16.0 - bits as f64).exp2() * (1.0 + amax * amax);
    (mu > 0.0).then(|| 1.0 / mu.sqrt())
}
