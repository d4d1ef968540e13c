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
