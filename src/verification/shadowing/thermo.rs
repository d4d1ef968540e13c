//! The billiard map along thermostatted flights, with its analytic Jacobian, and the clearance of
//! those flights from the other disks (`proofs-notes/shadowing.md`, "Under the thermostat").
//!
//! From the contact point X₀ with the outgoing unit velocity v (angle θ₀), the flight is the
//! kernel's closed form X(t) = X₀ + Δ(t) ([`Start::at`], `proofs-notes/thermostat-flight.md`),
//! at the working precision. The arrival on the recorded disk c′ is the first root of
//! F(t) = |X₀ − c′ + Δ(t)|² − r²: a march of steps each certified free of contact by the speed
//! (the distance to the disk) or by a quadratic lower bound on F from |v̇| ≤ ε ([`safe_step`]),
//! which near a transversal root are Newton's steps to second order, so the march ends there
//! quadratically. A root where the flight leaves the disk (n′·v⁻ ≥ 0) is a miss.
//!
//! The Jacobian follows the collision map of `proofs-notes/thermostat-lyapunov.md`: the
//! departure's tangent (δX₀, δv) with δθ₀ = v × δv; the flight at a fixed time
//! δX = δX₀ + (∂X/∂θ₀)δθ₀, δv = (∂θ/∂θ₀)δθ₀ Jv⁻ ([`Start::variation`]); the arrival time
//! δτ = −(n′·δX)/(n′·v⁻), δX′ = δX + v⁻δτ, δv⁻ ← δv + v̇δτ; then the arrival's (δs′, δp′).

use super::*;
use crate::kernel::thermostat::{Start, Thermostat};

/// Most points of the march to the recorded disk (and of a clearance march) before the flight
/// is declared a miss (or unresolved): a march stalls only beside a near-tangent contact.
const MAX_MARCH: usize = 20_000;

fn scaled(v: &Vec2<Float>, k: &Float) -> Vec2<Float> {
    Vec2::new(v.x.clone() * k, v.y.clone() * k)
}

fn plus(a: &Vec2<Float>, b: &Vec2<Float>) -> Vec2<Float> {
    Vec2::new(a.x.clone() + &b.x, a.y.clone() + &b.y)
}

/// J(x, y) = (−y, x).
fn quarter(v: &Vec2<Float>) -> Vec2<Float> {
    Vec2::new(-v.y.clone(), v.x.clone())
}

impl Table {
    /// The first contact time of the flight `start` with the disk whose centre c′ is at −`d`
    /// from the start's point (d = X₀ − c′), or `Miss`. `identity`: the disk just left (a
    /// return), where F(0) = 0 is taken exactly. A march of steps each free of contact (see
    /// [`safe_step`]) that ends where the step falls below the rounding level.
    fn first_contact(
        &self,
        start: &Start<'_, Float>,
        d: &Vec2<Float>,
        identity: bool,
    ) -> Result<Float, StepFailure> {
        let b = self.bits;
        let r = &self.r;
        let eps = start.thermostat().strength.to_f64();
        // Far beyond every disk of the cell's neighbourhood, and past any turn of the velocity.
        let far = 64.0 * (d.norm2().sqrt().to_f64() + r.to_f64()) + 64.0 / eps;
        let tol = Float::with_val(b, Float::i_exp(1, 8 - b as i32));
        let mut t = Float::new(b);
        for n in 0..MAX_MARCH {
            let at = start.at(&t);
            let rel = plus(d, &at.disp);
            let dist = rel.norm2().sqrt();
            let g = dist.clone() - r;
            if identity && n == 0 {
                let f1 = rel.dot(&at.vel) * 2u32;
                t = safe_step(&Float::new(b), &f1, &dist, &g, r, eps);
                continue;
            }
            if !g.is_sign_positive() || g.is_zero() {
                // At the rounding level of the root (each step ends before it).
                return Ok(t);
            }
            if g.to_f64() > far {
                return Err(StepFailure::Miss);
            }
            let f = g.clone() * &(dist.clone() + r);
            let f1 = rel.dot(&at.vel) * 2u32;
            let step = safe_step(&f, &f1, &dist, &g, r, eps);
            if step <= tol.clone() * &(t.clone() + 1u32) {
                return Ok(t + &step);
            }
            t += &step;
        }
        Err(StepFailure::Miss)
    }

    /// The thermostatted map from `x` to the disk `next` in the field `th` (world frame) and its
    /// Jacobian in (s, p) (see the module documentation).
    pub(super) fn thermo_step(
        &self,
        x: &OrbitPoint,
        next: [i64; 2],
        th: &Thermostat<Float>,
    ) -> Result<Step, StepFailure> {
        let b = self.bits;
        let dep = self.departure(x)?;
        let start = th.start(&dep.v);
        let c1 = self.centre(next);
        let d = dep.x0.sub(&c1);
        let tau = self.first_contact(&start, &d, next == x.disk)?;
        let at = start.at(&tau);
        let n1 = scaled(&plus(&d, &at.disp), &(Float::with_val(b, 1) / &self.r));
        let vin = at.vel;
        let nv = n1.dot(&vin);
        if !nv.is_sign_negative() {
            return Err(StepFailure::Miss);
        }
        let s1 = Float::with_val(b, n1.y.atan2_ref(&n1.x));
        let p1 = n1.cross(&vin);
        let (dx_dth, dth_dth) = start.variation(&tau);
        let jvin = quarter(&vin);
        let nn = n1.norm2();
        let mut jac: M2 = std::array::from_fn(|_| Float::new(b));
        for dir in 0..2 {
            let (dx0, dv) = self.departure_tangent(&dep, dir);
            let dth = dep.v.cross(&dv);
            let dq = plus(&dx0, &scaled(&dx_dth, &dth));
            let dvt = scaled(&jvin, &(dth_dth.clone() * &dth));
            let dtau = -(n1.dot(&dq) / &nv);
            let dx1 = plus(&dq, &scaled(&vin, &dtau));
            let dv1 = plus(&dvt, &scaled(&at.acc, &dtau));
            [jac[dir], jac[2 + dir]] = self.arrival_tangent(&n1, &nn, &dx1, &vin, &dv1);
        }
        Ok(Step {
            s: s1,
            p: p1,
            jac,
            cos_in: -nv,
            tau,
        })
    }
}

