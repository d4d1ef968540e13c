//! Comparisons with a verdict: a difference, its honest standard error and degrees of freedom,
//! and the crate's agreement bound — the normal 4σ tail probability as a Student-t quantile
//! ([`agreement_bound`]). Two estimates from the same batches are compared *paired* (the
//! standard error of the per-batch differences), never by adding their errors in quadrature:
//! their correlation would make the quadrature error too large (D over two fit windows of the
//! same trajectories correlate at 0.8) and hide a real difference.

use serde::{Deserialize, Serialize};

use super::{mean_se, normal_sigma_equivalent_t, normal_two_sided_tail, student_t_quantile};
use crate::Error;

/// The crate's agreement level: a difference within the Student-t equivalent of 4 normal σ
/// (tail probability 6.3·10⁻⁵) agrees.
pub const SIGMAS: f64 = 4.0;

/// Fewest independent values from which an error bar is reported without a warning: with 3 the
/// Student-t bound of "4σ" is 32.6σ, with 4 it is 14.2σ (3 dof), and it falls to 5.5σ at 16.
pub const FEW_SAMPLES: usize = 4;

/// Fewest degrees of freedom from which a comparison gives a verdict: the error of
/// [`FEW_SAMPLES`] independent values. Below it the bound means nothing (1 dof: 10 050σ; 2 dof:
/// 127σ) — any difference "agrees" — so no verdict is given, neither agree nor disagree, and an
/// audit reports the check as skipped (INCOMPLETE), never as a PASS.
pub const MIN_VERDICT_DOF: f64 = (FEW_SAMPLES - 1) as f64;

/// The verdict of |z| ≤ `bound` at `dof` degrees of freedom in a word: `agree`, `DISAGREE`, or
/// below [`MIN_VERDICT_DOF`] `no verdict (…)`.
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::comparison::verdict_word;
/// assert_eq!(verdict_word(1.0, 5.5, 15.0), "agree");
/// assert_eq!(verdict_word(9.0, 5.5, 15.0), "DISAGREE");
/// assert!(verdict_word(596.6, 140706.0, 1.0).starts_with("no verdict from 1 dof"));
/// ```
pub fn verdict_word(z: f64, bound: f64, dof: f64) -> String {
    if dof < MIN_VERDICT_DOF || dof.is_nan() {
        no_verdict(dof)
    } else if z.abs() <= bound {
        "agree".into()
    } else {
        "DISAGREE".into()
    }
}

/// Why there is no verdict from `dof` (below [`MIN_VERDICT_DOF`]) degrees of freedom.
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::comparison::no_verdict;
/// assert_eq!(
///     no_verdict(1.0),
///     "no verdict from 1 dof (its 4σ-equivalent bound, 10050σ, means nothing: 4 batches or more)"
/// );
/// ```
pub fn no_verdict(dof: f64) -> String {
    format!(
        "no verdict from {} dof (its 4σ-equivalent bound, {:.0}σ, means nothing: {FEW_SAMPLES} \
         batches or more)",
        dof_text(dof),
        agreement_bound(dof.max(1.0))
    )
}

/// The agreement bound |z| ≤ t for a z with `dof` degrees of freedom (Student-t quantile at the
/// normal 4σ tail).
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::comparison::agreement_bound;
/// assert!((agreement_bound(15.0) - 5.48038).abs() < 1e-4);
/// assert!((agreement_bound(f64::INFINITY) - 4.0).abs() < 1e-9);
/// ```
pub fn agreement_bound(dof: f64) -> f64 {
    normal_sigma_equivalent_t(dof, SIGMAS)
}

/// The bound on the largest of `m` such |z| (Bonferroni): each one at the 4σ tail over `m`, so
/// that a correct run exceeds it with probability at most 6.3·10⁻⁵.
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::comparison::{agreement_bound, largest_of_bound};
/// assert_eq!(largest_of_bound(31.0, 1), agreement_bound(31.0));
/// assert!(largest_of_bound(31.0, 20) > agreement_bound(31.0));
/// ```
pub fn largest_of_bound(dof: f64, m: usize) -> f64 {
    if m <= 1 {
        return agreement_bound(dof);
    }
    student_t_quantile(dof, 0.5 * normal_two_sided_tail(SIGMAS) / m as f64)
}

/// A difference with its standard error, degrees of freedom and agreement bound.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Comparison {
    /// The difference (first minus second).
    pub difference: f64,
    /// Its standard error.
    pub err: f64,
    /// Degrees of freedom of `err`.
    pub dof: f64,
    /// difference / err.
    pub z: f64,
    /// [`agreement_bound`] at `dof`.
    pub bound: f64,
}

impl Comparison {
    /// The difference `x` of two independent estimates with standard errors `(ea, eb)`, each over
    /// `batches` batches, as one of `m` comparisons: the quadrature error with Welch's degrees of
    /// freedom, and the Bonferroni bound over the `m` ([`largest_of_bound`]). Two exact zeros
    /// (both errors 0) are compared as the difference itself.
    pub fn welch(x: f64, (ea, eb): (f64, f64), batches: u32, m: usize) -> Comparison {
        let err = ea.hypot(eb);
        if err == 0.0 {
            return of(x, 0.0, f64::INFINITY);
        }
        let n = f64::from(batches);
        let dof = crate::statistics::welch_dof(ea, n, eb, n);
        Comparison {
            bound: largest_of_bound(dof, m),
            ..of(x, err, dof)
        }
    }

