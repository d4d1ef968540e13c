//! Verification: the machinery that shows why the digits can be trusted.
//!
//! * [`shadow`]: replays single `f64` events in MPFR from the same pre-event state.
//! * [`reversibility`]: forward N collisions, reverse, N back.
//! * [`birkhoff`]: the collision map in Birkhoff coordinates and its Jacobian.
//! * [`audit`], [`lyapunov`], [`certify`]: production audits, chaos, certified segments.
//! * [`oracle`]: the fuzzing oracle (also run by `cargo test`).

/// Sampled per-event audits of f64 production runs.
pub mod audit;
/// Birkhoff coordinates and the Jacobian of the collision map.
pub mod birkhoff;
/// Finite-segment certification by precision doubling.
pub mod certify;
/// Lyapunov exponents: tangent space and precision divergence.
pub mod lyapunov;
/// Fuzzing oracle: decodes raw bytes into valid (often degenerate) states and judges the kernel.
pub mod oracle;
/// Time reversal of long orbits.
pub mod reversibility;
/// Per-event MPFR shadows of f64 runs.
pub mod shadow;
