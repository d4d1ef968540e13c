//! A table the crate does not ship, defined in this one file and run through the library's own
//! estimators with no step loop of its own: the square lattice of unit spacing with disks of
//! radius 2/5 at the corners and 1/5 at the centres of the squares (two radii in one cell).
//!
//! ```sh
//! cargo run --release --example custom_scene
//! ```
//!
//! What a new scene supplies is its geometry ([`Scene`]): the cell as a [`ConvexCell`] (corners,
//! disks with their own radii, edges with their maps), where a world point lies, the
//! invariant-measure sampler and its closed forms (Santaló's mean free path, the crossing time,
//! whether the horizon is finite). Everything else comes with it:
//!
//! * D by the Einstein formula with its standard error over independent batches
//!   ([`diffusion::scene::run_on`]), with the scene's exact identities measured — the mean free
//!   path against Santaló's π|Q|/|∂Q|, the mean crossing time against π|Q|/L — each within the
//!   4σ-equivalent Student-t bound;
//! * the per-event shadow audit of the run's own events (a sample replayed in MPFR and judged
//!   against the f64 error model): no event may fall outside the model.
//!
//! The program exits with status 1 if any of these checks fails.

use lorentz_gas::Error;
use lorentz_gas::engine::options::{AuditSpec, RunOptions};
use lorentz_gas::estimators::diffusion::scene::{SceneDiffusionConfig, run_on};
use lorentz_gas::kernel::cell::{ConvexCell, Disk, Edge, EdgeMap, LatticeBasis};
use lorentz_gas::kernel::flight::Flight;
use lorentz_gas::kernel::vec2::Vec2;
use lorentz_gas::numbers::real::Real;
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::lattice::{CellIndex, LatticeState};
use lorentz_gas::scenes::sampling::direction;
use rand::Rng;
use rug::Rational;
use std::f64::consts::PI;

/// Disks of radius `rc` at the integer points and of radius `rm` at the centres (i + ½, j + ½)
/// of the unit squares. The cell is the unit square [0, 1]² with its four corner disks (labels
/// 0–3: (0, 0), (1, 0), (1, 1), (0, 1)) and its centre disk (label 4). With rc < ½ and
/// rc + rm < √2/2 no disks touch, and no other disk reaches into the cell: the next integer
/// points are at distance ≥ 1 > rc from it, the neighbours' centres at distance ½ > rm.
#[derive(Debug, Clone)]
pub struct TwoRadiusSquare {
    rc: Rational,
    rm: Rational,
}

impl TwoRadiusSquare {
    /// The table with corner radius `rc` and centre radius `rm`, given exactly.
    ///
    /// # Errors
    /// Unless 0 < rm, 0 < rc < ½ and rc + rm < √2/2 (no two disks touch).
    pub fn new(rc: Rational, rm: Rational) -> Result<Self, Error> {
        let sum = rc.clone() + &rm;
        // rc + rm < √2/2  ⇔  2(rc + rm)² < 1 (both sides positive).
        if !(rm > 0 && rc > 0 && rc < Rational::from((1, 2)) && sum.clone() * &sum * 2u32 < 1) {
            return Err(Error::Invalid(
                "use 0 < rc < 1/2, 0 < rm and rc + rm < sqrt(2)/2 (no two disks touch)".into(),
            ));
        }
        Ok(TwoRadiusSquare { rc, rm })
    }

    fn radii64(&self) -> (f64, f64) {
        (
            <f64 as Real>::from_rational((), &self.rc),
            <f64 as Real>::from_rational((), &self.rm),
        )
    }

    /// The free area of a cell, |Q| = 1 − π(rc² + rm²) (four quarter disks make one).
    fn free_area(&self) -> f64 {
        let (rc, rm) = self.radii64();
        1.0 - PI * (rc * rc + rm * rm)
    }
}

impl Scene for TwoRadiusSquare {
    type Kernel<T: Real> = ConvexCell<T>;

