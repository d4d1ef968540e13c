//! The analyses through the library: sweeps, the escape-rate estimator, trap hopping and the
//! corrected hierarchy, each against exact values or a second estimator with Student-t bounds.
//!
//! One test binary with one module per topic (one link of the library with static GMP/MPFR
//! instead of one per file); helpers shared by every binary are in `tests/common`.

#[path = "../common/mod.rs"]
mod common;

mod corridors;
mod current;
mod derived_errors;
mod driven_sweep;
mod escape;
mod field;
mod field_components;
mod field_sweep;
mod free_paths;
mod hopping;
mod msd_curve;
mod msd_times;
mod options;
mod planning;
mod section;
mod stops;
mod superdiffusion;
mod survival;
mod sweep;
mod table_configs;
mod theory;
