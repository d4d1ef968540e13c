//! The billiard table at the working precision and one step of the collision map with its derivative.

use super::*;

/// The billiard table at the working precision: the lattice basis and the disk radius, every
/// constant computed from the scene's exact parameters.
#[derive(Debug, Clone)]
pub struct Table {
    pub(super) a: Float,
    pub(super) beta: Float,
    pub(super) h: Float,
    pub(super) r: Float,
    pub(super) bits: u32,
    /// The field ω = B at the working precision (the velocity turns at the angular velocity ω,
    /// counter-clockwise for ω > 0), or `None`: straight flights.
    pub(super) omega: Option<Float>,
    /// The thermostatted electric field at the working precision (world frame), or `None`.
    pub(super) thermo: Option<crate::kernel::thermostat::Thermostat<Float>>,
    /// An open table's disk centres at the working precision (disk k is labelled (k, 0)), or
    /// `None`: the lattice's disks.
    pub(super) centres: Option<Vec<Vec2<Float>>>,
}

/// 2×2 matrix, row-major.
pub(crate) type M2 = [Float; 4];

/// One step of the map with its Jacobian.
pub(crate) struct Step {
    pub(crate) s: Float,
    pub(crate) p: Float,
    pub(crate) jac: M2,
    /// cos φ at the arrival.
    pub(crate) cos_in: Float,
    /// Free flight τ.
    pub(crate) tau: Float,
}

/// Why a step of the map could not be taken.
#[derive(Debug, Clone)]
pub(crate) enum StepFailure {
    /// |p| ≥ 1: the outgoing velocity is tangent to the disk (or beyond).
    Grazing(Float),
    /// The line of flight misses the recorded next disk.
    Miss,
}

impl Table {
    /// The table of `scene` at `bits` of precision.
    ///
    /// # Errors
    /// If `bits` is outside MPFR's range or the scene refuses it.
    pub fn new<S: Scene>(scene: &S, bits: u32) -> Result<Self, Error> {
        let lat = scene.lattice::<Float>(bits)?;
        let c = lat.cell();
        let r = c.disks[0].radius().clone();
        if c.disks.iter().any(|d| *d.radius() != r) {
            return Err(Error::Lacks {
                scene: scene.label(),
                capability: crate::error::Capability::OneRadius,
                analysis: "true shadowing",
            });
        }
        Ok(Table {
            a: c.lattice.a.clone(),
            beta: c.lattice.beta.clone(),
            h: c.lattice.h.clone(),
            r,
            bits,
            omega: None,
            thermo: None,
            centres: None,
        })
    }

    /// An open table at `bits`: the disks of radius `r` centred at `centres` (disk k is labelled
    /// (k, 0) in [`OrbitPoint::disk`]), with straight flights.
    pub(crate) fn open(centres: Vec<Vec2<Float>>, r: Float, bits: u32) -> Self {
        let zero = Float::new(bits);
        Table {
            a: zero.clone(),
            beta: zero.clone(),
            h: zero,
            r,
            bits,
            omega: None,
            thermo: None,
            centres: Some(centres),
        }
    }

    /// The disk radius at the working precision.
    pub fn radius(&self) -> &Float {
        &self.r
    }

    /// The table of `scene` at `bits` in the field `field` (exact, nonzero; `None` or zero:
    /// no field, as [`Table::new`]): flights are arcs of the cyclotron circle.
    ///
    /// # Errors
    /// As [`Table::new`].
    pub fn in_field<S: Scene>(
        scene: &S,
        bits: u32,
        field: Option<&rug::Rational>,
    ) -> Result<Self, Error> {
        let motion = field
            .filter(|q| q.cmp0() != std::cmp::Ordering::Equal)
            .map(|q| ExactMotion::Field(q.clone()));
        Table::in_motion(scene, bits, motion.as_ref())
    }

    /// The table of `scene` at `bits` under `motion` (`None`: straight flights): arcs of the
    /// magnetic field, or the flights of the thermostatted electric field.
    ///
    /// # Errors
    /// As [`Table::new`].
    pub fn in_motion<S: Scene>(
        scene: &S,
        bits: u32,
        motion: Option<&ExactMotion>,
    ) -> Result<Self, Error> {
        let mut t = Table::new(scene, bits)?;
        match motion {
            Some(ExactMotion::Field(b)) => t.omega = Some(Float::with_val(bits, b)),
            Some(ExactMotion::Thermostat { field, angle }) => {
                t.thermo = crate::kernel::thermostat::Thermostat::exact(field, angle, bits);
            }
            None => {}
        }
        Ok(t)
    }

