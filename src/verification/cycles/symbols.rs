//! The symbolic dynamics of the three-disk repeller and its C3v reduction: ChaosBook's binary
//! code of the fundamental domain (0: back to the disk just left, a reflection; 1: on to the
//! third disk, a rotation).

/// The binary prime cycles (Lyndon words: aperiodic, least among their rotations) of length 1 to
/// `max_len`, by length and then lexicographically.
pub fn prime_words(max_len: usize) -> Vec<Vec<u8>> {
    prime_words_over(2, max_len)
}

/// The prime cycles over the alphabet 0 … `letters` − 1 (Lyndon words) of length 1 to
/// `max_len`, by length and then lexicographically.
pub fn prime_words_over(letters: u8, max_len: usize) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for_each_prime_word(letters, max_len, |w| out.push(w.to_vec()));
    out.sort_by(|a, b| a.len().cmp(&b.len()).then(a.cmp(b)));
    out
}

/// The number of prime cycles (Lyndon words) over `letters` letters of length 1 to `max_len`:
/// Σ_n (1/n) Σ_{d | n} μ(d) letters^{n/d} (Möbius inversion).
pub fn prime_word_count(letters: u64, max_len: usize) -> u64 {
    let mobius = |k: usize| -> i64 {
        let (mut m, mut p, mut out) = (k, 2, 1);
        while p * p <= m {
            if m.is_multiple_of(p) {
                m /= p;
                if m.is_multiple_of(p) {
                    return 0;
                }
                out = -out;
            }
            p += 1;
        }
        if m > 1 { -out } else { out }
    };
    (1..=max_len)
        .map(|n| {
            let sum: i64 = (1..=n)
                .filter(|d| n.is_multiple_of(*d))
                .map(|d| mobius(d) * letters.pow((n / d) as u32) as i64)
                .sum();
            sum as u64 / n as u64
        })
        .sum()
}

/// Calls `f` on every prime cycle over the alphabet 0 … `letters` − 1 (Lyndon word) of length
/// 1 to `max_len`, in lexicographic order (Duval's algorithm), without keeping them.
pub fn for_each_prime_word(letters: u8, max_len: usize, mut f: impl FnMut(&[u8])) {
    if max_len == 0 || letters == 0 {
        return;
    }
    let top = letters - 1;
    let mut w: Vec<u8> = vec![0];
    loop {
        f(&w);
        // Next Lyndon word of length ≤ max_len: repeat w to max_len, drop trailing top letters,
        // increment the last.
        let m = w.len();
        while w.len() < max_len {
            w.push(w[w.len() - m]);
        }
        while w.last() == Some(&top) {
            w.pop();
        }
        match w.last_mut() {
            Some(x) => *x += 1,
            None => break,
        }
    }
}

/// The full-space disk sequence of the fundamental-domain word `word` and the order h of the
/// symmetry g it closes with (the full cycle is h·ñ long; 6/h distinct full-space cycles share
/// it): from disk 1 reached from disk 0, symbol 0 returns to the disk just left and 1 goes on to
/// the third, until the pair (previous, current) is (0, 1) again at the end of a pass.
pub fn full_space(word: &[u8]) -> (Vec<usize>, usize) {
    let (mut prev, mut cur) = (0usize, 1usize);
    let mut seq = Vec::new();
    let mut passes = 0;
    loop {
        for &sym in word {
            seq.push(cur);
            let next = if sym == 0 { prev } else { 3 - prev - cur };
            (prev, cur) = (cur, next);
        }
        passes += 1;
        if (prev, cur) == (0, 1) {
            return (seq, passes);
        }
    }
}

/// The word as text ("0", "01", …).
pub fn word_text(word: &[u8]) -> String {
    word.iter().map(|&b| char::from(b'0' + b)).collect()
}

/// The number of full-space prime cycles of length `n` ≥ 2 over three disks with no disk
/// following itself (cyclically), by brute force: the primitive sequences, n rotations each.
pub fn full_space_prime_count(n: usize) -> usize {
    fn walk(seq: &mut [usize], k: usize, found: &mut usize) {
        let n = seq.len();
        if k == n {
            let primitive =
                (1..n).all(|r| !n.is_multiple_of(r) || (0..n).any(|i| seq[i] != seq[(i + r) % n]));
            *found += usize::from(seq[n - 1] != seq[0] && primitive);
            return;
        }
        for d in 0..3 {
            if k == 0 || d != seq[k - 1] {
                seq[k] = d;
                walk(seq, k + 1, found);
            }
        }
    }
    if n < 2 {
        return 0;
    }
    let mut found = 0;
    walk(&mut vec![0; n], 0, &mut found);
    found / n
}
