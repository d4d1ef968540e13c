//! Honest error bars: batch means, blocking (Flyvbjerg–Petersen), and least-squares fits.

use nalgebra::{DMatrix, DVector};
use num_traits::Float;

/// Mean and standard error of the mean of independent values (the batch-means estimator).
///
/// # Examples
///
/// ```
/// use lorentz_gas::stats::mean_se;
/// let (m, se) = mean_se(&[1.0f64, 2.0, 3.0, 4.0]);
/// assert_eq!(m, 2.5);
/// assert!((se - (5.0f64 / 12.0).sqrt()).abs() < 1e-15);
/// ```
pub fn mean_se<F: Float>(xs: &[F]) -> (F, F) {
    let n = F::from(xs.len()).unwrap();
    let mean = xs.iter().fold(F::zero(), |a, &x| a + x) / n;
    if xs.len() < 2 {
        return (mean, F::nan());
    }
    let var = xs
        .iter()
        .fold(F::zero(), |a, &x| a + (x - mean) * (x - mean))
        / (n - F::one());
    (mean, (var / n).sqrt())
}

/// Standard error of the mean of a correlated series by blocking (Flyvbjerg & Petersen 1989):
/// pairwise block averaging until the naive error estimate stops growing. Returns the estimate
/// at the first level whose value agrees with the next within its own uncertainty
/// (σ_SE/SE = 1/√(2(n−1))), or the largest level with at least 32 blocks.
///
/// # Examples
///
/// ```
/// use lorentz_gas::stats::blocking_se;
/// // Independent values: blocking returns about the naive error.
/// let xs: Vec<f64> = (0..4096).map(|i| ((i * 7919) % 1000) as f64).collect();
/// let se = blocking_se(&xs);
/// assert!(se > 0.0);
/// ```
pub fn blocking_se(xs: &[f64]) -> f64 {
    let mut cur: Vec<f64> = xs.to_vec();
    let mut levels: Vec<(f64, f64)> = Vec::new(); // (se, its uncertainty)
    while cur.len() >= 32 {
        let n = cur.len() as f64;
        let (_, se) = mean_se(&cur);
        levels.push((se, se / (2.0 * (n - 1.0)).sqrt()));
        cur = cur.chunks_exact(2).map(|c| 0.5 * (c[0] + c[1])).collect();
    }
    if levels.is_empty() {
        return mean_se(xs).1;
    }
    for k in 0..levels.len().saturating_sub(1) {
        let (se, err) = levels[k];
        let next = levels[k + 1].0;
        if k > 0 && (next - se).abs() <= err {
            return se.max(next);
        }
    }
    levels.iter().map(|l| l.0).fold(0.0, f64::max)
}

/// Ordinary least-squares straight line y = c₀ + c₁x, solved by SVD (nalgebra).
/// Returns `(intercept, slope)`.
///
/// # Examples
///
/// ```
/// use lorentz_gas::stats::linear_fit;
/// let (c0, c1) = linear_fit(&[0.0, 1.0, 2.0], &[1.0, 3.0, 5.0]);
/// assert!((c0 - 1.0).abs() < 1e-12 && (c1 - 2.0).abs() < 1e-12);
/// ```
pub fn linear_fit(x: &[f64], y: &[f64]) -> (f64, f64) {
    assert_eq!(x.len(), y.len());
    let n = x.len();
    let m = DMatrix::from_fn(n, 2, |r, c| if c == 0 { 1.0 } else { x[r] });
    let b = DVector::from_column_slice(y);
    let sol = m.svd(true, true).solve(&b, 1e-14).expect("SVD solve");
    (sol[0], sol[1])
}

