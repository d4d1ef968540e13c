//! The generic cell kernel: free flight in a convex polygonal cell with disk obstacles.
//!
//! A scene describes its fundamental cell as a [`ConvexCell`]: a convex polygon (its edges as
//! inward unit normals nₖ and offsets oₖ, the signed distance to Eₖ being σₖ(p) = nₖ·p − oₖ),
//! the disks that can be met inside it (each a [`Disk`]: an exact centre and its own radius), and for every
//! edge the exact map into the neighbouring cell's frame ([`EdgeMap`]: a translation or a point
//! reflection), the labels the current exclusions take over there, and the integer step of the
//! cell index for unwrapping. The kernel then needs nothing else:
//!
//! * the next event is the earliest of the disk contacts (cancellation-free root,
//!   [`super::ray_disk::ray_circle_centred`]) and the crossings of the edges the velocity points
//!   out of (σₖ/(−nₖ·v), or 0 if the start is numerically beyond the edge), the disk left and
//!   the edge entered by being excluded **by identity**; ties go to the lower disk label, then
//!   collisions before crossings, then the lower edge label;
//! * a collision is the specular reflection v' = v − 2(v·n)n/r², n = x − c (r the radius of the
//!   disk met), times the Newton
//!   factor (3 − |v|²)/2 (`proofs-notes/energy.md`); a crossing maps position and velocity
//!   into the neighbour's frame exactly as the edge says.
//!
//! Correctness of a cell (no obstacle outside the candidate list can be met inside the cell)
//! is the scene's obligation, argued for each cell in `proofs-notes/no-missed-collision.md`.
//! A scene may supply a fused fast path for its cell ([`CellKernel`]); it must agree with this
//! generic kernel bit for bit (the triangular trap's does: `tests/numerics/scenes.rs`).

use super::flight::{Event, EventKind, Flight};
use super::ray_disk::ray_circle_centred;
use super::vec2::Vec2;
use crate::numbers::real::Real;

/// How a point leaving the cell through an edge is expressed in the neighbouring cell's frame.
#[derive(Debug, Clone, PartialEq)]
pub enum EdgeMap<T> {
    /// p ↦ p − t, v ↦ v: the neighbour is this cell translated by t (square lattice).
    Translation(Vec2<T>),
    /// p ↦ c − p, v ↦ −v: the neighbour is this cell point-reflected about c/2 (the
    /// triangular lattice's up and down traps). Flips the cell's orientation.
    PointReflection(Vec2<T>),
}

/// One edge of a cell.
#[derive(Debug, Clone, PartialEq)]
pub struct Edge<T> {
    /// Inward unit normal nₖ.
    pub normal: Vec2<T>,
    /// Offset oₖ: σₖ(p) = nₖ·p − oₖ ≥ 0 inside.
    pub offset: T,
    /// The map into the neighbour's frame.
    pub map: EdgeMap<T>,
    /// The label of this same edge seen from the neighbour (the edge the particle enters by).
    pub entered: u8,
    /// For each disk label of this cell, its label in the neighbour (`None`: not a disk of the
    /// neighbour's candidate list).
    pub disks_after: Vec<Option<u8>>,
    /// Integer step of the cell index across this edge, in the lattice basis, for a cell of
    /// positive orientation (a negatively oriented cell steps by the opposite vector).
    pub step: [i64; 2],
}

impl<T> Edge<T> {
    /// `true` if crossing this edge flips the orientation of the cell (a point reflection).
    pub fn flips(&self) -> bool {
        matches!(self.map, EdgeMap::PointReflection(_))
    }
}

/// The lattice of cells: e₁ = (a, 0), e₂ = (βa, h), with β exact (½ for the triangular lattice,
/// 0 for the square one). A cell with index (i, j) and orientation s = ±1 maps its frame point
/// p to the world point a(i + βj)·x̂ + hj·ŷ + s·p.
#[derive(Debug, Clone, PartialEq)]
pub struct LatticeBasis<T> {
    /// Length of e₁.
    pub a: T,
    /// The shear β of e₂ (exactly representable).
    pub beta: T,
    /// Height of e₂.
    pub h: T,
}

/// A disk obstacle: its centre in the cell's frame and its radius, with r² kept beside it (the
/// only way to build one is [`Disk::new`], so r² is always the rounded square of r).
#[derive(Debug, Clone, PartialEq)]
pub struct Disk<T> {
    /// Centre, in the cell's frame.
    pub centre: Vec2<T>,
    radius: T,
    radius2: T,
}