    /// The working precision.
    pub fn bits(&self) -> u32 {
        self.bits
    }

    /// Centre of disk (i, j): (a(i + βj), hj); on an open table, the centre of disk i.
    pub fn centre(&self, d: [i64; 2]) -> Vec2<Float> {
        if let Some(c) = &self.centres {
            return c[d[0] as usize].clone();
        }
        let (i, j) = (self.f(d[0] as f64), self.f(d[1] as f64));
        let x = self.a.clone() * &(i + &(self.beta.clone() * &j));
        Vec2::new(x, self.h.clone() * &j)
    }

    pub(super) fn f(&self, x: f64) -> Float {
        Float::with_val(self.bits, x)
    }

    /// The billiard map T from `x` to the disk `next` at the table's precision, and its
    /// Jacobian ∂(s′, p′)/∂(s, p) (row-major), by the chain rule through the flight. `None` if
    /// |p| ≥ 1 (grazing) or the line of flight misses `next`. Another disk in the way is not
    /// checked here (see [`shadow_pseudo_orbit`]).
    pub fn map(&self, x: &OrbitPoint, next: [i64; 2]) -> Option<(OrbitPoint, [Float; 4])> {
        let st = self.step(x, next).ok()?;
        Some((
            OrbitPoint {
                disk: next,
                s: st.s,
                p: st.p,
            },
            st.jac,
        ))
    }

    /// Contact point and outgoing velocity of the collision state `x`.
    pub(crate) fn phase(&self, x: &OrbitPoint) -> Result<(Vec2<Float>, Vec2<Float>), StepFailure> {
        let d = self.departure(x)?;
        Ok((d.x0, d.v))
    }

    /// The collision state `x` as a contact point and an outgoing velocity, with what the
    /// Jacobians need; `Grazing` if |p| ≥ 1.
    pub(super) fn departure(&self, x: &OrbitPoint) -> Result<Departure, StepFailure> {
        let b = self.bits;
        let s = Float::with_val(b, &x.s);
        let p = Float::with_val(b, &x.p);
        let cphi2 = Float::with_val(b, 1) - &p.clone().square();
        if !cphi2.is_sign_positive() || cphi2.is_zero() {
            return Err(StepFailure::Grazing(Float::with_val(b, 0)));
        }
        let cphi = cphi2.sqrt();
        let (sn, cs) = s.sin_cos(Float::new(b));
        let n = Vec2::new(cs.clone(), sn.clone());
        let t = Vec2::new(-sn, cs);
        let v = Vec2::new(
            cphi.clone() * &n.x + &(p.clone() * &t.x),
            cphi.clone() * &n.y + &(p.clone() * &t.y),
        );
        let x0 = self.centre(x.disk).along(&self.r, &n);
        Ok(Departure {
            n,
            t,
            v,
            cphi,
            p,
            x0,
        })
    }

    /// The tangent vector (δX, δv) of the departure along e_s (`dir` 0) or e_p (`dir` 1):
    /// δn = t δs, δt = −n δs, δcos φ = −p δp / cos φ, δv = δcos φ n + cos φ δn + δp t + p δt,
    /// δX = r δn.
    pub(super) fn departure_tangent(
        &self,
        d: &Departure,
        dir: usize,
    ) -> (Vec2<Float>, Vec2<Float>) {
        let (ds, dp) = if dir == 0 { (1.0, 0.0) } else { (0.0, 1.0) };
        let (ds, dp) = (self.f(ds), self.f(dp));
        let (n, t, p, cphi) = (&d.n, &d.t, &d.p, &d.cphi);
        let dn = Vec2::new(t.x.clone() * &ds, t.y.clone() * &ds);
        let dt = Vec2::new(-(n.x.clone() * &ds), -(n.y.clone() * &ds));
        let dc = -(p.clone() * &dp) / cphi;
        let dv = Vec2::new(
            dc.clone() * &n.x
                + &(cphi.clone() * &dn.x)
                + &(dp.clone() * &t.x)
                + &(p.clone() * &dt.x),
            dc * &n.y + &(cphi.clone() * &dn.y) + &(dp * &t.y) + &(p.clone() * &dt.y),
        );
        let dx0 = Vec2::new(dn.x.clone() * &self.r, dn.y.clone() * &self.r);
        (dx0, dv)
    }

