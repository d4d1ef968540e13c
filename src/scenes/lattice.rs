//! A periodic lattice of cells, walked one cell at a time — for any cell kernel.
//!
//! State: the current cell as exact integers — the index (i, j) and an orientation s = ±1 —
//! plus the flight in the cell's own frame, so that
//!
//! world position = a(i + βj)·x̂ + hj·ŷ + s·p   (e₁ = (a, 0), e₂ = (βa, h)).
//!
//! Crossing edge Eₖ moves the index by s·stepₖ and flips s if the edge map is a point
//! reflection ([`crate::kernel::cell::Edge`]). The offset p stays bounded for ever, so precision
//! does not decay with the distance travelled, and the unwrapped displacement is exact integers
//! plus a bounded offset.
//!
//! The triangular lattice of traps ([`TriangularLattice`]: up traps s = +1 with vertices
//! L(i,j), L(i+1,j), L(i,j+1); down traps s = −1 with vertices L(i,j), L(i−1,j), L(i,j−1))
//! runs on the trap's fused kernel; other scenes on the generic [`ConvexCell`].

use crate::Error;
use crate::kernel::cell::{CellKernel, ConvexCell, Edge};
use crate::kernel::trap::Trap;
use crate::kernel::vec2::Vec2;
use crate::kernel::{flight::Event, flight::EventKind, flight::Flight};
use crate::numbers::real::Real;

/// A cell of the lattice: index and orientation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct CellIndex {
    /// Index along e₁.
    pub i: i64,
    /// Index along e₂.
    pub j: i64,
    /// `true` for s = −1 (a point-reflected cell, the triangular lattice's "down" traps).
    pub down: bool,
}

impl CellIndex {
    /// The orientation s = ±1.
    pub fn sign(&self) -> f64 {
        if self.down { -1.0 } else { 1.0 }
    }
    /// The neighbouring cell across `edge`.
    #[inline(always)]
    pub fn across<T>(&self, edge: &Edge<T>) -> CellIndex {
        let [di, dj] = edge.step;
        let (i, j) = if self.down {
            (self.i - di, self.j - dj)
        } else {
            (self.i + di, self.j + dj)
        };
        CellIndex {
            i,
            j,
            down: self.down ^ edge.flips(),
        }
    }
}

/// A particle in the lattice.
#[derive(Debug, Clone, PartialEq)]
pub struct LatticeState<T> {
    /// The cell it is in.
    pub cell: CellIndex,
    /// Its flight in the cell's frame.
    pub flight: Flight<T>,
}

impl<T: Real> LatticeState<T> {
    /// Lifts an `f64` state exactly to precision `ctx`.
    pub fn convert_from_f64(ctx: T::Ctx, s: &LatticeState<f64>) -> Self {
        LatticeState {
            cell: s.cell,
            flight: Flight::convert_from_f64(ctx, &s.flight),
        }
    }
    /// Nearest `f64` state.
    pub fn to_f64(&self) -> LatticeState<f64> {
        LatticeState {
            cell: self.cell,
            flight: self.flight.to_f64(),
        }
    }

    /// The state exactly, its coordinates as rationals (what a checkpoint keeps: any precision,
    /// no rounding either way).
    pub fn to_exact(&self) -> ExactState {
        let bits = T::bits(self.flight.pos.x.ctx());
        let q = |x: &T| {
            x.to_mpfr(bits)
                .to_rational()
                .map_or_else(|| "nan".to_string(), |r| r.to_string())
        };
        let f = &self.flight;
        ExactState {
            cell: [self.cell.i, self.cell.j],
            down: self.cell.down,
            pos: [q(&f.pos.x), q(&f.pos.y)],
            vel: [q(&f.vel.x), q(&f.vel.y)],
            excluded_disk: f.excluded_disk,
            excluded_edge: f.excluded_edge,
        }
    }

    /// The state [`LatticeState::to_exact`] wrote, at precision `ctx`.
    ///
    /// # Errors
    /// A coordinate that is not a rational, not finite, or not exactly representable at `ctx`'s
    /// precision (a state of another precision); a label above 2; a cell index beyond ±2⁵³.
    pub fn from_exact(ctx: T::Ctx, e: &ExactState) -> Result<Self, Error> {
        let bits = T::bits(ctx);
        let value = |s: &str| -> Result<T, Error> {
            let q: rug::Rational = s.parse().map_err(|_| {
                Error::Invalid(format!("state coordinate {s:?} is not a rational p/q"))
            })?;
            let x = T::from_rational(ctx, &q);
            if x.to_mpfr(bits).to_rational().as_ref() != Some(&q) {
                return Err(Error::Invalid(format!(
                    "state coordinate {s} is not a {bits}-bit number: a state of another precision"
                )));
            }
            Ok(x)
        };
        let label = |l: Option<u8>| l.is_none_or(|m| m <= 2);
        const LIMIT: i64 = 1 << 53;
        if !label(e.excluded_disk)
            || !label(e.excluded_edge)
            || e.cell.iter().any(|c| c.abs() >= LIMIT)
        {
            return Err(Error::Invalid(format!(
                "state labels {:?}/{:?} or cell {:?} out of range (labels 0 to 2, cells within 2^53)",
                e.excluded_disk, e.excluded_edge, e.cell
            )));
        }
        Ok(LatticeState {
            cell: CellIndex {
                i: e.cell[0],
                j: e.cell[1],
                down: e.down,
            },
            flight: Flight {
                pos: Vec2::new(value(&e.pos[0])?, value(&e.pos[1])?),
                vel: Vec2::new(value(&e.vel[0])?, value(&e.vel[1])?),
                excluded_disk: e.excluded_disk,
                excluded_edge: e.excluded_edge,
            },
        })
    }
}

