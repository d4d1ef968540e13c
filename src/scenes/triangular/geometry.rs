//! Closed-form geometry of the triangular Lorentz gas (disk radius R = 1, speed v = 1).
//!
//! Every formula is generic over [`Real`] and evaluated at the working precision; the
//! derivations are in `proofs-notes/geometry.md`, each with the test that enforces it.
//!
//! | quantity | formula |
//! |---|---|
//! | lattice spacing | a = 2 + w |
//! | number density | n = 2 / (√3 a²) |
//! | horizon threshold | w∞ = 4/√3 − 2 ≈ 0.3094 (the paper's "4√3 − 2" is a typo) |
//! | collisionless-flight onset | w₀ = 2/√3 − 1 ≈ 0.1547 |
//! | trap (triangle minus three 60° sectors) | A = √3 a²/4 − π/2 |
//! | free area per disk | \|Q\| = 1/n − π = 2A |
//! | boundary per disk | \|∂Q\| = 2π |
//! | Santaló mean free path | ⟨ℓ⟩ = π\|Q\|/\|∂Q\| = A |
//! | distance between trap centres | l = a/√3 |
//! | mean trap residence (hop) time | τ = πA/(3w) |
//! | collisions per hop | τ/⟨ℓ⟩ = π/(3w) |
//! | Machta–Zwanzig | D_MZ = l²/(4τ) = w a² / (π(√3 a² − 2π)) |
//! | Boltzmann (excluded volume) | D_Bo = (3/16)(1/n − π) |

use rug::Float;

use crate::Error;
use crate::numbers::real::Real;

/// Closed-form quantities at one gap `w`, computed at the precision of `w`.
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::triangular::geometry::Geometry;
/// let g = Geometry::new(0.1f64).unwrap();
/// assert!((g.spacing() - 2.1).abs() < 1e-15);
/// // ⟨ℓ⟩ = A: Santaló's formula with |Q| = 2A and |∂Q| = 2π.
/// assert!((g.mean_free_path() - g.trap_area()).abs() < 1e-15);
/// ```
#[derive(Debug, Clone)]
pub struct Geometry<T: Real> {
    w: T,
    a: T,
    sqrt3: T,
    pi: T,
}

impl<T: Real> Geometry<T> {
    /// Geometry at gap `w > 0` (any `w > 0`, including `w ≥ w∞`, is a valid *geometry*;
    /// see [`check_diffusive_gap`] for the range where D exists).
    pub fn new(w: T) -> Result<Self, Error> {
        let ctx = w.ctx();
        let a = crate::kernel::trap::spacing(&w)?;
        Ok(Geometry {
            a,
            sqrt3: T::sqrt3(ctx),
            pi: T::pi(ctx),
            w,
        })
    }

    /// The precision context.
    pub fn ctx(&self) -> T::Ctx {
        self.w.ctx()
    }
    /// The gap w.
    pub fn gap(&self) -> T {
        self.w.clone()
    }
    /// √3 at the working precision.
    pub fn sqrt3(&self) -> T {
        self.sqrt3.clone()
    }
    /// π at the working precision.
    pub fn pi(&self) -> T {
        self.pi.clone()
    }
    /// Lattice spacing a = 2 + w.
    pub fn spacing(&self) -> T {
        self.a.clone()
    }
    /// Height of a trap triangle, h = √3 a / 2 (also the spacing between rows of disks).
    pub fn row_spacing(&self) -> T {
        (self.sqrt3.clone() * &self.a).scale(0.5)
    }
    /// Number density n = 2/(√3 a²) (paper eq. 1).
    pub fn density(&self) -> T {
        T::from_f64(self.ctx(), 2.0) / (self.sqrt3.clone() * &self.a.square())
    }
    /// Horizon threshold w∞ = 4/√3 − 2, evaluated as 2/(3 + 2√3) (same number, no cancellation:
    /// 4/√3 − 2 = 2(2 − √3)/√3 and 2 − √3 = 1/(2 + √3)).
    pub fn w_inf(ctx: T::Ctx) -> T {
        T::from_f64(ctx, 2.0) / &T::sqrt3(ctx).scale(2.0).add_f64(3.0)
    }
    /// Onset of collisionless flights across a trap, w₀ = 2/√3 − 1 = 1/(3 + 2√3) = w∞/2.
    pub fn w_0(ctx: T::Ctx) -> T {
        T::one(ctx) / &T::sqrt3(ctx).scale(2.0).add_f64(3.0)
    }
    /// Free area of one trap: A = √3 a²/4 − π/2.
    pub fn trap_area(&self) -> T {
        (self.sqrt3.clone() * &self.a.square()).scale(0.25) - &self.pi.clone().scale(0.5)
    }
    /// Free area per disk |Q| = 1/n − π = 2A (two traps per disk).
    pub fn free_area_per_disk(&self) -> T {
        self.trap_area().scale(2.0)
    }
    /// Scatterer boundary per disk |∂Q| = 2π.
    pub fn boundary_per_disk(&self) -> T {
        self.pi.clone().scale(2.0)
    }
    /// Santaló's mean free path ⟨ℓ⟩ = π|Q|/|∂Q| (= A).
    pub fn mean_free_path(&self) -> T {
        self.pi.clone() * &self.free_area_per_disk() / &self.boundary_per_disk()
    }
    /// Distance between neighbouring trap centres l = a/√3.
    pub fn trap_distance(&self) -> T {
        self.a.clone() / &self.sqrt3
    }
    /// Mean trap residence time τ = πA/(3w) (Machta–Zwanzig; Kac's lemma).
    pub fn hop_time(&self) -> T {
        self.pi.clone() * &self.trap_area() / &self.w.clone().scale(3.0)
    }
    /// Mean number of collisions per hop, τ/⟨ℓ⟩ = π/(3w).
    pub fn collisions_per_hop(&self) -> T {
        self.pi.clone() / &self.w.clone().scale(3.0)
    }
    /// Machta–Zwanzig D_MZ = l²/(4τ) = w(2+w)²/(π[√3(2+w)² − 2π]) (paper eq. 2).
    pub fn d_mz(&self) -> T {
        let a2 = self.a.square();
        self.w.clone() * &a2
            / &(self.pi.clone() * &(self.sqrt3.clone() * &a2 - &self.pi.clone().scale(2.0)))
    }
    /// Boltzmann with excluded volume D_Bo = (3/16)(1/n − π) (paper eq. 8).
    pub fn d_bo(&self) -> T {
        let inv_n = T::one(self.ctx()) / &self.density();
        (inv_n - &self.pi).scale(3.0 / 16.0)
    }
    /// Upper bound on the length of any free flight (finite for w < w∞, `None` otherwise);
    /// see [`crate::scenes::triangular::geometry::max_free_path_bound`].
    pub fn max_free_path_bound(&self) -> Option<T> {
        max_free_path_bound(self)
    }
}