/// A step from a point at the distance `dist` = r + `g` from the disk's centre, with
/// F = |X − c|² − r² = `f` ≥ 0 and F′ = `f1`, before which the flight cannot reach the disk: the
/// larger of g (the speed is 1) and the first root of the lower bound
/// L(s) = F + F′s + cs², c = 1 − ε(dist + S), on [0, S], S = max(2g, r/4) (F″/2 = 1 + (X − c)·v̇
/// and |v̇| ≤ ε, |X − c| ≤ dist + s), or S where L has none there. Near a transversal root the
/// step is Newton's to second order, so the march converges quadratically.
fn safe_step(f: &Float, f1: &Float, dist: &Float, g: &Float, r: &Float, eps: f64) -> Float {
    let cap = (g.clone() * 2u32).max(&(r.clone() / 4u32));
    let c = -((dist.clone() + &cap) * eps) + 1u32;
    let root = if f.is_zero() {
        // On the disk by identity, leaving: the root of F′ + cs.
        (f1.is_sign_positive() && c.is_sign_negative()).then(|| -(f1.clone() / &c))
    } else {
        let disc = f1.clone().square() - &(c.clone() * f * 4u32);
        let opens = c.is_sign_negative() || f1.is_sign_negative();
        (opens && disc.is_sign_positive()).then(|| f.clone() * 2u32 / &(disc.sqrt() - f1))
    };
    let step = root.map_or(cap.clone(), |s| s.min(&cap));
    step.max(g)
}

/// A lower bound on the clearance (distance − r) of one thermostatted flight, X₀ + Δ(t) for
/// 0 ≤ t ≤ `tau`, from the disks centred at `cs`: a march that evaluates the gap g at t and steps
/// by g/2 (the speed is 1, so the gap is ≥ g/2 over the step). `Err(g)` if a point is inside a
/// disk or the march stalls ([`MAX_MARCH`] points) at the gap g.
fn flight_clearance(
    start: &Start<'_, Float>,
    x0: &Vec2<Float>,
    tau: &Float,
    cs: &[Vec2<Float>],
    r: &Float,
) -> Result<f64, f64> {
    let mut t = Float::new(tau.prec());
    let mut min = f64::INFINITY;
    for _ in 0..MAX_MARCH {
        let p = plus(x0, &start.at(&t).disp);
        let g = cs
            .iter()
            .map(|c| (c.sub(&p).norm2().sqrt() - r).to_f64())
            .fold(f64::INFINITY, f64::min);
        if g <= 0.0 {
            return Err(g);
        }
        min = min.min(0.5 * g);
        if t >= *tau {
            return Ok(min);
        }
        t += 0.5 * g;
        if t > *tau {
            t = tau.clone();
        }
    }
    Err(min)
}

/// Smallest clearance (a lower bound, [`flight_clearance`]) of the thermostatted flights of `y`
/// (flight times `tau`, field `th`) from every disk near them other than their end disks, and
/// the first flight that passes through one or comes too close to resolve (k, disk, clearance).
/// A flight within the box of half-width τ about its start (the speed is 1). The disk a flight
/// leaves is not checked: the flight's curvature is at most ε, and a curve of curvature below
/// 1/r leaving a disk of radius r cannot re-enter it (for εr ≥ 1 this is not checked).
pub(super) fn thermo_clearance(
    table: &Table,
    y: &[OrbitPoint],
    tau: &[Float],
    th: &Thermostat<Float>,
) -> (f64, Option<(usize, [i64; 2], f64)>) {
    let mut min = f64::INFINITY;
    for k in 0..y.len() - 1 {
        let Ok(dep) = table.departure(&y[k]) else {
            continue;
        };
        let start = th.start(&dep.v);
        let (p0, t) = (dep.x0.to_f64(), tau[k].to_f64());
        let lo = [p0[0] - t, p0[1] - t];
        let hi = [p0[0] + t, p0[1] + t];
        let reach = t + table.r.to_f64() + 1e-9;
        for d in disks_near(table, lo, hi) {
            let c = [table.centre(d)];
            let far = c[0].sub(&dep.x0).norm2().sqrt().to_f64() > reach;
            if d == y[k].disk || d == y[k + 1].disk || far {
                continue;
            }
            match flight_clearance(&start, &dep.x0, &tau[k], &c, &table.r) {
                Ok(g) => min = min.min(g),
                Err(g) => return (g.min(min), Some((k, d, g))),
            }
        }
    }
    (min, None)
}
