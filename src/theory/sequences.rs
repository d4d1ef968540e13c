//! Probabilities of symbol sequences: the input of the hierarchy ([`super::hierarchy`]) and of
//! the correlated walks ([`super::markov`], [`super::lattice_walk`]).
//!
//! A table of order k holds p(s₁…s_k) for all 3^k words over {z, l, r}, indexed by
//! [`sequence_index`] (first symbol most significant). In the Lorentz gas, p(s₁…s_k) is the
//! frequency with which k consecutive trap exits are s₁, …, s_k, measured along a long
//! trajectory ([`count_sequences`]).

use crate::Error;
use crate::statistics::CompensatedSum;

use crate::scenes::symbols::{Symbol, sequence_from_index, sequence_index, word};

/// p(s₁…s_k) for all 3^k sequences of length k, validated: every entry finite and ≥ 0, the sum
/// equal to 1 within the rounding error model of [`SequenceProbabilities::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct SequenceProbabilities {
    k: usize,
    p: Vec<f64>,
}

impl SequenceProbabilities {
    /// Largest sequence length accepted (3¹² = 531 441 entries).
    pub const MAX_LEN: usize = 12;

    /// A table of length `k` from `p` in [`sequence_index`] order.
    ///
    /// Validation: `p.len() == 3^k`, every entry finite and ≥ 0, and |Σp − 1| ≤ 2N·u with
    /// N = 3^k and u = 2⁻⁵³. Error model for the sum: a table whose entries are correctly
    /// rounded quotients count/total carries |Σ fl(pᵢ) − 1| ≤ u·Σpᵢ = u; one normalised by a
    /// naively summed total carries at most (N − 1)u more; the sum itself is formed with
    /// Neumaier's compensated summation (error ≤ 2u). All together < 2N·u for N ≥ 3.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::theory::sequences::SequenceProbabilities;
    /// let p = SequenceProbabilities::new(1, vec![0.5, 0.25, 0.25]).unwrap();
    /// assert_eq!(p.len(), 1);
    /// assert!(SequenceProbabilities::new(1, vec![0.5, 0.5, 0.5]).is_err());
    /// assert!(SequenceProbabilities::new(1, vec![1.5, -0.25, -0.25]).is_err());
    /// ```
    pub fn new(k: usize, p: Vec<f64>) -> Result<Self, Error> {
        let n = Self::check_shape(k, p.len())?;
        Self::check_entries(k, &p)?;
        let mut s = CompensatedSum::default();
        for &x in &p {
            s.add(x);
        }
        let sum = s.value();
        let tol = 2.0 * n as f64 * f64::EPSILON / 2.0;
        if (sum - 1.0).abs() > tol {
            return Err(Error::parameter(
                "p",
                format!("probabilities summing to {sum:.17}"),
                format!(
                    "sequence probabilities of length {k} sum to 1 (allowed rounding error \
                     {tol:.1e}); use SequenceProbabilities::from_weights to normalise"
                ),
            ));
        }
        Ok(SequenceProbabilities { k, p })
    }

    /// A table from non-negative weights (e.g. counts), normalised by their compensated sum.
    pub fn from_weights(k: usize, w: Vec<f64>) -> Result<Self, Error> {
        Self::check_shape(k, w.len())?;
        Self::check_entries(k, &w)?;
        let mut s = CompensatedSum::default();
        for &x in &w {
            s.add(x);
        }
        let total = s.value();
        if total.is_nan() || total <= 0.0 || !total.is_finite() {
            return Err(Error::parameter(
                "w",
                format!("weights summing to {total}"),
                "sequence weights must have a positive finite sum",
            ));
        }
        let p = w.into_iter().map(|x| x / total).collect();
        Self::new(k, p)
    }

    /// A table from sequence counts (see [`count_sequences`]).
    pub fn from_counts(k: usize, counts: &[u64]) -> Result<Self, Error> {
        Self::from_weights(k, counts.iter().map(|&c| c as f64).collect())
    }

    /// Uncorrelated exits of length `k`: p(s₁…s_k) = Π p(sᵢ) with p(z) = p_bs,
    /// p(l) = p(r) = (1 − p_bs)/2 (the first-order symbolic dynamics of the paper).
    pub fn memoryless(k: usize, p_bs: f64) -> Result<Self, Error> {
        if !(0.0..=1.0).contains(&p_bs) {
            return Err(Error::out_of_range(
                "p_bs",
                p_bs,
                "use a backscattering probability from 0 to 1",
            ));
        }
        let q = (1.0 - p_bs) / 2.0;
        let one = [p_bs, q, q];
        let n = Self::check_shape(k, 3usize.pow(k as u32))?;
        let p = (0..n)
            .map(|mut i| {
                let mut x = 1.0;
                for _ in 0..k {
                    x *= one[i % 3];
                    i /= 3;
                }
                x
            })
            .collect();
        Self::new(k, p)
    }

