//! The hop-direction correlations of one sequence of trap hops, accumulated exactly as the hops
//! come: the observer half of the hop-level Green–Kubo estimator
//! ([`crate::theory::green_kubo`], which turns them into D and explains the window).

use crate::Error;

/// 2·cos(60°·m) for m = 0..5: exact integers 2, 1, −1, −2, −1, 1.
pub(crate) const TWO_COS: [i64; 6] = [2, 1, -1, -2, -1, 1];

/// Lags accumulated along Lorentz-gas trajectories (J_max): about 5 × the longest significant
/// hop correlation (j ≈ 10 near w∞), so the neglected tail stays below the statistical error
/// (module documentation); also the cap of the automatic window of [`green_kubo`](crate::theory::green_kubo::green_kubo).
pub const MAX_LAG: usize = 48;

/// Streaming accumulator of one sequence of hop directions (indices 0..6): for every origin i
/// with all `max_lag` successors seen, the exact integers 2 d̂ᵢ·d̂ᵢ₊ⱼ, j = 1 … `max_lag`, summed
/// per lag. All lags share the same origins i < N − `max_lag`, so for every J ≤ `max_lag` the
/// estimate 1 + 2Σ_{j≤J} Ĉ_j is exactly the mean of the gᵢ of the module documentation.
/// Memory O(`max_lag`), time O(`max_lag`) per hop.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HopCorrelations {
    /// The last max_lag + 1 directions, stored twice (ring of length cap = max_lag + 1 written at
    /// p and p + cap), so that the window of an origin is one contiguous slice.
    ring: Vec<u8>,
    pushed: u64,
    sums: Vec<i64>,
}

/// 2·cos(60°·(b − a)) as row a, column b (padded to 8 columns so that `b & 7` needs no bounds
/// check).
const TWO_COS_ROW: [[i64; 8]; 6] = {
    let mut t = [[0i64; 8]; 6];
    let mut a = 0;
    while a < 6 {
        let mut b = 0;
        while b < 6 {
            t[a][b] = TWO_COS[(b + 6 - a) % 6];
            b += 1;
        }
        a += 1;
    }
    t
};

impl HopCorrelations {
    /// An empty accumulator of lags 1 … `max_lag` (≥ 1).
    pub fn new(max_lag: usize) -> Result<Self, Error> {
        if max_lag == 0 {
            return Err(Error::Zero { what: "max_lag" });
        }
        Ok(HopCorrelations {
            ring: vec![0; 2 * (max_lag + 1)],
            pushed: 0,
            sums: vec![0; max_lag],
        })
    }

    /// Whether `self` (read from a checkpoint) is a state an accumulator of `max_lag` could be
    /// in: its sizes, and directions 0 … 5.
    pub fn is_reachable(&self, max_lag: usize) -> bool {
        self.ring.len() == 2 * (max_lag + 1)
            && self.sums.len() == max_lag
            && self.ring.iter().all(|&d| d < 6)
    }

    /// Largest lag accumulated.
    pub fn max_lag(&self) -> usize {
        self.sums.len()
    }

    /// The next hop direction, an index 0..6 (angle 60°·index plus any fixed offset); panics
    /// in debug builds on an index ≥ 6 ([`green_kubo`](crate::theory::green_kubo::green_kubo) validates its input).
    #[inline]
    pub fn push(&mut self, dir: u8) {
        debug_assert!(dir < 6, "hop direction index {dir} is not in 0..6");
        let m = self.sums.len();
        let cap = m + 1;
        let p = (self.pushed % cap as u64) as usize;
        self.ring[p] = dir;
        self.ring[p + cap] = dir;
        self.pushed += 1;
        if self.pushed > m as u64 {
            // Origin i = newest − max_lag sits right after the newest in the ring.
            let i = if p + 1 == cap { 0 } else { p + 1 };
            let window = &self.ring[i..i + cap];
            let row = &TWO_COS_ROW[(window[0] % 6) as usize];
            for (s, &b) in self.sums.iter_mut().zip(&window[1..]) {
                *s += row[(b & 7) as usize];
            }
        }
    }

    /// Σᵢ 2 d̂ᵢ·d̂ᵢ₊ⱼ over the complete origins (an exact integer), 1 ≤ j ≤ max_lag.
    pub fn lag_sum(&self, j: usize) -> i64 {
        self.sums[j - 1]
    }

    /// Hops pushed, N.
    pub fn hops(&self) -> u64 {
        self.pushed
    }

    /// Complete origins, N − max_lag (0 while N ≤ max_lag).
    pub fn origins(&self) -> u64 {
        self.pushed.saturating_sub(self.sums.len() as u64)
    }

    /// Ĉ_j of this sequence (mean of d̂ᵢ·d̂ᵢ₊ⱼ over the complete origins; 0 before any),
    /// 1 ≤ j ≤ max_lag.
    pub fn correlation(&self, j: usize) -> f64 {
        let n = self.origins();
        if n == 0 {
            0.0
        } else {
            self.sums[j - 1] as f64 / (2.0 * n as f64)
        }
    }

    /// 1 + 2Σ_{j≤J} Ĉ_j of this sequence (the mean of its gᵢ).
    pub fn d_over_d_mz(&self, j: usize) -> f64 {
        let n = self.origins().max(1) as f64;
        1.0 + self.sums[..j].iter().sum::<i64>() as f64 / n
    }
}
