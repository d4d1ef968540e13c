//! A [`PeriodicTable`] as a [`Scene`]: its parallelogram cell for the generic kernel at any
//! precision, where a world point lies, the invariant-measure sampler and the closed forms.

use std::f64::consts::PI;

use rand::Rng;
use rug::Rational;

use super::PeriodicTable;
use crate::Error;
use crate::kernel::cell::{ConvexCell, Disk, Edge, EdgeMap, LatticeBasis};
use crate::kernel::flight::Flight;
use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;
use crate::scenes::lattice::{CellIndex, LatticeState};
use crate::scenes::sampling::direction;
use crate::scenes::{Located, Scene};

/// The four edges: (lattice step (i, j) across it, the edge entered in the neighbour). Edge k
/// runs from corner k to corner k + 1 (bottom, right, top, left).
const EDGES: [([i64; 2], u8); 4] = [([0, -1], 2), ([1, 0], 3), ([0, 1], 0), ([-1, 0], 1)];

impl PeriodicTable {
    /// The label of each image after crossing edge `k` (its centre moved by −step), or `None`.
    fn images_after(&self, step: [i64; 2]) -> Vec<Option<u8>> {
        let [sx, sy] = self.shift(step[0], step[1]);
        self.images
            .iter()
            .map(|(d, c)| {
                let moved = [c[0].clone() - &sx, c[1].clone() - &sy];
                self.images
                    .iter()
                    .position(|(e, p)| e == d && *p == moved)
                    .map(|l| l as u8)
            })
            .collect()
    }

    /// The edges at precision `ctx`: inward unit normals, offsets, translations.
    fn edges<T: Real>(&self, ctx: T::Ctx) -> Vec<Edge<T>> {
        let q = |r: &Rational| T::from_rational(ctx, r);
        let (a, b, h) = (q(&self.a), q(&self.b), q(&self.h));
        let len =
            T::from_rational(ctx, &(self.b.clone().square() + self.h.clone().square())).sqrt();
        let (z, one) = (T::zero(ctx), T::one(ctx));
        // The left edge's inward normal (h, −b)/|e₂|; the right edge's is its opposite, at
        // offset n·e₁ = −ah/|e₂|.
        let left = Vec2::new(h.clone() / &len, -(b.clone() / &len));
        let right = Vec2::new(-left.x.clone(), -left.y.clone());
        let normals = [
            (Vec2::new(z.clone(), one.clone()), z.clone()),
            (right.clone(), right.x.clone() * &a),
            (Vec2::new(z.clone(), -one), -h.clone()),
            (left, z.clone()),
        ];
        EDGES
            .iter()
            .zip(normals)
            .map(|(&(step, entered), (normal, offset))| {
                let [tx, ty] = self.shift(step[0], step[1]);
                Edge {
                    normal,
                    offset,
                    map: EdgeMap::Translation(Vec2::new(q(&tx), q(&ty))),
                    entered,
                    disks_after: self.images_after(step),
                    step,
                }
            })
            .collect()
    }

    fn f64_images(&self) -> impl Iterator<Item = ([f64; 2], f64)> + '_ {
        self.images
            .iter()
            .map(|(d, c)| ([c[0].to_f64(), c[1].to_f64()], self.disks[*d].1.to_f64()))
    }

    /// |Q| = ah − πΣr² and |∂Q| = 2πΣr, as doubles.
    fn free_area_and_boundary(&self) -> (f64, f64) {
        let area = (self.a.clone() * &self.h).to_f64();
        let (r2, r1) = self.disks.iter().fold((0.0, 0.0), |(s2, s1), (_, r)| {
            let r = r.to_f64();
            (s2 + r * r, s1 + r)
        });
        (area - PI * r2, 2.0 * PI * r1)
    }

    /// L: the length of the cell's four edges outside every disk.
    fn free_edge_length(&self) -> f64 {
        let corners = self.corners().map(|c| [c[0].to_f64(), c[1].to_f64()]);
        (0..4)
            .map(|k| {
                let (s, e) = (corners[k], corners[(k + 1) % 4]);
                let d = [e[0] - s[0], e[1] - s[1]];
                let len = d[0].hypot(d[1]);
                let mut covered: Vec<(f64, f64)> = self
                    .f64_images()
                    .filter_map(|(c, r)| chord(s, d, len, c, r))
                    .collect();
                covered.sort_by(|x, y| x.0.total_cmp(&y.0));
                let (mut free, mut reach) = (0.0, 0.0f64);
                for (lo, hi) in covered {
                    free += (lo - reach).max(0.0);
                    reach = reach.max(hi);
                }
                free + (len - reach).max(0.0)
            })
            .sum()
    }
}

