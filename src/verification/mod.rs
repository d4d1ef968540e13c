//! Verification: the machinery that shows why the digits can be trusted.
//!
//! * [`shadow`]: replays single `f64` events in MPFR from the same pre-event state.
//! * [`reversibility`]: forward N collisions, reverse, N back.
//! * [`birkhoff`]: the collision map in Birkhoff coordinates and its Jacobian.

/// Birkhoff coordinates and the Jacobian of the collision map.
pub mod birkhoff;
/// Fuzzing oracle: decodes raw bytes into valid (often degenerate) states and judges the kernel.
pub mod oracle;
/// Time reversal of long orbits.
pub mod reversibility;
/// Per-event MPFR shadows of f64 runs.
pub mod shadow;
