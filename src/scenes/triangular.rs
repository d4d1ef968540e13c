//! The paper's scene: disks of radius 1 on the triangular lattice of spacing a = 2 + w, disk
//! centres at a(i + j/2, j√3/2). The cell is the canonical trap ([`Trap`]: three vertex disks,
//! three edges, point reflections into the neighbouring traps), run on its fused kernel.

use rand::Rng;
use rug::Rational;

use super::lattice::{CellIndex, LatticeState};
use super::Scene;
use crate::error::Error;
use crate::geometry::Geometry;
use crate::kernel::trap::Trap;
use crate::kernel::vec2::Vec2;
use crate::kernel::Flight;
use crate::real::Real;

/// The triangular Lorentz gas at gap w.
#[derive(Debug, Clone)]
pub struct TriangularScene {
    /// The gap, exactly as given.
    w: Rational,
    /// The trap at the nearest double (the production sampler's frame).
    trap64: Trap<f64>,
}

impl TriangularScene {
    /// The scene at the double `w` (taken exactly as that binary number).
    ///
    /// # Errors
    /// If `w` is not a positive finite gap.
    pub fn new(w: f64) -> Result<Self, Error> {
        let q = Rational::from_f64(w)
            .ok_or_else(|| Error::Invalid(format!("w = {w} is not a finite number")))?;
        Self::exact(q)
    }

    /// The scene at the exact gap `w` (a decimal such as 1/10 is not a double: at a working
    /// precision P every constant is computed from the exact value).
    pub fn exact(w: Rational) -> Result<Self, Error> {
        let trap64 = Trap::new(<f64 as Real>::from_rational((), &w))?;
        Ok(TriangularScene { w, trap64 })
    }

    /// The gap as the nearest double.
    pub fn w(&self) -> f64 {
        self.trap64.w
    }

    /// The exact gap.
    pub fn w_exact(&self) -> &Rational {
        &self.w
    }

    /// The canonical trap in `f64`.
    pub fn trap64(&self) -> &Trap<f64> {
        &self.trap64
    }
}

impl Scene for TriangularScene {
    type Kernel<T: Real> = Trap<T>;

    fn label(&self) -> String {
        format!("triangular w={}", self.w())
    }

    fn kernel<T: Real>(&self, ctx: T::Ctx) -> Result<Trap<T>, Error> {
        T::check_ctx(ctx)?;
        Trap::new(T::from_rational(ctx, &self.w))
    }

    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> LatticeState<f64> {
        equilibrium_state(&self.trap64, rng)
    }

    fn mean_free_path(&self) -> f64 {
        Geometry::new(self.w())
            .map(|g| g.mean_free_path())
            .unwrap_or(f64::NAN)
    }

    fn finite_horizon(&self) -> bool {
        self.w() < Geometry::<f64>::w_inf(())
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

/// A lattice state drawn from the invariant measure (trap (0, 0), up): the invariant measure of
/// the billiard flow is uniform in position over the free region and uniform in direction; every
/// trap is congruent to the canonical one and the lattice is homogeneous, so no burn-in is needed.
pub fn equilibrium_state<R: Rng + ?Sized>(trap: &Trap<f64>, rng: &mut R) -> LatticeState<f64> {
    let pos = position_in_trap(trap, rng);
    let vel = crate::sampling::direction(rng);
    LatticeState {
        cell: CellIndex::default(),
        flight: Flight::new(pos, vel),
    }
}
