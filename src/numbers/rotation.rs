//! The first entry of an integer rotation into a window: the least k ≥ 0 with
//! (a·k + b) mod m < c, in exact integers, by Euclid's recursion (`proofs-notes/long-flights.md`).
//!
//! A straight flight through a lattice of small disks meets a disk in column k exactly when the
//! line's height there, reduced modulo the lattice spacing, falls in a window of width about twice
//! the radius: the first collision is the first entry of a rotation into a window. Its recursion
//! swaps (m, a) for (a, m mod a) as Euclid's algorithm does, so it takes O(log m) steps whatever
//! the answer — the flight's length never enters. Integers are exact (GMP), so no rounding can
//! make it skip an entry.

use rug::Integer;
use rug::ops::DivRounding;

/// The least k ≥ 0 with (a·k + b) mod m < c, or `None` if there is none (the orbit of a rational
/// rotation is periodic and misses the window).
///
/// Requires m > 0 and c ≥ 0; a and b are taken modulo m.
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::rotation::first_entry;
/// use rug::Integer;
/// let i = |x: i64| Integer::from(x);
/// // 7k + 5 (mod 100): 5, 12, 19, …, 96, 3 — first below 4 at k = 14.
/// assert_eq!(first_entry(&i(7), &i(5), &i(100), &i(4)), Some(i(14)));
/// // 10k + 5 (mod 100) takes only the values 5, 15, …: never below 5.
/// assert_eq!(first_entry(&i(10), &i(5), &i(100), &i(5)), None);
/// ```
pub fn first_entry(a: &Integer, b: &Integer, m: &Integer, c: &Integer) -> Option<Integer> {
    assert!(*m > 0, "first_entry: the modulus must be positive");
    let a = modulo(a, m);
    let b = modulo(b, m);
    first(a, b, m.clone(), c)
}

/// [`first_entry`] with 0 ≤ a, b < m.
fn first(a: Integer, b: Integer, m: Integer, c: &Integer) -> Option<Integer> {
    if b < *c {
        return Some(Integer::new());
    }
    if *c <= 0 || a == 0 {
        return None;
    }
    // a·k + b enters [j·m, j·m + c) for some j ≥ 1; for that j the least such k is
    // k = ⌈(j·m − b)/a⌉, and it lies in the window iff (b − j·m) mod a < c.
    if *c >= a {
        return Some(ceil_div(Integer::from(&m - &b), &a));
    }
    // j = 1 + j′: (b − m − j′·m) mod a < c, i.e. (b₀ − m′·j′) mod a < c with m′ = m mod a and
    // b₀ = (b − m) mod a. The reflection y ↦ c − 1 − y maps [0, c) onto itself modulo a
    // (c < a), turning it into (m′·j′ + (c − 1 − b₀)) mod a < c: Euclid's step (m, a) → (a, m′).
    let mp = modulo(&m, &a);
    let b0 = modulo(&Integer::from(&b - &m), &a);
    let b1 = modulo(&(Integer::from(c - 1u32) - b0), &a);
    let jp = first(mp, b1, a.clone(), c)?;
    let j = jp + 1u32;
    Some(ceil_div(j * &m - b, &a))
}

/// An answer of [`first_entry_u64`] that does not fit 64 bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Overflow;

/// [`first_entry`] in machine integers, for 0 ≤ a, b < m and c ≥ 0: the same recursion with
/// every value below m < 2⁶⁴ and the final products in 128 bits. [`Overflow`] where an answer at
/// some level does not fit 64 bits (a far entry of a nearly rational rotation): the caller
/// falls back to [`first_entry`].
///
/// # Errors
/// An answer beyond 2⁶⁴ − 1 at some level of the recursion.
pub fn first_entry_u64(a: u64, b: u64, m: u64, c: u64) -> Result<Option<u64>, Overflow> {
    debug_assert!(a < m && b < m);
    if b < c {
        return Ok(Some(0));
    }
    if c == 0 || a == 0 {
        return Ok(None);
    }
    if c >= a {
        return Ok(Some(ceil_div_u128(u128::from(m - b), a)?));
    }
    let mp = m % a;
    // b₀ = (b − m) mod a and (c − 1 − b₀) mod a, without negative intermediates.
    let bm = b % a;
    let b0 = if bm >= mp { bm - mp } else { bm + (a - mp) };
    let b1 = if c > b0 {
        c - 1 - b0
    } else {
        (c - 1) + (a - b0)
    };
    let Some(jp) = first_entry_u64(mp, b1, a, c)? else {
        return Ok(None);
    };
    let j = u128::from(jp) + 1;
    let top = j.checked_mul(u128::from(m)).ok_or(Overflow)? - u128::from(b);
    Ok(Some(ceil_div_u128(top, a)?))
}

