//! Hop-level Green–Kubo estimator of D from sequences of hop directions.
//!
//! For hops of length l every τ with stationary directions d̂ᵢ,
//!
//! D = (l²/(4τ))·[1 + 2 Σ_{j≥1} C_j] = D_MZ·[1 + 2 Σ_{j≥1} C_j],  C_j = ⟨d̂ᵢ·d̂ᵢ₊ⱼ⟩
//!
//! (the discrete-time Green–Kubo formula: ⟨|Σᵢ₌₁ⁿ d̂ᵢ|²⟩ = n + 2Σ_{j<n}(n − j)C_j). The
//! estimator truncates at lag J:
//!
//! D_GK/D_MZ = (1/N') Σ_{i<N'} gᵢ,  gᵢ = 1 + 2 Σ_{j=1}^{J} d̂ᵢ·d̂ᵢ₊ⱼ,  N' = N − J,
//!
//! with d̂ᵢ·d̂ᵢ₊ⱼ = cos(60°·(kᵢ₊ⱼ − kᵢ)) ∈ {1, ½, −½, −1} for direction indices kᵢ, so every gᵢ
//! is an exact half-integer (accumulated in integers). Its expectation is exactly
//! 1 + 2Σ_{j≤J} C_j; the truncation bias is −2Σ_{j>J} C_j.
//!
//! Truncation: either fixed, or Sokal's automatic window: the smallest J with
//! J ≥ c·τ̂(J), τ̂(J) = 1 + 2Σ_{j≤J}|Ĉ_j| (absolute values, so that anticorrelated hops do
//! not shorten the window), Ĉ_j the pooled estimate. The chosen J is reported.
//!
//! Errors: with ≥ 2 independent sequences, the standard error of the mean of the per-sequence
//! estimates (batches); with one sequence, blocking of the gᵢ series
//! ([`crate::stats::blocking_se`]).

use crate::error::Error;
use crate::stats::{blocking_se, mean_se};

use super::honeycomb::{next_direction, Symbol};

/// 2·cos(60°·m) for m = 0..5: exact integers 2, 1, −1, −2, −1, 1.
const TWO_COS: [i64; 6] = [2, 1, -1, -2, -1, 1];

/// How the sum over lags is truncated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Truncation {
    /// Sum lags 1..=J.
    Fixed(usize),
    /// Sokal's window: the smallest J with J ≥ c·(1 + 2Σ_{j≤J}|Ĉ_j|) (c ≈ 5–6).
    Automatic {
        /// The window constant c.
        c: f64,
    },
}

/// How the standard error was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorMethod {
    /// Standard error of the mean over this many independent sequences.
    Batches(usize),
    /// Blocking of the single sequence's gᵢ series.
    Blocking,
}

/// Result of [`green_kubo`].
#[derive(Debug, Clone, PartialEq)]
pub struct GreenKubo {
    /// D_GK/D_MZ = 1 + 2Σ_{j≤J} C_j (estimated).
    pub d_over_d_mz: f64,
    /// Its standard error.
    pub se: f64,
    /// The truncation lag J used.
    pub truncation: usize,
    /// Pooled estimates Ĉ_1..Ĉ_J.
    pub correlations: Vec<f64>,
    /// How `se` was obtained.
    pub error_method: ErrorMethod,
}

/// Hop directions (indices 0..6) from an initial direction and exit symbols: kᵢ₊₁ = kᵢ + turn(sᵢ₊₁).
pub fn directions_from_symbols(d0: u8, symbols: &[Symbol]) -> Vec<u8> {
    let mut d = d0 % 6;
    let mut v = Vec::with_capacity(symbols.len() + 1);
    v.push(d);
    for &s in symbols {
        d = next_direction(d, s);
        v.push(d);
    }
    v
}

/// Σ_i 2 d̂ᵢ·d̂ᵢ₊ⱼ over i < n − j (an exact integer) and the number of terms.
fn lag_sum(dirs: &[u8], j: usize) -> (i64, usize) {
    if dirs.len() <= j {
        return (0, 0);
    }
    let s = dirs
        .iter()
        .zip(&dirs[j..])
        .map(|(&a, &b)| TWO_COS[((b + 6 - a) % 6) as usize])
        .sum();
    (s, dirs.len() - j)
}

/// The pooled estimate Ĉ_j = Σ d̂ᵢ·d̂ᵢ₊ⱼ / (number of pairs) over all sequences.
pub fn correlation(sequences: &[Vec<u8>], j: usize) -> f64 {
    let (s, n) = sequences
        .iter()
        .map(|d| lag_sum(d, j))
        .fold((0i64, 0usize), |a, b| (a.0 + b.0, a.1 + b.1));
    s as f64 / (2.0 * n as f64)
}

