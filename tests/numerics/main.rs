//! The numerical-correctness suite: the kernel's properties per scalar type, bit-for-bit
//! agreement of every path (MPFR-53, generic f64, SIMD), hard cases, physics identities, scenes,
//! certified trajectories, the fuzz oracle, shadowing and the shadow audits.
//!
//! One test binary with one module per topic (one link of the library with static GMP/MPFR
//! instead of one per file); helpers shared by every binary are in `tests/common`.

#[path = "../common/mod.rs"]
mod common;

mod arc_audit;
mod arc_engine;
mod arc_shadowing;
mod arc_tangency_band;
mod arc_tangent;
mod bit_for_bit;
mod cell_engine;
mod certified;
mod checkpoints;
mod choice;
mod engine;
mod field;
mod fuzz_oracle;
mod hard_cases;
mod kernel_properties;
mod long_flight;
mod long_flight_audit;
mod long_flight_triangular;
mod physics;
mod scene_diffusion;
mod scenes;
mod shadowing;
mod square;
mod table_field;
mod tables;
mod trajectory;
mod verification;
