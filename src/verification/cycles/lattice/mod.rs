//! Certified cycles of the triangular Lorentz gas's elementary cell with their windings, and the
//! diffusion coefficient by the cycle-averaging formula (`proofs-notes/lattice-cycles.md`).
//!
//! A cycle is a word δ₀ … δ_{n−1} of lattice displacements ([`letters`]), closed modulo the
//! lattice: its collision states solve F_k = T_k(x_k) − x_{k+1} = 0 with x_n the state x₀ on
//! the disk shifted by the winding n̂ = Σδ_k — the open tables' Newton method, certificate and
//! kernel check ([`crate::verification::cycles`]) with the closure shifted. One word per C6v
//! class is certified; its images have the same T_p and Λ_p and the rotated or reflected
//! winding. [`run::run`] expands the zeta function over every certified cycle
//! ([`averages`]) and tabulates D against the truncation N.

pub mod averages;
pub mod letters;
pub mod run;
mod screen;

use rug::Rational;
use serde::{Deserialize, Serialize};

use super::{Cycle, CycleTable, MAX_CYCLE_BITS, MIN_CYCLE_BITS, certify_closed, orbit_from_angles};
use crate::Error;
use crate::scenes::triangular::TriangularScene;
use crate::scenes::triangular::geometry::check_diffusive_gap_exact;
use crate::verification::shadowing::Table;

/// The triangular lattice of disks of radius 1 and spacing a = 2 + w, disk (i, j) centred at
/// a(i + j/2, j√3/2): the gap exact, every constant rounded once at the working precision.
#[derive(Debug, Clone)]
pub struct LatticeDisks {
    scene: TriangularScene,
    a: f64,
    h: f64,
}

impl LatticeDisks {
    /// The lattice at the exact gap `w`, 0 < w < w∞ (a finite horizon).
    ///
    /// # Errors
    /// A gap out of range, decided exactly.
    pub fn new(w: &Rational) -> Result<Self, Error> {
        let scene = TriangularScene::exact(w.clone())?;
        check_diffusive_gap_exact(scene.w(), Some(&w.to_string()))?;
        let a = 2.0 + scene.w();
        Ok(LatticeDisks {
            scene,
            a,
            h: a * 3f64.sqrt() / 2.0,
        })
    }

    /// The gap as its nearest double.
    pub fn w(&self) -> f64 {
        self.scene.w()
    }

    /// Centre of disk (i, j) in `f64`.
    pub fn centre_f64(&self, d: [i64; 2]) -> [f64; 2] {
        [
            self.a * (d[0] as f64 + 0.5 * d[1] as f64),
            self.h * d[1] as f64,
        ]
    }
}

impl CycleTable for LatticeDisks {
    fn table(&self, bits: u32) -> Result<Table, Error> {
        Table::new(&self.scene, bits)
    }
    fn radius_f64(&self) -> f64 {
        1.0
    }
    /// The disks whose centres lie within `reach` + 2 (+ 10⁻⁶) of the centre of `from`: a
    /// flight of length ≤ `reach` leaving a point of `from` stays within `reach` + 1 of its
    /// centre, so it comes within 1 of no other.
    fn near(&self, from: [i64; 2], reach: f64) -> Vec<[i64; 2]> {
        let bound = reach + 2.0 + 1e-6;
        let rows = (bound / self.h).ceil() as i64 + 1;
        let cols = (bound / self.a).ceil() as i64 + rows + 1;
        let c = self.centre_f64(from);
        let mut out = Vec::new();
        for j in -rows..=rows {
            for i in -cols..=cols {
                let d = [from[0] + i, from[1] + j];
                let x = self.centre_f64(d);
                if (x[0] - c[0]).hypot(x[1] - c[1]) <= bound {
                    out.push(d);
                }
            }
        }
        out
    }
    fn label(&self, d: [i64; 2]) -> String {
        format!("({}, {})", d[0], d[1])
    }
}

