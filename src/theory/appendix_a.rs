//! The paper's analytic approximation for the probability p_cf of a collisionless flight
//! across a trap (App. A of Klages & Dellago 2000), generic over [`Real`].
//!
//! | quantity | as printed | evaluated here |
//! |---|---|---|
//! | e (A4) | √3(2+w)/(2 sin(π/3)) − 1/sin(π/3) − 1 | a − 1 − 2/√3 = w − w₀ |
//! | w₀ (A5) | 2(sin(π/3) + 1)/√3 − 2 | 2/√3 − 1 = 1/(3 + 2√3) |
//! | φ (A6) | ∫_{β−δ}^{β+δ} cos²γ dγ = δ + ½cos(π/12) sin 2δ | δ + ½cos(2β) sin 2δ = δ + ¼ sin 2δ |
//! | δ (A7) | arctan[2e cos(π/6) / (2 + w − 2(e+1)cos(π/3) + e sin(π/6))] | arctan[√3 e / (a − 1 − e/2)] |
//! | p_cf (A8) | eφ/w | eφ/w for e > 0, 0 otherwise |
//!
//! With sin(π/3) = cos(π/6) = √3/2 and cos(π/3) = sin(π/6) = 1/2 every trigonometric constant
//! is an algebraic number and is evaluated with √3 at the working precision; only δ needs a
//! transcendental function (arctan) and φ a sine.
//!
//! The printed second line of eq. (A6) is a slip: with β = π/6 the integral is
//! δ + ½cos(π/3) sin 2δ = δ + ¼ sin 2δ, not δ + ½cos(π/12) sin 2δ
//! (`proofs-notes/paper-appendix-a.md`). [`phi`] is the correct integral,
//! [`phi_as_printed`] the printed one.
//!
//! e of eq. (A4) and w₀ of eq. (A5) agree with w₀ = 2/√3 − 1 of
//! [`Geometry::w_0`]: e = a − 1 − 2/√3 vanishes exactly at a = 1 + 2/√3.

use crate::numbers::real::Real;
use crate::scenes::triangular::geometry::Geometry;

/// Eq. (A4) simplified: e = a − 1 − 2/√3, evaluated as w − w₀ (no cancellation between a and
/// 1 + 2/√3). Negative below w₀ (no collisionless flights).
///
/// # Examples
///
/// ```
/// use lorentz_gas::{scenes::triangular::geometry::Geometry, theory::appendix_a::e};
/// let w0 = Geometry::<f64>::w_0(());
/// assert_eq!(e(&Geometry::new(w0).unwrap()), 0.0);
/// ```
pub fn e<T: Real>(g: &Geometry<T>) -> T {
    g.gap() - &Geometry::<T>::w_0(g.ctx())
}

/// Eq. (A4) exactly as printed, with sin(π/3) from the sine function:
/// e = √3(2+w)/(2 sin(π/3)) − 1/sin(π/3) − 1.
pub fn e_as_printed<T: Real>(g: &Geometry<T>) -> T {
    let ctx = g.ctx();
    let s = (g.pi() / &T::from_f64(ctx, 3.0)).sin();
    let t1 = g.sqrt3() * &g.spacing() / &s.clone().scale(2.0);
    let t2 = T::one(ctx) / &s;
    (t1 - &t2).add_f64(-1.0)
}

/// Eq. (A5) exactly as printed: w₀ = 2(sin(π/3) + 1)/√3 − 2 (equal to 2/√3 − 1).
pub fn w0_as_printed<T: Real>(ctx: T::Ctx) -> T {
    let s = (T::pi(ctx) / &T::from_f64(ctx, 3.0)).sin();
    (s.add_f64(1.0).scale(2.0) / &T::sqrt3(ctx)).add_f64(-2.0)
}

/// Eq. (A7): the half-width δ of the cone of directions around β = π/6 that cross the trap
/// without collision, δ = arctan[2e cos(π/6)/(2 + w − 2(e+1)cos(π/3) + e sin(π/6))]
/// = arctan[√3 e/(a − 1 − e/2)]. Only meaningful for e ≥ 0 (it is 0 at e = 0).
pub fn delta<T: Real>(g: &Geometry<T>) -> T {
    let e = e(g);
    let num = g.sqrt3() * &e;
    let den = g.spacing().add_f64(-1.0) - &e.scale(0.5);
    (num / &den).atan()
}

/// Eq. (A6), correct evaluation: φ = ∫_{β−δ}^{β+δ} cos²γ dγ = δ + ½cos(2β) sin(2δ) with
/// β = π/6, cos(2β) = cos(π/3) = ½: φ = δ + ¼ sin 2δ.
///
/// (∫cos²γ dγ = γ/2 + sin(2γ)/4, and sin(2β+2δ) − sin(2β−2δ) = 2 cos 2β sin 2δ.)
pub fn phi<T: Real>(g: &Geometry<T>) -> T {
    let d = delta(g);
    let s = d.clone().scale(2.0).sin();
    d + &s.scale(0.25)
}

