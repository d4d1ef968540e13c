//! Campaigns split into parts: shards merged into the bits of the whole sweep, and a real
//! one-node Slurm cluster running the job array and the dependent merge job.
//!
//! One test binary with one module per topic (one link of the library with static GMP/MPFR
//! instead of one per file); helpers shared by every binary are in `tests/common`.

#[path = "../common/mod.rs"]
mod common;

mod shards;
mod slurm;