    /// Whether |z| is within the bound.
    pub fn agrees(&self) -> bool {
        self.z.abs() <= self.bound
    }

    /// Whether there are degrees of freedom enough for a verdict ([`MIN_VERDICT_DOF`]).
    pub fn judged(&self) -> bool {
        self.dof >= MIN_VERDICT_DOF
    }

    /// The verdict in a word ([`verdict_word`]): `agree`, `DISAGREE`, or no verdict from too
    /// few degrees of freedom.
    pub fn verdict(&self) -> String {
        verdict_word(self.z, self.bound, self.dof)
    }

    /// One phrase for a report: `+0.7σ (paired over 32 batches, bound 4.6σ: agree)`.
    pub fn describe(&self, how: &str) -> String {
        let verdict = self.verdict();
        format!(
            "{:+.1}σ ({how}, bound {:.1}σ with {} dof: {verdict})",
            self.z,
            self.bound,
            dof_text(self.dof)
        )
    }
}

/// Two estimates from the same `n` batches, compared by the mean and standard error of their
/// per-batch differences (`n − 1` dof).
///
/// # Errors
/// Fewer than 2 batches, or values of different lengths.
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::comparison::paired;
/// // Strongly correlated values: the paired error is far below the quadrature one.
/// let a = [1.00, 2.00, 3.00, 4.00];
/// let b = [0.99, 1.98, 2.99, 3.98];
/// let c = paired(&a, &b).unwrap();
/// assert!((c.difference - 0.015).abs() < 1e-12);
/// assert!(c.z > 5.0); // in quadrature the two means' errors (0.65 each) would give 0.02σ
/// assert!(c.agrees()); // but 4 batches have 3 dof: the bound is 32.6σ
/// ```
pub fn paired(a: &[f64], b: &[f64]) -> Result<Comparison, Error> {
    if a.len() != b.len() {
        return Err(Error::Failed(format!(
            "a paired comparison needs the same batches: {} values against {}",
            a.len(),
            b.len()
        )));
    }
    if a.len() < 2 {
        return Err(Error::TooFew {
            what: "batches for a paired comparison",
            min: 2,
            got: a.len() as u64,
        });
    }
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    let (difference, err) = mean_se(&d);
    Ok(of(difference, err, (a.len() - 1) as f64))
}

/// The degrees of freedom of an error bar from `n` batches, n − 1 (at least 1, so a bound exists
/// for a result that records fewer).
pub fn batch_dof(n: usize) -> f64 {
    n.saturating_sub(1).max(1) as f64
}

/// A difference with standard error `err` on `dof` degrees of freedom (z = 0 for an exact
/// agreement with no spread).
pub fn of(difference: f64, err: f64, dof: f64) -> Comparison {
    let z = if err > 0.0 {
        difference / err
    } else if difference == 0.0 {
        0.0
    } else {
        f64::INFINITY.copysign(difference)
    };
    Comparison {
        difference,
        err,
        dof,
        z,
        bound: agreement_bound(dof),
    }
}

/// The jackknife standard error of an estimate θ computed from `n` batches, given its `n`
/// leave-one-out values θ₍ᵢ₎: √((n − 1)/n · Σ (θ₍ᵢ₎ − θ̄)²), with `n − 1` dof. For a mean it
/// is the batch-means error exactly; for a smooth function of means (a hierarchy value from
/// measured probability tables) it is its delta-method error without the derivatives.
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::{comparison::jackknife_se, mean_se};
/// let x = [1.0f64, 4.0, 2.0, 8.0, 5.0];
/// let n = x.len() as f64;
/// let loo: Vec<f64> = (0..x.len())
///     .map(|i| (x.iter().sum::<f64>() - x[i]) / (n - 1.0))
///     .collect();
/// assert!((jackknife_se(&loo) - mean_se(&x).1).abs() < 1e-12);
/// ```
pub fn jackknife_se(leave_one_out: &[f64]) -> f64 {
    let n = leave_one_out.len() as f64;
    if leave_one_out.len() < 2 {
        return f64::NAN;
    }
    let mean = leave_one_out.iter().sum::<f64>() / n;
    let ss: f64 = leave_one_out.iter().map(|t| (t - mean) * (t - mean)).sum();
    ((n - 1.0) / n * ss).sqrt()
}

/// A note for an error bar from `n` values: empty from [`FEW_SAMPLES`] on, otherwise how few
/// degrees of freedom it has and what "4σ" means with them.
///
/// # Examples
///
/// ```
/// use lorentz_gas::statistics::comparison::few_samples_note;
/// assert_eq!(few_samples_note(32, "batches"), "");
/// assert!(few_samples_note(2, "batches").contains("1 dof"));
/// ```
pub fn few_samples_note(n: usize, what: &str) -> String {
    if n >= FEW_SAMPLES {
        return String::new();
    }
    let dof = n.saturating_sub(1);
    format!(
        " [error from {n} {what}: {dof} dof, so 4σ-equivalent is {:.0}σ; use {FEW_SAMPLES} or more]",
        agreement_bound(dof.max(1) as f64)
    )
}

/// Degrees of freedom as printed: whole numbers as such, Welch's fractional ones to a tenth.
fn dof_text(dof: f64) -> String {
    if dof.fract() == 0.0 {
        format!("{dof}")
    } else {
        format!("{dof:.1}")
    }
}
