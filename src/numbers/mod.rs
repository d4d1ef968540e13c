//! Numbers: the working precisions and the exact inputs every layer above computes with.
//!
//! * [`real`]: the number trait [`Real`](real::Real), implemented by `f64` and `rug::Float`
//!   (≥ 53 bits); the kernel is generic over it.
//! * [`atan`]: atan2 written in the lanes' operations only: the same bits on every path and
//!   platform, for the observables of flights in a field.
//! * [`lanes`]: vectors of `f64` lanes (AVX-512, AVX2, portable, one `f64`) with exactly the
//!   scalar IEEE operations, for the SIMD engine and its observers.
//! * [`precision`]: a run's precision (`f64` or MPFR bits) and instantiation at it.
//! * [`ball`]: `f64` midpoint–radius enclosures of values computed at any precision ≥ 53 bits,
//!   to decide signs and orders before computing them.
//! * [`tracked`]: a value at 128 bits or more with a bound on the same computation's `f64`
//!   error (running error analysis), and its ambiguous decisions: the arcs' shadow audit.
//! * [`rotation`]: the first entry of an integer rotation into a window, in exact integers (the
//!   first disk a long straight flight meets in a lattice).
//! * [`count`]: counts (`2e9`) and thread numbers as typed, parsed exactly and checked.
//! * [`exact`]: exact decimals and fractions (`0.1`, `1/3`) parsed as rationals, and grids of them
//!   rounded once.

pub mod atan;
pub mod ball;
pub mod count;
pub mod exact;
pub mod lanes;
pub mod precision;
pub mod real;
pub mod rotation;
pub mod tracked;