/// Upper bound on the free path for `w < w∞` (proof in `proofs-notes/max-free-path.md`).
///
/// * `w < w₀`: no trap can be crossed without a collision, so a free flight visits at most two
///   adjacent traps, a rhombus whose diameter is its long diagonal: ℓ_max ≤ √3·a.
/// * `w₀ ≤ w < w∞`: take the row direction within 30° of the flight. Rows overlap (h < 2), so
///   a flight can cross at most two rows of disks, and between two row crossings it can cross
///   at most two traps from slanted gap to slanted gap; it thus visits at most 3 strips × 4
///   traps, each a chord of length ≤ a: ℓ_max ≤ 12·a.
///
/// Returns `None` at and above w∞, where a collision-free corridor exists.
pub fn max_free_path_bound<T: Real>(g: &Geometry<T>) -> Option<T> {
    let ctx = g.ctx();
    if g.gap() >= Geometry::<T>::w_inf(ctx) {
        return None;
    }
    if g.gap() < Geometry::<T>::w_0(ctx) {
        Some(g.spacing() * &g.sqrt3())
    } else {
        Some(g.spacing().scale(12.0))
    }
}

/// Checks that D exists at `w`: finite, `0 < w < w∞`. The comparison with w∞ is made at
/// 256 bits, so a double just below the exact threshold is accepted and one at or above is not.
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::triangular::geometry::check_diffusive_gap;
/// assert!(check_diffusive_gap(0.1).is_ok());
/// assert!(check_diffusive_gap(0.0).is_err());
/// assert!(check_diffusive_gap(0.31).is_err());
/// assert!(check_diffusive_gap(f64::NAN).is_err());
/// ```
pub fn check_diffusive_gap(w: f64) -> Result<(), Error> {
    if !w.is_finite() {
        return Err(Error::NotFinite { what: "w" });
    }
    if w <= 0.0 {
        return Err(Error::Trapped { w });
    }
    let w_inf = Geometry::<Float>::w_inf(256);
    if Float::with_val(256, w) >= w_inf {
        return Err(Error::InfiniteHorizon {
            w,
            w_inf: w_inf.to_f64(),
        });
    }
    Ok(())
}

