//! The square Lorentz gas (Sinai billiard): disks of radius 0 < r < 1/2 centred at every integer
//! point of the plane.
//!
//! Cell: the square [−½, ½]² around one disk centre, with that single disk as its only obstacle —
//! every other centre is an integer point ≠ 0, at distance ≥ ½ > r from the square, so no other
//! disk reaches into it (`proofs-notes/no-missed-collision.md`). The four edges map into the
//! neighbouring cells by the translations ±x̂, ±ŷ (exact in the cell index; in the offset, the
//! subtraction x − 1 with x ≈ ½ is exact by Sterbenz's lemma). The horizon is always infinite:
//! the corridors |y − k − ½| < ½ − r are free of disks, so the mean squared displacement grows
//! like t ln t and no finite diffusion coefficient exists.

use rand::Rng;
use rug::Rational;

use super::lattice::{CellIndex, LatticeState};
use super::{Located, Scene};
use crate::Error;
use crate::kernel::cell::{ConvexCell, Disk, Edge, EdgeMap, LatticeBasis};
use crate::kernel::flight::Flight;
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;

/// The square Lorentz gas with disk radius r.
#[derive(Debug, Clone)]
pub struct SquareScene {
    /// The radius, exactly as given.
    r: Rational,
    /// Nearest double of r.
    r64: f64,
}

impl SquareScene {
    /// The scene at the exact radius `r`.
    ///
    /// # Errors
    /// Unless 0 < r < 1/2 (at r = 1/2 neighbouring disks touch and the cell is no longer free).
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::scenes::{square::SquareScene, Scene};
    /// let s = SquareScene::exact(rug::Rational::from((1, 3))).unwrap();
    /// // Santaló: (1 − πr²)/(2r).
    /// let r = 1.0 / 3.0;
    /// assert!((s.mean_free_path() - (1.0 - std::f64::consts::PI * r * r) / (2.0 * r)).abs() < 1e-15);
    /// assert!(SquareScene::exact(rug::Rational::from((1, 2))).is_err());
    /// ```
    pub fn exact(r: Rational) -> Result<Self, Error> {
        check_radius(&r)?;
        let r64 = <f64 as Real>::from_rational((), &r);
        Ok(SquareScene { r, r64 })
    }

    /// The scene at the double `r` (taken exactly as that binary number).
    pub fn new(r: f64) -> Result<Self, Error> {
        let q = Rational::from_f64(r).ok_or(Error::NotFinite { what: "radius" })?;
        Self::exact(q)
    }

    /// The radius as the nearest double.
    pub fn radius(&self) -> f64 {
        self.r64
    }
}

/// Refuses a radius outside 0 < r < 1/2 (exactly): the disks of neighbouring cells would touch.
///
/// # Errors
/// [`Error::OutOfRange`] naming `radius` and its range.
pub fn check_radius(r: &Rational) -> Result<(), Error> {
    if *r <= 0 || *r >= Rational::from((1, 2)) {
        return Err(Error::out_of_range(
            "radius",
            Float64(r),
            "use 0 < radius < 1/2",
        ));
    }
    Ok(())
}

/// Displays a rational by its nearest double (for error messages).
struct Float64<'a>(&'a Rational);

impl std::fmt::Display for Float64<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", <f64 as Real>::from_rational((), self.0))
    }
}

impl Scene for SquareScene {
    type Kernel<T: Real> = ConvexCell<T>;

    fn label(&self) -> String {
        format!("square r={}", self.r64)
    }

