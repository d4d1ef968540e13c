//! Log-histograms of positive values: what the audits keep of their error distributions (bins of
//! 0.1 decade, so a quantile is known to within one bin, and two histograms merge by addition).

use serde::{Deserialize, Serialize};

/// Log-histogram of positive values: bins of 0.1 decade from 10⁻³⁰ to 10¹⁰, plus zeros.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LogHistogram {
    /// Counts per bin; bin k covers [10^(−30 + k/10), 10^(−30 + (k+1)/10)).
    pub counts: Vec<u64>,
    /// Exact zeros.
    pub zeros: u64,
    /// Largest value seen.
    pub max: f64,
}

impl Default for LogHistogram {
    fn default() -> Self {
        LogHistogram {
            counts: vec![0; 400],
            zeros: 0,
            max: 0.0,
        }
    }
}

impl LogHistogram {
    /// Records `x ≥ 0`.
    pub fn add(&mut self, x: f64) {
        if x <= 0.0 {
            self.zeros += 1;
            return;
        }
        self.max = self.max.max(x);
        let k = ((x.log10() + 30.0) * 10.0).floor().clamp(0.0, 399.0) as usize;
        self.counts[k] += 1;
    }
    /// Adds another histogram.
    pub fn merge(&mut self, o: &LogHistogram) {
        for (a, b) in self.counts.iter_mut().zip(&o.counts) {
            *a += b;
        }
        self.zeros += o.zeros;
        self.max = self.max.max(o.max);
    }
    /// Total count.
    pub fn total(&self) -> u64 {
        self.zeros + self.counts.iter().sum::<u64>()
    }
    /// Quantile q ∈ [0, 1], to the bin's upper edge (0.1 decade resolution).
    pub fn quantile(&self, q: f64) -> f64 {
        let n = self.total();
        if n == 0 {
            return f64::NAN;
        }
        let target = (q * n as f64).ceil().max(1.0) as u64;
        let mut c = self.zeros;
        if c >= target {
            return 0.0;
        }
        for (k, &x) in self.counts.iter().enumerate() {
            c += x;
            if c >= target {
                return 10f64.powf(-30.0 + (k + 1) as f64 / 10.0).min(self.max);
            }
        }
        self.max
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histogram_quantiles() {
        let mut h = LogHistogram::default();
        for k in 0..100 {
            h.add(10f64.powi(-(k % 10)));
        }
        h.add(0.0);
        assert_eq!(h.total(), 101);
        assert_eq!(h.quantile(0.0), 0.0);
        assert!((h.quantile(1.0) - 1.0).abs() < 1e-12);
        let med = h.quantile(0.5);
        assert!(med > 1e-6 && med < 1e-3, "{med}");
    }
}
