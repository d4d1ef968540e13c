//! The collision kernel, generic over [`crate::real::Real`]: one file per geometric query.
//!
//! * [`vec2`]: the plane vector.
//! * [`ray_disk`]: first contact with a unit disk (cancellation-free root).
//! * [`trap`]: the canonical triangular trap; next event among its three disks and three edges,
//!   specular reflection, and the point reflection into the neighbouring trap.
//!
//! Scenes ([`crate::scenes`]) compose the trap into the periodic lattice or a single open trap;
//! observables never touch this module.

pub mod ray_disk;
pub mod trap;
pub mod vec2;
