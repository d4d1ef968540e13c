//! The hop-direction correlations of one sequence of trap hops, accumulated exactly as the hops
//! come: the observer half of the hop-level Green–Kubo estimator
//! ([`crate::theory::green_kubo`], which turns them into D and explains the window).

use crate::Error;

/// 2·cos(60°·m) for m = 0..5: exact integers 2, 1, −1, −2, −1, 1 (the table [`two_cos`] is
/// tested against).
#[cfg(test)]
pub(crate) const TWO_COS: [i64; 6] = [2, 1, -1, -2, -1, 1];

/// Lags accumulated along Lorentz-gas trajectories (J_max): about 5 × the longest significant
/// hop correlation (j ≈ 10 near w∞), so the neglected tail stays below the statistical error
/// (module documentation); also the cap of the automatic window of [`green_kubo`](crate::theory::green_kubo::green_kubo).
pub const MAX_LAG: usize = 48;

/// Streaming accumulator of one sequence of hop directions (indices 0..6): for every origin i
/// with all `max_lag` successors seen, the exact integers 2 d̂ᵢ·d̂ᵢ₊ⱼ, j = 1 … `max_lag`, summed
/// per lag. All lags share the same origins i < N − `max_lag`, so for every J ≤ `max_lag` the
/// estimate 1 + 2Σ_{j≤J} Ĉ_j is exactly the mean of the gᵢ of the module documentation.
/// Memory O(`max_lag`), time O(`max_lag`) per hop, vectorised: a hop adds the lags of one
/// origin from a contiguous window of bytes (2·cos by byte arithmetic) to byte-wide sums, with
/// no division and no widening; every 63 origins ([`Self::push`]) those are added into the
/// 64-bit sums. Equality and the stored form see only the totals.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "Stored", into = "Stored")]
pub struct HopCorrelations {
    /// The last max_lag + 1 directions, stored twice (ring of length cap = max_lag + 1 written at
    /// p and p + cap), so that the window of an origin is one contiguous slice.
    ring: Vec<u8>,
    pushed: u64,
    /// The sums per lag, less what `recent` holds.
    sums: Vec<i64>,
    /// The sums per lag of the last `held` origins (each term is −2 … 2, so at most
    /// 2·[`RECENT`] = 126 in magnitude: exact in an `i8`).
    recent: Vec<i8>,
    held: u8,
    /// Where the next direction goes: `pushed` mod cap, kept so that a hop divides nothing
    /// (not stored: derived from `pushed` when read back).
    at: usize,
}

/// What a checkpoint keeps of a [`HopCorrelations`] (its fields but the derived position).
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct Stored {
    ring: Vec<u8>,
    pushed: u64,
    sums: Vec<i64>,
}

/// Origins whose terms are summed in bytes before they are added to the 64-bit sums.
const RECENT: u8 = 63;

impl From<HopCorrelations> for Stored {
    fn from(h: HopCorrelations) -> Self {
        Stored {
            sums: h.totals().collect(),
            ring: h.ring,
            pushed: h.pushed,
        }
    }
}

impl PartialEq for HopCorrelations {
    /// The same directions, count and sums per lag (however much of them is still held in
    /// bytes).
    fn eq(&self, o: &Self) -> bool {
        self.ring == o.ring && self.pushed == o.pushed && self.totals().eq(o.totals())
    }
}

impl TryFrom<Stored> for HopCorrelations {
    type Error = String;
    /// Refuses sizes no accumulator has (a ring other than 2·(lags + 1), no lag), so that the
    /// position is defined; [`HopCorrelations::is_reachable`] checks the rest.
    fn try_from(s: Stored) -> Result<Self, String> {
        let cap = s.sums.len() + 1;
        if s.sums.is_empty() || s.ring.len() != 2 * cap {
            return Err(format!(
                "hop correlations with {} lags need a ring of {} directions, not {}",
                s.sums.len(),
                2 * cap,
                s.ring.len()
            ));
        }
        Ok(HopCorrelations {
            at: (s.pushed % cap as u64) as usize,
            ring: s.ring,
            pushed: s.pushed,
            recent: vec![0; s.sums.len()],
            held: 0,
            sums: s.sums,
        })
    }
}

