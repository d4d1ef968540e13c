//! A scene defined outside the crate, in one file: the triangular Lorentz gas with disks of any
//! radius R (the crate's own scene fixes R = 1), described by its rhombic cell — four corner
//! disks, four edges that translate into the neighbouring cells — and run through the generic
//! kernel. The run checks Santaló's mean free path ⟨ℓ⟩ = (ah − πR²)/(2R) against the measured
//! one with a Student-t bound, and exits with status 1 if it fails.
//!
//! ```sh
//! cargo run --release --example custom_scene
//! ```
//!
//! What a new scene supplies is only its geometry ([`Scene`]): the cell as a
//! [`ConvexCell`] (corners, disks, edges with their maps), where a world point lies, the
//! invariant-measure sampler and its exact identities. Everything else — the kernel, the
//! lattice walk with exact integer cell indices, the engines, the MPFR shadow — comes with it.

use lorentz_gas::kernel::cell::{ConvexCell, Edge, EdgeMap, LatticeBasis};
use lorentz_gas::kernel::flight::{EventKind, Flight};
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::numbers::real::Real;
use lorentz_gas::scenes::lattice::{CellIndex, LatticeState};
use lorentz_gas::scenes::sampling::{direction, stream};
use lorentz_gas::scenes::Scene;
use lorentz_gas::statistics::{mean_se, normal_sigma_equivalent_t};
use lorentz_gas::Error;
use rand::Rng;
use rug::Rational;

/// Disks of radius `r` on the triangular lattice of spacing `a` (a > 2r: the disks do not
/// touch), in the rhombic cell with corners 0, e₁, e₁ + e₂, e₂ (e₁ = (a, 0), e₂ = (a/2, h),
/// h = √3a/2). No disk but the four corner ones reaches into the cell: every other lattice point
/// is at least h > r from it.
#[derive(Debug, Clone)]
struct RhombicTriangular {
    a: Rational,
    r: Rational,
}

impl RhombicTriangular {
    fn new(a: Rational, r: Rational) -> Result<Self, Error> {
        if !(r > 0 && a > r.clone() * 2u32) {
            return Err(Error::Invalid("use 0 < 2r < a".into()));
        }
        Ok(RhombicTriangular { a, r })
    }

    /// The spacing as the nearest double.
    fn a64(&self) -> f64 {
        <f64 as Real>::from_rational((), &self.a)
    }

    /// The radius as the nearest double.
    fn r64(&self) -> f64 {
        <f64 as Real>::from_rational((), &self.r)
    }
}

impl Scene for RhombicTriangular {
    type Kernel<T: Real> = ConvexCell<T>;

    fn label(&self) -> String {
        format!("rhombic triangular a={} r={}", self.a64(), self.r64())
    }

    fn kernel<T: Real>(&self, ctx: T::Ctx) -> Result<ConvexCell<T>, Error> {
        T::check_ctx(ctx)?;
        let a = T::from_rational(ctx, &self.a);
        let r = T::from_rational(ctx, &self.r);
        let (z, one, half) = (T::zero(ctx), T::one(ctx), T::from_f64(ctx, 0.5));
        let s = T::sqrt3(ctx).scale(0.5); // √3/2
        let h = s.clone() * &a;
        let v = |x: T, y: T| Vec2::new(x, y);
        let e1 = v(a.clone(), z.clone());
        let e2 = v(a.clone().scale(0.5), h.clone());
        let neg = |p: &Vec2<T>| v(-p.x.clone(), -p.y.clone());
        // Edges 0..3: bottom, right, top, left; each enters the neighbour by the opposite one.
        // Disks 0..3 at 0, e₁, e₁ + e₂, e₂; `after` relabels them in the neighbour's frame.
        let edge = |n: Vec2<T>, o: T, t: Vec2<T>, entered: u8, after: [Option<u8>; 4], step| Edge {
            normal: n,
            offset: o,
            map: EdgeMap::Translation(t),
            entered,
            disks_after: after.to_vec(),
            step,
        };
        let edges = vec![
            edge(
                v(z.clone(), one.clone()),
                z.clone(),
                neg(&e2),
                2,
                [Some(3), Some(2), None, None],
                [0, -1],
            ),
            edge(
                v(-s.clone(), half.clone()),
                -(s.clone() * &a),
                e1.clone(),
                3,
                [None, Some(0), Some(3), None],
                [1, 0],
            ),
            edge(
                v(z.clone(), -one),
                -h.clone(),
                e2.clone(),
                0,
                [None, None, Some(1), Some(0)],
                [0, 1],
            ),
            edge(
                v(s.clone(), -half),
                z.clone(),
                neg(&e1),
                1,
                [Some(1), None, None, Some(2)],
                [-1, 0],
            ),
        ];
        let far = v(a.clone().scale(1.5), h.clone());
        let disks = vec![v(z.clone(), z.clone()), e1.clone(), far.clone(), e2.clone()];
        Ok(ConvexCell {
            corners: disks.clone(),
            radius2: r.square(),
            radius: r,
            disks,
            edges,
            lattice: LatticeBasis {
                a,
                beta: T::from_f64(ctx, 0.5),
                h,
            },
        })
    }

