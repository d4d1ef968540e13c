//! The billiard map along arcs in a magnetic field, with its analytic Jacobian, and the
//! clearance of arcs from the other disks (`proofs-notes/shadowing.md`, "In a magnetic field").
//!
//! From the contact point X with the outgoing unit velocity v, the particle turns at the angular
//! velocity ω on the cyclotron circle of centre m = X + Jv/ω and radius ρ = 1/|ω|
//! (J(x, y) = (−y, x)). It meets the next disk c′ where the circle *enters* it: the particle is
//! outside c′ when it leaves X, so the first intersection it reaches is the entry, which is also
//! the return to the disk it left when c′ is that disk (a skipping orbit). The entry is
//! found from the circle's geometry without cancellation: with e = c′ − m, L = |e|,
//! L² − ρ² = |d|² − 2d·Jv/ω (d = c′ − X, |v| = 1), L − ρ = (L² − ρ²)/(L + ρ),
//! ρ − a = (r − (L − ρ))(r + (L − ρ))/(2L), ρ + a = (L + ρ − r)(L + ρ + r)/(2L), h² = (ρ − a)(ρ + a),
//! b = (L² − ρ² + r²)/(2L), the outward normal at the entry n′ = (−b e − sgn(ω) h Je)/(L r), and
//! cos φ′ = |ω| h L / r. The arc's angle θ about m is the angle from X − m to e + r n′ in the
//! sense of rotation, by `atan2`; the flight time is θ/|ω|.

use super::*;

/// J(x, y) = (−y, x).
fn quarter(v: &Vec2<Float>) -> Vec2<Float> {
    Vec2::new(-v.y.clone(), v.x.clone())
}

fn scaled(v: &Vec2<Float>, k: &Float) -> Vec2<Float> {
    Vec2::new(v.x.clone() * k, v.y.clone() * k)
}

fn plus(a: &Vec2<Float>, b: &Vec2<Float>) -> Vec2<Float> {
    Vec2::new(a.x.clone() + &b.x, a.y.clone() + &b.y)
}

/// The cyclotron circle of a departure: centre m, the radius vector u₀ = X − m of the start, the
/// radius ρ and the field ω.
pub(super) struct Circle {
    pub(super) m: Vec2<Float>,
    pub(super) u0: Vec2<Float>,
    pub(super) rho: Float,
    pub(super) omega: Float,
}

impl Circle {
    /// The circle of the particle at `x0` with the unit velocity `v` in the field `omega`.
    pub(super) fn new(x0: &Vec2<Float>, v: &Vec2<Float>, omega: &Float) -> Self {
        let k = Float::with_val(omega.prec(), 1) / omega;
        let off = scaled(&quarter(v), &k);
        Circle {
            m: plus(x0, &off),
            u0: -off,
            rho: k.abs(),
            omega: omega.clone(),
        }
    }

    /// The angle from u₀ to `w` about m in the sense of rotation, in [0, 2π).
    pub(super) fn swept(&self, w: &Vec2<Float>) -> Float {
        let mut c = self.u0.cross(w);
        if self.omega.is_sign_negative() {
            c = -c;
        }
        let a = c.atan2(&self.u0.dot(w));
        if a.is_sign_negative() {
            let two_pi = Float::with_val(a.prec(), rug::float::Constant::Pi) * 2u32;
            a + &two_pi
        } else {
            a
        }
    }

    /// The point at the angle `theta` (≥ 0) along the circle: m + R(sgn(ω)θ)u₀.
    pub(super) fn at(&self, theta: &Float) -> Vec2<Float> {
        let phi = if self.omega.is_sign_negative() {
            -theta.clone()
        } else {
            theta.clone()
        };
        let (sn, cs) = phi.sin_cos(Float::new(theta.prec()));
        let u = &self.u0;
        Vec2::new(
            self.m.x.clone() + &(cs.clone() * &u.x) - &(sn.clone() * &u.y),
            self.m.y.clone() + &(sn * &u.x) + &(cs * &u.y),
        )
    }

    /// The entry of the circle into the disk of centre `c` and radius `r` for the particle at
    /// `x0` with the unit velocity `v`: the outward normal there and cos φ′, or `Miss` if the
    /// circle does not cross the disk's boundary.
    pub(super) fn entry(
        &self,
        c: &Vec2<Float>,
        r: &Float,
        x0: &Vec2<Float>,
        v: &Vec2<Float>,
    ) -> Result<(Vec2<Float>, Float), StepFailure> {
        let d = c.sub(x0);
        let e = c.sub(&self.m);
        let l2_rho2 = d.norm2() - &(d.dot(&quarter(v)) * 2u32 / &self.omega);
        let l = e.norm2().sqrt();
        let lpr = l.clone() + &self.rho;
        let l_rho = l2_rho2.clone() / &lpr;
        let two_l = l.clone() * 2u32;
        let rho_minus_a = (r.clone() - &l_rho) * &(r.clone() + &l_rho) / &two_l;
        let rho_plus_a = (lpr.clone() - r) * &(lpr + r) / &two_l;
        if !rho_minus_a.is_sign_positive()
            || rho_minus_a.is_zero()
            || !rho_plus_a.is_sign_positive()
            || rho_plus_a.is_zero()
        {
            return Err(StepFailure::Miss);
        }
        let h = (rho_minus_a * &rho_plus_a).sqrt();
        let b = (l2_rho2 + &r.clone().square()) / &two_l;
        let mut side = quarter(&e);
        if self.omega.is_sign_positive() {
            side = -side;
        }
        let lr = l.clone() * r;
        let n1 = Vec2::new(
            (-(b.clone() * &e.x) + &(h.clone() * &side.x)) / &lr,
            (-(b * &e.y) + &(h.clone() * &side.y)) / &lr,
        );
        let cos_in = self.omega.clone().abs() * &h * &l / r;
        Ok((n1, cos_in))
    }
}

