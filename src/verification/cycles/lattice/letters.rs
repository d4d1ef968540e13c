//! The alphabet of the triangular lattice's cycles and its C6v symmetry: a letter is the
//! lattice displacement δ = (i, j) from one collision's disk to the next (centre
//! a(i + j/2, j√3/2)); a word δ₀ … δ_{n−1} names a cycle of the elementary cell with winding
//! n̂ = Σδ_k (`proofs-notes/lattice-cycles.md`).

use std::collections::BTreeSet;

use crate::verification::cycles::symbols::for_each_prime_word;

/// The twelve letters: the 6 nearest neighbours A–F (at 0°, 60°, …, 300°) and the 6 second
/// neighbours a–f (at 30°, 90°, …, 330°), as lattice indices (i, j).
pub const LETTERS: [[i64; 2]; 12] = [
    [1, 0],
    [0, 1],
    [-1, 1],
    [-1, 0],
    [0, -1],
    [1, -1],
    [1, 1],
    [-1, 2],
    [-2, 1],
    [-1, -1],
    [1, -2],
    [2, -1],
];

/// The letters' names, in the order of [`LETTERS`].
pub const NAMES: [char; 12] = ['A', 'B', 'C', 'D', 'E', 'F', 'a', 'b', 'c', 'd', 'e', 'f'];

/// The 12 elements of C6v: the rotation by `rotation` × 60° after the reflection in the x axis
/// when `reflect`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Symmetry {
    /// Rotation by this many sixths of a turn (0 … 5), counter-clockwise.
    pub rotation: u8,
    /// Reflection in the x axis first.
    pub reflect: bool,
}

impl Symmetry {
    /// All 12 elements, the identity first.
    pub fn all() -> Vec<Symmetry> {
        (0..12)
            .map(|k| Symmetry {
                rotation: k % 6,
                reflect: k >= 6,
            })
            .collect()
    }

    /// The image of the lattice vector (i, j): the reflection (i, j) ↦ (i + j, −j), then the
    /// rotation by 60°, (i, j) ↦ (−j, i + j), `rotation` times (both exact on the lattice).
    pub fn act(self, v: [i64; 2]) -> [i64; 2] {
        let mut v = if self.reflect {
            [v[0] + v[1], -v[1]]
        } else {
            v
        };
        for _ in 0..self.rotation {
            v = [-v[1], v[0] + v[1]];
        }
        v
    }

    /// The image of letter `k`.
    pub fn letter(self, k: u8) -> u8 {
        let v = self.act(LETTERS[k as usize]);
        LETTERS
            .iter()
            .position(|l| *l == v)
            .expect("C6v permutes the letters") as u8
    }
}

/// The word as text ("AD", "Acf", …).
pub fn word_text(word: &[u8]) -> String {
    word.iter().map(|&k| NAMES[k as usize]).collect()
}

/// The winding n̂ = Σδ_k of a word, in lattice indices.
pub fn winding(word: &[u8]) -> [i64; 2] {
    word.iter().fold([0, 0], |w, &k| {
        let d = LETTERS[k as usize];
        [w[0] + d[0], w[1] + d[1]]
    })
}

/// The least rotation of `word` (its name as a cycle: a Lyndon word when it is aperiodic).
pub fn least_rotation(word: &[u8]) -> Vec<u8> {
    let n = word.len();
    (0..n)
        .map(|r| {
            word[r..]
                .iter()
                .chain(&word[..r])
                .copied()
                .collect::<Vec<u8>>()
        })
        .min()
        .unwrap_or_default()
}

/// The distinct cycles the symmetries carry the cycle `word` to, as least rotations, sorted
/// (the C6v orbit of the cycle: 12 divided by the order of its stabiliser).
pub fn images(word: &[u8]) -> Vec<Vec<u8>> {
    let set: BTreeSet<Vec<u8>> = Symmetry::all()
        .into_iter()
        .map(|g| least_rotation(&word.iter().map(|&k| g.letter(k)).collect::<Vec<u8>>()))
        .collect();
    set.into_iter().collect()
}

/// One class of prime cycles under C6v: its representative (the least word of the class) and
/// the number of cycles in it (its members are [`images`] of the representative).
#[derive(Debug, Clone)]
pub struct Class {
    /// The least word of the class.
    pub representative: Vec<u8>,
    /// The class's cycles, the representative included.
    pub size: usize,
}

/// The C6v classes of the prime cycles (Lyndon words over the 12 letters) of length 1 to
/// `max_len`, by length and then by representative (only the representatives are kept: 5·10⁵
/// classes at length 7 stand for 5.7·10⁶ cycles).
pub fn classes(max_len: usize) -> Vec<Class> {
    let mut out = Vec::new();
    for_each_prime_word(LETTERS.len() as u8, max_len, |w| {
        let members = images(w);
        if members[0] == w {
            out.push(Class {
                representative: w.to_vec(),
                size: members.len(),
            });
        }
    });
    out.sort_by(|a, b| {
        (a.representative.len(), &a.representative)
            .cmp(&(b.representative.len(), &b.representative))
    });
    out
}
