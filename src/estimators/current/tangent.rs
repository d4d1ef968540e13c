//! The Lyapunov pair along a trajectory under the thermostat (`proofs-notes/thermostat-lyapunov.md`):
//! two tangent vectors (δx, δy, δφ) in world coordinates, carried through the flights by their
//! closed-form variation ([`Start::variation`]) and through the collisions by the reflection's
//! tangent map, reduced modulo the flow direction f = (v, φ̇) and orthonormalised at every
//! collision. The flow maps f onto itself, so the three-volume of (f, u₁, u₂) contracts exactly as
//! e^{−∫α}: the logarithmic stretchings sum to −∫α − ln(|f(T)|/|f(0)|) trajectory by trajectory,
//! which the run reports as a residual beside its rounding bound.

use super::mean_of;
use crate::estimators::diffusion::Estimate;
use crate::kernel::thermostat::{Start, Thermostat};
use crate::kernel::vec2::Vec2;
use crate::statistics::CompensatedSum;

/// Unit roundoff of `f64`.
const U: f64 = f64::EPSILON / 2.0;

/// What one trajectory's pair measured over its observed stretch.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct PairBatch {
    /// λ₊ and λ₋ per unit time.
    pub lambda: [f64; 2],
    /// ∫α dt over the same time, per unit time.
    pub alpha: f64,
    /// Σ ln stretchings + ∫α + ln(|f(T)|/|f(0)|): zero but for rounding.
    pub residual: f64,
    /// The residual's rounding bound.
    pub bound: f64,
    /// The flight time the pair measured over (to its last renormalisation).
    pub time: f64,
}

/// The Lyapunov pair over independent trajectories, each with its standard error over them.
pub(super) struct PairSummary {
    pub plus: Estimate,
    pub minus: Estimate,
    /// ⟨α⟩, the mean phase-space contraction rate.
    pub alpha: Estimate,
    /// λ₊ + λ₋ + ⟨α⟩ per trajectory.
    pub sum_rule: Estimate,
    pub kaplan_yorke: Estimate,
    /// The trajectory of the largest residual relative to its bound: (residual, bound).
    pub residual: (f64, f64),
}

/// The pair summarised over the trajectories `pairs`.
pub(super) fn pair_summary(pairs: &[PairBatch]) -> PairSummary {
    let per = |f: &dyn Fn(&PairBatch) -> f64| mean_of(&pairs.iter().map(f).collect::<Vec<_>>());
    let worst = pairs
        .iter()
        .map(|p| (p.residual.abs(), p.bound))
        .max_by(|a, b| (a.0 / a.1).total_cmp(&(b.0 / b.1)))
        .unwrap_or((0.0, 0.0));
    PairSummary {
        plus: per(&|p| p.lambda[0]),
        minus: per(&|p| p.lambda[1]),
        alpha: per(&|p| p.alpha),
        sum_rule: per(&|p| p.lambda[0] + p.lambda[1] + p.alpha),
        kaplan_yorke: per(&|p| 2.0 + p.lambda[0] / p.lambda[1].abs()),
        residual: worst,
    }
}

/// The tangent pair of one trajectory.
pub(super) struct Pair<'a> {
    world: &'a Thermostat<f64>,
    u: [[f64; 3]; 2],
    /// Σ ln stretchings, ∫α dt and the flight time, each summed with compensation (a plain sum
    /// of 10⁵ terms into totals of 10⁵ would lose 10⁻⁸).
    logs: [CompensatedSum; 2],
    alpha: CompensatedSum,
    time: CompensatedSum,
    pending: (f64, f64, u64),
    events: u64,
    /// Σ over renormalisations of |u_i| before the projections over the norm n_i after them: the
    /// cancellation that scales the rounding of ln n_i (≈ 1, large after a nearly grazing
    /// collision has turned both vectors towards the same direction).
    cancel: f64,
    ln_f0: f64,
    ln_f: f64,
}

/// ε(v × ê) = v × E, the rate φ̇ of the velocity angle at the velocity `v`.
fn turn(world: &Thermostat<f64>, v: &Vec2<f64>) -> f64 {
    world.strength * v.cross(&world.dir)
}

