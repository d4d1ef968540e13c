//! The `lorentz` binary: bad input, metadata, thread independence, and the publication audit.
//!
//! One test binary with one module per topic (one link of the library with static GMP/MPFR
//! instead of one per file); helpers shared by every binary are in `tests/common`.

#[path = "../common/mod.rs"]
mod common;

mod bad_inputs;
mod checkpoints;
mod commands;
mod cycles;
mod driven;
mod honest_numbers;
mod hostile;
mod planned;
mod records;
mod report;
mod report_current;
mod report_field;
mod report_survival;
mod result_keys;
mod tables;
