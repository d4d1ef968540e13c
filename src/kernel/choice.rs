//! Choosing the next event before dividing: the earliest disk by β, the earliest edge by
//! cross-multiplication, and then one square root and two divisions for the two times.
//!
//! The kernel's rule is unchanged: the next event is the candidate with the smallest *rounded*
//! time, offered disks first (by label), then edges (by label), a later offer winning only when
//! strictly earlier. Computing all three disk roots and all edge quotients and comparing them is
//! one way to apply it; this module's is another that gives the same event on every input the
//! argument of `proofs-notes/choose-before-dividing.md` covers:
//!
//! * **disks** ([`EarliestDisk`]): when the scene's disks are pairwise at least
//!   [`DISK_GAP_MIN`]·r apart, the valid disk (β < 0, Δ > 0) with the largest β = d·v is the one
//!   whose rounded entry time is smallest. Chords of disjoint disks on a line are disjoint, so the
//!   chord midpoints −β/|v|² come in the order of the entries, at least the gap apart; the
//!   worst-case rounding of a grazing entry time is about 2·10⁻⁷ at f64 (less at more bits).
//!   Below that gap every root is computed and compared, as before;
//! * **edges** ([`EarliestEdge`]): the time of edge k is s⁺ₖ/mₖ (s⁺ₖ = σₖ where σₖ > 0, else 0;
//!   mₖ = −nₖ·v > 0). Edge b is certainly earlier than edge a when the rounded products satisfy
//!   s⁺_b·m_a < (1 − 2^(3−p))·(s⁺_a·m_b), and then the rounded quotients say so strictly too;
//!   where neither order is certain (a near-tie at a corner, or a zero, infinite or NaN
//!   product), both quotients are computed and compared as before. The edge choice is therefore
//!   the full comparison's on every input, by construction.
//!
//! The chosen times are computed by exactly the operations of the full comparison, so the event
//! and its time keep every bit. The SIMD engine (`crate::engine::simd`) applies the same two rules
//! lane by lane, where every lane would otherwise compute all six candidates;
//! [`super::trap::Trap::next_event_chosen`] is their scalar form at any precision, tested against
//! the full comparison. The scalar engine keeps the full comparison in `f64`
//! ([`super::trap::Trap::next_event_compared`]): its branches already skip the candidates that
//! move away or miss, and the choice's extra comparisons made it slower, not faster (33 → 42 ns
//! per collision in f64; `proofs-notes/choose-before-dividing.md`). At MPFR precision it decides
//! in `f64` balls instead ([`super::certified`]).

use super::flight::{Event, EventKind};
use super::ray_disk::Approach;
use crate::numbers::real::Real;

/// The smallest gap between two disks, relative to their radius, at which the earliest disk is
/// chosen by β: 2⁻²⁰ ≈ 9.5·10⁻⁷, a factor 2.2 above the 4.4·10⁻⁷ that the worst-case rounding of
/// a grazing entry time needs at 53 bits (`proofs-notes/choose-before-dividing.md`).
pub const DISK_GAP_MIN: f64 = 1.0 / 1_048_576.0;

/// How a cell's kernel chooses before it divides (built once per cell, at its precision).
#[derive(Debug, Clone, PartialEq)]
pub struct Choice<T> {
    /// The disks are pairwise at least [`DISK_GAP_MIN`]·r apart (vacuous for one disk): the
    /// earliest is the valid one with the largest β. Otherwise every root is computed.
    pub disks_by_beta: bool,
    /// 1 − 2^(3−p) at the working precision p (exact): the factor of the edges' certificate.
    pub certain: T,
}

impl<T: Real> Choice<T> {
    /// The choice for a cell whose closest two disks are `gap` apart (`None`: fewer than two
    /// disks), disks of radius `radius`, at the context `ctx`.
    pub fn new(ctx: T::Ctx, gap: Option<&T>, radius: &T) -> Self {
        let disks_by_beta = match gap {
            None => true,
            Some(g) => *g >= radius.clone().scale(DISK_GAP_MIN),
        };
        let p = T::bits(ctx) as i32;
        let certain = T::one(ctx) - &T::from_f64(ctx, 2f64.powi(3 - p));
        Choice {
            disks_by_beta,
            certain,
        }
    }
}

