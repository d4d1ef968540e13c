//! Certified periodic orbits of open tables (finitely many disks, no lattice) and their cycle
//! expansions (`proofs-notes/cycles.md`).
//!
//! A cycle is named by its disk sequence d₀ … d_{n−1} (no two equal in a row, cyclically). Its
//! collision points x_k = (s_k, p_k) in Birkhoff coordinates solve the closed system
//!
//! F_k(y) = T_k(x_k) − x_{k+1 mod n} = 0,  k = 0 … n − 1,
//!
//! T_k the billiard map from disk d_k to disk d_{k+1} of [`crate::verification::shadowing`]
//! (the shadows' exact map and its analytic Jacobian A_k, shared, not copied). Newton's method
//! runs in MPFR; the Newton–Kantorovich certificate bounds ‖DF⁻¹‖ by a computed inverse and its
//! residual, the defect ε at twice the precision, and proves a unique zero within 2Kε. The
//! kernel's ray–disk contact ([`crate::kernel::ray_disk`]) then decides that each flight meets
//! its disk first and passes through no other (pruning decided, not assumed). The period T_p
//! and the expanding eigenvalue Λ_p of the monodromy ∏A_k carry bounds from the radius.

pub mod expansion;
pub mod lattice;
mod minimise;
mod newton;
mod prune;
pub mod repeller;
pub mod symbols;

use rug::{Float, Rational};
use serde::{Deserialize, Serialize};

use crate::Error;
use crate::kernel::vec2::Vec2;
use crate::numbers::exact::nearest_f64;
use crate::verification::shadowing::{M2, OrbitPoint, Table};

pub(crate) use newton::certify_closed;
pub use newton::certify_cycle;

/// Smallest working precision of a certified cycle.
pub const MIN_CYCLE_BITS: u32 = 128;
/// Largest working precision of a certified cycle.
pub const MAX_CYCLE_BITS: u32 = 4096;
/// Longest cycle (collisions) certified.
pub const MAX_CYCLE_LENGTH: usize = 512;

/// The disks of an open table: one radius, finitely many centres, no lattice.
#[derive(Debug, Clone, PartialEq)]
pub enum Disks {
    /// The three-disk repeller: disks of radius `radius` at the corners (0, 0), (R, 0),
    /// (R/2, R√3/2) of the equilateral triangle of side `side` = R (R > 2a), both exact
    /// (rounded once at the working precision).
    ThreeDisk {
        /// The side R of the triangle (distance between centres).
        side: Rational,
        /// The disk radius a.
        radius: Rational,
    },
    /// Disks of radius `radius` centred at `centres` (exact binary values), disjoint.
    Explicit {
        /// The centres.
        centres: Vec<[f64; 2]>,
        /// The disk radius.
        radius: f64,
    },
}

impl Disks {
    /// The three-disk repeller with centre distance `side` = R and disk radius `radius` = a,
    /// exact (`Disks::three_disk(6, 1)`, or rationals parsed from what a user typed).
    pub fn three_disk(side: impl Into<Rational>, radius: impl Into<Rational>) -> Self {
        Disks::ThreeDisk {
            side: side.into(),
            radius: radius.into(),
        }
    }

    /// Number of disks.
    pub fn count(&self) -> usize {
        match self {
            Disks::ThreeDisk { .. } => 3,
            Disks::Explicit { centres, .. } => centres.len(),
        }
    }

    /// The disk radius as its nearest double (for starting guesses and error bounds).
    pub fn radius(&self) -> f64 {
        match self {
            Disks::ThreeDisk { radius, .. } => nearest_f64(radius),
            Disks::Explicit { radius, .. } => *radius,
        }
    }

    /// The disk radius at `bits` of precision (an exact radius rounded once).
    pub fn radius_at(&self, bits: u32) -> Float {
        match self {
            Disks::ThreeDisk { radius, .. } => Float::with_val(bits, radius),
            Disks::Explicit { radius, .. } => Float::with_val(bits, radius),
        }
    }

