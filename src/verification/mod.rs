//! Verification: the machinery that shows why the digits can be trusted.
//!
//! * [`error_model`]: the constants of the `f64` error model (the bounds the checks and the tests share).
//! * [`replay`]: replays single `f64` events in MPFR from the same pre-event state.
//! * [`shadowing`]: true orbits near whole `f64` segments (Newton on the defects, GHYS).
//! * [`reversibility`]: forward N collisions, reverse, N back.
//! * [`birkhoff`]: the collision map in Birkhoff coordinates and its Jacobian.
//! * [`shadow_audit`]: the MPFR shadow audit of a production run's own trajectories;
//!   [`arc_audit`]: its events in a magnetic field, judged by the kernel's running error bound.
//! * [`lyapunov`], [`divergence`], [`certify`]: chaos, certified segments.
//! * `oracle` (feature `oracle`): the fuzzing oracle (also run by `cargo test`).

pub mod arc_audit;
pub mod arc_tangent;
pub mod birkhoff;
pub mod certify;
pub mod divergence;
pub mod error_model;
pub mod lyapunov;
#[cfg(feature = "oracle")]
pub mod oracle;
pub mod replay;
pub mod reversibility;
pub mod shadow_audit;
pub mod shadowing;
