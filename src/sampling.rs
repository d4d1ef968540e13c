//! Initial conditions from the invariant (Liouville) measure, and reproducible random streams.
//!
//! The invariant measure of the billiard flow is uniform in position over the free region and
//! uniform in direction. Every trap is congruent to the canonical one and the lattice is
//! homogeneous, so a start uniform in the canonical free trap with a uniform direction is a
//! sample of the equilibrium measure of the whole lattice; no burn-in is needed.
//!
//! Streams: batch `b` of a run with seed `s` uses xoshiro256++ seeded from `s` and advanced by
//! `b` jumps of 2¹²⁸ steps, so streams never overlap and a batch's bits depend only on
//! `(s, b)`, never on the number of threads.

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::kernel::trap::{Flight, Trap};
use crate::kernel::vec2::Vec2;
use crate::scenes::lattice::{Cell, LatticeState};

/// The random stream of batch `index` of a run with seed `seed`.
///
/// # Examples
///
/// ```
/// use lorentz_gas::sampling::stream;
/// use rand::Rng;
/// let a: u64 = stream(7, 3).random();
/// let b: u64 = stream(7, 3).random();
/// assert_eq!(a, b);
/// assert_ne!(a, stream(7, 4).random::<u64>());
/// ```
pub fn stream(seed: u64, index: u64) -> Xoshiro256PlusPlus {
    let mut r = Xoshiro256PlusPlus::seed_from_u64(seed);
    for _ in 0..index {
        r.jump();
    }
    r
}

/// A uniformly distributed unit vector (rejection from the annulus 1/16 ≤ r² ≤ 1, then
/// normalised with correctly rounded operations; no trigonometry).
pub fn direction<R: Rng + ?Sized>(rng: &mut R) -> Vec2<f64> {
    loop {
        let x = 2.0 * rng.random::<f64>() - 1.0;
        let y = 2.0 * rng.random::<f64>() - 1.0;
        let r2 = x * x + y * y;
        if (0.0625..=1.0).contains(&r2) {
            let r = r2.sqrt();
            return Vec2::new(x / r, y / r);
        }
    }
}

/// A point uniform in the free part of the canonical trap.
pub fn position_in_trap<R: Rng + ?Sized>(trap: &Trap<f64>, rng: &mut R) -> Vec2<f64> {
    loop {
        let (mut u1, mut u2) = (rng.random::<f64>(), rng.random::<f64>());
        if u1 + u2 > 1.0 {
            u1 = 1.0 - u1;
            u2 = 1.0 - u2;
        }
        let p = Vec2::new(u1 * trap.a + u2 * trap.a * 0.5, u2 * trap.h);
        if trap.is_free(&p) {
            return p;
        }
    }
}

/// A lattice state drawn from the invariant measure (trap (0, 0), up).
pub fn equilibrium_state<R: Rng + ?Sized>(trap: &Trap<f64>, rng: &mut R) -> LatticeState<f64> {
    let pos = position_in_trap(trap, rng);
    let vel = direction(rng);
    LatticeState {
        cell: Cell::default(),
        flight: Flight::new(pos, vel),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_are_unit_and_isotropic() {
        let mut r = stream(1, 0);
        let n = 200_000;
        let (mut sx, mut sy, mut sxx) = (0.0, 0.0, 0.0);
        for _ in 0..n {
            let d = direction(&mut r);
            assert!((d.x * d.x + d.y * d.y - 1.0).abs() < 4.0 * f64::EPSILON);
            sx += d.x;
            sy += d.y;
            sxx += d.x * d.x;
        }
        let nf = n as f64;
        // ⟨x⟩ = ⟨y⟩ = 0 with σ = √(1/2n); ⟨x²⟩ = 1/2 with σ = √(1/8n). Within 5σ.
        assert!((sx / nf).abs() < 5.0 * (0.5 / nf).sqrt());
        assert!((sy / nf).abs() < 5.0 * (0.5 / nf).sqrt());
        assert!((sxx / nf - 0.5).abs() < 5.0 * (0.125 / nf).sqrt());
    }

    #[test]
    fn positions_fill_the_free_trap_uniformly() {
        // The fraction of samples in the left half (x < a/2) is 1/2 by symmetry.
        let trap = Trap::new(0.1).unwrap();
        let mut r = stream(2, 0);
        let n = 100_000;
        let left = (0..n)
            .filter(|_| position_in_trap(&trap, &mut r).x < trap.a / 2.0)
            .count();
        let f = left as f64 / n as f64;
        assert!((f - 0.5).abs() < 5.0 * (0.25 / n as f64).sqrt(), "{f}");
    }
}