/// A lattice state written exactly: cell, orientation, position and velocity as rationals
/// `p/q` (for an `f64` state, q a power of two), exclusions.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ExactState {
    /// Cell index (i, j).
    pub cell: [i64; 2],
    /// A down (point-reflected) cell.
    pub down: bool,
    /// Position in the cell frame.
    pub pos: [String; 2],
    /// Velocity.
    pub vel: [String; 2],
    /// Excluded disk (0, 1, 2).
    pub excluded_disk: Option<u8>,
    /// Excluded edge (0, 1, 2).
    pub excluded_edge: Option<u8>,
}

/// The lattice basis as `f64` (a, β, h), for observables.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Basis64 {
    /// Length of e₁.
    pub a: f64,
    /// Shear of e₂ (exact).
    pub beta: f64,
    /// Height of e₂.
    pub h: f64,
}

/// An unwrapped world position: exact lattice integers plus a bounded `f64` offset.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Unwrapped {
    /// Lattice index along e₁.
    pub i: i64,
    /// Lattice index along e₂.
    pub j: i64,
    /// Offset s·p from the lattice point (bounded by the cell size).
    pub off: [f64; 2],
}

impl Unwrapped {
    /// Displacement `self − from` in world coordinates, with the integer parts differenced
    /// exactly before conversion.
    #[inline(always)]
    pub fn displacement_from(&self, from: &Unwrapped, b: &Basis64) -> [f64; 2] {
        let di = (self.i - from.i) as f64;
        let dj = (self.j - from.j) as f64;
        [
            b.a * (di + b.beta * dj) + (self.off[0] - from.off[0]),
            b.h * dj + (self.off[1] - from.off[1]),
        ]
    }
    /// World x-coordinate (for stopping rules on x; exact integers converted once).
    #[inline(always)]
    pub fn world_x(&self, b: &Basis64) -> f64 {
        b.a * (self.i as f64 + b.beta * self.j as f64) + self.off[0]
    }
}

/// The periodic lattice of the cells of one kernel.
#[derive(Debug, Clone)]
pub struct Lattice<T: Real, K: CellKernel<T>> {
    /// The cell kernel (generic or a scene's fused fast path).
    pub kernel: K,
    basis: Basis64,
    _t: std::marker::PhantomData<T>,
}

/// The triangular lattice of traps, on the trap's fused kernel.
pub type TriangularLattice<T> = Lattice<T, Trap<T>>;

impl<T: Real> Lattice<T, Trap<T>> {
    /// The triangular lattice at gap `w > 0`.
    pub fn new(w: T) -> Result<Self, Error> {
        Ok(Lattice::from_kernel(Trap::new(w)?))
    }
    /// The canonical trap.
    pub fn trap(&self) -> &Trap<T> {
        &self.kernel
    }
}

impl<T: Real, K: CellKernel<T>> Lattice<T, K> {
    /// The lattice of the cells of `kernel`.
    pub fn from_kernel(kernel: K) -> Self {
        let l = &kernel.cell().lattice;
        let basis = Basis64 {
            a: l.a.to_f64(),
            beta: l.beta.to_f64(),
            h: l.h.to_f64(),
        };
        Lattice {
            kernel,
            basis,
            _t: std::marker::PhantomData,
        }
    }

    /// The cell description.
    pub fn cell(&self) -> &ConvexCell<T> {
        self.kernel.cell()
    }

    /// The lattice basis as `f64` (for observables).
    pub fn basis_f64(&self) -> Basis64 {
        self.basis
    }

    /// The next event of the state's flight.
    #[inline(always)]
    pub fn next_event(&self, s: &LatticeState<T>) -> Option<Event<T>> {
        self.kernel.next_event(&s.flight)
    }

    /// Carries out `ev`, moving to the neighbouring cell on a crossing.
    #[inline(always)]
    pub fn apply(&self, s: &mut LatticeState<T>, ev: &Event<T>) {
        self.kernel.apply(&mut s.flight, ev);
        if let EventKind::Crossing(k) = ev.kind {
            s.cell = s.cell.across(&self.kernel.cell().edges[k as usize]);
        }
    }

