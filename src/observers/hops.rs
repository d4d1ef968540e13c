//! Trap-hopping statistics along a lattice trajectory: the exit symbols z/l/r
//! ([`crate::scenes::symbols::Symbol`], from [`crate::scenes::single_trap::exit_symbol`]), collisionless
//! visits, symbol-sequence counts up to an order K, and the hop directions, fed to the hop-level
//! Green–Kubo estimator ([`crate::theory::green_kubo`]) for D = D_MZ (1 + 2 Σ_j C_j)
//! (`proofs-notes/hops.md`).

use super::hop_correlations::{HopCorrelations, MAX_LAG};
use crate::Error;
use crate::engine::checkpoint::LaneCheckpoint;
use crate::engine::observe::{CROSSING_CODE, EventLanes, Observer, StepLanes, lanes};
use crate::kernel::flight::EventKind;
use crate::numbers::lanes::Lanes;
use crate::scenes::symbols::{MAX_ORDER, check_order};
use serde::{Deserialize, Serialize};

/// Hop statistics of one trajectory (also what a checkpoint keeps of it).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hops {
    order: usize,
    entered: Option<u8>,
    collided: bool,
    /// Complete visits (entered and left by a gap).
    pub visits: u64,
    /// Complete visits without a collision.
    pub collisionless: u64,
    /// `counts[k−1][index]`: occurrences of each length-k symbol sequence, in
    /// [`crate::scenes::symbols::sequence_index`] order, k = 1 … order.
    pub counts: Vec<Vec<u64>>,
    history: usize,
    seen: u64,
    /// Hop directions (60°·index + 30° in the world frame) accumulated for the Green–Kubo
    /// estimator, lags 1 … [`MAX_LAG`].
    pub directions: HopCorrelations,
}

impl Hops {
    /// Statistics up to sequences of length `order`, 1 ≤ `order` ≤ [`crate::scenes::symbols::MAX_ORDER`]
    /// (an error names the range otherwise).
    pub fn new(order: usize) -> Result<Self, Error> {
        check_order("order", order)?;
        Ok(Hops {
            order,
            entered: None,
            collided: false,
            visits: 0,
            collisionless: 0,
            counts: (1..=order).map(|k| vec![0; 3usize.pow(k as u32)]).collect(),
            history: 0,
            seen: 0,
            directions: HopCorrelations::new(MAX_LAG)?,
        })
    }

    /// The longest sequences counted.
    pub fn order(&self) -> usize {
        self.order
    }

    /// Called with each event `kind` and whether the trap it happens in is a down trap
    /// (the orientation before the event).
    #[inline(always)]
    pub fn observe(&mut self, kind: EventKind, down: bool) {
        match kind {
            EventKind::Collision(_) => self.collided = true,
            EventKind::Crossing(k) => self.hop(k, down, self.collided),
        }
    }

    /// The crossing of edge `k` out of a trap (a down trap if `down`), ending a visit that had a
    /// collision if `collided`. No division and no branch on the symbols: the symbol is
    /// (k − entrance) mod 3 ([`symbol_index`]) and the words' indices are reduced by
    /// [`mod_pow3`].
    #[inline(always)]
    fn hop(&mut self, k: u8, down: bool, collided: bool) {
        // Hop direction in the world: outward normals of E₀, E₁, E₂ at 30°, 150°, 270°,
        // i.e. 60°·{0, 2, 4} + 30°; a down trap is turned by 180° (+3).
        self.directions.push(DIRECTION[down as usize][k as usize]);
        if let Some(e) = self.entered {
            self.visits += 1;
            self.collisionless += (!collided) as u64;
            self.seen += 1;
            let next = self.history * 3 + symbol_index(e, k);
            self.history = mod_pow3(next, self.order);
            for len in 1..=self.order.min(self.seen as usize) {
                self.counts[len - 1][mod_pow3(self.history, len)] += 1;
            }
        }
        // The edge crossed is the entrance of the next trap (same label after the point
        // reflection).
        self.entered = Some(k);
        self.collided = false;
    }
}

/// Hop direction index (60°·index + 30° in the world) of a crossing of edge k, up and down traps.
const DIRECTION: [[u8; 3]; 2] = [[0, 2, 4], [3, 5, 1]];

/// The index of [`exit_symbol`](crate::scenes::single_trap::exit_symbol)`(entered, out)`:
/// (out − entered) mod 3 (z = 0, l = 1, r = 2), without its branches.
#[inline(always)]
fn symbol_index(entered: u8, out: u8) -> usize {
    (out as usize + 3 - entered as usize) % 3
}