/// Eq. (A6) as printed: φ = δ + ½cos(π/12) sin 2δ (a slip for ½cos(π/3) sin 2δ).
pub fn phi_as_printed<T: Real>(g: &Geometry<T>) -> T {
    let d = delta(g);
    let c = (g.pi() / &T::from_f64(g.ctx(), 12.0)).cos();
    let s = d.clone().scale(2.0).sin();
    d + &(c * &s).scale(0.5)
}

/// Eq. (A8): p_cf = eφ/w (S = 6e, p_cf = Sφ/(6w)), with the correct φ of [`phi`];
/// exactly 0 for w ≤ w₀ (e ≤ 0: no collisionless flight exists).
///
/// # Examples
///
/// ```
/// use lorentz_gas::{scenes::triangular::geometry::Geometry, theory::appendix_a::p_cf};
/// assert_eq!(p_cf(&Geometry::new(0.15f64).unwrap()), 0.0);
/// assert!(p_cf(&Geometry::new(0.25f64).unwrap()) > 0.0);
/// ```
pub fn p_cf<T: Real>(g: &Geometry<T>) -> T {
    let e = e(g);
    if !e.gt0() {
        return T::zero(g.ctx());
    }
    e * &phi(g) / &g.gap()
}

/// Eq. (A8) with the printed φ of [`phi_as_printed`] (0 for w ≤ w₀).
pub fn p_cf_as_printed<T: Real>(g: &Geometry<T>) -> T {
    let e = e(g);
    if !e.gt0() {
        return T::zero(g.ctx());
    }
    e * &phi_as_printed(g) / &g.gap()
}

/// Eq. (A1) before the Machta–Zwanzig substitution: p_cf = S v τ φ/(2πA) with S = 6e, v = 1
/// and τ = πA/(3w) from [`Geometry::hop_time`]; equals [`p_cf`] up to rounding.
pub fn p_cf_phase_space<T: Real>(g: &Geometry<T>) -> T {
    let e = e(g);
    if !e.gt0() {
        return T::zero(g.ctx());
    }
    e.scale(6.0) * &g.hop_time() * &phi(g) / &(g.pi().scale(2.0) * &g.trap_area())
}

