//! Trap hopping on the honeycomb lattice of trap centres: the action of the symbols
//! ([`crate::scenes::symbols`], re-exported here) on hop directions and exact walks.
//!
//! # Convention
//!
//! The centres of the triangular traps form a honeycomb lattice with nearest-neighbour
//! distance l = a/√3. A particle that has just hopped into a trap, moving along the unit
//! vector **d**, entered through the gap z, which lies in the direction **−d** as seen from the
//! trap centre. Standing at the centre and facing z:
//!
//! * **z** is the entrance gap itself (backscattering): the next hop is **−d**;
//! * **l** is the gap counter-clockwise from z by 120°, i.e. in the direction R(+120°)(−**d**);
//!   the next hop is R(+120°)(−**d**) = R(−60°)**d**;
//! * **r** is the gap rotated by −120° from z: the next hop is R(−120°)(−**d**) = R(+60°)**d**.
//!
//! (Seen from the *moving particle*, l is a 60° turn to its right: the labels are those of an
//! observer at the trap centre looking at the entrance, as the paper's "exit to the left of
//! this entrance". All distance classes and D are invariant under the mirror l ↔ r, so the
//! other reading gives the same physics.)
//!
//! # Exact coordinates
//!
//! All hop directions are one of six unit vectors **u**ₖ at angle 60°·k, k = 0..5 (any
//! rotation of the physical lattice gives the same distances). The symbols act on the index
//! by z: k ↦ k+3, l: k ↦ k−1, r: k ↦ k+1 (mod 6). Positions are integer combinations
//! m **e**₁ + n **e**₂ of **e**₁ = **u**₀, **e**₂ = **u**₁ (the triangular lattice spanned by
//! the hop vectors, which contains the honeycomb); in units of l² the squared distance is the
//! exact integer |m **e**₁ + n **e**₂|² = m² + mn + n².

use crate::kernel::vec2::Vec2;
use crate::numbers::real::Real;

use crate::scenes::symbols::Symbol;

impl Symbol {
    /// Change of the hop-direction index (mod 6): z → +3, l → −1 ≡ +5, r → +1.
    pub const fn turn(self) -> u8 {
        match self {
            Symbol::Z => 3,
            Symbol::L => 5,
            Symbol::R => 1,
        }
    }
}

/// The six hop vectors **u**ₖ (angle 60°·k) in the basis **e**₁ = **u**₀, **e**₂ = **u**₁:
/// **u**₂ = **e**₂ − **e**₁, **u**₃ = −**e**₁, **u**₄ = −**e**₂, **u**₅ = **e**₁ − **e**₂.
pub const HOP: [(i64, i64); 6] = [(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)];

/// The hop direction index after leaving through gap `s`, having arrived along direction `dir`.
pub fn next_direction(dir: u8, s: Symbol) -> u8 {
    (dir + s.turn()) % 6
}

/// A point of the triangular lattice m **e**₁ + n **e**₂ (units of l).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct LatticePoint {
    /// Coefficient of **e**₁ = **u**₀.
    pub m: i64,
    /// Coefficient of **e**₂ = **u**₁.
    pub n: i64,
}

impl LatticePoint {
    /// Adds the hop vector **u**_dir.
    pub fn hop(&mut self, dir: u8) {
        let (dm, dn) = HOP[dir as usize];
        self.m += dm;
        self.n += dn;
    }

    /// Exact squared length in units of l²: |m **e**₁ + n **e**₂|² = m² + mn + n²
    /// (from **e**₁·**e**₁ = **e**₂·**e**₂ = 1, **e**₁·**e**₂ = 1/2).
    pub fn norm2(&self) -> i64 {
        self.m * self.m + self.m * self.n + self.n * self.n
    }