    /// Checks the geometry: finite positive radius, at least two disks, no two touching (the
    /// three-disk repeller decided exactly: a > 0 and R > 2a).
    ///
    /// # Errors
    /// A bad radius or side, fewer than two disks, or overlapping disks.
    pub fn validate(&self) -> Result<(), Error> {
        if let Disks::ThreeDisk { side, radius } = self {
            if *radius <= 0 {
                return Err(Error::out_of_range(
                    "radius",
                    nearest_f64(radius),
                    "use a finite radius a > 0",
                ));
            }
            if *side <= Rational::from(radius * 2u32) {
                return Err(Error::out_of_range(
                    "side",
                    nearest_f64(side),
                    format!(
                        "use a finite side R > 2a = {} (disjoint disks)",
                        nearest_f64(&Rational::from(radius * 2u32))
                    ),
                ));
            }
            return Ok(());
        }
        let r = self.radius();
        if !(r.is_finite() && r > 0.0) {
            return Err(Error::out_of_range("radius", r, "use a finite radius > 0"));
        }
        let c = self.centres_f64();
        if c.len() < 2 {
            return Err(Error::TooFew {
                what: "disks",
                min: 2,
                got: c.len() as u64,
            });
        }
        for (i, a) in c.iter().enumerate() {
            if !(a[0].is_finite() && a[1].is_finite()) {
                return Err(Error::NotFinite { what: "centres" });
            }
            for b in &c[..i] {
                if (a[0] - b[0]).hypot(a[1] - b[1]) <= 2.0 * r {
                    return Err(Error::out_of_range(
                        "radius",
                        r,
                        "use a radius below half the smallest distance between centres (disjoint disks)",
                    ));
                }
            }
        }
        Ok(())
    }

    /// The centres in `f64` (rounded for the three-disk corners).
    pub fn centres_f64(&self) -> Vec<[f64; 2]> {
        match self {
            Disks::ThreeDisk { side, .. } => {
                let side = nearest_f64(side);
                vec![
                    [0.0, 0.0],
                    [side, 0.0],
                    [0.5 * side, 0.5 * side * 3f64.sqrt()],
                ]
            }
            Disks::Explicit { centres, .. } => centres.clone(),
        }
    }

    /// The centres at `bits` of precision (R rounded once, √3 rounded once at `bits`).
    pub fn centres(&self, bits: u32) -> Vec<Vec2<Float>> {
        match self {
            Disks::ThreeDisk { side, .. } => {
                let r = Float::with_val(bits, side);
                let h = Float::with_val(bits, 3).sqrt() * &r / 2u32;
                vec![
                    Vec2::new(Float::new(bits), Float::new(bits)),
                    Vec2::new(r.clone(), Float::new(bits)),
                    Vec2::new(r / 2u32, h),
                ]
            }
            Disks::Explicit { centres, .. } => centres
                .iter()
                .map(|c| Vec2::from_f64(bits, c[0], c[1]))
                .collect(),
        }
    }
}

/// A table whose periodic orbits [`certify_cycle`]'s Newton method certifies: an open table
/// ([`Disks`]) or a lattice ([`lattice::LatticeDisks`]). Disks are labelled as in
/// [`OrbitPoint::disk`].
pub(crate) trait CycleTable: Sync {
    /// The table at `bits`: the shadows' exact billiard map on these disks.
    fn table(&self, bits: u32) -> Result<Table, Error>;
    /// The disk radius as its nearest double.
    fn radius_f64(&self) -> f64;
    /// Every disk (the departure's included) that a flight of length at most `reach` from a
    /// point of disk `from` can come within one radius of.
    fn near(&self, from: [i64; 2], reach: f64) -> Vec<[i64; 2]>;
    /// The disk's name in messages.
    fn label(&self, d: [i64; 2]) -> String;
}

impl CycleTable for Disks {
    fn table(&self, bits: u32) -> Result<Table, Error> {
        Ok(Table::open(self.centres(bits), self.radius_at(bits), bits))
    }
    fn radius_f64(&self) -> f64 {
        self.radius()
    }
    fn near(&self, _from: [i64; 2], _reach: f64) -> Vec<[i64; 2]> {
        (0..self.count() as i64).map(|k| [k, 0]).collect()
    }
    fn label(&self, d: [i64; 2]) -> String {
        d[0].to_string()
    }
}