/// Adds 2·cos(60°·(b − a)) for each b of `later` to the byte sum beside it (`sums` and `later`
/// are as long; written for slices and fixed-size arrays alike). The caller keeps every sum
/// within an `i8` ([`RECENT`]).
#[inline(always)]
fn add_lags<S: AsMut<[i8]> + ?Sized, B: AsRef<[u8]> + ?Sized>(sums: &mut S, later: &B, a: u8) {
    for (s, &b) in sums.as_mut().iter_mut().zip(later.as_ref()) {
        *s += two_cos(a, b);
    }
}

/// 2·cos(60°·(b − a)) for directions a, b in 0..6, by arithmetic on bytes so that a window of
/// them vectorises: with e = min(|b − a|, 6 − |b − a|) ∈ {0, 1, 2, 3} the values are 2, 1, −1, −2,
/// that is 2 − e − [e ≥ 2] (the table of 2·cos(60°·m), checked for all 36 pairs by the tests).
#[inline(always)]
pub(crate) fn two_cos(a: u8, b: u8) -> i8 {
    let d = (b as i8).wrapping_sub(a as i8).unsigned_abs();
    let e = d.min(6u8.wrapping_sub(d)) as i8;
    2 - e - (e >= 2) as i8
}

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
            recent: vec![0; max_lag],
            held: 0,
            at: 0,
        })
    }

    /// Whether `self` (read from a checkpoint) is a state an accumulator of `max_lag` could be
    /// in: its sizes, and directions 0 … 5.
    pub fn is_reachable(&self, max_lag: usize) -> bool {
        self.ring.len() == 2 * (max_lag + 1)
            && self.sums.len() == max_lag
            && self.recent.len() == max_lag
            && self.held < RECENT
            && self.ring.iter().all(|&d| d < 6)
    }

    /// Largest lag accumulated.
    pub fn max_lag(&self) -> usize {
        self.sums.len()
    }

    /// The next hop direction, an index 0..6 (angle 60°·index plus any fixed offset); panics
    /// in debug builds on an index ≥ 6 ([`green_kubo`](crate::theory::green_kubo::green_kubo) validates its input).
    #[inline(always)]
    pub fn push(&mut self, dir: u8) {
        debug_assert!(dir < 6, "hop direction index {dir} is not in 0..6");
        let m = self.sums.len();
        let cap = m + 1;
        let p = self.at;
        self.ring[p] = dir;
        self.ring[p + cap] = dir;
        // The oldest direction (origin i = newest − max_lag) sits right after the newest.
        let i = if p + 1 == cap { 0 } else { p + 1 };
        self.at = i;
        self.pushed += 1;
        if self.pushed > m as u64 {
            let window = &self.ring[i..i + cap];
            let (a, later) = (window[0], &window[1..]);
            if m == MAX_LAG {
                // The Lorentz-gas observers' J_max: a fixed length, unrolled.
                let sums: &mut [i8; MAX_LAG] = self.recent.as_mut_slice().try_into().expect("m");
                let later: &[u8; MAX_LAG] = later.try_into().expect("m");
                add_lags(sums, later, a);
            } else {
                add_lags(&mut self.recent, later, a);
            }
            self.held += 1;
            if self.held == RECENT {
                self.fold();
            }
        }
    }

    /// Adds the byte sums into the 64-bit ones (every [`RECENT`] origins).
    #[cold]
    fn fold(&mut self) {
        for (s, r) in self.sums.iter_mut().zip(&mut self.recent) {
            *s += i64::from(*r);
            *r = 0;
        }
        self.held = 0;
    }

    /// The sums per lag, 1 … max_lag.
    fn totals(&self) -> impl Iterator<Item = i64> + '_ {
        self.sums
            .iter()
            .zip(&self.recent)
            .map(|(&s, &r)| s + i64::from(r))
    }

    /// Σᵢ 2 d̂ᵢ·d̂ᵢ₊ⱼ over the complete origins (an exact integer), 1 ≤ j ≤ max_lag.
    pub fn lag_sum(&self, j: usize) -> i64 {
        self.sums[j - 1] + i64::from(self.recent[j - 1])
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
            self.lag_sum(j) as f64 / (2.0 * n as f64)
        }
    }

    /// 1 + 2Σ_{j≤J} Ĉ_j of this sequence (the mean of its gᵢ).
    pub fn d_over_d_mz(&self, j: usize) -> f64 {
        let n = self.origins().max(1) as f64;
        1.0 + self.totals().take(j).sum::<i64>() as f64 / n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_cos_is_the_table_for_every_pair() {
        for a in 0..6u8 {
            for b in 0..6u8 {
                let want = TWO_COS[((b + 6 - a) % 6) as usize];
                assert_eq!(two_cos(a, b) as i64, want, "a = {a}, b = {b}");
            }
        }
    }

    /// The unrolled J_max path and the general one against the definition, lag by lag.
    #[test]
    fn lag_sums_equal_the_definition_at_every_max_lag() {
        let d: Vec<u8> = (0..700u64)
            .map(|i| ((i * i * 11 + i / 7) % 6) as u8)
            .collect();
        for m in [1, 7, MAX_LAG - 1, MAX_LAG, MAX_LAG + 1] {
            let mut a = HopCorrelations::new(m).unwrap();
            for &x in &d {
                a.push(x);
            }
            for j in 1..=m {
                let want: i64 = (0..d.len() - m)
                    .map(|i| TWO_COS[((d[i + j] + 6 - d[i]) % 6) as usize])
                    .sum();
                assert_eq!(a.lag_sum(j), want, "max_lag {m}, lag {j}");
            }
        }
    }

    /// Every term +2 (one direction) or every odd lag's −2 (a direction and its opposite, in
    /// turn): the byte sums reach ±2·[`RECENT`] = ±126 before they are moved out, and stay exact.
    #[test]
    fn extreme_sums_stay_exact_in_bytes() {
        for d in [
            vec![4u8; 1000],
            (0..1000).map(|i| 3 * (i % 2) as u8).collect(),
        ] {
            let mut a = HopCorrelations::new(MAX_LAG).unwrap();
            for &x in &d {
                a.push(x);
            }
            let n = (d.len() - MAX_LAG) as i64;
            for j in 1..=MAX_LAG {
                let want = if d[0] == d[1] || j % 2 == 0 {
                    2 * n
                } else {
                    -2 * n
                };
                assert_eq!(a.lag_sum(j), want, "lag {j}");
            }
        }
    }

    /// A state read back from its JSON goes on exactly as the one that was saved, at every
    /// phase of the ring (the position is derived from the count, not stored).
    #[test]
    fn read_back_state_continues_the_same_sums() {
        let d = |i: u64| ((i * i * 5 + i / 3) % 6) as u8;
        // (Past 68 hops some origins' sums have been moved out of the bytes: the stored sums
        // must hold both parts.)
        for cut in [0u64, 1, 4, 5, 6, 7, 11, 23, 67, 68, 69, 70, 131, 200] {
            let mut a = HopCorrelations::new(5).unwrap();
            for i in 0..cut {
                a.push(d(i));
            }
            let json = serde_json::to_string(&a).unwrap();
            assert!(!json.contains("\"at\""), "{json}");
            let mut b: HopCorrelations = serde_json::from_str(&json).unwrap();
            assert_eq!(a, b);
            assert!(
                (1..=5).all(|j| a.lag_sum(j) == b.lag_sum(j)),
                "cut at {cut}"
            );
            for i in cut..cut + 40 {
                a.push(d(i));
                b.push(d(i));
            }
            assert_eq!(a, b, "cut at {cut}");
        }
        let bad = r#"{"ring":[0,0,0],"pushed":0,"sums":[0]}"#;
        let e = serde_json::from_str::<HopCorrelations>(bad)
            .unwrap_err()
            .to_string();
        assert!(e.contains("need a ring of 4"), "{e}");
        let empty = r#"{"ring":[0,0],"pushed":0,"sums":[]}"#;
        assert!(serde_json::from_str::<HopCorrelations>(empty).is_err());
        let extra = r#"{"ring":[0,0,0,0],"pushed":0,"sums":[0],"at":1}"#;
        assert!(serde_json::from_str::<HopCorrelations>(extra).is_err());
    }
}
