//! One triangular trap of three disks and its three gaps, and nothing else: particles are
//! injected through a gap from the invariant flux and followed until they leave.
//!
//! Injection through gap E₂ (the base y = 0 of the canonical trap, free for x ∈ [1, a − 1]):
//! position uniform on the free part of the gap, and the angle α from the inward normal with
//! sin α uniform in [−1, 1] — the equilibrium flux through a line is ∝ cos α dα = d(sin α); a uniform
//! α would over-weight grazing entries. By Kac's lemma the mean visit time is the mean residence
//! time τ = πA/(3w) and the mean number of collisions per visit is π/(3w)
//! (`proofs-notes/trap-injection.md`).

use rand::Rng;

use crate::Error;
use crate::kernel::vec2::Vec2;
use crate::kernel::{flight::EventKind, flight::Flight, trap::Trap};
use crate::numbers::real::Real;
use crate::scenes::symbols::Symbol;

/// Symbol ([`crate::scenes::symbols::Symbol`]) of leaving by edge `out` after entering by edge `entered`
/// (edge labels 0, 1, 2), in the canonical frame.
/// The outward normals of E₂, E₀, E₁ point at −90°, 30°, 150°: counter-clockwise order 2 → 0 → 1,
/// so l = (k + 1) mod 3 and r = (k + 2) mod 3. A down trap is the canonical one turned by 180°,
/// which preserves orientation: the same rule holds in every trap.
pub fn exit_symbol(entered: u8, out: u8) -> Symbol {
    debug_assert!(entered < 3 && out < 3, "edge labels are 0, 1, 2");
    if out == entered {
        Symbol::Z
    } else if out == (entered + 1) % 3 {
        Symbol::L
    } else {
        Symbol::R
    }
}

/// Event cap of [`SingleTrap::random_visit`]: 2⁴⁰ ≈ 1.1·10¹² events, ~10⁸ times the mean visit
/// (π/(3w) collisions, below 10⁴ for every w ≥ 10⁻⁴) — reached only by an orbit trapped for ever
/// (a set of measure zero), whose endless loop it turns into an error.
pub const MAX_VISIT_EVENTS: u64 = 1 << 40;

/// One visit: injected, followed to the exit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Visit {
    /// Injection position along the gap, 2x/w ∈ [−1, 1] (0 at the gap centre).
    pub x: f64,
    /// sin α of the injection direction.
    pub sin_alpha: f64,
    /// Exit symbol.
    pub exit: Symbol,
    /// Time in the trap.
    pub time: f64,
    /// Collisions in the trap.
    pub collisions: u64,
}

/// The single-trap scene at gap `w`, on number type `T`.
#[derive(Debug, Clone)]
pub struct SingleTrap<T: Real> {
    /// The trap.
    pub trap: Trap<T>,
}

impl<T: Real> SingleTrap<T> {
    /// The trap at gap `w > 0`.
    pub fn new(w: T) -> Result<Self, Error> {
        Ok(SingleTrap {
            trap: Trap::new(w)?,
        })
    }

    /// Follows a particle that enters through E₂ at 2x/w = `x` with sin α = `sin_alpha`
    /// (α from the inward normal (0, 1), positive towards +x) until it leaves; at most
    /// `max_events` events (a particle on a trapped periodic orbit never leaves).
    pub fn visit(&self, x: f64, sin_alpha: f64, max_events: u64) -> Result<Visit, Error> {
        let ctx = self.trap.a.ctx();
        let half_w = self.trap.w.clone().scale(0.5);
        let px = self.trap.a.clone().scale(0.5) + &(half_w * &T::from_f64(ctx, x));
        let s = T::from_f64(ctx, sin_alpha);
        let c = (T::one(ctx) - &s.square()).sqrt();
        let mut f = Flight::new(Vec2::new(px, T::zero(ctx)), Vec2::new(s, c));
        f.excluded_edge = Some(2);
        let (mut time, mut coll) = (0.0, 0u64);
        for _ in 0..max_events {
            let ev = self
                .trap
                .next_event(&f)
                .ok_or_else(|| Error::Failed("no next event".into()))?;
            time += ev.time.to_f64();
            match ev.kind {
                EventKind::Collision(_) => {
                    coll += 1;
                    self.trap.apply(&mut f, &ev);
                }
                EventKind::Crossing(k) => {
                    return Ok(Visit {
                        x,
                        sin_alpha,
                        exit: exit_symbol(2, k),
                        time,
                        collisions: coll,
                    });
                }
            }
        }
        Err(Error::Failed(format!(
            "particle injected at 2x/w = {x}, sin a = {sin_alpha} did not leave within {max_events} events"
        )))
    }

    /// A visit from the invariant flux: 2x/w and sin α uniform in [−1, 1], at most
    /// [`MAX_VISIT_EVENTS`] events.
    pub fn random_visit<R: Rng + ?Sized>(&self, rng: &mut R) -> Result<Visit, Error> {
        let x = 2.0 * rng.random::<f64>() - 1.0;
        let s = 2.0 * rng.random::<f64>() - 1.0;
        self.visit(x, s, MAX_VISIT_EVENTS)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chirality_is_a_rotation() {
        assert_eq!(exit_symbol(2, 0), Symbol::L);
        assert_eq!(exit_symbol(0, 1), Symbol::L);
        assert_eq!(exit_symbol(1, 2), Symbol::L);
        assert_eq!(exit_symbol(2, 1), Symbol::R);
        assert_eq!(exit_symbol(1, 1), Symbol::Z);
    }

    #[test]
    fn straight_up_the_middle_hits_the_apex_disk_and_comes_back() {
        // Entering at the gap centre along the normal: head-on with P₂, straight back out.
        let t = SingleTrap::new(0.1f64).unwrap();
        let v = t.visit(0.0, 0.0, 100).unwrap();
        assert_eq!(v.exit, Symbol::Z);
        assert_eq!(v.collisions, 1);
        assert!((v.time - 2.0 * (t.trap.h - 1.0)).abs() < 1e-14);
    }
}
