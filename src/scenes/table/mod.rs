//! Any periodic table of disks, given as data: a lattice by its exact basis vectors and the disks
//! of one cell by their exact centres and radii ([`spec::TableSpec`], a TOML file or a Python
//! dict), validated exactly and run on the generic cell kernel.
//!
//! * The cell is the lattice's parallelogram 0, e₁, e₁ + e₂, e₂ (e₁ = (a, 0), e₂ = (b, h),
//!   h > 0); each edge maps into the neighbour by a lattice translation.
//! * Its candidate disks are every image c + i e₁ + j e₂ of a table disk that reaches the closed
//!   cell, decided exactly (the squared distance from the centre to the parallelogram against r²,
//!   in rationals): no disk outside the list can be met inside the cell.
//! * Refused, exactly and naming the disks: a radius ≤ 0, two disks (or a disk and its own image)
//!   that overlap or touch, a basis that spans no cell or whose e₁ is not along x.
//! * The horizon is decided exactly ([`horizon`]), with the widest corridor when it is infinite.
//!
//! The closed forms: Santaló's ⟨ℓ⟩ = π|Q|/|∂Q| with |Q| = ah − πΣr², |∂Q| = 2πΣr, and the
//! crossing time τ = π|Q|/L, L the free length of the cell's four edges.

mod cell;
pub mod horizon;
pub mod spec;
mod symmetry;
#[cfg(test)]
mod tests;

use rug::Rational;

use crate::Error;
use horizon::{Corridor, Geometry};
use spec::TableSpec;

/// The most disks a table's cell may list.
pub const MAX_DISKS: usize = 32;
/// The most disk images the cell kernel may hold (its labels are bytes).
pub const MAX_IMAGES: usize = 200;
/// The most lattice shifts tried around a disk when validating (a disk whose reach needs more
/// is too large against the cell: it overlaps its own images long before).
pub const MAX_SHIFTS: f64 = 1e6;

/// A periodic table of disks, validated (see the module documentation).
#[derive(Debug, Clone)]
pub struct PeriodicTable {
    spec: TableSpec,
    a: Rational,
    b: Rational,
    h: Rational,
    /// Each table disk: centre reduced into the cell, radius.
    disks: Vec<([Rational; 2], Rational)>,
    /// The candidate disks of the cell: (table disk, centre in the cell's frame).
    images: Vec<(usize, [Rational; 2])>,
    /// The widest corridor, or `None` for a finite horizon.
    corridor: Option<Corridor>,
}

/// What is wrong with a table, as data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TableError {
    /// Text that is not a table: the parser's message, with its line.
    #[error("not a table: {0}")]
    Syntax(String),
    /// e₁ is not (a, 0) with a > 0, or e₂.y ≤ 0.
    #[error(
        "the lattice e1 = ({e1}), e2 = ({e2}) is not a cell of this form: give e1 = (a, 0) with a > 0 along the x axis and e2 = (b, h) with h > 0"
    )]
    Basis {
        /// e₁ as written.
        e1: String,
        /// e₂ as written.
        e2: String,
    },
    /// No disks, or more than [`MAX_DISKS`].
    #[error("a table lists 1 to {MAX_DISKS} disks per cell, not {count}")]
    DiskCount {
        /// How many were given.
        count: usize,
    },
    /// A radius ≤ 0.
    #[error("disk {disk} has radius {radius}: every radius must be > 0")]
    Radius {
        /// The disk (1-based, in the order written).
        disk: usize,
        /// The radius as written.
        radius: String,
    },
    /// Two disks, or a disk and its image, overlap or touch.
    #[error("disk {first} (centre ({first_centre}), radius {first_radius}) and {} overlap or touch: their centres are {distance:.6} apart, no more than the sum of their radii", if first == second { format!("its own image shifted by {shift:?} lattice vectors") } else { format!("disk {second} (centre ({second_centre}), radius {second_radius}){}", if *shift == [0, 0] { String::new() } else { format!(" shifted by {shift:?} lattice vectors") }) })]
    Overlap {
        /// The first disk (1-based).
        first: usize,
        /// Its centre as written.
        first_centre: String,
        /// Its radius as written.
        first_radius: String,
        /// The second disk (1-based; equal to `first` for a disk and its own image).
        second: usize,
        /// Its centre as written.
        second_centre: String,
        /// Its radius as written.
        second_radius: String,
        /// The lattice vector (i, j) between the second disk's image and the second disk.
        shift: [i64; 2],
        /// The distance of the centres (nearest double).
        distance: f64,
    },
    /// Deciding the horizon would check more than [`horizon::MAX_WORK`] directions times disks.
    #[error(
        "the horizon of this table needs about {work:.1e} direction checks (more than {}): its disks are too small against its cell to decide it exactly",
        horizon::MAX_WORK
    )]
    TooFine {
        /// The estimated checks.
        work: f64,
    },
    /// The cell would hold more than [`MAX_IMAGES`] disk images.
    #[error(
        "the cell reaches {images} disk images (at most {MAX_IMAGES}): the disks are too large against the cell"
    )]
    Images {
        /// How many.
        images: usize,
    },
}