/// 3^k for k = 0 … [`MAX_ORDER`].
const POW3: [usize; MAX_ORDER + 1] = {
    let mut t = [1usize; MAX_ORDER + 1];
    let mut k = 1;
    while k <= MAX_ORDER {
        t[k] = 3 * t[k - 1];
        k += 1;
    }
    t
};

/// ⌊2³²/3^k⌋ + 1: with it ⌊v·m/2³²⌋ = ⌊v/3^k⌋ exactly for v·(m·3^k − 2³²) < 2³², which holds for
/// every v < 3^(MAX_ORDER + 1) (the largest word index times 3 plus a symbol; the tests check
/// every such v).
const MAGIC3: [u64; MAX_ORDER + 1] = {
    let mut t = [0u64; MAX_ORDER + 1];
    let mut k = 0;
    while k <= MAX_ORDER {
        t[k] = (1u64 << 32) / POW3[k] as u64 + 1;
        k += 1;
    }
    t
};

/// v mod 3^k, by a multiplication (a word index is reduced at every hop; a division there
/// costs more than the rest of the hop's symbol work).
#[inline(always)]
fn mod_pow3(v: usize, k: usize) -> usize {
    debug_assert!(v < POW3[MAX_ORDER] * 3 && k <= MAX_ORDER);
    let q = ((v as u64 * MAGIC3[k]) >> 32) as usize;
    v - q * POW3[k]
}

/// The hop statistics of L trajectories: a collision only sets the lane's bit in a mask, a
/// crossing (about one event in π/(3w)) updates that lane's [`Hops`].
#[derive(Debug, Clone)]
pub struct HopLanes {
    lanes: Vec<Hops>,
    /// Bit l: lane l has collided since it entered its trap. The lanes' own `collided` flags are
    /// brought up to date from it when a lane is saved or handed out, so that a step's
    /// collisions cost one OR for the whole block rather than a store per lane.
    collided: u64,
}

impl HopLanes {
    /// `lanes` accumulators of sequences up to `order` (at most 64 lanes).
    pub fn new(order: usize, lanes: usize) -> Result<Self, Error> {
        let h = Hops::new(order)?;
        if lanes > 64 {
            return Err(Error::Failed(format!(
                "hop statistics of {lanes} lanes: at most 64 are observed together"
            )));
        }
        Ok(HopLanes {
            lanes: vec![h; lanes],
            collided: 0,
        })
    }

    /// Lane `l`'s statistics, up to date.
    pub fn lane(&self, l: usize) -> Hops {
        let mut h = self.lanes[l].clone();
        h.collided = (self.collided >> l) & 1 == 1;
        h
    }

    /// Every lane's statistics, up to date.
    pub fn into_lanes(mut self) -> Vec<Hops> {
        for (l, h) in self.lanes.iter_mut().enumerate() {
            h.collided = (self.collided >> l) & 1 == 1;
        }
        self.lanes
    }
}

impl Hops {
    /// Whether `self` (read from a checkpoint) is a state an accumulator like `like` could be in.
    fn is_reachable_like(&self, like: &Hops) -> bool {
        let sizes = self.counts.len() == like.counts.len()
            && self
                .counts
                .iter()
                .zip(&like.counts)
                .all(|(a, b)| a.len() == b.len());
        sizes
            && self.order == like.order
            && self.entered.is_none_or(|e| e <= 2)
            && self.history < like.counts[like.order - 1].len()
            && self.collisionless <= self.visits
            && self.directions.is_reachable(like.directions.max_lag())
    }
}

impl LaneCheckpoint for HopLanes {
    type Lane = Hops;
    fn save_lane(&self, l: usize) -> Hops {
        self.lane(l)
    }
    fn restore_lane(&mut self, l: usize, saved: &Hops) -> Result<(), Error> {
        if !saved.is_reachable_like(&self.lanes[l]) {
            return Err(Error::Invalid(format!(
                "a saved hop state of order {} does not fit this run (order {})",
                saved.order, self.lanes[l].order
            )));
        }
        self.lanes[l] = saved.clone();
        self.collided = (self.collided & !(1 << l)) | (u64::from(saved.collided) << l);
        Ok(())
    }
}

impl<const L: usize> Observer<L> for HopLanes {
    #[inline(always)]
    fn observe<V: Lanes>(&mut self, steps: &[EventLanes<L>]) {
        for group in steps.chunks(StepLanes::<L>::STEPS) {
            self.group::<V, L>(group);
        }
    }
}

