//! Verification: the machinery that shows why the digits can be trusted.
//!
//! * [`error_model`]: the constants of the `f64` error model (the bounds the checks and the tests share).
//! * [`replay`]: replays single `f64` events in MPFR from the same pre-event state.
//! * [`shadowing`]: true orbits near whole `f64` segments, straight or on arcs (Newton on the
//!   defects, GHYS).
//! * [`reversibility`]: forward N collisions, reverse, N back.
//! * [`birkhoff`]: the collision map in Birkhoff coordinates and its Jacobian.
//! * [`shadow_audit`]: the MPFR shadow audit of a production run's own trajectories;
//!   [`arc_audit`]: its events in a magnetic field or under the thermostat ([`curved`], the two
//!   motions; [`thermo_audit`], the thermostat's own checks), judged by the kernel's running
//!   error bound.
//! * [`lyapunov`], [`divergence`], [`certify`]: chaos, certified segments.
//! * [`cycles`]: certified periodic orbits of open tables (the three-disk repeller) and their
//!   cycle expansions (escape rate, Lyapunov exponent, KS entropy).
//! * `oracle` (feature `oracle`): the fuzzing oracle (also run by `cargo test`).

pub mod arc_audit;
pub mod arc_tangent;
pub mod audited;
pub mod birkhoff;
pub mod certify;
pub mod curved;
pub mod cycles;
pub mod divergence;
pub mod error_model;
pub mod jump_audit;
pub mod jump_audit_triangular;
pub mod log_histogram;
pub mod lyapunov;
#[cfg(feature = "oracle")]
pub mod oracle;
pub mod replay;
pub mod reversibility;
pub mod shadow_audit;
pub mod shadowing;
pub mod thermo_audit;

/// A field given as text, exact, if there is one: `None` for an absent or zero field.
///
/// # Errors
/// A field that is not an exact decimal or fraction, or with |B| outside `range` (the message
/// names the range, and 0 for no field).
pub fn exact_field(
    text: Option<&str>,
    range: (f64, f64),
) -> Result<Option<rug::Rational>, crate::Error> {
    let Some(text) = text else {
        return Ok(None);
    };
    let q = crate::numbers::exact::parse_exact(text).map_err(|e| e.named("field"))?;
    if q.cmp0() == std::cmp::Ordering::Equal {
        return Ok(None);
    }
    let b = crate::numbers::exact::nearest_f64(&q);
    crate::scenes::spec::field_within(b, text, range)?;
    Ok(Some(q))
}
