//! The statistics of a diffusion result's batch values: between-group χ², the most extreme
//! batch, and the batch error against the errors of blocks of batches.

use super::{ALPHA, Checks};
use crate::statistics::{mean_se, student_t_quantile};

/// The between-group χ², the most extreme batch, and batch against block errors.
pub(super) fn batch_statistics(x: &[f64], checks: &mut Checks) {
    between_groups_check(x, checks);
    outlier_check(x, checks);
    block_error_checks(x, checks);
}

/// The between-group χ² of four groups of consecutive batches.
fn between_groups_check(x: &[f64], checks: &mut Checks) {
    let n = x.len();
    // Four groups of consecutive batches (the last takes the remainder).
    let groups = 4;
    let size = n / groups;
    let parts: Vec<(f64, f64)> = (0..groups)
        .map(|k| {
            let hi = if k + 1 == groups { n } else { (k + 1) * size };
            mean_se(&x[k * size..hi])
        })
        .collect();
    let wsum: f64 = parts.iter().map(|(_, e)| 1.0 / (e * e)).sum();
    let m = parts.iter().map(|(v, e)| v / (e * e)).sum::<f64>() / wsum;
    let chi2: f64 = parts.iter().map(|(v, e)| ((v - m) / e).powi(2)).sum();
    let p = chi2_upper_p(chi2, (groups - 1) as f64);
    checks.pass_if(
        p > ALPHA,
        "statistics",
        "between-batch χ²: four groups of consecutive batches agree",
        format!(
            "χ² = {chi2:.2} for {} dof, p = {p:.3} (fail below {ALPHA})",
            groups - 1
        ),
        &[("chi2", chi2), ("dof", (groups - 1) as f64), ("p", p)],
    );
}

/// The most extreme batch against a Bonferroni Student-t bound: each batch against the mean and
/// spread of the others (externally studentised, t with n − 2 dof), in O(n) from the totals.
fn outlier_check(x: &[f64], checks: &mut Checks) {
    let n = x.len();
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
        if t.abs() > worst.1.abs() {
            worst = (b, t);
        }
    }
    let bound = student_t_quantile((n - 2) as f64, ALPHA / (2.0 * n as f64));
    checks.pass_if(
        worst.1.abs() <= bound,
        "statistics",
        "no outlying batch",
        format!(
            "most extreme batch {}: t = {:+.2} against the Bonferroni bound {bound:.2} (t with {} dof, {ALPHA} over {n} batches)",
            worst.0,
            worst.1,
            n - 2
        ),
        &[("t", worst.1), ("bound", bound)],
    );
}

/// The batch error against the errors of blocks of 2 and 4 batches (F bounds).
fn block_error_checks(x: &[f64], checks: &mut Checks) {
    let n = x.len();
    // Blocks of k consecutive batches: (SE_k / SE_1)² ~ F(n/k − 1, n − 1) for independent batches.
    let se1 = mean_se(x).1;
    for k in [2usize, 4] {
        let nb = n / k;
        if nb < 3 {
            continue;
        }
        let blocks: Vec<f64> = (0..nb)
            .map(|i| x[i * k..(i + 1) * k].iter().sum::<f64>() / k as f64)
            .collect();
        let sek = mean_se(&blocks).1;
        let ratio2 = (sek / se1).powi(2);
        let (lo, hi) = (
            f_quantile((nb - 1) as f64, (n - 1) as f64, ALPHA / 2.0),
            f_quantile((nb - 1) as f64, (n - 1) as f64, 1.0 - ALPHA / 2.0),
        );
        checks.pass_if(
            ratio2 >= lo && ratio2 <= hi,
            "statistics",
            &format!("batch error against blocks of {k} batches"),
            format!(
                "error from {nb} blocks of {k} / error from {n} batches = {:.3} (independent batches: its square within [{lo:.3}, {hi:.3}], F({}, {}) at {ALPHA})",
                ratio2.sqrt(),
                nb - 1,
                n - 1
            ),
            &[("ratio", ratio2.sqrt())],
        );
    }
}

/// F(d1, d2) quantile at lower-tail probability p.
fn f_quantile(d1: f64, d2: f64, p: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, FisherSnedecor};
    FisherSnedecor::new(d1, d2).map_or(f64::NAN, |f| f.inverse_cdf(p))
}

fn chi2_upper_p(x: f64, dof: f64) -> f64 {
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    ChiSquared::new(dof).map_or(f64::NAN, |c| c.sf(x))
}
