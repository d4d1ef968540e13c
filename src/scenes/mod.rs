//! Scenes: geometry set-ups built from the kernel's canonical trap. Each carries only the
//! obstacles and the precision it needs.
//!
//! * [`lattice`]: the infinite periodic triangular lattice (trap hopping, unwrapped positions).

pub mod lattice;
