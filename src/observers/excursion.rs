//! Bounded or diffusing: one trajectory classified from its own displacement record
//! (`proofs-notes/magnetic-components.md`).
//!
//! In a field, phase space is mixed in general: besides the pinned and skipping orbits that exact
//! geometry finds, regular islands hold orbits that bounce round several disks for ever and
//! never leave a bounded region. A trajectory is called **bounded** when the largest distance
//! from its start that it reaches in its whole run stays within the [`Excursion::limit`] of the
//! table: a few lattice cells beyond a cyclotron diameter (or as much again in a weak field). A
//! diffusing trajectory that flies the time T reaches a distance of order √(4DT); the run says
//! where the two are not well apart ([`Excursion::AMBIGUOUS`]).
//!
//! The record is the unwrapped displacement at the samples of the run's time grid: its largest
//! squared norm.

use serde::{Deserialize, Serialize};

use crate::scenes::magnetic::DiskLattice;

/// The class of one trajectory from its displacement record.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Component {
    /// It stayed within the table's excursion limit for its whole run.
    Bounded,
    /// It went beyond it.
    Diffusing,
}

/// The largest distance from its start that one trajectory reached.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Reach {
    largest2: f64,
}

impl Reach {
    /// A trajectory seen at its start only.
    pub fn new() -> Self {
        Reach::default()
    }

    /// A trajectory that reached the distance `largest` (a record read back).
    pub fn at(largest: f64) -> Self {
        Reach {
            largest2: largest * largest,
        }
    }

    /// One point of the record: the displacement (x, y) from the start.
    #[inline]
    pub fn push(&mut self, x: f64, y: f64) {
        self.largest2 = self.largest2.max(x * x + y * y);
    }

    /// The largest distance from the start seen so far.
    pub fn largest(&self) -> f64 {
        self.largest2.sqrt()
    }
}

/// The excursion limit of a table in a field, and the classification it makes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Excursion {
    /// The limit: [`Excursion::CELLS`] times the longer lattice vector, plus a cyclotron
    /// diameter 2ρ or as much again, whichever is less (in a weak field the arcs between
    /// collisions are as long as the table's flights, not 2ρ).
    pub limit: f64,
}

impl Excursion {
    /// Lattice cells (the longer lattice vector) an island orbit may span: island orbits circle a
    /// few disks (the square lattice's at r = 2/5, B = 2 spans one and a half cells).
    pub const CELLS: f64 = 3.0;

    /// How far beyond the limit every diffusing trajectory of a run must reach for the split to
    /// be called clear: a diffusing trajectory that stays within this many limits is reported as
    /// an ambiguous one (run longer).
    pub const AMBIGUOUS: f64 = 2.0;

    /// The limit of the disk array `lattice` at the cyclotron radius `rho`.
    pub fn of(lattice: &DiskLattice, rho: f64) -> Self {
        let e2 = (lattice.beta * lattice.a).hypot(lattice.h);
        let cells = Self::CELLS * lattice.a.max(e2);
        Excursion {
            limit: cells + (2.0 * rho).min(cells),
        }
    }

    /// The class of a trajectory that reached `reach`.
    pub fn classify(&self, reach: &Reach) -> Component {
        if reach.largest() <= self.limit {
            Component::Bounded
        } else {
            Component::Diffusing
        }
    }

    /// Whether a diffusing trajectory that reached `reach` is near enough to the limit that the
    /// split is not clear.
    pub fn ambiguous(&self, reach: &Reach) -> bool {
        let r = reach.largest();
        r > self.limit && r <= Self::AMBIGUOUS * self.limit
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_circle_is_bounded_and_a_walk_away_is_not() {
        let tri = DiskLattice::equal(2.2, 0.5, 2.2 * 3f64.sqrt() / 2.0, 1.0);
        let ex = Excursion::of(&tri, 0.4);
        assert!((ex.limit - (3.0 * 2.2 + 0.8)).abs() < 1e-12, "{}", ex.limit);
        // A weak field: the arcs are the table's flights, not cyclotron diameters.
        assert_eq!(Excursion::of(&tri, 1000.0).limit, 2.0 * 3.0 * 2.2);
        let mut r = Reach::new();
        for k in 0..1000 {
            let t = f64::from(k) * 0.01;
            r.push(2.0 * t.cos() - 2.0, 2.0 * t.sin());
        }
        assert_eq!(ex.classify(&r), Component::Bounded);
        assert!((r.largest() - 4.0).abs() < 1e-3);
        r.push(ex.limit * 1.01, 0.0);
        assert_eq!(ex.classify(&r), Component::Diffusing);
        assert!(ex.ambiguous(&r));
        r.push(ex.limit * 2.5, 0.0);
        assert!(!ex.ambiguous(&r));
    }
}
