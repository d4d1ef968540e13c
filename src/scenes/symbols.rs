//! The symbolic dynamics of trap hopping: the paper's exit symbols z, l, r and the words they form
//! — the one encoding every part of the crate uses (the single-trap scene, the lattice-trajectory
//! observer, the hop reports, the theory and the figures).
//!
//! * A [`Symbol`] names the gap a particle leaves a trap by, relative to the gap it came in by:
//!   **z** = back through the entrance (backscattering), **l** / **r** = the gap 120°
//!   counter-clockwise / clockwise from the entrance, seen from the trap centre
//!   (geometry: [`crate::scenes::single_trap::exit_symbol`], [`crate::theory::honeycomb`]).
//! * Index (digit) z = 0, l = 1, r = 2; character `'z'`, `'l'`, `'r'` (parsed case-insensitively;
//!   any other character is an error naming z, l, r — never silently z).
//! * A word s₁…s_k has the base-3 sequence index Σ sᵢ 3^(k−i) (first symbol most significant),
//!   the order of every table of sequence counts or probabilities ([`sequence_index`],
//!   [`sequence_from_index`], [`sequence_name`], [`parse_sequence_index`]).
//! * Orders (word lengths of measured tables and memories of correlated walks) run from 1 to
//!   [`MAX_ORDER`] ([`check_order`]).
//!
//! `proofs-notes/hops.md` (the exit rule and the symmetries), `proofs-notes/honeycomb.md` (the
//! action on hop directions).

use std::fmt;

use crate::Error;

/// The exit gap of a trap relative to its entrance gap (the paper's symbols).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Symbol {
    /// Back through the entrance gap (backscattering): hop direction **d** ↦ −**d**.
    Z,
    /// The gap 120° counter-clockwise from the entrance (seen from the trap centre):
    /// **d** ↦ R(−60°)**d**.
    L,
    /// The gap 120° clockwise from the entrance: **d** ↦ R(+60°)**d**.
    R,
}

/// Largest order k accepted anywhere: sequence tables measured along trajectories
/// ([`crate::estimators::hops::run`]), the hierarchy and the exact and simulated order-k walks
/// ([`crate::theory::markov::CorrelatedWalk`]).
///
/// Why 7: the exact walk of order k is a dense complex LU on its 3^(k−1) histories — 729 at
/// k = 7 (8.5 MB, ~10⁹ flops); every further order multiplies memory by 9 and time by 27
/// (k = 8: 2187 histories, 77 MB, ~3·10¹⁰ flops), while the 3⁷ = 2187 words of order 7 are already
/// seen only a few thousand times on average in 10⁸ collisions (~10⁷ visits at w = 0.1), so longer
/// tables are dominated by counting noise.
pub const MAX_ORDER: usize = 7;

impl Symbol {
    /// The three symbols in index order z, l, r (indices 0, 1, 2).
    pub const ALL: [Symbol; 3] = [Symbol::Z, Symbol::L, Symbol::R];

    /// Index (base-3 digit) 0, 1, 2 for z, l, r.
    pub const fn index(self) -> usize {
        match self {
            Symbol::Z => 0,
            Symbol::L => 1,
            Symbol::R => 2,
        }
    }

    /// Inverse of [`Symbol::index`]; `None` for an index ≥ 3.
    pub fn from_index(i: usize) -> Option<Symbol> {
        Symbol::ALL.get(i).copied()
    }

    /// The mirror image (l ↔ r, z fixed).
    pub const fn mirror(self) -> Symbol {
        match self {
            Symbol::Z => Symbol::Z,
            Symbol::L => Symbol::R,
            Symbol::R => Symbol::L,
        }
    }

    /// The lower-case letter used by the paper.
    pub const fn to_char(self) -> char {
        match self {
            Symbol::Z => 'z',
            Symbol::L => 'l',
            Symbol::R => 'r',
        }
    }

    /// The symbol of a letter z, l, r (either case). Any other character is an error naming the
    /// valid ones.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::scenes::symbols::Symbol;
    /// assert_eq!(Symbol::from_char('L').unwrap(), Symbol::L);
    /// let e = Symbol::from_char('x').unwrap_err();
    /// assert!(e.to_string().contains("z, l, r"));
    /// ```
    pub fn from_char(c: char) -> Result<Symbol, Error> {
        match c.to_ascii_lowercase() {
            'z' => Ok(Symbol::Z),
            'l' => Ok(Symbol::L),
            'r' => Ok(Symbol::R),
            _ => Err(Error::Invalid(format!(
                "symbol '{c}' is not one of z, l, r"
            ))),
        }
    }
}

impl fmt::Display for Symbol {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.to_char())
    }
}

/// Checks an order k (a word length or a walk's memory plus one): 1 ≤ k ≤ [`MAX_ORDER`].
/// `what` names the parameter in the error.
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::symbols::check_order;
/// assert!(check_order("order", 4).is_ok());
/// let e = check_order("order", 100).unwrap_err();
/// assert!(e.to_string().starts_with("order = 100 is out of range: use 1 to 7 ("), "{e}");
/// assert!(check_order("order", 0).is_err());
/// ```
pub fn check_order(what: &'static str, k: usize) -> Result<(), Error> {
    if (1..=MAX_ORDER).contains(&k) {
        Ok(())
    } else {
        Err(Error::out_of_range(
            what,
            k,
            format!(
                "use 1 to {MAX_ORDER} (sequences of length k over z, l, r; the exact order-k \
                 walk needs a dense LU on 3^(k-1) histories)"
            ),
        ))
    }
}