impl From<TableError> for Error {
    fn from(e: TableError) -> Error {
        Error::Table(Box::new(e))
    }
}

/// The centre of disk `d` as written, "x, y".
fn written_centre(spec: &TableSpec, d: usize) -> String {
    let c = &spec.disks[d].centre;
    format!("{}, {}", c[0], c[1])
}

impl PeriodicTable {
    /// The table `spec`, validated exactly (see the module documentation).
    ///
    /// # Errors
    /// [`Error::Table`] naming what is wrong; a table too fine to decide its horizon.
    pub fn new(spec: &TableSpec) -> Result<Self, Error> {
        let [ax, ay] = [spec.lattice.e1[0].value(), spec.lattice.e1[1].value()];
        let [b, h] = [spec.lattice.e2[0].value(), spec.lattice.e2[1].value()];
        if ay != 0 || ax <= 0 || h <= 0 {
            let pair = |v: &[spec::Number; 2]| format!("{}, {}", v[0], v[1]);
            return Err(TableError::Basis {
                e1: pair(&spec.lattice.e1),
                e2: pair(&spec.lattice.e2),
            }
            .into());
        }
        if spec.disks.is_empty() || spec.disks.len() > MAX_DISKS {
            return Err(TableError::DiskCount {
                count: spec.disks.len(),
            }
            .into());
        }
        // The same lattice with e₂'s shear reduced into [−a/2, a/2] (b − a·round(b/a)): the
        // cell stays within a bounded number of neighbours of every point, however e₂ was written.
        let b = b.clone() - (b / &ax).round() * &ax;
        let mut table = PeriodicTable {
            spec: spec.clone(),
            a: ax,
            b,
            h,
            disks: Vec::new(),
            images: Vec::new(),
            corridor: None,
        };
        for (k, d) in spec.disks.iter().enumerate() {
            let r = d.radius.value();
            if r <= 0 {
                return Err(TableError::Radius {
                    disk: k + 1,
                    radius: d.radius.to_string(),
                }
                .into());
            }
            let c = table
                .reduce_exact(&d.centre[0].value(), &d.centre[1].value())
                .1;
            table.disks.push((c, r));
        }
        table.refuse_out_of_scale()?;
        table.refuse_overlaps()?;
        table.images = table.find_images();
        if table.images.len() > MAX_IMAGES {
            return Err(TableError::Images {
                images: table.images.len(),
            }
            .into());
        }
        table.corridor = Geometry {
            a: &table.a,
            b: &table.b,
            h: &table.h,
            disks: &table.disks,
        }
        .widest_corridor()?;
        Ok(table)
    }

    /// The table as written.
    pub fn spec(&self) -> &TableSpec {
        &self.spec
    }

    /// The widest corridor of an infinite horizon, or `None` for a finite one.
    pub fn corridor(&self) -> Option<&Corridor> {
        self.corridor.as_ref()
    }

    /// The lattice vector i e₁ + j e₂.
    fn shift(&self, i: i64, j: i64) -> [Rational; 2] {
        [
            Rational::from(i) * &self.a + Rational::from(j) * &self.b,
            Rational::from(j) * &self.h,
        ]
    }

    /// The cell (i, j) holding the world point (x, y), as exact integers, and the point in its
    /// frame, exactly (0 ≤ fractional coordinates < 1): no coordinate is too large for it.
    fn reduce_exact(&self, x: &Rational, y: &Rational) -> ([Rational; 2], [Rational; 2]) {
        // The fractional coordinates: p = u e₁ + v e₂ with v = y/h, u = (x − b v)/a.
        let v = y.clone() / &self.h;
        let i = ((x.clone() - self.b.clone() * &v) / &self.a).floor();
        let j = v.floor();
        let sx = i.clone() * &self.a + j.clone() * &self.b;
        let sy = j.clone() * &self.h;
        ([i, j], [x.clone() - sx, y.clone() - sy])
    }

    /// [`Self::reduce_exact`] with the cell index as `i64`, for points within
    /// ±[`crate::scenes::MAX_WORLD_COORDINATE`] (checked by the caller), and `None` beyond.
    fn reduce(&self, x: &Rational, y: &Rational) -> Option<([i64; 2], [Rational; 2])> {
        let ([i, j], p) = self.reduce_exact(x, y);
        Some(([i.numer().to_i64()?, j.numer().to_i64()?], p))
    }

    /// The cell's corners 0, e₁, e₁ + e₂, e₂ (counter-clockwise).
    fn corners(&self) -> [[Rational; 2]; 4] {
        [
            self.shift(0, 0),
            self.shift(1, 0),
            self.shift(1, 1),
            self.shift(0, 1),
        ]
    }

