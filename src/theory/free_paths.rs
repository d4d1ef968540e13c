//! The Boltzmann–Grad limit law of the free path between collisions on a lattice of small disks
//! (`proofs-notes/free-path-law.md` derives it).
//!
//! For disks of radius r at the points of a planar lattice with one disk per cell of area A, let
//! τ be the free path from one collision to the next under the billiard map's invariant measure
//! and ξ = τ/⟨ℓ⟩ with Santaló's mean free path ⟨ℓ⟩ = (A − πr²)/(2r) (so ⟨ξ⟩ = 1 exactly at
//! every radius). As r → 0 the law of ξ tends, for every lattice, to the density
//!
//! g(ξ) = (6/π²) F(ξ),  F(ξ) = c₊² + ∫_{|c|}^1 [(w + c) − (w − c) ln(2w/(w − c))] dw,
//! c = 2/ξ − 1,
//!
//! with F = 1 for ξ ≤ 1 (Dahlqvist 1997; Boca & Zaharescu 2007; Marklof & Strömbergsson 2008
//! write it as an integral over the impact parameters, which the inner integral above does in
//! closed form). Three exact moments fix it: ∫g = 1, ∫ξg = 1, and
//! ∫ ln ξ · g = 27ζ(3)/(2π²) − 3 ln 2 ([`LN_MEAN`]), which is Dahlqvist's constant of the
//! Lyapunov exponent less 1 − ln 2 (the mean of −ln cos φ). Its tail g ≈ 4/(π²ξ³) is the
//! small-r limit of the corridor constants ([`super::corridors`]).

use std::f64::consts::PI;

use super::quadrature::integrate;

/// ζ(3), Apéry's constant.
const ZETA3: f64 = 1.202_056_903_159_594_3;

/// The limit law's mean of ln ξ: 27ζ(3)/(2π²) − 3 ln 2 = −0.435 22.
pub const LN_MEAN: f64 = 27.0 * ZETA3 / (2.0 * PI * PI) - 3.0 * std::f64::consts::LN_2;

/// The limit law's density at 0 (and on all of (0, 1]): 6/π².
pub const DENSITY_AT_ZERO: f64 = 6.0 / (PI * PI);

/// x − ln(1 + x) for x ≥ 0, without the cancellation of the difference at small x.
fn x_minus_ln1p(x: f64) -> f64 {
    if x < 0.03 {
        // Alternating series; its 10th term is below 2⁻⁵³ of the first for x < 0.03.
        let mut sum = 0.0;
        let mut power = x * x;
        for k in 2..12 {
            let term = power / k as f64;
            sum += if k % 2 == 0 { term } else { -term };
            power *= x;
        }
        sum
    } else {
        x - x.ln_1p()
    }
}

/// F(ξ): the limit density over 6/π² (the probability that a random unimodular lattice leaves
/// the strip of the flight free up to ξ). 1 for ξ ≤ 1, about 2/(3ξ³) + 1/(2ξ⁴) for large ξ;
/// computed to a relative 10⁻¹² or better.
///
/// # Examples
///
/// ```
/// use lorentz_gas::theory::free_paths::shape;
/// assert_eq!(shape(0.5), 1.0);
/// assert!((shape(2.0) - 0.153_43).abs() < 1e-4);
/// let xi = 1e4;
/// assert!((shape(xi) / (2.0 / (3.0 * xi.powi(3))) - 1.0).abs() < 1e-3);
/// ```
pub fn shape(xi: f64) -> f64 {
    if xi <= 1.0 {
        return 1.0;
    }
    // With c = 2/ξ − 1 and η = w − |c| the bracket is (w − c)·φ(x), x = (w + c)/(w − c),
    // φ(x) = x − ln(1 + x), where w + c and w − c are η plus one of 2c₊ and 2(−c)₊: written so,
    // nothing cancels, not even where the integral is tiny (ξ large, c near −1).
    let h = |eta: f64, plus: f64, minus: f64| {
        let (sum, diff) = (eta + plus, eta + minus);
        if diff <= 0.0 {
            return sum;
        }
        diff * x_minus_ln1p(sum / diff)
    };
    if xi >= 2.0 {
        // c ≤ 0: η ∈ [0, 2/ξ], w + c = η, w − c = η + 2 − 4/ξ; F ≈ (2/ξ)³/12.
        let (len, minus) = (2.0 / xi, 2.0 - 4.0 / xi);
        let scale = len.powi(3) / 12.0;
        integrate(&|eta| h(eta, 0.0, minus), 0.0, len, 1e-14 * scale)
    } else {
        // c > 0: η ∈ [0, 1 − c], w + c = η + 2c, w − c = η.
        let c = 2.0 / xi - 1.0;
        c * c + integrate(&|eta| h(eta, 2.0 * c, 0.0), 0.0, 1.0 - c, 1e-14)
    }
}

/// The limit density g(ξ) = (6/π²)·F(ξ) of ξ = τ/⟨ℓ⟩ (0 for ξ < 0).
pub fn density(xi: f64) -> f64 {
    if xi < 0.0 {
        return 0.0;
    }
    DENSITY_AT_ZERO * shape(xi)
}

/// The limit probability of lo ≤ ξ < hi (hi may be +∞), to about 10⁻¹² absolute.
///
/// # Examples
///
/// ```
/// use lorentz_gas::theory::free_paths::probability;
/// assert!((probability(0.0, 1.0) - 6.0 / std::f64::consts::PI.powi(2)).abs() < 1e-12);
/// assert!((probability(0.0, f64::INFINITY) - 1.0).abs() < 1e-12);
/// ```
pub fn probability(lo: f64, hi: f64) -> f64 {
    let lo = lo.max(0.0);
    if hi <= lo {
        return 0.0;
    }
    if hi.is_infinite() {
        return 1.0 - below(lo);
    }
    DENSITY_AT_ZERO * integral(lo, hi)
}