    /// (δs′, δp′) at the arrival with the outward normal n′ (|n′|² = `nn`) and the incoming
    /// velocity v⁻ from the contact point's δX′ and the velocity's δv⁻: δn′ = δX′/r,
    /// δs′ = n′ × δn′/|n′|², δp′ = δn′ × v⁻ + n′ × δv⁻ (p′ = n′ × v⁻).
    pub(super) fn arrival_tangent(
        &self,
        n1: &Vec2<Float>,
        nn: &Float,
        dx1: &Vec2<Float>,
        vin: &Vec2<Float>,
        dvin: &Vec2<Float>,
    ) -> [Float; 2] {
        let dn1 = Vec2::new(dx1.x.clone() / &self.r, dx1.y.clone() / &self.r);
        [n1.cross(&dn1) / nn, dn1.cross(vin) + &n1.cross(dvin)]
    }

    /// The billiard map from `x` to the disk `next` and its analytic Jacobian in (s, p)
    /// (chain rule through the flight; `proofs-notes/shadowing.md`): along a straight line, or
    /// along an arc in a field ([`Table::arc_step`]).
    pub(crate) fn step(&self, x: &OrbitPoint, next: [i64; 2]) -> Result<Step, StepFailure> {
        if let Some(omega) = &self.omega {
            return self.arc_step(x, next, omega);
        }
        if let Some(th) = &self.thermo {
            return self.thermo_step(x, next, th);
        }
        let b = self.bits;
        let dep = self.departure(x)?;
        let v = &dep.v;
        let c1 = self.centre(next);
        let x0 = &dep.x0;
        let d = x0.sub(&c1);
        let beta = d.dot(v);
        let gamma = d.norm2() - &self.r.clone().square();
        let disc = beta.clone().square() - &gamma;
        if !beta.is_sign_negative() || !disc.is_sign_positive() || disc.is_zero() {
            return Err(StepFailure::Miss);
        }
        let sq = disc.clone().sqrt();
        // τ = −β − √Δ = γ/(√Δ − β), free of cancellation (β < 0, γ > 0).
        let tau = gamma / &(sq.clone() - &beta);
        let x1 = x0.along(&tau, v);
        let n1 = Vec2::new(
            (x1.x.clone() - &c1.x) / &self.r,
            (x1.y.clone() - &c1.y) / &self.r,
        );
        let s1 = Float::with_val(b, n1.y.atan2_ref(&n1.x));
        let p1 = n1.cross(v);
        let cos_in = sq.clone() / &self.r;
        let nn = n1.norm2();
        // Directional derivatives along e_s and e_p.
        let mut jac: M2 = std::array::from_fn(|_| Float::new(b));
        for dir in 0..2 {
            let (dx0, dv) = self.departure_tangent(&dep, dir);
            let dbeta = dx0.dot(v) + &d.dot(&dv);
            let dgamma = d.dot(&dx0) * 2u32;
            let ddisc = beta.clone() * &dbeta * 2u32 - &dgamma;
            let dtau = -dbeta - &(ddisc / &(sq.clone() * 2u32));
            let dx1 = Vec2::new(
                dx0.x.clone() + &(dtau.clone() * &v.x) + &(tau.clone() * &dv.x),
                dx0.y.clone() + &(dtau * &v.y) + &(tau.clone() * &dv.y),
            );
            [jac[dir], jac[2 + dir]] = self.arrival_tangent(&n1, &nn, &dx1, v, &dv);
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

/// A collision state as the maps use it: the outward normal n and tangent t at the contact
/// point X, the outgoing unit velocity v = cos φ n + p t.
pub(super) struct Departure {
    pub(super) n: Vec2<Float>,
    pub(super) t: Vec2<Float>,
    pub(super) v: Vec2<Float>,
    pub(super) cphi: Float,
    pub(super) p: Float,
    pub(super) x0: Vec2<Float>,
}
