//! # lorentz-gas
//!
//! Deterministic diffusion in the two-dimensional periodic Lorentz gas (point particle, speed 1,
//! hard disks of radius 1 on a triangular lattice of spacing 2 + w), after Klages & Dellago,
//! *J. Stat. Phys.* **101**, 145 (2000) — computed by one collision kernel that is generic over
//! `f64` (production) and `rug::Float` (the MPFR shadow that audits it).
//!
//! ## The map
//!
//! The layers, each using only the ones above it in this list (`ARCHITECTURE.md` says more):
//!
//! 1. [`numbers`]: the number trait (`f64`, MPFR), SIMD lanes, precisions, exact inputs.
//! 2. [`kernel`]: one file per geometric query — ray–disk root, flights and events, the generic
//!    cell kernel and the triangular trap's fused path.
//! 3. [`scenes`]: billiard tables built from kernels — the triangular lattice (and its closed
//!    forms), the square lattice, a single trap, the open strip; initial conditions; symbols.
//! 4. [`engine`]: what advances trajectories — the scalar engine (any precision), the SIMD
//!    engine (bit-identical `f64`), parallel batches, run options, resuming, run metadata.
//! 5. [`observers`]: what watches the events — MSD, counters, trap hops.
//! 6. [`estimators`]: the analyses (diffusion, hops, sweep, escape, superdiffusion, trajectory,
//!    throughput).
//! 7. [`report`]: publication audit, speed against error, reproduction, figures.
//!
//! Beside them: [`statistics`] (batch means, fits, Student-t), [`theory`] (symbolic dynamics,
//! the corrected hierarchy, exact correlated walks, Green–Kubo), [`verification`] (shadows,
//! shadowing, reversibility, Lyapunov exponents, certification, the fuzz oracle), [`campaigns`]
//! (shards, merge, Slurm), and the `lorentz` binary's `cli`. Errors are [`Error`].
//!
//! ## One way to call an analysis
//!
//! Every analysis is a validated configuration and one entry point,
//! `run(&config, &RunOptions)` ([`engine::options::RunOptions`]: engine, threads, progress,
//! resume, audit — never what is computed); analyses that work on any scene take it first,
//! `run(&scene, &config, &options)`:
//!
//! ```
//! use lorentz_gas::engine::options::RunOptions;
//! use lorentz_gas::estimators::diffusion::{self, DiffusionConfig};
//! let cfg = DiffusionConfig { collisions: 2_000_000, batches: 4, ..DiffusionConfig::new(0.2) };
//! let r = diffusion::run(&cfg, &RunOptions::default()).unwrap();
//! assert!(r.D > 0.0 && r.D_err > 0.0);
//! ```
#![warn(missing_docs)]

pub mod campaigns;
pub mod engine;
mod error;
pub mod estimators;
pub mod files;
pub mod kernel;
pub mod numbers;
pub mod observers;
#[cfg(feature = "report")]
pub mod report;
pub mod scenes;
pub mod statistics;
pub mod theory;
pub mod verification;

pub use error::{Capability, Error, ErrorKind};
