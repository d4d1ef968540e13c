//! Gauss–Legendre quadrature, adaptive, for the piecewise smooth integrands of the exact
//! magnetic-field geometry ([`super::magnetic`]). Written here because it is twenty lines and
//! none of the crates the project builds on provides it.
//!
//! Integrands with square-root behaviour at the ends of a piece (a circle tangent to the line of
//! integration) are integrated after the substitution x = lo + (hi − lo)(1 − cos θ)/2, which
//! makes them smooth in θ. [`integrate`] finds kinks inside a piece by bisection (to its
//! tolerance only: a kink costs accuracy); [`integrate_smooth`] is for pieces cut at every kink,
//! where the rule converges exponentially and the stopping test can ask for near-rounding
//! accuracy.

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

/// The 16-point Gauss–Legendre rule, computed once.
fn nodes16() -> &'static [(f64, f64)] {
    static NODES: std::sync::OnceLock<Vec<(f64, f64)>> = std::sync::OnceLock::new();
    NODES.get_or_init(|| gauss_legendre(16))
}

/// ∫ f over [lo, hi] for an `f` smooth inside the interval (square-root behaviour at its ends
/// allowed: the cos substitution makes it smooth) with |f| ≤ `bound`.
///
/// The interval is bisected in the substituted variable θ until the 16-point rule W on a part
/// and the sum L + R of the rules on its halves agree to `rel`·`bound`·(ℓ + `floor`·Δθ/π), ℓ the
/// part's length in x and Δθ its share of θ ∈ [0, π]; L + R is returned. For an integrand
/// analytic on the part, |L + R − W| is W's error to leading order, and L + R's own error is
/// smaller by the rule's order (2⁻³² per halving in the asymptotic regime), so the sum of the
/// tests, ≤ `rel`·`bound`·(hi − lo + `floor`), bounds the error with a wide margin. The test
/// stays above rounding: a term's rounding is relative 2⁻⁵³ of `bound`·ℓ, except next to a
/// square-root end, where f(lo + δ) has the rounding of lo amplified by 1/√δ — on a piece
/// shorter than (2⁻⁵³/`rel`)² that is every part, and the `floor` (a length: the caller's scale,
/// say 10⁻³ of its period) keeps those parts from being split for noise. At most 24 levels deep.
pub fn integrate_smooth<F: Fn(f64) -> f64>(
    f: &F,
    lo: f64,
    hi: f64,
    bound: f64,
    (rel, floor): (f64, f64),
) -> f64 {
    if hi <= lo {
        return 0.0;
    }
    let nodes = nodes16();
    let whole = rule(f, lo, hi, nodes, 0.0, PI);
    // The part [t0, t1] of θ spans (cos t0 − cos t1)(hi − lo)/2 in x.
    let tol = |t0: f64, t1: f64| {
        rel * bound * ((t0.cos() - t1.cos()) * (hi - lo) / 2.0 + floor * (t1 - t0) / PI)
    };
    let mut total = 0.0;
    let mut stack = vec![(0.0, PI, whole, 24u32)];
    while let Some((t0, t1, w, depth)) = stack.pop() {
        let tm = (t0 + t1) / 2.0;
        let (left, right) = (
            rule(f, lo, hi, nodes, t0, tm),
            rule(f, lo, hi, nodes, tm, t1),
        );
        if (left + right - w).abs() <= tol(t0, t1) || depth == 0 {
            total += left + right;
        } else {
            stack.push((t0, tm, left, depth - 1));
            stack.push((tm, t1, right, depth - 1));
        }
    }
    total
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

    #[test]
    fn a_smooth_piece_to_rounding() {
        // A quarter disk (square-root end at x = 1) and an analytic integrand.
        let quarter = integrate_smooth(
            &|x: f64| (1.0 - x * x).max(0.0).sqrt(),
            0.0,
            1.0,
            1.0,
            (1e-14, 1e-3),
        );
        assert!((quarter - PI / 4.0).abs() < 4e-16, "{}", quarter - PI / 4.0);
        let exp = integrate_smooth(&f64::exp, 0.0, 2.0, 8.0, (1e-14, 1e-3));
        assert!(
            (exp - (2f64.exp() - 1.0)).abs() < 4e-15,
            "{}",
            exp - (2f64.exp() - 1.0)
        );
    }
}
