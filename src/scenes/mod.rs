//! Scenes: geometry set-ups built from the kernel's canonical trap. Each carries only the
//! obstacles and the precision it needs.
//!
//! * [`lattice`]: the infinite periodic triangular lattice (trap hopping, unwrapped positions).
//! * [`single_trap`]: one trap of three disks and its gaps, for injection experiments.

pub mod lattice;
pub mod single_trap;