    /// Cartesian coordinates (units of l), computed at the precision `ctx` with √3 at that
    /// precision: (m + n/2, n√3/2).
    pub fn to_cartesian<T: Real>(&self, ctx: T::Ctx) -> Vec2<T> {
        let m = T::from_f64(ctx, self.m as f64);
        let n = T::from_f64(ctx, self.n as f64);
        Vec2::new(m + &n.clone().scale(0.5), (n * &T::sqrt3(ctx)).scale(0.5))
    }
}

/// Walks the initial hop (direction index `d0`) and then one hop per symbol; returns the
/// total displacement in exact lattice coordinates (units of l).
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::symbols::parse_symbols;
/// use lorentz_gas::theory::honeycomb::walk_exact;
/// // Initial hop and back: at the origin.
/// assert_eq!(walk_exact(0, &parse_symbols("z").unwrap()).norm2(), 0);
/// // A forward hop: next-nearest neighbour, |Δr|² = 3 l².
/// assert_eq!(walk_exact(0, &parse_symbols("l").unwrap()).norm2(), 3);
/// ```
pub fn walk_exact(d0: u8, symbols: &[Symbol]) -> LatticePoint {
    let mut p = LatticePoint::default();
    let mut dir = d0 % 6;
    p.hop(dir);
    for &s in symbols {
        dir = next_direction(dir, s);
        p.hop(dir);
    }
    p
}

/// |Δr|²/l² after the initial hop and the hops given by `symbols`: an exact integer,
/// independent of the initial direction (the walk is covariant under 60° rotations).
pub fn squared_displacement(symbols: &[Symbol]) -> i64 {
    walk_exact(0, symbols).norm2()
}

/// Rotation by +120° (`sign = +1`) or −120° (`sign = −1`):
/// (x, y) ↦ (−x/2 ∓ (√3/2) y, ±(√3/2) x − y/2), with √3 at the working precision.
pub fn rotate_120<T: Real>(v: &Vec2<T>, sign: i8, sqrt3: &T) -> Vec2<T> {
    let hx = v.x.clone().scale(-0.5);
    let hy = v.y.clone().scale(-0.5);
    let sx = (v.x.clone() * sqrt3).scale(0.5);
    let sy = (v.y.clone() * sqrt3).scale(0.5);
    if sign >= 0 {
        Vec2::new(hx - &sy, sx + &hy)
    } else {
        Vec2::new(hx + &sy, hy - &sx)
    }
}

/// The hop direction after leaving through gap `s`, having arrived along `d` (generic):
/// z: −**d**; l: R(+120°)(−**d**); r: R(−120°)(−**d**). No trigonometry.
pub fn next_hop<T: Real>(d: &Vec2<T>, s: Symbol, sqrt3: &T) -> Vec2<T> {
    let back = Vec2::new(-d.x.clone(), -d.y.clone());
    match s {
        Symbol::Z => back,
        Symbol::L => rotate_120(&back, 1, sqrt3),
        Symbol::R => rotate_120(&back, -1, sqrt3),
    }
}

