//! Estimators: the analyses, each a validated configuration and one entry point.
//!
//! * [`diffusion`]: D(w) by the Einstein formula (MSD slope) with batch errors.
//! * [`field`]: the diffusion tensor in a magnetic field — D_xx, the Hall D_xy, pinned and
//!   skipping orbits counted exactly.
//! * [`hops`]: trap hopping — symbol sequences, backscattering, Green–Kubo, lattice walks.
//! * [`sweep`]: D over a grid of gaps with a fit, in shards for campaigns.
//! * [`escape`]: D from the escape rate out of an open strip (Gaspard–Baras).
//! * [`free_paths`]: the free path between collisions against its Boltzmann–Grad limit law.
//! * [`superdiffusion`]: an infinite horizon's t ln t growth, flight tails and limit law against
//!   the exact corridor constants.
//! * [`section`]: a Poincaré section in Birkhoff coordinates, each orbit coloured by its
//!   component (pinned, skipping, a regular island, the chaotic sea).
//! * [`trajectory`]: one trajectory from exact initial conditions to certified digits.
//! * [`throughput`]: collisions per second of the engines (`lorentz bench`).
//! * [`observer_costs`]: what each set of observers adds to the engine's time, timed in turns
//!   (`lorentz bench --observer-costs`).
//!
//! [`metadata`](crate::engine::metadata) records how each result was computed.

pub mod current;
pub mod diffusion;
pub mod escape;
pub mod field;
pub mod free_paths;
pub mod hops;
pub mod observer_costs;
pub mod section;
pub mod superdiffusion;
pub mod sweep;
pub mod throughput;
pub mod trajectory;
pub mod transport;

use crate::Error;
use crate::scenes::spec::Table;

/// The gap of `table` for `analysis`, which follows straight flights on the triangular gas: the
/// double nearest the gap as typed (what `f64` runs use; runs at other precisions round
/// [`Table::gap_text`] once). Another scene is refused ([`Error::Lacks`] trap symbols), and so
/// is a field.
///
/// # Errors
/// Another scene, a field, or a gap that is not a number.
pub(crate) fn straight_gap(table: &Table, analysis: &'static str) -> Result<f64, Error> {
    let w = table.gap_for(analysis)?;
    if let Some(b) = table.field() {
        return Err(Error::parameter(
            "field",
            b,
            format!(
                "the {analysis} analysis follows straight flights between collisions: leave the \
                 field out"
            ),
        ));
    }
    Ok(w)
}

/// [`straight_gap`], a gap at which D exists (0 < w < w∞, decided on the gap as typed:
/// [`check_diffusive_gap_exact`](crate::scenes::triangular::geometry::check_diffusive_gap_exact)).
///
/// # Errors
/// As [`straight_gap`], and a gap outside (0, w∞).
pub(crate) fn diffusive_gap(table: &Table, analysis: &'static str) -> Result<f64, Error> {
    let w = straight_gap(table, analysis)?;
    crate::scenes::triangular::geometry::check_diffusive_gap_exact(w, table.gap_text())?;
    Ok(w)
}
