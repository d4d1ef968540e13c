//! Long flights of the triangular lattice beyond w∞ on decoded lines — near misses of far disks,
//! lattice directions, any direction, from just beyond w∞ to a spacing of 2²⁰ — each jump replayed
//! by the MPFR trap walk: see `lorentz_gas::verification::oracle::long_flight_triangular` and
//! `proofs-notes/fuzzing.md`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lorentz_gas::verification::oracle::long_flight_triangular;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = long_flight_triangular(data) {
        panic!("{e}");
    }
});
