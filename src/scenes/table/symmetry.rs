//! The symmetry a table's diffusion tensor inherits, decided exactly: a quarter turn that maps
//! the table onto itself makes every symmetric tensor of its transport isotropic (R D Rᵀ = D
//! for the rotation R by π/2 forces D ∝ 1), with or without a field (a rotation keeps the sense
//! of rotation of the orbits). A table given in rationals has no other rotation of order above 2:
//! a turn by π/3 or 2π/3 takes a nonzero rational vector to an irrational one.

use rug::Rational;

use super::PeriodicTable;

impl PeriodicTable {
    /// `true` if the vector (x, y) is a lattice vector i·e₁ + j·e₂ (integers i, j), exactly.
    fn is_lattice_vector(&self, x: &Rational, y: &Rational) -> bool {
        let j = y.clone() / &self.h;
        let i = (x.clone() - self.b.clone() * &j) / &self.a;
        j.denom() == &1 && i.denom() == &1
    }

    /// `true` if a quarter turn (about some point) maps the table onto itself: the lattice onto
    /// itself, and every disk onto a disk of the same radius. The turn is R(x, y) = (−y, x)
    /// followed by a translation t; disk 1 must land on some disk k of its radius, which fixes t
    /// up to the lattice, and each such t is tried.
    pub fn quarter_turn_symmetric(&self) -> bool {
        let zero = Rational::new();
        let (a, b, h) = (&self.a, &self.b, &self.h);
        if !self.is_lattice_vector(&zero, a) || !self.is_lattice_vector(&(-h.clone()), b) {
            return false;
        }
        let turn = |c: &[Rational; 2]| [-c[1].clone(), c[0].clone()];
        let (c0, r0) = &self.disks[0];
        let turned0 = turn(c0);
        self.disks.iter().filter(|(_, r)| r == r0).any(|(ck, _)| {
            let t = [ck[0].clone() - &turned0[0], ck[1].clone() - &turned0[1]];
            self.disks.iter().all(|(cm, rm)| {
                let p = turn(cm);
                let (_, reduced) =
                    self.reduce_exact(&(p[0].clone() + &t[0]), &(p[1].clone() + &t[1]));
                self.disks.iter().any(|(c, r)| r == rm && *c == reduced)
            })
        })
    }
}