/// P(ξ < x) = (6/π²)∫₀ˣ F.
fn below(x: f64) -> f64 {
    DENSITY_AT_ZERO * integral(0.0, x)
}

/// ∫ F over [lo, hi], in pieces that end at F's kinks (ξ = 1, 2) and grow geometrically beyond.
fn integral(lo: f64, hi: f64) -> f64 {
    let mut cuts = vec![lo];
    let mut x = 1.0;
    while x < hi {
        if x > lo {
            cuts.push(x);
        }
        x = if x < 2.0 { x + 0.5 } else { x * 1.5 };
    }
    cuts.push(hi);
    cuts.windows(2)
        .map(|p| integrate(&shape, p[0], p[1], 1e-13))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ₓ^∞ of F, ξF and ln ξ·F from the two-term tail F ≈ 2/(3ξ³) + 1/(2ξ⁴).
    fn tails(x: f64) -> [f64; 3] {
        let l = x.ln();
        [
            1.0 / (3.0 * x * x) + 1.0 / (6.0 * x.powi(3)),
            2.0 / (3.0 * x) + 1.0 / (4.0 * x * x),
            (2.0 / 3.0) * (l / (2.0 * x * x) + 1.0 / (4.0 * x * x))
                + 0.5 * (l / (3.0 * x.powi(3)) + 1.0 / (9.0 * x.powi(3))),
        ]
    }

    /// The three exact moments: total probability 1, mean 1 (⟨ξ⟩ = 1 by Santaló's formula at every
    /// radius), and ⟨ln ξ⟩ from Dahlqvist's Lyapunov constant. Up to ξ = 400 by quadrature, beyond
    /// by the two-term tail, whose next term contributes below 10⁻⁷. Broken on purpose
    /// (c = 2/ξ − 1 replaced by 1/ξ − 1): the total is 0.644, off by 0.36.
    #[test]
    fn the_limit_law_has_its_three_exact_moments() {
        let x = 400.0;
        let [t0, t1, tl] = tails(x);
        let cuts: Vec<f64> = [
            0.0, 1.0, 1.5, 2.0, 3.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, x,
        ]
        .to_vec();
        let mut m = [0.0; 3];
        for p in cuts.windows(2) {
            m[0] += integrate(&shape, p[0], p[1], 1e-12);
            m[1] += integrate(&|t: f64| t * shape(t), p[0], p[1], 1e-12);
            m[2] += integrate(&|t: f64| t.ln() * shape(t), p[0].max(1e-300), p[1], 1e-12);
        }
        let g = DENSITY_AT_ZERO;
        let total = g * (m[0] + t0);
        let mean = g * (m[1] + t1);
        let ln_mean = g * (m[2] + tl);
        println!("total {total:.12}, mean {mean:.12}, <ln xi> {ln_mean:.12} vs {LN_MEAN:.12}");
        assert!((total - 1.0).abs() < 1e-9, "{total}");
        assert!((mean - 1.0).abs() < 1e-7, "{mean}");
        assert!((ln_mean - LN_MEAN).abs() < 1e-7, "{ln_mean}");
    }

    /// F against its large-ξ expansion 2/(3ξ³) + 1/(2ξ⁴), whose next term is O(ξ⁻⁵).
    #[test]
    fn the_tail_is_the_corridor_tail() {
        for xi in [100.0f64, 1e3, 1e4, 1e6] {
            let asymptotic = 2.0 / (3.0 * xi * xi * xi) + 1.0 / (2.0 * xi.powi(4));
            let rel = shape(xi) / asymptotic - 1.0;
            assert!(rel.abs() < 10.0 / (xi * xi), "xi {xi}: {rel}");
        }
    }

    /// The closed form of the inner integral against the integral itself at ξ ≤ 2 (where the
    /// closed form does not cancel): H(1) − H(c) + c².
    #[test]
    fn the_quadrature_matches_the_closed_form() {
        for xi in [1.01, 1.2, 1.5, 1.9, 2.0, 2.5, 4.0] {
            let c: f64 = 2.0 / xi - 1.0;
            // x·ln x and x²·ln x, continued by 0 at x = 0.
            let xl = |x: f64, p: i32| if x > 0.0 { x.powi(p) * x.ln() } else { 0.0 };
            let hh = |w: f64| {
                let d = w - c;
                let l2 = |p: i32| xl(w, p) + w.powi(p) * std::f64::consts::LN_2;
                (w + c).powi(2) / 2.0 - (l2(2) / 2.0 - w * w / 4.0 - c * l2(1) + c * w)
                    + xl(d, 2) / 2.0
                    - d * d / 4.0
            };
            let closed = c.max(0.0).powi(2) + hh(1.0) - hh(c.abs());
            assert!(
                (shape(xi) - closed).abs() < 1e-12,
                "{xi}: {} vs {closed}",
                shape(xi)
            );
        }
    }

    #[test]
    fn bin_probabilities_add_up() {
        let edges = [0.0, 0.5, 1.0, 1.5, 2.0, 3.0, 5.0, 10.0, f64::INFINITY];
        let sum: f64 = edges.windows(2).map(|p| probability(p[0], p[1])).sum();
        assert!((sum - 1.0).abs() < 1e-11, "{sum}");
        assert!((probability(0.0, 1.0) - DENSITY_AT_ZERO).abs() < 1e-13);
    }
}
