//! Components, not averages: each trajectory of a run in a field classified as bounded or
//! diffusing from its own displacement record ([`crate::observers::excursion`]), the bounded ones
//! set aside, and the diffusing ones tested for one distribution
//! (`proofs-notes/magnetic-components.md`).

use serde::{Deserialize, Serialize};

use crate::observers::excursion::{Component, Excursion, Reach};
use crate::statistics::outlier::{Extreme, most_extreme};

/// The false-alarm rate of the test that the diffusing trajectories are one component: the
/// largest of their batch values of D_xx (and of D_xy) against a Bonferroni Student-t bound, each
/// at half this rate.
pub const SPLIT_ALPHA: f64 = 1e-3;

/// The trajectories of a run by component.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Components {
    /// The excursion limit: a trajectory that never went further from its start is bounded.
    pub limit: f64,
    /// Each batch's class.
    pub batch_component: Vec<Component>,
    /// Each batch's largest distance from its start (sampled on the time grid).
    pub batch_reach: Vec<f64>,
    /// Batches bounded (set aside: their D is not part of the diffusing part's).
    pub bounded: u32,
    /// Batches diffusing.
    pub diffusing: u32,
    /// Diffusing batches that went less than [`Excursion::AMBIGUOUS`] limits from their start:
    /// the split is not clear (run longer).
    pub ambiguous: u32,
    /// The share of phase space that never diffuses: the exact localized share plus the
    /// bounded batches' share of the rest.
    pub bounded_fraction: f64,
    /// Its binomial standard error (from the batches).
    pub bounded_fraction_err: f64,
    /// Its one-sided 95 % upper bound (Clopper–Pearson over the batches): with no bounded batch
    /// the error above is 0, and this says how large a share of islands the batches could have
    /// missed.
    pub bounded_fraction_upper: f64,
    /// The most extreme diffusing batch's D_xx (`null` below 3 diffusing batches).
    pub extreme_D_xx: Option<Extreme>,
    /// The most extreme diffusing batch's Hall D_xy.
    pub extreme_D_xy: Option<Extreme>,
    /// The diffusing batches are not one distribution: a further component among them.
    pub split: bool,
}

impl Components {
    /// The classification of batches that reached `reaches`, with their D_xx and D_xy, at
    /// the exact localized share `localized`.
    #[allow(non_snake_case)]
    pub fn of(
        excursion: Excursion,
        reaches: &[Reach],
        (D_xx, D_xy): (&[f64], &[f64]),
        localized: f64,
    ) -> Self {
        let classes: Vec<Component> = reaches.iter().map(|r| excursion.classify(r)).collect();
        let diffusing = |x: &[f64]| -> Vec<f64> {
            x.iter()
                .zip(&classes)
                .filter(|(_, c)| **c == Component::Diffusing)
                .map(|(v, _)| *v)
                .collect()
        };
        let n = classes.len();
        let bounded = classes.iter().filter(|c| **c == Component::Bounded).count();
        let p = if n == 0 {
            0.0
        } else {
            bounded as f64 / n as f64
        };
        let keep = (1.0 - localized).max(0.0);
        let extreme_D_xx = most_extreme(&diffusing(D_xx), SPLIT_ALPHA / 2.0);
        let extreme_D_xy = most_extreme(&diffusing(D_xy), SPLIT_ALPHA / 2.0);
        let split = [extreme_D_xx, extreme_D_xy]
            .iter()
            .any(|e| e.is_some_and(|e| !e.passes()));
        Components {
            limit: excursion.limit,
            batch_reach: reaches.iter().map(Reach::largest).collect(),
            bounded: bounded as u32,
            diffusing: (n - bounded) as u32,
            ambiguous: reaches.iter().filter(|r| excursion.ambiguous(r)).count() as u32,
            bounded_fraction: localized + keep * p,
            bounded_fraction_err: if n == 0 {
                0.0
            } else {
                keep * (p * (1.0 - p) / n as f64).sqrt()
            },
            bounded_fraction_upper: localized + keep * upper_95(bounded, n),
            batch_component: classes,
            extreme_D_xx,
            extreme_D_xy,
            split,
        }
    }

    /// Whether batch `i` is a diffusing one.
    pub fn diffusing(&self, i: usize) -> bool {
        self.batch_component.get(i) == Some(&Component::Diffusing)
    }

    /// The verdict in words: one component, or why not.
    pub fn describe(&self) -> String {
        let n = self.batch_component.len();
        let mut s = format!(
            "{} of {n} trajectories bounded (never beyond {:.3} of their start), {} diffusing; \
             bounded share {:.6} ± {:.6} (below {:.6} at 95 %)",
            self.bounded,
            self.limit,
            self.diffusing,
            self.bounded_fraction,
            self.bounded_fraction_err,
            self.bounded_fraction_upper
        );
        if self.split {
            s.push_str("; the diffusing ones are not one component (an outlying batch)");
        } else if self.diffusing >= 3 {
            s.push_str("; the diffusing ones are one component (no outlying batch)");
        }
        if self.ambiguous > 0 {
            s.push_str(&format!(
                "; {} diffusing within {} limits of the start: the split is not clear, run longer",
                self.ambiguous,
                Excursion::AMBIGUOUS
            ));
        }
        s
    }
}

/// The one-sided 95 % Clopper–Pearson upper bound on a share of which `k` of `n` trials were
/// hits: the share p at which k or fewer hits have probability 5 %, the 0.95 quantile of
/// Beta(k + 1, n − k) (1 where every trial hit, 0 with no trial).
pub fn upper_95(k: usize, n: usize) -> f64 {
    use statrs::distribution::{Beta, ContinuousCDF};
    if n == 0 {
        return 0.0;
    }
    if k >= n {
        return 1.0;
    }
    Beta::new((k + 1) as f64, (n - k) as f64).map_or(1.0, |b| b.inverse_cdf(0.95))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No hit in n: 1 − 0.05^(1/n) (the "rule of three" ≈ 3/n); one in ten against the binomial
    /// tail P(K ≤ 1 | p) = 0.05 solved by bisection.
    #[test]
    fn the_upper_bound_is_clopper_pearson() {
        for n in [1usize, 16, 100] {
            let u = upper_95(0, n);
            let x = 1.0 - 0.05f64.powf(1.0 / n as f64);
            assert!((u - x).abs() < 1e-9, "{n}: {u} {x}");
        }
        let tail = |p: f64| (1.0 - p).powi(10) + 10.0 * p * (1.0 - p).powi(9);
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..60 {
            let m = 0.5 * (lo + hi);
            if tail(m) > 0.05 { lo = m } else { hi = m }
        }
        assert!(
            (upper_95(1, 10) - lo).abs() < 1e-9,
            "{} {lo}",
            upper_95(1, 10)
        );
        assert_eq!(upper_95(3, 3), 1.0);
    }
}
