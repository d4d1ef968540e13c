//! Gauss–Legendre quadrature, adaptive, for the piecewise smooth integrands of the exact
//! magnetic-field geometry ([`super::magnetic`]). Written here because it is twenty lines and
//! none of the crates the project builds on provides it.
//!
//! Integrands with square-root behaviour at the ends of a piece (a circle tangent to the line of
//! integration) are integrated after the substitution x = lo + (hi − lo)(1 − cos θ)/2, which
//! makes them smooth in θ; kinks inside a piece are found by bisection.

use std::f64::consts::PI;

/// The n-point Gauss–Legendre nodes and weights on [−1, 1], by Newton's method on Pₙ.
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let step = p1 / dp;
                x -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

/// ∫ f over [lo, hi] after the substitution x = lo + (hi − lo)(1 − cos θ)/2, by one rule.
fn rule<F: Fn(f64) -> f64>(f: &F, lo: f64, hi: f64, nodes: &[(f64, f64)], t0: f64, t1: f64) -> f64 {
    let (mid, half) = ((t0 + t1) / 2.0, (t1 - t0) / 2.0);
    let span = (hi - lo) / 2.0;
    nodes
        .iter()
        .map(|&(u, w)| {
            let t = mid + half * u;
            w * f(lo + span * (1.0 - t.cos())) * span * t.sin()
        })
        .sum::<f64>()
        * half
}

/// ∫ f over [lo, hi] to the absolute tolerance `tol` (square-root ends allowed, kinks inside
/// found by bisection, at most 40 levels deep).
pub fn integrate<F: Fn(f64) -> f64>(f: &F, lo: f64, hi: f64, tol: f64) -> f64 {
    if hi <= lo {
        return 0.0;
    }
    let nodes = gauss_legendre(16);
    let whole = rule(f, lo, hi, &nodes, 0.0, PI);
    refine(f, lo, hi, &nodes, (0.0, PI), whole, tol, 40)
}

#[allow(clippy::too_many_arguments)]
fn refine<F: Fn(f64) -> f64>(
    f: &F,
    lo: f64,
    hi: f64,
    nodes: &[(f64, f64)],
    (t0, t1): (f64, f64),
    whole: f64,
    tol: f64,
    depth: u32,
) -> f64 {
    let tm = (t0 + t1) / 2.0;
    let left = rule(f, lo, hi, nodes, t0, tm);
    let right = rule(f, lo, hi, nodes, tm, t1);
    if (left + right - whole).abs() <= tol || depth == 0 {
        return left + right;
    }
    refine(f, lo, hi, nodes, (t0, tm), left, tol / 2.0, depth - 1)
        + refine(f, lo, hi, nodes, (tm, t1), right, tol / 2.0, depth - 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_area_of_a_half_disk_and_a_kink() {
        let half_disk = integrate(&|x: f64| (1.0 - x * x).max(0.0).sqrt(), -1.0, 1.0, 1e-14);
        assert!((half_disk - PI / 2.0).abs() < 1e-13, "{half_disk}");
        let kink = integrate(&|x: f64| (x - 0.3).abs(), 0.0, 1.0, 1e-14);
        assert!((kink - (0.09 + 0.49) / 2.0).abs() < 1e-12, "{kink}");
        let w = gauss_legendre(5).iter().map(|p| p.1).sum::<f64>();
        assert!((w - 2.0).abs() < 1e-14);
    }
}