/// Displacement (units of l) after the initial hop along the unit vector `d0` and the hops
/// given by `symbols`, generic over [`Real`]: Δr = **d**₀ + **d**₁ + … + **d**_k.
///
/// # Examples
///
/// ```
/// use lorentz_gas::kernel::vec2::Vec2;
/// use lorentz_gas::scenes::symbols::parse_symbols;
/// use lorentz_gas::theory::honeycomb::walk;
/// let d0 = Vec2::new(1.0f64, 0.0);
/// let r = walk(&d0, &parse_symbols("lr").unwrap());
/// assert!((r.x * r.x + r.y * r.y - 7.0).abs() < 1e-14);
/// ```
pub fn walk<T: Real>(d0: &Vec2<T>, symbols: &[Symbol]) -> Vec2<T> {
    let sqrt3 = T::sqrt3(d0.x.ctx());
    let mut d = d0.clone();
    let mut r = d0.clone();
    for &s in symbols {
        d = next_hop(&d, s, &sqrt3);
        r = Vec2::new(r.x + &d.x, r.y + &d.y);
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::symbols::all_sequences;
    use rug::Float;

    #[test]
    fn hop_vectors_have_unit_length_and_sum_to_zero() {
        let mut s = LatticePoint::default();
        for dir in 0..6u8 {
            let (m, n) = HOP[dir as usize];
            assert_eq!(LatticePoint { m, n }.norm2(), 1);
            s.hop(dir);
        }
        assert_eq!(s, LatticePoint::default());
    }

    #[test]
    fn every_trap_has_three_exits_on_one_sublattice() {
        // From any arrival direction the three exits have the same parity (bipartite honeycomb)
        // and are 120° apart; z reverses the hop.
        for dir in 0..6u8 {
            let e: Vec<u8> = Symbol::ALL
                .iter()
                .map(|&s| next_direction(dir, s))
                .collect();
            assert_eq!(e[0], (dir + 3) % 6);
            assert!(e.iter().all(|x| x % 2 == (dir + 1) % 2));
            let mut sorted = e.clone();
            sorted.sort();
            sorted.dedup();
            assert_eq!(sorted.len(), 3);
        }
    }

    #[test]
    fn first_order_distances() {
        // k = 1: z returns (0), l and r reach next-nearest neighbours (3 l²).
        assert_eq!(squared_displacement(&[Symbol::Z]), 0);
        assert_eq!(squared_displacement(&[Symbol::L]), 3);
        assert_eq!(squared_displacement(&[Symbol::R]), 3);
    }

    #[test]
    fn exact_walk_is_rotation_and_mirror_invariant() {
        for k in 0..6 {
            for s in all_sequences(k) {
                let n0 = squared_displacement(&s);
                for d0 in 0..6u8 {
                    assert_eq!(walk_exact(d0, &s).norm2(), n0);
                }
                let m: Vec<Symbol> = s.iter().map(|x| x.mirror()).collect();
                assert_eq!(squared_displacement(&m), n0);
            }
        }
    }

    #[test]
    fn generic_walk_matches_the_exact_lattice_walk() {
        // Error model: a ±120° rotation adds ≤ 4u per component (two products, one sum, one
        // halving of numbers ≤ 1), so direction i carries ≤ 4iu; summing k + 1 of them adds
        // ≤ (k+1)u per step: |error| ≤ Σ_i (4i + k + 1)u ≤ (k+1)(3k+1)u ≤ 64(k+1)u (k ≤ 21).
        for k in 0..6usize {
            for s in all_sequences(k) {
                let e = walk_exact(0, &s).to_cartesian::<Float>(256);
                let g = walk(&Vec2::<Float>::from_f64(53, 1.0, 0.0), &s);
                let g64 = walk(&Vec2::new(1.0f64, 0.0), &s);
                let tol = 64.0 * (k as f64 + 1.0) * f64::EPSILON / 2.0;
                assert!((g64.x - e.x.to_f64()).abs() <= tol);
                assert!((g64.y - e.y.to_f64()).abs() <= tol);
                // rug at 53 bits rounds like f64.
                assert_eq!(g.to_f64(), g64.to_f64());
                // 256 bits: the exact integer norm to 2^-240.
                let g256 = walk(&Vec2::<Float>::from_f64(256, 1.0, 0.0), &s);
                let n = g256.norm2() - Float::with_val(256, squared_displacement(&s));
                assert!(n.abs() < Float::with_val(256, -240f64).exp2());
            }
        }
    }

    #[test]
    fn generic_walk_from_an_arbitrary_direction() {
        // d0 = (3/5, 4/5): the squared displacement does not depend on d0.
        let d0 = Vec2::new(0.6f64, 0.8);
        for s in all_sequences(3) {
            let r = walk(&d0, &s);
            let n = squared_displacement(&s) as f64;
            assert!((r.norm2() - n).abs() <= 64.0 * 4.0 * f64::EPSILON * (1.0 + n));
        }
    }
}