impl<T: Real> Disk<T> {
    /// The disk of radius `radius` (> 0, at the working precision) centred at `centre`.
    pub fn new(centre: Vec2<T>, radius: T) -> Self {
        let radius2 = radius.square();
        Disk {
            centre,
            radius,
            radius2,
        }
    }

    /// The radius r.
    #[inline]
    pub fn radius(&self) -> &T {
        &self.radius
    }

    /// r², rounded once at the working precision.
    #[inline]
    pub fn radius2(&self) -> &T {
        &self.radius2
    }

    /// The specular reflection of `v` at the contact point `x`: v − 2(v·n)n/r², n = x − c.
    #[inline]
    pub fn reflect(&self, v: &mut Vec2<T>, x: &Vec2<T>) {
        let n = x.sub(&self.centre);
        let s = v.dot(&n).scale(2.0) / &self.radius2;
        v.x -= &(n.x.clone() * &s);
        v.y -= &(n.y * &s);
    }
}

impl<T: Real> EdgeMap<T> {
    /// The point `x` of this cell in the neighbour's frame, and `v` turned with it.
    #[inline]
    pub fn carry(&self, x: &Vec2<T>, v: &mut Vec2<T>) -> Vec2<T> {
        match self {
            EdgeMap::Translation(t) => x.sub(t),
            EdgeMap::PointReflection(c) => {
                v.x.neg_mut();
                v.y.neg_mut();
                c.sub(x)
            }
        }
    }
}

/// A convex polygonal cell with disk obstacles, each of its own radius: everything the generic
/// kernel knows about a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvexCell<T> {
    /// Polygon corners, counter-clockwise (for sampling and plots; the kernel uses the edges).
    pub corners: Vec<Vec2<T>>,
    /// The disks that can be met inside the cell.
    pub disks: Vec<Disk<T>>,
    /// The edges.
    pub edges: Vec<Edge<T>>,
    /// The lattice of cells.
    pub lattice: LatticeBasis<T>,
}

impl<T: Real> ConvexCell<T> {
    /// The same cell with every value mapped by `f` — a copy at another precision (the nearest
    /// `f64`s, or `f64` values lifted exactly to MPFR); each disk's r² is rounded again at the new
    /// precision ([`Disk::new`]).
    pub fn map_values<U: Real>(&self, f: impl Fn(&T) -> U) -> ConvexCell<U> {
        let v = |p: &Vec2<T>| Vec2::new(f(&p.x), f(&p.y));
        ConvexCell {
            corners: self.corners.iter().map(v).collect(),
            disks: self
                .disks
                .iter()
                .map(|d| Disk::new(v(&d.centre), f(&d.radius)))
                .collect(),
            edges: self
                .edges
                .iter()
                .map(|e| Edge {
                    normal: v(&e.normal),
                    offset: f(&e.offset),
                    map: match &e.map {
                        EdgeMap::Translation(t) => EdgeMap::Translation(v(t)),
                        EdgeMap::PointReflection(p) => EdgeMap::PointReflection(v(p)),
                    },
                    entered: e.entered,
                    disks_after: e.disks_after.clone(),
                    step: e.step,
                })
                .collect(),
            lattice: LatticeBasis {
                a: f(&self.lattice.a),
                beta: f(&self.lattice.beta),
                h: f(&self.lattice.h),
            },
        }
    }

    /// Largest |coordinate| of the corners and disk centres: the scale of the absolute rounding
    /// errors of the cell's constants, used by the shadow error model.
    pub fn extent(&self) -> f64 {
        self.corners
            .iter()
            .chain(self.disks.iter().map(|d| &d.centre))
            .flat_map(|p| [p.x.to_f64().abs(), p.y.to_f64().abs()])
            .fold(0.0, f64::max)
    }

    /// The smallest disk radius (as the nearest double; infinite for a cell without disks): the
    /// scale of the relative errors at a contact point.
    pub fn smallest_radius(&self) -> f64 {
        self.disks
            .iter()
            .map(|d| d.radius.to_f64())
            .fold(f64::INFINITY, f64::min)
    }