/// A periodic orbit found, with its certificate (or the reason there is none).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Cycle {
    /// The disk sequence d₀ … d_{n−1} (an open table's; empty, and absent from the JSON, for a
    /// lattice cycle, which its word names).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub disks: Vec<usize>,
    /// Working precision (bits).
    pub precision_bits: u32,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Period T_p (time at unit speed: the length of the orbit).
    pub period: f64,
    /// |T_p − period| ≤ this for the true orbit (2n·a·radius plus rounding).
    pub period_bound: f64,
    /// Λ_p: the expanding eigenvalue of the monodromy matrix ∏A_k (signed).
    pub stability: f64,
    /// |Λ_p − stability| ≤ this (first order in the radius, with the estimated ‖D²T‖, plus
    /// rounding).
    pub stability_bound: f64,
    /// ε = ‖F(y*)‖₂ at twice the precision plus the rounding allowance.
    pub residual: f64,
    /// K ≥ ‖DF(y*)⁻¹‖₂ (computed inverse X, ‖X‖_F/(1 − ‖I − X·DF‖_F)).
    pub inverse_bound: f64,
    /// 2Kε: the true cycle lies within this of y* (ℓ² norm on (s, p)ⁿ).
    pub radius: f64,
    /// 1/(K·M): no other cycle with this disk sequence within this of y*.
    pub uniqueness_radius: f64,
    /// M = 100 × the secant estimate of ‖D²T‖ (an estimate with a safety factor, not a bound).
    pub lipschitz: f64,
    /// Smallest cos φ of the collisions.
    pub min_cos_phi: f64,
    /// Smallest distance − a of a flight from a disk other than its two ends (∞, `null` in
    /// JSON, on a table of two disks).
    #[serde(deserialize_with = "crate::estimators::field::infinite_if_null")]
    pub min_clearance: f64,
    /// Existence and uniqueness proved (2MK²ε ≤ 1), the ball clear of grazing and of other
    /// disks, and the kernel's contact check passed.
    pub certified: bool,
    /// `Some`: the kernel refused the orbit (a flight meets another disk first), and why.
    pub pruned: Option<String>,
    /// `None`, or why the cycle is not certified.
    pub failure: Option<String>,
    /// The orbit (P bits).
    #[serde(skip)]
    pub orbit: Vec<OrbitPoint>,
    /// The Jacobians A_k of the map along the orbit.
    #[serde(skip)]
    pub jacobians: Vec<M2>,
    /// The period at the working precision.
    #[serde(skip)]
    pub period_exact: Option<Float>,
}

impl Cycle {
    /// The expanding eigenvalue of the product A_{m−1}⋯A₀ of the first `m` Jacobians (signed),
    /// at the working precision.
    pub fn partial_stability(&self, m: usize) -> Float {
        let bits = self.precision_bits;
        let mut p: M2 = std::array::from_fn(|i| Float::with_val(bits, u32::from(i % 3 == 0)));
        for a in &self.jacobians[..m] {
            p = crate::verification::shadowing::m_mul(a, &p);
        }
        expanding_eigenvalue(&p)
    }
}

/// The eigenvalue of larger modulus of a real 2×2 matrix with real eigenvalues (signed);
/// NaN if they are complex.
pub fn expanding_eigenvalue(m: &M2) -> Float {
    let t = m[0].clone() + &m[3];
    let d = m[0].clone() * &m[3] - &(m[1].clone() * &m[2]);
    let disc = (t.clone().square() - &(d * 4u32)).sqrt();
    if t.is_sign_negative() {
        (t - disc) / 2u32
    } else {
        (t + disc) / 2u32
    }
}

