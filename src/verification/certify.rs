//! Finite-segment certification by precision doubling.
//!
//! A segment of N collisions from an exactly given initial condition is certified to d digits when
//! its runs at precision P and 2P agree to d digits in every contact point and velocity. Chaos
//! amplifies rounding by ~e^{λk} after k collisions, so P is chosen as
//! P = ⌈(λN + d·ln 10)/ln 2⌉ + 64 bits from the tangent-space λ, and doubled until the two runs
//! agree (`proofs-notes/certification.md`). The certified segment also shows how far the f64 orbit
//! from the same start follows the true one.

use rug::Float;
use serde::Serialize;

use super::lyapunov::{collision_track, lyapunov};
use crate::error::Error;
use crate::kernel::trap::Flight;
use crate::scenes::lattice::{LatticeState, PeriodicLattice};

/// A certified segment.
#[derive(Debug, Clone, Serialize)]
pub struct Certificate {
    /// Gap w.
    pub w: f64,
    /// Collisions certified.
    pub collisions: usize,
    /// Digits requested.
    pub digits_requested: u32,
    /// Digits to which the P and 2P runs agree over the whole segment (−log₁₀ of the largest
    /// deviation).
    pub digits_agreed: f64,
    /// The precision P (bits) of the certifying pair (P, 2P).
    pub bits: u32,
    /// Precisions tried, in order.
    pub tried: Vec<u32>,
    /// Collisions for which the f64 orbit from the same start stays within 10⁻³ of the certified one.
    pub f64_faithful_collisions: usize,
}

fn max_dev(a: &[([Float; 4], f64)], b: &[([Float; 4], f64)]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            (0..4)
                .map(|i| (x.0[i].clone() - &y.0[i]).abs().to_f64())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

/// Certifies `n` collisions of the orbit from `start` (taken exactly) to `digits` digits.
pub fn certify(
    w: f64,
    start: &LatticeState<f64>,
    n: usize,
    digits: u32,
) -> Result<Certificate, Error> {
    if n == 0 {
        return Err(Error::Zero { what: "collisions" });
    }
    let lambda = lyapunov(w, 100_000, 4, 17, 1)?.per_collision;
    let need =
        (lambda * n as f64 + digits as f64 * std::f64::consts::LN_10) / std::f64::consts::LN_2;
    let mut bits = (need.ceil() as u32 + 64).max(128);
    let mut tried = Vec::new();
    let run = |b: u32, out: u32| -> Result<Vec<([Float; 4], f64)>, Error> {
        let lat = PeriodicLattice::new(Float::with_val(b, w))?;
        collision_track(
            &lat,
            &LatticeState::<Float>::convert_from_f64(b, start),
            n,
            out,
        )
    };
    loop {
        tried.push(bits);
        let out = 2 * bits;
        let (lo, hi) = (run(bits, out)?, run(2 * bits, out)?);
        let dev = max_dev(&lo, &hi);
        let agreed = if dev > 0.0 {
            -dev.log10()
        } else {
            f64::INFINITY
        };
        if agreed >= digits as f64 {
            let f = collision_track(&PeriodicLattice::new(w)?, start, n, out)?;
            let faithful = f
                .iter()
                .zip(&hi)
                .position(|(x, y)| (0..4).any(|i| (x.0[i].clone() - &y.0[i]).abs().to_f64() > 1e-3))
                .unwrap_or(n);
            return Ok(Certificate {
                w,
                collisions: n,
                digits_requested: digits,
                digits_agreed: agreed,
                bits,
                tried,
                f64_faithful_collisions: faithful,
            });
        }
        if bits > 1 << 20 {
            return Err(Error::Invalid(format!(
                "could not certify {n} collisions to {digits} digits below 2^20 bits"
            )));
        }
        bits *= 2;
    }
}

/// A start from its f64 components, exactly (for the CLI and tests).
pub fn start_from(x: f64, y: f64, vx: f64, vy: f64) -> LatticeState<f64> {
    LatticeState {
        cell: Default::default(),
        flight: Flight::new(
            crate::kernel::vec2::Vec2::new(x, y),
            crate::kernel::vec2::Vec2::new(vx, vy),
        ),
    }
}
