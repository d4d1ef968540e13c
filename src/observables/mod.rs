//! Observables: they watch the events of a scene and never touch the kernel.
//!
//! * [`msd`]: mean squared displacement at fixed lag times, sampled on a fixed time grid.
//! * [`counters`]: collisions, crossings, total time (compensated), longest flight.
//! * [`hops`]: trap-hopping symbols, collisionless visits, hop-direction correlations.

pub mod counters;
pub mod hops;
pub mod msd;