/// Parses a word such as `"lzr"` (case-insensitive) into symbols; any character other than
/// z, l, r is an error naming the word.
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::symbols::{parse_symbols, Symbol};
/// assert_eq!(parse_symbols("lZr").unwrap(), vec![Symbol::L, Symbol::Z, Symbol::R]);
/// assert!(parse_symbols("lx").is_err());
/// ```
pub fn parse_symbols(word: &str) -> Result<Vec<Symbol>, Error> {
    word.chars()
        .map(|c| {
            Symbol::from_char(c).map_err(|_| {
                Error::Invalid(format!("symbol '{c}' in \"{word}\" is not one of z, l, r"))
            })
        })
        .collect()
}

/// Writes symbols as the paper's word, e.g. `"lzr"`.
pub fn word(symbols: &[Symbol]) -> String {
    symbols.iter().map(|s| s.to_char()).collect()
}

/// Index of a sequence s₁…s_k as the base-3 number Σ sᵢ 3^(k−i) (first symbol most
/// significant, digits z = 0, l = 1, r = 2).
pub fn sequence_index(symbols: &[Symbol]) -> usize {
    symbols.iter().fold(0, |acc, s| 3 * acc + s.index())
}

/// Inverse of [`sequence_index`] for sequences of length `k` (`index` is taken mod 3^k).
pub fn sequence_from_index(k: usize, mut index: usize) -> Vec<Symbol> {
    let mut v = vec![Symbol::Z; k];
    for slot in v.iter_mut().rev() {
        *slot = Symbol::ALL[index % 3];
        index /= 3;
    }
    v
}

/// The word of the sequence of length `k` with index `index` (`"zl"`, …).
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::symbols::sequence_name;
/// assert_eq!(sequence_name(2, 3 + 2), "lr");
/// ```
pub fn sequence_name(k: usize, index: usize) -> String {
    word(&sequence_from_index(k, index))
}

/// The index of the word `name`, which must have length `k` and consist of z, l, r.
///
/// # Examples
///
/// ```
/// use lorentz_gas::scenes::symbols::parse_sequence_index;
/// assert_eq!(parse_sequence_index("lr", 2).unwrap(), 5);
/// assert!(parse_sequence_index("lx", 2).is_err());
/// assert!(parse_sequence_index("lr", 3).is_err());
/// ```
pub fn parse_sequence_index(name: &str, k: usize) -> Result<usize, Error> {
    let s = parse_symbols(name)?;
    if s.len() != k {
        return Err(Error::Invalid(format!(
            "sequence \"{name}\" has length {}, expected {k}",
            s.len()
        )));
    }
    Ok(sequence_index(&s))
}

/// All 3^k sequences of length `k`, in [`sequence_index`] order.
pub fn all_sequences(k: usize) -> Vec<Vec<Symbol>> {
    (0..3usize.pow(k as u32))
        .map(|i| sequence_from_index(k, i))
        .collect()
}

/// The index of the mirror image (l ↔ r in every position) of the length-`k` sequence `index`.
pub fn mirror_index(k: usize, index: usize) -> usize {
    let s: Vec<Symbol> = sequence_from_index(k, index)
        .into_iter()
        .map(Symbol::mirror)
        .collect();
    sequence_index(&s)
}

/// The index of the length-`k` sequence `index` read backwards.
pub fn reverse_index(k: usize, index: usize) -> usize {
    let mut s = sequence_from_index(k, index);
    s.reverse();
    sequence_index(&s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_char_round_trip() {
        for (i, s) in Symbol::ALL.into_iter().enumerate() {
            assert_eq!(s.index(), i);
            assert_eq!(Symbol::from_index(i), Some(s));
            assert_eq!(Symbol::from_char(s.to_char()).unwrap(), s);
            assert_eq!(s.to_string(), s.to_char().to_string());
            assert_eq!(s.mirror().mirror(), s);
        }
        assert_eq!(Symbol::from_index(3), None);
        for c in ['x', ' ', '0', 'Ω'] {
            let e = Symbol::from_char(c).unwrap_err().to_string();
            assert!(e.contains("z, l, r"), "{e}");
        }
    }

    #[test]
    fn sequence_index_round_trip() {
        for k in 0..5 {
            for (i, s) in all_sequences(k).iter().enumerate() {
                assert_eq!(sequence_index(s), i);
                assert_eq!(sequence_from_index(k, i), *s);
                assert_eq!(parse_sequence_index(&sequence_name(k, i), k).unwrap(), i);
            }
        }
        assert_eq!(sequence_index(&parse_symbols("lzr").unwrap()), 9 + 2);
        assert_eq!(word(&parse_symbols("RLZ").unwrap()), "rlz");
        let e = parse_symbols("lxr").unwrap_err().to_string();
        assert!(e.contains("'x'") && e.contains("z, l, r"), "{e}");
    }

    #[test]
    fn mirror_and_reverse() {
        let i = |w: &str| sequence_index(&parse_symbols(w).unwrap());
        assert_eq!(mirror_index(3, i("zlr")), i("zrl"));
        assert_eq!(reverse_index(3, i("zll")), i("llz"));
        for k in 1..5 {
            for c in 0..3usize.pow(k as u32) {
                assert_eq!(mirror_index(k, mirror_index(k, c)), c);
                assert_eq!(reverse_index(k, reverse_index(k, c)), c);
            }
        }
    }

    #[test]
    fn orders() {
        assert!(check_order("order", 1).is_ok());
        assert!(check_order("order", MAX_ORDER).is_ok());
        for k in [0, MAX_ORDER + 1, 100] {
            let e = check_order("order", k).unwrap_err().to_string();
            assert!(
                e.starts_with(&format!(
                    "order = {k} is out of range: use 1 to {MAX_ORDER} ("
                )),
                "{e}"
            );
        }
    }
}
