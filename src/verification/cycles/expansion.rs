//! Cycle expansions: the spectral determinant and the dynamical zeta function of the flow,
//! expanded in cycle length (curvature expansion), their leading zero s₀(β), and from it the
//! escape rate γ = −s₀(0), the mean Lyapunov exponent λ = s₀′(0) on the repeller, the KS entropy
//! h_KS = λ − γ and the partial dimension d with s₀(1 − d) = 0 (`proofs-notes/cycles.md`).

use rug::Float;
use rug::ops::Pow;
use serde::{Deserialize, Serialize};

use crate::Error;

/// Precision of the expansion's arithmetic (bits): the curvatures cancel to ~10⁻¹⁵ at length
/// 12, far above 2⁻¹²⁸.
pub const EXPANSION_BITS: u32 = 128;

/// One prime cycle as the expansion weighs it: topological length n_p, period T_p and the
/// expanding eigenvalue Λ_p (signed: its sign enters the spectral determinant).
#[derive(Debug, Clone)]
pub struct CycleWeight {
    /// Topological length n_p (the power of z).
    pub length: usize,
    /// Period T_p.
    pub period: Float,
    /// Expanding eigenvalue Λ_p (|Λ_p| > 1).
    pub stability: Float,
}

/// Which function of s is expanded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Expansion {
    /// det(s − A) = ∏_p ∏_{k≥0} (1 − t_p/Λ_p^k)^{k+1}: entire for the three-disk flow, its
    /// cycle expansion converges super-exponentially.
    SpectralDeterminant,
    /// 1/ζ(s) = ∏_p (1 − t_p): its expansion converges exponentially (the zeta function has
    /// poles from the next factor of the determinant).
    ZetaFunction,
}

/// The curvature-expanded function at (s, β) truncated at length `n`: with
/// t_p = e^{βA_p − sT_p}/|Λ_p| (A_p = ln|Λ_p|) and z = 1, ln F = −Σ_m c_m, c_m summing
/// (1/r)·e^{r(βA_p − sT_p)}·w_r(Λ_p) over the cycles and repeats with r·n_p = m
/// (w_r = 1/|det(1 − M_p^r)| = 1/(|Λ_p|^r(1 − Λ_p^{−r})²) for the determinant, 1/|Λ_p|^r for
/// the zeta function); exp is expanded as a power series in z (a₀ = 1,
/// a_m = −(1/m)Σ_k k c_k a_{m−k}) and F_n = Σ_{m≤n} a_m.
pub fn truncated(
    cycles: &[CycleWeight],
    n: usize,
    kind: Expansion,
    s: &Float,
    beta: &Float,
) -> Float {
    let b = EXPANSION_BITS;
    let mut c: Vec<Float> = (0..=n).map(|_| Float::new(b)).collect();
    for p in cycles.iter().filter(|p| p.length <= n) {
        let lam = Float::with_val(b, &p.stability);
        let abs = lam.clone().abs();
        let exponent = beta.clone() * &abs.clone().ln() - &(s.clone() * &p.period);
        for r in 1..=n / p.length {
            let r_f = Float::with_val(b, r);
            let mut w = (exponent.clone() * &r_f).exp() / &abs.clone().pow(r as u32);
            if kind == Expansion::SpectralDeterminant {
                let q = Float::with_val(b, 1) - &lam.clone().pow(r as u32).recip();
                w /= q.square();
            }
            c[r * p.length] += w / &r_f;
        }
    }
    exp_series(&c)
        .into_iter()
        .fold(Float::new(b), |acc, x| acc + x)
}

/// A coefficient of a power series in z that [`exp_series`] can exponentiate: a number, or a
/// jet of a function and its derivatives ([`super::lattice::averages::Jet`]).
pub(crate) trait Coefficient: Clone {
    /// The additive identity.
    fn zero() -> Self;
    /// The multiplicative identity.
    fn one() -> Self;
    /// `self + other`.
    fn plus(&self, other: &Self) -> Self;
    /// `self × other`.
    fn times(&self, other: &Self) -> Self;
    /// `self × k / m`.
    fn ratio(&self, k: i64, m: u32) -> Self;
}

impl Coefficient for Float {
    fn zero() -> Self {
        Float::new(EXPANSION_BITS)
    }
    fn one() -> Self {
        Float::with_val(EXPANSION_BITS, 1)
    }
    fn plus(&self, other: &Self) -> Self {
        self.clone() + other
    }
    fn times(&self, other: &Self) -> Self {
        self.clone() * other
    }
    fn ratio(&self, k: i64, m: u32) -> Self {
        self.clone() * k / m
    }
}

/// The coefficients a₀ … a_n of exp(−Σ_{m=1}^{n} c_m z^m) (`c[0]` unused): a₀ = 1,
/// a_m = −(1/m) Σ_{k=1}^{m} k c_k a_{m−k}. With c_m the sum of t_p^r/r over the prime cycles
/// and repeats of length r·n_p = m, Σ a_m z^m is ∏_p (1 − t_p) expanded to z^n: the
/// curvature expansion of a dynamical zeta function (or, with the determinant's weights, of the
/// spectral determinant).
pub(crate) fn exp_series<C: Coefficient>(c: &[C]) -> Vec<C> {
    let mut a: Vec<C> = vec![C::one()];
    for m in 1..c.len() {
        let mut sum = C::zero();
        for k in 1..=m {
            sum = sum.plus(&c[k].times(&a[m - k]).ratio(k as i64, 1));
        }
        a.push(sum.ratio(-1, m as u32));
    }
    a
}

