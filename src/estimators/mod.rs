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
//! * [`trajectory`]: one trajectory from exact initial conditions to certified digits.
//! * [`throughput`]: collisions per second of the engines (`lorentz bench`).
//! * [`observer_costs`]: what each set of observers adds to the engine's time, timed in turns
//!   (`lorentz bench --observer-costs`).
//!
//! [`metadata`](crate::engine::metadata) records how each result was computed.

pub mod diffusion;
pub mod escape;
pub mod field;
pub mod free_paths;
pub mod hops;
pub mod observer_costs;
pub mod superdiffusion;
pub mod sweep;
pub mod throughput;
pub mod trajectory;
pub mod transport;