    /// One event: find it and carry it out.
    ///
    /// # Errors
    /// If the state has no next event (zero or non-finite velocity).
    #[inline(always)]
    pub fn step(&self, s: &mut LatticeState<T>) -> Result<Event<T>, Error> {
        let ev = self.next_event(s).ok_or_else(|| {
            Error::Failed(format!(
                "state has no next event (velocity {:?})",
                s.flight.vel.to_f64()
            ))
        })?;
        self.apply(s, &ev);
        Ok(ev)
    }

    /// Unwrapped world position of the state, after a further free flight of time `dt`
    /// (`dt = 0` for the current position).
    #[inline(always)]
    pub fn unwrapped(&self, s: &LatticeState<T>, dt: f64) -> Unwrapped {
        let sg = s.cell.sign();
        let p = &s.flight.pos;
        let v = &s.flight.vel;
        Unwrapped {
            i: s.cell.i,
            j: s.cell.j,
            off: [
                sg * (p.x.to_f64() + dt * v.x.to_f64()),
                sg * (p.y.to_f64() + dt * v.y.to_f64()),
            ],
        }
    }

    /// World position at the working precision: a(i + βj)·x̂ + hj·ŷ + s·p.
    pub fn world(&self, s: &LatticeState<T>) -> Vec2<T> {
        let l = &self.kernel.cell().lattice;
        let ctx = l.a.ctx();
        let i = T::from_f64(ctx, s.cell.i as f64);
        let j = T::from_f64(ctx, s.cell.j as f64);
        let lx = l.a.clone() * &(i + &(l.beta.clone() * &j));
        let ly = l.h.clone() * &j;
        if s.cell.down {
            Vec2::new(lx - &s.flight.pos.x, ly - &s.flight.pos.y)
        } else {
            Vec2::new(lx + &s.flight.pos.x, ly + &s.flight.pos.y)
        }
    }
}

/// Most edge crossings [`settle`] makes: a first guess from `f64` is off by at most one cell
/// across an edge or a corner, so a few steps always suffice.
pub const MAX_SETTLE_STEPS: usize = 8;

/// Moves the point `p`, given in the frame of cell `index` (possibly a little outside it), into
/// the cell that contains it, deciding at the working precision: while some edge distance is
/// negative, the point is mapped across the edge with the most negative one (exactly as the
/// kernel maps a crossing). A point on an edge (distance exactly 0) stays where it is.
///
/// # Errors
/// If the point is still outside after [`MAX_SETTLE_STEPS`] crossings (the first guess was not
/// near the point).
pub fn settle<T: Real>(
    cell: &ConvexCell<T>,
    mut index: CellIndex,
    mut p: Vec2<T>,
) -> Result<(CellIndex, Vec2<T>), Error> {
    for _ in 0..=MAX_SETTLE_STEPS {
        let worst = (0..cell.edges.len())
            .map(|k| (k, cell.edge_distance(k, &p)))
            .filter(|(_, d)| d.lt0())
            .min_by(|a, b| a.1.partial_cmp(&b.1).unwrap_or(std::cmp::Ordering::Equal));
        let Some((k, _)) = worst else {
            return Ok((index, p));
        };
        let e = &cell.edges[k];
        p = match &e.map {
            crate::kernel::cell::EdgeMap::Translation(t) => p.sub(t),
            crate::kernel::cell::EdgeMap::PointReflection(c) => c.sub(&p),
        };
        index = index.across(e);
    }
    Err(Error::Failed(format!(
        "could not place the point {:?} in a cell within {MAX_SETTLE_STEPS} crossings",
        p.to_f64()
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn across_is_an_involution_and_matches_the_geometry() {
        let lat = TriangularLattice::new(0.1f64).unwrap();
        let t = lat.trap().clone();
        for down in [false, true] {
            let c = CellIndex { i: 3, j: -2, down };
            for k in 0..3u8 {
                let e = &t.cell().edges[k as usize];
                assert_eq!(c.across(e).across(e), c);
                // The world image of a point on edge k is the same seen from both traps.
                let mid = Vec2::new(t.centres[k as usize].x / 2.0, t.centres[k as usize].y / 2.0);
                let s1 = LatticeState {
                    cell: c,
                    flight: Flight::new(mid.clone(), Vec2::new(1.0, 0.0)),
                };
                let other = t.centres[k as usize].sub(&mid);
                let s2 = LatticeState {
                    cell: c.across(e),
                    flight: Flight::new(other, Vec2::new(1.0, 0.0)),
                };
                let (w1, w2) = (lat.world(&s1), lat.world(&s2));
                assert!((w1.x - w2.x).abs() < 1e-14 && (w1.y - w2.y).abs() < 1e-14);
            }
        }
    }
}
