//! Counts as physicists type them (`2e9`, `2_000_000_000`) and thread numbers, parsed exactly
//! and checked, with messages naming the valid range: the command line's value parsers and the
//! Python package's, one implementation for both.

/// Most worker threads accepted: far beyond any node this runs on; a larger pool only costs
/// memory (one stack per thread) and never speeds anything up.
pub const MAX_THREADS: usize = 4096;

/// A count as physicists type it: `2000000000`, `2_000_000_000`, `2e9`, `2.5e8` — a whole number
/// from 0 to 2⁶⁴ − 1, parsed exactly (never through a float).
pub fn parse_count(s: &str) -> Result<u64, String> {
    let bad = || {
        format!(
            "'{s}' is not a count: use a whole number from 0 to 18446744073709551615, such as 2000000000, 2_000_000_000 or 2e9"
        )
    };
    let t = s.trim();
    if t.is_empty() || t.starts_with('_') || t.ends_with('_') || t.contains("__") {
        return Err(bad());
    }
    let t = t.replace('_', "");
    let (mant, exp) = match t.find(['e', 'E']) {
        Some(i) => {
            let e = t[i + 1..].strip_prefix('+').unwrap_or(&t[i + 1..]);
            if e.is_empty() || !e.bytes().all(|b| b.is_ascii_digit()) && !e.starts_with('-') {
                return Err(bad());
            }
            (&t[..i], e.parse::<i64>().map_err(|_| bad())?)
        }
        None => (&t[..], 0),
    };
    let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
    if int.is_empty() && frac.is_empty()
        || !int.bytes().all(|b| b.is_ascii_digit())
        || !frac.bytes().all(|b| b.is_ascii_digit())
    {
        return Err(bad());
    }
    let digits = format!("{int}{frac}");
    // value = digits × 10^(exp − frac.len())
    let shift = exp - frac.len() as i64;
    let digits = digits.trim_start_matches('0');
    if digits.is_empty() {
        return Ok(0);
    }
    let (digits, shift) = if shift < 0 {
        let drop = (-shift) as usize;
        if drop > digits.len() || !digits[digits.len() - drop..].bytes().all(|b| b == b'0') {
            return Err(format!(
                "'{s}' is not a whole number: a count must be an integer"
            ));
        }
        (&digits[..digits.len() - drop], 0)
    } else {
        (digits, shift)
    };
    let too_large =
        || format!("'{s}' is too large: a count is at most 18446744073709551615 (2^64 - 1)");
    if digits.len() as i64 + shift > 20 {
        return Err(too_large());
    }
    let mut v: u128 = digits.parse().map_err(|_| too_large())?;
    for _ in 0..shift {
        v *= 10;
    }
    u64::try_from(v).map_err(|_| too_large())
}

/// A count that must fit in 32 bits (batches, runs, steps, orbits).
pub fn parse_count_u32(s: &str) -> Result<u32, String> {
    let v = parse_count(s)?;
    u32::try_from(v).map_err(|_| format!("'{s}' is too large: at most 4294967295"))
}

/// A count that indexes memory (`usize`).
pub fn parse_count_usize(s: &str) -> Result<usize, String> {
    let v = parse_count(s)?;
    usize::try_from(v).map_err(|_| format!("'{s}' is too large for this machine"))
}

/// Most worker threads accepted per core this process may use: a few more threads than cores
/// cost little, far more only slow a run down (4096 threads on 2 cores ran 350 times slower).
pub const MAX_THREADS_PER_CORE: usize = 4;

/// The cores this process may use (its CPU affinity and quota), at least 1.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// A thread count from 1 to [`MAX_THREADS_PER_CORE`] × [`cores`] (and at most [`MAX_THREADS`]).
pub fn parse_threads(s: &str) -> Result<usize, String> {
    let v = parse_count(s)?;
    let cores = cores();
    let max = (MAX_THREADS_PER_CORE * cores).min(MAX_THREADS);
    if v == 0 || v > max as u64 {
        return Err(format!(
            "threads must be from 1 to {max} ({MAX_THREADS_PER_CORE} per core on the {cores} \
             cores this process may use: more threads than that only slow a run down)"
        ));
    }
    Ok(v as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_as_physicists_type_them() {
        for (s, v) in [
            ("2000000000", 2_000_000_000u64),
            ("2_000_000_000", 2_000_000_000),
            ("2e9", 2_000_000_000),
            ("2E9", 2_000_000_000),
            ("2.5e8", 250_000_000),
            ("1e+3", 1000),
            ("0", 0),
            ("18446744073709551615", u64::MAX),
            ("1.8446744073709551615e19", u64::MAX),
            ("1200e-2", 12),
        ] {
            assert_eq!(parse_count(s), Ok(v), "{s}");
        }
        for s in [
            "",
            "-1",
            "1.5",
            "2e-3",
            "1e20",
            "18446744073709551616",
            "abc",
            "1e",
            "e9",
            "_1",
            "1__0",
            "0x10",
            "1e99999999999999999999",
            "NaN",
            "inf",
        ] {
            assert!(parse_count(s).is_err(), "{s} accepted");
        }
        assert!(parse_count_u32("5e9").is_err());
        assert_eq!(parse_threads("2"), Ok(2));
        assert!(parse_threads("0").is_err());
        assert!(parse_threads("1e6").is_err());
        let cores = cores();
        assert_eq!(parse_threads(&(4 * cores).to_string()), Ok(4 * cores));
        assert!(parse_threads(&(4 * cores + 1).to_string()).is_err());
    }
}