    fn check_shape(k: usize, len: usize) -> Result<usize, Error> {
        if k == 0 || k > Self::MAX_LEN {
            return Err(Error::out_of_range(
                "k",
                k,
                format!("use 1 ≤ k ≤ {} (the sequence length)", Self::MAX_LEN),
            ));
        }
        let n = 3usize.pow(k as u32);
        if len != n {
            return Err(Error::parameter(
                "p",
                format!("{len} probabilities"),
                format!("a table of sequences of length {k} needs 3^{k} = {n}"),
            ));
        }
        Ok(n)
    }

    fn check_entries(k: usize, p: &[f64]) -> Result<(), Error> {
        for (i, &x) in p.iter().enumerate() {
            if !x.is_finite() || x < 0.0 {
                let w = word(&sequence_from_index(k, i));
                return Err(Error::parameter(
                    "p",
                    format!("{x} for the sequence \"{w}\""),
                    "every probability must be finite and ≥ 0",
                ));
            }
        }
        Ok(())
    }

    /// Sequence length k.
    pub fn len(&self) -> usize {
        self.k
    }

    /// Always `false` (k ≥ 1); provided for the `len`/`is_empty` convention.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// p(s₁…s_k). Panics if `seq.len() != k`.
    pub fn get(&self, seq: &[Symbol]) -> f64 {
        assert_eq!(seq.len(), self.k, "sequence length");
        self.p[sequence_index(seq)]
    }

    /// All probabilities in [`sequence_index`] order.
    pub fn probabilities(&self) -> &[f64] {
        &self.p
    }

    /// The marginal table of the first `j ≤ k` symbols: p(s₁…s_j) = Σ p(s₁…s_k).
    pub fn prefix_marginal(&self, j: usize) -> Result<Self, Error> {
        if j == 0 || j > self.k {
            return Err(Error::out_of_range(
                "j",
                j,
                format!("use a prefix length from 1 to {}", self.k),
            ));
        }
        let block = 3usize.pow((self.k - j) as u32);
        let w = self.p.chunks(block).map(|c| c.iter().sum()).collect();
        Self::from_weights(j, w)
    }
}

/// Counts of all words of length `k` in `symbols` (sliding window, every start), in
/// [`sequence_index`] order: the estimator of p(s₁…s_k) along one trajectory.
pub fn count_sequences(symbols: &[Symbol], k: usize) -> Vec<u64> {
    let n = 3usize.pow(k as u32);
    let mut c = vec![0u64; n];
    if k == 0 || symbols.len() < k {
        return c;
    }
    let mut idx = 0usize;
    for (i, s) in symbols.iter().enumerate() {
        idx = (3 * idx + s.index()) % n;
        if i + 1 >= k {
            c[idx] += 1;
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::symbols::parse_symbols;

    #[test]
    fn validation_errors_are_clear() {
        let e = SequenceProbabilities::new(2, vec![0.1; 8]).unwrap_err();
        assert!(e.to_string().contains("needs 3^2 = 9"), "{e}");
        let mut p = vec![1.0 / 9.0; 9];
        p[4] = -p[4];
        let e = SequenceProbabilities::new(2, p).unwrap_err();
        assert!(e.to_string().contains("\"ll\""), "{e}");
        let e = SequenceProbabilities::new(1, vec![0.4, 0.4, 0.4]).unwrap_err();
        assert!(e.to_string().contains("sum to"), "{e}");
        assert!(SequenceProbabilities::new(1, vec![f64::NAN, 0.5, 0.5]).is_err());
        assert!(SequenceProbabilities::new(0, vec![1.0]).is_err());
        assert!(SequenceProbabilities::memoryless(2, 1.1).is_err());
    }

    #[test]
    fn thirds_pass_the_rounding_model() {
        // fl(1/3)·3 ≠ 1 in general, but it is within the model.
        for k in 1..=8 {
            let n = 3usize.pow(k as u32);
            assert!(SequenceProbabilities::new(k, vec![1.0 / n as f64; n]).is_ok());
            assert!(SequenceProbabilities::memoryless(k, 1.0 / 3.0).is_ok());
        }
    }

    #[test]
    fn counting_and_marginals() {
        let s = parse_symbols("zlzlr").unwrap();
        let c = count_sequences(&s, 2);
        assert_eq!(c.iter().sum::<u64>(), 4);
        assert_eq!(c[sequence_index(&parse_symbols("zl").unwrap())], 2);
        assert_eq!(c[sequence_index(&parse_symbols("lz").unwrap())], 1);
        assert_eq!(c[sequence_index(&parse_symbols("lr").unwrap())], 1);
        let p = SequenceProbabilities::from_counts(2, &c).unwrap();
        let m = p.prefix_marginal(1).unwrap();
        assert_eq!(m.probabilities(), &[0.5, 0.5, 0.0]);
        let q = SequenceProbabilities::memoryless(3, 0.38).unwrap();
        let q1 = q.prefix_marginal(1).unwrap();
        assert!((q1.get(&[Symbol::Z]) - 0.38).abs() < 8.0 * f64::EPSILON);
    }
}
