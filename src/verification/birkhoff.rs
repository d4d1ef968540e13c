//! The collision map in Birkhoff coordinates, its Jacobian, and the linearised flow.
//!
//! A collision state is the disk hit (a lattice point), the arc position s = θ (radius 1, θ the
//! polar angle of the contact point about the centre, counter-clockwise) and p = sin φ, φ the
//! angle of the outgoing velocity from the outward normal (positive counter-clockwise). The
//! billiard map T: (s, p) ↦ (s', p') preserves the measure ds dp, i.e. |det DT| = 1
//! (`proofs-notes/liouville.md`); [`birkhoff_jacobian`] measures DT by central differences at
//! high precision.
//!
//! [`Tangent`] propagates the 4×4 Jacobian of the flow in Cartesian coordinates (f64, nalgebra)
//! along an orbit, for error amplification bounds and Lyapunov exponents.

use nalgebra::{Matrix2, Matrix4, Vector2, Vector4};
use rug::Float;

use crate::numbers::real::Real;

use crate::Error;
use crate::kernel::vec2::Vec2;
use crate::kernel::{
    cell::CellKernel, cell::ConvexCell, flight::Event, flight::EventKind, flight::Flight,
};
use crate::scenes::Scene;
use crate::scenes::lattice::{CellIndex, Lattice, LatticeState};

/// A collision state in Birkhoff coordinates, at the working precision.
#[derive(Debug, Clone)]
pub struct Birkhoff {
    /// World centre of the disk (distinct disks are ≥ 2r apart: see [`Birkhoff::same_disk`]).
    pub disk: [f64; 2],
    /// Polar angle θ of the contact point (arc length on the unit circle).
    pub s: Float,
    /// sin φ of the outgoing velocity.
    pub p: Float,
}

impl Birkhoff {
    /// `true` if both states are on the same disk: disks do not overlap, so two centres closer
    /// than one radius (with rounding errors ~2⁻ᵇⁱᵗˢ) are the same disk.
    pub fn same_disk(&self, o: &Birkhoff, radius: f64) -> bool {
        (self.disk[0] - o.disk[0]).hypot(self.disk[1] - o.disk[1]) < radius
    }
}

/// Builds the lattice state just after a collision with disk 0 of the cell (0, 0), with contact
/// angle `s` (a point of the disk's arc inside the cell: (0, π/3) for the triangular trap's P₀,
/// any angle for a disk inside its cell) and outgoing sin φ = `p`.
pub fn state_from_birkhoff(cell: &ConvexCell<Float>, s: &Float, p: &Float) -> LatticeState<Float> {
    let bits = s.prec();
    let n = Vec2::new(
        Float::with_val(bits, s.cos_ref()),
        Float::with_val(bits, s.sin_ref()),
    );
    let t = Vec2::new(-n.y.clone(), n.x.clone());
    let cphi = (Float::with_val(bits, 1) - &Real::square(p)).sqrt();
    let vel = Vec2::new(
        cphi.clone() * &n.x + &(p.clone() * &t.x),
        cphi * &n.y + &(p.clone() * &t.y),
    );
    let (c, r) = (&cell.disks[0].centre, cell.disks[0].radius());
    let pos = Vec2::new(
        c.x.clone() + &(r.clone() * &n.x),
        c.y.clone() + &(r.clone() * &n.y),
    );
    let mut flight = Flight::new(pos, vel);
    flight.excluded_disk = Some(0);
    LatticeState {
        cell: CellIndex::default(),
        flight,
    }
}

/// Runs to the next collision and returns its Birkhoff coordinates (θ in world orientation).
pub fn next_collision<K: CellKernel<Float>>(
    lat: &Lattice<Float, K>,
    st: &mut LatticeState<Float>,
) -> Result<Birkhoff, Error> {
    loop {
        let ev: Event<Float> = lat.step(st)?;
        if let EventKind::Collision(m) = ev.kind {
            let f = &st.flight;
            let disk = &lat.cell().disks[m as usize];
            let c = &disk.centre;
            // Normal and velocity in world orientation: both flip with the trap's sign, so
            // n × v / r (= sin φ, |n| = r) is frame independent and θ = atan2(s·n).
            let (mut nx, mut ny) = (f.pos.x.clone() - &c.x, f.pos.y.clone() - &c.y);
            let p = (nx.clone() * &f.vel.y - &(ny.clone() * &f.vel.x)) / disk.radius();
            if st.cell.down {
                nx = -nx;
                ny = -ny;
            }
            let s = ny.atan2(&nx);
            let centre = LatticeState {
                cell: st.cell,
                flight: Flight::new(c.clone(), f.vel.clone()),
            };
            let cw = lat.world(&centre);
            return Ok(Birkhoff {
                disk: [cw.x.to_f64(), cw.y.to_f64()],
                s,
                p,
            });
        }
    }
}

/// Difference of two angles reduced to (−π, π].
fn angle_diff(a: &Float, b: &Float) -> Float {
    let prec = a.prec();
    let pi = Float::with_val(prec, rug::float::Constant::Pi);
    let two_pi = pi.clone() * 2u32;
    let mut d = a.clone() - b;
    while d > pi {
        d -= &two_pi;
    }
    while d <= -pi.clone() {
        d += &two_pi;
    }
    d
}