/// The part [lo, hi] ⊂ [0, len] of the segment s + t·d/len (t in length units) inside the disk
/// (c, r), if any.
fn chord(s: [f64; 2], d: [f64; 2], len: f64, c: [f64; 2], r: f64) -> Option<(f64, f64)> {
    let u = [d[0] / len, d[1] / len];
    let w = [c[0] - s[0], c[1] - s[1]];
    let along = w[0] * u[0] + w[1] * u[1];
    let across = w[0] * u[1] - w[1] * u[0];
    let half2 = r * r - across * across;
    if half2 <= 0.0 {
        return None;
    }
    let half = half2.sqrt();
    let (lo, hi) = ((along - half).max(0.0), (along + half).min(len));
    (lo < hi).then_some((lo, hi))
}

impl Scene for PeriodicTable {
    type Kernel<T: Real> = ConvexCell<T>;

    /// The table's name and its data as written (a checkpoint of another table is refused).
    fn label(&self) -> String {
        let s = &self.spec;
        let disks: Vec<String> = s
            .disks
            .iter()
            .map(|d| format!("r {} at ({}, {})", d.radius, d.centre[0], d.centre[1]))
            .collect();
        format!(
            "{} (e1 = ({}, {}), e2 = ({}, {}); {})",
            s.title(),
            s.lattice.e1[0],
            s.lattice.e1[1],
            s.lattice.e2[0],
            s.lattice.e2[1],
            disks.join(", ")
        )
    }

    fn kernel<T: Real>(&self, ctx: T::Ctx) -> Result<ConvexCell<T>, Error> {
        T::check_ctx(ctx)?;
        let q = |r: &Rational| T::from_rational(ctx, r);
        let corners = self
            .corners()
            .iter()
            .map(|c| Vec2::new(q(&c[0]), q(&c[1])))
            .collect();
        let disks = self
            .images
            .iter()
            .map(|(d, c)| Disk::new(Vec2::new(q(&c[0]), q(&c[1])), q(&self.disks[*d].1)))
            .collect();
        Ok(ConvexCell {
            corners,
            disks,
            edges: self.edges(ctx),
            lattice: LatticeBasis {
                a: q(&self.a),
                beta: q(&(self.b.clone() / &self.a)),
                h: q(&self.h),
            },
        })
    }

    /// The cell and the offset exactly in rationals, the offset rounded once at `ctx`.
    fn locate<T: Real>(&self, ctx: T::Ctx, x: &Rational, y: &Rational) -> Located<T> {
        T::check_ctx(ctx)?;
        crate::scenes::check_world_point(x, y)?;
        let ([i, j], p) = self
            .reduce(x, y)
            .ok_or_else(|| Error::Failed("a checked world point outside the i64 cells".into()))?;
        let at = |r: &Rational| T::from_rational(ctx, r);
        Ok((
            CellIndex { i, j, down: false },
            Vec2::new(at(&p[0]), at(&p[1])),
        ))
    }

    /// Uniform in the parallelogram, outside every disk (rejection), uniform direction.
    fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> LatticeState<f64> {
        let (a, b, h) = (self.a.to_f64(), self.b.to_f64(), self.h.to_f64());
        let images: Vec<([f64; 2], f64)> = self.f64_images().collect();
        let pos = loop {
            let (u, v): (f64, f64) = (rng.random(), rng.random());
            let (x, y) = (u * a + v * b, v * h);
            let free = images
                .iter()
                .all(|(c, r)| (x - c[0]).powi(2) + (y - c[1]).powi(2) >= r * r);
            if free {
                break Vec2::new(x, y);
            }
        };
        LatticeState {
            cell: CellIndex::default(),
            flight: Flight::new(pos, direction(rng)),
        }
    }

    fn mean_free_path(&self) -> f64 {
        let (area, boundary) = self.free_area_and_boundary();
        PI * area / boundary
    }

    fn finite_horizon(&self) -> bool {
        self.corridor.is_none()
    }

    fn crossing_time(&self) -> Option<f64> {
        let length = self.free_edge_length();
        (length > 0.0).then(|| PI * self.free_area_and_boundary().0 / length)
    }

    /// The disks of the cell at their (reduced) centres: the field's exact geometry of pinned
    /// and skipping orbits.
    fn disk_lattice(&self) -> Option<crate::scenes::magnetic::DiskLattice> {
        use crate::scenes::magnetic::{DiskLattice, ExactDisks, LatticeDisk};
        let exact = ExactDisks {
            a: self.a.clone(),
            b: self.b.clone(),
            h2: Rational::from(&self.h * &self.h),
            h: Some(self.h.clone()),
            disks: self.disks.clone(),
        };
        Some(DiskLattice {
            a: self.a.to_f64(),
            beta: (self.b.clone() / &self.a).to_f64(),
            h: self.h.to_f64(),
            disks: self
                .disks
                .iter()
                .map(|(c, r)| LatticeDisk {
                    centre: [c[0].to_f64(), c[1].to_f64()],
                    radius: r.to_f64(),
                })
                .collect(),
            exact: Some(exact),
        })
    }

    fn isotropic(&self) -> bool {
        self.quarter_turn_symmetric()
    }

    fn table_spec(&self) -> Option<&super::spec::TableSpec> {
        Some(&self.spec)
    }

    fn widest_corridor(&self) -> Option<super::horizon::Corridor> {
        self.corridor.clone()
    }
}
