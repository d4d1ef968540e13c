//! The paper's scene: disks of radius 1 on the triangular lattice of spacing a = 2 + w, disk
//! centres at a(i + j/2, j√3/2). The cell is the canonical trap ([`Trap`]: three vertex disks,
//! three edges, point reflections into the neighbouring traps), run on its fused kernel.

pub mod geometry;

use rand::Rng;
use rug::Rational;

use super::lattice::{CellIndex, LatticeState, settle};
use super::{Located, Scene};
use crate::Error;
use crate::kernel::flight::Flight;
use crate::kernel::trap::Trap;
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;
use crate::scenes::triangular::geometry::Geometry;

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
        let q = Rational::from_f64(w).ok_or(Error::NotFinite { what: "w" })?;
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

    /// The trap from the point's lattice coordinates (u, v) = (x/a − y/(2h), y/h): the
    /// parallelogram (⌊u⌋, ⌊v⌋) splits into the up trap (⌊u⌋, ⌊v⌋) (frac u + frac v ≤ 1) and the
    /// down trap (⌊u⌋ + 1, ⌊v⌋ + 1). This first guess is taken in `f64`; the offset is then
    /// computed at the working precision from the exact (x, y) and moved across any edge it is
    /// beyond, decided at the working precision ([`settle`]).
    fn locate<T: Real>(&self, ctx: T::Ctx, x: &Rational, y: &Rational) -> Located<T> {
        super::check_world_point(x, y)?;
        let trap = self.kernel::<T>(ctx)?;
        let (x64, y64) = (
            crate::numbers::exact::nearest_f64(x),
            crate::numbers::exact::nearest_f64(y),
        );
        let v = y64 / self.trap64.h;
        let u = x64 / self.trap64.a - v / 2.0;
        let (i, j) = (u.floor(), v.floor());
        let up = (u - i) + (v - j) <= 1.0;
        let (i, j) = (i as i64, j as i64);
        let lattice_point = |i: i64, j: i64| {
            let (fi, fj) = (T::from_f64(ctx, i as f64), T::from_f64(ctx, j as f64));
            Vec2::new(
                trap.a.clone() * &(fi + &fj.clone().scale(0.5)),
                trap.h.clone() * &fj,
            )
        };
        let world = Vec2::new(T::from_rational(ctx, x), T::from_rational(ctx, y));
        let (index, p) = if up {
            (
                CellIndex { i, j, down: false },
                world.sub(&lattice_point(i, j)),
            )
        } else {
            let (i, j) = (i + 1, j + 1);
            (
                CellIndex { i, j, down: true },
                lattice_point(i, j).sub(&world),
            )
        };
        settle(trap.cell(), index, p)
    }

    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> LatticeState<f64> {
        equilibrium_state(&self.trap64, rng)
    }

    fn mean_free_path(&self) -> f64 {
        Geometry::new(self.w())
            .map(|g| g.mean_free_path())
            .unwrap_or(f64::NAN)
    }

    /// Decided exactly from the exact gap: a corridor along the lattice vectors opens when the
    /// rows' spacing a√3/2 exceeds the diameter 2, i.e. 3(2 + w)² > 16 — a comparison of
    /// rationals, never of rounded w and w∞ (`proofs-notes/corridors.md`).
    fn finite_horizon(&self) -> bool {
        let a = Rational::from(2) + &self.w;
        Rational::from(3) * a.clone() * &a <= 16
    }

    /// The paper's mean hop time τ = πA/(3w): a trap's three gaps of width w are its free edges.
    fn walk(&self) -> super::Walk {
        super::Walk::Triangular
    }

    fn crossing_time(&self) -> Option<f64> {
        Geometry::new(self.w()).ok().map(|g| g.hop_time())
    }

    /// Jumps beyond w∞ up to a = [`super::long_flight::triangular::MAX_SPACING`], on the trap
    /// kernel's own a and h ([`super::long_flight::triangular`]).
    fn long_flights(&self) -> Option<super::long_flight::LongFlights> {
        use super::long_flight::triangular::MAX_SPACING;
        (!self.finite_horizon() && self.trap64.a <= MAX_SPACING).then_some(
            super::long_flight::LongFlights::Triangular(
                super::long_flight::triangular::TriangularFlights {
                    a: self.trap64.a,
                    h: self.trap64.h,
                },
            ),
        )
    }

    fn isotropic(&self) -> bool {
        true
    }

    /// Disks of radius 1 at spacing a = 2 + w (e₂ = (a/2, √3a/2)).
    fn disk_lattice(&self) -> Option<super::magnetic::DiskLattice> {
        let a = 2.0 + self.w();
        // e₂ = (a/2, a√3/2): h² = 3a²/4 is rational, h is not (one disk per cell).
        let ax = Rational::from(&self.w + 2u32);
        let exact = super::magnetic::ExactDisks {
            b: Rational::from(&ax / 2u32),
            h2: Rational::from(&ax * &ax) * 3u32 / 4u32,
            h: None,
            disks: vec![([Rational::new(), Rational::new()], Rational::from(1))],
            a: ax,
        };
        let lattice = super::magnetic::DiskLattice::equal(a, 0.5, a * 3f64.sqrt() / 2.0, 1.0);
        Some(lattice.with_exact(exact))
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
    let vel = crate::scenes::sampling::direction(rng);
    LatticeState {
        cell: CellIndex::default(),
        flight: Flight::new(pos, vel),
    }
}
