//! The number type of a run — `f64` or MPFR at a number of bits — and the one place where a
//! computation generic over [`Real`] is instantiated for the precision the user asked for.

use std::str::FromStr;

use rug::Float;
use serde::{Deserialize, Serialize};

use crate::Error;
use crate::numbers::real::Real;

/// Number type of a run: `f64`, or `rug::Float` with a number of bits ≥ 53.
///
/// Its serde form is its display form, the one typed on the command line and written in a result's
/// `meta.precision`: the string `"f64"` or the number of bits as a string (`"128"`); a JSON number
/// of bits is read too.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Precision {
    /// IEEE double.
    F64,
    /// MPFR with this many bits.
    Bits(u32),
}

impl std::fmt::Display for Precision {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Precision::F64 => write!(f, "f64"),
            Precision::Bits(b) => write!(f, "{b}"),
        }
    }
}

pub use crate::numbers::real::MAX_RUN_BITS;

impl Serialize for Precision {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> Deserialize<'de> for Precision {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Form {
            Text(String),
            Bits(u32),
        }
        let text = match Form::deserialize(d)? {
            Form::Text(t) => t,
            Form::Bits(b) => b.to_string(),
        };
        text.parse().map_err(serde::de::Error::custom)
    }
}

impl FromStr for Precision {
    type Err = Error;
    /// `f64`, or a number of bits from 53 to [`MAX_RUN_BITS`]; anything else is refused with the
    /// valid range (and, above the range, the memory one number would take).
    fn from_str(s: &str) -> Result<Self, Error> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("f64") {
            return Ok(Precision::F64);
        }
        let bits: u32 = s.parse().map_err(|_| {
            Error::out_of_range(
                "precision",
                format!("'{s}'"),
                format!("use 'f64' or a number of bits from 53 to {MAX_RUN_BITS}"),
            )
        })?;
        <Float as Real>::check_ctx(bits)?;
        Ok(Precision::Bits(bits))
    }
}

/// A computation generic over the number type: [`Precision::dispatch`] runs it on `f64` or on
/// `rug::Float` with the requested bits. This is the only `match` on [`Precision`] that chooses a
/// number type.
pub trait AtPrecision {
    /// What the computation returns.
    type Output;
    /// Runs the computation on number type `T` with context `ctx` (`()` for `f64`, the bits for
    /// MPFR).
    fn at<T: Real>(self, ctx: T::Ctx) -> Self::Output;
}

impl Precision {
    /// Runs `job` on the number type of this precision.
    ///
    /// # Examples
    ///
    /// ```
    /// use lorentz_gas::numbers::precision::{AtPrecision, Precision};
    /// use lorentz_gas::numbers::real::Real;
    /// struct Bits;
    /// impl AtPrecision for Bits {
    ///     type Output = u32;
    ///     fn at<T: Real>(self, ctx: T::Ctx) -> u32 { T::bits(ctx) }
    /// }
    /// assert_eq!(Precision::F64.dispatch(Bits), 53);
    /// assert_eq!(Precision::Bits(200).dispatch(Bits), 200);
    /// ```
    pub fn dispatch<A: AtPrecision>(self, job: A) -> A::Output {
        match self {
            Precision::F64 => job.at::<f64>(()),
            Precision::Bits(b) => job.at::<Float>(b),
        }
    }

    /// Bits of the significand (53 for `f64`).
    pub fn bits(self) -> u32 {
        match self {
            Precision::F64 => f64::MANTISSA_DIGITS,
            Precision::Bits(b) => b,
        }
    }
}
