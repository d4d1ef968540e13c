//! The hop-level Green–Kubo estimator of D — the crate's one: the Lorentz gas's lattice
//! trajectories feed it hop by hop ([`crate::observers::hops::Hops`] →
//! [`crate::estimators::hops::run`], window [`HOP_TRUNCATION`]), and so do simulated correlated walks
//! ([`super::lattice_walk::direction_sequence`] → [`green_kubo`]).
//!
//! For hops of length l every τ with stationary directions d̂ᵢ,
//!
//! D = (l²/(4τ))·[1 + 2 Σ_{j≥1} C_j] = D_MZ·[1 + 2 Σ_{j≥1} C_j],  C_j = ⟨d̂ᵢ·d̂ᵢ₊ⱼ⟩
//!
//! (the discrete-time Green–Kubo formula: ⟨|Σᵢ₌₁ⁿ d̂ᵢ|²⟩ = n + 2Σ_{j<n}(n − j)C_j). The
//! estimator accumulates lags up to J_max ([`HopCorrelations`]) and truncates at lag J ≤ J_max:
//!
//! D_GK/D_MZ = (1/N') Σ_{i<N'} gᵢ,  gᵢ = 1 + 2 Σ_{j=1}^{J} d̂ᵢ·d̂ᵢ₊ⱼ,  N' = N − J_max,
//!
//! with d̂ᵢ·d̂ᵢ₊ⱼ = cos(60°·(kᵢ₊ⱼ − kᵢ)) ∈ {1, ½, −½, −1} for direction indices kᵢ, so every gᵢ
//! is an exact half-integer (accumulated in integers). Its expectation is exactly
//! 1 + 2Σ_{j≤J} C_j; the truncation bias is −2Σ_{j>J} C_j.
//!
//! Truncation: either fixed, or Sokal's automatic window: the smallest J with
//! J ≥ c·τ̂(J), τ̂(J) = 1 + 2Σ_{j≤J}|Ĉ_j| (absolute values, so that anticorrelated hops do
//! not shorten the window), Ĉ_j the pooled estimate. The chosen J is reported.
//!
//! Errors: the standard error of the mean of the per-sequence estimates over ≥ 2 independent
//! sequences (batches) — never from one sequence, whose gᵢ are correlated.
//!
//! # The window of the Lorentz gas ([`HOP_TRUNCATION`]: all [`MAX_LAG`] = 48 lags)
//!
//! Measured (`proofs-notes/green-kubo.md`, 2·10⁸ collisions in 16 batches per w): the hop
//! correlations of the Lorentz gas decay geometrically and are indistinguishable from 0 beyond
//! j ≈ 7 at w ≤ 0.25 and beyond j ≈ 10 at w = 0.3 (long flights near w∞ = 0.3094 keep them
//! positive longest). Summing 48 lags, about 5 × the longest significant one, leaves a tail
//! below the statistical error at every w from 0.02 to 0.3: the sum over lags 49 … 256 is
//! within 2σ of 0, and D_GK agrees with the Einstein D within 2σ. Sokal's window (c = 6) would
//! pick J = 7–9 with an error about 2.5 × smaller, but at w = 0.3 it drops C₁₀ … C₁₆, together
//! about twice its own error bar, so that bar would no longer cover the truncation bias; 48
//! fixed lags trade that factor for an error bar that does. Cost: 48 integer additions per
//! hop, about 10 % of the collision time at w = 0.3 and less at smaller w (fewer hops per
//! collision).

use crate::Error;
use crate::observers::hop_correlations::{HopCorrelations, MAX_LAG};
use crate::statistics::mean_se;

use super::honeycomb::next_direction;
use crate::scenes::symbols::Symbol;

/// The window of the Lorentz gas's hop-level estimator: all [`MAX_LAG`] lags, not Sokal's
/// shorter automatic window, whose error bar would not cover the truncation bias near w∞
/// (module documentation).
pub const HOP_TRUNCATION: Truncation = Truncation::Fixed(MAX_LAG);

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

