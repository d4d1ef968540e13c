//! The sufficient statistics of the time-weighted survival, summed per batch, and the escape
//! rate, Lyapunov exponent and mean flight time they give.
//!
//! Z_n(s) = Σ_{alive at collision n} e^{sτ_n} behaves as c(s) ν(s)ⁿ once n is past the
//! transient, and ν(γ) = 1 at the escape rate γ (the weights e^{γτ} undo the decay of the
//! surviving fraction exactly). So γ̂ solves Z_{n+1}(s) = Z_n(s) at the window's collision n,
//! and with E_n\[f\] = Σ e^{γ̂τ_n} f / Z_n(γ̂) the increments E_{n+1} − E_n of τ and of ln Λ are
//! the natural measure's mean flight time ⟨T⟩ and mean expansion per flight ⟨ln Λ⟩:
//! λ = ⟨ln Λ⟩/⟨T⟩ (`docs/guide/cycles.md`, "Survival").
//!
//! The weights are kept as Taylor moments about the pilot's rate s₀: Σ e^{s₀τ} τᵐ and
//! Σ e^{s₀τ} τᵐ ln Λ for m ≤ [`ORDER`], so that any s near s₀ is evaluated after the run from
//! sums whose bits do not depend on the thread count.

use crate::Error;

/// The Taylor order of the moments: the remainder of e^x beyond xᴹ/M! with |x| ≤
/// [`MAX_SHIFT`] is below 10⁻¹⁴ of the sum.
pub const ORDER: usize = 28;

/// The largest |s − s₀|·τ_max at which the moments are evaluated.
pub const MAX_SHIFT: f64 = 3.0;

/// The moments of the collisions at one collision number.
#[derive(Debug, Clone, PartialEq)]
pub struct Moments {
    /// Σ e^{s₀τ} τᵐ, m = 0 … ORDER + 1.
    pub time: [f64; ORDER + 2],
    /// Σ e^{s₀τ} τᵐ ln Λ, m = 0 … ORDER.
    pub ln: [f64; ORDER + 1],
}

impl Default for Moments {
    fn default() -> Self {
        Moments {
            time: [0.0; ORDER + 2],
            ln: [0.0; ORDER + 1],
        }
    }
}

impl Moments {
    /// Adds one collision at time `tau` with ln Λ = `ln`, weighted by e^{s₀τ}.
    pub fn add(&mut self, s0: f64, tau: f64, ln: f64) {
        let mut w = (s0 * tau).exp();
        for m in 0..=ORDER + 1 {
            self.time[m] += w;
            if m <= ORDER {
                self.ln[m] += w * ln;
            }
            w *= tau;
        }
    }

    /// Adds `other` term by term.
    pub fn merge(&mut self, other: &Moments) {
        for (a, b) in self.time.iter_mut().zip(&other.time) {
            *a += b;
        }
        for (a, b) in self.ln.iter_mut().zip(&other.ln) {
            *a += b;
        }
    }

    /// (Σ e^{sτ}, Σ e^{sτ} τ, Σ e^{sτ} ln Λ) at s = s₀ + `ds`.
    fn at(&self, ds: f64) -> (f64, f64, f64) {
        let (mut z, mut t, mut l, mut c) = (0.0, 0.0, 0.0, 1.0);
        for m in 0..=ORDER {
            z += c * self.time[m];
            t += c * self.time[m + 1];
            l += c * self.ln[m];
            c *= ds / (m + 1) as f64;
        }
        (z, t, l)
    }
}

/// One batch's (or all batches') tally.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Tally {
    /// Particles alive at collision k = 0 … cap (k = 0: the starts).
    pub alive: Vec<u64>,
    /// The moments at each collision k = 0 … cap (k = 0, the start, has τ = 0 and ln Λ = 0).
    pub moments: Vec<Moments>,
    /// The latest collision time.
    pub time_max: f64,
    /// Collisions over all particles.
    pub collisions: u64,
}