/// A flux-consistent variant (not in the paper): the invariant measure is uniform in the
/// angle, so the crossing flux through a segment carries one factor cos γ, and
/// p = (S/(6w))∫_Γ cos γ dγ; over a whole gap (S = 3w) and all angles this gives 1, whereas
/// the paper's ∫cos²γ gives π/4. With Γ = [β − δ, β + δ]: ∫cos γ dγ = 2 cos β sin δ = √3 sin δ,
/// so p = √3 e sin δ / w (0 for w ≤ w₀). See `proofs-notes/paper-appendix-a.md`.
pub fn p_cf_flux_weighted<T: Real>(g: &Geometry<T>) -> T {
    let e = e(g);
    if !e.gt0() {
        return T::zero(g.ctx());
    }
    g.sqrt3() * &e * &delta(g).sin() / &g.gap()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rug::Float;

    fn g256(w: f64) -> Geometry<Float> {
        Geometry::new(Float::with_val(256, w)).unwrap()
    }

    #[test]
    fn printed_e_and_w0_agree_with_w0_of_the_geometry() {
        // A4 printed vs a − 1 − 2/√3 at 256 bits: a handful of roundings of numbers ≤ 3,
        // |Δ| ≤ 32·2^-256 (we allow 2^-240).
        let tol = Float::with_val(256, -240f64).exp2();
        for &w in &[0.1, 0.1547, 0.2, 0.3] {
            let g = g256(w);
            let d = (e_as_printed(&g) - &e(&g)).abs();
            assert!(d < tol, "w = {w}: {d}");
        }
        let w0 = Geometry::<Float>::w_0(256);
        assert!((w0_as_printed::<Float>(256) - &w0).abs() < tol);
        // e(w₀) = 0: exactly with the cancellation-free form, to 2^-240 as printed.
        let g0 = Geometry::new(w0).unwrap();
        assert_eq!(e(&g0), 0);
        assert!(e_as_printed(&g0).abs() < tol);
        // And the printed 0.1547.
        assert!((w0_as_printed::<f64>(()) - 0.1547).abs() < 5e-5);
    }

    #[test]
    fn no_collisionless_flights_below_w0() {
        for &w in &[0.01, 0.1, 0.15] {
            let g = Geometry::new(w).unwrap();
            assert_eq!(p_cf(&g), 0.0);
            assert_eq!(p_cf_as_printed(&g), 0.0);
            assert_eq!(p_cf_flux_weighted(&g), 0.0);
        }
        let g0 = Geometry::new(Geometry::<Float>::w_0(256)).unwrap();
        assert_eq!(p_cf(&g0), 0);
        assert_eq!(delta(&g0), 0);
    }

    #[test]
    fn phi_is_the_integral_of_cos_squared() {
        // Composite Simpson with n = 64 panels: |error| ≤ (b − a) h⁴ max|f⁗|/180 with
        // f = cos², f⁗ = −8 cos 2γ, h = 2δ/n; plus f64 rounding of ~n terms (≤ 2n·u).
        for &w in &[0.18, 0.25, 0.3] {
            let g = Geometry::new(w).unwrap();
            let d = delta(&g);
            let (a, b) = (
                std::f64::consts::PI / 6.0 - d,
                std::f64::consts::PI / 6.0 + d,
            );
            let n = 64;
            let h = (b - a) / n as f64;
            let f = |x: f64| x.cos() * x.cos();
            let mut s = f(a) + f(b);
            for i in 1..n {
                s += f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 };
            }
            let simpson = s * h / 3.0;
            let bound = (b - a) * h.powi(4) * 8.0 / 180.0 + 2.0 * n as f64 * f64::EPSILON;
            assert!((simpson - phi(&g)).abs() <= bound, "w = {w}");
            // The printed form is not the integral.
            assert!((simpson - phi_as_printed(&g)).abs() > 1e3 * bound);
        }
    }

    #[test]
    fn printed_phi_exceeds_the_integral_by_the_slip() {
        // φ_printed − φ = (½cos(π/12) − ¼) sin 2δ, at 256 bits to 2^-240.
        let g = g256(0.25);
        let diff = phi_as_printed(&g) - &phi(&g);
        let c = (Float::with_val(256, rug::float::Constant::Pi) / 12u32).cos() / 2u32 - 0.25f64;
        let expect = c * (delta(&g) * 2u32).sin();
        assert!((diff - &expect).abs() < Float::with_val(256, -240f64).exp2());
        assert!(expect > 0.05);
    }

    #[test]
    fn phase_space_form_equals_e_phi_over_w() {
        // p = 6e·τ·φ/(2πA) with τ = πA/(3w): eight roundings, |Δ|/p ≤ 16u.
        for &w in &[0.16, 0.2, 0.25, 0.3] {
            let g = Geometry::new(w).unwrap();
            let (a, b) = (p_cf(&g), p_cf_phase_space(&g));
            assert!((a - b).abs() <= 16.0 * f64::EPSILON / 2.0 * a, "w = {w}");
        }
    }

    #[test]
    fn f64_agrees_with_256_bits() {
        // Condition of the chain w ↦ e ↦ δ ↦ φ ↦ p near w = 0.3 is O(10) (e = w − w₀ loses
        // nothing: Sterbenz); libm sin/atan are within 1 ulp: relative 64u is an upper bound.
        for &w in &[0.16, 0.2, 0.25, 0.3] {
            let a = p_cf(&Geometry::new(w).unwrap());
            let b = p_cf(&g256(w)).to_f64();
            assert!(
                (a - b).abs() <= 64.0 * f64::EPSILON / 2.0 * b,
                "w = {w}: {a} {b}"
            );
        }
    }

    #[test]
    fn known_values() {
        // Values at 256 bits (recorded in proofs-notes/paper-appendix-a.md).
        let g = g256(0.3);
        let p = p_cf(&g).to_f64();
        let pp = p_cf_as_printed(&g).to_f64();
        let pf = p_cf_flux_weighted(&g).to_f64();
        assert!(p > 0.0 && pp > p && pf > p, "{p} {pp} {pf}");
        // e(0.3) = 0.3 − w₀ = 0.14529946162074848…
        let e3 = e(&g).to_f64();
        assert!((e3 - 0.145_299_461_620_748_48).abs() < 1e-16);
        // Recorded 256-bit values (proofs-notes/paper-appendix-a.md), 17 decimals: the decimal
        // rounding is ≤ 5e-18 absolute, the conversion to f64 ≤ u relative.
        let cases = [
            (0.2, 0.022_585_692_593_464_68, 0.029_587_389_557_863_16),
            (0.25, 0.077_689_445_106_467_05, 0.101_621_410_150_733_57),
            (0.3, 0.145_605_740_804_566_54, 0.190_010_473_171_062_54),
        ];
        for (w, correct, printed) in cases {
            let g = g256(w);
            let a = p_cf(&g).to_f64();
            let b = p_cf_as_printed(&g).to_f64();
            let u = f64::EPSILON / 2.0;
            assert!((a - correct).abs() <= 5e-18 + u * correct, "w = {w}: {a}");
            assert!((b - printed).abs() <= 5e-18 + u * printed, "w = {w}: {b}");
        }
    }
}
