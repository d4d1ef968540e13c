//! Errors for bad input: each names the valid range.

use std::fmt;

/// Everything a caller can get wrong. Never a panic, never a silent NaN.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// The gap `w` is NaN or infinite.
    NotFinite {
        /// Which parameter.
        what: &'static str,
    },
    /// `w ≤ 0`: the disks touch or overlap and the particle is trapped, there is no diffusion.
    Trapped {
        /// The offending gap.
        w: f64,
    },
    /// `w ≥ w∞ = 4/√3 − 2`: the horizon is infinite and D does not exist.
    InfiniteHorizon {
        /// The offending gap.
        w: f64,
        /// w∞ in f64.
        w_inf: f64,
    },
    /// Precision below 53 bits (or above MPFR's maximum).
    Precision {
        /// The requested number of bits.
        bits: u32,
    },
    /// A count that must be positive is zero.
    Zero {
        /// Which parameter.
        what: &'static str,
    },
    /// A count too small for the requested analysis.
    TooFew {
        /// Which parameter.
        what: &'static str,
        /// The smallest accepted value.
        min: u64,
        /// The value given.
        got: u64,
    },
    /// Any other invalid argument, with the reason.
    Invalid(String),
    /// An I/O error (checkpoint or output files).
    Io(String),
    /// A verification ran and its verdict is FAIL (not bad input: exit status 1).
    CheckFailed(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::NotFinite { what } => write!(f, "{what} must be a finite number"),
            Error::Trapped { w } => write!(
                f,
                "w = {w:?} is not > 0: at w <= 0 the disks touch and the particle is trapped in one \
                 triangle, there is no diffusion (valid range: 0 < w < 4/sqrt(3) - 2 = 0.3094...)"
            ),
            Error::InfiniteHorizon { w, w_inf } => write!(
                f,
                "w = {w:?} is not < w_inf = 4/sqrt(3) - 2 = {w_inf:.17}: the horizon is infinite, \
                 free flights are unbounded and the diffusion coefficient does not exist \
                 (valid range: 0 < w < {w_inf:.6})"
            ),
            Error::Precision { bits } => write!(
                f,
                "precision {bits} bits is out of range: use 'f64' or a number of bits from 53 to {}",
                rug::float::prec_max()
            ),
            Error::Zero { what } => write!(f, "{what} must be at least 1"),
            Error::TooFew { what, min, got } => {
                write!(f, "{what} = {got} is too small: at least {min} is needed")
            }
            Error::Invalid(s) => write!(f, "{s}"),
            Error::Io(s) => write!(f, "I/O error: {s}"),
            Error::CheckFailed(s) => write!(f, "{s}"),
        }
    }
}

impl std::error::Error for Error {}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        Error::Io(e.to_string())
    }
}