    /// Signed distance from `p` to edge `k` (positive inside the cell).
    #[inline]
    pub fn edge_distance(&self, k: usize, p: &Vec2<T>) -> T {
        let e = &self.edges[k];
        e.normal.dot(p) - &e.offset
    }

    /// `true` if `p` is in the closed cell and outside the open disks, decided at the working
    /// precision.
    pub fn is_free(&self, p: &Vec2<T>) -> bool {
        (0..self.edges.len()).all(|k| !self.edge_distance(k, p).lt0())
            && self
                .disks
                .iter()
                .all(|d| !(p.sub(&d.centre).norm2() - &d.radius2).lt0())
    }

    /// The next event of the straight flight `f`, or `None` if there is none (only for a zero
    /// or non-finite velocity: a finite nonzero velocity always leaves a bounded cell).
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::kernel::{trap::Trap, flight::EventKind, flight::Flight, vec2::Vec2};
    /// let cell = Trap::new(0.1f64).unwrap().cell().clone();
    /// // From the middle of the base gap straight up: head-on with the apex disk P₂.
    /// let f = Flight::new(Vec2::new(1.05, 0.0), Vec2::new(0.0, 1.0));
    /// assert_eq!(cell.next_event(&f).unwrap().kind, EventKind::Collision(2));
    /// ```
    pub fn next_event(&self, f: &Flight<T>) -> Option<Event<T>> {
        let (p, v) = (&f.pos, &f.vel);
        let vv = v.norm2();
        let mut best: Option<Event<T>> = None;
        let mut offer = |t: T, kind: EventKind| {
            if best.as_ref().is_none_or(|b| t < b.time) {
                best = Some(Event { kind, time: t });
            }
        };
        for (m, d) in self.disks.iter().enumerate() {
            let m = m as u8;
            if f.excluded_disk != Some(m) {
                let c = &d.centre;
                let (dx, dy) = (p.x.clone() - &c.x, p.y.clone() - &c.y);
                if let Some(t) = ray_circle_centred(dx, dy, v, &vv, &d.radius2) {
                    offer(t, EventKind::Collision(m));
                }
            }
        }
        for (k, e) in self.edges.iter().enumerate() {
            let k = k as u8;
            if f.excluded_edge == Some(k) {
                continue;
            }
            let nv = e.normal.dot(v);
            if nv.lt0() {
                let sigma = e.normal.dot(p) - &e.offset;
                let t = if sigma.gt0() {
                    sigma / &(-nv)
                } else {
                    T::zero(nv.ctx())
                };
                offer(t, EventKind::Crossing(k));
            }
        }
        best
    }

    /// Moves along the flight to the event and carries it out (see the module documentation).
    pub fn apply(&self, f: &mut Flight<T>, ev: &Event<T>) {
        let x = f.pos.along(&ev.time, &f.vel);
        match ev.kind {
            EventKind::Collision(m) => {
                let k = (-f.vel.norm2()).add_f64(3.0).scale(0.5);
                self.disks[m as usize].reflect(&mut f.vel, &x);
                f.vel.x *= &k;
                f.vel.y *= &k;
                f.pos = x;
                f.excluded_disk = Some(m);
                f.excluded_edge = None;
            }
            EventKind::Crossing(k) => {
                let e = &self.edges[k as usize];
                f.pos = e.map.carry(&x, &mut f.vel);
                f.excluded_disk = f.excluded_disk.and_then(|m| e.disks_after[m as usize]);
                f.excluded_edge = Some(e.entered);
            }
        }
    }
}

/// A cell with its kernel: the generic one, or a scene's fused fast path that reproduces the
/// generic kernel bit for bit.
pub trait CellKernel<T: Real>: Clone + std::fmt::Debug + Send + Sync {
    /// The cell's description (what the verification layer works from).
    fn cell(&self) -> &ConvexCell<T>;
    /// The next event of `f` (see [`ConvexCell::next_event`]).
    #[inline(always)]
    fn next_event(&self, f: &Flight<T>) -> Option<Event<T>> {
        self.cell().next_event(f)
    }
    /// Carries out `ev` (see [`ConvexCell::apply`]).
    #[inline(always)]
    fn apply(&self, f: &mut Flight<T>, ev: &Event<T>) {
        self.cell().apply(f, ev)
    }
}

impl<T: Real> CellKernel<T> for ConvexCell<T> {
    fn cell(&self) -> &ConvexCell<T> {
        self
    }
}