/// Result of [`estimate`] and [`green_kubo`].
#[derive(Debug, Clone, PartialEq)]
pub struct GreenKubo {
    /// D_GK/D_MZ = 1 + 2Σ_{j≤J} C_j (estimated): the mean of the per-sequence estimates.
    pub d_over_d_mz: f64,
    /// Its standard error over the independent sequences (batch means).
    pub se: f64,
    /// The truncation lag J used.
    pub truncation: usize,
    /// Pooled estimates Ĉ_1..Ĉ_J (sums over all sequences divided by all origins).
    pub correlations: Vec<f64>,
    /// The estimate of each sequence, in input order.
    pub batch_values: Vec<f64>,
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

/// The pooled estimate Ĉ_j = Σ d̂ᵢ·d̂ᵢ₊ⱼ / (number of origins) over all accumulators.
pub fn pooled_correlation(batches: &[HopCorrelations], j: usize) -> f64 {
    let (s, n) = batches
        .iter()
        .fold((0i64, 0u64), |a, b| (a.0 + b.lag_sum(j), a.1 + b.origins()));
    if n == 0 {
        0.0
    } else {
        s as f64 / (2.0 * n as f64)
    }
}

/// The Green–Kubo estimate of D/D_MZ from independent sequences (see the module documentation):
/// the window J from `truncation` (J ≤ the accumulators' `max_lag`), each sequence's
/// 1 + 2Σ_{j≤J} Ĉ_j, their mean and its standard error.
///
/// Needs ≥ 2 sequences (the error is over independent sequences), all with the same
/// `max_lag` and at least 4·`max_lag` hops each.
pub fn estimate(batches: &[HopCorrelations], truncation: Truncation) -> Result<GreenKubo, Error> {
    if batches.len() < 2 {
        return Err(Error::TooFew {
            what: "independent hop sequences (for a batch error)",
            min: 2,
            got: batches.len() as u64,
        });
    }
    let j_max = batches[0].max_lag();
    if batches.iter().any(|b| b.max_lag() != j_max) {
        return Err(Error::Failed(
            "hop sequences accumulated with different maximum lags".into(),
        ));
    }
    let shortest = batches.iter().map(|b| b.hops()).min().unwrap_or(0);
    if shortest < 4 * j_max as u64 {
        return Err(Error::TooFew {
            what: "hops per sequence (4 × the largest lag)",
            min: 4 * j_max as u64,
            got: shortest,
        });
    }
    let j = match truncation {
        Truncation::Fixed(j) => {
            if j == 0 || j > j_max {
                return Err(Error::out_of_range(
                    "truncation",
                    j,
                    format!("use J from 1 to {j_max} (the largest lag accumulated)"),
                ));
            }
            j
        }
        Truncation::Automatic { c } => {
            if c.is_nan() || c <= 0.0 {
                return Err(Error::out_of_range(
                    "truncation",
                    c,
                    "use a window constant c > 0",
                ));
            }
            let mut tau = 1.0;
            let mut found = None;
            for j in 1..=j_max {
                tau += 2.0 * pooled_correlation(batches, j).abs();
                if j as f64 >= c * tau {
                    found = Some(j);
                    break;
                }
            }
            found.ok_or_else(|| {
                Error::Failed(format!(
                    "no truncation J ≤ {j_max} satisfies J ≥ {c}·τ̂(J): the hop correlations \
                     are too long for the lags accumulated"
                ))
            })?
        }
    };
    let correlations = (1..=j).map(|l| pooled_correlation(batches, l)).collect();
    let batch_values: Vec<f64> = batches.iter().map(|b| b.d_over_d_mz(j)).collect();
    let (d, se) = mean_se(&batch_values);
    Ok(GreenKubo {
        d_over_d_mz: d,
        se,
        truncation: j,
        correlations,
        batch_values,
    })
}

/// [`estimate`] on stored sequences of hop-direction indices (0..6), accumulated up to lag
/// J for `Fixed(J)` and up to min([`MAX_LAG`], shortest/4) for `Automatic`.
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
    if let Some(bad) = sequences.iter().flatten().find(|&&d| d >= 6) {
        return Err(Error::out_of_range(
            "sequences",
            bad,
            "use hop direction indices 0 to 5",
        ));
    }
    let shortest = sequences.iter().map(|s| s.len()).min().unwrap_or(0);
    let j_max = match truncation {
        Truncation::Fixed(j) => j.max(1),
        Truncation::Automatic { .. } => MAX_LAG.min(shortest / 4).max(1),
    };
    let acc: Vec<HopCorrelations> = sequences
        .iter()
        .map(|s| {
            let mut a = HopCorrelations::new(j_max)?;
            for &d in s {
                a.push(d);
            }
            Ok(a)
        })
        .collect::<Result<_, Error>>()?;
    estimate(&acc, truncation)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::observers::hop_correlations::TWO_COS;
    use crate::scenes::symbols::parse_symbols;

