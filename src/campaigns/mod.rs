//! Campaigns: work too large for one machine, run through Slurm job arrays whose parts merge into
//! the bits of one run.
//!
//! * [`slurm`]: job-array scripts and the dependent merge job for a sweep.

pub mod slurm;
