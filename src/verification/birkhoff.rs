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

use crate::real::Real;

use crate::error::Error;
use crate::kernel::trap::{Event, EventKind, Flight, NONE};
use crate::kernel::vec2::Vec2;
use crate::scenes::lattice::{Cell, LatticeState, PeriodicLattice};

/// World-coordinate lattice point of vertex `m` of trap `cell`.
pub fn vertex_lattice_point(cell: &Cell, m: u8) -> (i64, i64) {
    // Up trap at anchor (i, j): vertices L(i,j), L(i+1,j), L(i,j+1); down: L(i,j), L(i-1,j), L(i,j-1).
    let (di, dj) = match m {
        0 => (0, 0),
        1 => (1, 0),
        _ => (0, 1),
    };
    if cell.down {
        (cell.i - di, cell.j - dj)
    } else {
        (cell.i + di, cell.j + dj)
    }
}

/// A collision state in Birkhoff coordinates, at the working precision.
#[derive(Debug, Clone)]
pub struct Birkhoff {
    /// Lattice point of the disk.
    pub disk: (i64, i64),
    /// Polar angle θ of the contact point (arc length on the unit circle).
    pub s: Float,
    /// sin φ of the outgoing velocity.
    pub p: Float,
}

/// Builds the lattice state just after a collision with the disk at the origin, with contact
/// angle `s ∈ (0, π/3)` (the arc of P₀ inside the up trap (0, 0)) and outgoing sin φ = `p`.
pub fn state_from_birkhoff(bits: u32, s: &Float, p: &Float) -> LatticeState<Float> {
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
    let mut flight = Flight::new(n, vel);
    flight.excluded_disk = 0;
    LatticeState {
        cell: Cell::default(),
        flight,
    }
}

/// Runs to the next collision and returns its Birkhoff coordinates (θ in world orientation).
pub fn next_collision(
    lat: &PeriodicLattice<Float>,
    st: &mut LatticeState<Float>,
) -> Result<Birkhoff, Error> {
    loop {
        let ev: Event<Float> = lat.step(st)?;
        if let EventKind::Collision(m) = ev.kind {
            let f = &st.flight;
            let c = &lat.trap.vertices[m as usize];
            // Normal and velocity in world orientation: both flip with the trap's sign, so
            // n × v (= sin φ) is frame independent and θ = atan2(s·n).
            let (mut nx, mut ny) = (f.pos.x.clone() - &c.x, f.pos.y.clone() - &c.y);
            let p = nx.clone() * &f.vel.y - &(ny.clone() * &f.vel.x);
            if st.cell.down {
                nx = -nx;
                ny = -ny;
            }
            let s = ny.atan2(&nx);
            return Ok(Birkhoff {
                disk: vertex_lattice_point(&st.cell, m),
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

/// The Jacobian of the Birkhoff map at (s, p) (contact on the disk at the origin, see
/// [`state_from_birkhoff`]) by central differences with step `h`, at `bits` of precision.
/// Returns `None` if a perturbed orbit hits a different disk (a singularity is within `h`).
pub fn birkhoff_jacobian(
    w: f64,
    bits: u32,
    s: &Float,
    p: &Float,
    h: &Float,
) -> Result<Option<Matrix2<Float>>, Error> {
    let lat = PeriodicLattice::new(Float::with_val(bits, w))?;
    let image = |s: &Float, p: &Float| -> Result<Birkhoff, Error> {
        let mut st = state_from_birkhoff(bits, s, p);
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
        if fp.disk != base.disk || fm.disk != base.disk {
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
    pub fn event_matrix(
        f: &Flight<f64>,
        ev: &Event<f64>,
        vertices: &[Vec2<f64>; 3],
    ) -> Matrix4<f64> {
        // The map is linear: its columns are the images of the unit tangent vectors.
        let mut m = Matrix4::zeros();
        for k in 0..4 {
            let mut e = Vector4::zeros();
            e[k] = 1.0;
            tangent_step(&mut e, f, ev, vertices);
            m.set_column(k, &e);
        }
        m
    }

    /// Multiplies in one event (call before the event is applied to `f`).
    pub fn push(&mut self, f: &Flight<f64>, ev: &Event<f64>, vertices: &[Vec2<f64>; 3]) {
        self.jac = Self::event_matrix(f, ev, vertices) * self.jac;
    }

    /// Largest singular value of the accumulated Jacobian.
    pub fn norm(&self) -> f64 {
        self.jac.singular_values().max()
    }
}

/// `NONE` re-exported for callers building flights by hand.
pub const NO_OBSTACLE: u8 = NONE;

/// Applies the linearisation of one event to the tangent vector (δq, δv) ∈ ℝ⁴.
pub fn tangent_step(
    t: &mut Vector4<f64>,
    f: &Flight<f64>,
    ev: &Event<f64>,
    vertices: &[Vec2<f64>; 3],
) {
    let tt = ev.time;
    let mut dq = Vector2::new(t[0] + tt * t[2], t[1] + tt * t[3]);
    let mut dv = Vector2::new(t[2], t[3]);
    match ev.kind {
        EventKind::Crossing(_) => {
            dq = -dq;
            dv = -dv;
        }
        EventKind::Collision(m) => {
            let x = f.pos.along(&tt, &f.vel);
            let c = &vertices[m as usize];
            let n = Vector2::new(x.x - c.x, x.y - c.y).normalize();
            let v = Vector2::new(f.vel.x, f.vel.y);
            let vn = v.dot(&n);
            let dt = -n.dot(&dq) / vn;
            let dn = dq + v * dt;
            let dq2 = dq - n * (2.0 * n.dot(&dq));
            let dv2 = dv - n * (2.0 * dv.dot(&n)) - n * (2.0 * v.dot(&dn)) - dn * (2.0 * vn);
            dq = dq2;
            dv = dv2;
        }
    }
    *t = Vector4::new(dq[0], dq[1], dv[0], dv[1]);
}