/// The Green–Kubo estimate of D/D_MZ from sequences of hop-direction indices (0..6), see the
/// module documentation.
///
/// # Examples
///
/// ```
/// use lorentz_gas::theory::green_kubo::{green_kubo, Truncation};
/// // Hops back and forth forever: C_j = (−1)^j, truncated at J = 1: 1 + 2(−1) = −1.
/// let s: Vec<u8> = (0..100).map(|i| if i % 2 == 0 { 0 } else { 3 }).collect();
/// let r = green_kubo(&[s.clone(), s], Truncation::Fixed(1)).unwrap();
/// assert_eq!(r.d_over_d_mz, -1.0);
/// ```
pub fn green_kubo(sequences: &[Vec<u8>], truncation: Truncation) -> Result<GreenKubo, Error> {
    if sequences.is_empty() {
        return Err(Error::TooFew {
            what: "sequences",
            min: 1,
            got: 0,
        });
    }
    if let Some(bad) = sequences.iter().flatten().find(|&&d| d >= 6) {
        return Err(Error::Invalid(format!(
            "hop direction index {bad} is not in 0..6"
        )));
    }
    let shortest = sequences.iter().map(|s| s.len()).min().unwrap_or(0);
    let j_cap = shortest / 4;
    if j_cap < 8 {
        return Err(Error::TooFew {
            what: "hops per sequence",
            min: 32,
            got: shortest as u64,
        });
    }
    let j = match truncation {
        Truncation::Fixed(j) => {
            if j == 0 || j > j_cap {
                return Err(Error::Invalid(format!(
                    "truncation J = {j} must be in 1..={j_cap} (a quarter of the shortest \
                     sequence, {shortest} hops)"
                )));
            }
            j
        }
        Truncation::Automatic { c } => {
            if c.is_nan() || c <= 0.0 {
                return Err(Error::Invalid(format!(
                    "window constant c = {c} must be > 0"
                )));
            }
            let mut tau = 1.0;
            let mut found = None;
            for j in 1..=j_cap {
                tau += 2.0 * correlation(sequences, j).abs();
                if j as f64 >= c * tau {
                    found = Some(j);
                    break;
                }
            }
            found.ok_or_else(|| {
                Error::Invalid(format!(
                    "no truncation J ≤ {j_cap} satisfies J ≥ {c}·τ̂(J): sequences too short \
                     for these correlations"
                ))
            })?
        }
    };
    let correlations: Vec<f64> = (1..=j).map(|l| correlation(sequences, l)).collect();
    // gᵢ·2 as integers, per sequence.
    let g2 = |d: &[u8]| -> Vec<i64> {
        (0..d.len() - j)
            .map(|i| {
                let a = d[i];
                2 + 2
                    * (1..=j)
                        .map(|l| TWO_COS[((d[i + l] + 6 - a) % 6) as usize])
                        .sum::<i64>()
            })
            .collect()
    };
    let (d, se, method) = if sequences.len() >= 2 {
        let means: Vec<f64> = sequences
            .iter()
            .map(|s| {
                let g = g2(s);
                g.iter().sum::<i64>() as f64 / (2.0 * g.len() as f64)
            })
            .collect();
        let (m, se) = mean_se(&means);
        (m, se, ErrorMethod::Batches(sequences.len()))
    } else {
        let g: Vec<f64> = g2(&sequences[0]).iter().map(|&x| x as f64 / 2.0).collect();
        let m = g.iter().sum::<f64>() / g.len() as f64;
        (m, blocking_se(&g), ErrorMethod::Blocking)
    };
    Ok(GreenKubo {
        d_over_d_mz: d,
        se,
        truncation: j,
        correlations,
        error_method: method,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::theory::honeycomb::parse_symbols;

    #[test]
    fn exact_correlations_of_deterministic_sequences() {
        // Always l: directions 0, 5, 4, 3, … ; C_j = cos(60° j) exactly.
        let s = vec![Symbol::L; 600];
        let d = directions_from_symbols(0, &s);
        for j in 1..=12 {
            let c = correlation(std::slice::from_ref(&d), j);
            assert_eq!(c, TWO_COS[j % 6] as f64 / 2.0);
        }
        // lr repeated: directions 0, 5, 0, 5, …: C_j = 1 (j even), ½ (j odd).
        let s = parse_symbols(&"lr".repeat(200)).unwrap();
        let d = directions_from_symbols(0, &s);
        assert_eq!(correlation(std::slice::from_ref(&d), 1), 0.5);
        assert_eq!(correlation(&[d], 2), 1.0);
    }

    #[test]
    fn fixed_truncation_is_exact_for_a_periodic_orbit() {
        // Circling a hexagon (always l): 1 + 2Σ_{j=1}^{6} cos(60° j) = 1 + 2·0 = 1, and every
        // gᵢ equals it, so the estimate is exact with zero error.
        let d = directions_from_symbols(0, &vec![Symbol::L; 240]);
        let r = green_kubo(&[d.clone(), d], Truncation::Fixed(6)).unwrap();
        assert_eq!(r.d_over_d_mz, 1.0);
        assert_eq!(r.se, 0.0);
        assert_eq!(r.truncation, 6);
        assert_eq!(r.error_method, ErrorMethod::Batches(2));
    }

    #[test]
    fn invalid_input() {
        assert!(green_kubo(&[], Truncation::Fixed(1)).is_err());
        assert!(green_kubo(&[vec![0, 7, 0, 1]], Truncation::Fixed(1)).is_err());
        assert!(green_kubo(&[vec![0; 100]], Truncation::Fixed(30)).is_err());
        assert!(green_kubo(&[vec![0; 100]], Truncation::Automatic { c: -1.0 }).is_err());
        assert!(green_kubo(&[vec![0; 16]], Truncation::Fixed(2)).is_err());
    }
}
