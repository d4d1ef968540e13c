//! Theory of the trap-hopping picture: the Machta–Zwanzig random walk and the paper's
//! corrections (Sec. III and Apps. A, B of Klages & Dellago 2000), and the exact and
//! Monte-Carlo diffusion coefficients of correlated walks on the honeycomb of traps.
//!
//! * [`honeycomb`]: symbols z, l, r; exact walks on the lattice of trap centres.
//! * [`sequences`]: validated tables of symbol-sequence probabilities.
//! * [`hierarchy`]: D_cf, D_bs, D₁ (eqs. 4–6) and D_k (App. B, corrected).
//! * [`corridors`]: the corridors of an infinite horizon and the superdiffusion constants.
//! * [`free_paths`]: the Boltzmann–Grad limit law of free paths between collisions.
//! * [`constants`]: every closed form at gap w, at any precision (`lorentz constants`).
//! * [`appendix_a`]: the analytic p_cf (eqs. A4–A8), with the printed slip.
//! * [`markov`]: exact D of the order-k correlated walk (resolvent of the history chain).
//! * [`lattice_walk`]: Monte Carlo of that walk (Fig. 6b), Einstein formula, batch errors.
//! * [`green_kubo`]: hop-level Green–Kubo estimator from direction sequences.
//! * [`magnetic`]: pinned and skipping orbits in a magnetic field — exact shares, the
//!   classification of a phase point, Kac's mean free time of the diffusing part.
//! * [`quadrature`]: adaptive Gauss–Legendre for those exact shares.
//!
//! The derivations are in `proofs-notes/` (index: `proofs-notes/theory-index.md`).

pub mod appendix_a;
pub mod constants;
pub mod corridors;
pub mod free_paths;
pub mod green_kubo;
pub mod hierarchy;
pub mod honeycomb;
pub mod lattice_walk;
pub mod magnetic;
pub mod markov;
pub mod quadrature;
pub mod sequences;