    fn accumulate(d: &[u8], max_lag: usize) -> HopCorrelations {
        let mut a = HopCorrelations::new(max_lag).unwrap();
        for &x in d {
            a.push(x);
        }
        a
    }

    #[test]
    fn exact_correlations_of_deterministic_sequences() {
        // Always l: directions 0, 5, 4, 3, … ; C_j = cos(60° j) exactly.
        let s = vec![Symbol::L; 600];
        let a = accumulate(&directions_from_symbols(0, &s), 12);
        for j in 1..=12 {
            assert_eq!(a.correlation(j), TWO_COS[j % 6] as f64 / 2.0);
        }
        // lr repeated: directions 0, 5, 0, 5, …: C_j = 1 (j even), ½ (j odd).
        let s = parse_symbols(&"lr".repeat(200)).unwrap();
        let a = accumulate(&directions_from_symbols(0, &s), 2);
        assert_eq!(a.correlation(1), 0.5);
        assert_eq!(a.correlation(2), 1.0);
        assert_eq!(pooled_correlation(&[a.clone(), a], 2), 1.0);
    }

    #[test]
    fn streaming_sums_equal_the_mean_of_g() {
        // The accumulator against the definition gᵢ = 1 + 2Σ_{j≤J} d̂ᵢ·d̂ᵢ₊ⱼ, i < N − J_max,
        // on an arbitrary sequence: equal as exact rationals (integer sums over one count).
        let d: Vec<u8> = (0..1000u64)
            .map(|i| ((i * i * 7 + i * 3 + (i >> 3)) % 6) as u8)
            .collect();
        let j_max = 10;
        let a = accumulate(&d, j_max);
        assert_eq!(a.hops(), 1000);
        assert_eq!(a.origins(), 990);
        for j in 1..=j_max {
            let g2: i64 = (0..d.len() - j_max)
                .map(|i| {
                    2 + 2
                        * (1..=j)
                            .map(|l| TWO_COS[((d[i + l] + 6 - d[i]) % 6) as usize])
                            .sum::<i64>()
                })
                .sum();
            assert_eq!(a.d_over_d_mz(j), g2 as f64 / (2.0 * 990.0));
        }
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
        assert_eq!(r.batch_values, vec![1.0, 1.0]);
    }

    #[test]
    fn invalid_input() {
        let e = |r: Result<GreenKubo, Error>| r.unwrap_err().to_string();
        assert!(e(green_kubo(&[], Truncation::Fixed(1))).contains("at least 2"));
        let two = |s: Vec<u8>| vec![s.clone(), s];
        assert!(e(green_kubo(&[vec![0; 100]], Truncation::Fixed(1))).contains("at least 2"));
        assert!(
            e(green_kubo(&two(vec![0, 7, 0, 1]), Truncation::Fixed(1)))
                .contains("sequences = 7 is out of range: use hop direction indices 0 to 5")
        );
        assert!(e(green_kubo(&two(vec![0; 100]), Truncation::Fixed(30))).contains("4 ×"));
        assert!(green_kubo(&two(vec![0; 100]), Truncation::Automatic { c: -1.0 }).is_err());
        assert!(green_kubo(&two(vec![0; 7]), Truncation::Fixed(2)).is_err());
        assert!(HopCorrelations::new(0).is_err());
        let a = HopCorrelations::new(3).unwrap();
        let b = HopCorrelations::new(4).unwrap();
        assert!(estimate(&[a, b], Truncation::Fixed(1)).is_err());
    }
}