    fn label(&self) -> String {
        let (rc, rm) = self.radii64();
        format!("two-radius square rc={rc} rm={rm}")
    }

    fn kernel<T: Real>(&self, ctx: T::Ctx) -> Result<ConvexCell<T>, Error> {
        T::check_ctx(ctx)?;
        let (z, one) = (T::zero(ctx), T::one(ctx));
        let half = T::from_f64(ctx, 0.5);
        let v = |x: &T, y: &T| Vec2::new(x.clone(), y.clone());
        let m1 = -one.clone();
        // Edges 0..3: bottom, right, top, left, as inward normals n and offsets o (n·p ≥ o
        // inside); each maps p ↦ p − t into the neighbour, which it enters by the opposite
        // edge. `after` relabels this cell's disks in the neighbour (the centre never carries).
        let edge = |n: Vec2<T>, o: &T, t: Vec2<T>, entered, after: [Option<u8>; 4], step| Edge {
            normal: n,
            offset: o.clone(),
            map: EdgeMap::Translation(t),
            entered,
            disks_after: after.iter().copied().chain([None]).collect(),
            step,
        };
        let edges = vec![
            edge(
                v(&z, &one),
                &z,
                v(&z, &m1),
                2,
                [Some(3), Some(2), None, None],
                [0, -1],
            ),
            edge(
                v(&m1, &z),
                &m1,
                v(&one, &z),
                3,
                [None, Some(0), Some(3), None],
                [1, 0],
            ),
            edge(
                v(&z, &m1),
                &m1,
                v(&z, &one),
                0,
                [None, None, Some(1), Some(0)],
                [0, 1],
            ),
            edge(
                v(&one, &z),
                &z,
                v(&m1, &z),
                1,
                [Some(1), None, None, Some(2)],
                [-1, 0],
            ),
        ];
        let corners = vec![v(&z, &z), v(&one, &z), v(&one, &one), v(&z, &one)];
        let rc = T::from_rational(ctx, &self.rc);
        let mut disks: Vec<Disk<T>> = corners
            .iter()
            .map(|c| Disk::new(c.clone(), rc.clone()))
            .collect();
        disks.push(Disk::new(v(&half, &half), T::from_rational(ctx, &self.rm)));
        Ok(ConvexCell {
            corners,
            disks,
            edges,
            lattice: LatticeBasis {
                a: one.clone(),
                beta: z,
                h: one,
            },
        })
    }

    /// The cell (⌊x⌋, ⌊y⌋), exactly; the offset (x − ⌊x⌋, y − ⌊y⌋) is exact in rationals and
    /// rounded once at the working precision.
    fn locate<T: Real>(
        &self,
        ctx: T::Ctx,
        x: &Rational,
        y: &Rational,
    ) -> Result<(CellIndex, Vec2<T>), Error> {
        lorentz_gas::scenes::check_world_point(x, y)?;
        let (i, j) = (x.clone().floor(), y.clone().floor());
        let p = Vec2::new(
            T::from_rational(ctx, &(x.clone() - &i)),
            T::from_rational(ctx, &(y.clone() - &j)),
        );
        let index = |q: Rational| q.numer().to_i64().unwrap_or(0);
        Ok((
            CellIndex {
                i: index(i),
                j: index(j),
                down: false,
            },
            p,
        ))
    }

    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> LatticeState<f64> {
        let (rc, rm) = self.radii64();
        let free = |x: f64, y: f64| {
            let corner = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
                .iter()
                .all(|c| (x - c.0).powi(2) + (y - c.1).powi(2) >= rc * rc);
            corner && (x - 0.5).powi(2) + (y - 0.5).powi(2) >= rm * rm
        };
        let pos = loop {
            let (x, y): (f64, f64) = (rng.random(), rng.random());
            if free(x, y) {
                break Vec2::new(x, y);
            }
        };
        LatticeState {
            cell: CellIndex::default(),
            flight: Flight::new(pos, direction(rng)),
        }
    }

