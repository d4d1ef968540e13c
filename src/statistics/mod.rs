//! Honest error bars: batch means, blocking (Flyvbjerg–Petersen), and least-squares fits.

use nalgebra::{DMatrix, DVector};
use num_traits::Float;

pub mod comparison;
pub mod fits;
pub mod outlier;

/// Mean and standard error of the mean of independent values (the batch-means estimator).
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::mean_se;
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
/// use lorentz_gas::statistics::blocking_se;
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
/// use lorentz_gas::statistics::linear_fit;
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
/// P(T > t) = `p`.
///
/// A z-score (x̄ − μ)/SE whose SE comes from the spread of `n` independent batch means is
/// Student-t with n − 1 degrees of freedom, not normal; with few batches its tails are much
/// heavier (t₃ exceeds 4 with probability 0.028, a normal with 6.3·10⁻⁵).
///
/// Method: statrs's inverse CDF (inverse regularised incomplete beta) as the start, polished by
/// Newton steps on ln P(T > t) = ln p with statrs's CDF and density (in ln t for t > 1, where
/// the tail is a power law), evaluated as the lower tail F(−t) so that a tiny `p` keeps its
/// relative accuracy; the start alone is off by up to 30 % at dof ≳ 10⁵ or dof < 1. Above
/// 10³ dof the Cornish–Fisher series in 1/dof to fourth order about the normal quantile
/// (Abramowitz & Stegun 26.7.5; truncation < 10⁻⁹ relative for |t| ≤ 6). Relative error
/// < 10⁻⁹ against 40-digit values for dof ∈ [0.5, 10⁷] and p ∈ [10⁻⁷, 0.3] (unit test).
/// `dof = f64::INFINITY` gives the normal quantile.
///
/// # Panics
///
/// If `dof` is not positive (or NaN), `p` is not in (0, 1), or the quantile overflows (dof ≪ 1
/// with a tiny `p`): the function never returns NaN or an infinity.
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::student_t_quantile;
/// // Textbook values: t₃(0.025) = 3.182446, t₁₅(0.005) = 2.946713.
/// assert!((student_t_quantile(3.0, 0.025) - 3.182446).abs() < 1e-5);
/// assert!((student_t_quantile(15.0, 0.005) - 2.946713).abs() < 1e-5);
/// // One degree of freedom is the Cauchy distribution: t = 1/tan(πp).
/// let p = 1e-4;
/// let cauchy = 1.0 / (std::f64::consts::PI * p).tan();
/// assert!((student_t_quantile(1.0, p) / cauchy - 1.0).abs() < 1e-9);
/// // Symmetric: the lower quantile is the negative upper one.
/// assert!((student_t_quantile(7.0, 0.975) + student_t_quantile(7.0, 0.025)).abs() < 1e-12);
/// // Infinitely many: the normal quantile, z(0.025) = 1.959964.
/// assert!((student_t_quantile(f64::INFINITY, 0.025) - 1.959964).abs() < 1e-6);
/// ```
pub fn student_t_quantile(dof: f64, p: f64) -> f64 {
    use statrs::distribution::{Continuous, ContinuousCDF, Normal, StudentsT};
    assert!(dof > 0.0, "Student-t needs dof > 0, got {dof}");
    assert!(p > 0.0 && p < 1.0, "a quantile needs 0 < p < 1, got {p}");
    if p > 0.5 {
        return -student_t_quantile(dof, 1.0 - p);
    }
    if p == 0.5 {
        return 0.0;
    }
    let t = if dof > 1e3 {
        // Upper normal quantile, then the Cornish–Fisher corrections g₁/ν … g₄/ν⁴.
        let z = -Normal::new(0.0, 1.0)
            .expect("standard normal")
            .inverse_cdf(p);
        let (z2, v) = (z * z, 1.0 / dof);
        let g1 = z * (z2 + 1.0) / 4.0;
        let g2 = z * ((5.0 * z2 + 16.0) * z2 + 3.0) / 96.0;
        let g3 = z * (((3.0 * z2 + 19.0) * z2 + 17.0) * z2 - 15.0) / 384.0;
        let g4 = z * ((((79.0 * z2 + 776.0) * z2 + 1482.0) * z2 - 1920.0) * z2 - 945.0) / 92160.0;
        z + v * (g1 + v * (g2 + v * (g3 + v * g4)))
    } else {
        let dist = StudentsT::new(0.0, 1.0, dof).expect("dof > 0 was checked");
        let mut t = -dist.inverse_cdf(p);
        if !(t.is_finite() && t > 0.0) {
            t = 1.0;
        }
        let lp = p.ln();
        for _ in 0..100 {
            let (tail, dens) = (dist.cdf(-t), dist.pdf(t));
            if !(tail > 0.0 && dens > 0.0) {
                break;
            }
            // h(t) = ln S(t) − ln p, h'(t) = −f(t)/S(t).
            let r = (tail.ln() - lp) * tail / dens;
            let next = if t > 1.0 {
                t * (r / t).clamp(-2.0, 2.0).exp()
            } else {
                (t + r).max(0.5 * t)
            };
            let done = (next - t).abs() <= 4.0 * f64::EPSILON * t;
            t = next;
            if done {
                break;
            }
        }
        t
    };
    assert!(
        t.is_finite() && t > 0.0,
        "t quantile ({dof}, {p}) is not finite"
    );
    t
}

