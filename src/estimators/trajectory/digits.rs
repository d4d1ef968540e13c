//! Decimal digits of a trajectory's values: how many two runs agree to, and a value correctly
//! rounded to them.

use rug::ops::Pow;
use rug::{Float, Integer};

/// Digits counted for `q`: the number of integer digits of |q| (0 if |q| < 1), so that
/// `digits` digits of `q` end at the decimal position 10^(lead − digits).
fn lead(q: &Float) -> i64 {
    let a = Float::with_val(64, q.abs_ref());
    if a < 1 {
        return 0;
    }
    a.log10().floor().to_f64() as i64 + 1
}

/// Digits to which `lo` (at `bits_lo` bits) and `hi` agree: lead(hi) − log₁₀|lo − hi|. Equal
/// values count as agreeing to the resolution 2^−bits_lo·max(|hi|, 1) of the lower run. The
/// logarithms are taken in MPFR (a deviation of 2^−30000 underflows a double).
pub fn digits_agreed(lo: &Float, hi: &Float, bits_lo: u32) -> f64 {
    let dev = Float::with_val(
        64,
        Float::with_val(hi.prec().max(lo.prec()), lo - hi).abs_ref(),
    );
    let scale = Float::with_val(64, hi.abs_ref()).max(&Float::with_val(64, 1));
    let resolution = scale >> bits_lo;
    let worst = if dev > resolution { dev } else { resolution };
    lead(hi) as f64 - worst.log10().to_f64()
}

/// `q` correctly rounded to `digits` digits counted from its leading integer digit, or from the
/// first decimal place when |q| < 1 (so `0.99526…` with 100 digits has 100 decimals), as a plain
/// decimal string.
pub fn decimal(q: &Float, digits: u32) -> String {
    let places = digits as i64 - lead(q);
    let prec = q.prec() + (places.unsigned_abs() as f64 * std::f64::consts::LOG2_10) as u32 + 64;
    let ten = Integer::from(10);
    let scaled = if places >= 0 {
        Float::with_val(prec, q * ten.pow(places as u32))
    } else {
        Float::with_val(prec, q / ten.pow((-places) as u32))
    };
    let n = scaled.to_integer().unwrap_or_default();
    let sign = if n < 0 { "-" } else { "" };
    let mut s = n.abs().to_string();
    if places <= 0 {
        s.push_str(&"0".repeat((-places) as usize));
        return format!("{sign}{s}");
    }
    let places = places as usize;
    if s.len() <= places {
        s = format!("{}{s}", "0".repeat(places + 1 - s.len()));
    }
    let (int, frac) = s.split_at(s.len() - places);
    format!("{sign}{int}.{frac}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimals_round_and_place_the_point() {
        let q = Float::with_val(200, Float::parse("0.99526").unwrap());
        assert_eq!(decimal(&q, 3), "0.995");
        assert_eq!(decimal(&q, 4), "0.9953");
        let q = Float::with_val(200, Float::parse("-12.345678").unwrap());
        assert_eq!(decimal(&q, 4), "-12.35");
        assert_eq!(decimal(&q, 1), "-10");
        let q = Float::with_val(200, Float::parse("0.00123").unwrap());
        assert_eq!(decimal(&q, 4), "0.0012");
        assert_eq!(decimal(&Float::with_val(64, 0), 2), "0.00");
    }

    #[test]
    fn agreement_counts_decimals_below_one_and_significant_digits_above() {
        let a = Float::with_val(300, Float::parse("0.123456789").unwrap());
        let b = Float::with_val(300, Float::parse("0.123456788").unwrap());
        assert!((digits_agreed(&a, &b, 300) - 9.0).abs() < 0.01);
        let a = Float::with_val(300, Float::parse("123.456789").unwrap());
        let b = Float::with_val(300, Float::parse("123.456788").unwrap());
        assert!((digits_agreed(&a, &b, 300) - 9.0).abs() < 0.01);
    }
}