/// The Jacobian of the Birkhoff map of `scene` at (s, p) (contact on disk 0 of cell (0, 0), see
/// [`state_from_birkhoff`]) by central differences with step `h`, at `bits` of precision.
/// Returns `None` if a perturbed orbit hits a different disk (a singularity is within `h`).
pub fn birkhoff_jacobian<S: Scene>(
    scene: &S,
    bits: u32,
    s: &Float,
    p: &Float,
    h: &Float,
) -> Result<Option<Matrix2<Float>>, Error> {
    let lat = scene.lattice::<Float>(bits)?;
    // The scale at which two contact disks are told apart: the smallest radius.
    let r = lat.cell().smallest_radius();
    let image = |s: &Float, p: &Float| -> Result<Birkhoff, Error> {
        let mut st = state_from_birkhoff(lat.cell(), s, p);
        next_collision(&lat, &mut st)
    };
    let base = image(s, p)?;
    let mut cols: Vec<(Float, Float)> = Vec::new();
    for j in 0..2 {
        let (mut sp, mut pp) = (s.clone(), p.clone());
        let (mut sm, mut pm) = (s.clone(), p.clone());
        if j == 0 {
            sp += h;
            sm -= h;
        } else {
            pp += h;
            pm -= h;
        }
        let (fp, fm) = (image(&sp, &pp)?, image(&sm, &pm)?);
        if !fp.same_disk(&base, r) || !fm.same_disk(&base, r) {
            return Ok(None);
        }
        let two_h = h.clone() * 2u32;
        cols.push((angle_diff(&fp.s, &fm.s) / &two_h, (fp.p - &fm.p) / &two_h));
    }
    let z = Float::with_val(bits, 0);
    let mut m = Matrix2::from_element(z);
    m[(0, 0)] = cols[0].0.clone();
    m[(1, 0)] = cols[0].1.clone();
    m[(0, 1)] = cols[1].0.clone();
    m[(1, 1)] = cols[1].1.clone();
    Ok(Some(m))
}

/// det of a 2×2 `Float` matrix.
pub fn det2(m: &Matrix2<Float>) -> Float {
    m[(0, 0)].clone() * &m[(1, 1)] - &(m[(0, 1)].clone() * &m[(1, 0)])
}

/// The Jacobian of the flow in Cartesian coordinates (δq, δv) ∈ ℝ⁴, propagated event by event
/// along an `f64` orbit in the canonical frames (`proofs-notes/tangent-map.md`).
#[derive(Debug, Clone)]
pub struct Tangent {
    /// The accumulated 4×4 Jacobian.
    pub jac: Matrix4<f64>,
}

impl Default for Tangent {
    fn default() -> Self {
        Tangent {
            jac: Matrix4::identity(),
        }
    }
}

impl Tangent {
    /// The linearisation of one event: flight for time t, then either the collision with unit
    /// normal n (incoming velocity v) or the point reflection of a crossing (δ ↦ −δ).
    pub fn event_matrix(f: &Flight<f64>, ev: &Event<f64>, cell: &ConvexCell<f64>) -> Matrix4<f64> {
        // The map is linear: its columns are the images of the unit tangent vectors.
        let mut m = Matrix4::zeros();
        for k in 0..4 {
            let mut e = Vector4::zeros();
            e[k] = 1.0;
            tangent_step(&mut e, f, ev, cell);
            m.set_column(k, &e);
        }
        m
    }

    /// Multiplies in one event (call before the event is applied to `f`).
    pub fn push(&mut self, f: &Flight<f64>, ev: &Event<f64>, cell: &ConvexCell<f64>) {
        self.jac = Self::event_matrix(f, ev, cell) * self.jac;
    }

    /// Largest singular value of the accumulated Jacobian.
    pub fn norm(&self) -> f64 {
        self.jac.singular_values().max()
    }
}

/// Applies the linearisation of one event of `cell` to the tangent vector (δq, δv) ∈ ℝ⁴: a
/// translation into the neighbour leaves it alone, a point reflection negates it, a collision
/// with a disk of radius r is the reflection with curvature 1/r (δn = δx_c/r).
pub fn tangent_step(
    t: &mut Vector4<f64>,
    f: &Flight<f64>,
    ev: &Event<f64>,
    cell: &ConvexCell<f64>,
) {
    let tt = ev.time;
    let mut dq = Vector2::new(t[0] + tt * t[2], t[1] + tt * t[3]);
    let mut dv = Vector2::new(t[2], t[3]);
    match ev.kind {
        EventKind::Crossing(k) => {
            if cell.edges[k as usize].flips() {
                dq = -dq;
                dv = -dv;
            }
        }
        EventKind::Collision(m) => {
            let x = f.pos.along(&tt, &f.vel);
            let disk = &cell.disks[m as usize];
            let c = &disk.centre;
            let n = Vector2::new(x.x - c.x, x.y - c.y).normalize();
            let v = Vector2::new(f.vel.x, f.vel.y);
            let vn = v.dot(&n);
            let dt = -n.dot(&dq) / vn;
            let dn = (dq + v * dt) / *disk.radius();
            let dq2 = dq - n * (2.0 * n.dot(&dq));
            let dv2 = dv - n * (2.0 * dv.dot(&n)) - n * (2.0 * v.dot(&dn)) - dn * (2.0 * vn);
            dq = dq2;
            dv = dv2;
        }
    }
    *t = Vector4::new(dq[0], dq[1], dv[0], dv[1]);
}
