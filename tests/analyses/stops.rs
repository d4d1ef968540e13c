//! A stop asked for in the middle of a batch ends the run within one leg of the trajectory
//! (`engine::parallel::in_legs`), not at the batch's end: counted in collisions reported, so the
//! test does not depend on the machine's speed.

use std::sync::atomic::{AtomicU64, Ordering};

use lorentz_gas::Error;
use lorentz_gas::engine::long_flight::Flights;
use lorentz_gas::engine::options::{RunOptions, StopFlag};
use lorentz_gas::engine::parallel::STOP_EVERY;
use lorentz_gas::estimators::free_paths::{self, FreePathConfig};
use lorentz_gas::scenes::spec::SceneSpec;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::verification::lyapunov::{self, LyapunovConfig};

/// Runs `analysis` on one thread with a stop asked for once one leg of collisions has been
/// reported; returns its error and the collisions reported by then.
fn stopped_after_a_leg<R: std::fmt::Debug>(
    analysis: impl FnOnce(&RunOptions) -> Result<R, Error>,
) -> (Error, u64) {
    let stop = StopFlag::default();
    let seen = AtomicU64::new(0);
    let ask = |n: u64| {
        if seen.fetch_add(n, Ordering::Relaxed) + n >= STOP_EVERY {
            stop.request();
        }
    };
    let opts = RunOptions {
        threads: 1,
        stop: Some(stop.clone()),
        progress: &ask,
        ..RunOptions::default()
    };
    let err = analysis(&opts).expect_err("the run was asked to stop");
    (err, seen.load(Ordering::Relaxed))
}

/// A batch of 2²⁴ collisions: stopped after its first leg of 2²⁰, the run has reported at most
/// two legs (the one that asked and, at most, one in flight), not the 2²⁴ of the whole batch.
/// Broken on purpose (one drive per batch, as before `in_legs`): 2²⁴ + transient are reported.
#[test]
fn a_stop_mid_batch_ends_lyapunov_within_a_leg() {
    let scene = TriangularScene::new(0.1).unwrap();
    let cfg = LyapunovConfig {
        collisions_per_batch: 1 << 24,
        batches: 2,
        seed: 1,
        flights: Flights::Walk,
        motion: Default::default(),
    };
    let (err, seen) = stopped_after_a_leg(|o| lyapunov::run(&scene, &cfg, o));
    assert!(matches!(err, Error::Interrupted), "{err}");
    assert!(seen <= 2 * STOP_EVERY, "{seen} collisions reported");
}

/// The same for `free-paths`, with jumps (square lattice, r = 1/1000).
#[test]
fn a_stop_mid_batch_ends_free_paths_within_a_leg() {
    let cfg = FreePathConfig {
        collisions: 1 << 25,
        batches: 2,
        ..FreePathConfig::new(SceneSpec::Square {
            radius: "1/1000".into(),
        })
    };
    let (err, seen) = stopped_after_a_leg(|o| free_paths::run(&cfg, o));
    assert!(matches!(err, Error::Interrupted), "{err}");
    assert!(seen <= 2 * STOP_EVERY, "{seen} collisions reported");
}
