//! Parameter grids from exact decimals: `--w-from 0.1 --w-to 0.2 --steps 3` gives exactly the
//! doubles nearest to 0.1, 0.15 and 0.2 (never 0.15000000000000002), because every grid point is
//! computed as an exact rational and rounded once.

use rug::{Float, Integer, Rational};

use crate::Error;
use crate::numbers::real::Real;

/// Most digits accepted in a decimal (a double has 17 significant digits; more only hides a typo).
const MAX_DECIMAL_DIGITS: usize = 40;

/// Parses a decimal such as `0.1`, `-2.5e-3` or `3` exactly.
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::exact::parse_decimal;
/// use rug::Rational;
/// assert_eq!(parse_decimal("0.1").unwrap(), Rational::from((1, 10)));
/// assert_eq!(parse_decimal("2.5e-3").unwrap(), Rational::from((1, 400)));
/// assert!(parse_decimal("0x1p-3").is_err());
/// ```
pub fn parse_decimal(s: &str) -> Result<Rational, Error> {
    let bad = || Error::NotANumber {
        text: s.to_string(),
        why: "is not a decimal number (such as 0.15 or 1.5e-1)",
    };
    let t = s.trim();
    let (neg, t) = match t.strip_prefix('-') {
        Some(r) => (true, r),
        None => (false, t.strip_prefix('+').unwrap_or(t)),
    };
    let (mant, exp) = match t.find(['e', 'E']) {
        Some(i) => (&t[..i], t[i + 1..].parse::<i32>().map_err(|_| bad())?),
        None => (t, 0),
    };
    let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
    if int.is_empty() && frac.is_empty()
        || !int.bytes().all(|b| b.is_ascii_digit())
        || !frac.bytes().all(|b| b.is_ascii_digit())
        || int.len() + frac.len() > MAX_DECIMAL_DIGITS
        || exp.unsigned_abs() > 400
    {
        return Err(bad());
    }
    let digits: Integer = format!("{int}{frac}").parse().map_err(|_| bad())?;
    let shift = exp - frac.len() as i32;
    let pow10 = |k: u32| Integer::from(Integer::u_pow_u(10, k));
    let mut r = if shift >= 0 {
        Rational::from(digits * pow10(shift as u32))
    } else {
        Rational::from((digits, pow10((-shift) as u32)))
    };
    if neg {
        r = -r;
    }
    Ok(r)
}

/// An exact number as a user types it: a decimal (`0.1`, `2.5e-3`) or a fraction of two
/// decimals (`1/3`, `-2/7`), parsed exactly (never through a double).
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::exact::parse_exact;
/// use rug::Rational;
/// assert_eq!(parse_exact("1/3").unwrap(), Rational::from((1, 3)));
/// assert_eq!(parse_exact("0.1").unwrap(), Rational::from((1, 10)));
/// assert!(parse_exact("1/0").is_err());
/// assert!(parse_exact("1/3/4").is_err());
/// ```
pub fn parse_exact(s: &str) -> Result<Rational, Error> {
    match s.split_once('/') {
        None => parse_decimal(s),
        Some((n, d)) => {
            let (n, d) = (parse_decimal(n)?, parse_decimal(d)?);
            if d == 0 {
                return Err(Error::NotANumber {
                    text: s.to_string(),
                    why: "divides by zero: use a decimal such as 0.25 or a fraction such as 1/3",
                });
            }
            Ok(n / d)
        }
    }
}

/// The double nearest to an exact rational (ties to even).
pub fn nearest_f64(r: &Rational) -> f64 {
    Float::with_val(f64::MANTISSA_DIGITS, r).to_f64()
}