/// Two-sided tail probability of a standard normal beyond ±`sigmas`: erfc(σ/√2)
/// (4σ: 6.334·10⁻⁵).
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::normal_two_sided_tail;
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
/// use lorentz_gas::statistics::{normal_sigma_equivalent_t, normal_two_sided_tail, student_t_quantile};
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
/// use lorentz_gas::statistics::welch_dof;
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
            assert!(
                n >= 2.0,
                "a standard error needs at least 2 values, got {n}"
            );
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

/// Probability that an F(d₁, d₂) variable exceeds `f` (NaN without degrees of freedom).
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::f_p_value;
/// // F(1, d) is t²_d: P(F > 4.3027²) = P(|t₂| > 4.3027) = 0.05.
/// assert!((f_p_value(4.302653f64.powi(2), 1.0, 2.0) - 0.05).abs() < 1e-6);
/// ```
pub fn f_p_value(f: f64, d1: f64, d2: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, FisherSnedecor};
    match FisherSnedecor::new(d1, d2) {
        Ok(d) if f.is_finite() => d.sf(f),
        _ => f64::NAN,
    }
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
    /// The sum from its running total and its compensation (as kept in vector lanes by
    /// [`crate::observers::counters::CounterLanes`]).
    pub fn from_parts(sum: f64, c: f64) -> Self {
        CompensatedSum { sum, c }
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
        let mut r = crate::scenes::sampling::stream(3, 0);
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
        // References from mpmath's regularised incomplete beta at 40 digits. p4 is the
        // 4σ-equivalent upper tail erfc(4/√2)/2 = 3.1671e-5.
        let p4 = 0.5 * normal_two_sided_tail(4.0);
        for (dof, p, t) in [
            (1.0, p4, 10050.4390326909),
            (3.0, p4, 32.6163970286674),
            (7.0, p4, 8.46692510346444),
            (15.0, p4, 5.48037608187021),
            (31.0, p4, 4.62163208514282),
            // Fractional (Welch–Satterthwaite) and extreme dof, where statrs's inverse CDF
            // alone is off by up to 30 %.
            (0.5, p4, 102534584.717637),
            (1.3, 1e-7, 107353.309282300),
            (2.5, 0.025, 3.57465484200368),
            (20.7, p4, 4.99357710686065),
            (999.0, p4, 4.01708145272838),
            (1001.0, 0.025, 1.96233670528088),
            (1e5, 0.025, 1.95998770753461),
            (9e6, 1e-3, 3.09023321173795),
        ] {
            let q = student_t_quantile(dof, p);
            assert!((q / t - 1.0).abs() < 1e-9, "dof {dof}, p {p}: {q} vs {t}");
            // 1 − p is rounded: the lower quantile agrees to that rounding.
            let lower = student_t_quantile(dof, 1.0 - p);
            assert!(
                (lower / q + 1.0).abs() < 1e-9,
                "dof {dof}, p {p}: {lower} vs {q}"
            );
        }
        // Monotone in dof, and no jump where the series takes over.
        let (a, b) = (
            student_t_quantile(1e3 - 1e-9, p4),
            student_t_quantile(1e3 + 1e-9, p4),
        );
        assert!((a - b).abs() < 1e-9, "{a} {b}");
        assert!(student_t_quantile(4.0, p4) < student_t_quantile(3.0, p4));
        assert!((student_t_quantile(f64::INFINITY, p4) - 4.0).abs() < 1e-9);
        assert_eq!(student_t_quantile(2.0, 0.5), 0.0);
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
