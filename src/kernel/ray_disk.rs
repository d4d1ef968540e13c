//! First contact of a ray with a unit disk, by the cancellation-free root.
//!
//! The particle at `p` with velocity `v` (|v| ≈ 1, not assumed exactly) meets the circle
//! |x − c| = 1 when |v|² t² + 2βt + γ = 0 with d = p − c, β = d·v, γ = |d|² − 1.
//! The Lagrange identity (d·v)² + (d×v)² = |d|²|v|² turns the discriminant into
//!
//! Δ = β² − |v|²γ = |v|² − q²,  q = d × v (the signed impact parameter times |v|),
//!
//! so a miss is exactly |q| > |v| and Δ never suffers the cancellation of β² − |v|²γ when the
//! start is near the surface (γ → 0). The entry root is, by Vieta,
//!
//! t = γ / (−β + √Δ)   (β < 0),
//!
//! a quotient of two terms with no subtraction of nearly equal numbers: −β > 0 and √Δ ≥ 0.
//! The textbook (−β − √Δ)/|v|² cancels catastrophically for γ → 0 and is *not* used
//! (parry's `ray_ball` uses it). Error model: `proofs-notes/ray-disk.md`.

use super::vec2::Vec2;
use crate::numbers::real::Real;

/// Time until the ray `p + t v` enters the unit disk centred at `c`, or `None` if it moves
/// away (β ≥ 0) or misses (Δ ≤ 0). A start numerically inside the disk (γ ≤ 0) moving inward
/// gives `Some(0)`: the collision happens where the particle is (the particle is never moved).
///
/// # Examples
///
/// ```
/// use lorentz_gas::kernel::{ray_disk::ray_disk, vec2::Vec2};
/// let p = Vec2::new(-3.0f64, 0.5);
/// let v = Vec2::new(1.0, 0.0);
/// let c = Vec2::new(0.0, 0.0);
/// // Enters where x = −√(1 − 0.25).
/// let t = ray_disk(&p, &v, &c).unwrap();
/// assert!((t - (3.0 - 0.75f64.sqrt())).abs() < 1e-15);
/// assert!(ray_disk(&p, &Vec2::new(-1.0, 0.0), &c).is_none());
/// ```
pub fn ray_disk<T: Real>(p: &Vec2<T>, v: &Vec2<T>, c: &Vec2<T>) -> Option<T> {
    ray_disk_with_speed(p, v, &v.norm2(), c)
}

/// As [`ray_disk`], with `vv = |v|²` supplied (computed once per event for the three disks).
#[inline(always)]
pub fn ray_disk_with_speed<T: Real>(p: &Vec2<T>, v: &Vec2<T>, vv: &T, c: &Vec2<T>) -> Option<T> {
    let d = p.sub(c);
    ray_disk_centred(d.x, d.y, v, vv)
}

/// As [`ray_disk_with_speed`], with the offset d = p − c from the centre already formed.
#[inline(always)]
pub fn ray_disk_centred<T: Real>(dx: T, dy: T, v: &Vec2<T>, vv: &T) -> Option<T> {
    root(dx, dy, v, vv.clone(), None)
}

/// First contact with the circle |x − c| = r of a general radius, for the generic cell kernel:
/// the same cancellation-free root with Δ = |v|²r² − q² and γ = |d|² − r², `r2 = r²` given at the
/// working precision. For r² = 1 every operation rounds exactly as in [`ray_disk_centred`]
/// (multiplying by 1 and subtracting 1 are the same correctly rounded operations), which is what
/// makes the generic kernel and the triangular trap's fused path agree bit for bit.
///
/// # Examples
///
/// ```
/// use lorentz_gas::kernel::{ray_disk::ray_circle_centred, vec2::Vec2};
/// // d = p − c = (−1, 0.1), moving east towards a circle of radius 1/2.
/// let v = Vec2::new(1.0f64, 0.0);
/// let t = ray_circle_centred(-1.0, 0.1, &v, &1.0, &0.25).unwrap();
/// assert!((t - (1.0 - (0.25f64 - 0.01).sqrt())).abs() < 1e-15);
/// ```
#[inline(always)]
pub fn ray_circle_centred<T: Real>(dx: T, dy: T, v: &Vec2<T>, vv: &T, r2: &T) -> Option<T> {
    root(dx, dy, v, vv.clone() * r2, Some(r2))
}

/// The root itself, with `vvr2 = |v|²r²` formed by the caller and `r2 = None` meaning r = 1.
#[inline(always)]
fn root<T: Real>(dx: T, dy: T, v: &Vec2<T>, vvr2: T, r2: Option<&T>) -> Option<T> {
    approach(dx, dy, v, vvr2).map(|a| a.entry(r2))
}

/// A ray that meets a circle, before its entry time is computed: the offset d = p − c, β = d·v
/// (< 0: moving towards the centre; −β/|v|² is the time of closest approach, the chord's
/// midpoint) and Δ = |v|²r² − (d×v)² (> 0: the line cuts the circle).
///
/// Splitting the root here lets the kernel choose the earliest of several disks by β before it
/// takes a square root or divides (`proofs-notes/choose-before-dividing.md`); [`Approach::entry`]
/// then finishes the root by exactly the operations of [`ray_circle_centred`].
#[derive(Debug, Clone, PartialEq)]
pub struct Approach<T> {
    /// d_x = p_x − c_x.
    pub dx: T,
    /// d_y = p_y − c_y.
    pub dy: T,
    /// β = d·v, negative.
    pub beta: T,
    /// Δ = |v|²r² − (d×v)², positive.
    pub disc: T,
}