/// Checks that D exists at the gap exactly as typed (`text`, a decimal or a fraction) and at
/// its nearest double `w`: both must lie in 0 < w < w∞. The exact gap q is compared with
/// w∞ = 4/√3 − 2 in rational arithmetic (q < w∞ ⟺ 3(q + 2)² < 16, as q + 2 > 0), so a gap typed
/// just above w∞ whose nearest double lies below it (0.30940107675850306) is refused: the run
/// would be on another table than the one asked for, and at MPFR precisions beyond the horizon.
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::triangular::geometry::check_diffusive_gap_exact;
/// assert!(check_diffusive_gap_exact(0.1, Some("1/10")).is_ok());
/// // The nearest double lies below w_inf, the gap as typed above it.
/// assert!(check_diffusive_gap_exact(0.30940107675850306, None).is_ok());
/// assert!(check_diffusive_gap_exact(0.30940107675850306, Some("0.30940107675850306")).is_err());
/// assert!(check_diffusive_gap_exact(0.309401076758503, Some("0.309401076758503")).is_ok());
/// ```
pub fn check_diffusive_gap_exact(w: f64, text: Option<&str>) -> Result<(), Error> {
    check_diffusive_gap(w)?;
    let Some(text) = text else { return Ok(()) };
    crate::numbers::exact::check_exact(("w", "w_exact"), w, Some(text))?;
    let q = crate::numbers::exact::parse_exact(text)?;
    if q <= 0 {
        return Err(Error::Trapped { w });
    }
    let s = rug::Rational::from(&q + 2u32);
    if rug::Rational::from(&s * &s) * 3u32 >= 16u32 {
        // w∞ to 22 decimals, truncated (w∞ is irrational, so "..." is honest).
        let w_inf = Geometry::<Float>::w_inf(256);
        let digits = (w_inf.clone() * rug::Integer::from(rug::Integer::u_pow_u(10, 22)))
            .to_integer()
            .map(|i| format!("0.{:0>22}", i.to_string()))
            .unwrap_or_default();
        return Err(Error::parameter(
            "w",
            text,
            format!(
                "exactly as typed, not < w_inf = 4/sqrt(3) - 2 = {digits}...: the horizon is \
                 infinite there and the diffusion coefficient does not exist, although the \
                 nearest double {w:?} lies below w_inf (valid range: 0 < w < {:.6}, decided \
                 exactly)",
                w_inf.to_f64()
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn thresholds_known_values() {
        // w∞ = 4/√3 − 2 = 0.30940107675850305…, w₀ = 2/√3 − 1 = 0.15470053837925152…
        // Three correctly rounded operations: relative error ≤ 3u ≈ 3.3e-16.
        assert_relative_eq!(
            Geometry::<f64>::w_inf(()),
            0.309_401_076_758_503_05,
            max_relative = 4e-16
        );
        assert_relative_eq!(
            Geometry::<f64>::w_0(()),
            0.154_700_538_379_251_52,
            max_relative = 4e-16
        );
        let exact = Float::with_val(512, 3).sqrt() * 2u32 + 3u32;
        let exact = Float::with_val(512, 2u32) / exact;
        assert_eq!(Geometry::<Float>::w_inf(512), exact);
        // w₀ is exactly half of w∞.
        let wi = Geometry::<Float>::w_inf(256);
        let w0 = Geometry::<Float>::w_0(256);
        assert_eq!(wi, w0 * 2u32);
    }

    #[test]
    fn paper_typo_4_sqrt3_minus_2_is_not_the_threshold() {
        // The paper prints w∞ = 4√3 − 2 = 0.3094; 4√3 − 2 = 4.93, the number it quotes is 4/√3 − 2.
        let typo = 4.0 * 3f64.sqrt() - 2.0;
        assert!((typo - 0.3094).abs() > 4.0);
        assert!((Geometry::<f64>::w_inf(()) - 0.3094).abs() < 1e-4);
    }

    #[test]
    fn d_mz_equals_l2_over_4tau() {
        for &w in &[0.01, 0.1, 0.3] {
            let g = Geometry::new(w).unwrap();
            let l = g.trap_distance();
            assert_relative_eq!(g.d_mz(), l * l / (4.0 * g.hop_time()), max_relative = 1e-14);
        }
    }

    #[test]
    fn d_mz_known_value() {
        // w = 0.1: a² = 4.41, D_MZ = 0.441 / (π (√3·4.41 − 2π)).
        let g = Geometry::new(0.1f64).unwrap();
        let expect =
            0.441 / (std::f64::consts::PI * (3f64.sqrt() * 4.41 - 2.0 * std::f64::consts::PI));
        assert_relative_eq!(g.d_mz(), expect, max_relative = 1e-14);
    }

    #[test]
    fn boltzmann_is_three_sixteenths_free_area() {
        let g = Geometry::new(0.2f64).unwrap();
        assert_relative_eq!(
            g.d_bo(),
            3.0 / 16.0 * g.free_area_per_disk(),
            max_relative = 1e-14
        );
    }

    #[test]
    fn trap_area_vanishes_continuously_at_close_packing() {
        // A(w=0) = √3 − π/2 > 0: the trapped region; τ → ∞ as w → 0.
        let g = Geometry::new(1e-12f64).unwrap();
        assert_relative_eq!(
            g.trap_area(),
            3f64.sqrt() - std::f64::consts::FRAC_PI_2,
            max_relative = 1e-10
        );
    }

    #[test]
    fn bad_gaps_are_rejected_with_the_range() {
        let e = check_diffusive_gap(0.4).unwrap_err().to_string();
        assert!(e.contains("0.3094"), "{e}");
        let e = check_diffusive_gap(-1.0).unwrap_err().to_string();
        assert!(e.contains("trapped"), "{e}");
        assert!(Geometry::new(f64::INFINITY).is_err());
        assert!(Geometry::new(Float::with_val(53, 0.1)).is_ok());
        assert!(Geometry::new(Float::with_val(40, 0.1)).is_err());
        // The double nearest w∞ is below it (w∞ is irrational); check at high precision.
        let wi = Geometry::<Float>::w_inf(256).to_f64();
        let below = Float::with_val(256, wi) < Geometry::<Float>::w_inf(256);
        assert_eq!(check_diffusive_gap(wi).is_ok(), below);
    }
}
