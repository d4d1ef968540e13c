//! Verification: the machinery that shows why the digits can be trusted.
//!
//! * [`shadow`]: replays single `f64` events in MPFR from the same pre-event state.
//! * [`shadowing`]: true orbits near whole `f64` segments (Newton on the defects, GHYS).
//! * [`reversibility`]: forward N collisions, reverse, N back.
//! * [`birkhoff`]: the collision map in Birkhoff coordinates and its Jacobian.
//! * [`audit`], [`lyapunov`], [`certify`]: production audits, chaos, certified segments.
//! * [`oracle`]: the fuzzing oracle (also run by `cargo test`).

pub mod audit;
pub mod birkhoff;
pub mod certify;
pub mod lyapunov;
pub mod oracle;
pub mod reversibility;
pub mod shadow;
pub mod shadowing;