/// The first half of the cancellation-free root: `Some` exactly where the root is (β < 0 and
/// Δ > 0), with `vvr2 = |v|²r²` formed by the caller. Written with in-place operations so that
/// rug::Float allocates as little as possible; the order of the correctly rounded operations is
/// exactly that of d·v, d×v, |v|²r² − q².
///
/// # Examples
///
/// ```
/// use lorentz_gas::kernel::{ray_disk::{approach, ray_disk_centred}, vec2::Vec2};
/// let v = Vec2::new(1.0f64, 0.0);
/// let a = approach(-3.0, 0.5, &v, 1.0).unwrap();
/// assert_eq!(a.beta, -3.0);
/// assert_eq!(Some(a.entry(None)), ray_disk_centred(-3.0, 0.5, &v, &1.0));
/// assert!(approach(-3.0, 1.5, &v, 1.0).is_none()); // misses
/// ```
#[inline(always)]
pub fn approach<T: Real>(dx: T, dy: T, v: &Vec2<T>, vvr2: T) -> Option<Approach<T>> {
    let mut beta = dx.clone() * &v.x;
    let mut tmp = dy.clone() * &v.y;
    beta += &tmp;
    if !beta.lt0() {
        return None;
    }
    let mut q = dx.clone() * &v.y;
    tmp.set_mul(&dy, &v.x);
    q -= &tmp;
    q.square_mut();
    let mut disc = vvr2;
    disc -= &q;
    if !disc.gt0() {
        return None;
    }
    Some(Approach { dx, dy, beta, disc })
}

impl<T: Real> Approach<T> {
    /// The entry time γ/(√Δ − β), γ = |d|² − r² (`r2 = None`: r = 1, γ = |d|² − 1 by adding
    /// −1), or 0 where γ ≤ 0 (a start numerically inside, moving in).
    #[inline(always)]
    pub fn entry(self, r2: Option<&T>) -> T {
        let Approach {
            mut dx,
            mut dy,
            beta,
            disc,
        } = self;
        dx.square_mut();
        dy.square_mut();
        dx += &dy;
        let gamma = match r2 {
            Some(r2) => dx - r2,
            None => dx.add_f64(-1.0),
        };
        if !gamma.gt0() {
            return T::zero(gamma.ctx());
        }
        let mut denom = disc.sqrt();
        denom -= &beta;
        gamma / &denom
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rug::Float;

    /// The textbook root −β − √Δ loses all digits for a start 1e-12 above the surface;
    /// the Vieta form keeps them. Reference: the same formula at 512 bits.
    #[test]
    fn near_surface_start_keeps_relative_accuracy() {
        let eps = 1e-12;
        let alpha: f64 = 0.3;
        let p = Vec2::new(-(1.0 + eps), 0.0f64);
        let v = Vec2::new(alpha.cos(), alpha.sin());
        let c = Vec2::new(0.0, 0.0);
        let t = ray_disk(&p, &v, &c).unwrap();
        let pr = Vec2::<Float>::from_f64(512, p.x, p.y);
        let vr = Vec2::<Float>::from_f64(512, v.x, v.y);
        let cr = Vec2::<Float>::from_f64(512, 0.0, 0.0);
        let tr = ray_disk(&pr, &vr, &cr).unwrap().to_f64();
        // t ≈ ε/cos α. The Vieta form's error is e_γ/D: here γ = p_x² − 1 loses only the δ² ≈ 1e-24
        // term of (1 + δ)², a relative 5e-13; the naive −β − √Δ loses u|β| ≈ 1e-16 absolute, a
        // relative 1e-4. (In general γ = |d|² − 1 is rounded to absolute u, which bounds both
        // forms at absolute O(u): proofs-notes/ray-disk.md.)
        assert!(((t - tr) / tr).abs() < 1e-11, "t={t:e} tr={tr:e}");
        let beta = p.x * v.x + p.y * v.y;
        let q = p.x * v.y - p.y * v.x;
        let naive = -beta - (v.x * v.x + v.y * v.y - q * q).sqrt();
        assert!(
            ((naive - tr) / tr).abs() > 1e-6,
            "the naive root should have cancelled: {naive:e} vs {tr:e}"
        );
    }

    #[test]
    fn grazing_miss_and_hit() {
        let c = Vec2::new(0.0f64, 0.0);
        let v = Vec2::new(1.0, 0.0);
        assert!(ray_disk(&Vec2::new(-2.0, 1.0 + 1e-15), &v, &c).is_none());
        assert!(ray_disk(&Vec2::new(-2.0, 1.0 - 1e-15), &v, &c).is_some());
        // Exactly tangent (Δ = 0) is a miss: the measure-zero tangency is not a collision.
        assert!(ray_disk(&Vec2::new(-2.0, 1.0), &v, &c).is_none());
    }
}
