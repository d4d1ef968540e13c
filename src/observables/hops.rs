//! Trap-hopping statistics along a lattice trajectory: the symbol sequence z/l/r
//! ([`crate::scenes::single_trap::exit_symbol`]), collisionless visits, symbol-sequence counts up to
//! an order K, and the correlations C_j of hop directions for the hop-level Green–Kubo formula
//! D = D_MZ (1 + 2 Σ_j C_j) (`proofs-notes/hops.md`).

use crate::kernel::trap::{Event, EventKind};
use crate::scenes::lattice::LatticeState;
use crate::scenes::single_trap::{exit_symbol, Exit};

/// Number of hop-direction correlations accumulated (C₁ … C_J).
pub const GK_LAGS: usize = 48;

/// Hop statistics of one trajectory.
#[derive(Debug, Clone)]
pub struct Hops {
    order: usize,
    entered: Option<u8>,
    collided: bool,
    /// Complete visits (entered and left by a gap).
    pub visits: u64,
    /// Complete visits without a collision.
    pub collisionless: u64,
    /// counts[k−1][code]: occurrences of each length-k symbol sequence (base-3 code, z = 0,
    /// l = 1, r = 2, first symbol most significant), k = 1 … order.
    pub counts: Vec<Vec<u64>>,
    history: u64,
    seen: u64,
    dirs: Vec<u8>,
    hops: u64,
    /// Σ cos(angle between hops j apart), j = 1 … GK_LAGS.
    pub corr_sums: Vec<f64>,
    /// Number of pairs in each sum.
    pub corr_counts: Vec<u64>,
}

fn code(e: Exit) -> u64 {
    match e {
        Exit::Z => 0,
        Exit::L => 1,
        Exit::R => 2,
    }
}

/// cos(60°·k) for k = 0 … 5.
const COS60: [f64; 6] = [1.0, 0.5, -0.5, -1.0, -0.5, 0.5];

impl Hops {
    /// Statistics up to sequences of length `order` (≥ 1).
    pub fn new(order: usize) -> Self {
        let order = order.max(1);
        Hops {
            order,
            entered: None,
            collided: false,
            visits: 0,
            collisionless: 0,
            counts: (1..=order).map(|k| vec![0; 3usize.pow(k as u32)]).collect(),
            history: 0,
            seen: 0,
            dirs: vec![0; GK_LAGS + 1],
            hops: 0,
            corr_sums: vec![0.0; GK_LAGS],
            corr_counts: vec![0; GK_LAGS],
        }
    }

    /// Called with the state *before* `ev` is applied.
    #[inline(always)]
    pub fn observe<T>(&mut self, s: &LatticeState<T>, ev: &Event<T>) {
        match ev.kind {
            EventKind::Collision(_) => self.collided = true,
            EventKind::Crossing(k) => {
                // Hop direction in the world: outward normals of E₀, E₁, E₂ at 30°, 150°, 270°,
                // i.e. 60°·{0, 2, 4} + 30°; a down trap is turned by 180° (+3).
                let dir = ([0u8, 2, 4][k as usize] + if s.cell.down { 3 } else { 0 }) % 6;
                let cap = self.dirs.len() as u64;
                let i = (self.hops % cap) as usize;
                self.dirs[i] = dir;
                for j in 1..=GK_LAGS.min(self.hops as usize) {
                    let old = self.dirs[(i + cap as usize - j) % cap as usize];
                    self.corr_sums[j - 1] += COS60[((dir + 6 - old) % 6) as usize];
                    self.corr_counts[j - 1] += 1;
                }
                self.hops += 1;
                if let Some(e) = self.entered {
                    self.visits += 1;
                    if !self.collided {
                        self.collisionless += 1;
                    }
                    let sym = code(exit_symbol(e, k));
                    self.seen += 1;
                    self.history = (self.history * 3 + sym) % 3u64.pow(self.order as u32);
                    for len in 1..=self.order.min(self.seen as usize) {
                        let c = self.history % 3u64.pow(len as u32);
                        self.counts[len - 1][c as usize] += 1;
                    }
                }
                // The edge crossed is the entrance of the next trap (same label after the point
                // reflection).
                self.entered = Some(k);
                self.collided = false;
            }
        }
    }

    /// Hop-direction correlations C_j.
    pub fn correlations(&self) -> Vec<f64> {
        self.corr_sums
            .iter()
            .zip(&self.corr_counts)
            .map(|(s, &c)| if c > 0 { s / c as f64 } else { 0.0 })
            .collect()
    }
}

/// Name of a base-3 code of length k ("zl", …).
pub fn sequence_name(code: usize, k: usize) -> String {
    let mut out = vec![' '; k];
    let mut c = code;
    for i in (0..k).rev() {
        out[i] = ['z', 'l', 'r'][c % 3];
        c /= 3;
    }
    out.into_iter().collect()
}
