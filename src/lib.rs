//! # lorentz-gas
//!
//! Deterministic diffusion in the two-dimensional periodic Lorentz gas (point particle, speed 1,
//! hard disks of radius 1 on a triangular lattice of spacing 2 + w), after Klages & Dellago,
//! *J. Stat. Phys.* **101**, 145 (2000) — computed by one collision kernel that is generic over
//! `f64` (production) and `rug::Float` (the MPFR shadow that audits it).
//!
//! Layout, physics first:
//! * [`real`]: the number trait (`f64`, `rug::Float` ≥ 53 bits).
//! * [`lanes`]: vectors of `f64` lanes (AVX-512, AVX2, portable, one `f64`) with exactly the
//!   scalar IEEE operations, for the SIMD engine and its observers.
//! * [`geometry`]: closed forms (w∞, w₀, ⟨ℓ⟩, τ, D_MZ, D_Bo, …).
//! * [`kernel`]: ray–disk root, the canonical trap, reflections.
//! * [`scenes`]: the periodic lattice built from the trap.
//! * [`engine`]: what runs trajectories — the scalar engine (any precision) and the SIMD
//!   multi-trajectory engine (`f64`, bit-identical), both feeding the same observers.
//! * [`sampling`]: initial conditions from the invariant measure; reproducible streams.
//! * [`symbols`]: the exit symbols z, l, r and their words (the one encoding).
//! * [`observables`]: mean squared displacement, event counters, trap-hopping statistics.
//! * [`stats`]: batch means, blocking, least-squares fits (weighted, with χ²), Student-t quantiles.
//! * [`diffusion`]: D(w) by the Einstein formula with error bars.
//! * [`escape`]: D(w) from the escape rate out of an open strip (Gaspard–Baras), extrapolated in
//!   the width.
//! * [`theory`]: symbolic dynamics, the corrected Machta–Zwanzig hierarchy, App. A, exact and
//!   simulated correlated lattice walks, hop-level Green–Kubo.
//! * [`trajectory`]: one trajectory from exact initial conditions to certified digits (precision
//!   doubling).
//! * [`verification`]: shadows, audits, reversibility, Birkhoff-map Jacobians, Lyapunov exponents.
#![warn(missing_docs)]

pub mod bench;
pub mod diffusion;
pub mod engine;
pub mod error;
pub mod escape;
pub mod figures;
pub mod geometry;
pub mod grid;
pub mod hopping;
pub mod kernel;
pub mod lanes;
pub mod metadata;
pub mod observables;
pub mod parallel;
pub mod precision;
pub mod publication;
pub mod real;
pub mod report;
pub mod reproduce;
pub mod sampling;
pub mod scenes;
pub mod slurm;
pub mod stats;
pub mod sweep;
pub mod symbols;
pub mod theory;
pub mod trajectory;
pub mod verification;

pub use error::Error;
