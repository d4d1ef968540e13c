//! Campaigns: work too large for one machine, run through Slurm job arrays whose parts merge into
//! the bits of one run.
//!
//! * [`shard`]: one part of a sweep (point i belongs to part i mod N).
//! * [`merge`]: the parts combined into the whole sweep, bit-identical to it.
//! * [`slurm`]: job-array scripts and the dependent merge job for a sweep.

pub mod merge;
pub mod shard;
pub mod slurm;