impl Tally {
    /// An empty tally for collisions up to `cap`.
    pub fn new(cap: usize) -> Self {
        Tally {
            alive: vec![0; cap + 1],
            moments: vec![Moments::default(); cap + 1],
            ..Tally::default()
        }
    }

    /// Adds `other` (the batches are merged in index order).
    pub fn merge(&mut self, other: &Tally) {
        for (a, b) in self.alive.iter_mut().zip(&other.alive) {
            *a += b;
        }
        for (a, b) in self.moments.iter_mut().zip(&other.moments) {
            a.merge(b);
        }
        self.time_max = self.time_max.max(other.time_max);
        self.collisions += other.collisions;
    }
}

/// What one window gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowEstimate {
    /// The escape rate γ̂.
    pub gamma: f64,
    /// The Lyapunov exponent λ = ⟨ln Λ⟩/⟨T⟩ at γ̂.
    pub lyapunov: f64,
    /// The mean flight time ⟨T⟩ at γ̂.
    pub mean_flight_time: f64,
}

/// The estimates from the window starting at collision `first` ≥ 1 (Z_{first+1} = Z_first),
/// the moments taken about `s0`.
///
/// # Errors
/// No survivors at the window's end, or no root within the moments' reach.
pub fn estimate(tally: &Tally, first: usize, s0: f64) -> Result<WindowEstimate, Error> {
    let (now, next) = (&tally.moments[first], &tally.moments[first + 1]);
    let survivors = tally.alive.get(first + 1).copied().unwrap_or(0);
    let too_few = || {
        Error::Failed(format!(
            "only {survivors} particles of a batch survived to collision {}, too few to place \
             the escape rate: use more particles (a few hundred survivors per batch) or an \
             earlier window",
            first + 1
        ))
    };
    if next.time[0] == 0.0 {
        return Err(too_few());
    }
    let reach = MAX_SHIFT / tally.time_max.max(1e-300);
    let g = |ds: f64| next.at(ds).0.ln() - now.at(ds).0.ln();
    let (mut lo, mut hi) = (-reach, reach);
    if !(g(lo) < 0.0 && g(hi) > 0.0) {
        return Err(too_few());
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if g(mid) < 0.0 { lo = mid } else { hi = mid }
    }
    let ds = 0.5 * (lo + hi);
    let ((z0, t0, l0), (z1, t1, l1)) = (now.at(ds), next.at(ds));
    let mean_flight_time = t1 / z1 - t0 / z0;
    Ok(WindowEstimate {
        gamma: s0 + ds,
        lyapunov: (l1 / z1 - l0 / z0) / mean_flight_time,
        mean_flight_time,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Collisions at times n·T exactly, a fraction q surviving each: Z_{n+1}/Z_n = q e^{sT}, so
    /// γ = −ln(q)/T; ln Λ = n·L gives λ = L/T.
    #[test]
    fn a_geometric_survival_gives_its_rate() {
        let (t, q, l) = (4.0f64, 0.25f64, 2.0f64);
        let mut tally = Tally::new(4);
        let s0 = 0.3;
        for n in [2u32, 3, 4] {
            let survivors = 4096 / 4u32.pow(n - 2);
            for _ in 0..survivors {
                tally.moments[n as usize].add(s0, f64::from(n) * t, f64::from(n) * l);
            }
            tally.time_max = f64::from(n) * t;
        }
        let e = estimate(&tally, 2, s0).unwrap();
        assert!((e.gamma - (-q.ln() / t)).abs() < 1e-12, "{e:?}");
        assert!((e.lyapunov - l / t).abs() < 1e-12, "{e:?}");
        assert!((e.mean_flight_time - t).abs() < 1e-12, "{e:?}");
        let late = estimate(&tally, 3, s0).unwrap();
        assert!((late.gamma - e.gamma).abs() < 1e-12);
    }
}