    /// Santaló: ⟨ℓ⟩ = π|Q|/|∂Q| with |∂Q| = 2π(rc + rm).
    fn mean_free_path(&self) -> f64 {
        let (rc, rm) = self.radii64();
        PI * self.free_area() / (2.0 * PI * (rc + rm))
    }

    /// Decided exactly. A corridor is a strip free of disks along a rational direction (p, q).
    /// Along the axes the rows of corner disks block |y − k| < rc and the rows of centre disks
    /// |y − k − ½| < rm: closed iff rc + rm ≥ ½. Along (1, 1) both kinds of centres lie on the
    /// lines x − y = k, 1/√2 apart: closed iff 2·max(rc, rm) ≥ 1/√2. Every other primitive
    /// direction has the corner lines at most 1/√5 apart, closed once 2rc ≥ 1/√2.
    fn finite_horizon(&self) -> bool {
        let big = if self.rc > self.rm {
            &self.rc
        } else {
            &self.rm
        };
        let axes = self.rc.clone() + &self.rm >= Rational::from((1, 2));
        let diagonal = big.clone() * big * 8u32 >= 1;
        let others = self.rc.clone() * &self.rc * 8u32 >= 1;
        axes && diagonal && others
    }

    /// τ = π|Q|/L: each edge is free between its two corner disks, L = 4(1 − 2rc).
    fn crossing_time(&self) -> Option<f64> {
        let (rc, _) = self.radii64();
        Some(PI * self.free_area() / (4.0 * (1.0 - 2.0 * rc)))
    }
}

fn main() -> Result<(), Error> {
    let scene = TwoRadiusSquare::new(Rational::from((2, 5)), Rational::from((1, 5)))?;
    let cfg = SceneDiffusionConfig {
        collisions: 32_000_000,
        batches: 16,
        seed: 7,
        ..SceneDiffusionConfig::default()
    };
    let options = RunOptions {
        audit: Some(AuditSpec::new(1e-3, 256)?),
        ..RunOptions::default()
    };
    let r = run_on(&scene, &cfg, &options)?;
    println!("{} (finite horizon: {})", r.scene, scene.finite_horizon());
    println!(
        "D = {:.6} ± {:.6} from {} batches of {} collisions (check window: {:.6} ± {:.6})",
        r.D,
        r.D_err,
        cfg.batches,
        cfg.collisions / cfg.batches as u64,
        r.D_check,
        r.D_check_err
    );
    let mut fails = Vec::new();
    for i in &r.identities {
        println!(
            "{:<24} {:.6} ± {:.6}   exact {:.6}   ({:+.2} sigma; bound ±{:.2})",
            i.name, i.measured, i.err, i.exact, i.t, i.bound
        );
        if !i.agrees {
            fails.push(format!(
                "{} is {:+.2} sigma from its closed form",
                i.name, i.t
            ));
        }
    }
    let audit = r
        .audit
        .as_ref()
        .ok_or_else(|| Error::Failed("no audit".into()))?;
    println!(
        "shadow audit: {} events replayed at 256 bits, {} outside the error model, {} ambiguous",
        audit.audited, audit.outside, audit.ambiguous
    );
    if audit.outside > 0 || audit.audited == 0 {
        fails.push(format!(
            "{} of {} audited events outside the model",
            audit.outside, audit.audited
        ));
    }
    if !(r.D > 0.0 && r.D_err > 0.0 && r.D_err < 0.05 * r.D) {
        fails.push(format!(
            "D = {} ± {} is not a resolved positive value",
            r.D, r.D_err
        ));
    }
    if fails.is_empty() {
        println!("PASS");
        Ok(())
    } else {
        eprintln!("FAIL: {}", fails.join("; "));
        std::process::exit(1);
    }
}