impl HopLanes {
    /// A collision only sets a bit; the crossings (one event in π/(3w)) of the group's steps are
    /// found first, with whether the visit each ends had a collision, and then taken as hops in
    /// one loop, step by step.
    #[inline(always)]
    fn group<V: Lanes, const L: usize>(&mut self, steps: &[EventLanes<L>]) {
        let (mut hops, mut had) = (StepLanes::<L>::default(), StepLanes::<L>::default());
        let mut state = self.collided;
        for (k, e) in steps.iter().enumerate() {
            let mut collided = 0u64;
            let mut o = 0;
            while o < L {
                let coll = V::load(&e.code[o..]).lt(V::splat(CROSSING_CODE));
                collided |= V::bits(coll) << o;
                o += V::WIDTH;
            }
            let live = e.live_bits;
            let hop = live & !collided;
            hops.set(k, hop);
            had.set(k, state & hop);
            state = (state & !hop) | (live & collided);
        }
        self.collided = state;
        let lanes = lanes::<Hops, L>(&mut self.lanes);
        for (k, l) in hops {
            let e = &steps[k];
            let edge = (e.code[l] - CROSSING_CODE) as u8;
            lanes[l].hop(edge, e.cell[2][l] < 0.0, had.contains(k, l));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes::lattice::TriangularLattice;
    use crate::scenes::sampling::stream;
    use crate::scenes::single_trap::exit_symbol;
    use crate::scenes::symbols::{MAX_ORDER, Symbol};
    use crate::scenes::triangular::equilibrium_state;
    use crate::theory::honeycomb::next_direction;

    #[test]
    fn symbol_index_is_the_exit_symbol() {
        for e in 0..3u8 {
            for k in 0..3u8 {
                assert_eq!(symbol_index(e, k), exit_symbol(e, k).index(), "{e} → {k}");
            }
        }
    }

    /// The multiplication reduces every word index a hop can form, at every order.
    #[test]
    fn mod_pow3_is_the_remainder() {
        for (k, &p) in POW3.iter().enumerate() {
            for v in 0..POW3[MAX_ORDER] * 3 {
                assert_eq!(mod_pow3(v, k), v % p, "{v} mod 3^{k}");
            }
        }
    }

    /// The lanes' collision bits travel with a saved lane and come back with it.
    #[test]
    fn collision_bits_are_saved_and_restored() {
        let mut h = HopLanes::new(2, 3).unwrap();
        h.collided = 0b010;
        assert!(h.lane(1).collided && !h.lane(0).collided);
        let saved = h.save_lane(1);
        let mut g = HopLanes::new(2, 3).unwrap();
        g.restore_lane(2, &saved).unwrap();
        assert_eq!(g.collided, 0b100);
        let lanes = g.into_lanes();
        assert!(lanes[2].collided && !lanes[1].collided);
        assert!(HopLanes::new(2, 65).is_err());
    }

    #[test]
    fn order_out_of_range_is_an_error() {
        for k in [0, MAX_ORDER + 1] {
            let e = Hops::new(k).unwrap_err().to_string();
            assert!(
                e.contains(&format!("is out of range: use 1 to {MAX_ORDER} (")),
                "{e}"
            );
        }
        assert_eq!(Hops::new(1).unwrap().order(), 1);
    }

    /// Along a real trajectory, the exit symbol of every visit turns the hop direction exactly
    /// as the honeycomb's convention says (z: +180°, l: −60°, r: +60°), and the counts of each
    /// length are consistent: the three one-symbol extensions of a word add up to it.
    #[test]
    fn symbols_agree_with_the_honeycomb_turns() {
        let lat = TriangularLattice::new(0.2).unwrap();
        let mut s = equilibrium_state(lat.trap(), &mut stream(3, 0));
        let mut h = Hops::new(3).unwrap();
        let (mut last_dir, mut entered): (Option<u8>, Option<u8>) = (None, None);
        let mut checked = 0;
        while h.visits < 5000 {
            let ev = lat.next_event(&s).unwrap();
            if let EventKind::Crossing(k) = ev.kind {
                let dir = ([0u8, 2, 4][k as usize] + if s.cell.down { 3 } else { 0 }) % 6;
                if let (Some(d), Some(e)) = (last_dir, entered) {
                    let sym: Symbol = exit_symbol(e, k);
                    assert_eq!(next_direction(d, sym), dir, "{sym} from {d}");
                    checked += 1;
                }
                last_dir = Some(dir);
                entered = Some(k);
            }
            h.observe(ev.kind, s.cell.down);
            lat.apply(&mut s, &ev);
        }
        assert_eq!(checked, 5000);
        for k in 1..3 {
            let long = &h.counts[k];
            for (i, &c) in h.counts[k - 1].iter().enumerate() {
                // Words of length k + 1 that start with word i: all but possibly the last window.
                let ext: u64 = long[3 * i..3 * i + 3].iter().sum();
                assert!(c == ext || c == ext + 1, "k = {k}, word {i}: {c} vs {ext}");
            }
        }
    }
}
