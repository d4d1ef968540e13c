//! Lattice runs of any scene stepped in f64 with invariants checked after every event: see
//! `lorentz_gas::verification::oracle::scene_stepper` and `proofs-notes/fuzzing.md`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lorentz_gas::verification::oracle::scene_stepper;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = scene_stepper(data) {
        panic!("{e}");
    }
});
