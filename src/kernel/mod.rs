//! The collision kernel, generic over [`crate::numbers::real::Real`]: one file per geometric query.
//!
//! * [`vec2`]: the plane vector.
//! * [`ray_disk`]: first contact with a disk (cancellation-free root), split at the choice.
//! * [`choice`]: the earliest disk and edge chosen before any square root or division, with the
//!   rounded-time rule's result (the SIMD engine's rule; the scalar kernel compares every time in
//!   `f64`).
//! * [`certified`]: the trap's next event decided in `f64` balls, only the chosen time computed at
//!   the working precision (MPFR), with the full comparison's bits.
//! * [`flight`]: the state of a free flight and the events that end it (exclusions by identity).
//! * [`open`]: an open table's next collision or its escape (finitely many disks, no cell).
//! * [`cell`]: the generic cell kernel — next event and its execution in any convex polygonal
//!   cell with disk obstacles, whose edges map exactly into the neighbouring cell.
//! * [`arc`], [`field`]: flights in a uniform magnetic field — arc contacts by algebra alone,
//!   ordered by their chords, and the generic cell kernel on arcs.
//! * [`thermostat`]: flights under a Gaussian-thermostatted electric field — a closed form
//!   without cancellation and contacts certified by a march of root-free steps.
//! * [`trap`]: the triangular lattice's trap (three disks, three edges, point reflections) with
//!   its fused fast path, bit-identical to the generic kernel on the same cell.
//!
//! Scenes ([`crate::scenes`]) supply the cells; observables never touch this module.

pub mod arc;
pub mod cell;
pub mod certified;
pub mod choice;
pub mod field;
pub mod flight;
pub mod open;
pub mod ray_disk;
pub mod thermostat;
pub mod trap;
pub mod vec2;