/// ⌈x / d⌉ as a u64, d > 0.
fn ceil_div_u128(x: u128, d: u64) -> Result<u64, Overflow> {
    let d = u128::from(d);
    u64::try_from(x.div_ceil(d)).map_err(|_| Overflow)
}

/// x mod m in [0, m), m > 0.
fn modulo(x: &Integer, m: &Integer) -> Integer {
    let mut r = Integer::from(x % m);
    if r < 0 {
        r += m;
    }
    r
}

/// ⌈x / d⌉ for d > 0.
fn ceil_div(x: Integer, d: &Integer) -> Integer {
    x.div_ceil(d)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    fn brute(a: i64, b: i64, m: i64, c: i64) -> Option<i64> {
        (0..=m).find(|k| (a * k + b).rem_euclid(m) < c)
    }

    /// Against the brute-force search over one period (k ≤ m) for random small rotations,
    /// windows and offsets, including a, b outside [0, m) and windows of width 0 and ≥ m.
    /// Broken on purpose (the reflection's c − 1 as c): fails at the first window of width > 1.
    #[test]
    fn first_entry_is_the_brute_force_answer() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(34);
        for _ in 0..20_000 {
            let m = rng.random_range(1..300i64);
            let a = rng.random_range(-400..400i64);
            let b = rng.random_range(-400..400i64);
            let c = rng.random_range(0..m + 2);
            let i = Integer::from;
            let got = first_entry(&i(a), &i(b), &i(m), &i(c)).map(|k| k.to_i64().unwrap());
            assert_eq!(got, brute(a, b, m, c), "a {a} b {b} m {m} c {c}");
        }
    }

    /// The machine-integer recursion gives the GMP one's answer wherever it answers, on random
    /// 64-bit rotations with windows from 1 to 2⁶⁴/4 (and on the small cases above).
    #[test]
    fn first_entry_u64_is_first_entry() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(36);
        let (mut answered, mut declined) = (0, 0);
        for n in 0..50_000 {
            let m: u64 = if n % 2 == 0 {
                rng.random_range(1..300)
            } else {
                rng.random::<u64>() | 1
            };
            let (a, b) = (rng.random::<u64>() % m, rng.random::<u64>() % m);
            let c = if n % 2 == 0 {
                rng.random_range(0..m + 2)
            } else {
                m >> rng.random_range(2..64)
            };
            let i = Integer::from;
            let big = first_entry(&i(a), &i(b), &i(m), &i(c)).map(|k| k.to_u64().unwrap());
            match first_entry_u64(a, b, m, c) {
                Ok(k) => {
                    answered += 1;
                    assert_eq!(k, big, "a {a} b {b} m {m} c {c}");
                }
                Err(Overflow) => declined += 1,
            }
        }
        assert!(
            declined * 100 < answered,
            "{declined} declined of {answered}"
        );
    }

    /// Large moduli: the answer is checked by its definition and by the absence of an earlier
    /// entry over a window of k below it (a full scan is out of reach).
    #[test]
    fn first_entry_of_large_rotations_is_an_entry_and_the_first() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(35);
        for _ in 0..200 {
            let m = Integer::from(rng.random::<u64>() | 1) << 40u32;
            let a = Integer::from(rng.random::<u64>()) << 20u32;
            let b = Integer::from(rng.random::<u64>()) << 30u32;
            let c = Integer::from(&m >> 20u32);
            let k = first_entry(&a, &b, &m, &c).expect("an irrational-looking rotation enters");
            let at = |k: &Integer| modulo(&(Integer::from(&a * k) + &b), &m);
            assert!(at(&k) < c);
            let lo = Integer::from(&k - 5000u32).max(Integer::new());
            let mut j = lo;
            while j < k {
                assert!(at(&j) >= c, "an earlier entry at {j} before {k}");
                j += 1u32;
            }
        }
    }
}
