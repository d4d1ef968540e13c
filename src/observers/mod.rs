//! Observers: they watch the events of a scene and never touch the kernel or the engine.
//!
//! An engine ([`crate::engine`]) advances a block of L independent trajectories one event per
//! step (L = 1 for the scalar engine) and shows every
//! [`Observer`](crate::engine::observe::Observer) the step as an
//! [`EventLanes`](crate::engine::observe::EventLanes): for each lane the event met (flight time and what ended the flight) and the
//! state before it. Observers keep one accumulator per lane and update them with plain loops
//! written with the engine's own vector type ([`Lanes`](crate::numbers::lanes::Lanes): AVX-512, AVX2, … or plain `f64` on the
//! scalar engine), so the per-event work is a few vector instructions for all lanes at once;
//! rare work (a sample of the MSD, a hop) is done lane by lane. The per-lane arithmetic is the same whatever
//! L is, so every observable has the same bits on every engine.
//!
//! * [`msd`]: mean squared displacement at fixed lag times, sampled on a fixed time grid.
//! * [`excursion`]: bounded or diffusing, one trajectory from the largest distance it reached.
//! * [`counters`]: collisions, crossings, total time (compensated), longest flight.
//! * [`hops`]: trap-hopping symbols, collisionless visits, hop-direction correlations.
//! * [`flight_tails`]: the tails of the free flights under the map and the flow.
//! * [`free_paths`]: the free paths between collisions in units of the mean free path, histogrammed.
//! * [`msd_curve`]: the MSD, the velocity autocorrelation and its running Green–Kubo integral
//!   on a multiple-τ logarithmic grid from inside the first flight (four times per octave).
//! * [`msd_times`]: the MSD, the velocity autocorrelation per component and the Green–Kubo
//!   integral at times the user gives, from t = 0 on.
//! * [`lag_ring`]: sums over time origins at fixed lags of any pair of samples (the moments of
//!   a run in a field and of the driven gas).
//! * [`lag_moments`]: ⟨|Δr|²⟩, ⟨v(0)·v(t)⟩ and the scaled displacement's histogram at lags on a
//!   logarithmic grid.

pub mod counters;
pub mod excursion;
pub mod flight_tails;
pub mod free_paths;
pub mod hop_correlations;
pub mod hops;
pub mod lag_moments;
pub mod lag_ring;
pub mod msd;
pub mod msd_curve;
pub mod msd_times;
