//! Honest error bars: batch means, blocking (Flyvbjerg–Petersen), and least-squares fits.

use nalgebra::{DMatrix, DVector};
use num_traits::Float;
use serde::{Deserialize, Serialize};

use crate::error::Error;

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

/// Weights 1/σ², refusing errors that are zero, negative or not finite.
fn weights(sigma: &[f64]) -> Result<Vec<f64>, Error> {
    if let Some(s) = sigma.iter().find(|s| !(s.is_finite() && **s > 0.0)) {
        return Err(Error::Invalid(format!(
            "a weighted fit needs positive finite errors (got {s})"
        )));
    }
    Ok(sigma.iter().map(|s| 1.0 / (s * s)).collect())
}

/// A weighted least-squares straight line y = c₀ + c₁x with its covariance and goodness of fit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LineFit {
    /// c₀.
    pub intercept: f64,
    /// c₁.
    pub slope: f64,
    /// Var(c₀) from the input errors.
    pub var_intercept: f64,
    /// Var(c₁).
    pub var_slope: f64,
    /// Cov(c₀, c₁).
    pub cov: f64,
    /// χ² = Σ ((y − c₀ − c₁x)/σ)².
    pub chi2: f64,
    /// Degrees of freedom, n − 2.
    pub dof: usize,
}

impl LineFit {
    /// The line at `x`.
    pub fn at(&self, x: f64) -> f64 {
        self.intercept + self.slope * x
    }

    /// χ²/dof (NaN without degrees of freedom).
    pub fn chi2_per_dof(&self) -> f64 {
        if self.dof == 0 {
            f64::NAN
        } else {
            self.chi2 / self.dof as f64
        }
    }

    /// Where the line crosses zero, x* = −c₀/c₁, with its standard error by linear propagation:
    /// Var x* = (Var c₀ + x*² Var c₁ + 2x* Cov)/c₁².
    pub fn root(&self) -> (f64, f64) {
        let x = -self.intercept / self.slope;
        let var = (self.var_intercept + x * x * self.var_slope + 2.0 * x * self.cov)
            / (self.slope * self.slope);
        (x, var.max(0.0).sqrt())
    }
}

/// Weighted least squares of a straight line through points (x, y ± σ), in coordinates centred on
/// the weighted mean of x (so the normal equations are diagonal and cannot cancel).
///
/// # Examples
///
/// ```
/// use lorentz_gas::stats::weighted_line_fit;
/// let f = weighted_line_fit(&[0.0, 1.0, 2.0], &[1.0, 3.0, 5.0], &[0.1, 0.1, 0.1]).unwrap();
/// assert!((f.intercept - 1.0).abs() < 1e-12 && (f.slope - 2.0).abs() < 1e-12);
/// assert!(f.chi2 < 1e-20 && f.dof == 1);
/// // Var(slope) = 1/Σw(x − x̄)² = 0.01/2.
/// assert!((f.var_slope - 0.005).abs() < 1e-15);
/// ```
pub fn weighted_line_fit(x: &[f64], y: &[f64], sigma: &[f64]) -> Result<LineFit, Error> {
    if x.len() != y.len() || x.len() != sigma.len() || x.len() < 2 {
        return Err(Error::Invalid(
            "a straight-line fit needs at least two points, each with x, y and an error".into(),
        ));
    }
    let w = weights(sigma)?;
    let sw: f64 = w.iter().sum();
    let xm = w.iter().zip(x).map(|(w, x)| w * x).sum::<f64>() / sw;
    let ym = w.iter().zip(y).map(|(w, y)| w * y).sum::<f64>() / sw;
    let stt: f64 = w.iter().zip(x).map(|(w, x)| w * (x - xm).powi(2)).sum();
    if stt.is_nan() || stt <= 0.0 {
        return Err(Error::Invalid(
            "a straight-line fit needs at least two distinct x".into(),
        ));
    }
    let sty: f64 = w
        .iter()
        .zip(x.iter().zip(y))
        .map(|(w, (x, y))| w * (x - xm) * (y - ym))
        .sum();
    let slope = sty / stt;
    let (var_a, var_b) = (1.0 / sw, 1.0 / stt);
    let intercept = ym - slope * xm;
    let chi2 = (0..x.len())
        .map(|i| ((y[i] - intercept - slope * x[i]) / sigma[i]).powi(2))
        .sum();
    Ok(LineFit {
        intercept,
        slope,
        var_intercept: var_a + xm * xm * var_b,
        var_slope: var_b,
        cov: -xm * var_b,
        chi2,
        dof: x.len() - 2,
    })
}

/// A weighted mean with its error and the χ² of the values about it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WeightedMean {
    /// Σ(x/σ²)/Σ(1/σ²).
    pub mean: f64,
    /// (Σ 1/σ²)^(−1/2): the error if the values scatter as their errors say.
    pub err: f64,
    /// χ² = Σ ((x − mean)/σ)².
    pub chi2: f64,
    /// n − 1.
    pub dof: usize,
}

/// The inverse-variance weighted mean of values x ± σ.
///
/// # Examples
///
/// ```
/// use lorentz_gas::stats::weighted_mean;
/// let m = weighted_mean(&[1.0, 3.0], &[1.0, 1.0]).unwrap();
/// assert_eq!(m.mean, 2.0);
/// assert!((m.err - 0.5f64.sqrt()).abs() < 1e-15);
/// assert_eq!((m.chi2, m.dof), (2.0, 1));
/// ```
pub fn weighted_mean(x: &[f64], sigma: &[f64]) -> Result<WeightedMean, Error> {
    if x.len() != sigma.len() || x.is_empty() {
        return Err(Error::Invalid("a weighted mean needs values with errors".into()));
    }
    let w = weights(sigma)?;
    let sw: f64 = w.iter().sum();
    let mean = w.iter().zip(x).map(|(w, x)| w * x).sum::<f64>() / sw;
    let chi2 = x
        .iter()
        .zip(sigma)
        .map(|(x, s)| ((x - mean) / s).powi(2))
        .sum();
    Ok(WeightedMean {
        mean,
        err: sw.sqrt().recip(),
        chi2,
        dof: x.len() - 1,
    })
}

/// Probability that a χ² variable with `dof` degrees of freedom exceeds `chi2` (the p-value of a
/// consistency check); NaN without degrees of freedom.
///
/// # Examples
///
/// ```
/// use lorentz_gas::stats::chi2_p_value;
/// // The median of χ² with 1 degree of freedom is 0.4549…
/// assert!((chi2_p_value(0.454936, 1) - 0.5).abs() < 1e-5);
/// ```
pub fn chi2_p_value(chi2: f64, dof: usize) -> f64 {
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    match ChiSquared::new(dof as f64) {
        Ok(d) if dof > 0 => d.sf(chi2),
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
