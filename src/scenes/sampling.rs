//! Reproducible random streams, and the scene-independent part of the invariant measure (a
//! uniform direction). Positions are drawn by each scene's sampler ([`crate::scenes::Scene::sample`]).
//!
//! Streams: every random stream is named by a [`StreamKey`] — the user's seed, what the stream is
//! for ([`Purpose`]), a run number and an index (the batch, trajectory or grid point) — and its
//! xoshiro256++ state is an injective function of that key (`proofs-notes/streams.md`): two
//! different keys never share a state, no key is computed by arithmetic that can overflow, and a
//! batch's bits depend only on its key, never on the number of threads.

use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::kernel::vec2::Vec2;

/// What a random stream is used for. The purpose is part of the stream's key, so that, say, the
/// events an audit samples are never drawn from the stream that started the trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Purpose {
    /// Initial conditions of trajectories (diffusion batches, hops, Lyapunov orbits, benchmarks).
    Trajectory,
    /// Which events a shadow audit replays.
    Audit,
    /// Injections into a single trap from the invariant flux.
    Injection,
    /// Steps of a simulated correlated lattice walk.
    LatticeWalk,
    /// Perturbations and starts used by verification (divergence, certification, reports).
    Verification,
    /// Initial conditions in the open strip of the escape-rate estimator.
    Escape,
    /// Phase points classified as pinned, skipping or diffusing in a magnetic field.
    Classification,
    /// Starts of the orbits of a Poincaré section (`estimators::section`).
    Section,
    /// Starts on an open table for the survival estimator of its escape rate.
    Survival,
}

impl Purpose {
    /// The purpose's word in the key: fixed forever, so results stay reproducible.
    const fn word(self) -> u64 {
        match self {
            Purpose::Trajectory => 1,
            Purpose::Audit => 2,
            Purpose::Injection => 3,
            Purpose::LatticeWalk => 4,
            Purpose::Verification => 5,
            Purpose::Escape => 6,
            Purpose::Classification => 7,
            Purpose::Section => 8,
            Purpose::Survival => 9,
        }
    }
}

/// The name of one random stream: `(seed, purpose, run, index)`.
///
/// `run` numbers the independent runs that share a seed (run `r` of sweep point `i` is
/// `i·runs + r`, computed in `u64` from two `u32`s, which cannot overflow); `index` numbers the
/// batches, trajectories or grid points inside a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct StreamKey {
    /// The user's seed.
    pub seed: u64,
    /// What the stream is for.
    pub purpose: Purpose,
    /// Which run of that seed.
    pub run: u64,
    /// Which batch, trajectory or point of that run.
    pub index: u64,
}

impl StreamKey {
    /// The key of batch `index` of run 0 for `purpose`.
    pub const fn new(seed: u64, purpose: Purpose, index: u64) -> Self {
        StreamKey {
            seed,
            purpose,
            run: 0,
            index,
        }
    }

    /// The same key in run `run`.
    pub const fn in_run(self, run: u64) -> Self {
        StreamKey { run, ..self }
    }

    /// The generator of this key.
    ///
    /// Each of the four key words goes through its own bijection of `u64` (xor with a distinct
    /// non-zero constant, then SplitMix64's finaliser, which is invertible), giving the four words
    /// of the xoshiro256++ state: different keys give different states, and the state is never
    /// all zero (that would need `purpose` word = its constant). One jump (2¹²⁸ steps, a bijective
    /// linear map of the state) then spreads a difference in one word over all 256 bits, so the
    /// first outputs of streams whose keys differ in one word are unrelated.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::scenes::sampling::{Purpose, StreamKey};
    /// use rand::Rng;
    /// let k = StreamKey::new(7, Purpose::Trajectory, 3);
    /// let a: u64 = k.rng().random();
    /// assert_eq!(a, k.rng().random::<u64>());
    /// assert_ne!(a, StreamKey::new(7, Purpose::Audit, 3).rng().random::<u64>());
    /// assert_ne!(a, k.in_run(1).rng().random::<u64>());
    /// ```
    pub fn rng(&self) -> Xoshiro256PlusPlus {
        // Distinct odd constants (digits of pi, e, sqrt 2, sqrt 3 in hex) keep the four bijections
        // distinct; any distinct constants larger than every purpose word would do.
        const K: [u64; 4] = [
            0x243F_6A88_85A3_08D3,
            0xB7E1_5162_8AED_2A6B,
            0x6A09_E667_F3BC_C909,
            0xBB67_AE85_84CA_A73B,
        ];
        let words = [self.seed, self.purpose.word(), self.run, self.index];
        let mut bytes = [0u8; 32];
        for (i, (w, k)) in words.iter().zip(K).enumerate() {
            bytes[8 * i..8 * i + 8].copy_from_slice(&splitmix_finalise(w ^ k).to_le_bytes());
        }
        let mut r = Xoshiro256PlusPlus::from_seed(bytes);
        r.jump();
        r
    }
}

/// SplitMix64's output function: a bijection of `u64` (xor-shifts and multiplications by odd
/// constants modulo 2⁶⁴ are each invertible). The multiplications are meant to wrap.
const fn splitmix_finalise(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The trajectory stream of batch `index` of run 0 with seed `seed`:
/// `StreamKey::new(seed, Purpose::Trajectory, index).rng()`.
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::sampling::stream;
/// use rand::Rng;
/// let a: u64 = stream(7, 3).random();
/// let b: u64 = stream(7, 3).random();
/// assert_eq!(a, b);
/// assert_ne!(a, stream(7, 4).random::<u64>());
/// ```
pub fn stream(seed: u64, index: u64) -> Xoshiro256PlusPlus {
    StreamKey::new(seed, Purpose::Trajectory, index).rng()
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
    fn stream_states_are_distinct_for_neighbouring_keys() {
        // Injectivity is by construction; check that keys differing in one word in the ways the
        // old arithmetic schemes collided (seed + 1000 i + r, seed ^ salt) give different streams.
        let mut seen = std::collections::HashSet::new();
        for seed in 0..4u64 {
            for p in [Purpose::Trajectory, Purpose::Audit, Purpose::Injection] {
                for run in 0..4u64 {
                    for index in [0u64, 1, 999, 1000, u64::MAX] {
                        let x: [u64; 2] = {
                            let mut r = StreamKey {
                                seed,
                                purpose: p,
                                run,
                                index,
                            }
                            .rng();
                            [r.random(), r.random()]
                        };
                        assert!(seen.insert(x), "{seed} {p:?} {run} {index}");
                    }
                }
            }
        }
    }

    #[test]
    fn splitmix_finaliser_is_invertible_on_samples() {
        // Distinct inputs, distinct outputs (the map is a bijection; sampled here).
        let outs: std::collections::HashSet<u64> = (0..100_000u64)
            .map(|x| splitmix_finalise(x.wrapping_mul(0x9E37_79B9_7F4A_7C15)))
            .collect();
        assert_eq!(outs.len(), 100_000);
    }

    #[test]
    fn positions_fill_the_free_trap_uniformly() {
        use crate::kernel::trap::Trap;
        use crate::scenes::triangular::position_in_trap;
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
