//! The most extreme of n batch values against a Bonferroni Student-t bound: the test of one
//! distribution that a field run's component check and the report's batch statistics share.

use serde::{Deserialize, Serialize};

use super::student_t_quantile;

/// The most extreme batch: each value against the mean and spread of the others (externally
/// studentised: t with n − 2 degrees of freedom for independent normal values), and the bound
/// that the largest of n such |t| exceeds with probability `alpha` (Bonferroni, so at most
/// `alpha`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Extreme {
    /// Index of the most extreme value.
    pub batch: usize,
    /// Its t.
    pub t: f64,
    /// The bound on |t|.
    pub bound: f64,
    /// The values tested.
    pub n: usize,
}

impl Extreme {
    /// `true` if the most extreme value is within the bound.
    pub fn passes(&self) -> bool {
        self.t.abs() <= self.bound
    }
}

/// The most extreme of `x` (at least 3 values, else `None`) at the false-alarm rate `alpha`, in
/// O(n) from the totals. Values that are all equal have t = 0.
pub fn most_extreme(x: &[f64], alpha: f64) -> Option<Extreme> {
    let n = x.len();
    if n < 3 {
        return None;
    }
    let nf = n as f64;
    let m = x.iter().sum::<f64>() / nf;
    let ss: f64 = x.iter().map(|v| (v - m).powi(2)).sum();
    let mut worst = (0usize, 0.0f64);
    for (b, &xb) in x.iter().enumerate() {
        // The others: mean (n m − x_b)/(n − 1), squares about it SS − (x_b − m)² n/(n − 1).
        let mr = (nf * m - xb) / (nf - 1.0);
        let ss_r = (ss - (xb - m).powi(2) * nf / (nf - 1.0)).max(0.0);
        let sd = (ss_r / (nf - 2.0)).sqrt();
        let t = (xb - mr) / (sd * (1.0 + 1.0 / (nf - 1.0)).sqrt());
        let t = if t.is_nan() { 0.0 } else { t };
        if t.abs() > worst.1.abs() {
            worst = (b, t);
        }
    }
    Some(Extreme {
        batch: worst.0,
        t: worst.1,
        bound: student_t_quantile((n - 2) as f64, alpha / (2.0 * nf)),
        n,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// `n` independent standard normal values (Box–Muller), for the tests of batch statistics.
    pub(crate) fn normals(rng: &mut impl Rng, n: usize) -> Vec<f64> {
        (0..n)
            .map(|_| {
                let (u, v): (f64, f64) = (rng.random(), rng.random());
                (-2.0 * (1.0 - u).ln()).sqrt() * (std::f64::consts::TAU * v).cos()
            })
            .collect()
    }

    /// Independent normal values: the false-alarm rate at α = 0.01 is at most α (Bonferroni),
    /// measured on 20 000 sets of 16 (expected ≤ 200 failures; more than 260 has probability
    /// below 10⁻⁴ at the nominal rate). One value moved by 12σ is found.
    #[test]
    fn independent_values_raise_false_alarms_at_most_at_the_nominal_rate() {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(58);
        let failed = (0..20_000)
            .filter(|_| !most_extreme(&normals(&mut rng, 16), 0.01).unwrap().passes())
            .count();
        assert!(failed <= 260, "{failed} of 20000");
        assert!(
            failed >= 100,
            "{failed} of 20000: the bound is far too loose"
        );
        let mut x = normals(&mut rng, 16);
        x[5] += 12.0;
        let e = most_extreme(&x, 0.01).unwrap();
        assert!(!e.passes() && e.batch == 5, "{e:?}");
    }
}