fn dot(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The tangent map of the flight `start` over the time `t` applied to `u` = (δx, δy, δφ):
/// δφ ↦ δφ·∂θ/∂θ₀, δr ↦ δr + δφ·∂X/∂θ₀ ([`Start::variation`]).
pub(super) fn flight_map(u: &mut [f64; 3], start: &Start<'_, f64>, t: f64) {
    let (dx, dth) = start.variation(&t);
    u[0] += u[2] * dx.x;
    u[1] += u[2] * dx.y;
    u[2] *= dth;
}

/// The tangent map of a specular collision at a disk of radius `radius` with outward unit
/// normal `n` at the contact, leaving with `out` (world), under the field `world`: with v⁻ the
/// arrival velocity, δt = −n·δr/(n·v⁻) the perturbed orbit's delay, the contact point's shift
/// δr_c = δr + v⁻δt and the normal's turn δψ = Jn·δr_c/r,
/// δφ ↦ 2δψ − δφ − (φ̇⁻ + φ̇⁺)δt and δr ↦ δr + (v⁻ − v⁺)δt (`proofs-notes/thermostat-lyapunov.md`).
pub(super) fn collision_map(
    u: &mut [f64; 3],
    world: &Thermostat<f64>,
    (n, radius): (&Vec2<f64>, f64),
    out: &Vec2<f64>,
) {
    let k = 2.0 * n.dot(out);
    let inn = Vec2::new(out.x - k * n.x, out.y - k * n.y);
    let turns = turn(world, &inn) + turn(world, out);
    let dt = -(n.x * u[0] + n.y * u[1]) / n.dot(&inn);
    let rc = [u[0] + inn.x * dt, u[1] + inn.y * dt];
    let dpsi = (n.x * rc[1] - n.y * rc[0]) / radius;
    u[2] = 2.0 * dpsi - u[2] - turns * dt;
    u[0] += (inn.x - out.x) * dt;
    u[1] += (inn.y - out.y) * dt;
}

impl<'a> Pair<'a> {
    /// The pair at a state of world velocity `v`: an orthonormal basis of the complement of f.
    pub(super) fn new(world: &'a Thermostat<f64>, v: &Vec2<f64>) -> Self {
        let g = turn(world, v);
        let u1 = [-v.y, v.x, 0.0];
        let f = [v.x, v.y, g];
        let c = [
            f[1] * u1[2] - f[2] * u1[1],
            f[2] * u1[0] - f[0] * u1[2],
            f[0] * u1[1] - f[1] * u1[0],
        ];
        let mut pair = Pair {
            world,
            u: [u1, c],
            logs: [CompensatedSum::default(); 2],
            alpha: CompensatedSum::default(),
            time: CompensatedSum::default(),
            pending: (0.0, 0.0, 0),
            events: 0,
            cancel: 0.0,
            ln_f0: 0.0,
            ln_f: 0.0,
        };
        pair.restart_at(v);
        pair
    }

    /// Renormalises at the world velocity `v` and starts the logs afresh there (the end of the
    /// warm-up).
    pub(super) fn restart_at(&mut self, v: &Vec2<f64>) {
        self.renormalise(v);
        self.logs = [CompensatedSum::default(); 2];
        (self.alpha, self.time) = (CompensatedSum::default(), CompensatedSum::default());
        self.events = 0;
        self.cancel = 0.0;
        self.ln_f0 = self.ln_f;
    }

    /// The flight `start` of time `t`, with its displacement `along` the field.
    pub(super) fn flight(&mut self, start: &Start<'_, f64>, t: f64, along: f64) {
        for u in &mut self.u {
            flight_map(u, start, t);
        }
        self.pending.0 += t;
        self.pending.1 += self.world.strength * along;
        self.pending.2 += 1;
    }

    /// The collision at a disk of radius `radius` whose outward unit normal at the contact is `n`
    /// (world), leaving with the world velocity `out`; then the renormalisation.
    pub(super) fn collision(&mut self, n: &Vec2<f64>, radius: f64, out: &Vec2<f64>) {
        for u in &mut self.u {
            collision_map(u, self.world, (n, radius), out);
        }
        self.renormalise(out);
    }

    /// Removes the flow direction at the world velocity `v`, orthonormalises, and takes the
    /// stretchings and the flights since the last renormalisation into the logs.
    fn renormalise(&mut self, v: &Vec2<f64>) {
        let f = [v.x, v.y, turn(self.world, v)];
        let ff = dot(&f, &f);
        let before = self.u.map(|u| dot(&u, &u).sqrt());
        for u in &mut self.u {
            let c = dot(u, &f) / ff;
            for (a, b) in u.iter_mut().zip(&f) {
                *a -= c * b;
            }
        }
        let n1 = dot(&self.u[0], &self.u[0]).sqrt();
        self.u[0] = self.u[0].map(|a| a / n1);
        let c = dot(&self.u[1], &self.u[0]);
        let u0 = self.u[0];
        for (a, b) in self.u[1].iter_mut().zip(&u0) {
            *a -= c * b;
        }
        let n2 = dot(&self.u[1], &self.u[1]).sqrt();
        self.u[1] = self.u[1].map(|a| a / n2);
        self.logs[0].add(n1.ln());
        self.logs[1].add(n2.ln());
        self.cancel += before[0] / n1 + before[1] / n2;
        self.ln_f = 0.5 * ff.ln();
        self.time.add(self.pending.0);
        self.alpha.add(self.pending.1);
        self.events += self.pending.2 + 1;
        self.pending = (0.0, 0.0, 0);
    }

    /// What the pair measured since [`Self::restart`], up to its last renormalisation.
    pub(super) fn finish(&self) -> PairBatch {
        let t = self.time.value().max(f64::MIN_POSITIVE);
        let (plus, minus, alpha) = (
            self.logs[0].value(),
            self.logs[1].value(),
            self.alpha.value(),
        );
        let mut residual = CompensatedSum::default();
        for x in [plus, minus, alpha, self.ln_f, -self.ln_f0] {
            residual.add(x);
        }
        PairBatch {
            lambda: [plus / t, minus / t],
            alpha: alpha / t,
            residual: residual.value(),
            time: self.time.value(),
            bound: 64.0 * U * self.events as f64
                + 16.0 * U * self.cancel
                + 4.0 * U * (plus.abs() + minus.abs() + alpha.abs())
                + 128.0 * U * self.world.strength * t,
        }
    }
}

#[cfg(test)]
#[path = "tangent_tests.rs"]
mod tests;
