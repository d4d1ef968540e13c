//! Long flights on decoded lines — near misses of far disks, small rational directions, any
//! direction, at radii 2⁻³² to 1/4 — each jump judged against the exact column walk of its line:
//! see `lorentz_gas::verification::oracle::long_flight` and `proofs-notes/fuzzing.md`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lorentz_gas::verification::oracle::long_flight;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = long_flight(data) {
        panic!("{e}");
    }
});