/// Newton's method for a zero of `f` from `x0` (central differences of step 2⁻⁴⁰), to 2⁻¹⁰⁰.
fn zero_of(f: impl Fn(&Float) -> Float, x0: Float) -> Result<Float, Error> {
    let h = Float::with_val(EXPANSION_BITS, -40f64).exp2();
    let mut x = x0;
    for _ in 0..100 {
        let fx = f(&x);
        let d = (f(&(x.clone() + &h)) - f(&(x.clone() - &h))) / (h.clone() * 2u32);
        let step = fx / d;
        if !step.is_finite() {
            break;
        }
        x -= &step;
        if step.abs() < 1e-30 {
            return Ok(x);
        }
    }
    Err(Error::Failed(
        "the leading zero of the cycle expansion was not found (Newton diverged): near \
         touching disks (R/a below about 2.05) pruning makes the truncated expansion \
         ill-conditioned; use a larger side or a shorter --max-length"
            .into(),
    ))
}

/// One truncation of the expansion: the averages from the cycles up to length `max_length`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Truncation {
    /// Longest cycle (topological length) in the expansion.
    pub max_length: usize,
    /// Escape rate γ = −s₀(0).
    pub escape_rate: f64,
    /// |γ_N − γ_{N−1}|: the truncation error estimate (NaN at N = 1, `null` in JSON).
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub escape_rate_error: f64,
    /// Mean Lyapunov exponent λ = s₀′(0) on the repeller (per unit time).
    pub lyapunov: f64,
    /// |λ_N − λ_{N−1}|.
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub lyapunov_error: f64,
    /// KS entropy h_KS = λ − γ.
    pub entropy: f64,
    /// |h_N − h_{N−1}|.
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub entropy_error: f64,
    /// Partial dimension d: s₀(1 − d) = 0 (Bowen's equation).
    pub partial_dimension: f64,
    /// |d_N − d_{N−1}|.
    #[serde(deserialize_with = "crate::estimators::field::nan_if_null")]
    pub partial_dimension_error: f64,
    /// γ at the working precision of the expansion.
    #[serde(skip)]
    pub escape_rate_exact: Option<Float>,
}

/// The convergence table of the expansion `kind` for N = 1 … `max_length`.
///
/// # Errors
/// No cycle of length 1 (the expansion needs one to start), or a zero not found.
pub fn convergence_table(
    cycles: &[CycleWeight],
    max_length: usize,
    kind: Expansion,
) -> Result<Vec<Truncation>, Error> {
    let b = EXPANSION_BITS;
    let shortest = cycles
        .iter()
        .min_by_key(|p| p.length)
        .ok_or_else(|| Error::Failed("no cycles to expand".into()))?;
    let lam = Float::with_val(b, &shortest.stability).abs().ln();
    let mut s0 = -(lam.clone() / &shortest.period);
    let mut beta0 = Float::with_val(b, 0.5);
    let mut rows: Vec<Truncation> = Vec::new();
    for n in 1..=max_length {
        let zero = Float::new(b);
        s0 = zero_of(|s| truncated(cycles, n, kind, s, &zero), s0)?;
        let h = Float::with_val(b, -40f64).exp2();
        let fs = (truncated(cycles, n, kind, &(s0.clone() + &h), &zero)
            - truncated(cycles, n, kind, &(s0.clone() - &h), &zero))
            / (h.clone() * 2u32);
        let fb = (truncated(cycles, n, kind, &s0, &h)
            - truncated(cycles, n, kind, &s0, &(-h.clone())))
            / (h.clone() * 2u32);
        let lyapunov = (-(fb / fs)).to_f64();
        beta0 = zero_of(|beta| truncated(cycles, n, kind, &zero, beta), beta0)?;
        let gamma = -s0.clone();
        let g = gamma.to_f64();
        let d = 1.0 - beta0.to_f64();
        let prev = rows.last();
        let change =
            |now: f64, f: fn(&Truncation) -> f64| prev.map_or(f64::NAN, |p| (now - f(p)).abs());
        rows.push(Truncation {
            max_length: n,
            escape_rate: g,
            escape_rate_error: match prev.and_then(|p| p.escape_rate_exact.as_ref()) {
                Some(before) => (gamma.clone() - before).abs().to_f64(),
                None => f64::NAN,
            },
            lyapunov,
            lyapunov_error: change(lyapunov, |p| p.lyapunov),
            entropy: lyapunov - g,
            entropy_error: change(lyapunov - g, |p| p.entropy),
            partial_dimension: d,
            partial_dimension_error: change(d, |p| p.partial_dimension),
            escape_rate_exact: Some(gamma),
        });
    }
    Ok(rows)
}