    /// Refuses disks so large against the cell that the lattice shifts within their reach could
    /// not be enumerated (more than [`MAX_SHIFTS`], or beyond the doubles): before any
    /// enumeration, so that no input makes validation slow.
    fn refuse_out_of_scale(&self) -> Result<(), Error> {
        let rmax = self.disks.iter().map(|d| d.1.to_f64()).fold(0.0, f64::max);
        let (a, h) = (self.a.to_f64(), self.h.to_f64());
        let rows = 2.0 * ((2.0 * rmax / h).ceil() + 1.0) + 1.0;
        let columns = 2.0 * (2.0 * rmax + a + a / 2.0 * (rows + 1.0)) / a + 5.0;
        let shifts = rows * columns;
        if shifts.is_finite() && shifts <= MAX_SHIFTS && a.is_finite() && h > 0.0 {
            return Ok(());
        }
        Err(TableError::Images {
            images: if shifts.is_finite() {
                shifts as usize
            } else {
                usize::MAX
            },
        }
        .into())
    }

    /// Every pair of disks (and every disk with its images) at a distance of at most the sum of
    /// their radii is refused.
    fn refuse_overlaps(&self) -> Result<(), Error> {
        for (p, (cp, rp)) in self.disks.iter().enumerate() {
            for (q, (cq, rq)) in self.disks.iter().enumerate().skip(p) {
                let reach = rp.clone() + rq;
                for [i, j] in self.shifts_within(&reach) {
                    if p == q && (i, j) <= (0, 0) {
                        continue; // a disk with itself, and each ± image pair once
                    }
                    let [sx, sy] = self.shift(i, j);
                    let (dx, dy) = (cq[0].clone() + sx - &cp[0], cq[1].clone() + sy - &cp[1]);
                    let d2 = dx.square() + dy.square();
                    if d2 <= reach.clone().square() {
                        let s = &self.spec;
                        return Err(TableError::Overlap {
                            first: p + 1,
                            first_centre: written_centre(s, p),
                            first_radius: s.disks[p].radius.to_string(),
                            second: q + 1,
                            second_centre: written_centre(s, q),
                            second_radius: s.disks[q].radius.to_string(),
                            shift: [i, j],
                            distance: d2.to_f64().sqrt(),
                        }
                        .into());
                    }
                }
            }
        }
        Ok(())
    }

    /// The lattice shifts (i, j) that can bring two points of the cell within `reach` of each
    /// other (a superset: every shift with |Δ| ≤ reach is among them).
    fn shifts_within(&self, reach: &Rational) -> Vec<[i64; 2]> {
        let (a, b, h, r) = (
            self.a.to_f64(),
            self.b.to_f64(),
            self.h.to_f64(),
            reach.to_f64(),
        );
        let jmax = (r / h).ceil() as i64 + 1;
        let mut out = Vec::new();
        for j in -jmax..=jmax {
            let lo = ((-r - a - b.abs() * (j.abs() + 1) as f64) / a).floor() as i64 - 1;
            let hi = ((r + a + b.abs() * (j.abs() + 1) as f64) / a).ceil() as i64 + 1;
            out.extend((lo..=hi).map(|i| [i, j]));
        }
        out
    }

    /// The squared distance from `p` to the closed cell, exactly.
    fn distance2_to_cell(&self, p: &[Rational; 2]) -> Rational {
        if self.reduce_exact(&p[0], &p[1]).0.iter().all(|k| *k == 0) {
            return Rational::new();
        }
        let corners = self.corners();
        (0..4)
            .map(|k| segment_distance2(p, &corners[k], &corners[(k + 1) % 4]))
            .min()
            .expect("four edges")
    }

    /// Every image of every disk that reaches the closed cell, by disk, then row, then column.
    fn find_images(&self) -> Vec<(usize, [Rational; 2])> {
        let mut out = Vec::new();
        for (k, (c, r)) in self.disks.iter().enumerate() {
            for [i, j] in self.shifts_within(r) {
                let [sx, sy] = self.shift(i, j);
                let p = [c[0].clone() + sx, c[1].clone() + sy];
                if self.distance2_to_cell(&p) <= r.clone().square() {
                    out.push((k, p));
                }
            }
        }
        out
    }
}

/// The squared distance from `p` to the segment [s, e], exactly.
fn segment_distance2(p: &[Rational; 2], s: &[Rational; 2], e: &[Rational; 2]) -> Rational {
    let d = [e[0].clone() - &s[0], e[1].clone() - &s[1]];
    let w = [p[0].clone() - &s[0], p[1].clone() - &s[1]];
    let len2 = d[0].clone().square() + d[1].clone().square();
    let t = (w[0].clone() * &d[0] + w[1].clone() * &d[1]) / len2;
    let t = t.clamp(&Rational::new(), &Rational::from(1));
    let (x, y) = (w[0].clone() - t.clone() * &d[0], w[1].clone() - t * &d[1]);
    x.square() + y.square()
}