/// Upper quantile of Student's t distribution with `dof` degrees of freedom: the `t` with
/// P(T > t) = `p`. `dof = f64::INFINITY` (or beyond 10⁷, where the two differ by < 10⁻⁵ at the
/// tails used here) gives the standard normal quantile. Computed as −F⁻¹(p) (statrs's inverse
/// regularised incomplete beta), so a tiny `p` keeps its relative accuracy instead of going
/// through 1 − p.
///
/// A z-score (x̄ − μ)/SE whose SE comes from the spread of `n` independent batch means is
/// Student-t with n − 1 degrees of freedom, not normal; with few batches its tails are much
/// heavier (t₃ exceeds 4 with probability 0.028, a normal with 6.3·10⁻⁵).
///
/// # Panics
///
/// If `dof` is not positive (or NaN) or `p` is not in (0, 1): there is no finite quantile, and the
/// function never returns NaN or an infinity.
///
/// # Examples
///
/// ```
/// use lorentz_gas::stats::student_t_quantile;
/// // Textbook values: t₃(0.025) = 3.182446, t₁₅(0.005) = 2.946713.
/// assert!((student_t_quantile(3.0, 0.025) - 3.182446).abs() < 1e-5);
/// assert!((student_t_quantile(15.0, 0.005) - 2.946713).abs() < 1e-5);
/// // One degree of freedom is the Cauchy distribution: t = 1/tan(πp).
/// let p = 1e-4;
/// let cauchy = 1.0 / (std::f64::consts::PI * p).tan();
/// assert!((student_t_quantile(1.0, p) / cauchy - 1.0).abs() < 1e-9);
/// // Infinitely many: the normal quantile, z(0.025) = 1.959964.
/// assert!((student_t_quantile(f64::INFINITY, 0.025) - 1.959964).abs() < 1e-6);
/// ```
pub fn student_t_quantile(dof: f64, p: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, Normal, StudentsT};
    assert!(dof > 0.0, "Student-t needs dof > 0, got {dof}");
    assert!(p > 0.0 && p < 1.0, "a quantile needs 0 < p < 1, got {p}");
    let q = if dof > 1e7 {
        -Normal::new(0.0, 1.0).expect("standard normal").inverse_cdf(p)
    } else {
        -StudentsT::new(0.0, 1.0, dof)
            .expect("dof > 0 was checked")
            .inverse_cdf(p)
    };
    assert!(q.is_finite(), "t quantile ({dof}, {p}) is not finite");
    q
}

/// Two-sided tail probability of a standard normal beyond ±`sigmas`: erfc(σ/√2)
/// (4σ: 6.334·10⁻⁵).
///
/// # Examples
///
/// ```
/// use lorentz_gas::stats::normal_two_sided_tail;
/// assert!((normal_two_sided_tail(1.96) - 0.05).abs() < 1e-4);
/// assert!((normal_two_sided_tail(4.0) / 6.334248e-5 - 1.0).abs() < 1e-6);
/// ```
pub fn normal_two_sided_tail(sigmas: f64) -> f64 {
    statrs::function::erf::erfc(sigmas / std::f64::consts::SQRT_2)
}

/// The "kσ-equivalent" threshold for a Student-t statistic with `dof` degrees of freedom: the
/// |t| exceeded with the same two-sided probability as |z| > `sigmas` for a normal z. Use it for
/// a z-score whose standard error is estimated from n batch means (dof = n − 1), or with
/// [`welch_dof`] for the difference of two such estimates.
///
/// # Examples
///
/// ```
/// use lorentz_gas::stats::{normal_sigma_equivalent_t, normal_two_sided_tail, student_t_quantile};
/// // With 4 batches (3 dof) "4σ" is |t| < 32.616, with 16 batches (15 dof) |t| < 5.4804.
/// let t3 = normal_sigma_equivalent_t(3.0, 4.0);
/// assert!((t3 - student_t_quantile(3.0, normal_two_sided_tail(4.0) / 2.0)).abs() < 1e-12);
/// assert!((t3 - 32.6164).abs() < 1e-3);
/// let t15 = normal_sigma_equivalent_t(15.0, 4.0);
/// assert!((t15 - 5.48038).abs() < 1e-4);
/// // Many dof: back to 4.
/// assert!((normal_sigma_equivalent_t(f64::INFINITY, 4.0) - 4.0).abs() < 1e-9);
/// ```
pub fn normal_sigma_equivalent_t(dof: f64, sigmas: f64) -> f64 {
    assert!(sigmas > 0.0, "sigmas must be positive, got {sigmas}");
    student_t_quantile(dof, 0.5 * normal_two_sided_tail(sigmas))
}