    fn kernel<T: Real>(&self, ctx: T::Ctx) -> Result<ConvexCell<T>, Error> {
        T::check_ctx(ctx)?;
        let r = T::from_rational(ctx, &self.r);
        let (z, one) = (T::zero(ctx), T::one(ctx));
        let half = T::from_f64(ctx, 0.5);
        let v = |x: &T, y: &T| Vec2::new(x.clone(), y.clone());
        let (mh, ph) = (-half.clone(), half.clone());
        // Edges 0..3: right, top, left, bottom; each enters the neighbour by the opposite one.
        let edge = |n: Vec2<T>, t: Vec2<T>, entered: u8, step: [i64; 2]| Edge {
            normal: n,
            offset: mh.clone(),
            map: EdgeMap::Translation(t),
            entered,
            disks_after: vec![None],
            step,
        };
        let edges = vec![
            edge(v(&-one.clone(), &z), v(&one, &z), 2, [1, 0]),
            edge(v(&z, &-one.clone()), v(&z, &one), 3, [0, 1]),
            edge(v(&one, &z), v(&-one.clone(), &z), 0, [-1, 0]),
            edge(v(&z, &one), v(&z, &-one.clone()), 1, [0, -1]),
        ];
        Ok(ConvexCell {
            corners: vec![v(&ph, &mh), v(&ph, &ph), v(&mh, &ph), v(&mh, &mh)],
            disks: vec![Disk::new(v(&z, &z), r)],
            edges,
            lattice: LatticeBasis {
                a: one.clone(),
                beta: z,
                h: one,
            },
        })
    }

    /// Exact: i = round(x), j = round(y) in rationals (halves round away from zero, so a point
    /// on a cell edge goes to the outer cell), offset (x − i, y − j) exact and rounded once.
    fn locate<T: Real>(&self, ctx: T::Ctx, x: &Rational, y: &Rational) -> Located<T> {
        T::check_ctx(ctx)?;
        super::check_world_point(x, y)?;
        let split = |q: &Rational| -> (i64, Rational) {
            let n = q.clone().round();
            let i = n
                .numer()
                .to_i64()
                .expect("|q| <= MAX_WORLD_COORDINATE fits an i64");
            (i, q.clone() - n)
        };
        let ((i, fx), (j, fy)) = (split(x), split(y));
        Ok((
            CellIndex { i, j, down: false },
            Vec2::new(T::from_rational(ctx, &fx), T::from_rational(ctx, &fy)),
        ))
    }

    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> LatticeState<f64> {
        let r2 = self.r64 * self.r64;
        let pos = loop {
            let p = Vec2::new(rng.random::<f64>() - 0.5, rng.random::<f64>() - 0.5);
            if p.x * p.x + p.y * p.y >= r2 {
                break p;
            }
        };
        LatticeState {
            cell: CellIndex::default(),
            flight: Flight::new(pos, crate::scenes::sampling::direction(rng)),
        }
    }

    fn mean_free_path(&self) -> f64 {
        // π|Q|/|∂Q| with |Q| = 1 − πr², |∂Q| = 2πr.
        let r = self.r64;
        (1.0 - std::f64::consts::PI * r * r) / (2.0 * r)
    }

    fn finite_horizon(&self) -> bool {
        false
    }

    /// τ = π(1 − πr²)/4: the unit square's four edges lie outside the disk (r < ½), L = 4.
    fn crossing_time(&self) -> Option<f64> {
        let r = self.r64;
        Some(std::f64::consts::PI * (1.0 - std::f64::consts::PI * r * r) / 4.0)
    }

    /// Jumps for 2⁻³² ≤ r ≤ 1/4 (`proofs-notes/long-flights.md`).
    fn long_flight_radius(&self) -> Option<f64> {
        use super::long_flight::{MAX_RADIUS, MIN_RADIUS};
        (MIN_RADIUS..=MAX_RADIUS)
            .contains(&self.r64)
            .then_some(self.r64)
    }

    fn isotropic(&self) -> bool {
        true
    }

    /// Disks of radius r on the unit square lattice.
    fn disk_lattice(&self) -> Option<super::magnetic::DiskLattice> {
        let one = || Rational::from(1);
        let exact = super::magnetic::ExactDisks {
            a: one(),
            b: Rational::new(),
            h2: one(),
            h: Some(one()),
            disks: vec![([Rational::new(), Rational::new()], self.r.clone())],
        };
        Some(super::magnetic::DiskLattice::equal(1.0, 0.0, 1.0, self.r64).with_exact(exact))
    }
}