/// The earliest of the disks offered in label order (see the module documentation).
#[derive(Debug)]
pub struct EarliestDisk<'a, T: Real> {
    by_beta: bool,
    r2: Option<&'a T>,
    chosen: Option<(u8, Approach<T>)>,
    timed: Option<Event<T>>,
}

impl<'a, T: Real> EarliestDisk<'a, T> {
    /// Nothing offered yet; `r2 = None` for unit disks (γ = |d|² − 1 by adding −1).
    #[inline(always)]
    pub fn new(by_beta: bool, r2: Option<&'a T>) -> Self {
        EarliestDisk {
            by_beta,
            r2,
            chosen: None,
            timed: None,
        }
    }

    /// Offers disk `m` with its [`super::ray_disk::approach`] (`None`: no contact).
    #[inline(always)]
    pub fn offer(&mut self, m: u8, a: Option<Approach<T>>) {
        let Some(a) = a else { return };
        if self.by_beta {
            if self.chosen.as_ref().is_none_or(|(_, b)| a.beta > b.beta) {
                self.chosen = Some((m, a));
            }
        } else {
            let t = a.entry(self.r2);
            if self.timed.as_ref().is_none_or(|b| t < b.time) {
                self.timed = Some(Event {
                    kind: EventKind::Collision(m),
                    time: t,
                });
            }
        }
    }

    /// The earliest disk event, its time computed now if it was chosen by β.
    #[inline(always)]
    pub fn event(self) -> Option<Event<T>> {
        match self.chosen {
            Some((m, a)) => Some(Event {
                kind: EventKind::Collision(m),
                time: a.entry(self.r2),
            }),
            None => self.timed,
        }
    }
}

/// The earliest of the edges offered in label order (see the module documentation).
#[derive(Debug)]
pub struct EarliestEdge<'a, T: Real> {
    certain: &'a T,
    /// (label, s⁺, m) of the earliest so far.
    best: Option<(u8, T, T)>,
}

/// An edge's time s⁺/m, or 0 where s⁺ = 0: the operations of σ/(−n·v) (or 0 where σ ≤ 0).
/// Shared with [`super::certified`], which times its chosen edge by it.
#[inline(always)]
pub(crate) fn edge_time<T: Real>(s: T, m: &T) -> T {
    if s.gt0() { s / m } else { T::zero(s.ctx()) }
}

impl<'a, T: Real> EarliestEdge<'a, T> {
    /// Nothing offered yet, with the choice's certificate factor.
    #[inline(always)]
    pub fn new(certain: &'a T) -> Self {
        EarliestEdge {
            certain,
            best: None,
        }
    }

    /// Offers edge `k` with nₖ·v and σₖ: a candidate where nₖ·v < 0.
    #[inline(always)]
    pub fn offer(&mut self, k: u8, nv: T, sigma: T) {
        if !nv.lt0() {
            return;
        }
        let mut m = nv;
        m.neg_mut();
        let s = if sigma.gt0() { sigma } else { T::zero(m.ctx()) };
        let later_wins = match &self.best {
            None => true,
            Some((_, sa, ma)) => {
                let later = s.clone() * ma;
                let sooner = sa.clone() * &m;
                if later < sooner.clone() * self.certain {
                    true
                } else if sooner < later * self.certain {
                    false
                } else {
                    edge_time(s.clone(), &m) < edge_time(sa.clone(), ma)
                }
            }
        };
        if later_wins {
            self.best = Some((k, s, m));
        }
    }

    /// The earliest crossing, its time computed now.
    #[inline(always)]
    pub fn event(self) -> Option<Event<T>> {
        self.best.map(|(k, s, m)| Event {
            kind: EventKind::Crossing(k),
            time: edge_time(s, &m),
        })
    }
}

/// The next event from the earliest disk and the earliest edge: the edge only where it is
/// strictly earlier (collisions before crossings on a tie).
#[inline(always)]
pub fn first<T: Real>(disk: Option<Event<T>>, edge: Option<Event<T>>) -> Option<Event<T>> {
    match (disk, edge) {
        (Some(d), Some(e)) => Some(if e.time < d.time { e } else { d }),
        (d, e) => d.or(e),
    }
}