    /// The cell is found in `f64` (j = ⌊y/h⌋, i = ⌊x/a − j/2⌋); the offset is computed at the
    /// working precision from the exact point. A point within rounding of an edge may land in
    /// either neighbour, which describes the same world point.
    fn locate<T: Real>(
        &self,
        ctx: T::Ctx,
        x: &Rational,
        y: &Rational,
    ) -> Result<(CellIndex, Vec2<T>), Error> {
        lorentz_gas::scenes::check_world_point(x, y)?;
        let (a64, h64) = (self.a64(), self.a64() * 3f64.sqrt() / 2.0);
        let j = (y.to_f64() / h64).floor() as i64;
        let i = (x.to_f64() / a64 - j as f64 / 2.0).floor() as i64;
        let a = T::from_rational(ctx, &self.a);
        let h = T::sqrt3(ctx).scale(0.5) * &a;
        let ox = a.clone() * &T::from_f64(ctx, i as f64 + j as f64 / 2.0);
        let oy = h * &T::from_f64(ctx, j as f64);
        let p = Vec2::new(
            T::from_rational(ctx, x) - &ox,
            T::from_rational(ctx, y) - &oy,
        );
        Ok((CellIndex { i, j, down: false }, p))
    }

    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> LatticeState<f64> {
        let (a, r) = (self.a64(), self.r64());
        let h = a * 3f64.sqrt() / 2.0;
        let corners = [(0.0, 0.0), (a, 0.0), (1.5 * a, h), (0.5 * a, h)];
        let pos = loop {
            let (u, w): (f64, f64) = (rng.random(), rng.random());
            let (x, y) = (u * a + w * a / 2.0, w * h);
            if corners
                .iter()
                .all(|c| (x - c.0).powi(2) + (y - c.1).powi(2) >= r * r)
            {
                break Vec2::new(x, y);
            }
        };
        LatticeState {
            cell: CellIndex::default(),
            flight: Flight::new(pos, direction(rng)),
        }
    }

    /// Santaló: ⟨ℓ⟩ = π|Q|/|∂Q| with |Q| = ah − πr² (the four corner sectors make one disk) and
    /// |∂Q| = 2πr.
    fn mean_free_path(&self) -> f64 {
        let (a, r) = (self.a64(), self.r64());
        (a * a * 3f64.sqrt() / 2.0 - std::f64::consts::PI * r * r) / (2.0 * r)
    }

    /// Finite horizon below a = 4r/√3 (the paper's w∞ at r = 1).
    fn finite_horizon(&self) -> bool {
        self.a64() < 4.0 * self.r64() / 3f64.sqrt()
    }
}

/// Flight time per collision of one trajectory of `collisions` collisions from `start`.
fn free_path(
    scene: &RhombicTriangular,
    start: LatticeState<f64>,
    collisions: u64,
) -> Result<f64, Error> {
    let lattice = scene.lattice::<f64>(())?;
    let (mut s, mut time, mut hits) = (start, 0.0, 0u64);
    while hits < collisions {
        let e = lattice.step(&mut s)?;
        time += e.time;
        hits += u64::from(matches!(e.kind, EventKind::Collision(_)));
    }
    Ok(time / hits as f64)
}

fn main() -> Result<(), Error> {
    // r = 3/2 at gap 1/5: a = 2r + w = 16/5 < 4r/√3 ≈ 3.46 (finite horizon).
    let scene = RhombicTriangular::new(Rational::from((16, 5)), Rational::from((3, 2)))?;
    let (batches, collisions) = (16u64, 200_000u64);
    let per: Vec<f64> = (0..batches)
        .map(|b| free_path(&scene, scene.sample(&mut stream(7, b)), collisions))
        .collect::<Result<_, _>>()?;
    let (mean, se) = mean_se(&per);
    let exact = scene.mean_free_path();
    let z = (mean - exact) / se;
    // The 4σ-equivalent Student-t bound for a mean of independent batch means.
    let bound = normal_sigma_equivalent_t((batches - 1) as f64, 4.0);
    println!(
        "{} (finite horizon: {})",
        scene.label(),
        scene.finite_horizon()
    );
    println!("mean free path = {mean:.6} ± {se:.6} from {batches} trajectories of {collisions} collisions");
    println!("Santaló        = {exact:.6}   ({z:+.2} sigma; bound ±{bound:.2})");
    if z.abs() > bound {
        eprintln!("FAIL: the measured mean free path is {z:+.2} sigma from Santaló's");
        std::process::exit(1);
    }
    println!("PASS");
    Ok(())
}