/// A double as exact text that [`parse_exact`] reads back as exactly `x`: the fraction m/2^k
/// in lowest terms (`"1/4"`, `"3602879701896397/36028797018963968"` for 0.1), or the integer
/// itself; for a parameter known only as a double. `None` for NaN, the infinities and the
/// doubles whose fraction needs more than the 40 digits a decimal may have (|x| < 2^-80 or
/// |x| ≥ 10^40 about, far outside every parameter's range).
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::exact::{exact_text_of, parse_exact, nearest_f64};
/// assert_eq!(exact_text_of(0.25).unwrap(), "1/4");
/// assert_eq!(exact_text_of(-3.0).unwrap(), "-3");
/// let tenth = exact_text_of(0.1).unwrap();
/// assert_eq!(tenth, "3602879701896397/36028797018963968");
/// assert_eq!(parse_exact(&tenth).unwrap(), rug::Rational::from_f64(0.1).unwrap());
/// assert!(exact_text_of(f64::NAN).is_none());
/// ```
pub fn exact_text_of(x: f64) -> Option<String> {
    let q = Rational::from_f64(x)?;
    let text = if *q.denom() == 1 {
        q.numer().to_string()
    } else {
        q.to_string()
    };
    // The text must read back (each side within the digits a decimal may have).
    let back = parse_exact(&text).ok()?;
    (back == q).then_some(text)
}

/// A parameter (a gap or a radius) at a working precision: `exact`, the decimal or fraction the
/// user typed, correctly rounded once to the context when it is given; otherwise the double
/// `value` itself, taken as that binary number. At 53 bits both give `value` (see
/// [`check_exact`]), so MPFR-53 runs keep the bits of `f64` runs.
///
/// # Errors
/// If `exact` does not parse.
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::exact::param_at;
/// let w: rug::Float = param_at(200, 0.1, Some("1/10")).unwrap();
/// assert_eq!(w, rug::Float::with_val(200, rug::Float::parse("0.1").unwrap()));
/// let w: f64 = param_at((), 0.1, Some("1/10")).unwrap();
/// assert_eq!(w, 0.1);
/// ```
pub fn param_at<T: Real>(ctx: T::Ctx, value: f64, exact: Option<&str>) -> Result<T, Error> {
    Ok(match exact {
        Some(text) => T::from_rational(ctx, &parse_exact(text)?),
        None => T::from_f64(ctx, value),
    })
}