/// Where a word that is not certified was stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// The `f64` screen: the shortest polygon is no billiard orbit (pruned, not certified as
    /// such).
    Screen,
    /// The kernel refused the converged MPFR orbit (a flight meets another disk first).
    Kernel,
    /// Newton's method in MPFR did not converge.
    Newton,
    /// Converged, but the Newton–Kantorovich certificate failed.
    Certificate,
}

/// A word's outcome: its cycle (when Newton's method ran) and, unless it is certified, where and
/// why it was stopped.
#[derive(Debug, Clone)]
pub struct WordOutcome {
    /// The cycle from Newton's method (`None` when the screen refused the word).
    pub cycle: Option<Cycle>,
    /// `None` when the cycle is certified; otherwise the stage and the reason.
    pub refused: Option<(Stage, String)>,
}

/// The cycle of the displacements `deltas` (lattice vectors, each nonzero) on `disks`, from the
/// shortest polygon through its disks, certified at `bits` and checked by the kernel; with
/// `screen`, refused first when that polygon is no billiard orbit in `f64`.
///
/// # Errors
/// An empty word, a zero displacement, or `bits` out of range.
pub fn certify_itinerary(
    disks: &LatticeDisks,
    deltas: &[[i64; 2]],
    bits: u32,
    screen: bool,
) -> Result<WordOutcome, Error> {
    Error::unless_in("bits", bits, MIN_CYCLE_BITS..=MAX_CYCLE_BITS, " bits")?;
    if deltas.is_empty() || deltas.contains(&[0, 0]) {
        return Err(Error::parameter(
            "word",
            format!("{deltas:?}"),
            "use a nonempty word of nonzero lattice displacements",
        ));
    }
    let mut labels = vec![[0i64, 0]];
    for d in deltas {
        let last = labels[labels.len() - 1];
        labels.push([last[0] + d[0], last[1] + d[1]]);
    }
    let close = labels
        .pop()
        .expect("one label per displacement and the closing disk");
    let centres: Vec<[f64; 2]> = labels.iter().map(|&d| disks.centre_f64(d)).collect();
    let shift = disks.centre_f64(close);
    let s = if screen {
        match screen::screen(disks, &centres, shift, &labels, close) {
            Ok(s) => s,
            Err(why) => {
                return Ok(WordOutcome {
                    cycle: None,
                    refused: Some((Stage::Screen, why)),
                });
            }
        }
    } else {
        let s0 = super::bisector_angles(&centres, shift);
        super::minimise::shortest_polygon(&centres, shift, 1.0, s0.clone()).unwrap_or(s0)
    };
    let y0 = orbit_from_angles(&centres, shift, 1.0, &s, &labels, bits);
    let cycle = certify_closed(disks, y0, close, bits)?;
    let refused = (!cycle.certified).then(|| {
        let why = cycle.failure.clone().unwrap_or_default();
        let stage = if cycle.pruned.is_some() {
            Stage::Kernel
        } else if cycle.orbit.is_empty() {
            Stage::Newton
        } else {
            Stage::Certificate
        };
        (stage, why)
    });
    Ok(WordOutcome {
        cycle: Some(cycle),
        refused,
    })
}

/// The cycle of the word `word` (letter indices of [`letters::LETTERS`]), screened in `f64`
/// and certified at `bits` ([`certify_itinerary`]).
///
/// # Errors
/// As [`certify_itinerary`]; a letter out of range.
pub fn certify_word(disks: &LatticeDisks, word: &[u8], bits: u32) -> Result<WordOutcome, Error> {
    let deltas: Option<Vec<[i64; 2]>> = word
        .iter()
        .map(|&k| letters::LETTERS.get(k as usize).copied())
        .collect();
    let deltas = deltas
        .ok_or_else(|| Error::parameter("word", format!("{word:?}"), "use letters 0 to 11"))?;
    certify_itinerary(disks, &deltas, bits, true)
}