/// The starting guess of the cycle through `disks`: each contact point on the bisector of the
/// directions to the previous and the next disk, each velocity towards the next contact point.
fn initial_guess(disks: &Disks, seq: &[usize], bits: u32) -> Vec<OrbitPoint> {
    let c = disks.centres_f64();
    let centres: Vec<[f64; 2]> = seq.iter().map(|&d| c[d]).collect();
    let labels: Vec<[i64; 2]> = seq.iter().map(|&d| [d as i64, 0]).collect();
    let s = bisector_angles(&centres, [0.0, 0.0]);
    orbit_from_angles(&centres, [0.0, 0.0], disks.radius(), &s, &labels, bits)
}

/// The closed itinerary's neighbours of collision k: the centres `c[k − 1]` and `c[k + 1]`, the
/// last followed by `c[0] + shift` and the first preceded by `c[n − 1] − shift` (`shift` the
/// winding of a lattice cycle, zero on an open table).
pub(crate) fn neighbours(c: &[[f64; 2]], shift: [f64; 2], k: usize) -> ([f64; 2], [f64; 2]) {
    let n = c.len();
    let prev = if k == 0 {
        [c[n - 1][0] - shift[0], c[n - 1][1] - shift[1]]
    } else {
        c[k - 1]
    };
    let next = if k + 1 == n {
        [c[0][0] + shift[0], c[0][1] + shift[1]]
    } else {
        c[k + 1]
    };
    (prev, next)
}

/// Each contact angle on the bisector of the directions to the previous and the next centre.
pub(crate) fn bisector_angles(c: &[[f64; 2]], shift: [f64; 2]) -> Vec<f64> {
    let unit = |a: [f64; 2], b: [f64; 2]| {
        let (x, y) = (b[0] - a[0], b[1] - a[1]);
        let l = x.hypot(y);
        [x / l, y / l]
    };
    (0..c.len())
        .map(|k| {
            let (prev, next) = neighbours(c, shift, k);
            let (u, w) = (unit(c[k], prev), unit(c[k], next));
            (u[1] + w[1]).atan2(u[0] + w[0])
        })
        .collect()
}

/// The collision states with contact angles `s` on the disks of centres `c` (radius `r`, labels
/// `labels`), each velocity towards the next contact point.
pub(crate) fn orbit_from_angles(
    c: &[[f64; 2]],
    shift: [f64; 2],
    r: f64,
    s: &[f64],
    labels: &[[i64; 2]],
    bits: u32,
) -> Vec<OrbitPoint> {
    let n = c.len();
    let contact = |k: usize, centre: [f64; 2]| {
        [
            centre[0] + r * s[k % n].cos(),
            centre[1] + r * s[k % n].sin(),
        ]
    };
    (0..n)
        .map(|k| {
            let here = contact(k, c[k]);
            let there = contact(k + 1, neighbours(c, shift, k).1);
            let (x, y) = (there[0] - here[0], there[1] - here[1]);
            let l = x.hypot(y);
            let p = s[k].cos() * (y / l) - s[k].sin() * (x / l);
            OrbitPoint {
                disk: labels[k],
                s: Float::with_val(bits, s[k]),
                p: Float::with_val(bits, p),
            }
        })
        .collect()
}

/// Refuses a disk sequence that names no cycle on `disks`, or a precision out of range.
fn check_sequence(disks: &Disks, seq: &[usize], bits: u32) -> Result<(), Error> {
    disks.validate()?;
    Error::unless_in(
        "cycle_length",
        seq.len(),
        2..=MAX_CYCLE_LENGTH,
        " collisions",
    )?;
    Error::unless_in("bits", bits, MIN_CYCLE_BITS..=MAX_CYCLE_BITS, " bits")?;
    let m = disks.count();
    if let Some(&d) = seq.iter().find(|&&d| d >= m) {
        return Err(Error::out_of_range(
            "disks",
            d,
            format!("use disk labels 0 to {}", m - 1),
        ));
    }
    let n = seq.len();
    if (0..n).any(|k| seq[k] == seq[(k + 1) % n]) {
        return Err(Error::parameter(
            "disks",
            format!("{seq:?}"),
            "no disk may follow itself (cyclically): a flight joins two different disks",
        ));
    }
    Ok(())
}
