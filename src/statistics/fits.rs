//! Weighted least squares with χ²: lines, quadratics and polynomials through values with
//! standard errors, and the weighted mean (the sweep's fits and the escape-rate extrapolation).
//! Their data are what a run computed (the analyses refuse too few points first, naming their
//! parameters), so data a fit cannot take is a failure of the run ([`Error::Failed`]).

use serde::{Deserialize, Serialize};

use crate::Error;

/// Weights 1/σ², refusing errors that are zero, negative or not finite.
fn weights(sigma: &[f64]) -> Result<Vec<f64>, Error> {
    if let Some(s) = sigma.iter().find(|s| !(s.is_finite() && **s > 0.0)) {
        return Err(Error::Failed(format!(
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
/// use lorentz_gas::statistics::fits::weighted_line_fit;
/// let f = weighted_line_fit(&[0.0, 1.0, 2.0], &[1.0, 3.0, 5.0], &[0.1, 0.1, 0.1]).unwrap();
/// assert!((f.intercept - 1.0).abs() < 1e-12 && (f.slope - 2.0).abs() < 1e-12);
/// assert!(f.chi2 < 1e-20 && f.dof == 1);
/// // Var(slope) = 1/Σw(x − x̄)² = 0.01/2.
/// assert!((f.var_slope - 0.005).abs() < 1e-15);
/// ```
pub fn weighted_line_fit(x: &[f64], y: &[f64], sigma: &[f64]) -> Result<LineFit, Error> {
    if x.len() != y.len() || x.len() != sigma.len() || x.len() < 2 {
        return Err(Error::Failed(
            "a straight-line fit needs at least two points, each with x, y and an error".into(),
        ));
    }
    let w = weights(sigma)?;
    let sw: f64 = w.iter().sum();
    let xm = w.iter().zip(x).map(|(w, x)| w * x).sum::<f64>() / sw;
    let ym = w.iter().zip(y).map(|(w, y)| w * y).sum::<f64>() / sw;
    let stt: f64 = w.iter().zip(x).map(|(w, x)| w * (x - xm).powi(2)).sum();
    if stt.is_nan() || stt <= 0.0 {
        return Err(Error::Failed(
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

/// A weighted least-squares quadratic y = c₀ + c₁t + c₂t² in t = x − x₀, with its covariance and χ².
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct QuadraticFit {
    /// The centre x₀.
    pub x0: f64,
    /// (c₀, c₁, c₂).
    pub c: [f64; 3],
    /// Covariance of the coefficients from the input errors.
    pub cov: [[f64; 3]; 3],
    /// χ² of the points about the fit.
    pub chi2: f64,
    /// Degrees of freedom, n − 3.
    pub dof: usize,
}

impl QuadraticFit {
    /// The root nearest t = 0 (as t, relative to x₀) and its standard error by linear propagation,
    /// or `None` if the quadratic has no real root. The roots are formed without cancellation:
    /// q = −(c₁ + sign(c₁)√(c₁² − 4c₀c₂))/2, roots q/c₂ and c₀/q.
    pub fn root_near_zero(&self) -> Option<(f64, f64)> {
        let [c0, c1, c2] = self.c;
        let disc = c1 * c1 - 4.0 * c0 * c2;
        if disc < 0.0 {
            return None;
        }
        let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
        let mut roots = vec![];
        if q != 0.0 {
            roots.push(c0 / q);
        }
        if c2 != 0.0 {
            roots.push(q / c2);
        }
        let t = roots
            .into_iter()
            .min_by(|a, b| a.abs().total_cmp(&b.abs()))?;
        let g = [1.0, t, t * t];
        let mut var = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                var += g[i] * self.cov[i][j] * g[j];
            }
        }
        let slope = c1 + 2.0 * c2 * t;
        Some((t, var.max(0.0).sqrt() / slope.abs()))
    }
}

/// χ² of a weighted least-squares polynomial of `degree` through (x, y ± σ), with x mapped onto
/// [−1, 1] first (so the normal equations stay well conditioned), solved by SVD; with its degrees of
/// freedom n − degree − 1.
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::fits::weighted_polynomial_chi2;
/// let x = [0.0, 1.0, 2.0, 3.0];
/// let y: Vec<f64> = x.iter().map(|x| 1.0 + x * x).collect();
/// let (chi2, dof) = weighted_polynomial_chi2(&x, &y, &[0.1; 4], 2).unwrap();
/// assert!(chi2 < 1e-18 && dof == 1);
/// ```
///
/// # Errors
/// Fewer than degree + 2 points, or an error that is not positive and finite.
pub fn weighted_polynomial_chi2(
    x: &[f64],
    y: &[f64],
    sigma: &[f64],
    degree: usize,
) -> Result<(f64, usize), Error> {
    let n = x.len();
    if y.len() != n || sigma.len() != n || n < degree + 2 {
        return Err(Error::Failed(format!(
            "a degree-{degree} fit with a χ² needs at least {} points, each with x, y and an error",
            degree + 2
        )));
    }
    let w = weights(sigma)?;
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let (mid, half) = (0.5 * (lo + hi), (0.5 * (hi - lo)).max(f64::MIN_POSITIVE));
    let a = nalgebra::DMatrix::from_fn(n, degree + 1, |r, k| {
        ((x[r] - mid) / half).powi(k as i32) * w[r].sqrt()
    });
    let b = nalgebra::DVector::from_fn(n, |r, _| y[r] * w[r].sqrt());
    let c = a
        .clone()
        .svd(true, true)
        .solve(&b, 1e-14)
        .map_err(|e| Error::Failed(format!("polynomial fit: {e}")))?;
    let r = a * c - b;
    Ok((r.norm_squared(), n - degree - 1))
}

/// Weighted least squares of a quadratic through points (x, y ± σ), in t = x − `x0`.
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::fits::weighted_quadratic_fit;
/// let x = [0.0, 1.0, 2.0, 3.0];
/// let y: Vec<f64> = x.iter().map(|x| 1.0 - 2.0 * x + 0.5 * x * x).collect();
/// let q = weighted_quadratic_fit(&x, &y, &[0.1; 4], 1.0).unwrap();
/// // In t = x − 1: y = −0.5 − t + 0.5t², roots t = 1 ± √2.
/// assert!((q.c[0] + 0.5).abs() < 1e-12 && (q.c[1] + 1.0).abs() < 1e-12 && (q.c[2] - 0.5).abs() < 1e-12);
/// let (t, _) = q.root_near_zero().unwrap();
/// assert!((t - (1.0 - 2f64.sqrt())).abs() < 1e-12);
/// ```
pub fn weighted_quadratic_fit(
    x: &[f64],
    y: &[f64],
    sigma: &[f64],
    x0: f64,
) -> Result<QuadraticFit, Error> {
    if x.len() != y.len() || x.len() != sigma.len() || x.len() < 3 {
        return Err(Error::Failed(
            "a quadratic fit needs at least three points, each with x, y and an error".into(),
        ));
    }
    let w = weights(sigma)?;
    let mut n = nalgebra::Matrix3::<f64>::zeros();
    let mut b = nalgebra::Vector3::<f64>::zeros();
    for i in 0..x.len() {
        let t = x[i] - x0;
        let g = nalgebra::Vector3::new(1.0, t, t * t);
        n += w[i] * g * g.transpose();
        b += w[i] * y[i] * g;
    }
    let inv = n
        .try_inverse()
        .ok_or_else(|| Error::Failed("a quadratic fit needs at least three distinct x".into()))?;
    let c = inv * b;
    let chi2 = (0..x.len())
        .map(|i| {
            let t = x[i] - x0;
            ((y[i] - c[0] - c[1] * t - c[2] * t * t) / sigma[i]).powi(2)
        })
        .sum();
    let mut cov = [[0.0; 3]; 3];
    for (i, row) in cov.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = inv[(i, j)];
        }
    }
    Ok(QuadraticFit {
        x0,
        c: [c[0], c[1], c[2]],
        cov,
        chi2,
        dof: x.len() - 3,
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
/// use lorentz_gas::statistics::fits::weighted_mean;
/// let m = weighted_mean(&[1.0, 3.0], &[1.0, 1.0]).unwrap();
/// assert_eq!(m.mean, 2.0);
/// assert!((m.err - 0.5f64.sqrt()).abs() < 1e-15);
/// assert_eq!((m.chi2, m.dof), (2.0, 1));
/// ```
pub fn weighted_mean(x: &[f64], sigma: &[f64]) -> Result<WeightedMean, Error> {
    if x.len() != sigma.len() || x.is_empty() {
        return Err(Error::Failed(
            "a weighted mean needs values with errors".into(),
        ));
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