/// Welch–Satterthwaite effective degrees of freedom of the difference of two *independent*
/// means with standard errors `se1`, `se2` estimated from `n1`, `n2` values:
/// ν = (s₁² + s₂²)² / (s₁⁴/(n₁ − 1) + s₂⁴/(n₂ − 1)). It lies between min(n₁, n₂) − 1 and
/// n₁ + n₂ − 2. A term with zero standard error (an exact value) drops out, so
/// `welch_dof(se, n, 0.0, 1.0)` = n − 1. (For two estimates from the *same* batches the
/// conservative choice is min(n₁, n₂) − 1.)
///
/// # Panics
///
/// If both standard errors are zero or an `n` with a non-zero error is below 2.
///
/// # Examples
///
/// ```
/// use lorentz_gas::stats::welch_dof;
/// assert_eq!(welch_dof(0.1, 16.0, 0.1, 16.0), 30.0);
/// assert_eq!(welch_dof(0.1, 4.0, 0.0, 1.0), 3.0);
/// let nu = welch_dof(1.0, 4.0, 0.1, 16.0);
/// assert!(nu > 3.0 && nu < 3.1);
/// ```
pub fn welch_dof(se1: f64, n1: f64, se2: f64, n2: f64) -> f64 {
    let (v1, v2) = (se1 * se1, se2 * se2);
    let term = |v: f64, n: f64| {
        if v == 0.0 {
            0.0
        } else {
            assert!(n >= 2.0, "a standard error needs at least 2 values, got {n}");
            v * v / (n - 1.0)
        }
    };
    let den = term(v1, n1) + term(v2, n2);
    assert!(
        den > 0.0 && den.is_finite(),
        "welch_dof: standard errors {se1}, {se2}"
    );
    (v1 + v2) * (v1 + v2) / den
}

/// Neumaier's compensated sum (for long accumulations of flight times).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CompensatedSum {
    sum: f64,
    c: f64,
}

impl CompensatedSum {
    /// Adds `x`.
    #[inline(always)]
    pub fn add(&mut self, x: f64) {
        let t = self.sum + x;
        if self.sum.abs() >= x.abs() {
            self.c += (self.sum - t) + x;
        } else {
            self.c += (x - t) + self.sum;
        }
        self.sum = t;
    }
    /// The compensated total.
    pub fn value(&self) -> f64 {
        self.sum + self.c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocking_sees_correlation() {
        // An AR(1) series with ρ = 0.9 has SE inflated by √((1+ρ)/(1−ρ)) ≈ 4.36.
        let mut r = crate::sampling::stream(3, 0);
        use rand::Rng;
        let n = 1 << 16;
        let mut x = 0.0;
        let xs: Vec<f64> = (0..n)
            .map(|_| {
                x = 0.9 * x + (r.random::<f64>() - 0.5);
                x
            })
            .collect();
        let naive = mean_se(&xs).1;
        let b = blocking_se(&xs);
        let ratio = b / naive;
        // Expected 4.36; blocking's own uncertainty at the chosen level is ≲ 15 %.
        assert!(ratio > 3.5 && ratio < 5.2, "ratio {ratio}");
    }

    #[test]
    fn t_quantiles_match_high_precision_values_and_join_the_normal() {
        // 4σ-equivalent (upper p = erfc(4/√2)/2 = 3.1671e-5) from mpmath's regularised
        // incomplete beta at 30 digits.
        let p = 0.5 * normal_two_sided_tail(4.0);
        for (dof, t) in [
            (1.0, 10050.439032690882),
            (3.0, 32.616397028667366),
            (7.0, 8.466925103464440),
            (15.0, 5.480376081870212),
            (31.0, 4.621632085142824),
        ] {
            let q = student_t_quantile(dof, p);
            assert!((q / t - 1.0).abs() < 1e-9, "dof {dof}: {q} vs {t}");
        }
        // No jump where the normal takes over; monotone in dof.
        let (a, b) = (student_t_quantile(9.9e6, p), student_t_quantile(1.01e7, p));
        assert!(a >= b && a - b < 1e-5, "{a} {b}");
        assert!(student_t_quantile(4.0, p) < student_t_quantile(3.0, p));
    }

    #[test]
    fn compensated_sum_is_exact_on_a_hard_case() {
        let mut s = CompensatedSum::default();
        s.add(1e16);
        for _ in 0..1000 {
            s.add(1.0);
        }
        s.add(-1e16);
        assert_eq!(s.value(), 1000.0);
    }
}
