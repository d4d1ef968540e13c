//! The constants of the `f64` error model, in one place: the library's checks (the fuzz oracle,
//! the MPFR replay, the reversibility bound) and the tests import them from here, so a bound is
//! stated once, with its derivation, and never copied.
//!
//! Each constant is a multiple of the unit roundoff of the working type (u = 2⁻⁵³ for `f64`,
//! 2⁻ᴾ at P bits): multiply by that type's u, so the same constant serves `f64` and MPFR. The
//! derivations are in `proofs-notes/error-model.md` (one event), `proofs-notes/energy.md` (the
//! speed after a collision) and `proofs-notes/reversibility.md` (one event forward and back).

/// Unit roundoff of `f64`, u = ε/2 = 2⁻⁵³.
pub const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;

/// ||v|² − 1| ≤ `ENERGY_BAND_U`·u after every collision of a unit-speed flight with the unit
/// disk, from the renormalised reflection (`proofs-notes/energy.md`: the rounded contact point is
/// on the disk within ε ≤ 28u, and 4·28u + 12u ≤ 128u). A cell whose disks have radius r and whose
/// coordinates reach `extent` scales it by 1 + extent/r (the fuzz oracle's `energy_band`; the
/// square cell's 128u·(1 + 1/(2r))).
pub const ENERGY_BAND_U: f64 = 128.0;

/// The one-event error K of the reversibility bound, in units of u: one event forward and the
/// same event back (velocity reversed) return within K·u in position and in the re-collision time,
/// and within 4·K·u/r in velocity (`proofs-notes/reversibility.md`); over E events amplified by
/// the flow's Jacobian, the bound is 2·E·K·u·max‖J‖
/// ([`crate::verification::reversibility::reversal_bound`]).
pub const ONE_EVENT_U: f64 = 256.0;

/// A post-event position may lie inside a disk by |x − c|² − r² ≥ −`POST_EVENT_U`·u, and outside
/// an edge by σ ≥ −`POST_EVENT_U`·u·extent (radii ≤ 1): the contact point's rounding (≤ 28u
/// relative, `proofs-notes/energy.md`) and a crossing's translation (a few u times the extent),
/// with a wide factor for the radii and extents of both scenes.
pub const POST_EVENT_U: f64 = 256.0;

/// Unwrapped displacement across one event: |Δx − t·s·v| ≤ `UNWRAP_EPS`·ε·(diameter + t), with
/// ε = 2u the machine epsilon, t the event time, s·v the world velocity and diameter that of the
/// cell polygon: the rounding of x + t·v (relative u in t·v and in the position, whose size is
/// at most the diameter) and of the frame map (a translation or point reflection by a vector of
/// the size of the cell), a few ε each, with a wide factor. Summed over N events it bounds the
/// drift of an unwrapped position from the summed flights: `UNWRAP_EPS`·ε·(N·diameter + Σt).
pub const UNWRAP_EPS: f64 = 64.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_constants_are_the_values_the_checks_were_derived_with() {
        assert_eq!(UNIT_ROUNDOFF, (-53f64).exp2());
        assert_eq!(ENERGY_BAND_U, 128.0);
        assert_eq!(ONE_EVENT_U, 256.0);
        assert_eq!(POST_EVENT_U, 256.0);
        assert_eq!(UNWRAP_EPS, 64.0);
    }
}