impl Table {
    /// The magnetic billiard map from `x` to the disk `next` along the cyclotron circle of the
    /// field `omega`, and its Jacobian in (s, p) by the chain rule: the departure's tangent
    /// vector, the flight at fixed time (δX ← δX + (sin φ/ω)δv + ((1 − cos φ)/ω)Jδv,
    /// δv ← R(φ)δv, φ = ωτ), the arrival time δτ = −(n′·δX)/(n′·v⁻), δX′ = δX + v⁻δτ,
    /// δv⁻ ← δv + ωJv⁻δτ, and δs′ = n′ × δn′, δp′ = δn′ × v⁻ + n′ × δv⁻ (δn′ = δX′/r).
    pub(super) fn arc_step(
        &self,
        x: &OrbitPoint,
        next: [i64; 2],
        omega: &Float,
    ) -> Result<Step, StepFailure> {
        let b = self.bits;
        let dep = self.departure(x)?;
        let circle = Circle::new(&dep.x0, &dep.v, omega);
        let c1 = self.centre(next);
        let (n1, cos_in) = circle.entry(&c1, &self.r, &dep.x0, &dep.v)?;
        let theta = circle.swept(&plus(&c1.sub(&circle.m), &scaled(&n1, &self.r)));
        let tau = theta.clone() / &omega.clone().abs();
        let x1 = c1.along(&self.r, &n1);
        let vin = scaled(&quarter(&x1.sub(&circle.m)), omega);
        let s1 = Float::with_val(b, n1.y.atan2_ref(&n1.x));
        let p1 = n1.cross(&vin);
        let phi = omega.clone() * &tau;
        let (sn, cs) = phi.clone().sin_cos(Float::new(b));
        let half = (phi / 2u32).sin();
        let along_v = sn.clone() / omega;
        let along_jv = half.square() * 2u32 / omega;
        let nv = n1.dot(&vin);
        let jvin = scaled(&quarter(&vin), omega);
        let nn = n1.norm2();
        let mut jac: M2 = std::array::from_fn(|_| Float::new(b));
        for dir in 0..2 {
            let (dx0, dv) = self.departure_tangent(&dep, dir);
            let jdv = quarter(&dv);
            let dq = plus(
                &plus(&dx0, &scaled(&dv, &along_v)),
                &scaled(&jdv, &along_jv),
            );
            let dvt = plus(&scaled(&dv, &cs), &scaled(&jdv, &sn));
            let dtau = -(n1.dot(&dq) / &nv);
            let dx1 = plus(&dq, &scaled(&vin, &dtau));
            let dv1 = plus(&dvt, &scaled(&jvin, &dtau));
            [jac[dir], jac[2 + dir]] = self.arrival_tangent(&n1, &nn, &dx1, &vin, &dv1);
        }
        Ok(Step {
            s: s1,
            p: p1,
            jac,
            cos_in,
            tau,
        })
    }
}

/// The distance from `c` to the arc of `circle` between the angles `lo` and `hi`: |‖c − m‖ − ρ|
/// if the direction of c from m lies between them (the distance along the circle is unimodal
/// about it), else the nearer end.
fn arc_distance(circle: &Circle, c: &Vec2<Float>, lo: &Float, hi: &Float) -> Float {
    let g = c.sub(&circle.m);
    let alpha = circle.swept(&g);
    if *lo <= alpha && alpha <= *hi {
        return (g.norm2().sqrt() - &circle.rho).abs();
    }
    let end = |t: &Float| c.sub(&circle.at(t)).norm2().sqrt();
    end(lo).min(&end(hi))
}

/// Smallest clearance (distance − r) of the arcs of `y` (flight times `tau`, field `omega`)
/// from every disk near them other than their end disks, and the first arc that passes through
/// one (k, disk, clearance). The disk an arc leaves needs no check: the cyclotron circle meets
/// its boundary twice, at the departure and at the return, so the part of the circle outside it
/// is the one arc between them, and the entry into any other disk (disjoint from it) lies on
/// that arc, before the return.
pub(super) fn arc_clearance(
    table: &Table,
    y: &[OrbitPoint],
    tau: &[Float],
    omega: &Float,
) -> (f64, Option<(usize, [i64; 2], f64)>) {
    let mut min = f64::INFINITY;
    let r = &table.r;
    for k in 0..y.len() - 1 {
        let Ok(dep) = table.departure(&y[k]) else {
            continue;
        };
        let circle = Circle::new(&dep.x0, &dep.v, omega);
        let theta = tau[k].clone() * &omega.clone().abs();
        let zero = Float::new(table.bits);
        let (x0, x1) = (dep.x0.to_f64(), circle.at(&theta).to_f64());
        let (th, rho) = (theta.to_f64(), circle.rho.to_f64());
        let m = circle.m.to_f64();
        let (lo, hi) = if th <= std::f64::consts::PI {
            let sag = 2.0 * rho * (0.25 * th).sin().powi(2);
            (
                [x0[0].min(x1[0]) - sag, x0[1].min(x1[1]) - sag],
                [x0[0].max(x1[0]) + sag, x0[1].max(x1[1]) + sag],
            )
        } else {
            ([m[0] - rho, m[1] - rho], [m[0] + rho, m[1] + rho])
        };
        for d in disks_near(table, lo, hi) {
            if d == y[k].disk || d == y[k + 1].disk {
                continue;
            }
            let g = (arc_distance(&circle, &table.centre(d), &zero, &theta) - r).to_f64();
            if g <= 0.0 {
                return (g.min(min), Some((k, d, g)));
            }
            min = min.min(g);
        }
    }
    (min, None)
}