/// Checks that `exact`, when given, is a decimal or fraction whose nearest double is `value`: a
/// configuration carries a parameter both ways (`what`, and `exact_field` as typed), and the two
/// must name the same number.
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::exact::check_exact;
/// assert!(check_exact(("w", "w_exact"), 0.1, Some("1/10")).is_ok());
/// assert!(check_exact(("w", "w_exact"), 0.1, None).is_ok());
/// let e = check_exact(("w", "w_exact"), 0.2, Some("1/10")).unwrap_err();
/// assert_eq!(
///     e.to_string(),
///     "w_exact = '1/10': not w = 0.2 (its nearest double is 0.1): give the same number in both"
/// );
/// assert!(check_exact(("w", "w_exact"), 0.1, Some("one tenth")).is_err());
/// ```
pub fn check_exact(
    (what, exact_field): (&str, &'static str),
    value: f64,
    exact: Option<&str>,
) -> Result<(), Error> {
    let Some(text) = exact else { return Ok(()) };
    let q = parse_exact(text).map_err(|e| e.named(exact_field))?;
    let near = nearest_f64(&q);
    if near.to_bits() != value.to_bits() {
        return Err(Error::parameter(
            exact_field,
            format!("'{text}'"),
            format!(
                "not {what} = {value:?} (its nearest double is {near:?}): give the same number \
                 in both"
            ),
        ));
    }
    Ok(())
}

/// `steps ≥ 2` points from `from` to `to` (decimals or fractions, as [`parse_exact`] reads them),
/// evenly spaced in exact arithmetic: point i is the double nearest to from + (to − from)·i/(steps − 1).
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::exact::decimal_grid;
/// assert_eq!(decimal_grid("0.1", "0.2", 3).unwrap(), vec![0.1, 0.15, 0.2]);
/// assert_eq!(decimal_grid("0.02", "0.3", 15).unwrap()[2], 0.06);
/// assert_eq!(decimal_grid("1/10", "1/5", 3).unwrap(), vec![0.1, 0.15, 0.2]);
/// ```
pub fn decimal_grid(from: &str, to: &str, steps: u32) -> Result<Vec<f64>, Error> {
    if steps < 2 {
        return Err(Error::TooFew {
            what: "steps",
            min: 2,
            got: steps.into(),
        });
    }
    let a = parse_exact(from)?;
    let b = parse_exact(to)?;
    let span = Rational::from(&b - &a);
    Ok((0..steps)
        .map(|i| {
            let x = a.clone() + span.clone() * Rational::from((i, steps - 1));
            nearest_f64(&x)
        })
        .collect())
}

/// Points a + i·h for i = 0 … n−1 (decimal strings), each rounded once.
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::exact::decimal_steps;
/// assert_eq!(decimal_steps("0.04", "0.001", 3).unwrap(), vec![0.04, 0.041, 0.042]);
/// ```
pub fn decimal_steps(a: &str, h: &str, n: u32) -> Result<Vec<f64>, Error> {
    let a = parse_decimal(a)?;
    let h = parse_decimal(h)?;
    Ok((0..n)
        .map(|i| nearest_f64(&(a.clone() + h.clone() * i)))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_points_are_the_decimals_asked_for() {
        // Naive arithmetic gives 0.15000000000000002 here.
        let naive = 0.1 + (0.2 - 0.1) * 1.0 / 2.0;
        assert_ne!(naive, 0.15);
        let g = decimal_grid("0.1", "0.2", 3).unwrap();
        assert_eq!(g[1], "0.15".parse::<f64>().unwrap());
        assert_eq!(format!("{}", g[1]), "0.15");
        // Every point of a long grid equals the parse of its decimal.
        let g = decimal_grid("0.2", "0.3", 21).unwrap();
        for (i, w) in g.iter().enumerate() {
            let d = format!("0.{}", 200 + 5 * i as u32);
            assert_eq!(*w, d.parse::<f64>().unwrap(), "{i}");
        }
        assert!(decimal_grid("0.1", "abc", 3).is_err());
        assert!(decimal_grid("0.1", "0.2", 1).is_err());
        assert_eq!(parse_decimal("-1.5").unwrap(), Rational::from((-3, 2)));
    }
}

/// A gap or a radius as a user typed it (on the command line, from Python): an exact decimal or
/// fraction (`0.1`, `1/10`), kept exactly and as its nearest double; `nan` and `inf` pass
/// through as doubles so that the analysis refuses them naming the valid range.
///
/// # Examples
///
/// ```
/// use lorentz_gas::numbers::exact::ExactInput;
/// let w = ExactInput::parse("1/10").unwrap();
/// assert_eq!(w.value, 0.1);
/// assert_eq!(w.exact_text().as_deref(), Some("1/10"));
/// assert!(ExactInput::parse("nan").unwrap().rational("w").is_err());
/// assert!(ExactInput::parse("0.1.2").is_err());
/// ```
#[derive(Debug, Clone)]
pub struct ExactInput {
    /// The nearest double (what `f64` runs use).
    pub value: f64,
    /// The exact value, for scenes and closed forms at any precision (`None` for `nan`, `inf`).
    pub exact: Option<Rational>,
    /// The text as typed (trimmed): what a configuration records as the exact value.
    pub text: String,
}

impl ExactInput {
    /// Parses `s`: an exact decimal or fraction, or a non-finite double.
    ///
    /// # Errors
    /// Anything else, with [`parse_exact`]'s message.
    pub fn parse(s: &str) -> Result<Self, Error> {
        match parse_exact(s) {
            Ok(q) => Ok(ExactInput {
                value: nearest_f64(&q),
                exact: Some(q),
                text: s.trim().to_string(),
            }),
            Err(e) => match s.trim().parse::<f64>() {
                Ok(v) if !v.is_finite() => Ok(ExactInput {
                    value: v,
                    exact: None,
                    text: s.trim().to_string(),
                }),
                _ => Err(e),
            },
        }
    }

    /// The value as typed, for a configuration's `w_exact` (`None` for `nan` and `inf`, which
    /// validation refuses).
    pub fn exact_text(&self) -> Option<String> {
        self.exact.as_ref().map(|_| self.text.clone())
    }

    /// The exact value of parameter `what`, or the refusal of a NaN or an infinity.
    pub fn rational(&self, what: &'static str) -> Result<Rational, Error> {
        self.exact.clone().ok_or(Error::NotFinite { what })
    }
}
